//! The walkthrough example's logic (`examples/walkthrough.rs`) as a test: 8 realtime frames of
//! 48x48 along the camera path through the Cornell box, written as PNG.
//!
//! Checks: one PNG per frame; every pixel of every frame is finite and each frame's mean
//! luminance is at least 0.05 (lit, not black); consecutive frames differ as the camera moves
//! (relMSE, linear HDR, mean((x-y)^2/(y^2+0.01)), at least 0.02 between neighbours; measured
//! 0.10 to 0.29, and 64 from the first frame, outside the box, to the second); and the frames
//! follow the path: against a reference-mode render at the last pose (32 frames), the last
//! frame's relMSE is under 0.1 and under a third of the first frame's (measured 2.3e-2 and 33).

mod common;

#[path = "../examples/walkthrough.rs"]
mod walkthrough;

use bevy_ecs::prelude::World;
use chiaro::eval::metrics::rel_mse;
use chiaro::gpu::{FrameSettings, RenderMode, RenderSettings, Renderer};
use glam::Vec3;

const SIZE: u32 = 48;
const FRAMES: u32 = 8;

fn mean_luminance(hdr: &[Vec3]) -> f64 {
    let weights = Vec3::new(0.2126, 0.7152, 0.0722);
    hdr.iter().map(|p| f64::from(p.dot(weights))).sum::<f64>() / hdr.len() as f64
}

#[test]
fn walkthrough_frames_follow_the_camera_path() {
    let Some(gpu) = common::gpu() else { return };
    let mut renderer = Renderer::new(gpu);
    let out = std::env::temp_dir().join(format!("chiaro_walkthrough_{}", std::process::id()));
    let images = walkthrough::walk(&mut renderer, FRAMES, SIZE, Some(&out)).unwrap();
    assert_eq!(images.len(), FRAMES as usize);
    for f in 0..FRAMES {
        let path = out.join(format!("frame_{f:03}.png"));
        let png = image::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert_eq!((png.width(), png.height()), (SIZE, SIZE));
    }
    std::fs::remove_dir_all(&out).unwrap();

    for (f, image) in images.iter().enumerate() {
        assert!(image.hdr.iter().all(|p| p.is_finite()), "frame {f}");
        let mean = mean_luminance(&image.hdr);
        assert!(mean > 0.05, "frame {f}: mean luminance {mean}");
    }
    for (f, pair) in images.windows(2).enumerate() {
        let step = rel_mse(&pair[1].hdr, &pair[0].hdr, 0.01);
        eprintln!("frames {f} to {}: relMSE {step:.3e}", f + 1);
        assert!(step > 0.02, "frames {f} and {} alike: {step}", f + 1);
    }

    // The reference at the path's end.
    let mut world = World::new();
    chiaro::scene::load_scene(&mut world, walkthrough::SCENE).unwrap();
    walkthrough::place_camera(&mut world, walkthrough::pose(1.0)).unwrap();
    let settings = RenderSettings {
        width: SIZE,
        height: SIZE,
        frames: 32,
        seed: 7,
        frame: FrameSettings {
            mode: RenderMode::Reference,
            ..FrameSettings::default()
        },
    };
    let reference = renderer.render(&mut world, &settings).unwrap();
    let first = rel_mse(&images[0].hdr, &reference.hdr, 0.01);
    let last = rel_mse(&images[FRAMES as usize - 1].hdr, &reference.hdr, 0.01);
    eprintln!("relMSE to the reference at the last pose: first frame {first:.3e}, last {last:.3e}");
    assert!(last < 0.1, "last frame {last}");
    assert!(last * 3.0 < first, "last frame {last}, first {first}");
}
