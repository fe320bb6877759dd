//! An orthonormal shading frame around a normal: world <-> local (z = normal) directions.
//!
//! The tangent and bitangent are built without branches on the normal's direction except its
//! sign of z, after Duff, Burgess, Christensen, Hery, Kensler, Liani and Villemin, 2017,
//! "Building an Orthonormal Basis, Revisited" (JCGT 6(1)), which fixes the precision loss of
//! Frisvad's 2012 construction near n = -z.

use glam::Vec3;

/// A right-handed orthonormal basis: `tangent x bitangent = normal`. Local coordinates put the
/// tangent on x, the bitangent on y and the normal on z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Local +x.
    pub tangent: Vec3,
    /// Local +y.
    pub bitangent: Vec3,
    /// Local +z.
    pub normal: Vec3,
}

impl Frame {
    /// A frame around the unit normal `n` (Duff et al. 2017, listing 3). `n` must be unit length;
    /// the result is then orthonormal to within a few ulps for every direction, including
    /// n = -z. The sign used is +1 for `n.z >= 0` (so -0.0 counts as positive, which WGSL's
    /// `select(-1.0, 1.0, n.z >= 0.0)` reproduces).
    pub fn from_normal(n: Vec3) -> Self {
        let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        let tangent = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
        let bitangent = Vec3::new(b, sign + n.y * n.y * a, -n.y);
        Self {
            tangent,
            bitangent,
            normal: n,
        }
    }

    /// The world direction `v` in local coordinates (projections on tangent, bitangent, normal).
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(
            v.dot(self.tangent),
            v.dot(self.bitangent),
            v.dot(self.normal),
        )
    }

    /// The local direction `v` in world coordinates.
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.tangent * v.x + self.bitangent * v.y + self.normal * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Pcg32;
    use crate::sampling::uniform_sphere;

    fn check(n: Vec3) {
        let f = Frame::from_normal(n);
        let tol = 1e-5;
        for (name, v) in [("t", f.tangent), ("b", f.bitangent), ("n", f.normal)] {
            assert!((v.length() - 1.0).abs() < tol, "{name} of {n}: {v}");
        }
        assert!(f.tangent.dot(f.bitangent).abs() < tol, "{n}");
        assert!(f.tangent.dot(f.normal).abs() < tol, "{n}");
        assert!(f.bitangent.dot(f.normal).abs() < tol, "{n}");
        assert!(
            (f.tangent.cross(f.bitangent) - f.normal).length() < tol,
            "not right-handed for {n}"
        );
        assert!((f.to_local(n) - Vec3::Z).length() < tol);
        let v = Vec3::new(0.3, -0.5, 0.8).normalize();
        assert!((f.to_world(f.to_local(v)) - v).length() < tol);
        assert!((f.to_local(f.to_world(v)) - v).length() < tol);
    }

    #[test]
    fn orthonormal_right_handed_and_invertible() {
        for n in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::X,
            -Vec3::Y,
            -Vec3::Z,
            Vec3::new(1.0, 0.0, -0.0),
            Vec3::new(1e-7, 0.0, -1.0).normalize(),
            Vec3::new(0.0, 1e-4, -1.0).normalize(),
            Vec3::new(1.0, 1.0, 1e-9).normalize(),
        ] {
            if n.length() > 0.5 {
                check(n);
            }
        }
        let mut rng = Pcg32::new(3, 4);
        for _ in 0..10_000 {
            check(uniform_sphere(rng.next_vec2()));
        }
    }

    #[test]
    fn preserves_dot_products() {
        let mut rng = Pcg32::new(5, 6);
        for _ in 0..1000 {
            let f = Frame::from_normal(uniform_sphere(rng.next_vec2()));
            let a = uniform_sphere(rng.next_vec2());
            let b = uniform_sphere(rng.next_vec2());
            assert!((f.to_local(a).dot(f.to_local(b)) - a.dot(b)).abs() < 1e-5);
        }
    }
}
