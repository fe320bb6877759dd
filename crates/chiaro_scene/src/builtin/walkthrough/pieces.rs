//! The walkthrough's meshes: fluted columns, sculptures, arches, paving, facades, stairs and
//! the small pieces (doors, a fan, foliage). Each large piece is its own mesh, shaped by the
//! seeded layout generator, so no two are alike; the small pieces are meshes shared by
//! instances.

use std::f32::consts::{PI, TAU};

use glam::{Quat, Vec2, Vec3};

use crate::builtin::Layout;
use crate::builtin::shapes::{append_quad, closed_quads, cuboid};
use crate::mesh_repair::MeshData;

use super::surface::{Grid, merge, smoothstep};

/// Length of one bay of the street along -Z, metres.
pub const BAY: f32 = 6.0;
/// Distance of the column rows from the street's axis.
pub const COLUMN_X: f32 = 4.0;
/// Distance of the facades from the street's axis.
pub const WALL_X: f32 = 7.0;
/// Height of a facade.
pub const WALL_HEIGHT: f32 = 9.0;
/// Height of a column's base block.
pub const BASE_HEIGHT: f32 = 0.3;
/// Height of a column's shaft.
pub const SHAFT_HEIGHT: f32 = 4.7;
/// Height of a column's capital block.
pub const CAPITAL_HEIGHT: f32 = 0.3;
/// Height where the arches spring from the capitals.
pub const SPRING_HEIGHT: f32 = BASE_HEIGHT + SHAFT_HEIGHT + CAPITAL_HEIGHT;
/// Height of a sculpture's pedestal.
pub const PEDESTAL_HEIGHT: f32 = 1.0;

/// Three random phases in [0, 2 pi).
fn phases(rng: &mut Layout) -> [f32; 3] {
    [
        rng.range(0.0, TAU),
        rng.range(0.0, TAU),
        rng.range(0.0, TAU),
    ]
}

/// A fluted column shaft standing on y = 0, 20 flutes, a slight entasis and weathering of its
/// own: `24 detail` by `40 detail` quads.
pub fn column_shaft(rng: &mut Layout, detail: u32) -> MeshData {
    let radius = 0.35;
    let [a, b, c] = phases(rng);
    let wear = rng.range(0.002, 0.008);
    let mut data = MeshData::default();
    Grid::new(24 * detail, 40 * detail)
        .textured(Vec2::new(1.0, 2.0))
        .append(&mut data, |u, v| {
            let theta = TAU * u;
            let h = v * SHAFT_HEIGHT;
            let entasis = 1.0 - 0.12 * v * v;
            let flute = 0.03 * (0.5 + 0.5 * (20.0 * theta).cos()).powi(2);
            let weathering = wear
                * ((3.0 * theta + a + 5.0 * h).sin()
                    + (7.0 * h + b).sin() * (2.0 * theta + c).cos());
            let r = radius * entasis - flute + weathering;
            Vec3::new(r * theta.cos(), h, -r * theta.sin())
        });
    data
}

/// The six (face, u axis, v axis) triples of a cube, u x v = face.
const CUBE_FACES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::Y, Vec3::Z),
    (Vec3::NEG_X, Vec3::Z, Vec3::Y),
    (Vec3::Y, Vec3::Z, Vec3::X),
    (Vec3::NEG_Y, Vec3::X, Vec3::Z),
    (Vec3::Z, Vec3::X, Vec3::Y),
    (Vec3::NEG_Z, Vec3::Y, Vec3::X),
];

/// An abstract sculpture about 2 m tall, its foot at the origin: a sphere swollen by five
/// random lobes and rippled, tessellated as a cube sphere of `6 (20 detail)^2` quads.
pub fn sculpture(rng: &mut Layout, detail: u32) -> MeshData {
    let lobes: Vec<(Vec3, f32, f32)> = (0..5)
        .map(|_| {
            let dir = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-0.3, 1.0),
                rng.range(-1.0, 1.0),
            )
            .normalize();
            (dir, rng.range(0.15, 0.4), rng.range(3.0, 9.0))
        })
        .collect();
    let [a, b, _] = phases(rng);
    let ripples = rng.range(6.0, 12.0);
    let shape = move |d: Vec3| {
        let swell: f32 = lobes
            .iter()
            .map(|&(c, amplitude, sharpness)| amplitude * (-sharpness * (1.0 - d.dot(c))).exp())
            .sum();
        let ripple = 0.02 * (ripples * d.y + a).sin() * (ripples * d.x + b).cos();
        let r = 0.45 + swell + ripple;
        d * r * Vec3::new(1.0, 1.6, 1.0) + Vec3::Y * 0.9
    };
    let n = 20 * detail;
    let mut data = MeshData::default();
    for (face, u_axis, v_axis) in CUBE_FACES {
        Grid::new(n, n).append(&mut data, |u, v| {
            shape((face + u_axis * (2.0 * u - 1.0) + v_axis * (2.0 * v - 1.0)).normalize())
        });
    }
    data
}

