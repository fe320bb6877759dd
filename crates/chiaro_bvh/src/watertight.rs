//! The watertight ray/triangle test of Woop, Benthin and Wald, "Watertight Ray/Triangle
//! Intersection", Journal of Computer Graphics Techniques 2(1), 2013.
//!
//! The ray is turned into the +Z axis of a sheared frame (its largest direction component
//! becomes Z, the other two are sheared away), the triangle's vertices are moved into that
//! frame, and the hit is decided by the signs of three 2D edge functions. Two triangles that share
//! an edge evaluate that edge's function on the same two (rounded) vertices, with opposite signs,
//! so no ray passes between them; an edge function that rounds to exactly zero is recomputed in
//! double precision, as the paper does. Every triangle test of this crate (traversal and brute
//! force alike) goes through [`WatertightRay::intersect`].

use glam::Vec3;

/// A triangle hit found by [`WatertightRay::intersect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    /// Ray parameter, in units of the ray's direction.
    pub t: f32,
    /// Barycentric weight of vertex 1.
    pub b1: f32,
    /// Barycentric weight of vertex 2.
    pub b2: f32,
}

/// A ray prepared for the watertight test: the axis permutation and shear that map its
/// direction to +Z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WatertightRay {
    origin: Vec3,
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl WatertightRay {
    /// Prepares a ray. `direction` must be finite with a non-zero component (a valid
    /// [`crate::Ray`] is); it need not be unit length.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        let a = direction.abs();
        // The dimension where the direction is largest becomes z.
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        let d = direction.to_array();
        // Swap to keep the winding of the triangle (and so the sign of the edge functions)
        // independent of the direction's sign.
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Self {
            origin,
            kx,
            ky,
            kz,
            sx: d[kx] / d[kz],
            sy: d[ky] / d[kz],
            sz: 1.0 / d[kz],
        }
    }

    /// The ray's origin.
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// Intersects triangle `(v0, v1, v2)`, either side, for `t` in the open interval
    /// `(t_min, t_max)`.
    #[inline(always)]
    pub fn intersect(
        &self,
        v0: Vec3,
        v1: Vec3,
        v2: Vec3,
        t_min: f32,
        t_max: f32,
    ) -> Option<TriangleHit> {
        let (kx, ky, kz) = (self.kx, self.ky, self.kz);
        let a = (v0 - self.origin).to_array();
        let b = (v1 - self.origin).to_array();
        let c = (v2 - self.origin).to_array();
        let ax = a[kx] - self.sx * a[kz];
        let ay = a[ky] - self.sy * a[kz];
        let bx = b[kx] - self.sx * b[kz];
        let by = b[ky] - self.sy * b[kz];
        let cx = c[kx] - self.sx * c[kz];
        let cy = c[ky] - self.sy * c[kz];

        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let (ax, ay, bx, by, cx, cy) = (
                f64::from(ax),
                f64::from(ay),
                f64::from(bx),
                f64::from(by),
                f64::from(cx),
                f64::from(cy),
            );
            u = (cx * by - cy * bx) as f32;
            v = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let az = self.sz * a[kz];
        let bz = self.sz * b[kz];
        let cz = self.sz * c[kz];
        let inv_det = 1.0 / det;
        let t = (u * az + v * bz + w * cz) * inv_det;
        if t > t_min && t < t_max {
            Some(TriangleHit {
                t,
                b1: v * inv_det,
                b2: w * inv_det,
            })
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: [Vec3; 3] = [
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];

    fn hit(o: Vec3, d: Vec3) -> Option<TriangleHit> {
        WatertightRay::new(o, d).intersect(TRI[0], TRI[1], TRI[2], 0.0, f32::INFINITY)
    }

    #[test]
    fn hits_report_t_and_barycentrics() {
        let h = hit(Vec3::new(0.25, 0.5, 2.0), Vec3::new(0.0, 0.0, -0.5)).unwrap();
        assert!((h.t - 4.0).abs() < 1e-6, "{h:?}");
        assert!(
            (h.b1 - 0.25).abs() < 1e-6 && (h.b2 - 0.5).abs() < 1e-6,
            "{h:?}"
        );
        // From behind: no culling of either side.
        let h = hit(Vec3::new(0.25, 0.5, -1.0), Vec3::Z).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
        assert!(hit(Vec3::new(0.75, 0.75, 1.0), Vec3::NEG_Z).is_none());
        assert!(hit(Vec3::new(0.25, 0.25, 1.0), Vec3::Z).is_none(), "behind");
    }

    #[test]
    fn interval_is_open() {
        let r = WatertightRay::new(Vec3::new(0.2, 0.2, 1.0), Vec3::NEG_Z);
        let t = r
            .intersect(TRI[0], TRI[1], TRI[2], 0.0, f32::INFINITY)
            .unwrap()
            .t;
        assert_eq!(t, 1.0);
        assert!(r.intersect(TRI[0], TRI[1], TRI[2], 0.0, t).is_none());
        assert!(r.intersect(TRI[0], TRI[1], TRI[2], t, 2.0).is_none());
    }

    #[test]
    fn rays_through_a_shared_edge_hit_one_of_the_two_triangles() {
        // A quad split along its diagonal; rays aimed at points of the diagonal.
        let q = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let mut state = 12345u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        for _ in 0..10_000 {
            let s = next();
            let target = q[0].lerp(q[2], s);
            let origin = Vec3::new(next() * 4.0 - 2.0, next() * 4.0 - 2.0, 0.5 + next() * 1e3);
            let r = WatertightRay::new(origin, target - origin);
            let a = r.intersect(q[0], q[1], q[2], 0.0, f32::INFINITY);
            let b = r.intersect(q[0], q[2], q[3], 0.0, f32::INFINITY);
            assert!(a.is_some() || b.is_some(), "{origin} -> {target} escaped");
        }
    }
}
