//! Raster finishing (and Z-level roughing) on meshes, checked by an independent computation:
//! the remaining height along the surface normal to the swept ball envelope and the gouge, on
//! dense samples of the mesh (`checks::oracle::raster`, which does not use the drop-cutter).

mod common;

use std::path::Path;

use talas::checks::oracle::raster::{RemainingOptions, ball_remaining_height};
use talas::geometry::DVec2;
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::import::stl::{StlOptions, read_stl};
use talas::strategies::raster::{Boundary, RasterOptions, RasterPattern, raster};
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::parse_tool_spec;

fn load(name: &str) -> (TriMesh, MeshBvh) {
    let stl = read_stl(&common::data(name), &StlOptions::default()).unwrap();
    let bvh = MeshBvh::new(&stl.mesh).unwrap();
    (stl.mesh, bvh)
}

fn tool(spec: &str) -> ToolRecord {
    ToolRecord {
        spec: spec.into(),
        cutter: parse_tool_spec(spec).unwrap(),
    }
}

/// What the planner predicted and the independent check measured.
struct Checked {
    /// The planner's largest predicted scallop, mm.
    predicted: f64,
    /// Remaining height p99 and max over the checked samples, mm.
    p99: f64,
    max: f64,
    /// Fraction of samples within h + chord tolerance.
    within: f64,
    /// Largest gouge, mm.
    gouge: f64,
    /// The samples with the largest remaining height (largest first), mm.
    worst: Vec<(talas::geometry::DVec3, f64)>,
    /// The planner's notes.
    notes: Vec<String>,
    /// X of every cut pose, mm.
    cut_x: Vec<f64>,
}

/// Plan, check, and return what was predicted and measured.
fn plan_and_check(
    mesh: &TriMesh,
    bvh: &MeshBvh,
    opts: &RasterOptions,
    region: Option<(DVec2, DVec2)>,
    check_slope: f64,
) -> Checked {
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
        "passes {}, poses {}, cut {:.0} mm, samples {}, remaining p50 {:.4} p90 {:.4} p99 {:.4} max {:.4} mm, ≤ h+tol {:.4}, uncovered {}, max gouge {:.2e} mm at {:?}, predicted max {:.4}",
        plan.passes,
        tp.poses.len(),
        tp.summary.cut_length_mm,
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
    Checked {
        predicted: plan.max_predicted_scallop_mm,
        p99: rep.quantile(0.99),
        max: rep.quantile(1.0),
        within,
        gouge: rep.max_gouge_mm,
        worst: rep.worst.clone(),
        notes: plan.diagnostics.iter().map(|d| d.message.clone()).collect(),
        cut_x: tp
            .poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .map(|p| p.tip.x)
            .collect(),
    }
}

/// The planner's prediction against the request and against the independent check: the step
/// holds the scallop (prediction ≤ h, and not far below it, or the step is wastefully small),
/// and the prediction is honest (the measured p99 is not above it by more than the chord
/// tolerance, with which the followed path may stand above the true CL).
fn assert_prediction(c: &Checked, opts: &RasterOptions) {
    let h = opts.scallop_mm;
    assert!(
        c.predicted <= h + 1e-9,
        "predicted max scallop {} mm for a request of {h} mm",
        c.predicted
    );
    assert!(c.predicted >= 0.8 * h, "predicted {} mm", c.predicted);
    assert!(
        c.p99 <= c.predicted + opts.chord_tol_mm,
        "measured p99 {} mm above the prediction {} mm",
        c.p99,
        c.predicted
    );
    assert!(
        c.within >= 0.99,
        "only {} of samples within h + tol",
        c.within
    );
    assert!(c.gouge <= 1e-3, "gouge {} mm", c.gouge);
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
    let c = plan_and_check(&mesh, &bvh, &opts, region, opts.max_slope_rad);
    assert_prediction(&c, &opts);
    // Away from the region's edge every sample is within h + tol.
    assert!(
        c.max <= opts.scallop_mm + opts.chord_tol_mm,
        "max {}",
        c.max
    );
}

