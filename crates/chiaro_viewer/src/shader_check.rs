//! Test support: the viewer's shaders validated by naga, and the size naga gives a struct.

/// Validates the composed WGSL `source` (panicking on an error) and returns the size in bytes of
/// its struct `name`.
pub fn struct_size(source: &str, name: &str) -> usize {
    let module = naga::front::wgsl::parse_str(source).unwrap();
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .unwrap();
    module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .map(|(_, t)| t.inner.size(module.to_ctx()) as usize)
        .unwrap_or_else(|| panic!("no struct {name} in the shader"))
}
