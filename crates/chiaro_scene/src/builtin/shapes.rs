//! Mesh data for the built-in scenes: quads, boxes and icospheres, with flat or smooth normals.

use std::collections::HashMap;
use std::ops::Range;

use glam::{Vec2, Vec3};

use crate::mesh_repair::MeshData;

/// A planar quad through corners `c` (in order around the edge), two triangles wound so their
/// normal points to the `facing` side, flat normals and UVs over [0, 1]^2.
pub fn quad(c: [Vec3; 4], facing: Vec3) -> MeshData {
    let mut data = MeshData::default();
    append_quad(&mut data, c, facing);
    data
}

/// Appends a quad (see [`quad`]) to `data`.
pub fn append_quad(data: &mut MeshData, c: [Vec3; 4], facing: Vec3) {
    let mut normal = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
    let mut order = [0usize, 1, 2, 3];
    if normal.dot(facing) < 0.0 {
        normal = -normal;
        order = [0, 3, 2, 1];
    }
    let base = data.positions.len() as u32;
    let uvs = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
    for &k in &order {
        data.positions.push(c[k]);
        data.normals.get_or_insert_with(Vec::new).push(normal);
        data.uvs[0].get_or_insert_with(Vec::new).push(uvs[k]);
    }
    data.indices
        .get_or_insert_with(Vec::new)
        .extend([0, 1, 2, 0, 2, 3].map(|i| base + i));
}

/// Appends a band of a surface of revolution about the Y axis to `data`: `segments` quads from
/// angle `arc.start` to `arc.end` (radians, `start < end`, counter-clockwise seen from +Y: +X
/// toward -Z) between the circle of radius `from.x` at height `from.y` and that of radius `to.x`
/// at height `to.y`. Smooth normals point to the left of the profile from `from` to `to`: away
/// from the axis on a rising wall (a cylinder or cone), up on a disc shrinking toward the axis.
/// A zero radius closes the band to the axis with one triangle a segment (a disc, a cone's tip).
/// UVs run over [0, 1] along the arc and the profile.
pub fn append_band(data: &mut MeshData, from: Vec2, to: Vec2, arc: Range<f32>, segments: u32) {
    let d = to - from;
    let normal = Vec2::new(d.y, -d.x).normalize();
    for k in 0..segments {
        let base = data.positions.len() as u32;
        for (step, ring, v) in [
            (k, from, 0.0),
            (k + 1, from, 0.0),
            (k + 1, to, 1.0),
            (k, to, 1.0),
        ] {
            let u = step as f32 / segments as f32;
            let (sin, cos) = (arc.start + u * (arc.end - arc.start)).sin_cos();
            let radial = Vec3::new(cos, 0.0, -sin);
            data.positions.push(radial * ring.x + Vec3::Y * ring.y);
            data.normals
                .get_or_insert_with(Vec::new)
                .push(radial * normal.x + Vec3::Y * normal.y);
            data.uvs[0]
                .get_or_insert_with(Vec::new)
                .push(Vec2::new(u, v));
        }
        // Corners 0 and 1 meet on the axis when `from` is on it, 2 and 3 when `to` is.
        let indices = data.indices.get_or_insert_with(Vec::new);
        if from.x != 0.0 {
            indices.extend([0, 1, 2].map(|i| base + i));
        }
        if to.x != 0.0 {
            indices.extend([0, 2, 3].map(|i| base + i));
        }
    }
}

/// An axis-aligned square of side `size` in the XZ plane at y = 0, facing +Y.
pub fn floor(size: f32) -> MeshData {
    let h = 0.5 * size;
    quad(
        [
            Vec3::new(-h, 0.0, -h),
            Vec3::new(h, 0.0, -h),
            Vec3::new(h, 0.0, h),
            Vec3::new(-h, 0.0, h),
        ],
        Vec3::Y,
    )
}

/// A closed polyhedron from its quad faces, each wound to face away from the centroid of all
/// corners (right for convex shapes).
pub fn closed_quads(faces: &[[Vec3; 4]]) -> MeshData {
    let corners = faces.iter().flatten();
    let center = corners.clone().sum::<Vec3>() / corners.count().max(1) as f32;
    let mut data = MeshData::default();
    for &face in faces {
        let face_center = face.iter().sum::<Vec3>() / 4.0;
        append_quad(&mut data, face, face_center - center);
    }
    data
}

