//! The one reader of parts (`import::open`): the kind decided once by extension, one
//! tessellation policy, the exact faces kept, one BVH built once and shared.

mod common;

use std::path::Path;

use common::data;
use std::sync::Arc;

use talas::diagnostics::Progress;
use talas::import::{FileFormat, OpenOptions, Workpiece, open};

#[test]
fn a_step_part_keeps_its_faces_and_one_shared_bvh() {
    let w = open(
        &data("pocket-fillets.stp"),
        &OpenOptions::default(),
        &Progress::new(),
    )
    .expect("reads");
    assert_eq!(w.format, FileFormat::Step);
    let part = w.part.as_ref().expect("a B-rep");
    assert_eq!(w.surfaces.len(), part.faces.len());
    assert_eq!(w.face_of_triangle.len(), w.mesh.triangles.len());
    assert!(
        w.face_of_triangle
            .iter()
            .all(|&f| (f as usize) < part.faces.len())
    );
    // Built once: every caller gets the same hierarchy.
    let (a, b) = (w.bvh().unwrap(), w.bvh().unwrap());
    assert!(Arc::ptr_eq(&a, &b));
    // A clone made after the BVH exists shares it too.
    let c = w.clone();
    assert!(Arc::ptr_eq(&a, &c.bvh().unwrap()));
    // The size-relative default is never coarser than 0.01 mm: a finer tolerance only adds
    // triangles.
    let fine = open(
        &data("pocket-fillets.stp"),
        &OpenOptions {
            chord_tol_mm: Some(0.001),
        },
        &Progress::new(),
    )
    .unwrap();
    assert!(fine.mesh.triangles.len() > w.mesh.triangles.len());
}

#[test]
fn an_stl_part_is_a_mesh_without_faces() {
    let w: Workpiece = open(
        &data("pocket-fillets.stl"),
        &OpenOptions::default(),
        &Progress::new(),
    )
    .unwrap();
    assert_eq!(w.format, FileFormat::Stl);
    assert!(w.part.is_none() && w.surfaces.is_empty());
    assert!(w.face_of_triangle.iter().all(|&f| f == 0));
    assert!(w.surface(0).is_none());
}

#[test]
fn unknown_kinds_and_cancels_are_refused_naming_the_file() {
    let e = open(
        Path::new("part.iges"),
        &OpenOptions::default(),
        &Progress::new(),
    )
    .expect_err("unknown kind");
    assert!(
        e.to_string().contains("part.iges") && e.to_string().contains(".stp"),
        "{e}"
    );
    let cancelled = Progress::new();
    cancelled.cancel();
    let e = open(
        &data("pocket-fillets.stp"),
        &OpenOptions::default(),
        &cancelled,
    )
    .expect_err("cancelled");
    assert!(e.to_string().contains("cancelled"), "{e}");
}
