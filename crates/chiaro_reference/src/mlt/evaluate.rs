//! The target function a chain samples: the bidirectional tracer at a point of primary sample
//! space, either every connection strategy of one sample (Kelemen et al.'s primary sample
//! space over the bidirectional tracer) or one strategy of one path length (multiplexed), and
//! the scalar importance I the chains follow.
//!
//! The multiplexed form draws the path length k >= 1 from a distribution p(k) with the point's
//! third camera coordinate and divides by p(k), so one chain walks every length: a small step
//! of that coordinate across a boundary of p's table moves it to another length
//! ([`super::lengths`]).

use chiaro_shading::color::luminance;
use chiaro_shading::distribution::Distribution1D;
use glam::{Vec2, Vec3};

use super::primary_sample::PrimarySamples;
use crate::bdpt::{self, Splat, Strategies, Subpaths};
use crate::random::{RandomSource, Stream};
use crate::render::RenderSettings;
use crate::scene::RenderScene;

/// Which paths a point of primary sample space stands for.
#[derive(Clone, Copy, Debug)]
pub enum Paths<'a> {
    /// A camera and a light subpath joined by every strategy, weighted by MIS.
    AllStrategies,
    /// One strategy, drawn by the point, of the paths of this many bounces
    /// ([`bdpt::multiplexed`]).
    Bounces(u32),
    /// One strategy of one length, both drawn by the point, the length from this distribution
    /// over the number of bounces less one (paths of one bounce or more).
    AnyLength(&'a Distribution1D),
}

/// One evaluation of the bidirectional tracer at a point of primary sample space.
#[derive(Default)]
pub struct Contributions {
    /// (pixel index, value): the camera subpath's pixel first, then light tracing's splats.
    pub values: Vec<(u32, Vec3)>,
    /// Sum of the values' luminances, each times its pixel's weight: the density the chains
    /// follow.
    pub importance: f32,
    /// True when a value was not finite (the sample then counts as zero).
    pub non_finite: bool,
}

/// Reusable storage of one chain.
#[derive(Default)]
pub struct Workspace {
    subpaths: Subpaths,
    splats: Vec<Splat>,
}

/// Traces the `paths` the point `samples` stands at into `out`; each value's luminance counts
/// in the importance times its pixel's entry of `weights` (1 where it is empty).
pub fn evaluate(
    scene: &RenderScene,
    settings: &RenderSettings,
    paths: Paths,
    weights: &[f32],
    samples: &mut PrimarySamples,
    work: &mut Workspace,
    out: &mut Contributions,
) {
    let (width, height) = (settings.width, settings.height);
    samples.start_stream(Stream::Camera);
    let film = samples.next_vec2() * Vec2::new(width as f32, height as f32);
    let x = (film.x as u32).min(width - 1);
    let y = (film.y as u32).min(height - 1);
    let jitter = (film - Vec2::new(x as f32, y as f32)).clamp(Vec2::ZERO, Vec2::splat(1.0));
    work.splats.clear();
    let (subpaths, splats) = (&mut work.subpaths, &mut work.splats);
    let l = match paths {
        Paths::AllStrategies => bdpt::sample(
            scene,
            (x, y),
            jitter,
            samples,
            &settings.path,
            Strategies::All,
            subpaths,
            splats,
        ),
        Paths::Bounces(bounces) => {
            bdpt::multiplexed::sample(scene, (x, y), jitter, samples, bounces, subpaths, splats)
        }
        Paths::AnyLength(lengths) => {
            let (index, p) = lengths.sample(samples.next_f32());
            let l = bdpt::multiplexed::sample(
                scene,
                (x, y),
                jitter,
                samples,
                index as u32 + 1,
                subpaths,
                splats,
            );
            for splat in splats.iter_mut() {
                splat.value /= p;
            }
            l / p
        }
    };
    out.values.clear();
    if l != Vec3::ZERO {
        out.values.push((y * width + x, l));
    }
    for splat in &work.splats {
        out.values
            .push((splat.pixel(width, height) as u32, splat.value));
    }
    out.non_finite = out.values.iter().any(|(_, v)| !v.is_finite());
    out.importance = if out.non_finite {
        0.0
    } else {
        out.values
            .iter()
            .map(|(pixel, v)| luminance(*v).max(0.0) * weights.get(*pixel as usize).unwrap_or(&1.0))
            .sum()
    };
}
