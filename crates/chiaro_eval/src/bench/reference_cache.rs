//! The converged reference of a benchmark scene, rendered once (by the CPU reference path
//! tracer, or by the GPU frame's reference mode where the CPU would take far too long) and
//! cached on disk under a hash of everything that decides its pixels.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use bevy_ecs::world::World;
use chiaro_gpu::{FrameSettings, RenderMode, Renderer};
use chiaro_reference::{
    Integrator, PathSettings, RenderSettings, read_exr, render_world, write_exr,
};
use chiaro_scene::SceneInfo;
use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::{BenchError, BenchScene};
use crate::HdrImage;
use crate::metrics::rel_mse;

/// The seed of every converged reference (the GPU runs use other seeds, so the two share no
/// random numbers).
const REFERENCE_SEED: u64 = 0x005e_ed0f_7e57;

/// Which renderer draws the converged references.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ReferenceRenderer {
    /// The CPU reference on every core, with this integrator: code apart from the GPU frame
    /// under test.
    Cpu(Integrator),
    /// The GPU frame's reference mode, in two halves of other seeds than the runs': for a
    /// real GPU at sizes where the CPU reference would take many times longer than the runs
    /// (the hard-case suite tests that the two references agree).
    Gpu,
}

impl Default for ReferenceRenderer {
    fn default() -> Self {
        Self::Cpu(Integrator::Pt)
    }
}

impl ReferenceRenderer {
    /// Its name in the results: the CPU's names its integrator unless it is the path tracer.
    pub fn name(self) -> String {
        match self {
            Self::Cpu(Integrator::Pt) => "CPU reference".to_owned(),
            Self::Cpu(integrator) => format!("CPU reference ({integrator})"),
            Self::Gpu => "GPU reference mode".to_owned(),
        }
    }
}

/// A converged reference and what is known of its own noise.
pub struct Reference {
    /// The linear HDR image.
    pub image: HdrImage,
    /// Its own relMSE noise: a quarter of the relMSE between its two independent halves.
    pub noise: f64,
    /// Seconds the reference took (when it was rendered, not read from the cache).
    pub seconds: f64,
    /// True when it was read from the cache.
    pub cached: bool,
}

/// What the cache keeps beside the image.
#[derive(Serialize, Deserialize)]
struct Sidecar {
    noise: f64,
    seconds: f64,
}

/// FNV-1a over `bytes`: a hash that stays the same across builds and platforms.
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A file as the cache knows it: its path, size and a hash of its bytes. A copy or a fresh
/// checkout of the same file (a new modification time) keeps its cached reference; an edit
/// renders it again. A file that cannot be read is named as such (loading it fails anyway).
fn file_stamp(path: &Path) -> String {
    match fs::read(path) {
        Ok(bytes) => format!("{} {} {:016x}", path.display(), bytes.len(), fnv1a(&bytes)),
        Err(e) => format!("{} unreadable: {e}", path.display()),
    }
}

/// What decides the reference's pixels: the scene (its name; its file's size and content hash
/// when it is a file; and `held`, the summary of what the loaded scene holds: meshes,
/// triangles, materials, lights, camera, bounds, environment, so that a scene that changed
/// under the same name, a built-in one included, is rendered again), how its light intensities
/// are read, its environment file (by
/// path, size and content hash), the image size, the sample count, the seed, the path
/// settings, the chiaro version, and `drawn_by`: which renderer (for the GPU, on which
/// adapter).
fn cache_key(
    scene: &BenchScene,
    held: &SceneInfo,
    (width, height, spp): (u32, u32, u32),
    drawn_by: &str,
) -> String {
    let file = (!scene.scene.starts_with("builtin:")).then(|| file_stamp(Path::new(&scene.scene)));
    let env = scene.env.as_deref().map(file_stamp);
    format!(
        "{} {file:?} {held:?} {:?} {env:?} {width}x{height} {spp} {REFERENCE_SEED} {:?} {} \
         {drawn_by}",
        scene.scene,
        scene.light_units,
        PathSettings::default(),
        env!("CARGO_PKG_VERSION")
    )
}

