//! Stock simulation against closed forms: removed volumes of slots (ball, flat, bull-nose, with
//! their end caps), a helical entry (per-point depth in closed form, integrated by quadrature),
//! a tilted flat-end pass (cross-section of the tilted cylinder × length); gouge and holder
//! crash detection with their block numbers; determinism; the memory check; the STL mesh; the
//! command line.

mod common;

use std::f64::consts::{PI, TAU};
use std::path::PathBuf;
use std::process::Command;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::gcode::{InterpretOptions, interpret};
use talas::geometry::mesh::TriMesh;
use talas::simulation::{
    CollisionKind, DeviationOptions, DexelMode, DexelStock, MovePlan, SimError, SimOptions,
    StepOptions, StockShape, deviation, plan_program, plan_toolpath, simulate,
};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::{Cutter, CutterKind, parse_tool_spec};

const RES: f64 = 0.05;

fn boxed(min: [f64; 3], max: [f64; 3]) -> StockShape {
    StockShape::Box {
        min: DVec3::from_array(min),
        max: DVec3::from_array(max),
    }
}

fn gcode_plan(text: &str, cutter: &Cutter) -> MovePlan {
    let prog = interpret(text, &InterpretOptions::default()).expect("valid G-code");
    let opts = StepOptions {
        reach_mm: cutter.flute_length,
        ..StepOptions::default()
    };
    plan_program(&prog, None, &opts).expect("plan")
}

fn run(stock: &mut DexelStock, cutter: &Cutter, plan: &MovePlan) -> talas::simulation::SimReport {
    simulate(
        stock,
        cutter,
        plan,
        &SimOptions::default(),
        &Progress::new(),
    )
    .expect("simulate")
}

fn rel(got: f64, want: f64) -> f64 {
    (got - want).abs() / want
}

/// A slot along X from x=5 to x=25 at depth h (plunge, feed, retract), off the grid rows.
fn slot_program(h: f64) -> String {
    format!(
        "G21 G90 G94\nG0 Z5\nG0 X5 Y0.0123 Z5\nG1 Z{} F300\nG1 X25 F600\nG0 Z5\nM30\n",
        -h
    )
}

fn slot_volume(cutter: &Cutter, h: f64) -> f64 {
    let mut stock = DexelStock::new(
        vec![boxed([0.0, -8.0, -6.0], [30.0, 8.0, 0.0])],
        RES,
        DexelMode::Z,
        1 << 30,
    )
    .expect("stock");
    let plan = gcode_plan(&slot_program(h), cutter);
    let report = run(&mut stock, cutter, &plan);
    assert!(report.collisions.is_empty(), "{:?}", report.collisions);
    report.removed_volume_mm3
}

#[test]
fn slots_match_closed_forms() {
    let (r, h, l) = (3.0_f64, 2.0_f64, 20.0_f64);
    // Ball: circular segment of depth h swept over L, plus two half spherical caps.
    let seg = r * r * ((r - h) / r).acos() - (r - h) * (2.0 * r * h - h * h).sqrt();
    let cap = PI * h * h * (3.0 * r - h) / 3.0;
    let ball = seg * l + cap;
    // Flat: rectangle 2R × h over L plus a disc of depth h.
    let flat = 2.0 * r * h * l + PI * r * r * h;
    // Bull-nose r_c = 1 (h ≥ r_c): the rectangle minus two corner pieces (r_c² (1 − π/4)
    // each), plus the solid of revolution minus the ring of corner pieces (Pappus: centroid
    // radius a + r_c / (6 (1 − π/4)), a = R − r_c).
    let rc = 1.0_f64;
    let a = r - rc;
    let corner = rc * rc * (1.0 - PI / 4.0);
    let bull = (2.0 * r * h - 2.0 * corner) * l + PI * r * r * h
        - 2.0 * PI * (a * corner + rc * rc * rc / 6.0);
    let cases = [
        ("ball", Cutter::new(CutterKind::Ball, 6.0), ball),
        ("flat", Cutter::new(CutterKind::Flat, 6.0), flat),
        (
            "bull",
            Cutter::new(CutterKind::BullNose { corner_radius: rc }, 6.0),
            bull,
        ),
    ];
    for (name, cutter, want) in cases {
        let cutter = cutter.expect("cutter");
        let got = slot_volume(&cutter, h);
        let e = rel(got, want);
        eprintln!(
            "slot {name}: {got:.4} mm³ vs {want:.4} mm³ ({:.4} %)",
            100.0 * e
        );
        assert!(e < 0.005, "{name}: {got} vs {want}");
    }
}