/// The whole of bicubic-hills with passes along +X (the command line's default): the surface
/// slopes along the passes almost everywhere, which the old cusp measure (the tool's profile at
/// the grid point, hanging R·(sec θ − 1) above the surface on a slope θ along the pass) took for
/// scallop: 0.121 mm predicted for 0.05 mm requested, and a step shrunk to 0.3 mm. With the
/// contact boundary (the default) the passes run on past the part's edges until the contact
/// point reaches the edge, so every sample, up to the edges x = 0 and 160 mm where the surface
/// falls away under the tool, is within h + tol (stopping with the axis over the edge left up
/// to 0.136 mm there), and the tool never stands more than its radius beyond the outline.
#[test]
fn raster_ball_on_whole_bicubic_hills_holds_the_scallop_up_to_the_edges() {
    let (mesh, bvh) = load("bicubic-hills.stl");
    let opts = RasterOptions {
        scallop_mm: 0.05,
        chord_tol_mm: 0.01,
        ..RasterOptions::default()
    };
    assert!(opts.contact_boundary);
    let c = plan_and_check(&mesh, &bvh, &opts, None, opts.max_slope_rad);
    assert_prediction(&c, &opts);
    let limit = opts.scallop_mm + opts.chord_tol_mm;
    assert!(c.max <= limit, "{} mm left at {:?}", c.max, c.worst.first());
    // Final chords are checked against the true CL every quarter millimetre (a 3 mm chord
    // merged by thinning dipped 1.3 µm under it).
    assert!(c.gouge <= 5e-4, "gouge {} mm", c.gouge);
    // The passes reach past x = 160 (the surface falls toward it), but by less than R.
    let beyond = c.cut_x.iter().fold(f64::NEG_INFINITY, |m, x| m.max(*x)) - 160.0;
    assert!(beyond > 0.3 && beyond < 3.0, "{beyond} mm past the edge");
    // The planner no longer reports material left at the ends of passes (82 points up to
    // 0.116 mm before), but at a corner or two.
    let at_ends: usize = c
        .notes
        .iter()
        .filter(|n| n.contains("ends of passes"))
        .filter_map(|n| n.split_whitespace().next()?.parse::<usize>().ok())
        .sum();
    assert!(at_ends < 10, "{:?}", c.notes);
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
    let c = plan_and_check(&mesh, &bvh, &opts, None, 45f64.to_radians());
    assert_prediction(&c, &opts);
}

