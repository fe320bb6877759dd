//! glTF animations read into [`AnimationClip`]s (see [`crate::animation`]): each channel that
//! drives a node's translation, rotation, scale or morph target weights (split into one channel
//! per target), its sampler's key times and values read through the checked accessor reader.
//! What chiaro cannot play is left out with a repair line naming the animation and the channel:
//! a channel whose node is not in the imported scene, morph target weights of a node without
//! morph targets, and any channel whose keys are malformed (times not increasing, counts that
//! do not match, values that are not finite, the wrong accessor format), so that the scene's
//! static pose still renders.

use std::collections::HashMap;

use glam::Vec4;
use gltf::animation::{Interpolation as GltfInterpolation, Property as GltfProperty};

use crate::animation::{AnimationClip, Channel, Interpolation, Keyframes, Property};
use crate::gltf::accessor::{AccessorReader, Formats};
use crate::gltf::nodes::element;
use crate::scene_builder::{NodeIndex, SceneBuilder};

/// What a channel drives: one property of a transform, or all `n` morph weights of a node.
#[derive(Clone, Copy)]
enum Driven {
    Transform(Property),
    Weights(usize),
}

/// The keyframes of a channel's sampler (one per morph target for weights), or why they cannot
/// be played.
fn keyframes(
    reader: &AccessorReader,
    channel: &gltf::animation::Channel,
    driven: Driven,
) -> Result<Vec<(Property, Keyframes)>, String> {
    let sampler = channel.sampler();
    let times: Vec<f32> = reader
        .read::<1>(&sampler.input(), Formats::Float)
        .map_err(|why| format!("key times: {why}"))?
        .into_iter()
        .map(|[t]| t as f32)
        .collect();
    let output = sampler.output();
    let interpolation = match sampler.interpolation() {
        GltfInterpolation::Step => Interpolation::Step,
        GltfInterpolation::Linear => Interpolation::Linear,
        GltfInterpolation::CubicSpline => Interpolation::CubicSpline,
    };
    let (property, values): (Property, Vec<Vec4>) = match driven {
        Driven::Transform(Property::Rotation) => (
            Property::Rotation,
            reader
                .read::<4>(&output, Formats::FloatOrNorm)
                .map_err(|why| format!("rotations: {why}"))?
                .into_iter()
                .map(|v| Vec4::from_array(v.map(|c| c as f32)))
                .collect(),
        ),
        Driven::Transform(property) => (
            property,
            reader
                .read::<3>(&output, Formats::Float)
                .map_err(|why| format!("values: {why}"))?
                .into_iter()
                .map(|v| Vec4::new(v[0] as f32, v[1] as f32, v[2] as f32, 0.0))
                .collect(),
        ),
        Driven::Weights(n) => {
            let scalars = reader
                .read::<1>(&output, Formats::FloatOrNorm)
                .map_err(|why| format!("weights: {why}"))?;
            return weight_keyframes(&scalars, n, &times, interpolation);
        }
    };
    Ok(vec![(
        property,
        Keyframes::new(times, values, interpolation)?,
    )])
}

/// One sampler's weights split into the keyframes of each of the `n` morph targets: the values
/// of target k are every n-th scalar from k.
fn weight_keyframes(
    scalars: &[[f64; 1]],
    n: usize,
    times: &[f32],
    interpolation: Interpolation,
) -> Result<Vec<(Property, Keyframes)>, String> {
    if !scalars.len().is_multiple_of(n) {
        return Err(format!(
            "holds {} weights, not a multiple of the {n} morph targets",
            scalars.len()
        ));
    }
    (0..n)
        .map(|k| {
            let values = scalars
                .iter()
                .skip(k)
                .step_by(n)
                .map(|[w]| Vec4::new(*w as f32, 0.0, 0.0, 0.0))
                .collect();
            Keyframes::new(times.to_vec(), values, interpolation)
                .map(|keys| (Property::MorphWeight(k), keys))
        })
        .collect()
}