/// Depth cut at (r, θ) by a flat end mill of radius `rt` whose tip follows the helix of radius
/// `rh` from angle 0 (z = 0) to `phi_end` (z = −depth), descending linearly in angle.
fn helix_depth(r: f64, theta: f64, rh: f64, rt: f64, phi_end: f64, depth: f64) -> f64 {
    let kappa = (r * r + rh * rh - rt * rt) / (2.0 * r * rh);
    if kappa > 1.0 {
        return 0.0;
    }
    let at = |phi: f64| depth * phi / phi_end;
    if kappa <= -1.0 {
        return depth;
    }
    let alpha = kappa.acos();
    // Covered when φ ∈ [θ − α + 2πk, θ + α + 2πk]: the last covering φ ≤ φ_end.
    let k = ((phi_end - (theta - alpha)) / TAU).floor();
    let start = theta - alpha + TAU * k;
    let end = (theta + alpha + TAU * k).min(phi_end);
    if end < 0.0 || start > phi_end {
        return 0.0;
    }
    at(end)
}

#[test]
fn helical_entry_matches_quadrature_of_the_exact_depth() {
    let cutter = Cutter::new(CutterKind::Flat, 6.0).expect("cutter");
    let (rh, rt, depth, turns) = (4.0, 3.0, 2.0, 2.0);
    let text =
        "G21 G90 G94 G17\nG0 X4 Y0 Z5\nG1 Z0 F300\nG3 X4 Y0 Z-2 I-4 J0 P2 F300\nG0 Z5\nM30\n";
    let plan = gcode_plan(text, &cutter);
    let mut stock = DexelStock::new(
        vec![boxed([-9.0, -9.0, -5.0], [9.0, 9.0, 0.0])],
        RES,
        DexelMode::Z,
        1 << 30,
    )
    .expect("stock");
    let report = run(&mut stock, &cutter, &plan);
    assert!(report.collisions.is_empty(), "{:?}", report.collisions);
    let phi_end = TAU * turns;
    let (nr, nt) = (600, 2400);
    let (r0, r1) = (rh - rt, rh + rt);
    let mut want = 0.0;
    for i in 0..nr {
        let r = r0 + (r1 - r0) * (f64::from(i) + 0.5) / f64::from(nr);
        for j in 0..nt {
            let theta = TAU * (f64::from(j) + 0.5) / f64::from(nt);
            want += helix_depth(r, theta, rh, rt, phi_end, depth) * r;
        }
    }
    want *= (r1 - r0) / f64::from(nr) * TAU / f64::from(nt);
    let got = report.removed_volume_mm3;
    let e = rel(got, want);
    eprintln!("helix: {got:.4} mm³ vs {want:.4} mm³ ({:.4} %)", 100.0 * e);
    assert!(e < 0.005, "{got} vs {want}");
}

/// Area of a polygon clipped to the half-plane z ≤ 0 (Sutherland–Hodgman), shoelace.
fn clipped_area(poly: &[(f64, f64)]) -> f64 {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for k in 0..poly.len() {
        let p = poly[k];
        let q = poly[(k + 1) % poly.len()];
        let (pin, qin) = (p.1 <= 0.0, q.1 <= 0.0);
        if pin {
            out.push(p);
        }
        if pin != qin {
            let t = p.1 / (p.1 - q.1);
            out.push((p.0 + t * (q.0 - p.0), 0.0));
        }
    }
    let mut a = 0.0;
    for k in 0..out.len() {
        let (x0, y0) = out[k];
        let (x1, y1) = out[(k + 1) % out.len()];
        a += x0 * y1 - x1 * y0;
    }
    0.5 * a.abs()
}

