//! The workstation's document loader against the reference files: the STEP part tessellated by
//! the engine matches the Open CASCADE STL export of the same part (bounds and area), and bad
//! files give errors that name the file.
#![cfg(feature = "gui")]

use std::path::Path;

use talas::app::document::Document;
use talas::app::document_loader::{LoadError, load_part};
use talas::diagnostics::Progress;

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

#[test]
fn step_and_occt_stl_of_bicubic_hills_agree() {
    let step = load_part(&data("bicubic-hills.stp"), &Progress::new()).expect("STEP loads");
    let stl = load_part(&data("bicubic-hills.stl"), &Progress::new()).expect("STL loads");
    assert_eq!(step.format, "STEP");
    assert!(!step.faces.is_empty());
    assert_eq!(step.face_of_triangle().len(), step.mesh().triangles.len());
    // A STEP part draws the workpiece's own mesh (no copy); an STL part its crease-split copy,
    // with the workpiece's triangles in the same order.
    assert!(step.display_mesh.is_none());
    assert!(std::ptr::eq(step.mesh(), &step.workpiece.mesh));
    let split = stl.display_mesh.as_ref().expect("STL creases split");
    assert_eq!(split.triangles.len(), stl.workpiece.mesh.triangles.len());
    assert_eq!(stl.face_of_triangle().len(), split.triangles.len());
    assert!(
        step.face_of_triangle()
            .iter()
            .all(|&f| (f as usize) < step.faces.len())
    );
    let (a, b) = (Document::new(step, 1), Document::new(stl, 3));
    // Both are tessellations of the same surface: bounds within the chord tolerances, area
    // within 0.2 %.
    assert!(
        (a.bounds.min - b.bounds.min).length() < 0.05,
        "{:?} vs {:?}",
        a.bounds,
        b.bounds
    );
    assert!(
        (a.bounds.max - b.bounds.max).length() < 0.05,
        "{:?} vs {:?}",
        a.bounds,
        b.bounds
    );
    let rel = (a.area_mm2 - b.area_mm2).abs() / b.area_mm2;
    assert!(rel < 2e-3, "area {} vs {} mm²", a.area_mm2, b.area_mm2);
    // Per-face areas add up to the total.
    let sum: f64 = a.face_area_mm2.iter().sum();
    assert!((sum - a.area_mm2).abs() < 1e-6 * a.area_mm2);
}

#[test]
fn a_malformed_step_file_is_an_error_naming_it() {
    let path = std::env::temp_dir().join(format!("talas-app-loader-{}.stp", std::process::id()));
    std::fs::write(&path, "ISO-10303-21;\nHEADER;\nthis is not STEP\n").expect("temp file");
    let r = load_part(&path, &Progress::new());
    let _ = std::fs::remove_file(&path);
    match r {
        Err(LoadError::Import(e)) => assert_eq!(e.file, path),
        other => panic!("expected an import error, got {other:?}"),
    }
}

#[test]
fn the_embedded_default_part_is_the_asset_file() {
    let embedded = talas::app::document_loader::load_default_part(&Progress::new())
        .expect("default part loads");
    let asset = load_part(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/bicubic-hills.stp"),
        &Progress::new(),
    )
    .expect("asset loads");
    assert_eq!(embedded.mesh(), asset.mesh());
    assert_eq!(embedded.faces, asset.faces);
    assert_eq!(embedded.name, "bicubic-hills");
}
