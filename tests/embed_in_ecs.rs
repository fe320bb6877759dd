//! The embedding example's logic (`examples/embed_in_ecs.rs`) as a test: the app's own
//! schedule runs its system and chiaro's, chiaro renders each frame offscreen, and the images
//! show the animation.
//!
//! Checks, on 64x64 realtime frames: every pixel of every frame is finite; each frame's mean
//! luminance is at least 0.05 (the lit box, not a black image); and the orbiting light shows:
//! the frames with the light on the image's left (world +x: the camera looks down +z) and on
//! its right (half an orbit later) differ, the left half brighter in the first and the right
//! half brighter in the second, each by at least 3% of the half's luminance (measured: 5.5% and
//! 33%: the temporal histories carry part of the earlier frames into frame 4).

mod common;

#[path = "../examples/embed_in_ecs.rs"]
mod embed;

use glam::Vec3;

fn luminance(p: &Vec3) -> f64 {
    f64::from(p.dot(Vec3::new(0.2126, 0.7152, 0.0722)))
}

/// Mean luminance of the left and right halves of a `size` x `size` image.
fn halves(hdr: &[Vec3], size: usize) -> (f64, f64) {
    let (mut left, mut right) = (0.0, 0.0);
    for (i, p) in hdr.iter().enumerate() {
        if i % size < size / 2 {
            left += luminance(p);
        } else {
            right += luminance(p);
        }
    }
    let n = (hdr.len() / 2) as f64;
    (left / n, right / n)
}

#[test]
fn embedded_app_renders_its_animation() {
    let Some(gpu) = common::gpu() else { return };
    let size = 64;
    // Eight frames per orbit: frame 0 puts the light at +x (image left), frame 4 at -x.
    let images = embed::run_app(gpu, 8, size, None).unwrap();
    assert_eq!(images.len(), 8);
    for (f, image) in images.iter().enumerate() {
        assert!(
            image.hdr.iter().all(|p| p.is_finite()),
            "frame {f}: non-finite pixels"
        );
        let mean = image.hdr.iter().map(luminance).sum::<f64>() / image.hdr.len() as f64;
        assert!(mean > 0.05, "frame {f}: mean luminance {mean}");
    }
    let (left0, right0) = halves(&images[0].hdr, size as usize);
    let (left4, right4) = halves(&images[4].hdr, size as usize);
    eprintln!("light left: halves {left0:.4} {right0:.4}; light right: {left4:.4} {right4:.4}");
    assert!(
        left0 > 1.03 * left4,
        "left half {left0} with the light left, {left4} right"
    );
    assert!(
        right4 > 1.03 * right0,
        "right half {right4} with the light right, {right0} left"
    );
}
