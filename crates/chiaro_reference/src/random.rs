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

/// Where a render's numbers come from (Metropolis light transport mutates its own).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Sampler {
    /// Independent uniform numbers, one [`Pcg32`] stream per pixel: plain Monte Carlo, whose
    /// error falls as 1/n.
    Independent,
    /// Owen-scrambled Sobol points, one or two dimensions per draw (module `sobol`):
    /// randomised quasi-Monte Carlo, unbiased, each draw stratified over a pixel's samples.
    #[default]
    Sobol,
}

impl std::fmt::Display for Sampler {
    /// Its name on the command line.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Independent => "independent",
            Self::Sobol => "sobol",
        })
    }
}

impl std::str::FromStr for Sampler {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "independent" => Ok(Self::Independent),
            "sobol" => Ok(Self::Sobol),
            other => Err(format!(
                "unknown sampler '{other}' (expected independent or sobol)"
            )),
        }
    }
}