#[test]
fn tilted_flat_pass_matches_the_projected_cylinder() {
    let cutter = Cutter::new(CutterKind::Flat, 6.0).expect("cutter");
    let beta = 20f64.to_radians();
    let axis = DVec3::new(0.0, beta.sin(), beta.cos());
    let (y0, z0) = (0.0123, -1.5);
    let tool = ToolRecord {
        spec: "flat:d=6".into(),
        cutter: cutter.clone(),
    };
    let poses = vec![
        Pose::new(MoveKind::Rapid, DVec3::new(-10.0, y0, z0), axis, 0.0),
        Pose::new(MoveKind::Cut, DVec3::new(40.0, y0, z0), axis, 600.0),
    ];
    let tp = Toolpath::new(tool, poses);
    let plan = plan_toolpath(&tp, &StepOptions::default()).expect("plan");
    assert!(plan.tilted());
    let mut stock = DexelStock::new(
        vec![boxed([0.0, -10.0, -6.0], [30.0, 10.0, 0.0])],
        RES,
        DexelMode::Tri,
        1 << 30,
    )
    .expect("stock");
    let report = run(&mut stock, &cutter, &plan);
    // The pass goes right through the stock, so the removed volume is the stock length times
    // the part below z = 0 of the cylinder's projection along X: a rectangle 2R × L in YZ.
    let (r, l) = (cutter.radius(), cutter.flute_length);
    let n = (beta.cos(), -beta.sin());
    let a = (beta.sin(), beta.cos());
    let corner = |s: f64, t: f64| {
        (
            y0 + s * r * n.0 + t * l * a.0,
            z0 + s * r * n.1 + t * l * a.1,
        )
    };
    let rect = [
        corner(-1.0, 0.0),
        corner(1.0, 0.0),
        corner(1.0, 1.0),
        corner(-1.0, 1.0),
    ];
    let want = 30.0 * clipped_area(&rect);
    let got = report.removed_volume_mm3;
    let e = rel(got, want);
    eprintln!("tilted: {got:.4} mm³ vs {want:.4} mm³ ({:.4} %)", 100.0 * e);
    for f in &stock.families {
        eprintln!("  family {:?}: {:.4} mm³ left", f.axis, f.volume());
    }
    assert!(e < 0.005, "{got} vs {want}");
}