/// Why channel `c` of animation `a` cannot even be looked at, checked on the JSON: the gltf
/// crate's accessors for a channel's sampler, node, path, interpolation and accessors index
/// unchecked (and its validation leaves some of them out). None when all exist.
fn dangling_reference(document: &gltf::Document, a: usize, c: usize) -> Option<String> {
    use gltf::json::validation::Checked;
    let root = document.as_json();
    let animation = &root.animations[a];
    let channel = &animation.channels[c];
    let Some(sampler) = animation.samplers.get(channel.sampler.value()) else {
        return Some(format!(
            "names sampler {}, which does not exist",
            channel.sampler.value()
        ));
    };
    let node = channel.target.node.value();
    if node >= root.nodes.len() {
        return Some(format!("drives node {node}, which does not exist"));
    }
    if !matches!(channel.target.path, Checked::Valid(_)) {
        return Some("drives a property chiaro does not know".into());
    }
    if !matches!(sampler.interpolation, Checked::Valid(_)) {
        return Some("its sampler's interpolation is not STEP, LINEAR or CUBICSPLINE".into());
    }
    for (what, index) in [
        ("input", sampler.input.value()),
        ("output", sampler.output.value()),
    ] {
        if index >= root.accessors.len() {
            return Some(format!(
                "its sampler's {what} names accessor {index}, which does not exist"
            ));
        }
    }
    None
}

/// How many morph targets the mesh of glTF node `node` has (0 without a mesh).
fn morph_target_count(node: &gltf::Node) -> usize {
    node.mesh()
        .and_then(|mesh| mesh.primitives().map(|p| p.morph_targets().count()).max())
        .unwrap_or(0)
}

/// Adds the file's animations to `builder`, whose nodes were imported from `document` (each
/// carrying its glTF node index as `source_node`).
pub(crate) fn import(
    document: &gltf::Document,
    reader: &AccessorReader,
    builder: &mut SceneBuilder,
) {
    let mut node_of: HashMap<u32, NodeIndex> = HashMap::new();
    for (index, node) in builder.nodes().iter().enumerate() {
        if let Some(source) = node.source_node {
            node_of.entry(source).or_insert(index);
        }
    }
    for animation in document.animations() {
        let name = element("animation", animation.index(), animation.name());
        let mut channels = Vec::new();
        for (c, channel) in animation.channels().enumerate() {
            let at = format!("{name}, channel {c}");
            if let Some(why) = dangling_reference(document, animation.index(), c) {
                builder.repair(at, format!("{why}: channel left out"));
                continue;
            }
            let node = channel.target().node().index();
            let driven = match channel.target().property() {
                GltfProperty::Translation => Driven::Transform(Property::Translation),
                GltfProperty::Rotation => Driven::Transform(Property::Rotation),
                GltfProperty::Scale => Driven::Transform(Property::Scale),
                GltfProperty::MorphTargetWeights => {
                    match morph_target_count(&channel.target().node()) {
                        0 => {
                            builder.repair(
                                at,
                                "drives the morph weights of a node whose mesh has no morph \
                                 targets: channel left out",
                            );
                            continue;
                        }
                        n => Driven::Weights(n),
                    }
                }
            };
            let Some(&target) = node_of.get(&(node as u32)) else {
                builder.repair(
                    at,
                    format!("drives node {node}, which is not in the scene: channel left out"),
                );
                continue;
            };
            match keyframes(reader, &channel, driven) {
                Ok(keyed) => {
                    channels.extend(keyed.into_iter().map(|(property, keyframes)| Channel {
                        target,
                        property,
                        keyframes,
                    }))
                }
                Err(why) => builder.repair(
                    format!("{at}, sampler {}", channel.sampler().index()),
                    format!("{why}: channel left out"),
                ),
            }
        }
        if !channels.is_empty() {
            builder.add_animation(AnimationClip {
                name: animation.name().map_or_else(|| name.clone(), str::to_owned),
                channels,
            });
        }
    }
}