/// Coordinates from `lo` to `hi` (both included) that crowd around `focus`: focus +- finest x
/// 2^k for k = 0, 1, ... wherever they fall strictly inside, so each gap is at most about its
/// distance from the focus.
fn graded_lines(lo: f32, hi: f32, focus: f32, finest: f32) -> Vec<f32> {
    let mut lines = vec![lo, hi];
    let mut step = finest;
    while focus - step > lo || focus + step < hi {
        lines.extend(
            [focus - step, focus + step]
                .into_iter()
                .filter(|x| *x > lo && *x < hi),
        );
        step *= 2.0;
    }
    lines.sort_by(f32::total_cmp);
    lines
}

/// An axis-aligned box from `min` to `max` whose top and bottom faces are grids graded toward
/// `focus` (x, z), cells from `finest` wide there, doubling outward, and whose sides follow
/// the same grid lines (no T-junctions). Near the focus every triangle is about as small as
/// its distance from it, so f32 resolves a point there to the precision of that distance,
/// not to that of the box's size (two triangles 1e5 wide seen from 1e-3 away lose every
/// digit of their plane where the camera looks).
pub fn graded_box(min: Vec3, max: Vec3, focus: Vec2, finest: f32) -> MeshData {
    let xs = graded_lines(min.x, max.x, focus.x, finest);
    let zs = graded_lines(min.z, max.z, focus.y, finest);
    let mut data = MeshData::default();
    for x in xs.windows(2) {
        for z in zs.windows(2) {
            for (y, facing) in [(max.y, Vec3::Y), (min.y, Vec3::NEG_Y)] {
                let c = [
                    Vec3::new(x[0], y, z[0]),
                    Vec3::new(x[1], y, z[0]),
                    Vec3::new(x[1], y, z[1]),
                    Vec3::new(x[0], y, z[1]),
                ];
                append_quad(&mut data, c, facing);
            }
        }
    }
    for (x, facing) in [(min.x, Vec3::NEG_X), (max.x, Vec3::X)] {
        for z in zs.windows(2) {
            let c = [
                Vec3::new(x, min.y, z[0]),
                Vec3::new(x, min.y, z[1]),
                Vec3::new(x, max.y, z[1]),
                Vec3::new(x, max.y, z[0]),
            ];
            append_quad(&mut data, c, facing);
        }
    }
    for (z, facing) in [(min.z, Vec3::NEG_Z), (max.z, Vec3::Z)] {
        for x in xs.windows(2) {
            let c = [
                Vec3::new(x[0], min.y, z),
                Vec3::new(x[1], min.y, z),
                Vec3::new(x[1], max.y, z),
                Vec3::new(x[0], max.y, z),
            ];
            append_quad(&mut data, c, facing);
        }
    }
    data
}

/// The six faces of the axis-aligned box from `min` to `max`, corners in order around each: at
/// -X, +X, -Y (the floor of a room), +Y, -Z, +Z.
pub fn box_faces(min: Vec3, max: Vec3) -> [[Vec3; 4]; 6] {
    let corner = |x: usize, y: usize, z: usize| {
        Vec3::new([min.x, max.x][x], [min.y, max.y][y], [min.z, max.z][z])
    };
    let x = |at| [(at, 0, 0), (at, 1, 0), (at, 1, 1), (at, 0, 1)];
    let y = |at| [(0, at, 0), (1, at, 0), (1, at, 1), (0, at, 1)];
    let z = |at| [(0, 0, at), (1, 0, at), (1, 1, at), (0, 1, at)];
    [x(0), x(1), y(0), y(1), z(0), z(1)].map(|face| face.map(|(i, j, k)| corner(i, j, k)))
}

/// Appends the axis-aligned box from `min` to `max` to `data`: six outward-facing quads.
pub fn append_cuboid(data: &mut MeshData, min: Vec3, max: Vec3) {
    let center = 0.5 * (min + max);
    for face in box_faces(min, max) {
        append_quad(data, face, face.iter().sum::<Vec3>() / 4.0 - center);
    }
}