/// The cached reference's path in `cache_dir`.
fn cache_path(cache_dir: &Path, key: &str) -> PathBuf {
    cache_dir.join(format!("reference-{:016x}.exr", fnv1a(key.as_bytes())))
}

/// The converged reference of `scene` (loaded in `world`) at `width` x `height` with `spp`
/// samples per pixel, drawn by `drawn_by` (the GPU one with `renderer`): read from
/// `cache_dir` when it is there, else rendered and stored.
pub fn converged_reference(
    scene: &BenchScene,
    world: &mut World,
    (width, height, spp): (u32, u32, u32),
    drawn_by: ReferenceRenderer,
    renderer: &mut Renderer,
    cache_dir: &Path,
) -> Result<Reference, BenchError> {
    let renderer_key = match drawn_by {
        ReferenceRenderer::Cpu(_) => drawn_by.name(),
        ReferenceRenderer::Gpu => format!("{} {}", drawn_by.name(), renderer.context.describe()),
    };
    let held = SceneInfo::gather(world);
    // A pose of the scene's animations is part of what it holds.
    let time = world
        .get_resource::<chiaro_scene::Time>()
        .map(|t| t.seconds);
    let key = format!(
        "{} at {time:?}",
        cache_key(scene, &held, (width, height, spp), &renderer_key)
    );
    let path = cache_path(cache_dir, &key);
    let sidecar_path = path.with_extension("json");
    if let (Ok(text), true) = (fs::read_to_string(&sidecar_path), path.exists())
        && let Ok(sidecar) = serde_json::from_str::<Sidecar>(&text)
    {
        let (w, h, pixels) = read_exr(&path)?;
        let image = HdrImage::new(&path.display().to_string(), w, h, pixels)?;
        return Ok(Reference {
            image,
            noise: sidecar.noise,
            seconds: sidecar.seconds,
            cached: true,
        });
    }
    let start = Instant::now();
    let (pixels, noise) = match drawn_by {
        ReferenceRenderer::Cpu(integrator) => {
            let settings = RenderSettings {
                width,
                height,
                spp,
                seed: REFERENCE_SEED,
                path: PathSettings {
                    integrator,
                    ..PathSettings::default()
                },
                ..RenderSettings::default()
            };
            let output = render_world(world, &settings, false)?;
            let noise = output.halves_rel_mse() / 4.0;
            (output.image, noise)
        }
        ReferenceRenderer::Gpu => {
            let size = (width, height, spp / 2);
            let a = gpu_half(renderer, world, size, REFERENCE_SEED)?;
            let b = gpu_half(renderer, world, size, REFERENCE_SEED + 1)?;
            let noise = rel_mse(&a, &b, 0.01) / 4.0;
            let mean = a.iter().zip(&b).map(|(x, y)| (*x + *y) * 0.5).collect();
            (mean, noise)
        }
    };
    let seconds = start.elapsed().as_secs_f64();
    fs::create_dir_all(cache_dir).map_err(|e| BenchError::io(cache_dir, &e))?;
    write_exr(&path, width, height, &pixels)?;
    let sidecar = serde_json::to_string(&Sidecar { noise, seconds }).expect("plain numbers");
    fs::write(&sidecar_path, sidecar).map_err(|e| BenchError::io(&sidecar_path, &e))?;
    let image = HdrImage::new(&scene.label(), width, height, pixels)?;
    Ok(Reference {
        image,
        noise,
        seconds,
        cached: false,
    })
}

