//! For the built-in scenes' tests: a loaded scene's world-space triangles, traced by brute force
//! (Möller and Trumbore 1997, "Fast, Minimum Storage Ray/Triangle Intersection"), to tell which
//! emitters a point sees.

use bevy_ecs::world::World;
use glam::Vec3;

use crate::components::{ActiveCamera, MeshInstance};
use crate::material::Materials;
use crate::mesh::Meshes;
use crate::transform::GlobalTransform;
use crate::{SceneInfo, load_scene};

/// A triangle in world space and whether its material emits.
struct Triangle {
    corners: [Vec3; 3],
    emits: bool,
}

/// A built-in scene, loaded, as world-space triangles.
pub(super) struct Sight {
    /// Where the active camera is.
    pub camera: Vec3,
    /// What `info` says of it.
    pub info: SceneInfo,
    triangles: Vec<Triangle>,
}

impl Sight {
    /// Loads `spec`, which must build without repairs.
    pub fn load(spec: &str) -> Self {
        let mut world = World::new();
        let spawned = load_scene(&mut world, spec).unwrap_or_else(|e| panic!("{spec}: {e}"));
        assert!(spawned.repairs.is_empty(), "{spec}: {:?}", spawned.repairs);
        // Gathering the info also propagates the transforms.
        let info = SceneInfo::gather(&mut world);
        let camera_entity = world.resource::<ActiveCamera>().0;
        let camera = world.get::<GlobalTransform>(camera_entity).unwrap().0;
        let (meshes, materials) = (world.resource::<Meshes>(), world.resource::<Materials>());
        let mut triangles = Vec::new();
        for (instance, global) in world
            .try_query::<(&MeshInstance, &GlobalTransform)>()
            .unwrap()
            .iter(&world)
        {
            let mesh = meshes.get(instance.mesh).unwrap();
            let emits = materials
                .get(instance.material)
                .unwrap()
                .emitted_radiance()
                .max_element()
                > 0.0;
            for t in mesh.indices().chunks_exact(3) {
                let corners = [t[0], t[1], t[2]]
                    .map(|i| global.0.transform_point3(mesh.positions()[i as usize]));
                triangles.push(Triangle { corners, emits });
            }
        }
        Self {
            camera: camera.translation.into(),
            info,
            triangles,
        }
    }

    /// Checks that the scene is lit by emissive triangles alone: no punctual light, a black
    /// environment.
    pub fn assert_lit_by_emitters_alone(&self) {
        assert!(self.info.emissive_triangles > 0);
        assert_eq!(
            self.info.lights.values().sum::<usize>(),
            0,
            "{:?}",
            self.info.lights
        );
        assert!(
            self.info
                .environment
                .starts_with("constant (0.000, 0.000, 0.000)"),
            "{}",
            self.info.environment
        );
    }

    /// The centroids of the emissive triangles.
    pub fn emitter_centroids(&self) -> Vec<Vec3> {
        self.triangles
            .iter()
            .filter(|t| t.emits)
            .map(|t| t.corners.iter().sum::<Vec3>() / 3.0)
            .collect()
    }

    /// The first triangle the segment from `from` to `to` crosses, as the fraction of the way
    /// there (up to a hair past `to`) and whether it emits.
    fn first_hit(&self, from: Vec3, to: Vec3) -> Option<(f32, bool)> {
        self.triangles
            .iter()
            .filter_map(|t| crossing(from, to - from, &t.corners).map(|d| (d, t.emits)))
            .filter(|&(d, _)| d < 1.0 + 1e-4)
            .min_by(|a, b| a.0.total_cmp(&b.0))
    }

    /// Whether nothing stands between `from` and `to`.
    pub fn clear(&self, from: Vec3, to: Vec3) -> bool {
        self.first_hit(from, to)
            .is_none_or(|(d, _)| d >= 1.0 - 1e-4)
    }

    /// The emissive triangles' centroids that `eye` sees: the first triangle the segment from
    /// `eye` to one crosses is emissive (its own, or another emitter's in front of it).
    pub fn emitters_seen_from(&self, eye: Vec3) -> Vec<Vec3> {
        self.emitter_centroids()
            .into_iter()
            .filter(|&target| self.first_hit(eye, target).is_some_and(|(_, emits)| emits))
            .collect()
    }
}

/// Where the ray `origin + d * direction` crosses triangle `c` (either face), as d > 1e-6. The
/// triangle is taken a hair wider than it is (1e-5 in barycentric terms), so that a ray
/// along the edge two triangles share cannot slip between them.
fn crossing(origin: Vec3, direction: Vec3, c: &[Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (c[1] - c[0], c[2] - c[0]);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let s = origin - c[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    let d = e2.dot(q) / det;
    const WIDER: f32 = 1e-5;
    (u >= -WIDER && v >= -WIDER && u + v <= 1.0 + WIDER && d > 1e-6).then_some(d)
}

#[test]
fn a_segment_crosses_a_triangle_only_inside_it_and_ahead() {
    let c = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let from = Vec3::new(0.25, 0.25, 1.0);
    assert_eq!(crossing(from, Vec3::new(0.0, 0.0, -2.0), &c), Some(0.5));
    assert_eq!(crossing(from, Vec3::new(0.0, 0.0, 2.0), &c), None);
    assert_eq!(crossing(from, Vec3::new(1.0, 1.0, -1.0), &c), None);
}
