//! A point of primary sample space, the unit hypercube whose coordinates a tracer turns into a
//! path, and its mutations (Kelemen, Szirmay-Kalos, Antal and Csonka 2002, "A Simple and Robust
//! Mutation Strategy for the Metropolis Light Transport Algorithm"): a large step draws every
//! coordinate afresh; a small step moves each by a normal offset, wrapping round the unit
//! interval. Coordinates are mutated lazily, when the tracer reads them, so a path that reads
//! few of them pays for few: a coordinate left unread for n small steps takes them at once, as
//! one offset with n times the variance. Each [`Stream`] keeps its own sequence of
//! coordinates.

use std::f32::consts::TAU;

use chiaro_shading::rng::Pcg32;

use crate::random::{RandomSource, STREAMS, Stream};

/// `Coordinate::modified` of a coordinate never read.
const NEVER: u64 = u64::MAX;

/// One coordinate, and what it was before the current iteration changed it.
#[derive(Clone, Copy, Debug)]
struct Coordinate {
    value: f32,
    /// The iteration that last set `value`.
    modified: u64,
    backup: f32,
    backup_modified: u64,
}

/// A mutable point of primary sample space.
#[derive(Clone, Debug)]
pub struct PrimarySamples {
    /// Draws the large steps' coordinates and the small steps' offsets.
    rng: Pcg32,
    coordinates: Vec<Coordinate>,
    iteration: u64,
    last_large_step: u64,
    large_step: bool,
    large_step_probability: f32,
    /// Standard deviation of a small step's offset.
    sigma: f32,
    stream: usize,
    index_in_stream: usize,
}

impl PrimarySamples {
    /// A point whose coordinates are drawn from `rng` as they are first read (the first
    /// evaluation is a large step); later iterations mutate it.
    pub fn new(rng: Pcg32, sigma: f32, large_step_probability: f32) -> Self {
        Self {
            rng,
            coordinates: Vec::new(),
            iteration: 0,
            last_large_step: 0,
            large_step: true,
            large_step_probability,
            sigma,
            stream: 0,
            index_in_stream: 0,
        }
    }

    /// Replaces the generator that drives later mutations (chains started from the same
    /// point then walk apart).
    pub fn reseed(&mut self, rng: Pcg32) {
        self.rng = rng;
    }

    /// Starts a mutation: a large step with the large-step probability, else a small one.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.rng.next_f32() < self.large_step_probability;
        self.stream = 0;
        self.index_in_stream = 0;
    }

    /// True when the current iteration is a large step.
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Keeps the mutated point.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// Returns to the point before the current iteration.
    pub fn reject(&mut self) {
        for c in &mut self.coordinates {
            if c.modified == self.iteration {
                c.value = c.backup;
                c.modified = c.backup_modified;
            }
        }
        self.iteration -= 1;
    }

    /// A standard normal number (Box and Muller 1958).
    fn normal(&mut self) -> f32 {
        let radius = (-2.0 * (1.0 - self.rng.next_f32()).ln()).sqrt();
        radius * (TAU * self.rng.next_f32()).cos()
    }

    /// Brings coordinate `i` up to the current iteration.
    fn ensure_ready(&mut self, i: usize) {
        if i >= self.coordinates.len() {
            // Never read: each takes a fresh value as of the last large step below.
            self.coordinates.resize(
                i + 1,
                Coordinate {
                    value: 0.0,
                    modified: NEVER,
                    backup: 0.0,
                    backup_modified: NEVER,
                },
            );
        }
        let iteration = self.iteration;
        let last_large_step = self.last_large_step;
        let mut c = self.coordinates[i];
        // Not read since the last accepted large step (or ever): that step drew it afresh.
        if c.modified == NEVER || c.modified < last_large_step {
            c.value = self.rng.next_f32();
            c.modified = last_large_step;
        }
        // Read before in this iteration (or drawn afresh for it just now).
        if c.modified == iteration {
            self.coordinates[i] = c;
            return;
        }
        c.backup = c.value;
        c.backup_modified = c.modified;
        if self.large_step {
            c.value = self.rng.next_f32();
        } else {
            let steps = iteration - c.modified;
            if steps > 0 {
                let offset = self.normal() * self.sigma * (steps as f32).sqrt();
                let moved = c.value + offset;
                c.value = moved - moved.floor();
                if c.value >= 1.0 {
                    c.value = 0.0;
                }
            }
        }
        c.modified = iteration;
        self.coordinates[i] = c;
    }
}

