//! Built-in scenes, addressed as `builtin:NAME`, some with parameters
//! (`builtin:NAME?key=value&key=value`):
//!
//! | name | what | parameters |
//! |---|---|---|
//! | `caustic` | a small emitter's caustics on a floor, from a polished metal ring and a glass sphere | |
//! | `cornell` | the Cornell box, published dimensions and reflectances, emissive quad light | |
//! | `door` | Veach's door: a room lit only through a door ajar from the next room's emitter | |
//! | `furnace` | inside a closed diffuse sphere of albedo 0.5 emitting 0.5: radiance 1 everywhere | |
//! | `hard-cases` | numerically hard cases side by side, each with its camera (`scale` only alone) | `case` (one case alone) |
//! | `instances` | one mesh instanced on a grid | `n` (instances, default 1024) |
//! | `lamp` | a room lit by a small emitter hidden in a pendant lamp's shade | |
//! | `many-lights` | small emissive quads and punctual lights over a floor | `quads`, `lights` (256 each) |
//! | `walkthrough` | a colonnaded street of 1.3M unique triangles that moves, with a camera path | `size` (bays, 8), `detail` (4), `seed` (1) |
//!
//! Built-in scenes go through the same mesh validation as files; they need no file.

mod caustic;
mod cornell;
mod door;
mod furnace;
mod hard_cases;
mod instances;
mod lamp;
mod many_lights;
pub mod shapes;
#[cfg(test)]
mod sight;
pub mod walkthrough;

use std::collections::BTreeMap;

use crate::error::{Fault, SceneError};
use crate::material::MaterialId;
use crate::mesh_repair::MeshData;
use crate::scene_builder::SceneBuilder;
use crate::transform::Transform;

pub use hard_cases::{CASES_ALONE, HARD_CASES, hard_case_scene};

/// Names of the built-in scenes.
pub const BUILTIN_SCENES: [&str; 9] = [
    "caustic",
    "cornell",
    "door",
    "furnace",
    "hard-cases",
    "instances",
    "lamp",
    "many-lights",
    "walkthrough",
];

/// Parameters of a built-in scene, parsed from its `?key=value&...` suffix.
pub(crate) struct Params {
    spec: String,
    values: BTreeMap<String, String>,
}

impl Params {
    fn error(&self, why: String) -> SceneError {
        SceneError::whole(self.spec.clone(), Fault::Builtin(why))
    }

    /// An integer parameter in `range`, or `default` when absent.
    pub fn count(&mut self, key: &str, default: usize, max: usize) -> Result<usize, SceneError> {
        match self.values.remove(key) {
            None => Ok(default),
            Some(text) => match text.parse::<usize>() {
                Ok(v) if v <= max => Ok(v),
                _ => Err(self.error(format!(
                    "parameter {key}={text} is not a whole number in 0..={max}"
                ))),
            },
        }
    }

    /// A text parameter, if present.
    pub fn text(&mut self, key: &str) -> Option<String> {
        self.values.remove(key)
    }

    /// Fails if any parameter was not consumed.
    fn finish(&self) -> Result<(), SceneError> {
        match self.values.keys().next() {
            Some(key) => Err(self.error(format!("unknown parameter '{key}'"))),
            None => Ok(()),
        }
    }
}

/// Builds the built-in scene `spec` (`builtin:NAME[?params]`).
pub fn build(spec: &str) -> Result<SceneBuilder, SceneError> {
    let whole = |why: String| SceneError::whole(spec, Fault::Builtin(why));
    let rest = spec
        .strip_prefix("builtin:")
        .ok_or_else(|| whole("a built-in scene name starts with 'builtin:'".into()))?;
    let (name, query) = rest.split_once('?').unwrap_or((rest, ""));
    let mut values = BTreeMap::new();
    for pair in query.split('&').filter(|p| !p.is_empty()) {
        let (k, v) = pair
            .split_once('=')
            .ok_or_else(|| whole(format!("parameter '{pair}' is not key=value")))?;
        values.insert(k.to_owned(), v.to_owned());
    }
    let mut params = Params {
        spec: spec.to_owned(),
        values,
    };
    let mut builder = SceneBuilder::new(spec);
    match name {
        "caustic" => caustic::build(&mut builder)?,
        "cornell" => cornell::build(&mut builder)?,
        "door" => door::build(&mut builder)?,
        "furnace" => furnace::build(&mut builder)?,
        "hard-cases" => hard_cases::build(&mut builder, &mut params)?,
        "instances" => instances::build(&mut builder, &mut params)?,
        "lamp" => lamp::build(&mut builder)?,
        "many-lights" => many_lights::build(&mut builder, &mut params)?,
        "walkthrough" => walkthrough::build(&mut builder, &mut params)?,
        _ => {
            return Err(whole(format!(
                "unknown built-in scene '{name}' (known: {})",
                BUILTIN_SCENES.join(", ")
            )));
        }
    }
    params.finish()?;
    Ok(builder)
}

/// Adds `data` as a mesh named `name` and one instance of it with `material` at `transform`.
pub(super) fn add_shape(
    b: &mut SceneBuilder,
    name: &str,
    material: MaterialId,
    data: MeshData,
    transform: Transform,
) -> Result<(), SceneError> {
    if let Some(mesh) = b.add_mesh(&format!("mesh {name:?}"), name, data)? {
        b.add_instance(name, mesh, material, transform);
    }
    Ok(())
}

/// A small deterministic generator (SplitMix64) for scene layouts: same parameters, same scene.
pub(crate) struct Layout(u64);

impl Layout {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    /// Uniform in [0, 1).
    pub fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.next()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_names_and_parameters_are_errors() {
        let e = build("builtin:nope").unwrap_err().to_string();
        assert!(e.contains("unknown built-in scene 'nope'"), "{e}");
        let e = build("builtin:cornell?n=3").unwrap_err().to_string();
        assert!(e.contains("unknown parameter 'n'"), "{e}");
        let e = build("builtin:instances?n=lots").unwrap_err().to_string();
        assert!(
            e.starts_with("builtin:instances?n=lots: parameter n=lots"),
            "{e}"
        );
        assert!(build("builtin:instances?n=100000000000").is_err());
    }

    #[test]
    fn layout_is_deterministic_and_in_range() {
        let (mut a, mut b) = (Layout::new(7), Layout::new(7));
        for _ in 0..1000 {
            let x = a.next();
            assert_eq!(x, b.next());
            assert!((0.0..1.0).contains(&x));
        }
    }
}
