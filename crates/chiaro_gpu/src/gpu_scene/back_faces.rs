//! Which instances the G-buffer may draw without their back faces.
//!
//! The G-buffer draws back faces (a back face of a single-sided material is a surface that
//! does not shade, as the CPU reference sees it), but where no back face can be the nearest
//! surface along any camera ray, dropping them leaves the image as it was and saves the
//! rasterizer half the triangles of a closed mesh. That holds when
//! - the mesh is closed and faces outward: with corners welded by position, every edge is in
//!   exactly two triangles, once in each direction, and every connected part encloses a
//!   positive signed volume (so a ray from outside a part enters it through a front face first);
//! - the material is not alpha-masked (a hole would show the inside);
//! - the instance does not mirror (its front faces wind the other way);
//! - the camera is a perspective one whose eye, and the near plane around it (the rasterizer
//!   clips nearer points), lie outside the instance's world-space bounds.

use std::collections::HashMap;

use glam::{BVec3, Vec3};

/// Object-space bounds of a mesh that is closed and faces outward (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosedBounds {
    /// Least corner.
    pub min: Vec3,
    /// Greatest corner.
    pub max: Vec3,
}

/// The bounds of the mesh (`positions`, triangle list `indices`) when it is closed and faces
/// outward; `None` otherwise (including a mesh without triangles).
pub fn closed_bounds(positions: &[Vec3], indices: &[u32]) -> Option<ClosedBounds> {
    if indices.is_empty() || !indices.len().is_multiple_of(3) {
        return None;
    }
    // Weld corners by exact position, each vertex looked up once.
    const UNSEEN: u32 = u32::MAX;
    let mut welded: HashMap<[u32; 3], u32> = HashMap::new();
    let mut weld_of_vertex = vec![UNSEEN; positions.len()];
    let mut points = Vec::new();
    let mut ids = Vec::with_capacity(indices.len());
    for &i in indices {
        let slot = weld_of_vertex.get_mut(i as usize)?;
        if *slot == UNSEEN {
            let p = positions[i as usize];
            let next = points.len() as u32;
            *slot = *welded.entry(p.to_array().map(f32::to_bits)).or_insert(next);
            if *slot == next {
                points.push(p);
            }
        }
        ids.push(*slot);
    }
    // Every directed edge once, and its reverse once.
    let mut edges: Vec<u64> = Vec::with_capacity(ids.len());
    for t in ids.chunks_exact(3) {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a == b {
                return None;
            }
            edges.push((u64::from(a) << 32) | u64::from(b));
        }
    }
    edges.sort_unstable();
    if edges.windows(2).any(|w| w[0] == w[1]) {
        return None;
    }
    let reversed = |e: u64| e.rotate_right(32);
    if edges
        .iter()
        .any(|&e| edges.binary_search(&reversed(e)).is_err())
    {
        return None;
    }
    // Signed volume per connected part (parts joined through shared corners).
    let mut parent: Vec<u32> = (0..points.len() as u32).collect();
    fn root(parent: &mut [u32], mut i: u32) -> u32 {
        while parent[i as usize] != i {
            let up = parent[parent[i as usize] as usize];
            parent[i as usize] = up;
            i = up;
        }
        i
    }
    for t in ids.chunks_exact(3) {
        for k in 1..3 {
            let (a, b) = (root(&mut parent, t[0]), root(&mut parent, t[k]));
            parent[a as usize] = b;
        }
    }
    let mut volume: HashMap<u32, f64> = HashMap::new();
    for t in ids.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| points[t[k] as usize].as_dvec3());
        *volume.entry(root(&mut parent, t[0])).or_default() += a.dot(b.cross(c)) / 6.0;
    }
    if volume.values().any(|&v| v <= 0.0) {
        return None;
    }
    let (min, max) = points.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    Some(ClosedBounds { min, max })
}

/// A perspective camera as the back-face test needs it.
#[derive(Clone, Copy, Debug)]
pub struct CullView {
    /// The eye.
    pub eye: Vec3,
    /// The farthest the near plane's points are from the eye (the rasterizer clips nearer
    /// points, so a surface within it may be cut open).
    pub near_reach: f32,
}

/// The world bounds of an instance that may drop its back faces whatever the camera, with
/// object-to-world rows `object_to_world` (3x4, translation in w), of a mesh with `bounds`
/// (`None`: not closed and outward), whose material is `alpha_masked` or not; `None` where the
/// instance must keep them. Made when the scene changes; [`eye_outside`] decides per frame.
pub fn cullable_box(
    bounds: Option<ClosedBounds>,
    object_to_world: &[[f32; 4]; 3],
    alpha_masked: bool,
) -> Option<ClosedBounds> {
    let bounds = bounds?;
    let row = |r: usize| {
        Vec3::new(
            object_to_world[r][0],
            object_to_world[r][1],
            object_to_world[r][2],
        )
    };
    let (r0, r1, r2) = (row(0), row(1), row(2));
    let determinant = r0.dot(r1.cross(r2));
    // A mirroring (or degenerate, or NaN) transform turns the front faces round.
    if alpha_masked || determinant.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    // World bounds of the eight corners.
    let translation = Vec3::new(
        object_to_world[0][3],
        object_to_world[1][3],
        object_to_world[2][3],
    );
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for corner in 0..8 {
        let upper = BVec3::new(corner & 1 != 0, corner & 2 != 0, corner & 4 != 0);
        let p = Vec3::select(upper, bounds.max, bounds.min);
        let w = Vec3::new(r0.dot(p), r1.dot(p), r2.dot(p)) + translation;
        lo = lo.min(w);
        hi = hi.max(w);
    }
    (lo.is_finite() && hi.is_finite()).then_some(ClosedBounds { min: lo, max: hi })
}

