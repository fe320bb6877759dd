//! Everything a render reads, gathered once from the World: the BVH, the shared assets, the
//! light table, the environment and the camera.

use bevy_ecs::prelude::*;
use chiaro_bvh::{FLAT_MAX_TRIANGLES, FlatBvh, Hit, Ray, SceneBvh};
use chiaro_scene::{
    ActiveCamera, AlphaMode, Camera, Environment, EnvironmentSource, GlobalTransform, Material,
    Materials, Meshes, Textures,
};
use chiaro_shading::lights::EnvironmentLight;

use crate::camera::CameraRays;
use crate::error::ReferenceError;
use crate::light_table::{LightSampling, LightTable};
use crate::surface::stops_ray;

/// A scene ready to be path traced; borrows the World's assets.
pub struct RenderScene<'w> {
    /// The BVH over every instance.
    pub bvh: SceneBvh,
    /// The same triangles in world space under one tree, which ray queries take when the scene
    /// has at most [`FLAT_MAX_TRIANGLES`] (the render is of a still scene; see [`FlatBvh`]).
    pub flat: Option<FlatBvh>,
    /// Mesh data.
    pub meshes: &'w Meshes,
    /// Materials.
    pub materials: &'w Materials,
    /// Textures.
    pub textures: &'w Textures,
    /// Used where an instance names a missing material.
    pub default_material: Material,
    /// The lights.
    pub lights: LightTable,
    /// The environment as a light.
    pub environment: EnvironmentLight,
    /// The camera.
    pub camera: CameraRays,
    /// True when some material is alpha-masked or alpha-blended: only then do ray queries test
    /// candidates' alpha (an opaque scene takes the unfiltered traversal, without a callback
    /// per hit).
    pub has_alpha_tests: bool,
}

/// The environment resource as a light (black when absent).
fn environment_light(world: &World) -> EnvironmentLight {
    let Some(env) = world.get_resource::<Environment>() else {
        return EnvironmentLight::constant(glam::Vec3::ZERO);
    };
    match &env.source {
        EnvironmentSource::Constant(c) => EnvironmentLight::constant(*c * env.strength),
        EnvironmentSource::Equirect(image) => EnvironmentLight::new(
            &image.texels,
            image.width as usize,
            image.height as usize,
            env.strength,
            env.rotation,
        ),
    }
}

/// Builds the BVH and light table of `world` (propagating transforms first), the lights picked
/// by `sampling`. Call [`RenderScene::new`] with the result.
pub fn prepare(world: &mut World, sampling: LightSampling) -> (SceneBvh, LightTable) {
    let bvh = SceneBvh::build(world);
    let mean = world
        .get_resource::<Environment>()
        .map_or(glam::Vec3::ZERO, Environment::light_sampling_radiance);
    let lights = LightTable::gather(world, &bvh, mean, sampling);
    (bvh, lights)
}

impl<'w> RenderScene<'w> {
    /// The scene of `world` seen by its active camera, for a `width` x `height` image.
    pub fn new(
        world: &'w World,
        (bvh, lights): (SceneBvh, LightTable),
        width: u32,
        height: u32,
    ) -> Result<Self, ReferenceError> {
        let active = world
            .get_resource::<ActiveCamera>()
            .ok_or(ReferenceError::NoCamera)?;
        let entity = world
            .get_entity(active.0)
            .map_err(|_| ReferenceError::NoCamera)?;
        let (Some(camera), Some(global)) =
            (entity.get::<Camera>(), entity.get::<GlobalTransform>())
        else {
            return Err(ReferenceError::NoCamera);
        };
        let (Some(meshes), Some(materials), Some(textures)) = (
            world.get_resource::<Meshes>(),
            world.get_resource::<Materials>(),
            world.get_resource::<Textures>(),
        ) else {
            return Err(ReferenceError::NoScene);
        };
        let flat = FlatBvh::build(&bvh, FLAT_MAX_TRIANGLES);
        Ok(Self {
            bvh,
            flat,
            meshes,
            materials,
            textures,
            default_material: Material::default(),
            lights,
            environment: environment_light(world),
            camera: CameraRays::new(camera, global, width, height),
            has_alpha_tests: materials
                .iter()
                .any(|(_, m)| m.alpha_mode != AlphaMode::Opaque),
        })
    }

    /// The nearest surface along `ray` that stops it: alpha-masked texels are skipped, and
    /// alpha-blended surfaces stop it with probability alpha (`chiaro_shading::coverage`).
    pub fn closest_hit(&self, ray: &Ray) -> Option<Hit> {
        match (&self.flat, self.has_alpha_tests) {
            (Some(flat), true) => flat.closest_hit_with(ray, &|h| stops_ray(self, ray, h)),
            (Some(flat), false) => flat.closest_hit(ray),
            (None, true) => self.bvh.closest_hit_with(ray, &|h| stops_ray(self, ray, h)),
            (None, false) => self.bvh.closest_hit(ray),
        }
    }

    /// True when something blocks `ray`: alpha-masked texels let it through, alpha-blended
    /// surfaces block it with probability alpha (so the expected visibility is the product of
    /// their 1 - alpha, as the GPU's shadow rays decide too).
    pub fn occluded(&self, ray: &Ray) -> bool {
        match (&self.flat, self.has_alpha_tests) {
            (Some(flat), true) => flat.any_hit_with(ray, &|h| stops_ray(self, ray, h)),
            (Some(flat), false) => flat.any_hit(ray),
            (None, true) => self.bvh.any_hit_with(ray, &|h| stops_ray(self, ray, h)),
            (None, false) => self.bvh.any_hit(ray),
        }
    }
}
