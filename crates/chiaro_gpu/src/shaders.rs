//! The WGSL sources and their composition.
//!
//! Every `.wgsl` file under the workspace's `shaders/` directory is embedded in the binary (the
//! build script lists them, each with `include_str!`), named by its path relative to `shaders/`,
//! e.g. `direct.wgsl` or `lib/brdf.wgsl`.
//!
//! A file imports modules with whole lines `#import lib/NAME.wgsl` (paths relative to
//! `shaders/`). [`compose`] resolves them depth-first: each module's imports come before the
//! module, every file appears once however many files import it, and an import cycle or a
//! missing file is refused with an error naming it. This small preprocessor replaces WESL
//! because chiaro's modules need only include-once semantics (one flat namespace, no
//! generics or conditional compilation: features are specialised through WGSL's
//! pipeline-overridable constants instead), and it adds no dependency.
//!
//! `lib/generated.wgsl` is a virtual module: [`generated_constants`] writes it from the Rust
//! constants the shaders share (PI, the mirror threshold, light kinds, material flags, ...), so
//! no such number is copied into WGSL by hand. `lib/features.wgsl` is another: the
//! pipeline-overridable feature flags of [`crate::specialization`].

use std::collections::HashSet;
use std::fmt::Write as _;

use thiserror::Error;

/// Every embedded shader file: (path relative to `shaders/`, source).
pub static SHADER_FILES: &[(&str, &str)] = include!(concat!(env!("OUT_DIR"), "/shader_table.rs"));

/// Name of the virtual module holding the generated constants.
pub const GENERATED_MODULE: &str = "lib/generated.wgsl";

/// The prefix of an import line.
const IMPORT: &str = "#import ";

/// Why a shader could not be composed.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum ShaderError {
    /// A file, or a file's import, names no embedded file.
    #[error("shader '{name}' not found (imported by {importer})")]
    Missing {
        /// The missing file.
        name: String,
        /// The file that imports it, or `the caller`.
        importer: String,
    },
    /// Files import each other in a cycle.
    #[error("shader import cycle: {}", cycle.join(" -> "))]
    Cycle {
        /// The files of the cycle, first repeated at the end.
        cycle: Vec<String>,
    },
}

/// The source of the embedded file `name`, or of the virtual generated module.
pub fn source(name: &str) -> Option<String> {
    if name == GENERATED_MODULE {
        return Some(generated_constants());
    }
    if name == crate::specialization::FEATURES_MODULE {
        return Some(crate::specialization::features_module());
    }
    SHADER_FILES
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, s)| (*s).to_owned())
}

/// The entry files: embedded files outside `lib/` (one per pass).
pub fn entry_files() -> impl Iterator<Item = &'static str> {
    SHADER_FILES
        .iter()
        .map(|(n, _)| *n)
        .filter(|n| !n.starts_with("lib/"))
}

/// `name` with its imports resolved (see the module documentation).
pub fn compose(name: &str) -> Result<String, ShaderError> {
    compose_with(name, &source)
}

/// [`compose`] over the files `lookup` returns (tests use their own tables).
pub fn compose_with(
    name: &str,
    lookup: &dyn Fn(&str) -> Option<String>,
) -> Result<String, ShaderError> {
    let mut composer = Composer {
        lookup,
        done: HashSet::new(),
        stack: Vec::new(),
        out: String::new(),
    };
    composer.include(name, "the caller")?;
    Ok(composer.out)
}

struct Composer<'a> {
    lookup: &'a dyn Fn(&str) -> Option<String>,
    done: HashSet<String>,
    stack: Vec<String>,
    out: String,
}

impl Composer<'_> {
    fn include(&mut self, name: &str, importer: &str) -> Result<(), ShaderError> {
        if self.done.contains(name) {
            return Ok(());
        }
        if let Some(at) = self.stack.iter().position(|n| n == name) {
            let mut cycle = self.stack[at..].to_vec();
            cycle.push(name.to_owned());
            return Err(ShaderError::Cycle { cycle });
        }
        let text = (self.lookup)(name).ok_or_else(|| ShaderError::Missing {
            name: name.to_owned(),
            importer: importer.to_owned(),
        })?;
        self.stack.push(name.to_owned());
        let mut body = String::new();
        for line in text.lines() {
            match line.trim_end().strip_prefix(IMPORT) {
                Some(import) => self.include(import.trim(), name)?,
                None => {
                    body.push_str(line);
                    body.push('\n');
                }
            }
        }
        self.stack.pop();
        self.done.insert(name.to_owned());
        let _ = writeln!(self.out, "// ---- {name} ----");
        self.out.push_str(&body);
        Ok(())
    }
}

