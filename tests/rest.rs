//! Rest finishing against a closed form: in a 90° V-groove (flanks z = |x|) a reference ball of
//! radius 5 rests on both flanks with its centre 5·√2 above the bottom; at a flank point
//! (x, x) it leaves √(x² + (x − 5√2)²) − 5 of material, which exceeds the threshold t inside
//! |x| < x_t. A finishing ball of radius 1.5 touches a flank at (x, x) with its axis at
//! x − 1.5/√2, so its passes must cover |x_axis| < x_t − 1.5/√2 and nothing more (to the
//! sample step), and each cut pose must be an exact drop-cutter location.

mod common;

use std::path::Path;

use common::{talas, temp_file};
use glam::DVec3;
use talas::diagnostics::Progress;
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
use talas::import::Workpiece;
use talas::project::pipeline::compute;
use talas::project::simulate::{Simulated, SimulationSettings, simulate_toolpaths};
use talas::project::{Operation, OperationKind, Project, ToolEntry};
use talas::strategies::rest::{RestError, RestOptions, rest};
use talas::toolpath::{MoveKind, ToolRecord, Toolpath};
use talas::tools::dropcutter::drop_cutter_at;
use talas::tools::parse_tool_spec;

fn tool(spec: &str) -> ToolRecord {
    ToolRecord {
        spec: spec.into(),
        cutter: parse_tool_spec(spec).unwrap(),
    }
}

/// z = |x|·tan α over x ∈ [−10, 10], y ∈ [0, 20].
fn v_groove(alpha: f64) -> TriMesh {
    let t = alpha.tan();
    let p = |x: f64, y: f64| DVec3::new(x, y, x.abs() * t);
    let positions = vec![
        p(-10.0, 0.0),
        p(0.0, 0.0),
        p(10.0, 0.0),
        p(-10.0, 20.0),
        p(0.0, 20.0),
        p(10.0, 20.0),
    ];
    TriMesh::new(positions, vec![[0, 1, 4], [0, 4, 3], [1, 2, 5], [1, 5, 4]])
}

fn opts(reference: &str, thr: f64) -> RestOptions {
    RestOptions {
        reference: parse_tool_spec(reference).unwrap(),
        threshold_mm: thr,
        scallop_mm: 0.05,
        chord_tol_mm: 0.005,
        sampling_mm: Some(0.25),
        overlap_mm: 0.0,
        clearance_mm: 5.0,
        feed_mm_per_min: 1000.0,
        plunge_feed_mm_per_min: 300.0,
    }
}

#[test]
fn rest_in_a_v_groove_covers_the_band_the_reference_ball_leaves() {
    let mesh = v_groove(45f64.to_radians());
    let bvh = MeshBvh::new(&mesh).unwrap();
    let (rr, rf, thr) = (5.0f64, 1.5f64, 0.05);
    let fin = tool("ball:d=3");
    let plan = rest(&mesh, &bvh, &fin, &opts("ball:d=10", thr)).unwrap();
    // Closed form of the band's edge: left(x) = thr, solved by bisection on x ∈ [0, rr/√2].
    let left = |x: f64| (x * x + (x - rr * 2f64.sqrt()).powi(2)).sqrt() - rr;
    let (mut a, mut b) = (0.0, rr / 2f64.sqrt());
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if left(m) > thr { a = m } else { b = m }
    }
    let band = a - rf / 2f64.sqrt();
    // The deepest point: the finishing ball touches both flanks at rf/√2 from the axis.
    let deepest = left(rf / 2f64.sqrt());
    // (Passes just beyond the mesh's ends, where the balls rest on its boundary edges, may
    // meet a little more.)
    assert!(
        plan.max_rest_mm >= deepest - 1e-9 && plan.max_rest_mm < deepest + 0.01,
        "{} vs {deepest}",
        plan.max_rest_mm
    );
    let tp = &plan.toolpath;
    tp.validate("<rest>").unwrap();
    let cuts: Vec<_> = tp
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .collect();
    assert!(!cuts.is_empty());
    let step = 0.25;
    let widest = cuts.iter().map(|p| p.tip.x.abs()).fold(0.0, f64::max);
    assert!(
        widest <= band + step + 1e-9 && widest >= band - step,
        "passes reach |x| = {widest}, band {band}"
    );
    for side in [-1.0, 1.0] {
        assert!(
            cuts.iter().any(|p| p.tip.x * side >= band - step),
            "side {side}"
        );
    }
    for p in &cuts {
        let cl = drop_cutter_at(&bvh, &mesh, &fin.cutter, p.tip.truncate()).unwrap();
        assert!((cl.z - p.tip.z).abs() < 1e-9);
    }
    // Passes every 2·√(2·1.5·0.05 − 0.05²) mm cover y from 0 to 20.
    let ys: Vec<f64> = cuts.iter().map(|p| p.tip.y).collect();
    assert!(ys.iter().any(|y| *y <= 0.0) && ys.iter().any(|y| *y >= 20.0));
    // A reference barely larger than the finishing ball leaves less than the threshold.
    let e = rest(&mesh, &bvh, &fin, &opts("ball:d=3.2", thr)).unwrap_err();
    assert!(matches!(e, RestError::Empty(_)), "{e}");
    // A reference smaller than the finishing tool and a flat finishing tool are refused.
    assert!(matches!(
        rest(&mesh, &bvh, &fin, &opts("ball:d=2", thr)),
        Err(RestError::Option(_))
    ));
    let flat = tool("flat:d=3");
    assert!(matches!(
        rest(&mesh, &bvh, &flat, &opts("ball:d=10", thr)),
        Err(RestError::Option(_))
    ));
}

