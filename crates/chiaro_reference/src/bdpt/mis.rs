//! The multiple-importance weight of one connection strategy: the power heuristic (exponent 2)
//! over every strategy that could have made the same path (Veach 1997, section 10.2), found
//! from the ratios of neighbouring strategies' densities along the path (Pharr, Jakob and
//! Humphreys, "Physically Based Rendering", 3rd ed., 16.3.4).
//!
//! Strategies this estimator never takes count zero: joining a light's own first vertex to the
//! camera (s = 1, t = 1: a light seen directly is found by the camera path alone), and any
//! whose density is zero where the path's is not (the environment where it is not
//! light-sampled; a light path cannot start there).

use super::Strategies;
use super::vertex::Vertex;
use crate::scene::RenderScene;

/// The area densities of one vertex under the strategy being weighed.
#[derive(Clone, Copy)]
struct Densities {
    forward: f32,
    reverse: f32,
    delta: bool,
}

impl From<&Vertex> for Densities {
    fn from(v: &Vertex) -> Self {
        Self {
            forward: v.pdf_fwd,
            reverse: v.pdf_rev,
            delta: v.delta,
        }
    }
}

/// The ratio of the neighbouring strategy's density to this one's at a vertex: a delta
/// vertex's zero densities count 1 (they cancel), and a zero reverse density against a
/// non-zero forward one is a strategy that cannot make this path.
fn ratio(d: Densities) -> f32 {
    match (d.reverse == 0.0, d.forward == 0.0) {
        (true, true) => 1.0,
        (true, false) => 0.0,
        (false, true) => d.reverse,
        (false, false) => d.reverse / d.forward,
    }
}

/// The weight of joining light vertex `s` - 1 to camera vertex `t` - 1, among the strategies
/// `taken`; `sampled` is the vertex that strategy drew afresh (the light point for s = 1, the
/// eye for t = 1).
pub fn weight(
    scene: &RenderScene,
    light: &[Vertex],
    camera: &[Vertex],
    (s, t): (usize, usize),
    sampled: Option<&Vertex>,
    taken: Strategies,
) -> f32 {
    if s + t == 2 {
        return 1.0;
    }
    let qs: Option<&Vertex> = match s {
        0 => None,
        1 => sampled,
        _ => Some(&light[s - 1]),
    };
    let pt: &Vertex = if t == 1 {
        sampled.expect("t = 1 draws the eye")
    } else {
        &camera[t - 1]
    };
    let qs_minus = (s > 1).then(|| &light[s - 2]);
    let pt_minus = (t > 1).then(|| &camera[t - 2]);

    let mut cam: Vec<Densities> = camera[..t].iter().map(Densities::from).collect();
    if t == 1 {
        cam[0] = pt.into();
    }
    // Next-event estimation's light point stands in for the light subpath's first vertex.
    let mut lig: Vec<Densities> = match (s, qs) {
        (1, Some(q)) => vec![q.into()],
        _ => light[..s].iter().map(Densities::from).collect(),
    };
    // The joined vertices are not sampled from a delta lobe under this strategy.
    cam[t - 1].delta = false;
    if s > 0 {
        lig[s - 1].delta = false;
    }
    cam[t - 1].reverse = match qs {
        Some(q) => q.pdf(scene, qs_minus, pt),
        None => pt_minus.map_or(0.0, |m| pt.pdf_light_origin(scene, m)),
    };
    if let Some(m) = pt_minus {
        cam[t - 2].reverse = match qs {
            Some(q) => pt.pdf(scene, Some(q), m),
            None => pt.pdf_light(scene, m),
        };
    }
    if let Some(q) = qs {
        lig[s - 1].reverse = pt.pdf(scene, pt_minus, q);
    }
    if let (Some(q), Some(m)) = (qs, qs_minus) {
        lig[s - 2].reverse = q.pdf(scene, Some(pt), m);
    }

    let mut sum = 0.0;
    let mut r = 1.0;
    // The strategy with i camera vertices and s + t - i light vertices.
    for i in (1..t).rev() {
        r *= ratio(cam[i]);
        if !cam[i].delta && !cam[i - 1].delta && taken.takes(s + t - i, i) {
            sum += r * r;
        }
    }
    let delta_light = match s {
        0 => false,
        1 => sampled.is_some_and(|v| v.is_delta_light(scene)),
        _ => light[0].is_delta_light(scene),
    };
    r = 1.0;
    // The strategy with i light vertices and s + t - i camera vertices.
    for i in (0..s).rev() {
        r *= ratio(lig[i]);
        let delta_before = if i > 0 { lig[i - 1].delta } else { delta_light };
        if !lig[i].delta && !delta_before && taken.takes(i, s + t - i) {
            sum += r * r;
        }
    }
    1.0 / (1.0 + sum)
}