/// A constant shared between Rust and WGSL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SharedConstant {
    /// An `f32`.
    F32(&'static str, f32),
    /// A `u32`.
    U32(&'static str, u32),
}

/// Every constant of the generated module, with its Rust value.
pub fn shared_constants() -> Vec<SharedConstant> {
    use SharedConstant::{F32, U32};
    let mut all = vec![
        F32("PI", std::f32::consts::PI),
        F32("INV_PI", std::f32::consts::FRAC_1_PI),
        F32("MIRROR_ALPHA", chiaro_shading::brdf::MIRROR_ALPHA),
        F32("ETA_DELTA_BAND", chiaro_shading::brdf::ETA_DELTA_BAND),
        F32("COAT_F0", chiaro_shading::brdf::COAT_F0),
        F32(
            "MIN_REFLECTION_COSINE",
            chiaro_shading::shading_normal::MIN_REFLECTION_COSINE,
        ),
        F32(
            "MIN_LOBE_PROBABILITY",
            chiaro_shading::brdf::MIN_LOBE_PROBABILITY,
        ),
        F32(
            "DEFAULT_F0_DIELECTRIC",
            chiaro_shading::brdf::DEFAULT_F0_DIELECTRIC,
        ),
        F32("ALPHA_FLOOR", chiaro_shading::ggx::ALPHA_FLOOR),
        F32(
            "VISIBILITY_DENOMINATOR_FLOOR",
            chiaro_shading::ggx::VISIBILITY_DENOMINATOR_FLOOR,
        ),
        F32(
            "UNIFORM_HEMISPHERE_PDF",
            chiaro_shading::sampling::UNIFORM_HEMISPHERE_PDF,
        ),
        F32(
            "UNIFORM_SPHERE_PDF",
            chiaro_shading::sampling::UNIFORM_SPHERE_PDF,
        ),
        F32(
            "MIN_PUNCTUAL_DISTANCE",
            chiaro_shading::lights::MIN_PUNCTUAL_DISTANCE,
        ),
        F32(
            "MIN_SPOT_COS_DIFFERENCE",
            chiaro_shading::lights::MIN_SPOT_COS_DIFFERENCE,
        ),
        F32(
            "MAX_TONEMAP_INPUT",
            chiaro_shading::tonemap::MAX_TONEMAP_INPUT,
        ),
        F32("LUMINANCE_R", chiaro_shading::color::LUMINANCE_WEIGHTS.x),
        F32("LUMINANCE_G", chiaro_shading::color::LUMINANCE_WEIGHTS.y),
        F32("LUMINANCE_B", chiaro_shading::color::LUMINANCE_WEIGHTS.z),
        F32("BLAS_PAD_ULPS", chiaro_bvh::slab::BLAS_PAD_ULPS),
        F32("TLAS_PAD_ULPS", chiaro_bvh::slab::TLAS_PAD_ULPS),
        U32("TLAS_LEAF_BIT", chiaro_bvh::TLAS_LEAF_BIT),
        F32("FRAC_PI_2", std::f32::consts::FRAC_PI_2),
        F32("FRAC_PI_4", std::f32::consts::FRAC_PI_4),
        F32("TAU", std::f32::consts::TAU),
        F32("F32_EPSILON", f32::EPSILON),
        F32("TWO_GAMMA3", chiaro_bvh::slab::TWO_GAMMA3),
        F32("MAX_RAY_COORDINATE", chiaro_bvh::ray::MAX_RAY_COORDINATE),
        F32("MIN_RAY_DIRECTION", chiaro_bvh::ray::MIN_RAY_DIRECTION),
        U32("BVH_STACK_SIZE", chiaro_bvh::blas::MAX_BINARY_DEPTH as u32),
        F32("OFFSET_ORIGIN", chiaro_bvh::offset::ORIGIN),
        F32("OFFSET_FLOAT_SCALE", chiaro_bvh::offset::FLOAT_SCALE),
        F32("OFFSET_INT_SCALE", chiaro_bvh::offset::INT_SCALE),
        F32(
            "ONE_MINUS_EPSILON",
            chiaro_shading::distribution::ONE_MINUS_EPSILON,
        ),
        F32("MIN_SIN_THETA", chiaro_shading::lights::MIN_SIN_THETA),
        U32(
            "PCG32_MULTIPLIER_LO",
            chiaro_shading::rng::PCG32_MULTIPLIER as u32,
        ),
        U32(
            "PCG32_MULTIPLIER_HI",
            (chiaro_shading::rng::PCG32_MULTIPLIER >> 32) as u32,
        ),
    ];
    all.extend(crate::gpu_scene::constants());
    all.push(F32(
        "SHADOW_RAY_REACH",
        crate::passes::direct::SHADOW_RAY_REACH,
    ));
    all.extend(crate::passes::composite::constants());
    all.extend(
        chiaro_shading::tonemap::CURVE_CONSTANTS
            .iter()
            .map(|&(name, value)| F32(name, value)),
    );
    all.extend(
        chiaro_shading::sheen::SHADER_CONSTANTS
            .iter()
            .map(|&(name, value)| F32(name, value)),
    );
    all
}

/// The source of `lib/generated.wgsl`: one `const` per [`shared_constants`] entry. Floats are
/// written as their bit patterns' shortest round-trip decimal, so WGSL reads the same `f32`.
pub fn generated_constants() -> String {
    let mut out = String::from(
        "// Generated by chiaro_gpu::shaders::generated_constants from the Rust constants.\n",
    );
    for constant in shared_constants() {
        match constant {
            SharedConstant::F32(name, value) => {
                let _ = writeln!(out, "const {name}: f32 = {value:e};");
            }
            SharedConstant::U32(name, value) => {
                let _ = writeln!(out, "const {name}: u32 = {value}u;");
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn table(files: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let map: HashMap<String, String> = files
            .iter()
            .map(|(n, s)| ((*n).to_owned(), (*s).to_owned()))
            .collect();
        move |name| map.get(name).cloned()
    }

    #[test]
    fn imports_come_first_and_once() {
        let lookup = table(&[
            (
                "main.wgsl",
                "#import lib/a.wgsl\n#import lib/b.wgsl\nfn main_fn() {}",
            ),
            ("lib/a.wgsl", "#import lib/c.wgsl\nfn a() {}"),
            (
                "lib/b.wgsl",
                "#import lib/c.wgsl\n#import lib/a.wgsl\nfn b() {}",
            ),
            ("lib/c.wgsl", "fn c() {}"),
        ]);
        let out = compose_with("main.wgsl", &lookup).unwrap();
        let at = |s: &str| {
            assert_eq!(out.matches(s).count(), 1, "{s} once in\n{out}");
            out.find(s).unwrap()
        };
        assert!(at("fn c()") < at("fn a()"));
        assert!(at("fn a()") < at("fn b()"));
        assert!(at("fn b()") < at("fn main_fn()"));
        assert!(!out.contains("#import"));
    }

    #[test]
    fn a_cycle_is_refused_and_named() {
        let lookup = table(&[
            ("main.wgsl", "#import lib/a.wgsl\n"),
            ("lib/a.wgsl", "#import lib/b.wgsl\n"),
            ("lib/b.wgsl", "#import lib/a.wgsl\n"),
        ]);
        let err = compose_with("main.wgsl", &lookup).unwrap_err();
        assert_eq!(
            err,
            ShaderError::Cycle {
                cycle: vec![
                    "lib/a.wgsl".into(),
                    "lib/b.wgsl".into(),
                    "lib/a.wgsl".into()
                ]
            }
        );
        assert!(err.to_string().contains("lib/a.wgsl -> lib/b.wgsl"));
    }

    #[test]
    fn a_missing_file_is_refused_and_named() {
        let lookup = table(&[("main.wgsl", "#import lib/gone.wgsl\n")]);
        let err = compose_with("main.wgsl", &lookup).unwrap_err();
        assert_eq!(
            err,
            ShaderError::Missing {
                name: "lib/gone.wgsl".into(),
                importer: "main.wgsl".into()
            }
        );
        assert!(compose("no-such-pass.wgsl").is_err());
    }

    #[test]
    fn the_generated_module_is_importable_and_exact() {
        let text = compose(GENERATED_MODULE).unwrap();
        let pi = format!("const PI: f32 = {:e};", std::f32::consts::PI);
        assert!(text.contains(&pi), "{text}");
        for constant in shared_constants() {
            if let SharedConstant::F32(name, value) = constant {
                let written = format!("{value:e}").parse::<f32>().unwrap();
                assert_eq!(written.to_bits(), value.to_bits(), "{name}");
            }
        }
    }
}
