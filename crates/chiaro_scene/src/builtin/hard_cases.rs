//! Numerically hard cases, each a small group with its own camera, laid out far apart so they
//! do not light or shadow one another. `builtin:hard-cases` holds them all but those of
//! [`CASES_ALONE`] (its camera is the first case's); `builtin:hard-cases?case=NAME` holds one,
//! with the shared sun and sky.
//!
//! `scale` lives alone, at the origin: its 1e5 box would light and shadow every other case
//! anywhere near them, and 5e4 or more from the origin, where it would not, the spacing of f32
//! values (0.004 at 5e4, 0.016 at 2e5) is wider than its 1e-3 cube, so no f32 world position
//! could hold the cube. Its box's top is a grid graded toward the cube (see
//! [`super::shapes::graded_box`]).
//!
//! | case | what it stresses |
//! |---|---|
//! | `spheres` | roughness 0, 0.001, 0.5, 1 at metallic 0 (front row) and 1 (back row) |
//! | `grazing` | a large plane seen at a grazing angle (1 degree) |
//! | `scale` | a cube 1e-3 wide sitting on a box 1e5 wide |
//! | `lit-group` | a small lit group near the origin |
//! | `far-copy` | the same group, camera and lights translated 1e5 units along +X |
//! | `coplanar` | two overlapping coplanar quads of different colours |
//! | `tiny-emitter` | a 1 cm emitter of radiance 1e5 over a floor |
//! | `degenerate` | a mesh with zero-area and repeated-index triangles that import drops |

use glam::{Quat, Vec2, Vec3};

use crate::components::{Camera, Light, LightKind, Projection};
use crate::environment::Environment;
use crate::error::{Fault, SceneError};
use crate::material::{Material, MaterialId};
use crate::mesh_repair::MeshData;
use crate::scene_builder::{Node, SceneBuilder};
use crate::transform::Transform;

use super::Params;
use super::shapes::{cuboid, floor, graded_box, icosphere, quad};

/// The cases, in layout order.
pub const HARD_CASES: [&str; 8] = [
    "spheres",
    "grazing",
    "scale",
    "lit-group",
    "far-copy",
    "coplanar",
    "tiny-emitter",
    "degenerate",
];

/// The cases that `builtin:hard-cases` leaves out: each is seen in its own scene,
/// `builtin:hard-cases?case=NAME`.
pub const CASES_ALONE: [&str; 1] = ["scale"];

/// The scene in which `case` is seen from its camera: `builtin:hard-cases`, or the case's own
/// for one of [`CASES_ALONE`].
pub fn hard_case_scene(case: &str) -> String {
    if CASES_ALONE.contains(&case) {
        format!("builtin:hard-cases?case={case}")
    } else {
        "builtin:hard-cases".to_owned()
    }
}

/// Distance between neighbouring cases along X.
const SPACING: f32 = 100.0;
/// Translation of the far copy relative to the lit group.
pub const FAR_OFFSET: Vec3 = Vec3::new(1.0e5, 0.0, 0.0);

/// Where a case's local origin is.
fn origin(case: &str) -> Vec3 {
    match case {
        "far-copy" => origin("lit-group") + FAR_OFFSET,
        // The 1e5 box would cover every other case: it lives far away along -Z.
        // Alone in its scene (see the module's doc).
        "scale" => Vec3::ZERO,
        _ => {
            let k = HARD_CASES.iter().position(|c| *c == case).unwrap_or(0);
            Vec3::new(k as f32 * SPACING, 0.0, 0.0)
        }
    }
}

struct Case<'a> {
    b: &'a mut SceneBuilder,
    origin: Vec3,
    grey: MaterialId,
}

impl Case<'_> {
    fn mesh(
        &mut self,
        name: &str,
        data: MeshData,
        material: MaterialId,
        transform: Transform,
    ) -> Result<(), SceneError> {
        if let Some(mesh) = self.b.add_mesh(&format!("mesh {name:?}"), name, data)? {
            let t = Transform {
                translation: transform.translation + self.origin,
                ..transform
            };
            self.b.add_instance(name, mesh, material, t);
        }
        Ok(())
    }

    fn camera(&mut self, name: &str, eye: Vec3, target: Vec3, yfov_degrees: f32) {
        self.b.add_node(Node {
            name: Some(format!("{name} camera")),
            transform: Transform::looking_at(eye + self.origin, target + self.origin, Vec3::Y),
            camera: Some(Camera {
                projection: Projection::Perspective {
                    yfov: yfov_degrees.to_radians(),
                    aspect_ratio: None,
                    znear: 1e-4,
                    zfar: None,
                },
            }),
            ..Node::default()
        });
    }

    fn point_light(&mut self, name: &str, at: Vec3, intensity: f32) {
        self.b.add_node(Node {
            name: Some(name.into()),
            transform: Transform::from_translation(at + self.origin),
            light: Some(Light {
                kind: LightKind::Point,
                color: Vec3::ONE,
                intensity,
                range: None,
            }),
            ..Node::default()
        });
    }

    fn emitter(
        &mut self,
        name: &str,
        center: Vec3,
        size: f32,
        radiance: f32,
    ) -> Result<(), SceneError> {
        let h = 0.5 * size;
        let corners = [
            Vec3::new(-h, 0.0, -h),
            Vec3::new(h, 0.0, -h),
            Vec3::new(h, 0.0, h),
            Vec3::new(-h, 0.0, h),
        ];
        let material = self
            .b
            .add_material(Material::emitter(name, Vec3::splat(radiance)));
        self.mesh(
            name,
            quad(corners, Vec3::NEG_Y),
            material,
            Transform::from_translation(center),
        )
    }
}

