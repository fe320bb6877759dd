//! Randomised quasi-Monte Carlo numbers: Owen-scrambled Sobol points, one or two dimensions per
//! draw.
//!
//! Every draw of a path (the position in the pixel, a light pick, a point on the light, a BRDF
//! lobe and direction, Russian roulette) is a dimension of its own. A two-number draw reads the
//! first two dimensions of the Sobol sequence (Sobol 1967; the second from the primitive
//! polynomial x + 1), which form a (0, 2)-sequence in base 2: any 2^m consecutive points from an
//! index that is a multiple of 2^m put exactly one point in each of the 2^m elementary intervals
//! of area 2^-m. A one-number draw reads the first dimension, the van der Corput sequence, with
//! one point in each interval of length 2^-m. A choice (a BRDF lobe, a light) drawn with the two
//! numbers of its warp reads the first three dimensions, a (1, 3)-sequence, so the directions of
//! each lobe stay stratified too. So each draw alone is stratified over a pixel's samples, which
//! is where the error falls faster than Monte Carlo's 1/n.
//!
//! Each dimension of each pixel (and half) then takes points in an order of its own, a nested
//! uniform scramble of the sample index, and its own Owen scramble of the values. Both are the
//! hash-based permutations of Burley (2020, "Practical Hash-based Owen Scrambling", JCGT 9(4),
//! after Laine and Karras 2011). Shuffling the order keeps the first 2^m samples on one aligned
//! block of 2^m points, so the stratification holds, and pairs draws of different dimensions at
//! random, so they are not correlated. Scrambling makes every point uniformly distributed, so the
//! estimate stays unbiased (Owen 1995). Drawing one or two dimensions at a time and padding them
//! this way is the layout of pbrt-v4's padded Sobol sampler (Pharr, Jakob and Humphreys,
//! "Physically Based Rendering", 4th ed., section 8.7).
//!
//! The Sobol dimensions and the permutation are [`chiaro_shading::owen_sobol`]'s, shared with
//! the GPU's reference mode; this sampler keys its scrambles by 64-bit hashes.
//!
//! The bidirectional tracer's [`Stream`]s each number their dimensions from zero, so a longer
//! camera subpath does not shift what its light subpath reads.

use chiaro_shading::owen_sobol::{
    laine_karras, scramble_reversed, sobol_second_reversed, sobol_third_reversed, to_unit,
};
use glam::Vec2;

use crate::random::{RandomSource, Stream};

/// A 64-bit mixing function (the finaliser of Steele, Lea and Flood's SplitMix64): every input
/// bit changes about half the output bits.
fn mix(mut x: u64) -> u64 {
    x ^= x >> 30;
    x = x.wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x ^= x >> 27;
    x = x.wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// The scrambled first two coordinates of the dimension with hash `hash`, whose shuffled
/// first coordinate is `x`.
fn scrambled_pair(hash: u64, x: u32) -> Vec2 {
    let shuffled = x.reverse_bits();
    let y_seed = (hash.wrapping_mul(0xd6e8_feb8_6659_fd93) >> 32) as u32;
    Vec2::new(
        to_unit(scramble_reversed(shuffled, (hash >> 32) as u32)),
        to_unit(scramble_reversed(sobol_second_reversed(shuffled), y_seed)),
    )
}

/// One pixel's (and one half's) sequence of Owen-scrambled Sobol samples. Call
/// [`OwenSobol::start_sample`] before each sample; its draws then read the dimensions in order.
#[derive(Clone, Copy, Debug)]
pub struct OwenSobol {
    /// The scrambles' key: a hash of the seed, the pixel and the half.
    key: u64,
    /// The sample's index among this sequence's, its bits reversed.
    reversed_index: u32,
    /// The stream being drawn from.
    stream: u64,
    /// The next dimension of that stream.
    dimension: u64,
}

impl OwenSobol {
    /// The sequence of `seed` for `pixel`, half `half` (the halves must be independent, so each
    /// has scrambles of its own).
    pub fn new(seed: u64, pixel: u64, half: u32) -> Self {
        Self {
            key: mix(mix(seed ^ mix(pixel)) ^ u64::from(half)),
            reversed_index: 0,
            stream: 0,
            dimension: 0,
        }
    }

    /// Starts sample `index` of the sequence, at its first dimension of the camera stream.
    pub fn start_sample(&mut self, index: u32) {
        self.reversed_index = index.reverse_bits();
        self.stream = Stream::Camera as u64;
        self.dimension = 0;
    }

    /// The hash for the next dimension, which it then moves past.
    fn next_dimension(&mut self) -> u64 {
        let id = (self.stream << 48) | self.dimension;
        self.dimension += 1;
        mix(self.key ^ id.wrapping_mul(0x9e37_79b9_7f4a_7c15))
    }

    /// The dimension's first Sobol coordinate, unscrambled, of the sample's place in the
    /// dimension's own order (the index's nested uniform scramble by `seed`). The radical
    /// inverse of the shuffled index is the Laine-Karras permutation of the reversed index.
    fn shuffled_first(&self, seed: u32) -> u32 {
        laine_karras(self.reversed_index, seed)
    }
}

impl RandomSource for OwenSobol {
    fn next_f32(&mut self) -> f32 {
        let hash = self.next_dimension();
        let x = self.shuffled_first(hash as u32);
        to_unit(scramble_reversed(x.reverse_bits(), (hash >> 32) as u32))
    }

    fn next_vec2(&mut self) -> Vec2 {
        let hash = self.next_dimension();
        scrambled_pair(hash, self.shuffled_first(hash as u32))
    }

    /// The choice is the third Sobol dimension, the warp's numbers the first two: the first
    /// three dimensions form a (1, 3)-sequence, so the points whose choice falls in an interval
    /// of 2^-k are still stratified in the other two (up to pairs).
    fn next_choice_and_vec2(&mut self) -> (f32, Vec2) {
        let hash = self.next_dimension();
        let x = self.shuffled_first(hash as u32);
        let choice_seed = (hash.wrapping_mul(0x9e6c_63d0_676a_9a99) >> 32) as u32;
        let choice = scramble_reversed(sobol_third_reversed(x.reverse_bits()), choice_seed);
        (to_unit(choice), scrambled_pair(hash, x))
    }

    fn start_stream(&mut self, stream: Stream) {
        self.stream = stream as u64;
        self.dimension = 0;
    }
}

#[cfg(test)]
#[path = "sobol_tests.rs"]
mod tests;
