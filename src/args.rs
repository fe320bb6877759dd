//! Parsers for the command line's values. Each refuses what means nothing (NaN, infinities,
//! numbers out of range, a colour that is not three finite non-negative numbers) with a message
//! that clap prefixes with the argument's name, so `--env-strength nan` says which argument is
//! wrong and what it takes instead of acting as some default.

use std::path::PathBuf;

use glam::Vec3;

/// Largest image side the command line takes.
pub const MAX_SIDE: u32 = 16384;

/// Most frames `render` and `bench` take (a frame's timings are kept, so the count is bounded).
pub const MAX_FRAMES: u32 = 1_000_000;

/// Most worker threads `reference` starts.
pub const MAX_THREADS: usize = chiaro::reference::MAX_THREADS;

/// Largest multiplier of the environment's radiance (radiance beyond ~1e38 overflows f32).
pub const MAX_ENV_STRENGTH: f32 = 1e9;

/// `WxH`, each side in `1..=MAX_SIDE`.
pub fn size(text: &str) -> Result<(u32, u32), String> {
    let (w, h) = text
        .split_once('x')
        .ok_or_else(|| format!("'{text}' is not WxH"))?;
    match (w.parse::<u32>(), h.parse::<u32>()) {
        (Ok(w), Ok(h)) if (1..=MAX_SIDE).contains(&w) && (1..=MAX_SIDE).contains(&h) => Ok((w, h)),
        _ => Err(format!("'{text}' is not WxH with sides in 1..={MAX_SIDE}")),
    }
}

/// A finite number.
fn finite(text: &str) -> Result<f32, String> {
    let value: f32 = text
        .trim()
        .parse()
        .map_err(|_| format!("'{text}' is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("'{text}' is not a finite number"))
    }
}

/// A finite number at or above 0.
pub fn non_negative(text: &str) -> Result<f32, String> {
    match finite(text)? {
        v if v >= 0.0 => Ok(v),
        _ => Err(format!("{text} is below 0")),
    }
}

/// A finite number above 0.
pub fn positive(text: &str) -> Result<f32, String> {
    match finite(text)? {
        v if v > 0.0 => Ok(v),
        _ => Err(format!("{text} is not above 0")),
    }
}

/// The environment's strength: finite, in `0..=MAX_ENV_STRENGTH`.
pub fn env_strength(text: &str) -> Result<f32, String> {
    match non_negative(text)? {
        v if v <= MAX_ENV_STRENGTH => Ok(v),
        _ => Err(format!("{text} is above {MAX_ENV_STRENGTH:e}")),
    }
}

/// Most stops `--exposure` takes either way (2^30 is far past any display's range).
pub const MAX_EXPOSURE_STOPS: f32 = 30.0;

/// `--exposure`: stops, a finite number in `-MAX_EXPOSURE_STOPS..=MAX_EXPOSURE_STOPS`.
pub fn exposure_stops(text: &str) -> Result<f32, String> {
    match finite(text)? {
        v if v.abs() <= MAX_EXPOSURE_STOPS => Ok(v),
        _ => Err(format!(
            "{text} is outside -{MAX_EXPOSURE_STOPS}..={MAX_EXPOSURE_STOPS} stops"
        )),
    }
}

/// `--light-units`: how glTF punctual lights' intensities are read (the values are described
/// in the option's help, which stays on one line that way).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum LightUnitsArg {
    // chiaro::scene::LightUnits::Photometric.
    Photometric,
    // chiaro::scene::LightUnits::Unitless.
    Unitless,
}

/// The `--light-units` option of every command that loads a scene.
#[derive(Clone, Copy, clap::Args)]
pub struct LightUnitsArgs {
    /// How a glTF's punctual light intensities are read: photometric, candela (point, spot)
    /// and lux (directional) divided by 683 lm/W into W/sr and W/m^2, as Blender's glTF
    /// importer reads them; or unitless, the numbers as W/sr and W/m^2 (683 times brighter).
    /// Built-in scenes are not affected.
    #[arg(long, value_enum, default_value_t = LightUnitsArg::Photometric)]
    pub light_units: LightUnitsArg,
}

impl LightUnitsArgs {
    /// The loader's setting.
    pub fn units(self) -> chiaro::scene::LightUnits {
        match self.light_units {
            LightUnitsArg::Photometric => chiaro::scene::LightUnits::Photometric,
            LightUnitsArg::Unitless => chiaro::scene::LightUnits::Unitless,
        }
    }
}

/// `--time`: the animation time every command that loads a scene poses it at.
#[derive(Clone, Copy, clap::Args)]
pub struct TimeArgs {
    /// Poses the scene's glTF animations at this time, in seconds (each clip loops over its
    /// length). Without it the scene keeps the pose its nodes describe.
    #[arg(long, value_parser = finite_seconds, allow_negative_numbers = true)]
    pub time: Option<f64>,
}

