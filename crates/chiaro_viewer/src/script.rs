//! Scripted input: a small text file of events the viewer replays, one per line, then exits.
//! Tests drive the window with it, and it makes a walkthrough reproducible.
//!
//! ```text
//! # comments and blank lines are skipped
//! panel off            # hide (or `panel on`: show) the side panel
//! scale 0.5            # render at half the window's resolution (in (0, 1]; 1 by default)
//! view normal          # show a debug view (albedo normal depth motion direct indirect
//!                      # instances filtered variance history traversal; `view frame`:
//!                      # the frame)
//! frames 8             # render 8 frames
//! key W 10             # hold W for 10 frames (keys: W A S D Q E, SHIFT+W etc. for fast)
//! look 40 -10          # turn the view as a mouse motion of (40, -10) pixels would
//! click 48 30          # left click at pixel (48, 30) of the frame: selects what it shows
//! move 0 10 0          # move the selected entity by (0, 10, 0) (its Transform, in its
//!                      # parent's frame); an error when nothing is selected
//! resize 320 240       # resize the window and wait until it has that size
//! drop scene.glb       # load a file as if dropped on the window (.glb, .gltf, .hdr, .exr)
//! screenshot out.png   # save the last frame: .png (8-bit, tonemapped) or .exr (linear HDR)
//! ```
//!
//! A scripted frame advances the camera by a fixed [`SCRIPT_DT`], so a script moves the camera
//! the same way on any machine.

use std::path::{Path, PathBuf};

use glam::Vec3;

use thiserror::Error;

use crate::camera::MoveKeys;
use crate::debug_view::DebugView;

/// Seconds of camera motion per scripted frame.
pub const SCRIPT_DT: f32 = 1.0 / 30.0;

/// One scripted event.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Render this many frames.
    Frames(u32),
    /// Hold these keys for this many frames.
    Keys(MoveKeys, u32),
    /// Turn the view as a mouse motion of this many pixels (x right, y down) would.
    Look(f32, f32),
    /// Left click at this point of the frame (pixels from its top-left corner): selects the
    /// instance seen there.
    Click(f32, f32),
    /// Add this to the selected entity's translation.
    Move(Vec3),
    /// Resize the window's inner area to this many pixels and wait until it has that size.
    Resize(u32, u32),
    /// Load a file as if it were dropped on the window.
    Drop(PathBuf),
    /// Save the last frame (.png or .exr).
    Screenshot(PathBuf),
    /// Show or hide the side panel.
    Panel(bool),
    /// Show this view of the frame.
    View(DebugView),
    /// Render this many pixels per window pixel, in [1/16, 1].
    Scale(f32),
}

/// A line of a script that does not parse.
#[derive(Debug, Error, PartialEq)]
#[error("script line {line}: {message}: '{text}'")]
pub struct ScriptError {
    /// Line number, from 1.
    pub line: usize,
    /// The line's text.
    pub text: String,
    /// What is wrong with it.
    pub message: String,
}

/// Largest frame count one line may ask for.
pub const MAX_FRAMES: u32 = 100_000;
/// Largest window side a `resize` may ask for.
pub const MAX_SIDE: u32 = 16_384;

fn count(word: &str) -> Result<u32, String> {
    match word.parse::<u32>() {
        Ok(n) if (1..=MAX_FRAMES).contains(&n) => Ok(n),
        _ => Err(format!("'{word}' is not a frame count in 1..={MAX_FRAMES}")),
    }
}

fn keys(word: &str) -> Result<MoveKeys, String> {
    let mut keys = MoveKeys::default();
    for part in word.split('+') {
        let held = match part.to_ascii_uppercase().as_str() {
            "W" => &mut keys.forward,
            "S" => &mut keys.back,
            "A" => &mut keys.left,
            "D" => &mut keys.right,
            "E" => &mut keys.up,
            "Q" => &mut keys.down,
            "SHIFT" => &mut keys.fast,
            _ => {
                return Err(format!(
                    "unknown key '{part}' (W A S D Q E SHIFT, joined by +)"
                ));
            }
        };
        *held = true;
    }
    Ok(keys)
}

fn float(word: &str) -> Result<f32, String> {
    match word.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("'{word}' is not a finite number")),
    }
}

fn side(word: &str) -> Result<u32, String> {
    match word.parse::<u32>() {
        Ok(n) if (1..=MAX_SIDE).contains(&n) => Ok(n),
        _ => Err(format!("'{word}' is not a window side in 1..={MAX_SIDE}")),
    }
}