impl RandomSource for PrimarySamples {
    fn next_f32(&mut self) -> f32 {
        let i = self.index_in_stream * STREAMS + self.stream;
        self.index_in_stream += 1;
        self.ensure_ready(i);
        self.coordinates[i].value
    }

    fn start_stream(&mut self, stream: Stream) {
        self.stream = stream as usize;
        self.index_in_stream = 0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(samples: &mut PrimarySamples, n: usize) -> Vec<f32> {
        samples.start_stream(Stream::Camera);
        (0..n).map(|_| samples.next_f32()).collect()
    }

    #[test]
    fn a_rejected_mutation_restores_the_point() {
        let mut samples = PrimarySamples::new(Pcg32::new(1, 2), 0.01, 0.3);
        let first = read(&mut samples, 6);
        for _ in 0..50 {
            samples.start_iteration();
            let moved = read(&mut samples, 6);
            assert_ne!(moved, first, "every iteration moves the point");
            samples.reject();
            assert_eq!(read(&mut samples, 6), first);
        }
    }

    #[test]
    fn small_steps_stay_close_and_wrap_round() {
        let mut samples = PrimarySamples::new(Pcg32::new(3, 4), 0.01, 0.0);
        let mut current = read(&mut samples, 4);
        for _ in 0..200 {
            samples.start_iteration();
            let moved = read(&mut samples, 4);
            for (a, b) in current.iter().zip(&moved) {
                assert!((0.0..1.0).contains(b));
                let d = (a - b).abs();
                // Six standard deviations, across the wrap included.
                assert!(d.min(1.0 - d) < 0.06, "{a} -> {b}");
            }
            samples.accept();
            current = moved;
        }
    }

    #[test]
    fn coordinates_unread_through_a_large_step_are_drawn_afresh() {
        let mut samples = PrimarySamples::new(Pcg32::new(5, 6), 0.01, 1.0);
        let before = read(&mut samples, 8);
        samples.start_iteration();
        // The large step reads only two coordinates, then is accepted.
        let early = read(&mut samples, 2);
        samples.accept();
        samples.large_step_probability = 0.0;
        samples.start_iteration();
        let after = read(&mut samples, 8);
        assert!((early[0] - after[0]).abs() < 0.06 || (early[0] - after[0]).abs() > 0.94);
        let far = before[2..]
            .iter()
            .zip(&after[2..])
            .filter(|(a, b)| (*a - *b).abs() > 0.06)
            .count();
        assert!(far >= 4, "{before:?} -> {after:?}");
    }

    #[test]
    fn large_steps_are_uniform() {
        let mut samples = PrimarySamples::new(Pcg32::new(7, 8), 0.01, 1.0);
        let n = 20_000;
        let mut bins = [0u32; 10];
        for _ in 0..n {
            samples.start_iteration();
            let x = read(&mut samples, 1)[0];
            bins[(x * 10.0) as usize] += 1;
            samples.accept();
        }
        for count in bins {
            // Binomial standard deviation about 42.
            assert!((count as i64 - 2000).abs() < 200, "{bins:?}");
        }
    }

    #[test]
    fn the_first_read_of_every_stream_is_uniform() {
        let mut sums = [0.0f64; 3];
        let n = 4000;
        for seed in 0..n {
            let mut samples = PrimarySamples::new(Pcg32::new(11, seed), 0.01, 0.3);
            for _ in 0..7 {
                samples.next_f32();
            }
            for (k, stream) in [Stream::Camera, Stream::Light, Stream::Connect]
                .into_iter()
                .enumerate()
            {
                samples.start_stream(stream);
                sums[k] += samples.next_vec2().x as f64;
            }
        }
        for sum in sums {
            // Mean 1/2, standard error about 0.0046.
            assert!((sum / n as f64 - 0.5).abs() < 0.02, "{sums:?}");
        }
    }

    #[test]
    fn streams_do_not_shift_each_other() {
        let mut samples = PrimarySamples::new(Pcg32::new(9, 10), 0.01, 0.3);
        samples.start_stream(Stream::Light);
        let light = samples.next_vec2();
        samples.start_stream(Stream::Camera);
        for _ in 0..5 {
            samples.next_f32();
        }
        samples.start_stream(Stream::Light);
        assert_eq!(samples.next_vec2(), light);
    }
}