/// The arch over the street at z = 0 from one column row to the other, springing at
/// [`SPRING_HEIGHT`]: a rounded-square profile swept along a half circle, with wear of its own;
/// `8 detail` by `32 detail` quads.
pub fn arch(rng: &mut Layout, detail: u32) -> MeshData {
    let [a, b, _] = phases(rng);
    let mut data = MeshData::default();
    Grid::new(8 * detail, 32 * detail)
        .textured(Vec2::new(1.0, 6.0))
        .flipped()
        .append(&mut data, |u, v| {
            let psi = TAU * u;
            let phi = PI * v;
            // A superellipse of exponent 4: |x|^4 + |z|^4 = 1.
            let round = |c: f32| c.signum() * c.abs().sqrt();
            let wear = 0.01 * (9.0 * phi + a).sin() * (3.0 * psi + b).cos();
            let r = COLUMN_X + (0.3 + wear) * round(psi.cos());
            let z = (0.35 + wear) * round(psi.sin());
            Vec3::new(r * phi.cos(), SPRING_HEIGHT + r * phi.sin(), z)
        });
    data
}

/// One bay's paving, across the street from facade to facade, z from 0 to -[`BAY`], with a
/// gentle unevenness of its own; `24 detail` by `16 detail` quads.
pub fn paving(rng: &mut Layout, detail: u32) -> MeshData {
    let [a, b, c] = phases(rng);
    let mut data = MeshData::default();
    Grid::new(24 * detail, 16 * detail)
        .textured(Vec2::new(WALL_X, BAY / 2.0))
        .append(&mut data, |u, v| {
            let (x, z) = (WALL_X * (2.0 * u - 1.0), -BAY * v);
            let y = 0.004 * ((1.3 * x + a).sin() + (1.7 * z + b).sin() * (0.9 * x + c).cos());
            Vec3::new(x, y, z)
        });
    data
}

/// One bay's facade on the left (`side` -1, facing +X) or right (`side` 1, facing -X): dressed
/// stone with two recessed window panels; `16 detail` by `8 detail` quads.
pub fn facade(rng: &mut Layout, side: f32, detail: u32) -> MeshData {
    let depth = rng.range(0.15, 0.3);
    let [a, _, _] = phases(rng);
    let mut data = MeshData::default();
    let grid = Grid::new(16 * detail, 8 * detail).textured(Vec2::new(BAY / 2.0, WALL_HEIGHT / 2.0));
    let grid = if side > 0.0 { grid.flipped() } else { grid };
    grid.append(&mut data, |u, v| {
        let (z, y) = (-BAY * u, WALL_HEIGHT * v);
        let window =
            |lo: f32, hi: f32| smoothstep(lo, lo + 0.03, u) * (1.0 - smoothstep(hi - 0.03, hi, u));
        let panel = (window(0.15, 0.42) + window(0.58, 0.85))
            * smoothstep(0.38, 0.41, v)
            * (1.0 - smoothstep(0.72, 0.75, v));
        let relief = depth * panel + 0.01 * (4.0 * y + a).sin() * (3.0 * z).cos();
        Vec3::new(side * (WALL_X + relief), y, z)
    });
    data
}

/// A box of half extents `half` turned by `rotation` about its centre `center`.
pub fn turned_box(center: Vec3, half: Vec3, rotation: Quat) -> MeshData {
    let corner = |x: f32, y: f32, z: f32| center + rotation * (half * Vec3::new(x, y, z));
    let c = [
        corner(-1.0, -1.0, -1.0),
        corner(1.0, -1.0, -1.0),
        corner(1.0, 1.0, -1.0),
        corner(-1.0, 1.0, -1.0),
        corner(-1.0, -1.0, 1.0),
        corner(1.0, -1.0, 1.0),
        corner(1.0, 1.0, 1.0),
        corner(-1.0, 1.0, 1.0),
    ];
    closed_quads(&[
        [c[0], c[1], c[2], c[3]],
        [c[4], c[5], c[6], c[7]],
        [c[0], c[1], c[5], c[4]],
        [c[3], c[2], c[6], c[7]],
        [c[0], c[3], c[7], c[4]],
        [c[1], c[2], c[6], c[5]],
    ])
}

