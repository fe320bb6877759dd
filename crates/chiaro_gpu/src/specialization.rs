//! Pipelines specialised to what a scene uses: a scene without textures, alpha masks, punctual
//! lights, emissive meshes or an environment pays nothing for them.
//!
//! The shaders that read the scene (`gbuffer`, `direct`, `indirect`) import the virtual module
//! `lib/features.wgsl`, written by [`features_module`]: one pipeline-overridable `bool` per
//! [`PipelineFeatures`] flag, `true` by default, guarding the code of that feature (a texture
//! lookup, the alpha-mask and coverage tests in BVH traversal, vertex colours, a kind of
//! light, the environment). A pipeline is created with the flags of the scene's
//! [`SceneFeatures`]; the driver's compiler then drops the code behind every flag that is off.
//! The image is the same: a flag is off only when the scene has nothing the guarded code would
//! act on, and no guarded code draws random numbers the rest of the shader depends on (the
//! coverage test of alpha blending hashes its numbers: `chiaro_shading::coverage`).
//!
//! [`PipelineCache`] keeps one pipeline per feature set. When an edit changes the features, it
//! either builds the new pipeline before the frame (headless rendering: the frame is exact) or
//! on a background thread while the old pipeline goes on rendering (an interactive app: no
//! stall).

use std::collections::HashMap;
use std::fmt::Write as _;
use std::sync::mpsc;

use chiaro_scene::{EnvironmentFeature, SceneFeatures};

/// Name of the virtual module declaring the feature flags.
pub const FEATURES_MODULE: &str = "lib/features.wgsl";

/// A set of shader features, one bit per flag of [`PipelineFeatures::FLAGS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineFeatures(u32);

/// One feature flag: its bit, its WGSL override's name and what it guards.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FeatureFlag {
    /// The flag as a one-bit set.
    pub bit: PipelineFeatures,
    /// Name of the WGSL `override` constant.
    pub name: &'static str,
    /// What the flag's code does.
    pub doc: &'static str,
}

impl PipelineFeatures {
    /// Base colour textures are read.
    pub const BASE_COLOR_TEXTURES: Self = Self(1 << 0);
    /// Metallic-roughness textures are read.
    pub const METALLIC_ROUGHNESS_TEXTURES: Self = Self(1 << 1);
    /// Emissive textures are read.
    pub const EMISSIVE_TEXTURES: Self = Self(1 << 2);
    /// Normal maps perturb the shading normal.
    pub const NORMAL_MAPS: Self = Self(1 << 3);
    /// Alpha-masked materials are tested, in the rasterizer and at every candidate ray hit.
    pub const ALPHA_MASKS: Self = Self(1 << 4);
    /// Point lights are sampled.
    pub const POINT_LIGHTS: Self = Self(1 << 5);
    /// Spot lights are sampled.
    pub const SPOT_LIGHTS: Self = Self(1 << 6);
    /// Directional lights are sampled.
    pub const DIRECTIONAL_LIGHTS: Self = Self(1 << 7);
    /// Emissive triangles are sampled and their emission is found by rays.
    pub const EMISSIVE_TRIANGLES: Self = Self(1 << 8);
    /// The environment emits (a constant colour or an image).
    pub const ENVIRONMENT: Self = Self(1 << 9);
    /// The environment is an image (looked up and importance-sampled).
    pub const ENVIRONMENT_MAP: Self = Self(1 << 10);
    /// Light trees to pick lights through ([`crate::gpu_scene::GpuScene::light_trees`]), and
    /// the frame picks through them ([`crate::settings::LightSampling::Tree`]).
    pub const LIGHT_TREES: Self = Self(1 << 11);
    /// Vertex colours multiply the base colour and alpha.
    pub const VERTEX_COLORS: Self = Self(1 << 12);
    /// Alpha-blended materials stop rays with probability alpha, in the rasterizer and at
    /// every candidate ray hit (`chiaro_shading::coverage`).
    pub const ALPHA_BLEND: Self = Self(1 << 13);
    /// A clear coat (KHR_materials_clearcoat) is evaluated and sampled in the BRDF.
    pub const CLEARCOAT: Self = Self(1 << 14);
    /// Transmissive materials (KHR_materials_transmission): their lobe is evaluated and
    /// sampled, and rays and light samples pass through them.
    pub const TRANSMISSION: Self = Self(1 << 15);
    /// A sheen (KHR_materials_sheen) is layered over the base in the BRDF.
    pub const SHEEN: Self = Self(1 << 16);
    /// Volumes (KHR_materials_volume): transmission refracts by the IOR, and light crossing a
    /// medium is attenuated.
    pub const VOLUMES: Self = Self(1 << 17);
    /// The material extensions' textures (chiaro_scene::LayerTextures) multiply their factors,
    /// at ray hits and at the surface the G-buffer holds (found again from its triangle).
    pub const LAYER_TEXTURES: Self = Self(1 << 18);
    /// The direct pass shades the resampled reservoirs' area light
    /// ([`crate::settings::RestirSettings`]), and the frame asks for it.
    pub const RESTIR_DI: Self = Self(1 << 19);

