//! chiaro's interactive viewer: a window (winit, X11) presenting the realtime frame of a scene,
//! a walkthrough camera, an egui side panel over the world's `FrameSettings`, screenshots, and
//! files dropped on the window. `chiaro view` runs it.
//!
//! Every edit goes through the ECS World: the camera moves by its entity's `Transform`, the
//! panel edits the `FrameSettings` resource, a dropped environment replaces the `Environment`
//! resource, so the renderer's change tracking (history reset, motion vectors, uploads) sees
//! each one.
//!
//! Keys: W/A/S/D move, Q/E down and up, the right mouse button held turns the view, the wheel
//! changes the speed, shift moves faster; Tab shows or hides the panel; Esc quits; F12 saves
//! `chiaro-NNNN.png` and `chiaro-NNNN.exr` in the working folder. A left click on the frame
//! selects the instance seen there ([`selection`]); the panel then edits its `Transform` and its
//! material (in the `Materials` resource), or a light's colour and intensity, and adds or removes
//! point lights.
//!
//! A [`script`] replays input and exits, for tests and reproducible walkthroughs:
//!
//! ```no_run
//! use bevy_ecs::world::World;
//! use chiaro_viewer::{ViewerOptions, script};
//!
//! let mut world = World::new();
//! chiaro_scene::load_scene(&mut world, "builtin:cornell").unwrap();
//! let commands = script::parse("panel off\nframes 8\nkey W 4\n", ".".as_ref()).unwrap();
//! let options = ViewerOptions {
//!     size: (96, 96),
//!     script: Some(commands),
//!     screenshot: Some("walk.png".into()),
//!     ..ViewerOptions::default()
//! };
//! chiaro_viewer::run(world, options).unwrap();
//! ```

#![warn(missing_docs)]

mod app;
pub mod camera;
pub mod debug_view;
mod display;
pub mod files;
mod inspector;
mod panel;
pub mod script;
pub mod selection;
#[cfg(test)]
mod shader_check;
pub mod traversal_view;

use std::path::PathBuf;

use bevy_ecs::world::World;
use thiserror::Error;
use winit::event_loop::{ControlFlow, EventLoop};

pub use app::read_script;

/// Why the viewer could not run or stopped.
#[derive(Debug, Error)]
pub enum ViewerError {
    /// No display to open a window on.
    #[error(
        "no display to open a window on: set DISPLAY to an X server (or run `chiaro render`, which needs none)"
    )]
    NoDisplay,
    /// The display could not be opened, in winit's words without its source location.
    #[error("cannot open the display: {0}")]
    EventLoop(String),
    /// The window could not be made.
    #[error("cannot create the window: {0}")]
    Window(String),
    /// No adapter could present to the window and run chiaro, or presenting failed.
    #[error("{0}")]
    Gpu(String),
    /// A script line does not parse.
    #[error(transparent)]
    Script(#[from] script::ScriptError),
    /// A file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The fault.
        message: String,
    },
    /// A scripted screenshot could not be written.
    #[error("screenshot: {0}")]
    Screenshot(String),
    /// A script moved the selection when nothing was selected.
    #[error("the script moves the selection, but nothing is selected (click on an instance first)")]
    NothingSelected,
    /// The window did not take the size a script asked for.
    #[error("the window did not resize to {0}x{1} (it is {2:?})")]
    Resize(u32, u32, winit::dpi::PhysicalSize<u32>),
}

/// How the viewer starts.
#[derive(Clone, Debug)]
pub struct ViewerOptions {
    /// The window's title.
    pub title: String,
    /// The window's inner size in pixels.
    pub size: (u32, u32),
    /// Input to replay; the viewer exits when it ends.
    pub script: Option<Vec<script::Command>>,
    /// A screenshot saved when the script ends (.png or .exr).
    pub screenshot: Option<PathBuf>,
    /// Seed of the frame's random numbers.
    pub seed: u64,
}

impl Default for ViewerOptions {
    fn default() -> Self {
        Self {
            title: "chiaro".into(),
            size: (1280, 720),
            script: None,
            screenshot: None,
            seed: 0,
        }
    }
}

/// Opens a window on `world` and runs until it is closed (or the script ends).
pub fn run(world: World, options: ViewerOptions) -> Result<(), ViewerError> {
    let has_display = ["DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET"]
        .iter()
        .any(|name| std::env::var_os(name).is_some_and(|v| !v.is_empty()));
    if !has_display {
        return Err(ViewerError::NoDisplay);
    }
    let event_loop = EventLoop::new().map_err(event_loop_error)?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = app::App::new(world, options, event_loop.owned_display_handle());
    event_loop.run_app(&mut app).map_err(event_loop_error)?;
    match app.fatal.take() {
        Some(error) => Err(error),
        None => Ok(()),
    }
}

/// winit's error as a user reads it: its OS errors begin with the source file and line in
/// winit that raised them, which mean nothing to a user and are dropped.
fn event_loop_error(error: winit::error::EventLoopError) -> ViewerError {
    let text = error.to_string();
    let words = match text.strip_prefix("os error at ") {
        Some(rest) => rest
            .split_once(": ")
            .map_or(rest.to_owned(), |(_, what)| what.to_owned()),
        None => text,
    };
    ViewerError::EventLoop(words)
}

/// The viewer's own shader `name` (source `text`), its `#import`s resolved from chiaro's shader
/// library.
fn compose_shader(name: &str, text: &str) -> Result<String, chiaro_gpu::ShaderError> {
    chiaro_gpu::shaders::compose_with(name, &|wanted| {
        if wanted == name {
            Some(text.to_owned())
        } else {
            chiaro_gpu::shaders::source(wanted)
        }
    })
}
