//! One connection strategy of one path length per sample, as multiplexed Metropolis light
//! transport draws them (Hachisuka, Kaplanyan and Dachsbacher 2014, "Multiplexed Metropolis
//! Light Transport"): the sample's first number picks the strategy (s, t) among the k + 2 that
//! make a path of k bounces, the subpaths are traced to exactly s and t vertices (no Russian
//! roulette: a subpath that ends sooner makes no path), and the one connection is weighted by
//! its MIS weight over all k + 2 strategies times k + 2. Summed over the strategies' equal
//! chances, that is the bidirectional estimate of the light carried by paths of k bounces, at
//! the cost of one connection instead of every pair's.

use glam::{Vec2, Vec3};

use super::walk::{Roulette, camera_subpath, light_subpath};
use super::{Splat, Strategies, Subpaths, connect, mis};
use crate::random::{RandomSource, Stream};
use crate::scene::RenderScene;

/// The number of connection strategies that make a path of `bounces` bounces: k + 2, but one
/// for a camera path that reaches an emitter at once (a light is not joined to the eye).
pub fn strategy_count(bounces: u32) -> u32 {
    if bounces == 0 { 1 } else { bounces + 2 }
}

/// One sample of pixel (x, y) at `jitter`, restricted to paths of `bounces` bounces: the
/// radiance it brings to the pixel, or, where the strategy it draws is light tracing (t = 1),
/// a splat in `splats`. The strategy and the camera subpath draw from the stream `rng` is on;
/// the light subpath and the connection start streams of their own.
pub fn sample(
    scene: &RenderScene,
    pixel: (u32, u32),
    jitter: Vec2,
    rng: &mut impl RandomSource,
    bounces: u32,
    subpaths: &mut Subpaths,
    splats: &mut Vec<Splat>,
) -> Vec3 {
    let count = strategy_count(bounces);
    let s = if bounces == 0 {
        0
    } else {
        ((rng.next_f32() * count as f32) as u32).min(count - 1)
    };
    let t = bounces + 2 - s;
    let Subpaths { camera, light } = subpaths;
    camera_subpath(scene, pixel, jitter, rng, t - 1, &Roulette(None), camera);
    if camera.len() != t as usize {
        return Vec3::ZERO;
    }
    light.clear();
    if s > 1 {
        rng.start_stream(Stream::Light);
        light_subpath(scene, rng, s - 1, &Roulette(None), light);
        if light.len() != s as usize {
            return Vec3::ZERO;
        }
    }
    rng.start_stream(Stream::Connect);
    let (s, t) = (s as usize, t as usize);
    let Some((value, drawn, raster)) = connect(scene, light, camera, (s, t), rng) else {
        return Vec3::ZERO;
    };
    let weighted = value
        * mis::weight(
            scene,
            light,
            camera,
            (s, t),
            drawn.as_ref(),
            Strategies::All,
        )
        * count as f32;
    match raster {
        Some(raster) => {
            splats.push(Splat {
                raster,
                value: weighted,
            });
            Vec3::ZERO
        }
        None => weighted,
    }
}