/// An axis-aligned box from `min` to `max`, six outward-facing quads (12 triangles).
pub fn cuboid(min: Vec3, max: Vec3) -> MeshData {
    let mut data = MeshData::default();
    append_cuboid(&mut data, min, max);
    data
}

/// The inside of a room, the axis-aligned box from `min` to `max` seen from within: its walls
/// and ceiling, and apart (for a material of its own) its floor, quads facing inward.
pub fn room(min: Vec3, max: Vec3) -> (MeshData, MeshData) {
    let center = 0.5 * (min + max);
    let (mut walls, mut floor) = (MeshData::default(), MeshData::default());
    for (k, face) in box_faces(min, max).into_iter().enumerate() {
        let facing = center - face.iter().sum::<Vec3>() / 4.0;
        append_quad(if k == 2 { &mut floor } else { &mut walls }, face, facing);
    }
    (walls, floor)
}

/// A table filling the box from `min` to `max` (metres): a top 4 cm thick on four legs 5 cm
/// square, set 5 cm in from its corners (60 triangles).
pub fn table(min: Vec3, max: Vec3) -> MeshData {
    let mut data = MeshData::default();
    let knee = max.y - 0.04;
    append_cuboid(&mut data, Vec3::new(min.x, knee, min.z), max);
    let (inset, leg) = (0.05, 0.05);
    for x in [min.x + inset, max.x - inset - leg] {
        for z in [min.z + inset, max.z - inset - leg] {
            let foot = Vec3::new(x, min.y, z);
            append_cuboid(&mut data, foot, foot + Vec3::new(leg, knee - min.y, leg));
        }
    }
    data
}