/// Z-level roughing of pocket-fillets from a box stock with a flat end mill: no cut pose (nor
/// any point of a cut move) brings the tool closer to the part than the stock to leave, judged
/// by the drop-cutter with the real tool; on the flat top and pocket floor the deepest level
/// lies within one step-down above the stock to leave (the staircase).
#[test]
fn zlevel_rough_pocket_fillets_leaves_the_stock_and_never_cuts_the_part() {
    use talas::geometry::DVec3;
    use talas::geometry::stock::Stock;
    use talas::strategies::zlevel::{ZlevelOptions, zlevel_rough};
    use talas::tools::dropcutter::drop_cutter;
    let (mesh, bvh) = load("pocket-fillets.stl");
    let t = tool("flat:d=10");
    let (sd, dr, da) = (3.0, 0.5, 0.3);
    let opts = ZlevelOptions {
        stock: Stock::Box {
            min_mm: [-5.0, -5.0, 0.0],
            max_mm: [105.0, 85.0, 35.0],
        },
        step_down_mm: sd,
        step_over_mm: 4.0,
        stock_to_leave_radial_mm: dr,
        stock_to_leave_axial_mm: da,
        tolerance_mm: 0.5,
        ..ZlevelOptions::default()
    };
    let plan = zlevel_rough(&mesh, &bvh, &t, &opts).unwrap();
    let tp = &plan.toolpath;
    tp.validate("<zlevel>").unwrap();
    assert!(plan.contours > 10, "{} contours", plan.contours);
    // Every point of every fed move, every 0.5 mm.
    let mut pts: Vec<DVec3> = Vec::new();
    for w in tp.poses.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b.kind == MoveKind::Rapid {
            continue;
        }
        let n = (a.tip.distance(b.tip) / 0.5).ceil().max(1.0) as usize;
        for i in 0..=n {
            pts.push(a.tip.lerp(b.tip, i as f64 / n as f64));
        }
    }
    let xy: Vec<DVec2> = pts.iter().map(|p| p.truncate()).collect();
    let cl = drop_cutter(&bvh, &mesh, &t.cutter, &xy);
    let mut worst = f64::INFINITY;
    for (p, c) in pts.iter().zip(&cl) {
        if let Some(c) = c {
            worst = worst.min(p.z - (c.z + da));
        }
    }
    eprintln!(
        "levels {:?}, contours {}, poses {}, closest approach (tip − CL − δa) {worst:.4} mm",
        plan.levels,
        plan.contours,
        tp.poses.len()
    );
    let tol = 0.05;
    assert!(
        worst >= -tol,
        "a cut comes {worst} mm inside the stock to leave"
    );
    // Staircase on the flat top (z = 30) and the pocket floor (z = 15).
    let lowest_in = |lo: DVec2, hi: DVec2| {
        tp.poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .filter(|p| p.tip.x >= lo.x && p.tip.y >= lo.y && p.tip.x <= hi.x && p.tip.y <= hi.y)
            .map(|p| p.tip.z)
            .fold(f64::INFINITY, f64::min)
    };
    let top = lowest_in(DVec2::new(10.0, 3.0), DVec2::new(90.0, 12.0));
    let floor = lowest_in(DVec2::new(35.0, 30.0), DVec2::new(65.0, 50.0));
    eprintln!("lowest cut over the top {top:.3} mm, over the pocket floor {floor:.3} mm");
    assert!(top >= 30.0 + da - tol && top <= 30.0 + da + sd, "top {top}");
    assert!(
        floor >= 15.0 + da - tol && floor <= 15.0 + da + sd,
        "floor {floor}"
    );
}

/// Points of every fed move of `tp` every `step` mm, with the index of the move's end pose.
fn fed_points(tp: &talas::toolpath::Toolpath, step: f64) -> Vec<(usize, talas::geometry::DVec3)> {
    let mut pts = Vec::new();
    for (k, w) in tp.poses.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        if b.kind == MoveKind::Rapid {
            continue;
        }
        let n = (a.tip.distance(b.tip) / step).ceil().max(1.0) as usize;
        for i in 0..=n {
            pts.push((k + 1, a.tip.lerp(b.tip, i as f64 / n as f64)));
        }
    }
    pts
}