    /// Every flag, in bit order.
    pub const FLAGS: [FeatureFlag; 20] = [
        flag(
            Self::BASE_COLOR_TEXTURES,
            "FEATURE_BASE_COLOR_TEXTURES",
            "base colour textures",
        ),
        flag(
            Self::METALLIC_ROUGHNESS_TEXTURES,
            "FEATURE_METALLIC_ROUGHNESS_TEXTURES",
            "metallic-roughness textures",
        ),
        flag(
            Self::EMISSIVE_TEXTURES,
            "FEATURE_EMISSIVE_TEXTURES",
            "emissive textures",
        ),
        flag(Self::NORMAL_MAPS, "FEATURE_NORMAL_MAPS", "normal maps"),
        flag(
            Self::ALPHA_MASKS,
            "FEATURE_ALPHA_MASKS",
            "alpha-masked materials",
        ),
        flag(Self::POINT_LIGHTS, "FEATURE_POINT_LIGHTS", "point lights"),
        flag(Self::SPOT_LIGHTS, "FEATURE_SPOT_LIGHTS", "spot lights"),
        flag(
            Self::DIRECTIONAL_LIGHTS,
            "FEATURE_DIRECTIONAL_LIGHTS",
            "directional lights",
        ),
        flag(
            Self::EMISSIVE_TRIANGLES,
            "FEATURE_EMISSIVE_TRIANGLES",
            "emissive triangles",
        ),
        flag(
            Self::ENVIRONMENT,
            "FEATURE_ENVIRONMENT",
            "an emitting environment",
        ),
        flag(
            Self::ENVIRONMENT_MAP,
            "FEATURE_ENVIRONMENT_MAP",
            "an environment image",
        ),
        flag(
            Self::LIGHT_TREES,
            "FEATURE_LIGHT_TREES",
            "light trees, and the frame picks lights through them",
        ),
        flag(
            Self::VERTEX_COLORS,
            "FEATURE_VERTEX_COLORS",
            "vertex colours",
        ),
        flag(
            Self::ALPHA_BLEND,
            "FEATURE_ALPHA_BLEND",
            "alpha-blended materials (stochastic coverage)",
        ),
        flag(
            Self::CLEARCOAT,
            "FEATURE_CLEARCOAT",
            "clear-coated materials",
        ),
        flag(
            Self::TRANSMISSION,
            "FEATURE_TRANSMISSION",
            "transmissive materials",
        ),
        flag(Self::SHEEN, "FEATURE_SHEEN", "sheen"),
        flag(
            Self::VOLUMES,
            "FEATURE_VOLUMES",
            "volumes (refraction and attenuation)",
        ),
        flag(
            Self::LAYER_TEXTURES,
            "FEATURE_LAYER_TEXTURES",
            "material extension textures",
        ),
        flag(
            Self::RESTIR_DI,
            "FEATURE_RESTIR_DI",
            "resampled direct light (its frame settings ask for it)",
        ),
    ];

    /// No feature.
    pub const NONE: Self = Self(0);
    /// Every feature: the pipeline that renders any scene.
    pub const ALL: Self = Self((1 << Self::FLAGS.len()) - 1);

