//! Raster finishing (and Z-level roughing) on meshes, checked by an independent computation:
//! the remaining height along the surface normal to the swept ball envelope and the gouge, on
//! dense samples of the mesh (`strategies::raster_check`, which does not use the drop-cutter).

use std::path::Path;

use talas::geometry::DVec2;
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::import::stl::{StlOptions, read_stl};
use talas::strategies::raster::{Boundary, RasterOptions, RasterPattern, raster};
use talas::strategies::raster_check::{RemainingOptions, ball_remaining_height};
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::parse_tool_spec;

fn load(name: &str) -> (TriMesh, MeshBvh) {
    let stl = read_stl(
        Path::new(&format!("tests/data/{name}")),
        &StlOptions::default(),
    )
    .unwrap();
    let bvh = MeshBvh::new(&stl.mesh).unwrap();
    (stl.mesh, bvh)
}

fn tool(spec: &str) -> ToolRecord {
    ToolRecord {
        spec: spec.into(),
        cutter: parse_tool_spec(spec).unwrap(),
    }
}

/// Plan, check, and return (p50, p99, fraction ≤ h + tol, max gouge).
fn plan_and_check(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    opts: &RasterOptions,
    region: Option<(DVec2, DVec2)>,
    check_slope: f64,
) -> (f64, f64, f64, f64) {
    let t0 = std::time::Instant::now();
    let plan = raster(mesh, bvh, &tool("ball:d=6"), opts).unwrap();
    eprintln!("raster planned in {:?}", t0.elapsed());
    for d in &plan.diagnostics {
        eprintln!("{}", d.message);
    }
    let tp = &plan.toolpath;
    tp.validate("<raster>").unwrap();
    assert!(tp.poses.iter().any(|p| p.kind == MoveKind::Cut));
    assert!(
        tp.poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .all(|p| p.cc.is_some())
    );
    let check = RemainingOptions {
        sample_spacing_mm: 0.6,
        max_slope_rad: check_slope,
        max_height_mm: 0.5,
        march_step_mm: 0.004,
        region,
    };
    let t0 = std::time::Instant::now();
    let rep = ball_remaining_height(mesh, tp, &check).unwrap();
    eprintln!("checked in {:?}", t0.elapsed());
    let h = opts.scallop_mm + opts.chord_tol_mm;
    let within = rep.fraction_within(h);
    eprintln!(
        "passes {}, poses {}, samples {}, remaining p50 {:.4} p90 {:.4} p99 {:.4} max {:.4} mm, ≤ h+tol {:.4}, uncovered {}, max gouge {:.2e} mm at {:?}, predicted max {:.4}",
        plan.passes,
        tp.poses.len(),
        rep.samples(),
        rep.quantile(0.5),
        rep.quantile(0.9),
        rep.quantile(0.99),
        rep.quantile(1.0),
        within,
        rep.uncovered,
        rep.max_gouge_mm,
        rep.max_gouge_at,
        plan.max_predicted_scallop_mm
    );
    for (p, v) in rep.worst.iter().take(12) {
        eprintln!("  worst {v:.4} at {p:.3}");
    }
    assert!(rep.samples() > 5000, "{} samples", rep.samples());
    (
        rep.quantile(0.5),
        rep.quantile(0.99),
        within,
        rep.max_gouge_mm,
    )
}

#[test]
fn raster_ball_on_bicubic_hills_holds_the_scallop_without_gouge() {
    let (mesh, bvh) = load("bicubic-hills.stl");
    let poly = vec![
        DVec2::new(30.0, 20.0),
        DVec2::new(110.0, 20.0),
        DVec2::new(110.0, 80.0),
        DVec2::new(30.0, 80.0),
    ];
    let opts = RasterOptions {
        angle_rad: 30f64.to_radians(),
        pattern: RasterPattern::ZigZag,
        scallop_mm: 0.05,
        chord_tol_mm: 0.01,
        boundary: Boundary::Polygon(poly),
        ..RasterOptions::default()
    };
    let region = Some((DVec2::new(31.0, 21.0), DVec2::new(109.0, 79.0)));
    let (_, _, within, gouge) = plan_and_check(&mesh, &bvh, &opts, region, opts.max_slope_rad);
    assert!(within >= 0.99, "only {within} of samples within h + tol");
    assert!(gouge <= 1e-3, "gouge {gouge} mm");
}

#[test]
fn raster_ball_on_pocket_fillets_holds_the_scallop_without_gouge() {
    let (mesh, bvh) = load("pocket-fillets.stl");
    let opts = RasterOptions {
        angle_rad: 0.0,
        pattern: RasterPattern::ZigZag,
        scallop_mm: 0.05,
        chord_tol_mm: 0.01,
        boundary: Boundary::Silhouette,
        ..RasterOptions::default()
    };
    let (_, _, within, gouge) = plan_and_check(&mesh, &bvh, &opts, None, 45f64.to_radians());
    assert!(within >= 0.99, "only {within} of samples within h + tol");
    assert!(gouge <= 1e-3, "gouge {gouge} mm");
}
