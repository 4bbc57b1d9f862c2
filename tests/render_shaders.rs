//! Every WGSL shader parses and validates with naga (no GPU needed), and every file in `shaders/`
//! is one the renderer uses.
#![cfg(feature = "gui")]

use talas::render::shaders::Shader;
use wgpu::naga;

#[test]
fn every_shader_validates_with_naga() {
    for shader in Shader::ALL {
        let source = shader.source();
        let module = naga::front::wgsl::parse_str(&source)
            .unwrap_or_else(|e| panic!("{}: {}", shader.file_name(), e.emit_to_string(&source)));
        let mut validator = naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::default(),
        );
        if let Err(e) = validator.validate(&module) {
            panic!("{}: {}", shader.file_name(), e.emit_to_string(&source));
        }
        for entry in ["vs_main", "fs_main"] {
            assert!(
                module.entry_points.iter().any(|e| e.name == entry),
                "{} lacks the entry point {entry}",
                shader.file_name()
            );
        }
    }
}

#[test]
fn every_shader_file_is_used() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .expect("shaders/ exists")
        .filter_map(|e| e.ok().map(|e| e.file_name().to_string_lossy().into_owned()))
        .filter(|n| n.ends_with(".wgsl"))
        .collect();
    files.sort();
    for f in &files {
        assert!(
            f == "common.wgsl" || Shader::ALL.iter().any(|s| s.file_name() == f),
            "shaders/{f} is not used by the renderer"
        );
    }
    assert_eq!(files.len(), Shader::ALL.len() + 1);
}