/// One half of a GPU reference: the reference mode for `spp` frames of one sample per pixel
/// from `seed`. One frame draws the camera ray and its direct light once whatever its `spp`
/// (which multiplies only the indirect paths), so every sample is a frame of its own.
fn gpu_half(
    renderer: &mut Renderer,
    world: &mut World,
    (width, height, spp): (u32, u32, u32),
    seed: u64,
) -> Result<Vec<Vec3>, BenchError> {
    let settings = chiaro_gpu::RenderSettings {
        width,
        height,
        frames: spp,
        seed,
        frame: FrameSettings {
            mode: RenderMode::Reference,
            spp: 1,
            ..FrameSettings::default()
        },
    };
    Ok(renderer.render(world, &settings)?.hdr)
}

#[cfg(test)]
mod tests {
    use super::*;
    use chiaro_scene::LightUnits;

    #[test]
    fn the_key_changes_with_everything_that_decides_the_pixels() {
        let scene = BenchScene::builtin("builtin:cornell");
        let mut world = scene.load().unwrap();
        let held = SceneInfo::gather(&mut world);
        let base = cache_key(&scene, &held, (64, 64, 16), "cpu");
        assert_ne!(base, cache_key(&scene, &held, (64, 32, 16), "cpu"));
        assert_ne!(base, cache_key(&scene, &held, (64, 64, 32), "cpu"));
        assert_ne!(base, cache_key(&scene, &held, (64, 64, 16), "gpu"));
        let integrators = [Integrator::Pt, Integrator::Bdpt, Integrator::Mlt].map(|i| {
            cache_key(
                &scene,
                &held,
                (64, 64, 16),
                &ReferenceRenderer::Cpu(i).name(),
            )
        });
        assert_ne!(integrators[0], integrators[1]);
        assert_ne!(integrators[1], integrators[2]);
        assert_ne!(
            base,
            cache_key(
                &BenchScene::builtin("builtin:furnace"),
                &held,
                (64, 64, 16),
                "cpu"
            )
        );
        let lit = BenchScene {
            env: Some(PathBuf::from("sky.hdr")),
            ..scene.clone()
        };
        assert_ne!(base, cache_key(&lit, &held, (64, 64, 16), "cpu"));
        let unitless = BenchScene {
            light_units: LightUnits::Unitless,
            ..scene.clone()
        };
        assert_ne!(base, cache_key(&unitless, &held, (64, 64, 16), "cpu"));
        assert_eq!(base, cache_key(&scene, &held, (64, 64, 16), "cpu"));
        // The same name holding another scene (as a built-in scene changed by a new build).
        let other = SceneInfo::gather(&mut BenchScene::builtin("builtin:furnace").load().unwrap());
        assert_ne!(base, cache_key(&scene, &other, (64, 64, 16), "cpu"));
    }

    #[test]
    fn fnv1a_matches_its_published_test_vectors() {
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(b"foobar"), 0x8594_4171_f739_67e8);
    }

    #[test]
    fn a_scene_file_is_known_by_its_bytes_not_its_time() {
        let dir = std::env::temp_dir().join(format!("chiaro-cache-key-{}", std::process::id()));
        fs::create_dir_all(&dir).unwrap();
        let file = dir.join("scene.glb");
        let scene = BenchScene {
            scene: file.display().to_string(),
            env: None,
            light_units: LightUnits::default(),
        };
        let held = SceneInfo::gather(&mut BenchScene::builtin("builtin:cornell").load().unwrap());
        fs::write(&file, b"glTF one").unwrap();
        let base = cache_key(&scene, &held, (64, 64, 16), "cpu");
        // The same bytes written again, with a modification time a day older.
        fs::write(&file, b"glTF one").unwrap();
        let day_ago = std::time::SystemTime::now() - std::time::Duration::from_secs(86_400);
        fs::File::options()
            .write(true)
            .open(&file)
            .unwrap()
            .set_modified(day_ago)
            .unwrap();
        assert_eq!(base, cache_key(&scene, &held, (64, 64, 16), "cpu"));
        // Other bytes of the same size.
        fs::write(&file, b"glTF two").unwrap();
        assert_ne!(base, cache_key(&scene, &held, (64, 64, 16), "cpu"));
        fs::remove_dir_all(&dir).unwrap();
    }
}
