//! `builtin:walkthrough`: a colonnaded street to walk down, procedural but built like a game
//! level, for measuring chiaro on a large scene that moves.
//!
//! Each bay of the street (6 m) has two fluted columns carrying an arch across it, paving,
//! facades with recessed windows on both sides, an abstract sculpture on a pedestal, planters
//! with alpha-masked foliage, a bench, an emissive sign and eight lights (four lanterns and
//! sconces, two spots, two uplights). Stairs lead up to an end wall with two doors that open
//! and close, and a fan that turns above them; two balls, one steel and one glass, travel the
//! street. A sun and a sky light it from above. The camera walks the street on a scripted
//! path.
//!
//! Columns, arches, sculptures, paving and facades are each a mesh of their own, shaped by a
//! seeded generator: every triangle is unique. Bases, capitals, pedestals, planters, plants,
//! benches, door leaves and balls are shared meshes, instanced. Motion is animation clips,
//! played by the ECS animation system ([`crate::animation`]).
//!
//! Parameters: `size` (bays, default [`DEFAULT_BAYS`]), `detail` (tessellation, default
//! [`DEFAULT_DETAIL`]; triangles grow with its square), `seed` (default 1). The defaults make
//! about 1.3 million triangles.

mod materials;
mod motion;
mod pieces;
mod surface;
mod textures;

use glam::{Quat, Vec3};

use crate::components::{Camera, Light, LightKind, Projection};
use crate::error::SceneError;
use crate::mesh::MeshId;
use crate::mesh_repair::MeshData;
use crate::scene_builder::{Node, SceneBuilder};
use crate::transform::Transform;

use super::shapes::{cuboid, icosphere};
use super::{Layout, Params};
use pieces::{BAY, COLUMN_X, WALL_X};

pub use motion::{EYE_HEIGHT, SECONDS_PER_BAY};

/// Bays by default.
pub const DEFAULT_BAYS: usize = 8;
/// Most bays accepted.
pub const MAX_BAYS: usize = 64;
/// Tessellation detail by default.
pub const DEFAULT_DETAIL: usize = 4;
/// Most detail accepted.
pub const MAX_DETAIL: usize = 16;
/// Steps up to the end wall.
const STEPS: u32 = 6;

/// The length of the camera's path through a walkthrough of `bays` bays, seconds.
pub fn path_seconds(bays: usize) -> f64 {
    f64::from(SECONDS_PER_BAY) * bays as f64
}

/// Adds mesh `data`, which the generator made valid.
fn mesh(b: &mut SceneBuilder, name: &str, data: MeshData) -> Result<MeshId, SceneError> {
    let id = b.add_mesh(&format!("mesh \"{name}\""), name, data)?;
    Ok(id.expect("generated meshes have triangles"))
}

/// Adds a box mesh standing on y = 0, `half_x` and `half_z` from its axis, `height` tall: the
/// shared pieces (bases, capitals, pedestals, planters, benches).
fn block(
    b: &mut SceneBuilder,
    name: &str,
    half_x: f32,
    height: f32,
    half_z: f32,
) -> Result<MeshId, SceneError> {
    let min = Vec3::new(-half_x, 0.0, -half_z);
    mesh(b, name, cuboid(min, Vec3::new(half_x, height, half_z)))
}

/// Adds a light.
fn light(
    b: &mut SceneBuilder,
    name: String,
    transform: Transform,
    kind: LightKind,
    color: Vec3,
    intensity: f32,
) {
    b.add_node(Node {
        name: Some(name),
        transform,
        light: Some(Light {
            kind,
            color,
            intensity,
            range: None,
        }),
        ..Node::default()
    });
}