/// `--frames-in-flight`: how many frames the CPU may have submitted before it waits for the
/// GPU (1 waits for every frame; see `chiaro::gpu::in_flight`).
#[derive(Clone, Copy, Debug, clap::Args)]
pub struct FramesInFlightArgs {
    /// Frames the GPU may have in flight, 1..=3: with 2 the CPU prepares the next frame while
    /// the GPU renders one; 1 waits for each (lowest latency). By default 2 on a GPU and 1 on
    /// a CPU adapter (lavapipe, llvmpipe), which runs one submission at a time. Wall-clock
    /// pass timing (CHIARO_TIMER=wall, or a device without timestamps) keeps it at 1.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=chiaro::gpu::MAX_FRAMES_IN_FLIGHT as i64))]
    pub frames_in_flight: Option<u32>,
}

impl FramesInFlightArgs {
    /// Sets the renderer's frames in flight where the option was given.
    pub fn apply(&self, renderer: &mut chiaro::gpu::Renderer) {
        if let Some(n) = self.frames_in_flight {
            renderer.set_frames_in_flight(n);
        }
    }
}

/// `--fps`: a frame rate in `0.001..=10000`.
pub fn frame_rate(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(f) if (0.001..=10_000.0).contains(&f) => Ok(f),
        _ => Err(format!("{text:?} is not a frame rate in 0.001..=10000")),
    }
}

/// A finite number of seconds.
fn finite_seconds(text: &str) -> Result<f64, String> {
    match text.trim().parse::<f64>() {
        Ok(t) if t.is_finite() => Ok(t),
        _ => Err(format!("{text:?} is not a finite number of seconds")),
    }
}

/// What `--env` names: a constant colour or an image file.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvArg {
    /// A constant linear colour.
    Color(Vec3),
    /// An equirectangular .hdr or .exr image.
    Image(PathBuf),
}

/// `--env`: an image file ending in .hdr or .exr, or a colour `R,G,B` of three finite numbers
/// in `0..=MAX_ENV_STRENGTH`.
pub fn env(text: &str) -> Result<EnvArg, String> {
    let lower = text.to_ascii_lowercase();
    if lower.ends_with(".hdr") || lower.ends_with(".exr") {
        return Ok(EnvArg::Image(PathBuf::from(text)));
    }
    if !text.contains(',') {
        return Err(format!(
            "'{text}' is neither an .hdr or .exr image nor a colour R,G,B"
        ));
    }
    let parts: Vec<&str> = text.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "'{text}' is not a colour R,G,B: it has {} components",
            parts.len()
        ));
    }
    let mut color = [0.0; 3];
    for (c, part) in color.iter_mut().zip(&parts) {
        *c = env_strength(part).map_err(|why| format!("colour '{text}': {why}"))?;
    }
    Ok(EnvArg::Color(Vec3::from(color)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_that_mean_nothing_are_refused() {
        for bad in ["nan", "inf", "-inf", "1e39", "x", ""] {
            assert!(non_negative(bad).is_err(), "{bad}");
            assert!(positive(bad).is_err(), "{bad}");
        }
        assert!(non_negative("-1").unwrap_err().contains("below 0"));
        assert_eq!(non_negative("0"), Ok(0.0));
        assert!(positive("0").unwrap_err().contains("not above 0"));
        assert!(env_strength("1e10").unwrap_err().contains("above"));
        assert_eq!(env_strength("2.5"), Ok(2.5));
        assert_eq!(exposure_stops("-1.5"), Ok(-1.5));
        assert!(exposure_stops("31").unwrap_err().contains("outside"));
        assert!(exposure_stops("nan").is_err());
    }

    #[test]
    fn env_tells_colours_from_images_and_names_the_fault() {
        assert_eq!(
            env("0.1, 0.2,0.3"),
            Ok(EnvArg::Color(Vec3::new(0.1, 0.2, 0.3)))
        );
        assert_eq!(env("sky.EXR"), Ok(EnvArg::Image(PathBuf::from("sky.EXR"))));
        assert!(
            env("1,nan,2")
                .unwrap_err()
                .contains("'nan' is not a finite number")
        );
        assert!(env("-1,0,0").unwrap_err().contains("-1 is below 0"));
        assert!(env("1e39,0,0").unwrap_err().contains("not a finite number"));
        assert!(env("1,2").unwrap_err().contains("2 components"));
        assert!(env("sky.png").unwrap_err().contains("neither"));
    }

    #[test]
    fn sizes_are_bounded() {
        assert_eq!(size("64x32"), Ok((64, 32)));
        for bad in ["0x4", "4x0", "16385x2", "4", "axb"] {
            assert!(size(bad).is_err(), "{bad}");
        }
    }
}
