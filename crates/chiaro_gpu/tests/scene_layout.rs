//! The Rust records of the scene buffers, and the direct and indirect passes' uniforms, and the
//! WGSL structs that mirror them have the same size and the same field offsets, read from the
//! WGSL through naga's layouter; the scene's own WGSL modules validate.

use std::mem::{offset_of, size_of};

use chiaro_bvh::{BvhTriangle, GpuInstance, TlasNode};
use chiaro_gpu::gpu_scene::layout::*;
use chiaro_gpu::passes::direct::DirectParams;
use chiaro_gpu::passes::indirect::IndirectParams;
use chiaro_gpu::passes::restir::RestirParams;
use chiaro_gpu::shaders;

/// A WGSL struct: name, size, (member name, offset) in order.
type WgslStruct = (String, u32, Vec<(String, u32)>);

/// Every named struct of the composed module `name`.
fn wgsl_structs(name: &str) -> Vec<WgslStruct> {
    let source = shaders::compose(name).unwrap();
    let module = naga::front::wgsl::parse_str(&source).unwrap();
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    module
        .types
        .iter()
        .filter_map(|(handle, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, span } => Some((
                ty.name.clone()?,
                {
                    assert_eq!(layouter[handle].size, *span);
                    *span
                },
                members
                    .iter()
                    .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
                    .collect(),
            )),
            _ => None,
        })
        .collect()
}

macro_rules! check {
    ($structs:expr, $ty:ty, $wgsl:literal, [$($field:ident),* $(,)?]) => {{
        let (_, size, members) = $structs
            .iter()
            .find(|(n, _, _)| n == $wgsl)
            .unwrap_or_else(|| panic!("no WGSL struct {}", $wgsl));
        assert_eq!(*size as usize, size_of::<$ty>(), "size of {}", $wgsl);
        let names: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, [$(stringify!($field)),*], "members of {}", $wgsl);
        $(
            let offset = members.iter().find(|(n, _)| n == stringify!($field)).unwrap().1;
            assert_eq!(offset as usize, offset_of!($ty, $field), "{}.{}", $wgsl, stringify!($field));
        )*
    }};
}

#[test]
fn scene_records_match_their_wgsl_structs() {
    let s = wgsl_structs("lib/scene_bindings.wgsl");
    check!(
        s,
        GpuVertex,
        "GpuVertex",
        [position, u0, normal, v0, tangent, uv1, color]
    );
    check!(
        s,
        GpuMesh,
        "GpuMesh",
        [index_base, vertex_base, triangle_count, flags]
    );
    check!(
        s,
        GpuTextureSlot,
        "GpuTextureSlot",
        [texture, uv_set, sampler, pad, transform_m, transform_t]
    );
    check!(
        s,
        GpuMaterial,
        "GpuMaterial",
        [
            base_color,
            emission,
            alpha_cutoff,
            metallic,
            roughness,
            f0_dielectric,
            absorption,
            normal_scale,
            flags,
            specular,
            clearcoat,
            specular_color,
            clearcoat_roughness,
            sheen_color,
            sheen_roughness,
            transmission,
            ior,
            clearcoat_normal_scale,
            pad1,
            attenuation,
            pad2,
            base_color_texture,
            metallic_roughness_texture,
            normal_texture,
            emissive_texture,
            specular_texture,
            specular_color_texture,
            clearcoat_texture,
            clearcoat_roughness_texture,
            transmission_texture,
            sheen_color_texture,
            sheen_roughness_texture,
            clearcoat_normal_texture
        ]
    );
    check!(
        s,
        GpuTextureInfo,
        "GpuTextureInfo",
        [offset, width, height, srgb]
    );
    check!(
        s,
        GpuLight,
        "GpuLight",
        [
            position,
            kind,
            direction,
            range,
            intensity,
            cdf,
            inner,
            outer,
            pmf,
            directional_cdf
        ]
    );
    check!(
        s,
        GpuAreaLight,
        "GpuAreaLight",
        [instance, triangle, cdf, pmf]
    );
    check!(
        s,
        GpuInstanceExtra,
        "GpuInstanceExtra",
        [previous_object_to_world, area_first, mirrored, pad0, pad1]
    );
    check!(
        s,
        GpuSceneInfo,
        "GpuSceneInfo",
        [
            env_radiance,
            env_kind,
            env_width,
            env_height,
            env_cos_rotation,
            env_sin_rotation,
            light_count,
            area_count,
            env_pmf,
            instance_count,
            area_tree,
            punctual_tree,
            directional_share,
            area_leaves
        ]
    );
    check!(
        s,
        GpuLightTreeNode,
        "GpuLightTreeNode",
        [
            min, power, max, theta_o, axis, theta_e, first, second, parent, leaf
        ]
    );
    // The BVH records the scene bind group also carries.
    check!(s, TlasNode, "TlasNode", [min, child, max, kappa]);
    check!(
        s,
        BvhTriangle,
        "BvhTriangle",
        [v0, triangle, v1, pad0, v2, pad1]
    );
    check!(
        s,
        GpuInstance,
        "GpuInstance",
        [
            world_to_object,
            object_to_world,
            blas_root,
            mesh,
            material,
            mesh_magnitude
        ]
    );
}