pub(super) fn build(b: &mut SceneBuilder, params: &mut Params) -> Result<(), SceneError> {
    let bays = params.count("size", DEFAULT_BAYS, MAX_BAYS)?;
    let detail = params.count("detail", DEFAULT_DETAIL, MAX_DETAIL)?;
    let seed = params.count("seed", 1, u32::MAX as usize)?;
    if bays == 0 || detail == 0 {
        return Err(params.error("size and detail must be at least 1".into()));
    }
    let (bays_u32, detail) = (bays as u32, detail as u32);
    let mut rng = Layout::new(seed as u64 ^ 0x57A1_C0DE_0000_0000);
    let palette = materials::add(b, textures::generate(seed as u32));
    b.set_environment(textures::sky());

    let base = block(b, "column base", 0.5, pieces::BASE_HEIGHT, 0.5)?;
    let capital = block(b, "capital", 0.55, pieces::CAPITAL_HEIGHT, 0.55)?;
    let pedestal = block(b, "pedestal", 0.5, pieces::PEDESTAL_HEIGHT, 0.5)?;
    let planter = block(b, "planter", 0.4, 0.5, 0.4)?;
    let bench = block(b, "bench", 0.25, 0.45, 1.0)?;
    let plant = mesh(b, "plant", pieces::plant())?;
    let sign = mesh(
        b,
        "sign",
        super::shapes::quad(
            [
                Vec3::new(0.0, 1.8, -2.65),
                Vec3::new(0.0, 1.8, -3.35),
                Vec3::new(0.0, 3.2, -3.35),
                Vec3::new(0.0, 3.2, -2.65),
            ],
            Vec3::X,
        ),
    )?;

    let warm = Vec3::new(1.0, 0.75, 0.45);
    for k in 0..bays {
        let z0 = -BAY * k as f32;
        let mid = z0 - 0.5 * BAY;
        let at = |x: f32, y: f32, z: f32| Transform::from_translation(Vec3::new(x, y, z));
        let paving = mesh(b, &format!("paving {k}"), pieces::paving(&mut rng, detail))?;
        b.add_instance(
            &format!("paving {k}"),
            paving,
            palette.marble,
            at(0.0, 0.0, z0),
        );
        for (side, name) in [(-1.0f32, "left"), (1.0, "right")] {
            let facade = mesh(
                b,
                &format!("{name} facade {k}"),
                pieces::facade(&mut rng, side, detail),
            )?;
            b.add_instance(
                &format!("{name} facade {k}"),
                facade,
                palette.stone,
                at(0.0, 0.0, z0),
            );
            let x = side * COLUMN_X;
            let shaft = mesh(
                b,
                &format!("{name} column {k}"),
                pieces::column_shaft(&mut rng, detail),
            )?;
            b.add_instance(
                &format!("{name} column {k}"),
                shaft,
                palette.stone,
                at(x, pieces::BASE_HEIGHT, mid),
            );
            b.add_instance(
                &format!("{name} base {k}"),
                base,
                palette.stone,
                at(x, 0.0, mid),
            );
            let capital_y = pieces::BASE_HEIGHT + pieces::SHAFT_HEIGHT;
            b.add_instance(
                &format!("{name} capital {k}"),
                capital,
                palette.stone,
                at(x, capital_y, mid),
            );
            // A planter with a plant, turned and sized at random, in front of the column.
            let (px, pz) = (side * (COLUMN_X - 0.9), mid + 1.2);
            b.add_instance(
                &format!("{name} planter {k}"),
                planter,
                palette.stone,
                at(px, 0.0, pz),
            );
            let turn = Quat::from_rotation_y(rng.range(0.0, std::f32::consts::TAU));
            let plant_at = at(px, 0.5, pz)
                .with_rotation(turn)
                .with_scale(Vec3::splat(rng.range(0.8, 1.3)));
            b.add_instance(
                &format!("{name} plant {k}"),
                plant,
                palette.foliage,
                plant_at,
            );
            light(
                b,
                format!("{name} lantern {k}"),
                at(side * (COLUMN_X - 0.5), 3.6, mid),
                LightKind::Point,
                warm,
                3.0,
            );
            light(
                b,
                format!("{name} sconce {k}"),
                at(side * (WALL_X - 0.3), 2.6, z0 - 1.5),
                LightKind::Point,
                warm,
                1.5,
            );
            light(
                b,
                format!("{name} uplight {k}"),
                at(px, 0.15, pz - 0.6),
                LightKind::Point,
                Vec3::new(0.6, 0.8, 1.0),
                0.8,
            );
        }
        let arch = mesh(b, &format!("arch {k}"), pieces::arch(&mut rng, detail))?;
        b.add_instance(&format!("arch {k}"), arch, palette.stone, at(0.0, 0.0, mid));

        // The sculpture under the colonnade, on the side the camera turns to at this bay.
        let side = if k % 2 == 1 { -1.0 } else { 1.0 };
        let (sx, sz) = (side * 5.6, z0 - 1.5);
        b.add_instance(
            &format!("pedestal {k}"),
            pedestal,
            palette.stone,
            at(sx, 0.0, sz),
        );
        let sculpture = mesh(
            b,
            &format!("sculpture {k}"),
            pieces::sculpture(&mut rng, detail),
        )?;
        let material = palette.sculptures[k % palette.sculptures.len()];
        let turn = Quat::from_rotation_y(rng.range(0.0, std::f32::consts::TAU));
        let pose = at(sx, pieces::PEDESTAL_HEIGHT, sz)
            .with_rotation(turn)
            .with_scale(Vec3::splat(0.8));
        b.add_instance(&format!("sculpture {k}"), sculpture, material, pose);
        let above = Vec3::new(sx - side * 1.5, 4.6, sz + 1.0);
        let aim = Transform::looking_at(above, Vec3::new(sx, 2.0, sz), Vec3::Y);
        let spot = LightKind::Spot {
            inner_cone_angle: 0.2,
            outer_cone_angle: 0.35,
        };
        light(b, format!("sculpture spot {k}"), aim, spot, Vec3::ONE, 25.0);
        let down = Transform::looking_at(
            Vec3::new(0.0, 8.0, mid),
            Vec3::new(0.0, 0.0, mid - 0.5),
            Vec3::Y,
        );
        let wide = LightKind::Spot {
            inner_cone_angle: 0.4,
            outer_cone_angle: 0.6,
        };
        light(b, format!("arch spot {k}"), down, wide, warm, 20.0);

        // A bench and a sign across the street from the sculpture.
        b.add_instance(
            &format!("bench {k}"),
            bench,
            palette.wood,
            at(-side * 5.4, 0.0, z0 - 3.0),
        );
        let sign_at = at(-side * (WALL_X - 0.05), 0.0, z0).with_rotation(Quat::from_rotation_y(
            if side > 0.0 {
                0.0
            } else {
                std::f32::consts::PI
            },
        ));
        let sign_material = palette.signs[k % palette.signs.len()];
        b.add_instance(&format!("sign {k}"), sign, sign_material, sign_at);
    }
    finish_street(b, &palette, bays_u32)?;

    let camera = b.add_node(Node {
        name: Some("camera".into()),
        transform: motion::camera_start(),
        camera: Some(Camera {
            projection: Projection::Perspective {
                yfov: 60f32.to_radians(),
                aspect_ratio: None,
                znear: 0.05,
                zfar: None,
            },
        }),
        ..Node::default()
    });
    b.add_animation(motion::camera_path(camera, bays_u32));
    Ok(())
}

