//! Read a STEP part (default: the embedded default part), tessellate it to a chord tolerance and
//! print what came out: faces by kind, area, triangles, and whether the mesh is closed.
//!
//! `cargo run --example 01_tessellate_part -- [FILE.stp] [TOL_MM]`

use std::collections::BTreeMap;
use std::path::PathBuf;

use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
use talas::import::step::read_step;

fn main() {
    let mut args = std::env::args().skip(1);
    let file = args.next().map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/bicubic-hills.stp"),
        PathBuf::from,
    );
    let tol_mm: f64 = args.next().and_then(|t| t.parse().ok()).unwrap_or(0.01);
    let part = match read_step(&file) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let mesh = tessellate_part(&part, &TessellationOptions::with_chord_tol(tol_mm));
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    for f in &part.faces {
        *kinds.entry(f.surface.kind()).or_default() += 1;
    }
    println!("{}: {} faces {:?}", file.display(), part.faces.len(), kinds);
    println!(
        "chord tolerance {tol_mm} mm: {} triangles, area {:.4} mm²",
        mesh.mesh.triangles.len(),
        mesh.area_mm2()
    );
    let mut welded = mesh.mesh.clone();
    welded.weld(1e-9 * mesh.bbox().diagonal().max(1.0));
    if welded.is_closed() {
        println!("closed, volume {:.4} mm³", welded.signed_volume().abs());
    } else {
        println!("open ({} boundary edges)", welded.boundary_edges().len());
    }
    for d in part.diagnostics.iter().chain(&mesh.diagnostics) {
        println!("{d}");
    }
}