/// The WGSL struct `wgsl` has `size` bytes and the named members at the given offsets (padding,
/// an array in Rust and single words in WGSL, is named by its first word).
fn check_fields(structs: &[WgslStruct], wgsl: &str, size: usize, fields: &[(&str, usize)]) {
    let (_, wgsl_size, members) = structs
        .iter()
        .find(|(n, _, _)| n == wgsl)
        .unwrap_or_else(|| panic!("no WGSL struct {wgsl}"));
    assert_eq!(*wgsl_size as usize, size, "size of {wgsl}");
    for &(name, rust) in fields {
        let offset = members.iter().find(|(n, _)| n == name).map(|m| m.1);
        assert_eq!(offset, Some(rust as u32), "{wgsl}.{name}");
    }
}

#[test]
fn pass_params_match_their_wgsl_structs() {
    for shader in ["indirect.wgsl", "restir_gi_initial.wgsl"] {
        check_fields(
            &wgsl_structs(shader),
            "IndirectParams",
            size_of::<IndirectParams>(),
            &[
                ("frame", offset_of!(IndirectParams, frame)),
                ("seed_lo", offset_of!(IndirectParams, seed_lo)),
                ("seed_hi", offset_of!(IndirectParams, seed_hi)),
                ("spp", offset_of!(IndirectParams, spp)),
                ("bounces", offset_of!(IndirectParams, bounces)),
                ("naive", offset_of!(IndirectParams, naive)),
                ("poison", offset_of!(IndirectParams, poison)),
                ("light_sampling", offset_of!(IndirectParams, light_sampling)),
                ("firefly_clamp", offset_of!(IndirectParams, firefly_clamp)),
                ("sampler", offset_of!(IndirectParams, sampler)),
                ("gi_history_cap", offset_of!(IndirectParams, gi_history_cap)),
                ("pad", offset_of!(IndirectParams, pad)),
            ],
        );
    }
    check_fields(
        &wgsl_structs("direct.wgsl"),
        "DirectParams",
        size_of::<DirectParams>(),
        &[
            ("frame", offset_of!(DirectParams, frame)),
            ("seed_lo", offset_of!(DirectParams, seed_lo)),
            ("seed_hi", offset_of!(DirectParams, seed_hi)),
            ("lights", offset_of!(DirectParams, lights)),
            ("light_sampling", offset_of!(DirectParams, light_sampling)),
            ("firefly_clamp", offset_of!(DirectParams, firefly_clamp)),
            ("restir", offset_of!(DirectParams, restir)),
            ("sampler", offset_of!(DirectParams, sampler)),
        ],
    );
    for shader in [
        "restir_temporal.wgsl",
        "restir_spatial.wgsl",
        "restir_gi_spatial.wgsl",
    ] {
        check_fields(
            &wgsl_structs(shader),
            "RestirParams",
            size_of::<RestirParams>(),
            &[
                ("frame", offset_of!(RestirParams, frame)),
                ("seed_lo", offset_of!(RestirParams, seed_lo)),
                ("seed_hi", offset_of!(RestirParams, seed_hi)),
                ("light_sampling", offset_of!(RestirParams, light_sampling)),
                ("candidates", offset_of!(RestirParams, candidates)),
                ("temporal", offset_of!(RestirParams, temporal)),
                ("history_cap", offset_of!(RestirParams, history_cap)),
                ("spatial_samples", offset_of!(RestirParams, spatial_samples)),
                ("spatial_radius", offset_of!(RestirParams, spatial_radius)),
                ("unbiased", offset_of!(RestirParams, unbiased)),
                (
                    "indirect_spatial_samples",
                    offset_of!(RestirParams, indirect_spatial_samples),
                ),
                ("firefly_clamp", offset_of!(RestirParams, firefly_clamp)),
            ],
        );
    }
}

#[test]
fn scene_modules_validate() {
    for name in [
        "lib/scene_bindings.wgsl",
        "lib/textures.wgsl",
        "lib/alpha.wgsl",
    ] {
        let source = shaders::compose(name).unwrap();
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{}", e.emit_to_string_with_path(&source, name)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string_with_path(&source, name)));
    }
}