    /// The features a scene with `features` needs.
    pub fn of_scene(features: &SceneFeatures) -> Self {
        let mut set = Self::NONE;
        let mut add = |on: bool, flag: Self| {
            if on {
                set = set.with(flag);
            }
        };
        add(features.base_color_textures, Self::BASE_COLOR_TEXTURES);
        add(
            features.metallic_roughness_textures,
            Self::METALLIC_ROUGHNESS_TEXTURES,
        );
        add(features.emissive_textures, Self::EMISSIVE_TEXTURES);
        add(features.normal_maps, Self::NORMAL_MAPS);
        add(features.alpha_masks, Self::ALPHA_MASKS);
        add(features.vertex_colors, Self::VERTEX_COLORS);
        add(features.alpha_blend, Self::ALPHA_BLEND);
        add(features.clearcoat, Self::CLEARCOAT);
        add(features.transmission, Self::TRANSMISSION);
        add(features.sheen, Self::SHEEN);
        add(features.volumes, Self::VOLUMES);
        add(features.layer_textures, Self::LAYER_TEXTURES);
        add(features.point_lights, Self::POINT_LIGHTS);
        add(features.spot_lights, Self::SPOT_LIGHTS);
        add(features.directional_lights, Self::DIRECTIONAL_LIGHTS);
        add(features.emissive_triangles, Self::EMISSIVE_TRIANGLES);
        add(
            features.environment != EnvironmentFeature::Black,
            Self::ENVIRONMENT,
        );
        add(
            features.environment == EnvironmentFeature::Map,
            Self::ENVIRONMENT_MAP,
        );
        set
    }

    /// Whether every flag of `other` is in `self`.
    pub fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// `self` with the flags of `other` added.
    pub fn with(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }

    /// `self` without the flags of `other`.
    pub fn without(self, other: Self) -> Self {
        Self(self.0 & !other.0)
    }

    /// The names of the flags that are on.
    pub fn names(self) -> Vec<&'static str> {
        Self::FLAGS
            .iter()
            .filter(|f| self.contains(f.bit))
            .map(|f| f.name)
            .collect()
    }

    /// The values of every override, for `wgpu::PipelineCompilationOptions::constants`.
    pub fn constants(self) -> Vec<(&'static str, f64)> {
        Self::FLAGS
            .iter()
            .map(|f| (f.name, if self.contains(f.bit) { 1.0 } else { 0.0 }))
            .collect()
    }
}

const fn flag(bit: PipelineFeatures, name: &'static str, doc: &'static str) -> FeatureFlag {
    FeatureFlag { bit, name, doc }
}

/// The source of `lib/features.wgsl`: one `override NAME: bool = true;` per flag.
pub fn features_module() -> String {
    let mut out = String::from(
        "// Generated by chiaro_gpu::specialization::features_module: the pipeline-overridable\n\
         // feature flags. Each is true unless the pipeline is specialised to a scene without it.\n",
    );
    for f in PipelineFeatures::FLAGS {
        let _ = writeln!(out, "// The scene has {}.", f.doc);
        let _ = writeln!(out, "override {}: bool = true;", f.name);
    }
    out
}

/// Which feature set a frame's pipelines are compiled for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PipelineChoice {
    /// The features the scene uses ([`SceneFeatures`]), kept current as it is edited.
    #[default]
    Specialized,
    /// Every feature: the general pipeline, for measuring what specialisation saves.
    AllFeatures,
    /// Exactly these features, whatever the scene uses (a scene using a feature that is off
    /// renders without it): for tests of the specialisation itself.
    Exactly(PipelineFeatures),
}

impl PipelineChoice {
    /// The feature set to compile for a scene using `scene` (all of them when unknown), whose
    /// frame picks lights through light trees when `light_trees` (the GPU scene has a tree and
    /// the settings ask for them: [`crate::gpu_scene::GpuScene::light_trees`]) and resamples
    /// its direct light when `restir_di`.
    pub fn features(
        self,
        scene: Option<&SceneFeatures>,
        light_trees: bool,
        restir_di: bool,
    ) -> PipelineFeatures {
        let setting = |on: bool, flag| {
            if on { flag } else { PipelineFeatures::NONE }
        };
        match self {
            PipelineChoice::Specialized => match scene {
                Some(scene) => PipelineFeatures::of_scene(scene)
                    .with(setting(light_trees, PipelineFeatures::LIGHT_TREES))
                    .with(setting(restir_di, PipelineFeatures::RESTIR_DI)),
                None => PipelineFeatures::ALL,
            },
            PipelineChoice::AllFeatures => PipelineFeatures::ALL,
            PipelineChoice::Exactly(features) => features,
        }
    }
}