fn build_case(b: &mut SceneBuilder, case: &str, grey: MaterialId) -> Result<(), SceneError> {
    let mut c = Case {
        b,
        origin: origin(case),
        grey,
    };
    match case {
        "spheres" => {
            c.mesh("spheres floor", floor(12.0), c.grey, Transform::IDENTITY)?;
            let roughness = [0.0, 0.001, 0.5, 1.0];
            let sphere =
                c.b.add_mesh("mesh \"sphere\"", "sphere", icosphere(4, false))?;
            for (row, metallic) in [0.0f32, 1.0].into_iter().enumerate() {
                for (col, &r) in roughness.iter().enumerate() {
                    let name = format!("metallic {metallic} roughness {r}");
                    let mut m = Material::diffuse(&name, Vec3::new(0.9, 0.6, 0.3), r);
                    m.metallic = metallic;
                    let id = c.b.add_material(m);
                    let at = c.origin + Vec3::new(col as f32 * 1.2 - 1.8, 0.5, -(row as f32) * 1.5);
                    if let Some(sphere) = sphere {
                        c.b.add_instance(
                            &name,
                            sphere,
                            id,
                            Transform::from_translation(at).with_scale(Vec3::splat(0.5)),
                        );
                    }
                }
            }
            c.emitter("spheres light", Vec3::new(0.0, 4.0, 1.0), 2.0, 10.0)?;
            c.camera(
                "spheres",
                Vec3::new(0.0, 2.0, 5.0),
                Vec3::new(0.0, 0.4, -0.75),
                40.0,
            );
        }
        "grazing" => {
            c.mesh("grazing plane", floor(60.0), c.grey, Transform::IDENTITY)?;
            c.mesh(
                "grazing marker",
                cuboid(Vec3::splat(-0.25), Vec3::splat(0.25)),
                c.grey,
                Transform::from_translation(Vec3::new(0.0, 0.25, -10.0)),
            )?;
            c.camera(
                "grazing",
                Vec3::new(0.0, 0.3, 25.0),
                Vec3::new(0.0, 0.3 - 50.0 * 1f32.to_radians().tan(), -25.0),
                30.0,
            );
        }
        "scale" => {
            c.mesh(
                "huge box",
                graded_box(
                    Vec3::new(-5.0e4, -1.0e5, -5.0e4),
                    Vec3::new(5.0e4, 0.0, 5.0e4),
                    Vec2::ZERO,
                    5.0e-4,
                ),
                c.grey,
                Transform::IDENTITY,
            )?;
            c.mesh(
                "tiny cube",
                cuboid(Vec3::ZERO, Vec3::splat(1.0e-3)),
                c.grey,
                Transform::from_translation(Vec3::new(-5.0e-4, 0.0, -5.0e-4)),
            )?;
            c.camera(
                "scale",
                Vec3::new(0.002, 0.0025, 0.004),
                Vec3::new(0.0, 0.0004, 0.0),
                40.0,
            );
        }
        "lit-group" | "far-copy" => {
            c.mesh(
                &format!("{case} floor"),
                floor(4.0),
                c.grey,
                Transform::IDENTITY,
            )?;
            let blue = c.b.add_material(Material::diffuse(
                &format!("{case} blue"),
                Vec3::new(0.2, 0.3, 0.8),
                0.4,
            ));
            c.mesh(
                &format!("{case} sphere"),
                icosphere(3, false),
                blue,
                Transform::from_translation(Vec3::new(-0.5, 0.4, 0.0)).with_scale(Vec3::splat(0.4)),
            )?;
            let rotated = Transform::from_translation(Vec3::new(0.6, 0.0, -0.3))
                .with_rotation(Quat::from_rotation_y(0.5));
            c.mesh(
                &format!("{case} box"),
                cuboid(Vec3::new(-0.3, 0.0, -0.3), Vec3::new(0.3, 0.6, 0.3)),
                c.grey,
                rotated,
            )?;
            c.emitter(
                &format!("{case} light"),
                Vec3::new(0.0, 2.0, 0.5),
                0.5,
                20.0,
            )?;
            c.point_light(
                &format!("{case} point light"),
                Vec3::new(-1.0, 1.5, 1.0),
                2.0,
            );
            c.camera(
                case,
                Vec3::new(0.0, 1.2, 3.0),
                Vec3::new(0.0, 0.3, 0.0),
                45.0,
            );
        }
        "coplanar" => {
            let red = c.b.add_material(Material::diffuse(
                "coplanar red",
                Vec3::new(0.8, 0.1, 0.1),
                1.0,
            ));
            let blue = c.b.add_material(Material::diffuse(
                "coplanar blue",
                Vec3::new(0.1, 0.1, 0.8),
                1.0,
            ));
            c.mesh(
                "coplanar red quad",
                floor(2.0),
                red,
                Transform::from_translation(Vec3::new(-0.5, 0.0, 0.0)),
            )?;
            c.mesh(
                "coplanar blue quad",
                floor(2.0),
                blue,
                Transform::from_translation(Vec3::new(0.5, 0.0, 0.0)),
            )?;
            c.camera("coplanar", Vec3::new(0.0, 3.0, 2.0), Vec3::ZERO, 45.0);
        }
        "tiny-emitter" => {
            c.mesh(
                "tiny-emitter floor",
                floor(6.0),
                c.grey,
                Transform::IDENTITY,
            )?;
            c.mesh(
                "tiny-emitter sphere",
                icosphere(3, false),
                c.grey,
                Transform::from_translation(Vec3::new(0.8, 0.5, 0.0)).with_scale(Vec3::splat(0.5)),
            )?;
            c.emitter("tiny emitter", Vec3::new(0.0, 1.0, 0.0), 0.01, 1.0e5)?;
            c.camera(
                "tiny-emitter",
                Vec3::new(0.0, 1.5, 3.5),
                Vec3::new(0.3, 0.4, 0.0),
                45.0,
            );
        }
        "degenerate" => {
            c.mesh("degenerate floor", floor(4.0), c.grey, Transform::IDENTITY)?;
            c.mesh(
                "degenerate mesh",
                degenerate_mesh(),
                c.grey,
                Transform::from_translation(Vec3::new(0.0, 0.5, 0.0)),
            )?;
            c.camera(
                "degenerate",
                Vec3::new(0.0, 1.0, 3.0),
                Vec3::new(0.0, 0.5, 0.0),
                45.0,
            );
        }
        _ => unreachable!("case names are checked by build"),
    }
    Ok(())
}

