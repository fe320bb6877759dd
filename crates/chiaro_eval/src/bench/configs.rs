//! The GPU configurations the benchmark measures: the default set, those measured only when
//! named, and the runs along the camera path that go with them.

use chiaro_gpu::settings::LightSampling;
use chiaro_gpu::{FrameSettings, PipelineChoice, RenderMode, RenderSettings, RestirBias};

use super::camera_path::PATH_CONFIG;

/// One GPU configuration to measure.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Its name in the tables and plots.
    pub name: String,
    /// How it renders (size and frame count are the benchmark's).
    pub settings: RenderSettings,
}

/// The realtime configuration with resampled direct light.
pub const RESTIR_DI_CONFIG: &str = "realtime-restir-di";
/// The realtime configuration with resampled indirect light.
pub const RESTIR_GI_CONFIG: &str = "realtime-restir-gi";
/// The realtime configuration with resampled indirect light and temporal reuse of its
/// reservoirs (history cap 20).
pub const RESTIR_GI_TEMPORAL_CONFIG: &str = "realtime-restir-gi-temporal";
/// The realtime configuration with resampled indirect light weighted by pairwise MIS with
/// visibility ([`chiaro_gpu::RestirBias::Unbiased`]).
pub const RESTIR_GI_UNBIASED_CONFIG: &str = "realtime-restir-gi-unbiased";
/// The realtime configuration with resampled direct and indirect light.
pub const RESTIR_CONFIG: &str = "realtime-restir";

/// The realtime configuration compiled with every shader feature, whatever the scene uses.
pub const ALL_FEATURES_CONFIG: &str = "realtime-all-features";

/// The configurations measured by default: direct light only; realtime as it ships, and
/// without its denoiser, with 2 and 4 paths per pixel and with bounce caps 1 and 2 (it ships
/// with 3); the naive paths; the GPU reference.
pub fn default_configs() -> Vec<BenchConfig> {
    let realtime = FrameSettings::default();
    let mut raw = realtime;
    raw.denoise.enabled = false;
    let mode = |mode| FrameSettings { mode, ..realtime };
    configs([
        ("direct", mode(RenderMode::Direct)),
        ("realtime", realtime),
        ("realtime-no-denoise", raw),
        ("realtime-spp2", FrameSettings { spp: 2, ..realtime }),
        ("realtime-spp4", FrameSettings { spp: 4, ..realtime }),
        (
            "realtime-bounces1",
            FrameSettings {
                bounces: 1,
                ..realtime
            },
        ),
        (
            "realtime-bounces2",
            FrameSettings {
                bounces: 2,
                ..realtime
            },
        ),
        ("naive", mode(RenderMode::Naive)),
        ("reference", mode(RenderMode::Reference)),
    ])
}

/// The configurations measured only when asked for by name: realtime with every shader
/// feature compiled in rather than only the scene's (what specialisation saves), direct
/// and realtime with lights picked by power instead of through the light trees (the
/// many-lights baseline), realtime whose still view keeps the moving average's memory
/// (what [`chiaro_gpu::still_view`] buys), and realtime with resampled direct light, indirect
/// light (with and without temporal reuse, by counts or by pairwise MIS) or both
/// ([`chiaro_gpu::RestirSettings`]).
pub fn extra_configs() -> Vec<BenchConfig> {
    let realtime = FrameSettings::default();
    let power = LightSampling::Power;
    let mut moving_average = realtime;
    moving_average.denoise.converge_when_still = false;
    let mut restir_di = realtime;
    restir_di.restir.direct = true;
    let mut restir_gi = realtime;
    restir_gi.restir.indirect = true;
    let mut restir_gi_temporal = restir_gi;
    restir_gi_temporal.restir.indirect_history_cap = 20;
    let mut restir_gi_unbiased = restir_gi;
    restir_gi_unbiased.restir.bias = RestirBias::Unbiased;
    let mut restir = restir_di;
    restir.restir.indirect = true;
    configs([
        (
            "direct-power",
            FrameSettings {
                mode: RenderMode::Direct,
                light_sampling: power,
                ..realtime
            },
        ),
        (
            ALL_FEATURES_CONFIG,
            FrameSettings {
                pipeline: PipelineChoice::AllFeatures,
                ..realtime
            },
        ),
        (
            "realtime-power",
            FrameSettings {
                light_sampling: power,
                ..realtime
            },
        ),
        ("realtime-moving-average", moving_average),
        (RESTIR_DI_CONFIG, restir_di),
        (RESTIR_GI_CONFIG, restir_gi),
        (RESTIR_GI_TEMPORAL_CONFIG, restir_gi_temporal),
        (RESTIR_GI_UNBIASED_CONFIG, restir_gi_unbiased),
        (RESTIR_CONFIG, restir),
    ])
}

/// The runs along the camera path: the realtime frame as it ships (`realtime-path`), and each
/// resampling configuration `configs` measure (`realtime-restir-di-path`, ...).
pub(super) fn path_configs(configs: &[BenchConfig]) -> Vec<BenchConfig> {
    let mut paths = vec![BenchConfig {
        name: PATH_CONFIG.into(),
        settings: RenderSettings::default(),
    }];
    let resampling = [
        RESTIR_DI_CONFIG,
        RESTIR_GI_CONFIG,
        RESTIR_GI_TEMPORAL_CONFIG,
        RESTIR_GI_UNBIASED_CONFIG,
        RESTIR_CONFIG,
    ];
    paths.extend(
        configs
            .iter()
            .filter(|c| resampling.contains(&c.name.as_str()))
            .map(|c| BenchConfig {
                name: format!("{}-path", c.name),
                settings: c.settings,
            }),
    );
    paths
}

fn configs<const N: usize>(named: [(&str, FrameSettings); N]) -> Vec<BenchConfig> {
    named
        .into_iter()
        .map(|(name, frame)| BenchConfig {
            name: name.into(),
            settings: RenderSettings {
                frame,
                ..RenderSettings::default()
            },
        })
        .collect()
}