/// Z-level roughing with flat-area detection on pocket-fillets (top z = 30, pocket floor
/// z = 15, both flat): with the stock top at 35 and a 4 mm step-down the levels are 31, 27,
/// 23, 19 (then 15 lies below the floor plus the stock), so both flat areas lie between two
/// levels. Judged independently from the path alone (a flat end mill removes, over every
/// point within its radius of the axis, everything above its tip): every floor sample keeps
/// the stock to leave (not the 4 mm step), the part is never cut (drop-cutter with the real
/// tool), and every plunge ends over material already cleared below it across the whole
/// footprint (no full-width plunge into material). Without the option the floor keeps a
/// whole step.
#[test]
fn zlevel_rough_detects_flat_floors_between_levels() {
    use talas::geometry::DVec3;
    use talas::geometry::stock::Stock;
    use talas::strategies::zlevel::{ZlevelOptions, flat_areas, zlevel_rough};
    use talas::tools::dropcutter::drop_cutter;
    let (mesh, bvh) = load("pocket-fillets.stl");
    // The reference heights of the flat areas, from the mesh.
    let flats: Vec<f64> = flat_areas(&mesh)
        .iter()
        .filter(|(_, a)| *a > 100.0)
        .map(|(z, _)| *z)
        .collect();
    assert!(
        flats.iter().any(|z| (z - 15.0).abs() < 1e-6)
            && flats.iter().any(|z| (z - 30.0).abs() < 1e-6),
        "{flats:?}"
    );
    let t = tool("flat:d=10");
    let big = 5.0;
    let (sd, dr, da) = (4.0, 0.3, 0.3);
    let opts = ZlevelOptions {
        stock: Stock::Box {
            min_mm: [-5.0, -5.0, 0.0],
            max_mm: [105.0, 85.0, 35.0],
        },
        step_down_mm: sd,
        step_over_mm: 4.0,
        stock_to_leave_radial_mm: dr,
        stock_to_leave_axial_mm: da,
        tolerance_mm: 0.5,
        ..ZlevelOptions::default()
    };
    // Floor samples: a 2 mm grid over the pocket floor's box (x 25–75, y 25–55), kept where
    // the part's top surface is the floor itself (z = 15) within 1.5 mm around (the corners of
    // the pocket are rounded).
    let on_floor = |q: DVec2| {
        bvh.ray_cast(q.extend(50.0), DVec3::NEG_Z, 100.0)
            .is_some_and(|h| (h.point.z - 15.0).abs() < 1e-6)
    };
    let floor: Vec<DVec2> = (0..=25)
        .flat_map(|i| {
            (0..=15).map(move |j| DVec2::new(25.0 + 2.0 * f64::from(i), 25.0 + 2.0 * f64::from(j)))
        })
        .filter(|q| {
            [(1.5, 0.0), (-1.5, 0.0), (0.0, 1.5), (0.0, -1.5), (0.0, 0.0)]
                .iter()
                .all(|(dx, dy)| on_floor(*q + DVec2::new(*dx, *dy)))
        })
        .collect();
    assert!(floor.len() > 250, "{} floor samples", floor.len());
    let left_on_floor = |tp: &talas::toolpath::Toolpath| -> (f64, f64) {
        let pts = fed_points(tp, 0.25);
        let lows: Vec<f64> = floor
            .iter()
            .map(|q| {
                pts.iter()
                    .filter(|(_, p)| p.truncate().distance(*q) <= big)
                    .map(|(_, p)| p.z)
                    .fold(35.0, f64::min)
                    - 15.0
            })
            .collect();
        (
            lows.iter().copied().fold(f64::INFINITY, f64::min),
            lows.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        )
    };

    let plan = zlevel_rough(&mesh, &bvh, &t, &opts).unwrap();
    let tp = &plan.toolpath;
    tp.validate("<zlevel>").unwrap();
    let (lo, hi) = left_on_floor(tp);
    eprintln!(
        "levels {:?}, {:?}; left on {} floor samples {lo:.4}..{hi:.4} mm, cut {:.0} mm",
        plan.levels,
        plan.diagnostics
            .iter()
            .map(|d| &d.message)
            .collect::<Vec<_>>(),
        floor.len(),
        tp.summary.cut_length_mm
    );
    assert!(
        (lo - da).abs() <= 1e-6 && (hi - da).abs() <= 1e-6,
        "left on the floor {lo}..{hi} mm, want {da}"
    );
    // Never closer to the part than the stock to leave.
    let pts = fed_points(tp, 0.5);
    let xy: Vec<DVec2> = pts.iter().map(|(_, p)| p.truncate()).collect();
    let cl = drop_cutter(&bvh, &mesh, &t.cutter, &xy);
    let worst = pts
        .iter()
        .zip(&cl)
        .filter_map(|((_, p), c)| c.map(|c| p.z - (c.z + da.max(dr))))
        .fold(f64::INFINITY, f64::min);
    assert!(
        worst >= -0.05,
        "a cut comes {worst} mm inside the stock to leave"
    );
    // Every plunge ends where the material under the whole footprint was already cleared
    // below the plunge's end (or above the stock).
    let ring: Vec<DVec2> = (0..12)
        .map(|i| {
            let a = f64::from(i) * std::f64::consts::TAU / 12.0;
            DVec2::new(a.cos(), a.sin()) * 0.95 * big
        })
        .chain(std::iter::once(DVec2::ZERO))
        .collect();
    let mut plunges = 0;
    for (k, p) in tp.poses.iter().enumerate() {
        if p.kind != MoveKind::Plunge || p.tip.z >= 35.0 {
            continue;
        }
        plunges += 1;
        for off in &ring {
            let q = p.tip.truncate() + *off;
            let cleared = pts
                .iter()
                .filter(|(i, c)| *i < k && c.truncate().distance(q) <= big)
                .map(|(_, c)| c.z)
                .fold(35.0, f64::min);
            assert!(
                cleared <= p.tip.z + 1e-6,
                "plunge {k} to z {} over {q} where material stands up to {cleared}",
                p.tip.z
            );
        }
    }
    assert!(plunges > 0);

    // Without flat detection the floor keeps a whole step (19 − 15 mm).
    let plain = zlevel_rough(
        &mesh,
        &bvh,
        &t,
        &ZlevelOptions {
            detect_flats: false,
            ..opts.clone()
        },
    )
    .unwrap();
    let (lo0, _) = left_on_floor(&plain.toolpath);
    eprintln!(
        "without flat levels: {:?}, left on the floor ≥ {lo0:.3} mm",
        plain.levels
    );
    assert!(lo0 > sd - 0.5, "{lo0}");
}

