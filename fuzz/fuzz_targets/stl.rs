//! Fuzz the STL reader: any bytes give a mesh or an error, never a panic, and a mesh that was
//! read writes back (binary and ASCII) and reads again with the same triangles.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use talas::import::stl::{StlOptions, parse_stl, write_stl_ascii, write_stl_binary};

fuzz_target!(|data: &[u8]| {
    let name = Path::new("fuzz.stl");
    // The first byte picks the weld tolerance, so that the grid weld is exercised too.
    let weld_tol_mm = match data.first() {
        Some(b) if b % 3 == 0 => 0.0,
        Some(b) if b % 3 == 1 => 1e-3,
        _ => 1e-5,
    };
    let opts = StlOptions {
        weld_tol_mm,
        ..StlOptions::default()
    };
    let Ok(stl) = parse_stl(data, name, &opts) else {
        return;
    };
    assert!(stl.mesh.validate().is_ok());
    assert!(stl.mesh.triangles.len() <= stl.facet_count);
    let exact = StlOptions {
        weld_tol_mm: 0.0,
        ..StlOptions::default()
    };
    let mut bin = Vec::new();
    if write_stl_binary(&stl.mesh, &mut bin).is_ok() {
        let back = parse_stl(&bin, name, &exact).expect("own binary output reads back");
        assert_eq!(back.facet_count, stl.mesh.triangles.len());
    }
    let mut text = Vec::new();
    write_stl_ascii(&stl.mesh, &stl.name, &mut text).expect("valid mesh writes as ASCII");
    let back = parse_stl(&text, name, &exact).expect("own ASCII output reads back");
    assert_eq!(back.facet_count, stl.mesh.triangles.len());
});
