//! The side panel: what the frame computes (the world's `FrameSettings`), how long it took,
//! the camera's speed, and the last error.

use chiaro_gpu::denoiser::MAX_ATROUS_ITERATIONS;
use chiaro_gpu::settings::{MAX_BOUNCES, MAX_SPP};
use chiaro_gpu::timing::PassTimes;
use chiaro_gpu::{FrameSettings, RenderMode};
use chiaro_shading::tonemap::{Tonemapper, exposure_from_ev};

use crate::debug_view::DebugView;

/// What the panel shows besides the settings.
pub struct PanelInfo<'a> {
    /// Size of the rendered frame in pixels.
    pub size: (u32, u32),
    /// The last frame's pass times.
    pub times: &'a PassTimes,
    /// Wall-clock time of the last frame, milliseconds.
    pub frame_ms: f64,
    /// The camera's base speed (scene units per second).
    pub speed: f32,
    /// The adapter.
    pub adapter: &'a str,
    /// The last error, if any.
    pub message: Option<&'a str>,
}

/// Shows the last error, if any; returns whether the user dismissed it.
pub fn message(ui: &mut egui::Ui, info: &PanelInfo) -> bool {
    let Some(message) = info.message else {
        return false;
    };
    ui.colored_label(egui::Color32::from_rgb(255, 110, 90), message);
    let dismissed = ui.button("dismiss").clicked();
    ui.separator();
    dismissed
}

/// Shows the frame settings' editors, the debug view's choice and the render scale (rendered
/// pixels per window pixel); edits them in place.
pub fn settings(
    ui: &mut egui::Ui,
    settings: &mut FrameSettings,
    view: &mut DebugView,
    render_scale: &mut f32,
) {
    egui::ComboBox::from_label("view")
        .selected_text(view.name())
        .show_ui(ui, |ui| {
            for v in DebugView::ALL {
                ui.selectable_value(view, v, v.name());
            }
        });
    if *view == DebugView::Traversal {
        crate::traversal_view::legend(ui);
    }
    egui::ComboBox::from_label("mode")
        .selected_text(settings.mode.name())
        .show_ui(ui, |ui| {
            for mode in RenderMode::ALL {
                ui.selectable_value(&mut settings.mode, mode, mode.name());
            }
        });
    ui.add(egui::Slider::new(render_scale, 0.25..=1.0).text("render scale"));
    ui.add(egui::Slider::new(&mut settings.spp, 1..=MAX_SPP).text("spp"));
    ui.add(egui::Slider::new(&mut settings.bounces, 1..=MAX_BOUNCES).text("bounces"));
    ui.separator();
    let d = &mut settings.denoise;
    ui.checkbox(&mut d.enabled, "denoiser");
    ui.add_enabled_ui(d.enabled, |ui| {
        ui.add(
            egui::Slider::new(&mut d.temporal_floor, 0.01..=1.0)
                .logarithmic(true)
                .text("temporal floor"),
        );
        ui.checkbox(&mut d.converge_when_still, "converge when still");
        let most = MAX_ATROUS_ITERATIONS as u32;
        ui.add(egui::Slider::new(&mut d.atrous_iterations, 0..=most).text("a-trous iterations"));
        ui.add(
            egui::Slider::new(&mut d.sigma_depth, 0.01..=100.0)
                .logarithmic(true)
                .text("sigma depth"),
        );
        ui.add(
            egui::Slider::new(&mut d.sigma_normal, 1.0..=1024.0)
                .logarithmic(true)
                .text("sigma normal"),
        );
        ui.add(
            egui::Slider::new(&mut d.sigma_luminance, 0.1..=100.0)
                .logarithmic(true)
                .text("sigma luminance"),
        );
    });
    ui.separator();
    let mut stops = settings.exposure.log2();
    if ui
        .add(egui::Slider::new(&mut stops, -10.0..=10.0).text("exposure (stops)"))
        .changed()
    {
        settings.exposure = exposure_from_ev(stops);
    }
    egui::ComboBox::from_label("tonemapper")
        .selected_text(settings.tonemapper.name())
        .show_ui(ui, |ui| {
            for t in Tonemapper::ALL {
                ui.selectable_value(&mut settings.tonemapper, t, t.name());
            }
        });
}

/// Shows the frame's size and times, the camera's speed, the keys and the adapter.
pub fn times(ui: &mut egui::Ui, info: &PanelInfo) {
    ui.label(format!(
        "{}x{}: frame {:.1} ms ({:.1} fps)",
        info.size.0,
        info.size.1,
        info.frame_ms,
        1e3 / info.frame_ms.max(1e-3)
    ));
    let clock = if info.times.gpu_timestamps {
        "GPU timestamps"
    } else {
        "wall clock"
    };
    ui.label(format!("passes {:.2} ms ({clock})", info.times.total_ms()));
    for (name, ms) in &info.times.passes {
        ui.monospace(format!("{name:<10} {ms:9.2} ms"));
    }
    ui.separator();
    ui.label(format!("speed {:.3} units/s", info.speed));
    ui.small("WASD move, Q/E down/up, right drag look, wheel speed, shift fast");
    ui.small("Tab panel, F12 screenshot, drop .glb/.gltf/.hdr/.exr");
    ui.small(info.adapter);
}
