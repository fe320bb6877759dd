//! The indirect pass's uniform has the same size and field offsets in Rust and in
//! `shaders/indirect.wgsl`, read from the composed WGSL through naga's layouter.

use std::mem::{offset_of, size_of};

use chiaro_gpu::passes::indirect::IndirectParams;
use chiaro_gpu::shaders;

#[test]
fn indirect_params_match_their_wgsl_struct() {
    let source = shaders::compose("indirect.wgsl").unwrap();
    let module = naga::front::wgsl::parse_str(&source).unwrap();
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let (handle, members) = module
        .types
        .iter()
        .find_map(|(handle, ty)| match &ty.inner {
            naga::TypeInner::Struct { members, .. }
                if ty.name.as_deref() == Some("IndirectParams") =>
            {
                Some((handle, members))
            }
            _ => None,
        })
        .expect("a WGSL struct IndirectParams");
    assert_eq!(layouter[handle].size as usize, size_of::<IndirectParams>());
    let offset = |name: &str| {
        members
            .iter()
            .find(|m| m.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("no member {name}"))
            .offset as usize
    };
    let rust = [
        ("frame", offset_of!(IndirectParams, frame)),
        ("seed_lo", offset_of!(IndirectParams, seed_lo)),
        ("seed_hi", offset_of!(IndirectParams, seed_hi)),
        ("spp", offset_of!(IndirectParams, spp)),
        ("bounces", offset_of!(IndirectParams, bounces)),
        ("naive", offset_of!(IndirectParams, naive)),
        ("poison", offset_of!(IndirectParams, poison)),
        ("light_sampling", offset_of!(IndirectParams, light_sampling)),
        ("firefly_clamp", offset_of!(IndirectParams, firefly_clamp)),
    ];
    for (name, at) in rust {
        assert_eq!(offset(name), at, "IndirectParams.{name}");
    }
    assert_eq!(offset("pad0"), offset_of!(IndirectParams, pad));
}