/// The CLI entry point: both mesh strategies from an STL, and clear errors for bad names.
#[test]
fn plan_mesh_runs_both_strategies_and_rejects_bad_input() {
    use talas::cli::plan_mesh::{MeshPlanOptions, plan_mesh, plan_mesh_noted};
    let file = Path::new("tests/data/pocket-fillets.stl");
    let opts = MeshPlanOptions {
        scallop_mm: 0.3,
        tolerance_mm: 0.05,
        stock: "box:-2,-2,0,102,82,32".into(),
        step_down_mm: 5.0,
        ..MeshPlanOptions::default()
    };
    let raster = plan_mesh(file, "raster", "ball:d=10", &opts).unwrap();
    assert!(raster.summary.cut_length_mm > 1000.0);
    // The raster never goes below the pocket floor's ball-tip height (15 mm).
    assert!(
        raster.summary.bbox_min.z >= 15.0 - 1e-6,
        "{}",
        raster.summary.bbox_min.z
    );
    let opts = MeshPlanOptions {
        tolerance_mm: 0.5,
        ..opts
    };
    let (rough, notes) = plan_mesh_noted(file, "zlevel-rough", "flat:d=10", &opts).unwrap();
    assert!(rough.summary.cut_length_mm > 500.0);
    // Levels 27, 22, 17, 12, ...: the top (30) and the floor (15) get their own levels.
    assert!(
        notes.iter().any(|d| d
            .message
            .contains("top of the part: level added at z = 30.300")),
        "{notes:?}"
    );
    assert!(
        notes.iter().any(|d| d.message.contains("z = 15.300")),
        "{notes:?}"
    );
    assert!(rough.poses.iter().any(|p| p.kind == MoveKind::Plunge));
    let e = plan_mesh(file, "spiral", "ball:d=6", &opts).unwrap_err();
    assert!(e.to_string().contains("--strategy"), "{e}");
    let e = plan_mesh(file, "raster", "ball:d=-1", &opts).unwrap_err();
    assert!(e.to_string().contains("--tool"), "{e}");
    let bad_stock = MeshPlanOptions {
        stock: "sphere".into(),
        ..opts
    };
    let e = plan_mesh(file, "zlevel-rough", "flat:d=10", &bad_stock).unwrap_err();
    assert!(e.to_string().contains("--stock"), "{e}");
}

/// A closed axis-aligned box mesh from `lo` to `hi` (12 triangles, outward).
fn box_mesh(lo: talas::geometry::DVec3, hi: talas::geometry::DVec3) -> TriMesh {
    use talas::geometry::DVec3;
    let c = |i: usize| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    };
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let positions: Vec<DVec3> = (0..8).map(c).collect();
    let triangles = quads
        .iter()
        .flat_map(|q: &[u32; 4]| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    TriMesh::new(positions, triangles)
}