fn box_mesh(min: DVec3, max: DVec3) -> TriMesh {
    let p = |i: u32| {
        DVec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    let positions = (0..8).map(p).collect();
    let triangles = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    TriMesh::new(positions, triangles)
}

#[test]
fn a_gouging_slot_is_found_where_it_is() {
    // The part's top is at z = −1; the ball slot goes 2 mm deep: a 1 mm gouge along y ≈ 0.
    let part = box_mesh(DVec3::new(0.0, -8.0, -6.0), DVec3::new(30.0, 8.0, -1.0));
    assert!(part.signed_volume() > 0.0 && part.is_closed());
    let cutter = Cutter::new(CutterKind::Ball, 6.0).expect("cutter");
    let mut stock = DexelStock::new(
        vec![boxed([0.0, -8.0, -6.0], [30.0, 8.0, 0.0])],
        0.1,
        DexelMode::Z,
        1 << 30,
    )
    .expect("stock");
    run(
        &mut stock,
        &cutter,
        &gcode_plan(&slot_program(2.0), &cutter),
    );
    let d = deviation(
        &stock,
        &part,
        &DeviationOptions::default(),
        &Progress::new(),
    )
    .expect("deviation");
    eprintln!(
        "gouge {:.4} at {:?}, remaining {:.4}",
        d.max_gouge_mm, d.max_gouge_at, d.max_remaining_mm
    );
    assert!((d.max_gouge_mm - 1.0).abs() < 0.01, "{}", d.max_gouge_mm);
    let at = d.max_gouge_at.expect("located");
    assert!(at[0] > 4.9 && at[0] < 25.1 && at[1].abs() < 0.1, "{at:?}");
    // The uncut top layer is 1 mm of remaining material.
    assert!(
        (d.max_remaining_mm - 1.0).abs() < 1e-6,
        "{}",
        d.max_remaining_mm
    );
    // A slot that stops at the part's top leaves no gouge (grazing within float rounding).
    let mut clean = DexelStock::new(
        vec![boxed([0.0, -8.0, -6.0], [30.0, 8.0, 0.0])],
        0.1,
        DexelMode::Z,
        1 << 30,
    )
    .expect("stock");
    run(
        &mut clean,
        &cutter,
        &gcode_plan(&slot_program(1.0), &cutter),
    );
    let d = deviation(
        &clean,
        &part,
        &DeviationOptions::default(),
        &Progress::new(),
    )
    .expect("deviation");
    assert!(d.max_gouge_mm < 1e-4, "{}", d.max_gouge_mm);
}

#[test]
fn holder_crash_and_rapid_through_material_name_their_lines() {
    // Flutes 10 mm, shank to 25 mm, holder Ø40: plunging 30 mm buries the holder 5 mm.
    let cutter = parse_tool_spec("flat:d=6,flute=10,length=25,holder=40x50").expect("tool");
    let text = "G21 G90 G94\nG0 X25 Y25 Z5\nG1 Z-30 F300\nG0 Z5\nG0 X10 Y10\nG0 Z-2\nM30\n";
    let plan = gcode_plan(text, &cutter);
    let mut stock = DexelStock::new(
        vec![boxed([0.0, 0.0, -40.0], [50.0, 50.0, 0.0])],
        0.2,
        DexelMode::Z,
        1 << 30,
    )
    .expect("stock");
    let report = run(&mut stock, &cutter, &plan);
    eprintln!("{:#?}", report.collisions);
    // The first holder contact is the plunge (line 3); the retract (line 4) starts buried.
    let holder = report
        .collisions
        .iter()
        .find(|c| c.kind == CollisionKind::Holder)
        .expect("holder crash found");
    assert_eq!(holder.block, 3);
    // In the holder's footprint (radius 20 around X25 Y25), outside the cut hole (radius 3).
    let r = (holder.position.truncate() - glam::DVec2::new(25.0, 25.0)).length();
    assert!(r > 2.9 && r < 20.1, "{r}");
    assert!((holder.depth_mm - 5.0).abs() < 0.01, "{}", holder.depth_mm);
    assert!(holder.position.z < 0.0 && holder.position.z > -5.0);
    let rapid = report
        .collisions
        .iter()
        .find(|c| c.kind == CollisionKind::Rapid)
        .expect("rapid into material found");
    assert_eq!(rapid.block, 6);
    assert!((rapid.position.x - 10.0).abs() < 3.1 && (rapid.position.y - 10.0).abs() < 3.1);
    assert!(
        report
            .collisions
            .iter()
            .all(|c| [3, 4, 6].contains(&c.block)),
        "{:?}",
        report.collisions
    );
}

#[test]
fn same_input_same_stock_bit_for_bit() {
    for cutter in [
        Cutter::new(CutterKind::BullNose { corner_radius: 1.0 }, 6.0),
        Cutter::new(CutterKind::Ball, 6.0),
    ] {
        same_stock_at_any_thread_count(&cutter.expect("cutter"));
    }
}

fn same_stock_at_any_thread_count(cutter: &Cutter) {
    let text =
        "G21 G90\nG0 X2 Y2 Z5\nG1 Z-1 F300\nG1 X12 Y9 Z-2.5\nG2 X14 Y3 R4\nG1 X3 Y4 Z-0.5\nM30\n";
    let plan = gcode_plan(text, cutter);
    let fresh = || {
        DexelStock::new(
            vec![boxed([0.0, 0.0, -5.0], [16.0, 12.0, 0.0])],
            0.1,
            DexelMode::Z,
            1 << 30,
        )
        .expect("stock")
    };
    let mut a = fresh();
    let mut b = fresh();
    simulate(
        &mut a,
        cutter,
        &plan,
        &SimOptions::default(),
        &Progress::new(),
    )
    .expect("a");
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("pool");
    let opts = SimOptions {
        batch_steps: 1,
        ..SimOptions::default()
    };
    one.install(|| simulate(&mut b, cutter, &plan, &opts, &Progress::new()))
        .expect("b");
    assert!(a.volume_mm3() < fresh().volume_mm3());
    for (fa, fb) in a.families.iter().zip(&b.families) {
        assert!(fa.dexels == fb.dexels, "dexels differ");
    }
}

#[test]
fn memory_is_checked_before_allocating() {
    let err = DexelStock::new(
        vec![boxed([0.0, 0.0, 0.0], [1000.0, 1000.0, 100.0])],
        0.001,
        DexelMode::Tri,
        1 << 30,
    )
    .expect_err("too large");
    assert!(matches!(err, SimError::Memory { .. }), "{err}");
    assert!(err.to_string().contains("MiB"), "{err}");
}

#[test]
fn closed_mesh_volume_is_the_stock_volume() {
    let cutter = Cutter::new(CutterKind::Ball, 4.0).expect("cutter");
    let mut stock = DexelStock::new(
        vec![
            boxed([0.0, 0.0, -3.0], [10.0, 8.0, 0.0]),
            StockShape::Cylinder {
                base: DVec3::new(5.0, 4.0, 0.0),
                radius: 3.0,
                height: 2.0,
            },
        ],
        0.2,
        DexelMode::Z,
        1 << 30,
    )
    .expect("stock");
    let plan = gcode_plan("G0 X-3 Y4 Z0.5\nG1 X13 Y4 Z-1.5 F500\nM30\n", &cutter);
    run(&mut stock, &cutter, &plan);
    let mesh = stock.closed_mesh();
    let (v, m) = (stock.volume_mm3(), mesh.signed_volume());
    // Each interval end moves at most half the mesh's height step, over one cell.
    let ends = 2.0 * (10.0 * 8.0 + std::f64::consts::PI * 9.0) / (0.2 * 0.2);
    let bound = ends * 0.5 * talas::simulation::MESH_HEIGHT_STEP_MM * 0.04;
    assert!((v - m).abs() <= bound, "{v} vs {m} (bound {bound})");
    // Closed edge by edge (the boss on the block and the slot give walls of every height, so
    // a wall's edges meet the other columns' walls part-way: no T-junction may be left), and
    // so it is a stock again (issue 35: `simulate --stl` wrote 3 974 boundary edges).
    assert!(
        mesh.is_closed(),
        "{} boundary and {} bad edges",
        mesh.boundary_edges().len(),
        mesh.bad_edges().len()
    );
    let mut again = DexelStock::new(
        vec![StockShape::mesh(mesh.clone()).expect("closed mesh stock")],
        0.2,
        DexelMode::Z,
        1 << 30,
    )
    .expect("the written stock reads back as a stock");
    let v2 = again.volume_mm3();
    assert!((v2 - v).abs() < 1e-3 * v, "{v2} vs {v}");
    run(&mut again, &cutter, &plan);
    assert!((again.volume_mm3() - v).abs() < 1e-3 * v);
    let hf = stock.height_field_mesh();
    assert!(!hf.triangles.is_empty());
}

fn temp(name: &str) -> PathBuf {
    common::temp_path("sim", name)
}

#[test]
fn command_line_reports_volume_collisions_and_errors() {
    let prog = temp("slot.ngc");
    std::fs::write(&prog, slot_program(2.0)).expect("write");
    let stl = temp("stock.stl");
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["simulate"])
        .arg(&prog)
        .args(["--tool", "flat:d=6", "--stock", "box:0,-8,-6,30,8,0"])
        .args(["--resolution", "0.1", "--json", "--stl"])
        .arg(&stl)
        .output()
        .expect("run");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let v = doc["removed_volume_mm3"].as_f64().expect("volume");
    let want = 2.0 * 3.0 * 2.0 * 20.0 + PI * 9.0 * 2.0;
    assert!(rel(v, want) < 0.01, "{v} vs {want}");
    assert!(doc["time_s"].as_f64().expect("time") > 0.0);
    assert!(doc["memory_bytes"].as_u64().expect("memory") > 0);
    assert!(std::fs::metadata(&stl).expect("stl written").len() > 84);
    // The written stock is a closed mesh (read back through the STL reader, which joins
    // vertices by position) and a stock again: the same slot cut into it removes nothing
    // more, and the stock it starts from is the one written.
    let written = talas::import::stl::read_stl(&stl, &talas::import::stl::StlOptions::default())
        .expect("read stl")
        .mesh;
    assert!(
        written.is_closed(),
        "{} boundary edges",
        written.boundary_edges().len()
    );
    let again = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["simulate"])
        .arg(&prog)
        .args(["--tool", "flat:d=6", "--stock"])
        .arg(format!("mesh:{}", stl.display()))
        .args(["--resolution", "0.1", "--json"])
        .output()
        .expect("run");
    assert!(
        again.status.success(),
        "{}",
        String::from_utf8_lossy(&again.stderr)
    );
    let doc2: serde_json::Value = serde_json::from_slice(&again.stdout).expect("json");
    let start = doc2["initial_volume_mm3"].as_f64().expect("volume");
    let end = doc["final_volume_mm3"].as_f64().expect("volume");
    assert!(rel(start, end) < 1e-3, "{start} vs {end}");
    assert!(doc2["removed_volume_mm3"].as_f64().expect("volume") < 1e-3 * want);

    let bad = temp("bad.ngc");
    std::fs::write(&bad, "G1 X1 F100\nG1 X2 Q7\n").expect("write");
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["simulate"])
        .arg(&bad)
        .args([
            "--tool",
            "flat:d=6",
            "--stock",
            "box:0,0,0,1,1,1",
            "--resolution",
            "0.1",
        ])
        .output()
        .expect("run");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("bad.ngc") && err.contains("line 2"), "{err}");
}