/// A unit quad (2 good triangles) plus 4 that import must drop: one with a repeated index, two
/// with collinear corners, one with two distinct vertices at the same place.
pub fn degenerate_mesh() -> MeshData {
    let positions = vec![
        Vec3::new(-0.5, -0.5, 0.0),
        Vec3::new(0.5, -0.5, 0.0),
        Vec3::new(0.5, 0.5, 0.0),
        Vec3::new(-0.5, 0.5, 0.0),
        Vec3::new(0.0, -0.5, 0.0), // on the edge 0-1
        Vec3::new(0.5, 0.5, 0.0),  // where vertex 2 is
        Vec3::new(0.0, 0.5, 0.0),  // on the edge 2-3
    ];
    let normals = Some(vec![Vec3::Z; positions.len()]);
    let indices = Some(vec![0, 1, 2, 0, 2, 3, 0, 0, 1, 0, 4, 1, 1, 2, 5, 2, 6, 3]);
    MeshData {
        positions,
        normals,
        indices,
        ..MeshData::default()
    }
}

/// Builds all cases, or the one named by the `case` parameter.
pub(super) fn build(b: &mut SceneBuilder, params: &mut Params) -> Result<(), SceneError> {
    let cases: Vec<&str> = match params.text("case") {
        None => HARD_CASES
            .into_iter()
            .filter(|c| !CASES_ALONE.contains(c))
            .collect(),
        Some(name) => match HARD_CASES.iter().find(|c| **c == name) {
            Some(c) => vec![*c],
            None => {
                return Err(SceneError::whole(
                    b.source().to_owned(),
                    Fault::Builtin(format!(
                        "unknown case '{name}' (known: {})",
                        HARD_CASES.join(", ")
                    )),
                ));
            }
        },
    };
    let grey = b.add_material(Material::diffuse("grey", Vec3::splat(0.5), 0.8));
    for case in cases {
        build_case(b, case, grey)?;
    }
    b.add_node(Node {
        name: Some("sun".into()),
        transform: Transform::looking_at(Vec3::ZERO, Vec3::new(-0.4, -1.0, -0.6), Vec3::Y),
        light: Some(Light {
            kind: LightKind::Directional,
            color: Vec3::ONE,
            intensity: 2.0,
            range: None,
        }),
        ..Node::default()
    });
    b.set_environment(Environment::constant(Vec3::new(0.25, 0.3, 0.4)));
    Ok(())
}