/// Parses one line (without comment); `None` for a blank line.
fn parse_line(line: &str, base: &Path) -> Result<Option<Command>, String> {
    let mut words = line.split_whitespace();
    let Some(verb) = words.next() else {
        return Ok(None);
    };
    let args: Vec<&str> = words.collect();
    let path = |args: &[&str]| -> Result<PathBuf, String> {
        match args {
            [] => Err("needs a path".into()),
            _ => Ok(base.join(args.join(" "))),
        }
    };
    let command = match (verb.to_ascii_lowercase().as_str(), &args[..]) {
        ("frames", [n]) => Command::Frames(count(n)?),
        ("key", [k, n]) => Command::Keys(keys(k)?, count(n)?),
        ("look", [dx, dy]) => Command::Look(float(dx)?, float(dy)?),
        ("click", [x, y]) => Command::Click(float(x)?, float(y)?),
        ("move", [x, y, z]) => Command::Move(Vec3::new(float(x)?, float(y)?, float(z)?)),
        ("resize", [w, h]) => Command::Resize(side(w)?, side(h)?),
        ("drop", _) => Command::Drop(path(&args)?),
        ("screenshot", _) => {
            let out = path(&args)?;
            match out.extension().and_then(|e| e.to_str()) {
                Some("png" | "exr") => Command::Screenshot(out),
                _ => return Err("a screenshot must end in .png or .exr".into()),
            }
        }
        ("view", [name]) => Command::View(DebugView::from_name(name).ok_or_else(|| {
            let names: Vec<&str> = DebugView::ALL.iter().map(|v| v.name()).collect();
            format!("unknown view '{name}' ({})", names.join(", "))
        })?),
        ("scale", [s]) => match float(s)? {
            s if (1.0 / 16.0..=1.0).contains(&s) => Command::Scale(s),
            _ => return Err(format!("'{s}' is not a render scale in [1/16, 1]")),
        },
        ("panel", ["on"]) => Command::Panel(true),
        ("panel", ["off"]) => Command::Panel(false),
        (
            "frames" | "key" | "look" | "click" | "move" | "resize" | "panel" | "view" | "scale",
            _,
        ) => {
            return Err(format!("wrong arguments for '{verb}'"));
        }
        _ => {
            return Err(format!(
                "unknown command '{verb}' (frames, key, look, click, move, resize, drop, \
                 screenshot, panel, view, scale)"
            ));
        }
    };
    Ok(Some(command))
}

/// Parses a script; relative paths in it are taken from `base` (the script's folder). The
/// first bad line is the error.
pub fn parse(text: &str, base: &Path) -> Result<Vec<Command>, ScriptError> {
    let mut commands = Vec::new();
    for (index, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        match parse_line(line, base) {
            Ok(Some(command)) => commands.push(command),
            Ok(None) => {}
            Err(message) => {
                return Err(ScriptError {
                    line: index + 1,
                    text: raw.trim().to_string(),
                    message,
                });
            }
        }
    }
    Ok(commands)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_command() {
        let text = "# a walk\n\npanel off\nframes 8\nkey shift+W 10 # fast\nlook 4 -2.5\n\
                    click 3 4.5\nmove 0 -1 2.5\nresize 320 240\ndrop scenes/box.glb\n\
                    screenshot shot 1.png\npanel on\nview normal\nscale 0.5\n";
        let commands = parse(text, Path::new("/tmp")).unwrap();
        let fast_w = MoveKeys {
            forward: true,
            fast: true,
            ..Default::default()
        };
        assert_eq!(
            commands,
            [
                Command::Panel(false),
                Command::Frames(8),
                Command::Keys(fast_w, 10),
                Command::Look(4.0, -2.5),
                Command::Click(3.0, 4.5),
                Command::Move(Vec3::new(0.0, -1.0, 2.5)),
                Command::Resize(320, 240),
                Command::Drop(PathBuf::from("/tmp/scenes/box.glb")),
                Command::Screenshot(PathBuf::from("/tmp/shot 1.png")),
                Command::Panel(true),
                Command::View(DebugView::Normal),
                Command::Scale(0.5),
            ]
        );
        // Absolute paths stay as they are.
        assert_eq!(
            parse("drop /data/a.hdr", Path::new("/tmp")).unwrap(),
            [Command::Drop(PathBuf::from("/data/a.hdr"))]
        );
    }

    #[test]
    fn a_bad_line_is_named_by_number_and_text() {
        let cases = [
            ("frames 2\njump 3\n", 2, "unknown command 'jump'"),
            ("frames 0", 1, "not a frame count"),
            ("frames\n", 1, "wrong arguments for 'frames'"),
            ("\n\nkey X 3", 3, "unknown key 'X'"),
            ("key W", 1, "wrong arguments"),
            ("look 1 nan", 1, "not a finite number"),
            ("resize 0 10", 1, "not a window side"),
            ("click 3", 1, "wrong arguments for 'click'"),
            ("move 1 2", 1, "wrong arguments for 'move'"),
            ("screenshot out.jpg", 1, "must end in .png or .exr"),
            ("drop", 1, "needs a path"),
            ("panel maybe", 1, "wrong arguments for 'panel'"),
            ("view heat", 1, "unknown view 'heat'"),
            ("scale 2", 1, "not a render scale"),
        ];
        for (text, line, message) in cases {
            let error = parse(text, Path::new(".")).unwrap_err();
            assert_eq!(error.line, line, "{text:?}: {error}");
            assert!(error.message.contains(message), "{text:?}: {error}");
            assert!(
                error
                    .to_string()
                    .starts_with(&format!("script line {line}: "))
            );
        }
    }
}
