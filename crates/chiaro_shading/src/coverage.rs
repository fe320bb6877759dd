//! Stochastic coverage, chiaro's reading of glTF's alpha mode BLEND: a surface of alpha `a`
//! stops a ray with probability `a`; otherwise the ray passes straight through it (no
//! refraction, no change of colour). Every tracer applies the same rule at every candidate hit:
//! camera rays (the G-buffer's raster discards the fragment instead), BRDF rays and shadow
//! rays, which a surface therefore blocks with probability `a`. Each is unbiased: averaged over
//! samples, a surface is seen in proportion `a` and what lies behind it in proportion `1 - a`,
//! and a shadow ray's expected visibility is the product of the `1 - a` it crosses.
//!
//! The uniform number of each decision is a hash of what identifies the ray (or the pixel and
//! frame) and the surface, not a draw from a path's generator: the decision is deterministic
//! per seed, independent of thread count and of the order in which traversal meets
//! candidates, and the same candidate met twice by one ray gets the same answer. The hash is
//! Jarzynski and Olano's PCG hash ("Hash Functions for GPU Rendering", JCGT 9(3), 2020),
//! chained over the words. `shaders/lib/coverage.wgsl` mirrors this module bit for bit.

use glam::{UVec2, Vec3};

/// 2^-24: maps a 24-bit integer to [0, 1) exactly.
const TWO_POW_MINUS_24: f32 = 1.0 / 16_777_216.0;

/// Jarzynski and Olano's PCG hash of one word.
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// The hash of `words`, chained: each word is XORed into the hash so far and hashed again.
pub fn hash_words(words: &[u32]) -> u32 {
    words.iter().fold(0, |h, &w| pcg_hash(h ^ w))
}

/// A uniform number in [0, 1) from a hash: its top 24 bits, exact.
pub fn unit_float(hash: u32) -> f32 {
    (hash >> 8) as f32 * TWO_POW_MINUS_24
}

/// The coverage number of triangle `triangle` of instance `instance` for the world ray from
/// `origin` along `direction` (their bits identify the ray).
pub fn ray_number(origin: Vec3, direction: Vec3, instance: u32, triangle: u32) -> f32 {
    let o = origin.to_array().map(f32::to_bits);
    let d = direction.to_array().map(f32::to_bits);
    unit_float(hash_words(&[
        o[0], o[1], o[2], d[0], d[1], d[2], instance, triangle,
    ]))
}

/// The coverage number of a fragment of instance `instance` at depth `depth` in pixel `pixel`
/// of the frame whose number is `frame_seed` (the G-buffer's raster test).
pub fn fragment_number(pixel: UVec2, frame_seed: u32, instance: u32, depth: f32) -> f32 {
    unit_float(hash_words(&[
        pixel.x,
        pixel.y,
        frame_seed,
        instance,
        depth.to_bits(),
    ]))
}

/// Whether a surface of alpha `alpha` stops a ray whose coverage number is `u`: with
/// probability `alpha` for `u` uniform in [0, 1).
pub fn stops(alpha: f32, u: f32) -> bool {
    u < alpha
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stops_in_proportion_to_alpha() {
        for alpha in [0.0, 0.25, 0.5, 0.9, 1.0] {
            let n = 20_000;
            let stopped = (0..n)
                .filter(|&i| {
                    let origin = Vec3::new(i as f32 * 1e-3, 0.5, -2.0);
                    stops(alpha, ray_number(origin, Vec3::Z, 3, 7))
                })
                .count();
            let fraction = stopped as f32 / n as f32;
            // Four standard errors of a Bernoulli mean over n draws.
            let tolerance = 4.0 * (alpha * (1.0 - alpha) / n as f32).sqrt() + 1e-6;
            assert!(
                (fraction - alpha).abs() <= tolerance,
                "alpha {alpha}: stopped {fraction}"
            );
        }
    }

    #[test]
    fn numbers_are_in_the_unit_interval_and_depend_on_every_word() {
        assert_eq!(unit_float(0), 0.0);
        assert!(unit_float(u32::MAX) < 1.0);
        let base = fragment_number(UVec2::new(4, 9), 17, 2, 0.5);
        assert_ne!(base, fragment_number(UVec2::new(5, 9), 17, 2, 0.5));
        assert_ne!(base, fragment_number(UVec2::new(4, 9), 18, 2, 0.5));
        assert_ne!(base, fragment_number(UVec2::new(4, 9), 17, 3, 0.5));
        assert_ne!(base, fragment_number(UVec2::new(4, 9), 17, 2, 0.25));
        let ray = ray_number(Vec3::ONE, Vec3::X, 0, 0);
        assert_ne!(ray, ray_number(Vec3::ONE, Vec3::X, 0, 1));
        assert_ne!(ray, ray_number(Vec3::ONE, Vec3::X, 1, 0));
        assert_ne!(ray, ray_number(Vec3::ONE, Vec3::Y, 0, 0));
    }
}