#[test]
fn posted_five_axis_program_goes_through_the_machine_kinematics() {
    use talas::machine::Machine;
    use talas::post::{Dialect, PostOptions, post};
    // The tilted pass of `tilted_flat_pass_matches_the_projected_cylinder`, posted for the
    // table-tilting A/C machine in joint space, read back and simulated through the forward
    // kinematics: the same closed-form volume.
    let cutter = Cutter::new(CutterKind::Flat, 6.0).expect("cutter");
    let beta = 20f64.to_radians();
    let axis = DVec3::new(0.0, beta.sin(), beta.cos());
    let (y0, z0) = (0.0123, -1.5);
    let poses = vec![
        Pose::new(MoveKind::Rapid, DVec3::new(-10.0, y0, 10.0), axis, 0.0),
        Pose::new(MoveKind::Plunge, DVec3::new(-10.0, y0, z0), axis, 300.0),
        Pose::new(MoveKind::Cut, DVec3::new(40.0, y0, z0), axis, 600.0),
        Pose::new(MoveKind::Rapid, DVec3::new(40.0, y0, 10.0), axis, 0.0),
    ];
    let tp = Toolpath::new(
        ToolRecord {
            spec: "flat:d=6".into(),
            cutter: cutter.clone(),
        },
        poses,
    );
    let machine = Machine::builtin("trt-ac").expect("machine");
    let dialect = Dialect::resolve("linuxcnc").expect("dialect");
    // Joint space (Talas does the kinematics) and tool-centre-point output (the controller
    // does): the same volume.
    for tcp in [false, true] {
        let options = PostOptions {
            tcp,
            ..PostOptions::default()
        };
        let text = post(&tp, &machine, &dialect, &options).expect("post");
        assert!(text.contains('A'), "{text}");
        let prog = interpret(&text, &InterpretOptions::default()).expect("interpret");
        // Coarser steps for the rotations of the rapids (they only need to miss the stock).
        let opts = StepOptions {
            reach_mm: cutter.flute_length,
            axis_tolerance_mm: 0.05,
            chord_tolerance_mm: 0.01,
            ..StepOptions::default()
        };
        assert!(
            plan_program(&prog, None, &opts).is_err(),
            "rotary needs a machine"
        );
        assert_eq!(prog.blocks.iter().any(|b| b.tcp), tcp);
        let plan = plan_program(&prog, Some(&machine), &opts).expect("plan");
        assert!(plan.tilted());
        let mut stock = DexelStock::new(
            vec![boxed([0.0, -10.0, -6.0], [30.0, 10.0, 0.0])],
            0.1,
            DexelMode::Tri,
            1 << 30,
        )
        .expect("stock");
        let report = run(&mut stock, &cutter, &plan);
        assert!(report.collisions.is_empty(), "{:?}", report.collisions);
        let (r, l) = (cutter.radius(), cutter.flute_length);
        let n = (beta.cos(), -beta.sin());
        let a = (beta.sin(), beta.cos());
        let corner = |s: f64, t: f64| {
            (
                y0 + s * r * n.0 + t * l * a.0,
                z0 + s * r * n.1 + t * l * a.1,
            )
        };
        let rect = [
            corner(-1.0, 0.0),
            corner(1.0, 0.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        let want = 30.0 * clipped_area(&rect);
        let got = report.removed_volume_mm3;
        eprintln!(
            "posted tilted (tcp {tcp}): {got:.4} mm³ vs {want:.4} mm³ ({:.4} %)",
            100.0 * rel(got, want)
        );
        assert!(rel(got, want) < 0.005, "{got} vs {want}");
    }
}

#[path = "simulation/finish.rs"]
mod finish;

#[test]
fn closed_parts_and_open_sheets_are_told_apart() {
    use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
    use talas::import::step::read_step;
    use talas::import::stl::{StlOptions, read_stl};
    use talas::simulation::is_closed;
    let data = common::data("");
    // A solid tessellated face by face: the seams meet, so it bounds material.
    let solid = read_step(&data.join("pocket-fillets.stp")).unwrap();
    let mesh = tessellate_part(&solid, &TessellationOptions::default()).mesh;
    assert!(is_closed(&mesh), "pocket-fillets.stp is a solid");
    assert!(is_closed(
        &read_stl(&data.join("pocket-fillets.stl"), &StlOptions::default())
            .unwrap()
            .mesh
    ));
    // A single surface is a sheet.
    let sheet = read_step(&data.join("bicubic-hills.stp")).unwrap();
    assert!(!is_closed(
        &tessellate_part(&sheet, &TessellationOptions::default()).mesh
    ));
    // The solid less one triangle is open.
    let mut holed = mesh.clone();
    holed.triangles.pop();
    assert!(!is_closed(&holed));
}

/// A zig-zag over the box part of `a_gouging_slot_is_found_where_it_is`, `rows` rows of 24
/// poses at depth `z` (every other row deeper, the axis tilting with x), entered by a rapid
/// plunge into the material (a collision to carry through the keyframes).
fn zigzag(cutter: &Cutter, rows: usize, z: f64) -> Toolpath {
    let mut poses = vec![Pose::new(
        MoveKind::Rapid,
        DVec3::new(-4.0, -8.0, 5.0),
        DVec3::Z,
        0.0,
    )];
    poses.push(Pose::new(
        MoveKind::Rapid,
        DVec3::new(2.0, -8.0, z),
        DVec3::Z,
        0.0,
    ));
    for r in 0..rows {
        let y = -8.0 + 16.0 * r as f64 / (rows - 1).max(1) as f64;
        for k in 0..24 {
            let t = k as f64 / 23.0;
            let x = if r % 2 == 0 {
                30.0 * t
            } else {
                30.0 * (1.0 - t)
            };
            let depth = z - 0.3 * (r % 2) as f64 - 0.2 * (x / 30.0 * PI).sin();
            let axis = DVec3::new(0.3 * (x / 15.0 - 1.0), 0.0, 1.0).normalize();
            poses.push(Pose::new(
                MoveKind::Cut,
                DVec3::new(x, y, depth),
                axis,
                600.0,
            ));
        }
    }
    let tool = ToolRecord {
        spec: "ball:d=6".into(),
        cutter: cutter.clone(),
    };
    Toolpath::new(tool, poses)
}

/// "Stock here" from keyframes equals simulating the path cut at the pose from the start, bit
/// for bit (stock heights, deviation, volumes, collisions), at every kind of pose; with a small
/// memory budget fewer keyframes are kept. Quick: a 0.5 mm grid, 266 + 122 poses.
/// `cargo test --no-default-features --test simulation stock_here`
#[test]
fn stock_here_from_keyframes_is_the_simulation_up_to_the_pose() {
    use talas::project::Stock;
    use talas::project::keyframes::{simulate_with_keyframes, stock_here};
    use talas::project::simulate::{Simulated, SimulationSettings, simulate_toolpaths};
    let part = box_mesh(DVec3::new(0.0, -8.0, -6.0), DVec3::new(30.0, 8.0, -1.0));
    let cutter = Cutter::new(CutterKind::Ball, 6.0).expect("cutter");
    let rough = zigzag(&cutter, 5, 0.5);
    let finish = zigzag(&cutter, 11, -0.5);
    let settings = SimulationSettings {
        resolution_mm: Some(0.5),
        ..SimulationSettings::default()
    };
    let stock = Stock::None;
    let paths = [(&rough, &cutter), (&finish, &cutter)];
    let same = |a: &Simulated, b: &Simulated, what: &str| {
        assert_eq!(a.reports, b.reports, "{what}");
        assert_eq!(a.report, b.report, "{what}");
        assert_eq!(a.stock_mesh.positions, b.stock_mesh.positions, "{what}");
        assert_eq!(a.deviation_mm, b.deviation_mm, "{what}");
        assert_eq!(a.max_gouge_mm.to_bits(), b.max_gouge_mm.to_bits(), "{what}");
    };
    let progress = Progress::new();
    let whole = simulate_toolpaths(&stock, &part, &paths, &settings, &progress).expect("whole");
    assert!(
        !whole.report.collisions.is_empty(),
        "the rapid plunge collides"
    );
    for budget in [256 << 20, 200_000] {
        let (sim, frames) =
            simulate_with_keyframes(&stock, &part, &paths, &settings, budget, &progress)
                .expect("keyframes");
        same(&sim, &whole, "whole run");
        assert!(frames.matches(&stock, &part, &paths, &settings));
        assert!(!frames.matches(&stock, &part, &paths[..1], &settings));
        assert!(!frames.is_empty() && frames.memory_bytes() <= budget);
        assert!(
            budget > 1 << 20 || frames.len() < 10,
            "{} keyframes",
            frames.len()
        );
        eprintln!(
            "budget {budget} B: {} keyframes, {} B, at most {} steps re-cut",
            frames.len(),
            frames.memory_bytes(),
            frames.max_gap_steps()
        );
        for pose in [
            0,
            1,
            2,
            30,
            131,
            200,
            finish.poses.len() - 1,
            finish.poses.len() + 5,
        ] {
            let here = stock_here(&frames, &part, pose, &progress).expect("stock here");
            let cut = Toolpath::new(
                finish.tool.clone(),
                finish.poses.iter().take(pose + 1).copied().collect(),
            );
            let direct = simulate_toolpaths(
                &stock,
                &part,
                &[(&rough, &cutter), (&cut, &cutter)],
                &settings,
                &progress,
            )
            .expect("direct");
            same(&here, &direct, &format!("pose {pose}, budget {budget}"));
        }
    }
}