/// Z-level roughing of a 225 mm deep part with a 22 mm-flute, 70 mm tool stops at the depth the
/// flutes reach below the stock top (22 mm) with a warning that names the depth and what the
/// levels below need, instead of planning the full depth; a necked tool (shank narrower than
/// the cut) reaches its length out of the holder less 1 mm; a tool long enough plans it all.
/// `cargo test --no-default-features --test mesh_strategies roughing_stops`
#[test]
fn roughing_stops_where_the_flutes_and_the_stick_out_reach() {
    use talas::geometry::DVec3;
    use talas::geometry::stock::Stock;
    use talas::strategies::zlevel::{ZlevelOptions, reach_below_top_mm, reach_note, zlevel_rough};
    let mesh = box_mesh(DVec3::new(0.0, 0.0, 0.0), DVec3::new(40.0, 30.0, 225.0));
    let bvh = MeshBvh::new(&mesh).unwrap();
    let stock = Stock::Box {
        min_mm: [-12.0, -12.0, 0.0],
        max_mm: [52.0, 42.0, 227.0],
    };
    let opts = ZlevelOptions {
        stock,
        step_down_mm: 5.0,
        step_over_mm: 5.0,
        tolerance_mm: 0.5,
        ..ZlevelOptions::default()
    };
    // The lowest level the part allows: its bottom plus the axial stock to leave.
    let floor = opts.stock_to_leave_axial_mm;
    let lowest_cut = |plan: &talas::strategies::zlevel::ZlevelPlan| {
        plan.toolpath
            .poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .map(|p| p.tip.z)
            .fold(f64::INFINITY, f64::min)
    };
    // 22 mm of flute, 70 mm out of the holder, shank as wide as the cut.
    let short = tool("flat:d=10,flute=22,length=70");
    assert_eq!(reach_below_top_mm(&short.cutter), 22.0);
    let plan = zlevel_rough(&mesh, &bvh, &short, &opts).unwrap();
    assert!(
        (plan.levels.last().unwrap() - (227.0 - 22.0)).abs() < 1e-9,
        "{:?}",
        plan.levels
    );
    assert!((lowest_cut(&plan) - 205.0).abs() < 1e-9);
    let warning = plan
        .diagnostics
        .iter()
        .find(|d| d.message.contains("roughing stops"))
        .unwrap_or_else(|| panic!("no warning in {:?}", plan.diagnostics));
    assert!(
        warning.message.contains("z = 205.000 mm")
            && warning.message.contains("22.000 mm flute length")
            && warning
                .message
                .contains("reaches 22.000 mm below the stock top at z = 227.000")
            && warning
                .message
                .contains(&format!("reaches {:.3} mm", 227.0 - floor)),
        "{}",
        warning.message
    );
    // A necked tool: a 6 mm shank behind a 10 mm cut, 70 mm out of the holder.
    let necked = tool("flat:d=10,flute=22,shank=6,length=70");
    assert_eq!(reach_below_top_mm(&necked.cutter), 69.0);
    let plan = zlevel_rough(&mesh, &bvh, &necked, &opts).unwrap();
    assert!((lowest_cut(&plan) - (227.0 - 69.0)).abs() < 1e-9);
    // Long enough: the whole depth, no warning.
    let long = tool("flat:d=10,flute=240,length=260");
    let plan = zlevel_rough(&mesh, &bvh, &long, &opts).unwrap();
    assert!(
        (lowest_cut(&plan) - floor).abs() < 1e-9,
        "{}",
        lowest_cut(&plan)
    );
    assert!(
        !plan
            .diagnostics
            .iter()
            .any(|d| d.message.contains("roughing stops"))
    );
    // Said before planning, from the same rule.
    let part = bvh.bbox();
    let before = reach_note(&short.cutter, &stock, &part, floor).unwrap();
    assert!(
        before.contains("reaches 22.000 mm") && before.contains("stops at z = 205.000 mm"),
        "{before}"
    );
    assert_eq!(reach_note(&long.cutter, &stock, &part, floor), None);
}
