//! The winit application: window events to camera moves, settings edits, dropped files and
//! screenshots; one realtime frame per redraw, shown beside the egui panel.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use bevy_ecs::hierarchy::ChildOf;
use bevy_ecs::prelude::*;
use bevy_ecs::system::RunSystemOnce;
use chiaro_gpu::gpu_scene::GpuScene;
use chiaro_gpu::timing::PassTimes;
use chiaro_gpu::{FrameSettings, RenderSettings};
use chiaro_scene::transform::propagate_transforms;
use chiaro_scene::{ActiveCamera, Animations, GlobalTransform, SceneInfo, Time, Transform};
use glam::{Affine3A, Vec2, Vec3};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, OwnedDisplayHandle};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::camera::{MoveKeys, WalkCamera, speed_for_extent};
use crate::debug_view::DebugView;
use crate::display::Display;
use crate::files::{Dropped, load_dropped, next_screenshot_stem, save_screenshot};
use crate::inspector;
use crate::panel::{self, PanelInfo};
use crate::script::SCRIPT_DT;
use crate::selection::pick;
use crate::{ViewerError, ViewerOptions};

mod scripted;

pub use scripted::read_script;
use scripted::{Script, Step};

/// Longest camera step of one interactive frame, seconds (a stall does not jump the camera).
const MAX_DT: f32 = 0.1;

/// The viewer's state.
pub struct App {
    world: World,
    options: ViewerOptions,
    display_handle: OwnedDisplayHandle,
    window: Option<Arc<Window>>,
    display: Option<Display>,
    egui: egui::Context,
    egui_state: Option<egui_winit::State>,
    camera: Option<(Entity, WalkCamera)>,
    keys: MoveKeys,
    looking: bool,
    cursor: Option<Vec2>,
    look: Vec2,
    /// The frame's area in the window, physical pixels: (top-left corner, size).
    frame_rect: Option<(Vec2, Vec2)>,
    /// A left click on the frame, in the frame's pixels, to pick at the next redraw.
    click: Option<Vec2>,
    selected: Option<Entity>,
    view: DebugView,
    /// The scene's bounding-box diagonal.
    extent: f32,
    /// Rendered pixels per window pixel, in (0, 1] (below 1 the frame is upscaled: faster on
    /// slow devices).
    render_scale: f32,
    panel: bool,
    message: Option<String>,
    times: PassTimes,
    frame_ms: f64,
    last_frame: Instant,
    script: Option<Script>,
    /// Why the viewer stopped, when it failed.
    pub fatal: Option<ViewerError>,
}

/// The diagonal of the scene's bounds.
fn scene_extent(world: &mut World) -> f32 {
    SceneInfo::gather(world).bounds.size().length()
}

/// The camera entity and a walkthrough camera at its world placement, with a speed for a
/// scene of diagonal `extent`.
fn scene_camera(world: &mut World, extent: f32) -> Option<(Entity, WalkCamera)> {
    if let Err(e) = world.run_system_once(propagate_transforms) {
        log::warn!("cannot place the camera: {e}");
    }
    let entity = world.get_resource::<ActiveCamera>()?.0;
    let global = world.get::<GlobalTransform>(entity)?.0;
    let (_, rotation, translation) = global.to_scale_rotation_translation();
    let placement = Transform {
        translation,
        rotation,
        ..Transform::IDENTITY
    };
    let speed = speed_for_extent(extent);
    Some((entity, WalkCamera::from_transform(&placement, speed)))
}

impl App {
    /// The viewer of `world` (which gets a [`FrameSettings`] resource if it has none).
    pub fn new(
        mut world: World,
        options: ViewerOptions,
        display_handle: OwnedDisplayHandle,
    ) -> Self {
        if !world.contains_resource::<FrameSettings>() {
            world.insert_resource(FrameSettings::default());
        }
        let extent = scene_extent(&mut world);
        let camera = scene_camera(&mut world, extent);
        let script = options.script.clone().map(|commands| Script {
            commands: commands.into(),
            frames_left: 0,
            held: MoveKeys::default(),
            waiting: None,
        });
        Self {
            world,
            options,
            display_handle,
            window: None,
            display: None,
            egui: egui::Context::default(),
            egui_state: None,
            camera,
            keys: MoveKeys::default(),
            looking: false,
            cursor: None,
            look: Vec2::ZERO,
            frame_rect: None,
            click: None,
            selected: None,
            view: DebugView::Frame,
            extent,
            render_scale: 1.0,
            panel: true,
            message: None,
            times: PassTimes::default(),
            frame_ms: 0.0,
            last_frame: Instant::now(),
            script,
            fatal: None,
        }
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, error: ViewerError) {
        self.fatal = Some(error);
        event_loop.exit();
    }