/// Stairs of `steps` steps up from z = 0 towards -Z across the street, with the landing
/// beyond them (`landing` deep): the stone the doors stand on.
pub fn stairs(steps: u32, landing: f32) -> MeshData {
    let (rise, run) = (0.18, 0.35);
    let mut data = MeshData::default();
    for k in 0..steps {
        let top = rise * (k + 1) as f32;
        let front = -run * k as f32;
        let back = if k + 1 == steps {
            front - run - landing
        } else {
            front - run
        };
        merge(
            &mut data,
            cuboid(Vec3::new(-WALL_X, 0.0, back), Vec3::new(WALL_X, top, front)),
        );
    }
    data
}

/// Height of the landing the stairs of `steps` steps lead to.
pub fn stairs_height(steps: u32) -> f32 {
    0.18 * steps as f32
}

/// The end wall across the street at z = 0 with a doorway `door_width` wide and
/// `door_height` tall in its middle.
pub fn end_wall(door_width: f32, door_height: f32) -> MeshData {
    let (half, thick) = (0.5 * door_width, 0.4);
    let mut data = MeshData::default();
    for (min, max) in [
        (
            Vec3::new(-WALL_X, 0.0, -thick),
            Vec3::new(-half, WALL_HEIGHT, 0.0),
        ),
        (
            Vec3::new(half, 0.0, -thick),
            Vec3::new(WALL_X, WALL_HEIGHT, 0.0),
        ),
        (
            Vec3::new(-half, door_height, -thick),
            Vec3::new(half, WALL_HEIGHT, 0.0),
        ),
    ] {
        merge(&mut data, cuboid(min, max));
    }
    data
}

/// A fan of five blades about its hub at the origin, turning about Z.
pub fn fan() -> MeshData {
    let mut data = MeshData::default();
    merge(
        &mut data,
        turned_box(Vec3::ZERO, Vec3::new(0.12, 0.12, 0.1), Quat::IDENTITY),
    );
    for k in 0..5 {
        let angle = TAU * k as f32 / 5.0;
        let turn = Quat::from_rotation_z(angle) * Quat::from_rotation_x(0.35);
        let center = Quat::from_rotation_z(angle) * Vec3::new(0.0, 0.5, 0.0);
        merge(
            &mut data,
            turned_box(center, Vec3::new(0.1, 0.4, 0.01), turn),
        );
    }
    data
}

/// A plant: four crossed upright quads 1.2 m tall, for an alpha-masked leaf texture (stem at
/// the bottom of the texture).
pub fn plant() -> MeshData {
    let (w, h) = (0.45, 1.2);
    let mut data = MeshData::default();
    for k in 0..4 {
        let d = Quat::from_rotation_y(PI * k as f32 / 4.0) * Vec3::X * w;
        append_quad(
            &mut data,
            [-d + Vec3::Y * h, d + Vec3::Y * h, d, -d],
            d.cross(Vec3::Y),
        );
    }
    data
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::walkthrough::surface::tests::normals_face_out;

    #[test]
    fn every_piece_faces_out() {
        let mut rng = Layout::new(3);
        for (name, data) in [
            ("column", column_shaft(&mut rng, 1)),
            ("sculpture", sculpture(&mut rng, 1)),
            ("arch", arch(&mut rng, 1)),
            ("paving", paving(&mut rng, 1)),
            ("left facade", facade(&mut rng, -1.0, 1)),
            ("right facade", facade(&mut rng, 1.0, 1)),
            ("stairs", stairs(4, 2.0)),
            ("end wall", end_wall(2.0, 3.0)),
            ("fan", fan()),
        ] {
            normals_face_out(&data).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }

    #[test]
    fn facades_face_the_street_and_paving_faces_up() {
        let mut rng = Layout::new(3);
        let left = facade(&mut rng, -1.0, 1);
        assert!(left.normals.unwrap()[0].x > 0.9);
        let right = facade(&mut rng, 1.0, 1);
        assert!(right.normals.unwrap()[0].x < -0.9);
        let paving = paving(&mut rng, 1);
        assert!(paving.normals.unwrap().iter().all(|n| n.y > 0.99));
    }

    #[test]
    fn two_columns_differ_and_the_same_seed_repeats_one() {
        let a = column_shaft(&mut Layout::new(1), 1);
        let b = column_shaft(&mut Layout::new(2), 1);
        assert_eq!(a, column_shaft(&mut Layout::new(1), 1));
        assert_ne!(a.positions, b.positions);
    }
}
