//! Rest finishing against a closed form: in a 90° V-groove (flanks z = |x|) a reference ball of
//! radius 5 rests on both flanks with its centre 5·√2 above the bottom; at a flank point
//! (x, x) it leaves √(x² + (x − 5√2)²) − 5 of material, which exceeds the threshold t inside
//! |x| < x_t. A finishing ball of radius 1.5 touches a flank at (x, x) with its axis at
//! x − 1.5/√2, so its passes must cover |x_axis| < x_t − 1.5/√2 and nothing more (to the
//! sample step), and each cut pose must be an exact drop-cutter location.

mod common;

use common::{talas, temp_file};
use glam::DVec3;
use talas::geometry::bvh::MeshBvh;
use talas::geometry::mesh::TriMesh;
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