fn groove_stl() -> String {
    let mesh = v_groove(30f64.to_radians());
    let mut s = String::from("solid groove\n");
    for t in &mesh.triangles {
        s.push_str("facet normal 0 0 0\nouter loop\n");
        for v in t {
            let p = mesh.positions[*v as usize];
            s.push_str(&format!("vertex {} {} {}\n", p.x, p.y, p.z));
        }
        s.push_str("endloop\nendfacet\n");
    }
    s.push_str("endsolid groove\n");
    s
}

#[test]
fn pencil_and_rest_from_the_command_line() {
    let stl = temp_file("corners-cli", "groove.stl", &groove_stl());
    let out = stl.with_file_name("p.json");
    let (stl_s, out_s) = (stl.to_str().unwrap(), out.to_str().unwrap());
    let run = |extra: &[&str]| {
        let mut args = vec!["plan", stl_s, "-o", out_s, "--json"];
        args.extend_from_slice(extra);
        talas(&args)
    };
    let o = run(&["--tool", "ball:d=6", "--strategy", "pencil"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tp = Toolpath::load(&out).unwrap();
    let z0 = 3.0 * (1.0 / 30f64.to_radians().cos() - 1.0);
    let inner: Vec<_> = tp
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut && (0.0..=20.0).contains(&p.tip.y))
        .collect();
    assert!(inner.len() >= 2);
    assert!(
        inner
            .iter()
            .all(|p| p.tip.x.abs() < 1e-4 && (p.tip.z - z0).abs() < 1e-4)
    );
    let o = run(&[
        "--tool",
        "ball:d=3",
        "--strategy",
        "rest",
        "--reference-tool",
        "ball:d=10",
        "--scallop",
        "0.05",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tp = Toolpath::load(&out).unwrap();
    assert!(tp.poses.iter().filter(|p| p.kind == MoveKind::Cut).count() > 20);
    let bad: [(&[&str], &str); 4] = [
        (&["--tool", "flat:d=6", "--strategy", "pencil"], "ball"),
        (
            &[
                "--tool",
                "ball:d=6",
                "--strategy",
                "pencil",
                "--angle",
                "200",
            ],
            "angle",
        ),
        (
            &["--tool", "ball:d=3", "--strategy", "rest"],
            "--reference-tool",
        ),
        (
            &[
                "--tool",
                "ball:d=3",
                "--strategy",
                "rest",
                "--reference-tool",
                "cone:d=1",
            ],
            "--reference-tool",
        ),
    ];
    for (b, word) in bad {
        let o = run(b);
        assert_eq!(o.status.code(), Some(2), "{b:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{b:?}: {err}");
        assert!(err.contains("groove.stl") && err.contains(word), "{err}");
    }
}

/// `talas plan --strategy rest --from-stock --after PATH.json`: a Ø10 ball raster cut into the
/// default stock leaves the 30° groove's bottom, where the ball rests on both flanks (contacts
/// at |x| = 5·sin 30° = 2.5 mm), and scallops of 0.01 mm on the flanks, under the 0.06 mm
/// threshold (scallop + tolerance). So the Ø3 ball's rest passes lie inside |x| < 2.5 mm, like
/// the reference-tool rest, and the note names the simulated stock. Bad combinations are refused
/// on one line naming the option.
#[test]
fn rest_from_the_stock_from_the_command_line() {
    let stl = temp_file("rest-stock-cli", "groove.stl", &groove_stl());
    let (first, out) = (
        stl.with_file_name("raster.json"),
        stl.with_file_name("rest.json"),
    );
    let (stl_s, first_s, out_s) = (
        stl.to_str().unwrap(),
        first.to_str().unwrap(),
        out.to_str().unwrap(),
    );
    let o = talas(&[
        "plan",
        stl_s,
        "--tool",
        "ball:d=10",
        "--strategy",
        "raster",
        "--scallop",
        "0.01",
        "-o",
        first_s,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let run_rest = |extra: &[&str]| {
        let mut a = vec![
            "plan",
            stl_s,
            "--tool",
            "ball:d=3",
            "--strategy",
            "rest",
            "--scallop",
            "0.05",
            "--json",
            "-o",
            out_s,
        ];
        a.extend_from_slice(extra);
        talas(&a)
    };
    let o = run_rest(&["--from-stock", "--after", first_s]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let said = doc["diagnostics"].to_string();
    assert!(said.contains("simulated stock"), "{said}");
    let tp = Toolpath::load(&out).unwrap();
    let cuts: Vec<_> = tp
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut && (0.0..=20.0).contains(&p.tip.y))
        .collect();
    assert!(cuts.len() > 20, "{} cuts", cuts.len());
    let widest = cuts.iter().map(|p| p.tip.x.abs()).fold(0.0, f64::max);
    assert!(widest < 2.5, "rest passes reach |x| = {widest}");
    let bad: [(&[&str], &str); 3] = [
        (&["--from-stock"], "--after"),
        (
            &["--after", first_s, "--reference-tool", "ball:d=10"],
            "--after",
        ),
        (&["--from-stock", "--after", "missing.json"], "missing.json"),
    ];
    for (b, word) in bad {
        let o = run_rest(b);
        assert_eq!(o.status.code(), Some(2), "{b:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{b:?}: {err}");
        assert!(err.contains(word), "{err}");
    }
}

/// The corner part's top profile (x, z), x rising: a plateau at z = 12, a 60° wall down into a
/// sharp corner at (`SHARP_X`, 4), a floor, a concave fillet of radius `FILLET_R` centred at
/// (`FILLET_X`, 4 + `FILLET_R`), a 60° wall up and a plateau to x = 36.
const SHARP_X: f64 = 4.0 + 8.0 / 1.732_050_807_568_877_2;
const FILLET_X: f64 = 24.0;
const FILLET_R: f64 = 1.75;

fn corner_profile() -> Vec<(f64, f64)> {
    let t60 = 60f64.to_radians().tan();
    let mut p = vec![(0.0, 12.0), (4.0, 12.0), (SHARP_X, 4.0)];
    for k in 0..=24 {
        let th = f64::from(k) / 24.0 * 60f64.to_radians();
        p.push((
            FILLET_X + FILLET_R * th.sin(),
            4.0 + FILLET_R - FILLET_R * th.cos(),
        ));
    }
    let (xw, zw) = *p.last().unwrap();
    p.push((xw + (12.0 - zw) / t60, 12.0));
    p.push((36.0, 12.0));
    p
}

/// The profile extruded over y ∈ [0, 20] into a closed solid down to z = 0.
fn corner_part() -> TriMesh {
    let prof = corner_profile();
    let mut pos: Vec<DVec3> = Vec::new();
    let mut id = |p: DVec3| -> u32 {
        if let Some(i) = pos.iter().position(|q| q.distance(p) < 1e-9) {
            return i as u32;
        }
        pos.push(p);
        (pos.len() - 1) as u32
    };
    let mut tris = Vec::new();
    let mut quad = |a: DVec3, b: DVec3, c: DVec3, d: DVec3, tris: &mut Vec<[u32; 3]>| {
        let (a, b, c, d) = (id(a), id(b), id(c), id(d));
        tris.push([a, b, c]);
        tris.push([a, c, d]);
    };
    let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    for w in prof.windows(2) {
        let ((x0, z0), (x1, z1)) = (w[0], w[1]);
        quad(
            v(x0, 0.0, z0),
            v(x1, 0.0, z1),
            v(x1, 20.0, z1),
            v(x0, 20.0, z0),
            &mut tris,
        );
        quad(
            v(x0, 0.0, 0.0),
            v(x0, 20.0, 0.0),
            v(x1, 20.0, 0.0),
            v(x1, 0.0, 0.0),
            &mut tris,
        );
        quad(
            v(x0, 0.0, 0.0),
            v(x1, 0.0, 0.0),
            v(x1, 0.0, z1),
            v(x0, 0.0, z0),
            &mut tris,
        );
        quad(
            v(x0, 20.0, 0.0),
            v(x0, 20.0, z0),
            v(x1, 20.0, z1),
            v(x1, 20.0, 0.0),
            &mut tris,
        );
    }
    quad(
        v(0.0, 0.0, 0.0),
        v(0.0, 0.0, 12.0),
        v(0.0, 20.0, 12.0),
        v(0.0, 20.0, 0.0),
        &mut tris,
    );
    quad(
        v(36.0, 0.0, 0.0),
        v(36.0, 20.0, 0.0),
        v(36.0, 20.0, 12.0),
        v(36.0, 0.0, 12.0),
        &mut tris,
    );
    TriMesh::new(pos, tris)
}

/// The material a simulated stock keeps over the corner part's pocket, mm: the largest
/// deviation at the stock's top vertices away from the open ends (4 ≤ y ≤ 16) whose x lies in
/// `x_range` and outside `skip`.
fn left_over(sim: &Simulated, x_range: (f64, f64), skip: (f64, f64)) -> (f64, DVec3) {
    let mut worst = (f64::MIN, DVec3::ZERO);
    for (p, d) in sim.stock_mesh.positions.iter().zip(&sim.deviation_mm) {
        let (x, y) = (p.x, p.y);
        if !(4.0..=16.0).contains(&y) || x < x_range.0 || x > x_range.1 {
            continue;
        }
        if x > skip.0 && x < skip.1 {
            continue;
        }
        if *d > worst.0 {
            worst = (*d, *p);
        }
    }
    worst
}

/// Acceptance of rest finishing through the project pipeline and the stock simulation: a
/// 10 mm flat end mill roughs, a 6 mm ball finishes (raster, 0.05 mm scallop), a 3 mm ball
/// rest-finishes with the 6 mm ball as reference. The part (an extruded profile) has a fillet
/// of radius 1.75 mm, which the 6 mm ball cannot reach (it leaves (3 − 1.75)·(1/sin 60° − 1)
/// ≈ 0.19 mm at its middle) and the 3 mm ball reaches everywhere, and a sharp 120° corner,
/// which neither reaches: the 3 mm ball resting in it touches the floor 1.5/tan 60° to the
/// right of the corner and the wall as far up the wall, and the material between its contacts
/// is out of its reach. Everywhere else over the pocket the simulated stock must keep less than
/// the scallop height plus the chord tolerance and the simulation's step (0.02 mm).
/// `cargo test --no-default-features --test rest -- rest_after --nocapture`
#[test]
fn rest_after_roughing_and_finishing_leaves_the_scallop_wherever_the_small_ball_reaches() {
    rest_acceptance(false);
}

/// [`rest_after_roughing_and_finishing_leaves_the_scallop_wherever_the_small_ball_reaches`]
/// with the rest taken from the simulated stock of the roughing and the finishing.
#[test]
fn rest_from_the_stock_after_roughing_and_finishing_leaves_the_scallop_where_it_reaches() {
    rest_acceptance(true);
}

fn rest_acceptance(stock: bool) {
    let part = Workpiece::from_mesh(Path::new("corner.stl"), corner_part(), Vec::new());
    let spec = |s: &str| parse_tool_spec(s).unwrap();
    let entry = |name: &str, s: &str| ToolEntry {
        name: name.into(),
        cutter: spec(s),
    };
    let h = 0.05;
    let mut finish = Operation::new(OperationKind::Raster, 1, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut finish {
        *scallop_mm = h;
    }
    let mut rest_op = Operation::new(OperationKind::Rest, 2, 0);
    if let Operation::Rest {
        reference_tool,
        from_stock,
        scallop_mm,
        ..
    } = &mut rest_op
    {
        *reference_tool = 1;
        *from_stock = stock;
        *scallop_mm = h;
    }
    let project = Project {
        tools: vec![
            entry("T1", "flat:d=10,flute=30,length=50"),
            entry("T2", "ball:d=6,flute=30,length=50"),
            entry("T3", "ball:d=3,flute=20,length=50"),
        ],
        selected_tool: Some(0),
        operations: vec![Operation::new(OperationKind::Rough, 0, 0), finish, rest_op],
        ..Project::default()
    };
    let computed: Vec<_> = (0..3)
        .map(|i| compute(&project, i, &part, &Progress::new()).unwrap())
        .collect();
    let paths: Vec<_> = computed.iter().map(|c| c.toolpath.clone()).collect();
    if stock {
        let alone = Project {
            operations: vec![project.operations[2].clone()],
            ..project.clone()
        };
        let e = compute(&alone, 0, &part, &Progress::new()).unwrap_err();
        assert!(e.to_string().contains("needs an earlier operation"), "{e}");
        // After the roughing alone (0.3 mm allowance) the stock is rest everywhere: the passes
        // span the part, where the reference tool's rest lies in the two corners only.
        let rough_only = Project {
            operations: vec![project.operations[0].clone(), project.operations[2].clone()],
            ..project.clone()
        };
        let tp = compute(&rough_only, 1, &part, &Progress::new())
            .unwrap()
            .toolpath;
        let xs = tp
            .poses
            .iter()
            .filter(|p| p.kind == MoveKind::Cut)
            .map(|p| p.tip.x);
        let (lo, hi) = xs.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
        assert!(
            lo < 1.0 && hi > 35.0,
            "rest after roughing spans x {lo}..{hi}"
        );
    }
    let said = &computed[2].diagnostics[0].message;
    assert_eq!(said.contains("simulated stock"), stock, "{said}");
    let settings = SimulationSettings {
        resolution_mm: Some(0.1),
        ..SimulationSettings::default()
    };
    let sim = |n: usize| {
        let cut: Vec<_> = (0..n)
            .map(|i| (&paths[i], &project.tools[i].cutter))
            .collect();
        simulate_toolpaths(
            &project.stock,
            &part.mesh,
            &cut,
            &settings,
            &Progress::new(),
        )
        .unwrap()
    };
    let (before, after) = (sim(2), sim(3));
    let tol = h + 0.02;
    // The sharp corner's band out of the 3 mm ball's reach, one dexel wider on each side.
    let reach = 1.5 / 60f64.to_radians().tan();
    let skip = (SHARP_X - reach * 0.5 - 0.1, SHARP_X + reach + 0.1);
    let fillet = (FILLET_X - 1.0, FILLET_X + 2.5);
    let (b, at_b) = left_over(&before, fillet, (0.0, 0.0));
    assert!(
        b > 0.15,
        "the 6 mm ball leaves only {b} mm in the fillet (at {at_b})"
    );
    let (a, at_a) = left_over(&after, fillet, (0.0, 0.0));
    assert!(a <= tol, "rest leaves {a} mm in the fillet at {at_a}");
    let (sharp, at_s) = left_over(&before, (SHARP_X - 3.0, SHARP_X + 3.0), skip);
    assert!(
        sharp > 0.07,
        "the 6 mm ball leaves only {sharp} mm at the sharp corner (at {at_s})"
    );
    let (w, at_w) = left_over(&after, (1.0, 35.0), skip);
    assert!(
        w <= tol,
        "{w} mm left at {at_w} where the 3 mm ball reaches"
    );
    assert!(after.max_gouge_mm < 0.01, "gouge {} mm", after.max_gouge_mm);
    eprintln!(
        "rest acceptance (from the stock: {stock}, {} runs): before rest {b:.4} mm in the fillet, {sharp:.4} mm at the sharp corner; \
         after {a:.4} / {w:.4} mm (tolerance {tol} mm), gouge {:.4} mm",
        computed[2].passes, after.max_gouge_mm
    );
}

/// What a 12 mm ball cannot reach in a 90° V-groove, as raster finishing reports it: the ball
/// resting on both flanks has its lower surface on the circle of radius R = 6 mm about
/// (0, R·√2); its point at angle θ from the bottom lies R − R·cos(45° − θ) from the flank, more
/// than h while θ < 45° − acos(1 − h/R), i.e. over |x| < R·sin(45° − acos(1 − h/R)); over the
/// groove's 20 mm that band's plan-view area is 40·R·sin(45° − acos(1 − h/R)). The raster's
/// estimate (sample step × pass gap per point, sampled every 0.25 mm) must agree within 10 %.
#[test]
fn raster_reports_the_plan_area_a_v_groove_keeps_out_of_reach() {
    use talas::strategies::raster::{RasterOptions, raster};
    let mesh = v_groove(45f64.to_radians());
    let bvh = MeshBvh::new(&mesh).unwrap();
    let (r, h) = (6.0f64, 0.05f64);
    let opts = RasterOptions {
        scallop_mm: h,
        chord_tol_mm: 0.01,
        sample_step_mm: Some(0.25),
        ..RasterOptions::default()
    };
    let plan = raster(&mesh, &bvh, &tool("ball:d=12"), &opts).unwrap();
    let want = 40.0 * r * (45f64.to_radians() - (1.0 - h / r).acos()).sin();
    let got = plan.unreachable_area_mm2;
    eprintln!("unreachable area {got:.2} mm², closed form {want:.2} mm²");
    assert!((got - want).abs() < 0.1 * want, "{got} mm² vs {want} mm²");
    assert!(
        plan.diagnostics
            .iter()
            .any(|d| d.message.contains("mm² in plan view")),
        "{:?}",
        plan.diagnostics
    );
}
