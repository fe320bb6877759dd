//! Error against time, log-log, one line per configuration, drawn as PNG with plotters.

use std::path::Path;
use std::sync::OnceLock;

use plotters::prelude::*;
use plotters::style::FontStyle;

use super::BenchError;
use super::results::{BenchResults, SceneResult};

/// Plot size in pixels.
const SIZE: (u32, u32) = (900, 600);

/// Where a TrueType font for the labels is looked for (plotters draws text only with a font
/// registered from its bytes).
const FONT_CANDIDATES: [&str; 4] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
];

/// Registers the first font found, once; the error names where it looked.
fn register_font() -> Result<(), BenchError> {
    static FONT: OnceLock<Result<(), String>> = OnceLock::new();
    FONT.get_or_init(|| {
        let bytes = FONT_CANDIDATES
            .iter()
            .find_map(|path| std::fs::read(path).ok())
            .ok_or_else(|| format!("no font for the labels in {FONT_CANDIDATES:?}"))?;
        // plotters keeps fonts for the whole run.
        let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
        plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
            .map_err(|_| "the font found is not a valid TrueType font".to_string())
    })
    .clone()
    .map_err(BenchError::Plot)
}

/// The span of `values` widened to whole decades, for a log axis.
fn decades(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (lo, hi) = values
        .filter(|v| *v > 0.0 && v.is_finite())
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    (hi > 0.0).then(|| {
        (
            10f64.powf(lo.log10().floor()),
            10f64.powf(hi.log10().ceil()),
        )
    })
}

/// Draws `scene`'s relMSE against cumulative frame time into `path`, titled with the adapter
/// and resolution of `results`.
pub fn plot_scene(
    path: &Path,
    results: &BenchResults,
    scene: &SceneResult,
) -> Result<(), BenchError> {
    register_font()?;
    let points = || scene.runs.iter().flat_map(|r| &r.checkpoints);
    let (Some(x), Some(y)) = (
        decades(points().map(|c| c.seconds)),
        decades(points().map(|c| c.rel_mse)),
    ) else {
        return Err(BenchError::Plot(format!(
            "{}: nothing to plot",
            scene.scene
        )));
    };
    let mut pixels = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    let fault = |e: &dyn std::fmt::Display| BenchError::Plot(format!("{}: {e}", path.display()));
    {
        let root = BitMapBackend::with_buffer(&mut pixels, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fault(&e))?;
        let title = format!(
            "{} - {} - {}x{}",
            scene.scene, results.adapter, results.width, results.height
        );
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d((x.0..x.1).log_scale(), (y.0..y.1).log_scale())
            .map_err(|e| fault(&e))?;
        chart
            .configure_mesh()
            .x_desc("time of the frames (s)")
            .y_desc("relMSE vs converged reference")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| fault(&e))?;
        for (i, run) in scene.runs.iter().enumerate() {
            let colour = Palette99::pick(i).to_rgba();
            let line: Vec<(f64, f64)> = run
                .checkpoints
                .iter()
                .map(|c| (c.seconds, c.rel_mse))
                .collect();
            chart
                .draw_series(LineSeries::new(line.clone(), colour.stroke_width(2)))
                .map_err(|e| fault(&e))?
                .label(run.config.clone())
                .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], colour));
            chart
                .draw_series(line.into_iter().map(|p| Circle::new(p, 3, colour.filled())))
                .map_err(|e| fault(&e))?;
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| fault(&e))?;
        root.present().map_err(|e| fault(&e))?;
    }
    image::save_buffer(path, &pixels, SIZE.0, SIZE.1, image::ColorType::Rgb8).map_err(|e| fault(&e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_cover_the_values_with_whole_powers_of_ten() {
        let (lo, hi) = decades([0.03, 2.5, f64::NAN, 0.0].into_iter()).unwrap();
        assert!((lo - 0.01).abs() < 1e-12 && (hi - 10.0).abs() < 1e-12);
        assert_eq!(decades([0.0, -1.0].into_iter()), None);
    }
}