/// One pipeline per feature set, built on demand.
pub struct PipelineCache<P> {
    pipelines: HashMap<PipelineFeatures, P>,
    /// The feature set being built on a background thread.
    pending: Option<(PipelineFeatures, mpsc::Receiver<P>)>,
    /// The feature set the last frame rendered with.
    current: Option<PipelineFeatures>,
    /// Pipelines built (or started in the background) so far.
    builds: u32,
}

impl<P> Default for PipelineCache<P> {
    fn default() -> Self {
        Self {
            pipelines: HashMap::new(),
            pending: None,
            current: None,
            builds: 0,
        }
    }
}

impl<P: Send + 'static> PipelineCache<P> {
    /// The pipeline this frame renders with, for a scene wanting `wanted`. A cached pipeline
    /// is used at once. Otherwise, with `background` and a pipeline already in use, `build`
    /// runs on another thread and the pipeline in use goes on rendering until the new one is
    /// ready; without, `build` runs now.
    pub fn select(
        &mut self,
        wanted: PipelineFeatures,
        background: bool,
        build: impl FnOnce(PipelineFeatures) -> P + Send + 'static,
    ) -> &P {
        if let Some((features, receiver)) = &self.pending
            && let Ok(pipeline) = receiver.try_recv()
        {
            self.pipelines.insert(*features, pipeline);
            self.pending = None;
        }
        let use_now = if self.pipelines.contains_key(&wanted) {
            wanted
        } else if let (true, Some(current)) = (background, self.current) {
            if self.pending.as_ref().is_none_or(|(f, _)| *f != wanted) {
                self.builds += 1;
                let (sender, receiver) = mpsc::channel();
                std::thread::spawn(move || {
                    // The receiver is gone only when the cache was dropped: nothing to do.
                    let _ = sender.send(build(wanted));
                });
                self.pending = Some((wanted, receiver));
            }
            current
        } else {
            self.builds += 1;
            self.pipelines.insert(wanted, build(wanted));
            wanted
        };
        self.current = Some(use_now);
        &self.pipelines[&use_now]
    }

    /// The feature set the last [`PipelineCache::select`] returned the pipeline of.
    pub fn current(&self) -> Option<PipelineFeatures> {
        self.current
    }

    /// The pipeline the last [`PipelineCache::select`] returned.
    pub fn pipeline(&self) -> Option<&P> {
        self.current.and_then(|f| self.pipelines.get(&f))
    }

    /// Pipelines built, or started in the background, since the cache was made.
    pub fn builds(&self) -> u32 {
        self.builds
    }

    /// Whether a pipeline is being built in the background.
    pub fn compiling(&self) -> bool {
        self.pending.is_some()
    }
}

/// Builds a pass's pipeline from its module and layout for a feature set.
pub type PipelineBuilder<P> =
    fn(&wgpu::Device, &wgpu::ShaderModule, &wgpu::PipelineLayout, PipelineFeatures) -> P;

/// A pass's shader module and pipeline layout, with one pipeline per feature set built from them
/// on demand.
pub struct SpecializedPipelines<P> {
    module: wgpu::ShaderModule,
    layout: wgpu::PipelineLayout,
    build: PipelineBuilder<P>,
    cache: PipelineCache<P>,
}