/// A unit-radius icosphere: an icosahedron subdivided `level` times (20 * 4^level triangles),
/// smooth normals, equirectangular UVs. `inward` flips winding and normals (to be seen from
/// inside).
pub fn icosphere(level: u32, inward: bool) -> MeshData {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                positions.push((positions[a as usize] + positions[b as usize]).normalize());
                positions.len() as u32 - 1
            })
        };
        faces = faces
            .iter()
            .flat_map(|&[a, b, c]| {
                let ab = midpoint(a, b, &mut positions);
                let bc = midpoint(b, c, &mut positions);
                let ca = midpoint(c, a, &mut positions);
                [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]
            })
            .collect();
    }
    let sign = if inward { -1.0 } else { 1.0 };
    let uvs = positions
        .iter()
        .map(|p| {
            Vec2::new(
                0.5 + p.z.atan2(p.x) / std::f32::consts::TAU,
                p.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI,
            )
        })
        .collect();
    let indices = faces
        .into_iter()
        .flat_map(|[a, b, c]| if inward { [a, c, b] } else { [a, b, c] })
        .collect();
    MeshData {
        normals: Some(positions.iter().map(|&p| p * sign).collect()),
        positions,
        uvs: [Some(uvs), None],
        indices: Some(indices),
        ..MeshData::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    fn outward_fraction(data: &MeshData, center: Vec3) -> f32 {
        let idx = data.indices.as_ref().unwrap();
        let out = idx
            .chunks_exact(3)
            .filter(|t| {
                let p = t
                    .iter()
                    .map(|&i| data.positions[i as usize])
                    .collect::<Vec<_>>();
                let n = (p[1] - p[0]).cross(p[2] - p[0]);
                n.dot((p[0] + p[1] + p[2]) / 3.0 - center) > 0.0
            })
            .count();
        out as f32 / (idx.len() / 3) as f32
    }

    #[test]
    fn icosphere_has_the_expected_triangles_and_winding() {
        for level in 0..3 {
            let (mesh, repairs) = Mesh::new("s", icosphere(level, false)).unwrap();
            assert!(repairs.is_empty());
            assert_eq!(mesh.triangle_count(), 20 * 4usize.pow(level));
        }
        assert_eq!(outward_fraction(&icosphere(2, false), Vec3::ZERO), 1.0);
        assert_eq!(outward_fraction(&icosphere(2, true), Vec3::ZERO), 0.0);
    }

    #[test]
    fn cuboid_faces_point_out() {
        let data = cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0));
        assert_eq!(data.indices.as_ref().unwrap().len(), 36);
        assert_eq!(outward_fraction(&data, Vec3::new(0.5, 1.0, 1.5)), 1.0);
        for (p, n) in data.positions.iter().zip(data.normals.as_ref().unwrap()) {
            assert!(n.dot(*p - Vec3::new(0.5, 1.0, 1.5)) > 0.0);
        }
    }

    #[test]
    fn graded_box_is_closed_outward_and_fine_near_its_focus() {
        let (min, max) = (Vec3::new(-100.0, -50.0, -80.0), Vec3::new(60.0, 0.0, 90.0));
        let (focus, finest) = (Vec2::new(3.0, -2.0), 0.01);
        let data = graded_box(min, max, focus, finest);
        assert_eq!(outward_fraction(&data, 0.5 * (min + max)), 1.0);
        // Closed, no T-junctions: every edge belongs to exactly two triangles.
        let idx = data.indices.as_ref().unwrap();
        let key = |i: u32| data.positions[i as usize].to_array().map(f32::to_bits);
        let mut edges = HashMap::new();
        for t in idx.chunks_exact(3) {
            for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                let (a, b) = (key(a), key(b));
                *edges
                    .entry(if a < b { (a, b) } else { (b, a) })
                    .or_insert(0) += 1;
            }
        }
        assert!(edges.values().all(|&n| n == 2));
        // Every top triangle is at most about as large as its distance from the focus.
        let f = Vec3::new(focus.x, max.y, focus.y);
        for t in idx.chunks_exact(3) {
            let p = [t[0], t[1], t[2]].map(|i| data.positions[i as usize]);
            if p.iter().any(|q| q.y != max.y) {
                continue;
            }
            let longest = (0..3)
                .map(|k| p[k].distance(p[(k + 1) % 3]))
                .fold(0.0, f32::max);
            let nearest = p
                .iter()
                .map(|q| q.distance(f))
                .fold(f32::INFINITY, f32::min);
            assert!(longest <= 2.0 * nearest.max(2.0 * finest), "{p:?}");
        }
    }

    #[test]
    fn bands_wind_with_their_normals_and_close_on_the_axis() {
        // Every triangle's winding agrees with its vertices' normals.
        let agrees = |data: &MeshData| {
            let n = data.normals.as_ref().unwrap();
            data.indices.as_ref().unwrap().chunks_exact(3).all(|t| {
                let p = [t[0], t[1], t[2]].map(|i| data.positions[i as usize]);
                let face = (p[1] - p[0]).cross(p[2] - p[0]);
                t.iter().all(|&i| face.dot(n[i as usize]) > 0.0)
            })
        };
        let mut cone = MeshData::default();
        let half_turn = 0.0..std::f32::consts::PI;
        append_band(
            &mut cone,
            Vec2::new(1.0, 0.0),
            Vec2::new(0.5, 1.0),
            half_turn,
            12,
        );
        let (mesh, repairs) = Mesh::new("cone", cone.clone()).unwrap();
        assert!(repairs.is_empty());
        assert_eq!(mesh.triangle_count(), 24);
        assert!(agrees(&cone));
        assert_eq!(outward_fraction(&cone, Vec3::ZERO), 1.0);
        assert!(
            cone.positions.iter().all(|p| p.z <= 1e-6),
            "the half turn is on -Z"
        );

        let mut disc = MeshData::default();
        let full_turn = 0.0..std::f32::consts::TAU;
        append_band(
            &mut disc,
            Vec2::new(1.0, 2.0),
            Vec2::new(0.0, 2.0),
            full_turn,
            16,
        );
        let (mesh, repairs) = Mesh::new("disc", disc.clone()).unwrap();
        assert!(repairs.is_empty());
        assert_eq!(mesh.triangle_count(), 16);
        assert!(agrees(&disc));
        assert!(disc.normals.as_ref().unwrap().iter().all(|n| *n == Vec3::Y));
    }

    #[test]
    fn quad_faces_the_requested_side() {
        let c = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, 1.0), Vec3::Z];
        for facing in [Vec3::Y, Vec3::NEG_Y] {
            let data = quad(c, facing);
            let p = &data.positions;
            assert!((p[1] - p[0]).cross(p[2] - p[0]).dot(facing) > 0.0);
            assert_eq!(data.normals.as_ref().unwrap()[0], facing);
        }
    }
}