/// Whether `view` (`None`: an orthographic camera) sees the instance with world bounds
/// `world` ([`cullable_box`]) from outside, its near plane included, so that it may be drawn
/// without back faces.
pub fn eye_outside(world: ClosedBounds, view: Option<CullView>) -> bool {
    let Some(view) = view else {
        return false;
    };
    if !(view.eye.is_finite() && view.near_reach.is_finite()) {
        return false;
    }
    // Distance from the eye to the box, against the near plane's reach with a relative margin.
    let (lo, hi) = (world.min, world.max);
    let outside = (lo - view.eye).max(view.eye - hi).max(Vec3::ZERO);
    let margin = 1e-3 * (hi - lo).length().max(view.eye.abs().max_element());
    outside.length() > view.near_reach + margin
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube's 12 triangles, counter-clockwise seen from outside, over 8 shared corners.
    fn cube() -> (Vec<Vec3>, Vec<u32>) {
        let p = (0..8)
            .map(|i| Vec3::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let quads = [
            [0, 2, 3, 1], // z = 0, facing -z
            [4, 5, 7, 6], // z = 1
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = 1
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = 1
        ];
        let i = quads
            .iter()
            .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
            .collect();
        (p, i)
    }

    /// Both halves of the test, as the G-buffer applies them.
    fn front_faces_suffice(
        bounds: Option<ClosedBounds>,
        object_to_world: &[[f32; 4]; 3],
        alpha_masked: bool,
        view: Option<CullView>,
    ) -> bool {
        cullable_box(bounds, object_to_world, alpha_masked).is_some_and(|b| eye_outside(b, view))
    }

    const IDENTITY: [[f32; 4]; 3] = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ];

    #[test]
    fn a_cube_is_closed_and_faces_out() {
        let (p, i) = cube();
        let b = closed_bounds(&p, &i).unwrap();
        assert_eq!((b.min, b.max), (Vec3::ZERO, Vec3::ONE));
    }

    #[test]
    fn open_inside_out_or_part_inside_out_meshes_are_not() {
        let (p, i) = cube();
        assert_eq!(closed_bounds(&p, &i[6..]), None, "a face missing");
        let flipped: Vec<u32> = i.chunks_exact(3).flat_map(|t| [t[0], t[2], t[1]]).collect();
        assert_eq!(closed_bounds(&p, &flipped), None, "inside out");
        // A second, inside-out cube beside the first: the total volume is 0 here, so make the
        // outward one larger; the inside-out part still refuses the mesh.
        let mut two = p.iter().map(|v| *v * 3.0).collect::<Vec<_>>();
        two.extend(p.iter().map(|v| *v + Vec3::X * 5.0));
        let mut ids = i.clone();
        ids.extend(flipped.iter().map(|k| k + 8));
        assert_eq!(closed_bounds(&two, &ids), None, "one part inside out");
        assert_eq!(closed_bounds(&p, &[]), None);
    }

    #[test]
    fn split_corners_are_welded() {
        // Every triangle with corners of its own (as at UV seams): closed once welded.
        let (p, i) = cube();
        let split: Vec<Vec3> = i.iter().map(|&k| p[k as usize]).collect();
        let ids: Vec<u32> = (0..split.len() as u32).collect();
        assert!(closed_bounds(&split, &ids).is_some());
    }

    #[test]
    fn back_faces_drop_only_for_an_eye_well_outside() {
        let b = closed_bounds(&cube().0, &cube().1);
        let view = |eye: Vec3| {
            Some(CullView {
                eye,
                near_reach: 0.1,
            })
        };
        let far = view(Vec3::new(0.5, 0.5, 5.0));
        assert!(front_faces_suffice(b, &IDENTITY, false, far));
        assert!(
            !front_faces_suffice(b, &IDENTITY, false, view(Vec3::splat(0.5))),
            "inside"
        );
        let near = view(Vec3::new(0.5, 0.5, 1.05));
        assert!(
            !front_faces_suffice(b, &IDENTITY, false, near),
            "within the near plane"
        );
        assert!(
            !front_faces_suffice(b, &IDENTITY, true, far),
            "alpha-masked"
        );
        assert!(
            !front_faces_suffice(b, &IDENTITY, false, None),
            "orthographic"
        );
        assert!(
            !front_faces_suffice(None, &IDENTITY, false, far),
            "not closed"
        );
        let mut mirror = IDENTITY;
        mirror[0][0] = -1.0;
        assert!(!front_faces_suffice(b, &mirror, false, far), "mirrored");
        // Moved and scaled: the world bounds follow the instance.
        let moved = [
            [2.0, 0.0, 0.0, 10.0],
            [0.0, 2.0, 0.0, 0.0],
            [0.0, 0.0, 2.0, 0.0],
        ];
        assert!(!front_faces_suffice(
            b,
            &moved,
            false,
            view(Vec3::new(11.0, 1.0, 1.0))
        ));
        assert!(front_faces_suffice(
            b,
            &moved,
            false,
            view(Vec3::new(0.5, 0.5, 0.5))
        ));
    }
}
