//! The WGSL library in shaders/lib/ (no GPU needed): every module validates under naga on its
//! own, the modules that call hooks of their importer (bvh.wgsl's hit_accepted,
//! environment.wgsl's env_* accessors) validate together with the scene's real hooks
//! (alpha.wgsl, scene_bindings.wgsl), and the CWBVH node struct bvh_bindings.wgsl reads has
//! obvhs's layout (the other BVH records are checked in scene_layout.rs).

use std::mem::{offset_of, size_of};

use chiaro_bvh::CwBvhNode;
use chiaro_gpu::shaders;

fn validate(name: &str, source: &str) -> naga::Module {
    let module = naga::front::wgsl::parse_str(source)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string_with_path(source, name)));
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap_or_else(|e| panic!("{}", e.emit_to_string_with_path(source, name)));
    module
}

/// Composes a virtual file made of `imports`.
fn compose_imports(imports: &[&str]) -> String {
    let entry: String = imports.iter().map(|i| format!("#import {i}\n")).collect();
    shaders::compose_with("library-check.wgsl", &|name| {
        if name == "library-check.wgsl" {
            Some(entry.clone())
        } else {
            shaders::source(name)
        }
    })
    .unwrap()
}

#[test]
fn self_contained_modules_validate_alone() {
    let modules = [
        "lib/float.wgsl",
        "lib/rng.wgsl",
        "lib/frame.wgsl",
        "lib/sampling.wgsl",
        "lib/color.wgsl",
        "lib/ggx.wgsl",
        "lib/brdf.wgsl",
        "lib/offset.wgsl",
        "lib/watertight.wgsl",
        "lib/bvh_bindings.wgsl",
        "lib/lights.wgsl",
        "lib/tonemap.wgsl",
        "lib/coverage.wgsl",
    ];
    for name in modules {
        let source = shaders::compose(name).unwrap_or_else(|e| panic!("{e}"));
        let module = validate(name, &source);
        assert!(
            !module.functions.is_empty() || !module.types.is_empty(),
            "{name} is empty"
        );
    }
}

#[test]
fn modules_with_hooks_validate_with_the_scenes_hooks() {
    let source = compose_imports(&[
        "lib/alpha.wgsl",
        "lib/bvh.wgsl",
        "lib/scene_bindings.wgsl",
        "lib/environment.wgsl",
        "lib/first_bounce.wgsl",
    ]);
    let module = validate("bvh + environment", &source);
    for f in [
        "trace_closest",
        "trace_any",
        "environment_sample",
        "environment_pdf",
        "first_bounce_numbers",
    ] {
        assert!(
            module
                .functions
                .iter()
                .any(|(_, g)| g.name.as_deref() == Some(f)),
            "{f} missing"
        );
    }
    // Without the hook, bvh.wgsl must not compile: the importer is meant to supply it.
    let alone = shaders::compose("lib/bvh.wgsl").unwrap();
    assert!(naga::front::wgsl::parse_str(&alone).is_err());
}

#[test]
fn cwbvh_node_matches_obvhs() {
    let source = shaders::compose("lib/bvh_bindings.wgsl").unwrap();
    let module = validate("lib/bvh_bindings.wgsl", &source);
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let (handle, ty) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("CwBvhNode"))
        .expect("CwBvhNode in bvh_bindings.wgsl");
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("CwBvhNode is not a struct");
    };
    assert_eq!(layouter[handle].size, *span);
    assert_eq!(*span as usize, size_of::<CwBvhNode>());
    let offset = |name: &str| {
        members
            .iter()
            .find(|m| m.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no member {name}"))
            .offset as usize
    };
    // e (3 bytes) and imask (1 byte) share one u32 word.
    assert_eq!(offset_of!(CwBvhNode, imask), offset_of!(CwBvhNode, e) + 3);
    let pairs = [
        ("p", offset_of!(CwBvhNode, p)),
        ("e_imask", offset_of!(CwBvhNode, e)),
        ("child_base_idx", offset_of!(CwBvhNode, child_base_idx)),
        (
            "primitive_base_idx",
            offset_of!(CwBvhNode, primitive_base_idx),
        ),
        ("child_meta", offset_of!(CwBvhNode, child_meta)),
        ("child_min_x", offset_of!(CwBvhNode, child_min_x)),
        ("child_max_x", offset_of!(CwBvhNode, child_max_x)),
        ("child_min_y", offset_of!(CwBvhNode, child_min_y)),
        ("child_max_y", offset_of!(CwBvhNode, child_max_y)),
        ("child_min_z", offset_of!(CwBvhNode, child_min_z)),
        ("child_max_z", offset_of!(CwBvhNode, child_max_z)),
    ];
    for (name, rust) in pairs {
        assert_eq!(offset(name), rust, "CwBvhNode.{name}");
    }
    assert_eq!(members.len(), pairs.len());
}
