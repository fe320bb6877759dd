//! glTF animations read into [`AnimationClip`]s (see [`crate::animation`]): each channel that
//! drives a node's translation, rotation or scale, its sampler's key times and values read
//! through the checked accessor reader. What chiaro cannot play is left out with a repair line
//! naming the animation and the channel: a channel whose node is not in the imported scene,
//! morph target weights, and any channel whose keys are malformed (times not increasing, counts
//! that do not match, values that are not finite, the wrong accessor format), so that the
//! scene's static pose still renders.

use std::collections::HashMap;

use glam::Vec4;
use gltf::animation::{Interpolation as GltfInterpolation, Property as GltfProperty};

use crate::animation::{AnimationClip, Channel, Interpolation, Keyframes, Property};
use crate::gltf::accessor::{AccessorReader, Formats};
use crate::gltf::nodes::element;
use crate::scene_builder::{NodeIndex, SceneBuilder};

/// The keyframes of a channel's sampler, or why they cannot be played.
fn keyframes(
    reader: &AccessorReader,
    channel: &gltf::animation::Channel,
    property: Property,
) -> Result<Keyframes, String> {
    let sampler = channel.sampler();
    let times: Vec<f32> = reader
        .read::<1>(&sampler.input(), Formats::Float)
        .map_err(|why| format!("key times: {why}"))?
        .into_iter()
        .map(|[t]| t as f32)
        .collect();
    let output = sampler.output();
    let values: Vec<Vec4> = match property {
        Property::Rotation => reader
            .read::<4>(&output, Formats::FloatOrNorm)
            .map_err(|why| format!("rotations: {why}"))?
            .into_iter()
            .map(|v| Vec4::from_array(v.map(|c| c as f32)))
            .collect(),
        Property::Translation | Property::Scale => reader
            .read::<3>(&output, Formats::Float)
            .map_err(|why| format!("values: {why}"))?
            .into_iter()
            .map(|v| Vec4::new(v[0] as f32, v[1] as f32, v[2] as f32, 0.0))
            .collect(),
    };
    let interpolation = match sampler.interpolation() {
        GltfInterpolation::Step => Interpolation::Step,
        GltfInterpolation::Linear => Interpolation::Linear,
        GltfInterpolation::CubicSpline => Interpolation::CubicSpline,
    };
    Keyframes::new(times, values, interpolation)
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
            let node = channel.target().node().index();
            let property = match channel.target().property() {
                GltfProperty::Translation => Property::Translation,
                GltfProperty::Rotation => Property::Rotation,
                GltfProperty::Scale => Property::Scale,
                GltfProperty::MorphTargetWeights => {
                    builder.repair(at, "morph target weights are not played: channel left out");
                    continue;
                }
            };
            let Some(&target) = node_of.get(&(node as u32)) else {
                builder.repair(
                    at,
                    format!("drives node {node}, which is not in the scene: channel left out"),
                );
                continue;
            };
            match keyframes(reader, &channel, property) {
                Ok(keyframes) => channels.push(Channel {
                    target,
                    property,
                    keyframes,
                }),
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
