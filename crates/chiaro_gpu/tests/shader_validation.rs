//! Every shader entry file composes and validates under naga (no GPU needed), binds no uniform
//! buffer and no more storage buffers than chiaro asks the device for, and the generated
//! constants read back in WGSL as exactly the Rust values.

use chiaro_gpu::shaders::{self, SharedConstant};

/// Parses and validates composed WGSL, or explains why not.
fn validate(name: &str, source: &str) -> Result<naga::Module, String> {
    let module = naga::front::wgsl::parse_str(source)
        .map_err(|e| format!("{name}: {}", e.emit_to_string_with_path(source, name)))?;
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
    .validate(&module)
    .map_err(|e| format!("{name}: {}", e.emit_to_string_with_path(source, name)))?;
    Ok(module)
}

#[test]
fn every_entry_file_composes_and_validates() {
    let mut failures = Vec::new();
    let mut count = 0;
    for name in shaders::entry_files() {
        count += 1;
        match shaders::compose(name) {
            Ok(source) => {
                if let Err(e) = validate(name, &source) {
                    failures.push(e);
                }
            }
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    eprintln!("{count} entry files checked");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Parameters live in read-only storage buffers, never uniform buffers (lavapipe recompiles a
/// shader at every dispatch whose branches read uniforms: `chiaro_gpu::passes::params`), and
/// the busiest shader binds exactly the storage buffers the device is asked for.
#[test]
fn no_shader_binds_a_uniform_buffer_and_storage_buffers_fit_the_limit() {
    let mut most = (0, "");
    for name in shaders::entry_files() {
        let source = shaders::compose(name).unwrap();
        let module = validate(name, &source).unwrap();
        let mut storage = 0;
        for (_, global) in module.global_variables.iter() {
            assert_ne!(
                global.space,
                naga::AddressSpace::Uniform,
                "{name} declares {:?} as a uniform buffer",
                global.name
            );
            if matches!(global.space, naga::AddressSpace::Storage { .. }) {
                storage += 1;
            }
        }
        if storage > most.0 {
            most = (storage, name);
        }
    }
    eprintln!("most storage buffers: {} in {}", most.0, most.1);
    assert_eq!(
        most.0,
        chiaro_gpu::context::STORAGE_BUFFERS_PER_STAGE,
        "{}",
        most.1
    );
}

#[test]
fn generated_constants_read_back_exactly() {
    let source = shaders::generated_constants();
    let module = validate(shaders::GENERATED_MODULE, &source).unwrap();
    let mut checked = 0;
    for constant in shaders::shared_constants() {
        let name = match constant {
            SharedConstant::F32(name, _) | SharedConstant::U32(name, _) => name,
        };
        let (_, c) = module
            .constants
            .iter()
            .find(|(_, c)| c.name.as_deref() == Some(name))
            .unwrap_or_else(|| panic!("{name} missing from the generated module"));
        let naga::Expression::Literal(literal) = module.global_expressions[c.init] else {
            panic!("{name} is not a literal");
        };
        match (constant, literal) {
            (SharedConstant::F32(_, v), naga::Literal::F32(w)) => {
                assert_eq!(v.to_bits(), w.to_bits(), "{name}")
            }
            (SharedConstant::U32(_, v), naga::Literal::U32(w)) => assert_eq!(v, w, "{name}"),
            (c, l) => panic!("{c:?} read back as {l:?}"),
        }
        checked += 1;
    }
    assert!(checked >= 20, "only {checked} constants");
}
