//! Replaying a script: the commands that render frames, wait for a size or act at once.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};

use chiaro_scene::Transform;
use glam::Vec2;
use winit::dpi::PhysicalSize;
use winit::event_loop::ActiveEventLoop;

use super::App;
use crate::ViewerError;
use crate::camera::MoveKeys;
use crate::script::Command;

/// Frames a scripted `resize` waits for the window to take the size before failing.
const RESIZE_WAIT_FRAMES: u32 = 300;

/// A script being replayed.
pub(super) struct Script {
    pub(super) commands: VecDeque<Command>,
    pub(super) frames_left: u32,
    pub(super) held: MoveKeys,
    /// A size asked for, and the frames waited for it.
    pub(super) waiting: Option<(u32, u32, u32)>,
}

/// What a scripted frame does.
pub(super) enum Step {
    Render(MoveKeys),
    Exit,
}

impl App {
    /// The next scripted step: runs instant commands until one that renders.
    pub(super) fn step_script(&mut self, event_loop: &ActiveEventLoop) -> Step {
        loop {
            let Some(script) = self.script.as_mut() else {
                return Step::Exit;
            };
            if script.frames_left > 0 {
                script.frames_left -= 1;
                return Step::Render(script.held);
            }
            if let Some((w, h, waited)) = script.waiting {
                let size = self.window.as_ref().map(|w| w.inner_size());
                if size == Some(PhysicalSize::new(w, h)) {
                    script.waiting = None;
                    continue;
                }
                if waited >= RESIZE_WAIT_FRAMES {
                    self.fail(
                        event_loop,
                        ViewerError::Resize(w, h, size.unwrap_or_default()),
                    );
                    return Step::Exit;
                }
                script.waiting = Some((w, h, waited + 1));
                return Step::Render(MoveKeys::default());
            }
            let Some(command) = script.commands.pop_front() else {
                if let Some(path) = self.options.screenshot.take()
                    && let Err(e) = self.screenshot(&path)
                {
                    self.fail(event_loop, ViewerError::Screenshot(e));
                }
                return Step::Exit;
            };
            match command {
                Command::Frames(n) => (script.frames_left, script.held) = (n, MoveKeys::default()),
                Command::Keys(keys, n) => (script.frames_left, script.held) = (n, keys),
                Command::Look(dx, dy) => self.look += Vec2::new(dx, dy),
                Command::Click(x, y) => self.pick_at(Vec2::new(x, y)),
                Command::Move(offset) => {
                    let transform = self
                        .selected
                        .and_then(|e| self.world.get_mut::<Transform>(e));
                    match transform {
                        Some(mut t) => t.translation += offset,
                        None => {
                            self.fail(event_loop, ViewerError::NothingSelected);
                            return Step::Exit;
                        }
                    }
                }
                Command::Resize(w, h) => {
                    script.waiting = Some((w, h, 0));
                    if let Some(window) = &self.window {
                        let _ = window.request_inner_size(PhysicalSize::new(w, h));
                    }
                }
                Command::Panel(on) => self.panel = on,
                Command::View(view) => self.view = view,
                Command::Scale(scale) => self.render_scale = scale,
                Command::Drop(path) => self.drop_file(&path),
                Command::Screenshot(path) => {
                    if let Err(e) = self.screenshot(&path) {
                        self.fail(event_loop, ViewerError::Screenshot(e));
                        return Step::Exit;
                    }
                }
            }
        }
    }
}

/// Reads and parses a script file.
pub fn read_script(path: &Path) -> Result<Vec<Command>, ViewerError> {
    let text = std::fs::read_to_string(path).map_err(|e| ViewerError::Io {
        path: PathBuf::from(path),
        message: e.to_string(),
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    Ok(crate::script::parse(&text, base)?)
}