    /// Shows an error in the panel and on stderr; the viewer goes on.
    fn report(&mut self, message: String) {
        eprintln!("chiaro view: {message}");
        self.message = Some(message);
    }

    /// Loads a dropped file; a failure keeps the current scene and reports the error.
    fn drop_file(&mut self, path: &Path) {
        match load_dropped(path) {
            Ok(Dropped::Scene(mut world)) => {
                let settings = self.world.resource::<FrameSettings>();
                world.insert_resource(*settings);
                self.extent = scene_extent(&mut world);
                self.camera = scene_camera(&mut world, self.extent);
                self.world = *world;
                self.selected = None;
                self.message = None;
                log::info!("loaded {}", path.display());
            }
            Ok(Dropped::Environment(environment)) => {
                self.world.insert_resource(environment);
                self.message = None;
                log::info!("environment {}", path.display());
            }
            Err(e) => self.report(e),
        }
    }

    fn screenshot(&self, path: &Path) -> Result<(), String> {
        let display = self.display.as_ref().ok_or("no window")?;
        let (w, h) = save_screenshot(&display.renderer, display.debug_image(), path)?;
        println!("wrote {} ({w}x{h})", path.display());
        Ok(())
    }

    /// Moves the camera by the held keys and the mouse motion, through its `Transform`.
    fn move_camera(&mut self, keys: &MoveKeys, dt: f32) {
        let look = std::mem::take(&mut self.look);
        let Some((entity, camera)) = self.camera.as_mut() else {
            return;
        };
        let mut moved = camera.advance(keys, dt);
        if look != Vec2::ZERO {
            camera.look(look.x, look.y);
            moved = true;
        }
        if !moved {
            return;
        }
        let mut placement = camera.transform();
        // A camera under a parent keeps its Transform relative to the parent.
        let parent = self.world.get::<ChildOf>(*entity).map(|c| c.parent());
        if let Some(parent) = parent.and_then(|p| self.world.get::<GlobalTransform>(p)) {
            let local = parent.0.inverse()
                * Affine3A::from_rotation_translation(placement.rotation, placement.translation);
            let (scale, rotation, translation) = local.to_scale_rotation_translation();
            placement = Transform {
                translation,
                rotation,
                scale,
            };
        }
        if let Some(mut transform) = self.world.get_mut::<Transform>(*entity) {
            *transform = placement;
        }
    }

