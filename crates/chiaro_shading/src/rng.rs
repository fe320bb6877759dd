//! A small, deterministic random number generator: PCG32.
//!
//! O'Neill, 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good Algorithms for
//! Random Number Generation" (the `pcg32` member: a 64-bit LCG state, XSH-RR output permutation to
//! 32 bits). Seeding follows the reference implementation's `pcg32_srandom_r`, so the first
//! outputs for a given `(seed, stream)` match the reference's published demo output.
//!
//! # Mirroring in WGSL
//!
//! Everything here is integer arithmetic, so a shader can reproduce it bit for bit. WGSL has no
//! 64-bit integers: the state and increment are kept as two `u32` halves, and the one 64-bit
//! multiply-add `state * MULTIPLIER + inc` (mod 2^64) is done with 32x32->64 partial products
//! (16-bit limbs, or a `mul_hi` helper). The output permutation works on the halves directly:
//! `xorshifted = ((old >> 18) ^ old) >> 27` keeps bits 27..59 of the 64-bit value, and the rotation
//! is `old >> 59`. Conversions to float take the top 24 bits, which a `u32 -> f32` conversion
//! represents exactly, so [`Pcg32::next_f32`] is exact on both sides too.

use glam::Vec2;

/// The LCG multiplier of the reference implementation (`PCG_DEFAULT_MULTIPLIER_64`).
pub const PCG32_MULTIPLIER: u64 = 6_364_136_223_846_793_005;

/// 2^-24: maps a 24-bit integer to [0, 1) exactly.
const INV_2_POW_24: f32 = 1.0 / 16_777_216.0;

/// O'Neill's PCG32 (XSH-RR 64/32): 64 bits of state, 2^63 selectable streams, 32-bit outputs.
///
/// ```
/// use chiaro_shading::rng::Pcg32;
///
/// let mut rng = Pcg32::new(42, 54);
/// assert_eq!(rng.next_u32(), 0xa15c_02b7); // the reference implementation's demo output
/// let x = rng.next_f32();
/// assert!((0.0..1.0).contains(&x));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Pcg32 {
    state: u64,
    /// The increment; always odd.
    inc: u64,
}

impl Pcg32 {
    /// A generator for `seed` (the starting point) on `stream` (which of the 2^63 sequences; only
    /// the low 63 bits matter). Same as the reference `pcg32_srandom_r(seed, stream)`.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut rng = Self {
            state: 0,
            inc: (stream << 1) | 1,
        };
        rng.step();
        rng.state = rng.state.wrapping_add(seed);
        rng.step();
        rng
    }

    /// Advances the LCG by one step.
    fn step(&mut self) {
        self.state = self
            .state
            .wrapping_mul(PCG32_MULTIPLIER)
            .wrapping_add(self.inc);
    }

    /// The next 32 uniformly distributed bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.step();
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rotation = (old >> 59) as u32;
        xorshifted.rotate_right(rotation)
    }

    /// A uniform float in [0, 1): the top 24 bits of [`Pcg32::next_u32`] times 2^-24, so every
    /// value is exact and 1.0 is never returned.
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * INV_2_POW_24
    }

    /// Two uniform floats in [0, 1): `x` is drawn first, then `y`.
    pub fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        let y = self.next_f32();
        Vec2::new(x, y)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference implementation's `pcg32-demo` prints these for seed 42, stream 54; they were
    /// also recomputed with an independent Python transcription of the algorithm.
    #[test]
    fn matches_reference_outputs() {
        let mut rng = Pcg32::new(42, 54);
        let expected = [
            0xa15c_02b7,
            0x7b47_f409,
            0xba1d_3330,
            0x83d2_f293,
            0xbfa4_784b,
            0xcbed_606e,
        ];
        for e in expected {
            assert_eq!(rng.next_u32(), e);
        }
        let mut zero = Pcg32::new(0, 0);
        let expected = [0xe4c1_4788, 0x379c_6516, 0x5c4a_b3bb, 0x601d_23e0];
        for e in expected {
            assert_eq!(zero.next_u32(), e);
        }
    }

    #[test]
    fn streams_and_seeds_differ_and_repeat() {
        let a: Vec<u32> = {
            let mut r = Pcg32::new(7, 1);
            (0..8).map(|_| r.next_u32()).collect()
        };
        let b: Vec<u32> = {
            let mut r = Pcg32::new(7, 2);
            (0..8).map(|_| r.next_u32()).collect()
        };
        let c: Vec<u32> = {
            let mut r = Pcg32::new(7, 1);
            (0..8).map(|_| r.next_u32()).collect()
        };
        assert_ne!(a, b);
        assert_eq!(a, c);
        // Only the low 63 bits of the stream matter, as in the reference.
        let mut high = Pcg32::new(7, 1 | (1 << 63));
        assert_eq!(high.next_u32(), a[0]);
    }

    #[test]
    fn floats_are_in_unit_interval_and_uniform() {
        let mut rng = Pcg32::new(0x853c_49e6_748f_ea9b, 0xda3e_39cb_94b9_5bdb);
        let n = 200_000;
        let mut bins = [0u32; 10];
        let mut sum = 0.0f64;
        for _ in 0..n {
            let v = rng.next_vec2();
            for x in [v.x, v.y] {
                assert!((0.0..1.0).contains(&x), "{x}");
                bins[(x * 10.0) as usize] += 1;
                sum += x as f64;
            }
        }
        let mean = sum / (2 * n) as f64;
        // Standard error of the mean is 1/sqrt(12 * 400000) = 4.6e-4; allow ~6 sigma.
        assert!((mean - 0.5).abs() < 3e-3, "{mean}");
        for b in bins {
            // Expected 40000 per bin, sd ~190.
            assert!((b as i64 - 40_000).abs() < 1_200, "{bins:?}");
        }
    }

    #[test]
    fn largest_output_maps_below_one() {
        assert!((u32::MAX >> 8) as f32 * INV_2_POW_24 < 1.0);
        assert_eq!(0u32 as f32 * INV_2_POW_24, 0.0);
    }
}
