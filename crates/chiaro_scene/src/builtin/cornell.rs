//! The Cornell box, from the Cornell Program of Computer Graphics' published measurements
//! ("Cornell Box Data", www.graphics.cornell.edu/online/box/data.html): geometry in millimetres
//! (scaled here to metres), camera at (278, 273, -800) looking +Z with a 35 mm lens on a 25 mm
//! film. Reflectances and light radiance are the RGB values commonly used for it in physically
//! based renderers (white 0.725/0.71/0.68, red 0.63/0.065/0.05, green 0.14/0.45/0.091, light
//! 17/12/4). The surfaces are measured as diffuse, so they are pure Lambertian here (IOR 1: F0 = 0,
//! no specular lobe), which also lets any diffuse renderer reproduce the box exactly. The light
//! quad sits 0.5 mm under the ceiling so the two never coincide.

use glam::Vec3;

use crate::components::{Camera, Projection};
use crate::error::SceneError;
use crate::material::Material;
use crate::scene_builder::{Node, SceneBuilder};
use crate::transform::Transform;

use super::add_shape;
use super::shapes::{closed_quads, quad};

const MM: f32 = 0.001;

fn p(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z) * MM
}

/// Builds the box into `b`: 8 meshes, 32 triangles, 4 materials, one camera.
pub(super) fn build(b: &mut SceneBuilder) -> Result<(), SceneError> {
    let white = b.add_material(Material::lambertian("white", Vec3::new(0.725, 0.71, 0.68)));
    let red = b.add_material(Material::lambertian("red", Vec3::new(0.63, 0.065, 0.05)));
    let green = b.add_material(Material::lambertian("green", Vec3::new(0.14, 0.45, 0.091)));
    let light = b.add_material(Material {
        specular: 0.0,
        ..Material::emitter("light", Vec3::new(17.0, 12.0, 4.0))
    });

    let room_center = p(278.0, 274.4, 279.6);
    let walls = [
        (
            "floor",
            white,
            [
                p(552.8, 0.0, 0.0),
                p(0.0, 0.0, 0.0),
                p(0.0, 0.0, 559.2),
                p(549.6, 0.0, 559.2),
            ],
        ),
        (
            "ceiling",
            white,
            [
                p(556.0, 548.8, 0.0),
                p(556.0, 548.8, 559.2),
                p(0.0, 548.8, 559.2),
                p(0.0, 548.8, 0.0),
            ],
        ),
        (
            "back wall",
            white,
            [
                p(549.6, 0.0, 559.2),
                p(0.0, 0.0, 559.2),
                p(0.0, 548.8, 559.2),
                p(556.0, 548.8, 559.2),
            ],
        ),
        (
            "right wall",
            green,
            [
                p(0.0, 0.0, 559.2),
                p(0.0, 0.0, 0.0),
                p(0.0, 548.8, 0.0),
                p(0.0, 548.8, 559.2),
            ],
        ),
        (
            "left wall",
            red,
            [
                p(552.8, 0.0, 0.0),
                p(549.6, 0.0, 559.2),
                p(556.0, 548.8, 559.2),
                p(556.0, 548.8, 0.0),
            ],
        ),
        (
            "light",
            light,
            [
                p(343.0, 548.3, 227.0),
                p(343.0, 548.3, 332.0),
                p(213.0, 548.3, 332.0),
                p(213.0, 548.3, 227.0),
            ],
        ),
    ];
    for (name, material, corners) in walls {
        let center = corners.iter().sum::<Vec3>() / 4.0;
        add_shape(
            b,
            name,
            material,
            quad(corners, room_center - center),
            Transform::IDENTITY,
        )?;
    }

    let short_block = [
        [
            p(130.0, 165.0, 65.0),
            p(82.0, 165.0, 225.0),
            p(240.0, 165.0, 272.0),
            p(290.0, 165.0, 114.0),
        ],
        [
            p(290.0, 0.0, 114.0),
            p(290.0, 165.0, 114.0),
            p(240.0, 165.0, 272.0),
            p(240.0, 0.0, 272.0),
        ],
        [
            p(130.0, 0.0, 65.0),
            p(130.0, 165.0, 65.0),
            p(290.0, 165.0, 114.0),
            p(290.0, 0.0, 114.0),
        ],
        [
            p(82.0, 0.0, 225.0),
            p(82.0, 165.0, 225.0),
            p(130.0, 165.0, 65.0),
            p(130.0, 0.0, 65.0),
        ],
        [
            p(240.0, 0.0, 272.0),
            p(240.0, 165.0, 272.0),
            p(82.0, 165.0, 225.0),
            p(82.0, 0.0, 225.0),
        ],
    ];
    let tall_block = [
        [
            p(423.0, 330.0, 247.0),
            p(265.0, 330.0, 296.0),
            p(314.0, 330.0, 456.0),
            p(472.0, 330.0, 406.0),
        ],
        [
            p(423.0, 0.0, 247.0),
            p(423.0, 330.0, 247.0),
            p(472.0, 330.0, 406.0),
            p(472.0, 0.0, 406.0),
        ],
        [
            p(472.0, 0.0, 406.0),
            p(472.0, 330.0, 406.0),
            p(314.0, 330.0, 456.0),
            p(314.0, 0.0, 456.0),
        ],
        [
            p(314.0, 0.0, 456.0),
            p(314.0, 330.0, 456.0),
            p(265.0, 330.0, 296.0),
            p(265.0, 0.0, 296.0),
        ],
        [
            p(265.0, 0.0, 296.0),
            p(265.0, 330.0, 296.0),
            p(423.0, 330.0, 247.0),
            p(423.0, 0.0, 247.0),
        ],
    ];
    for (name, faces) in [("short block", short_block), ("tall block", tall_block)] {
        add_shape(b, name, white, closed_quads(&faces), Transform::IDENTITY)?;
    }

    let eye = p(278.0, 273.0, -800.0);
    b.add_node(Node {
        name: Some("camera".into()),
        transform: Transform::looking_at(eye, eye + Vec3::Z, Vec3::Y),
        camera: Some(Camera {
            projection: Projection::Perspective {
                yfov: 2.0 * (12.5f32 / 35.0).atan(),
                aspect_ratio: Some(1.0),
                znear: 0.01,
                zfar: None,
            },
        }),
        ..Node::default()
    });
    Ok(())
}