/// The end of the street: stairs, the end wall with its doors and fan, the sun, and the balls
/// travelling the street.
fn finish_street(
    b: &mut SceneBuilder,
    palette: &materials::Palette,
    bays: u32,
) -> Result<(), SceneError> {
    let end = -BAY * bays as f32;
    let stairs = mesh(b, "stairs", pieces::stairs(STEPS, 3.0))?;
    b.add_instance(
        "stairs",
        stairs,
        palette.stone,
        Transform::from_translation(Vec3::Z * end),
    );
    let landing = pieces::stairs_height(STEPS);
    let wall_z = end - 0.35 * STEPS as f32 - 2.0;
    let (door_width, door_height) = (2.4, 3.2);
    let wall = mesh(b, "end wall", pieces::end_wall(door_width, door_height))?;
    b.add_instance(
        "end wall",
        wall,
        palette.stone,
        Transform::from_translation(Vec3::new(0.0, landing, wall_z)),
    );

    let half = 0.5 * door_width;
    let leaf = mesh(
        b,
        "door",
        cuboid(
            Vec3::new(0.0, 0.0, -0.04),
            Vec3::new(half, door_height, 0.04),
        ),
    )?;
    let mut hinges = [0; 2];
    for (k, side) in [-1.0f32, 1.0].into_iter().enumerate() {
        let hinge = b.add_node(Node {
            name: Some(format!("door hinge {k}")),
            transform: Transform::from_translation(Vec3::new(side * half, landing, wall_z - 0.2)),
            ..Node::default()
        });
        b.add_node(Node {
            name: Some(format!("door {k}")),
            parent: Some(hinge),
            transform: Transform::from_translation(Vec3::X * if side > 0.0 { -half } else { 0.0 }),
            instance: Some(crate::MeshInstance {
                mesh: leaf,
                material: palette.wood,
            }),
            ..Node::default()
        });
        hinges[k] = hinge;
    }
    b.add_animation(motion::doors(hinges));
    let fan = mesh(b, "fan", pieces::fan())?;
    let fan_node = b.add_instance(
        "fan",
        fan,
        palette.steel,
        Transform::from_translation(Vec3::new(0.0, landing + 6.0, wall_z + 0.15)),
    );
    b.add_animation(motion::fan_turning(fan_node));

    let ball = mesh(b, "ball", icosphere(3, false))?;
    for (k, (x, radius, material, eased)) in [
        (-2.0f32, 0.35f32, palette.steel, false),
        (2.0, 0.4, palette.glass, true),
    ]
    .into_iter()
    .enumerate()
    {
        let start = Vec3::new(x, radius, -1.0);
        let pose = Transform::from_translation(start).with_scale(Vec3::splat(radius));
        let node = b.add_instance(&format!("ball {k}"), ball, material, pose);
        let period = (2 + k) as f32 * bays as f32;
        b.add_animation(motion::ball_path(
            node,
            start,
            Vec3::new(x, radius, end + 1.0),
            period,
            eased,
        ));
    }

    let sun_travel = Vec3::new(-0.55, -0.6, -0.35);
    light(
        b,
        "sun".into(),
        Transform::looking_at(Vec3::ZERO, sun_travel, Vec3::Y),
        LightKind::Directional,
        Vec3::new(1.0, 0.85, 0.65),
        3.0,
    );
    Ok(())
}

#[cfg(test)]
mod tests;
