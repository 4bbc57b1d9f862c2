//! Steep-and-shallow finishing with a ball end mill, judged by the independent remaining-height
//! check (`checks::oracle::raster`, which does not use the drop-cutter nor the push-cutter): the share of
//! the surface up to 85° steep left within h + chord tolerance, and no gouge.
//!
//! `cargo test --no-default-features --test steep_shallow -- --nocapture` prints the figures.

use std::path::Path;

use talas::checks::oracle::raster::{RemainingOptions, ball_remaining_height};
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::import::stl::{StlOptions, read_stl};
use talas::strategies::raster::RasterOptions;
use talas::strategies::steep_shallow::{SteepShallowOptions, SteepShallowPlan, steep_shallow};
use talas::strategies::waterline::WaterlineOptions;
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::parse_tool_spec;

fn load(name: &str) -> (TriMesh, MeshBvh) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let mesh = read_stl(&path, &StlOptions::default()).unwrap().mesh;
    let bvh = MeshBvh::new(&mesh).unwrap();
    (mesh, bvh)
}

const H_MM: f64 = 0.05;
const TOL_MM: f64 = 0.01;

fn pocket_plan() -> (TriMesh, SteepShallowPlan) {
    let (mesh, bvh) = load("pocket-fillets.stl");
    let (h, tol) = (H_MM, TOL_MM);
    let tool = ToolRecord {
        spec: "ball:d=6".into(),
        cutter: parse_tool_spec("ball:d=6").unwrap(),
    };
    let opts = SteepShallowOptions {
        raster: RasterOptions {
            scallop_mm: h,
            chord_tol_mm: tol,
            ..RasterOptions::default()
        },
        waterline: WaterlineOptions {
            scallop_mm: h,
            chord_tol_mm: tol,
            ..WaterlineOptions::default()
        },
        ..SteepShallowOptions::default()
    };
    let plan = steep_shallow(&mesh, &bvh, &tool, &opts).unwrap();
    (mesh, plan)
}

#[test]
fn steep_shallow_on_pocket_fillets_holds_the_scallop_on_walls_and_floors() {
    let (mesh, plan) = pocket_plan();
    let (h, tol) = (H_MM, TOL_MM);
    plan.toolpath.validate("<steep-shallow>").unwrap();
    assert!(plan.raster_passes > 0 && plan.waterline_runs > 0 && plan.levels > 1);
    assert!(plan.toolpath.poses.iter().any(|p| p.kind == MoveKind::Cut));
    let check = RemainingOptions {
        sample_spacing_mm: 0.6,
        max_slope_rad: 85f64.to_radians(),
        max_height_mm: 0.5,
        march_step_mm: 0.004,
        region: None,
    };
    let rep = ball_remaining_height(&mesh, &plan.toolpath, &check).unwrap();
    let within = rep.fraction_within(h + tol);
    eprintln!(
        "raster passes {}, waterline runs {} on {} levels, samples {}, within h+tol {:.4}, p99 {:.4} mm, uncovered {}, gouge {:.2e} mm, reported out of reach {:.1} mm²",
        plan.raster_passes,
        plan.waterline_runs,
        plan.levels,
        rep.samples(),
        within,
        rep.quantile(0.99),
        rep.uncovered,
        rep.max_gouge_mm,
        plan.unreachable_area_mm2
    );
    for d in &plan.diagnostics {
        eprintln!("  {}", d.message);
    }
    for (p, v) in rep.worst.iter().take(8) {
        eprintln!("  worst {v:.4} at {p:.3}");
    }
    assert!(rep.samples() > 5000);
    // Measured 99.78 % (p99 0.048 mm): the waterline adds a level where the fillets' steep
    // band ends between two levels (without it 98.65 %, up to 0.17 mm on the fillets at z ≈ 17).
    assert!(
        within >= 0.99,
        "only {within} of the surface within h + tol"
    );
    assert!(rep.max_gouge_mm <= 1e-3, "gouge {} mm", rep.max_gouge_mm);
}

/// The same path cut in the stock simulation (the default stock, the part's box + 2 mm, on a
/// 0.2 mm Z-dexel grid): the share of the cut stock's top over the part (its outline less
/// 0.5 mm) left within h + chord tolerance + 0.01 mm (the grid's step along the moves), and no
/// gouge. Material left on a wall shows at the rays beside it. Slow in the debug build (about a
/// minute): `cargo test --no-default-features --test steep_shallow -- --ignored --nocapture`
#[test]
#[ignore = "slow in the debug build: planning and a 220 000-ray simulation"]
fn steep_shallow_on_pocket_fillets_holds_the_scallop_in_the_stock_simulation() {
    use talas::diagnostics::Progress;
    use talas::project::Stock;
    use talas::project::simulate::{SimulationSettings, simulate_toolpath};
    let (mesh, plan) = pocket_plan();
    let settings = SimulationSettings {
        resolution_mm: Some(0.2),
        ..SimulationSettings::default()
    };
    let cutter = plan.toolpath.tool.cutter.clone();
    let sim = simulate_toolpath(
        &Stock::None,
        &mesh,
        &plan.toolpath,
        &cutter,
        &settings,
        &Progress::new(),
    )
    .unwrap();
    let b = mesh.bbox();
    let mut left: Vec<(f64, glam::DVec3)> = sim
        .stock_mesh
        .positions
        .iter()
        .zip(&sim.deviation_mm)
        .filter(|(p, _)| {
            p.x > b.min.x + 0.5 && p.x < b.max.x - 0.5 && p.y > b.min.y + 0.5 && p.y < b.max.y - 0.5
        })
        .map(|(p, d)| (*d, *p))
        .collect();
    left.sort_by(|a, b| b.0.total_cmp(&a.0));
    let limit = H_MM + TOL_MM + 0.01;
    let over = left.iter().filter(|(d, _)| *d > limit).count();
    let within = 1.0 - over as f64 / left.len() as f64;
    eprintln!(
        "stock simulation: {} top points over the part, within {limit} mm {within:.4}, p99 {:.4} mm, gouge {:.4} mm",
        left.len(),
        left[left.len() / 100].0,
        sim.max_gouge_mm
    );
    for (d, p) in left.iter().take(8) {
        eprintln!("  worst {d:.4} at {p:.3}");
    }
    assert!(left.len() > 100_000);
    assert!(within >= 0.99, "only {within} of the top within {limit} mm");
    assert!(sim.max_gouge_mm <= 0.01, "gouge {} mm", sim.max_gouge_mm);
}