impl<P: Send + 'static> SpecializedPipelines<P> {
    /// No pipeline yet; `build` makes one from `module` and `layout`.
    pub fn new(
        module: wgpu::ShaderModule,
        layout: wgpu::PipelineLayout,
        build: PipelineBuilder<P>,
    ) -> Self {
        Self {
            module,
            layout,
            build,
            cache: PipelineCache::default(),
        }
    }

    /// Selects the pipeline for `features`, building it now or, with `background`, on another
    /// thread while the pipeline in use renders (see [`PipelineCache::select`]).
    pub fn specialize(
        &mut self,
        device: &wgpu::Device,
        features: PipelineFeatures,
        background: bool,
    ) {
        if self.cache.current() == Some(features) && !self.cache.compiling() {
            return; // The frame's usual case: nothing to select.
        }
        let (device, module, layout) = (device.clone(), self.module.clone(), self.layout.clone());
        let build = self.build;
        self.cache.select(features, background, move |features| {
            build(&device, &module, &layout, features)
        });
    }

    /// The pipeline in use (none before the first [`SpecializedPipelines::specialize`]).
    pub fn pipeline(&self) -> Option<&P> {
        self.cache.pipeline()
    }

    /// The feature set of the pipeline in use.
    pub fn features(&self) -> Option<PipelineFeatures> {
        self.cache.current()
    }

    /// Pipelines built so far (one per feature set rendered with).
    pub fn builds(&self) -> u32 {
        self.cache.builds()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_flags_are_distinct_bits_and_all_holds_them() {
        let mut seen = PipelineFeatures::NONE;
        for f in PipelineFeatures::FLAGS {
            assert_eq!(f.bit.0.count_ones(), 1, "{}", f.name);
            assert!(!seen.contains(f.bit), "{} repeats a bit", f.name);
            seen = seen.with(f.bit);
        }
        assert_eq!(seen, PipelineFeatures::ALL);
        assert!(features_module().contains("override FEATURE_ALPHA_MASKS: bool = true;"));
    }

    #[test]
    fn a_plain_scene_needs_no_feature_and_each_feature_turns_on_its_flag() {
        let plain = SceneFeatures::default();
        assert_eq!(PipelineFeatures::of_scene(&plain), PipelineFeatures::NONE);
        let map = SceneFeatures {
            environment: EnvironmentFeature::Map,
            alpha_masks: true,
            ..plain
        };
        assert_eq!(
            PipelineFeatures::of_scene(&map).names(),
            [
                "FEATURE_ALPHA_MASKS",
                "FEATURE_ENVIRONMENT",
                "FEATURE_ENVIRONMENT_MAP"
            ]
        );
        let constants = PipelineFeatures::ALPHA_MASKS.constants();
        assert_eq!(constants.len(), PipelineFeatures::FLAGS.len());
        assert!(constants.contains(&("FEATURE_ALPHA_MASKS", 1.0)));
        assert!(constants.contains(&("FEATURE_NORMAL_MAPS", 0.0)));
    }

    #[test]
    fn the_cache_builds_once_per_feature_set() {
        let mut cache = PipelineCache::default();
        let a = PipelineFeatures::NONE;
        let b = PipelineFeatures::ALPHA_MASKS;
        assert_eq!(*cache.select(a, false, |f| f.0), 0);
        assert_eq!(*cache.select(a, false, |_| panic!("built twice")), 0);
        assert_eq!(*cache.select(b, false, |f| f.0), b.0);
        assert_eq!(cache.current(), Some(b));
        assert_eq!(cache.builds(), 2);
    }

    #[test]
    fn in_the_background_the_old_pipeline_renders_until_the_new_one_is_ready() {
        let mut cache = PipelineCache::default();
        let old = PipelineFeatures::NONE;
        let new = PipelineFeatures::NORMAL_MAPS;
        // Nothing to show yet: the first pipeline is built at once even in the background.
        assert_eq!(*cache.select(old, true, |f| f.0), old.0);
        let (go, wait) = mpsc::channel::<()>();
        let build = move |f: PipelineFeatures| {
            wait.recv().unwrap();
            f.0
        };
        assert_eq!(*cache.select(new, true, build), old.0);
        assert!(cache.compiling());
        assert_eq!(*cache.select(new, true, |_| panic!("built twice")), old.0);
        go.send(()).unwrap();
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
        while *cache.select(new, true, |_| panic!("built twice")) != new.0 {
            assert!(std::time::Instant::now() < deadline, "never switched");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        assert!(!cache.compiling());
        assert_eq!(cache.current(), Some(new));
    }
}