    /// Plays the scene's glTF animations: their time advances by the frame's `dt` seconds.
    fn play_animations(&mut self, dt: f32) {
        let animated = self
            .world
            .get_resource::<Animations>()
            .is_some_and(|a| !a.clips.is_empty());
        if animated {
            self.world.get_resource_or_init::<Time>().seconds += f64::from(dt);
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let elapsed = now.duration_since(self.last_frame).as_secs_f32();
        self.last_frame = now;
        let (keys, dt) = match self.script {
            Some(_) => match self.step_script(event_loop) {
                Step::Render(keys) => (keys, SCRIPT_DT),
                Step::Exit => {
                    event_loop.exit();
                    return;
                }
            },
            None => (self.keys, elapsed.min(MAX_DT)),
        };
        self.move_camera(&keys, dt);
        self.play_animations(dt);
        if let Some(at) = self.click.take() {
            self.pick_at(at);
        }
        let (Some(window), Some(state), Some(display)) = (
            self.window.clone(),
            self.egui_state.as_mut(),
            self.display.as_mut(),
        ) else {
            return;
        };

        let eye = self.camera.as_ref().map_or(Vec3::ZERO, |c| c.1.position);
        let settings = *self.world.resource::<FrameSettings>();
        let mut edited = settings;
        let texture = display.frame_texture();
        let frame_size = display
            .renderer
            .frame()
            .map_or((0, 0), |f| (f.targets.width, f.targets.height));
        let adapter = display.renderer.context.describe();
        let info = PanelInfo {
            size: frame_size,
            times: &self.times,
            frame_ms: self.frame_ms,
            speed: self.camera.as_ref().map_or(0.0, |c| c.1.speed),
            adapter: &adapter,
            message: self.message.as_deref(),
        };
        let show_panel = self.panel;
        let mut dismissed = false;
        let mut area = (1, 1);
        let mut frame_rect = None;
        let (world, selected, view) = (&mut self.world, &mut self.selected, &mut self.view);
        let render_scale = &mut self.render_scale;
        let input = state.take_egui_input(&window);
        let output = self.egui.run_ui(input, |ui| {
            if show_panel {
                egui::Panel::left("settings")
                    .resizable(true)
                    .default_size(270.0)
                    .show(ui, |ui| {
                        egui::ScrollArea::vertical().show(ui, |ui| {
                            dismissed = panel::message(ui, &info);
                            let section =
                                |name| egui::CollapsingHeader::new(name).default_open(true);
                            section("frame").show(ui, |ui| {
                                panel::settings(ui, &mut edited, view, render_scale)
                            });
                            section("scene")
                                .show(ui, |ui| inspector::show(ui, world, selected, eye));
                            section("time").show(ui, |ui| panel::times(ui, &info));
                        });
                    });
            } else if let Some(message) = info.message {
                egui::Panel::top("message").show(ui, |ui| {
                    ui.colored_label(egui::Color32::from_rgb(255, 110, 90), message);
                });
            }
            egui::CentralPanel::no_frame().show(ui, |ui| {
                let ppp = ui.ctx().pixels_per_point();
                let rect = ui.max_rect();
                let min = (rect.min.to_vec2() * ppp).round();
                let max = (rect.max.to_vec2() * ppp).round();
                let size = (max - min).max(egui::Vec2::splat(1.0));
                area = (size.x as u32, size.y as u32);
                frame_rect = Some((Vec2::new(min.x, min.y), Vec2::new(size.x, size.y)));
                let aligned = egui::Rect::from_min_size((min / ppp).to_pos2(), size / ppp);
                if let Some(texture) = texture {
                    let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
                    ui.painter()
                        .image(texture, aligned, uv, egui::Color32::WHITE);
                }
            });
        });
        self.frame_rect = frame_rect;
        if dismissed {
            self.message = None;
        }
        if edited != settings {
            match edited.validate() {
                Ok(()) => {
                    self.world.insert_resource(edited);
                }
                Err(e) => self.message = Some(e.to_string()),
            }
        }

        let render = RenderSettings {
            width: ((area.0 as f32 * self.render_scale).round() as u32).max(1),
            height: ((area.1 as f32 * self.render_scale).round() as u32).max(1),
            frames: 1,
            seed: self.options.seed,
            frame: *self.world.resource::<FrameSettings>(),
        };
        match display.renderer.accumulate(&mut self.world, &render, 1) {
            // The latest frame the GPU finished; with frames in flight, one or two behind.
            Ok(mut times) => {
                if let Some(latest) = times.pop() {
                    self.times = latest;
                }
            }
            Err(e) => {
                let message = format!("cannot render: {e}");
                if self.message.as_deref() != Some(message.as_str()) {
                    eprintln!("chiaro view: {message}");
                    self.message = Some(message);
                }
            }
        }
        let depth_scale = 0.5 * self.extent;
        let scene = self.world.get_resource::<GpuScene>();
        let shown = scene.map_or(Ok(()), |scene| {
            let upscaled = self.render_scale < 1.0;
            display.update_frame_texture(scene, self.view, eye, depth_scale, upscaled)
        });
        if let Err(e) = shown {
            eprintln!("chiaro view: {e}");
            self.message = Some(e.to_string());
            self.view = DebugView::Frame;
        }
        state.handle_platform_output(&window, output.platform_output);
        let jobs = self.egui.tessellate(output.shapes, output.pixels_per_point);
        if let Err(e) = display.present(&jobs, output.textures_delta, output.pixels_per_point) {
            self.fail(event_loop, e);
            return;
        }
        self.frame_ms = now.elapsed().as_secs_f64() * 1e3;
    }

    /// Selects the instance seen at `at` (pixels of the last frame), or nothing.
    fn pick_at(&mut self, at: Vec2) {
        let size = self.display.as_ref().and_then(|d| d.renderer.frame());
        self.selected = size.and_then(|frame| {
            let (w, h) = (frame.targets.width, frame.targets.height);
            pick(&self.world, at.x, at.y, w, h)
        });
        if let Some(entity) = self.selected {
            log::info!("selected {entity}");
        }
    }

    /// Whether the cursor is over the frame (not over the panel).
    fn over_frame(&self) -> bool {
        match (self.cursor, self.frame_rect) {
            (Some(c), Some((min, size))) => c.cmpge(min).all() && c.cmplt(min + size).all(),
            _ => false,
        }
    }

    /// Keys the viewer handles itself (before egui, which takes Tab for focus).
    fn on_key(
        &mut self,
        event_loop: &ActiveEventLoop,
        code: KeyCode,
        pressed: bool,
        egui_wants_keys: bool,
    ) {
        match code {
            KeyCode::Escape if pressed => event_loop.exit(),
            KeyCode::Tab if pressed => self.panel = !self.panel,
            KeyCode::F12 if pressed => {
                let stem = next_screenshot_stem(Path::new("."));
                for extension in ["png", "exr"] {
                    if let Err(e) = self.screenshot(&stem.with_extension(extension)) {
                        self.report(e);
                    }
                }
            }
            KeyCode::ShiftLeft | KeyCode::ShiftRight => self.keys.fast = pressed,
            _ if egui_wants_keys && pressed => {}
            KeyCode::KeyW => self.keys.forward = pressed,
            KeyCode::KeyS => self.keys.back = pressed,
            KeyCode::KeyA => self.keys.left = pressed,
            KeyCode::KeyD => self.keys.right = pressed,
            KeyCode::KeyE => self.keys.up = pressed,
            KeyCode::KeyQ => self.keys.down = pressed,
            _ => {}
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let (w, h) = self.options.size;
        let attributes = Window::default_attributes()
            .with_title(self.options.title.clone())
            .with_inner_size(PhysicalSize::new(w, h));
        let window = match event_loop.create_window(attributes) {
            Ok(window) => Arc::new(window),
            Err(e) => return self.fail(event_loop, ViewerError::Window(e.to_string())),
        };
        let display = match Display::new(window.clone(), self.display_handle.clone()) {
            Ok(display) => display,
            Err(e) => return self.fail(event_loop, e),
        };
        let max_side = display
            .renderer
            .context
            .device
            .limits()
            .max_texture_dimension_2d;
        let state = egui_winit::State::new(
            self.egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(max_side as usize),
        );
        log::info!("viewer on {}", display.renderer.context.describe());
        self.egui_state = Some(state);
        self.display = Some(display);
        self.last_frame = Instant::now();
        window.request_redraw();
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let (Some(window), Some(state)) = (self.window.clone(), self.egui_state.as_mut()) else {
            return;
        };
        // The viewer's own input is decided by where the cursor is (over the frame or the
        // panel), not by egui's verdict, which counts the frame's area as egui's.
        let _ = state.on_window_event(&window, &event);
        let egui_wants_keys = self.egui.egui_wants_keyboard_input();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::Resized(size) => {
                if let Some(display) = self.display.as_mut() {
                    display.resize(size.width, size.height);
                }
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            WindowEvent::DroppedFile(path) => self.drop_file(&path),
            WindowEvent::KeyboardInput { event, .. } => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.on_key(
                        event_loop,
                        code,
                        event.state == ElementState::Pressed,
                        egui_wants_keys,
                    );
                }
            }
            WindowEvent::Focused(false) => self.keys = MoveKeys::default(),
            WindowEvent::MouseInput {
                state: button_state,
                button: MouseButton::Right,
                ..
            } => self.looking = button_state == ElementState::Pressed && self.over_frame(),
            WindowEvent::MouseInput {
                state: ElementState::Pressed,
                button: MouseButton::Left,
                ..
            } if self.over_frame() => {
                self.click = self
                    .cursor
                    .zip(self.frame_rect)
                    .map(|(cursor, (min, _))| (cursor - min) * self.render_scale);
            }
            WindowEvent::CursorMoved { position, .. } => {
                let position = Vec2::new(position.x as f32, position.y as f32);
                if let (true, Some(last)) = (self.looking, self.cursor) {
                    self.look += position - last;
                }
                self.cursor = Some(position);
            }
            WindowEvent::MouseWheel { delta, .. } if self.over_frame() => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 50.0,
                };
                if let Some((_, camera)) = self.camera.as_mut() {
                    camera.scroll(steps);
                }
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _: &ActiveEventLoop) {
        if let Some(window) = &self.window {
            window.request_redraw();
        }
    }
}
