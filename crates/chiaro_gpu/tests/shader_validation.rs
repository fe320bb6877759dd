//! Every shader entry file composes and validates under naga (no GPU needed), and the
//! generated constants read back in WGSL as exactly the Rust values.

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
