//! Where a sampler's random numbers come from. The path tracer and the bidirectional tracer
//! draw them from a [`Pcg32`] stream; Metropolis light transport draws the bidirectional
//! tracer's from a mutated vector of primary samples ([`crate::mlt`]) instead, so the tracers
//! are written against this trait.

use chiaro_shading::rng::Pcg32;
use glam::Vec2;

/// The part of a sample a number is drawn for. A primary-sample vector keeps one sequence per
/// stream, so that a longer camera subpath does not shift the numbers its light subpath reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stream {
    /// The film position and the camera subpath.
    Camera = 0,
    /// The light subpath.
    Light = 1,
    /// The connections between the two.
    Connect = 2,
}

/// How many [`Stream`]s there are.
pub const STREAMS: usize = 3;

/// A source of uniform numbers in [0, 1).
pub trait RandomSource {
    /// The next number of the current stream.
    fn next_f32(&mut self) -> f32;

    /// The next two numbers of the current stream.
    fn next_vec2(&mut self) -> Vec2 {
        let x = self.next_f32();
        Vec2::new(x, self.next_f32())
    }

    /// A choice (which lobe, which light) and the two numbers of the chosen one's warp, drawn
    /// together so that a stratified sampler can stratify the warp within each choice: the next
    /// number, then the next two.
    fn next_choice_and_vec2(&mut self) -> (f32, Vec2) {
        let choice = self.next_f32();
        (choice, self.next_vec2())
    }

    /// Draws from the start of `stream` from here on. One sequence (a [`Pcg32`]) ignores it.
    fn start_stream(&mut self, _stream: Stream) {}
}

impl RandomSource for Pcg32 {
    fn next_f32(&mut self) -> f32 {
        Pcg32::next_f32(self)
    }

    fn next_vec2(&mut self) -> Vec2 {
        Pcg32::next_vec2(self)
    }
}

pub use chiaro_shading::owen_sobol::Sampler;
