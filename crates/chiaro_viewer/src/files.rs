//! Files the viewer reads and writes: screenshots (PNG of the tonemapped frame, EXR of its
//! linear HDR) and files dropped on the window (a glTF scene or an environment image).

use std::path::{Path, PathBuf};

use bevy_ecs::world::World;
use chiaro_gpu::{RenderSettings, Renderer};
use chiaro_scene::{Environment, load_scene};

/// Saves the renderer's last frame to `path`: `.png` writes the 8-bit image the window shows
/// (`shown`, a debug view, or else the tonemapped frame), `.exr` the frame's linear HDR image.
/// Returns the image size.
pub fn save_screenshot(
    renderer: &Renderer,
    shown: Option<&wgpu::Texture>,
    path: &Path,
) -> Result<(u32, u32), String> {
    let frame = renderer
        .frame()
        .ok_or_else(|| format!("{}: nothing was rendered yet", path.display()))?;
    let (width, height) = (frame.targets.width, frame.targets.height);
    let settings = RenderSettings {
        width,
        height,
        ..RenderSettings::default()
    };
    let mut image = renderer
        .read(&settings)
        .map_err(|e| format!("{}: {e}", path.display()))?;
    if let Some(texture) = shown {
        let context = &renderer.context;
        image.ldr = chiaro_gpu::readback::read_texture(&context.device, &context.queue, texture, 4)
            .map_err(|e| format!("{}: {e}", path.display()))?;
    }
    match path.extension().and_then(|e| e.to_str()) {
        Some("exr") => chiaro_reference::write_exr(path, width, height, &image.hdr)
            .map_err(|e| e.to_string())?,
        Some("png") => chiaro_reference::write_png_pixels(
            path,
            width,
            height,
            &image.ldr,
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|e| e.to_string())?,
        _ => return Err(format!("{}: must end in .png or .exr", path.display())),
    }
    Ok((width, height))
}

/// The first `chiaro-NNNN` in `folder` with neither a .png nor an .exr of that name.
pub fn next_screenshot_stem(folder: &Path) -> PathBuf {
    (0..10_000)
        .map(|n| folder.join(format!("chiaro-{n:04}")))
        .find(|stem| !stem.with_extension("png").exists() && !stem.with_extension("exr").exists())
        .unwrap_or_else(|| folder.join("chiaro-last"))
}

/// What a dropped file became.
pub enum Dropped {
    /// A new scene, loaded into its own World.
    Scene(Box<World>),
    /// A new environment for the current scene.
    Environment(Environment),
}

/// "cannot load PATH: ERROR", the path left out when the error names it already.
fn naming(path: &Path, error: impl std::fmt::Display) -> String {
    let error = error.to_string();
    let name = path.display().to_string();
    if error.contains(&name) {
        format!("cannot load: {error}")
    } else {
        format!("cannot load {name}: {error}")
    }
}

/// Loads a dropped file: `.glb`/`.gltf` as a new scene (a World of its own, so the current
/// one is untouched on failure), `.hdr`/`.exr` as the environment (strength 1). The error
/// names the file and the fault.
pub fn load_dropped(path: &Path) -> Result<Dropped, String> {
    let extension = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("glb" | "gltf") => {
            let spec = path
                .to_str()
                .ok_or_else(|| format!("{}: the path is not UTF-8", path.display()))?;
            let mut world = World::new();
            let spawned = load_scene(&mut world, spec).map_err(|e| naming(path, e))?;
            for repair in &spawned.repairs {
                log::warn!("{}: {repair}", path.display());
            }
            Ok(Dropped::Scene(Box::new(world)))
        }
        Some("hdr" | "exr") => {
            let (environment, repairs) =
                Environment::from_file(path, 1.0).map_err(|e| naming(path, e))?;
            for repair in repairs {
                log::warn!("{}: {repair}", path.display());
            }
            Ok(Dropped::Environment(environment))
        }
        _ => Err(format!(
            "{}: only .glb, .gltf, .hdr and .exr files can be dropped",
            path.display()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn broken_and_unknown_files_are_errors_naming_the_file() {
        let dir = std::env::temp_dir().join(format!("chiaro-viewer-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let broken = dir.join("broken.glb");
        std::fs::write(&broken, b"glTF\x02\x00garbage").unwrap();
        for path in [broken, dir.join("missing.hdr"), dir.join("notes.txt")] {
            match load_dropped(&path) {
                Ok(_) => panic!("{} loaded", path.display()),
                Err(e) => assert!(e.contains(&path.display().to_string()), "{e}"),
            }
        }
        assert_eq!(next_screenshot_stem(&dir), dir.join("chiaro-0000"));
        std::fs::write(dir.join("chiaro-0000.exr"), b"").unwrap();
        assert_eq!(next_screenshot_stem(&dir), dir.join("chiaro-0001"));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
