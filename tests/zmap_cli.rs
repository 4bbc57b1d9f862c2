//! `talas dropcutter` and `talas reduce` through the command line: the contract's JSON, and bad
//! input giving exit code 2 with one line naming the file and the line.

mod common;
use common::{data, talas, talas_json, temp_file};

#[test]
fn dropcutter_json_keeps_input_order_and_marks_misses() {
    let stl = data("bicubic-hills.stl");
    // The last point is far outside the part: null.
    let pts = temp_file(
        "zmap-cli",
        "pts.csv",
        "x,y\n40,30\n45.5,31\n\n-1000,-1000\n",
    );
    let doc = talas_json(&[
        "dropcutter",
        stl.to_str().unwrap(),
        "--tool",
        "ball:d=6",
        "--points",
        pts.to_str().unwrap(),
        "--json",
    ]);
    let cl = doc["cl"].as_array().unwrap();
    assert_eq!(cl.len(), 3);
    assert_eq!(cl[0][0], 40.0);
    assert_eq!(cl[1][1], 31.0);
    assert!(cl[0][2].as_f64().unwrap().is_finite());
    assert!(cl[2].is_null());
}

#[test]
fn dropcutter_bad_input_names_the_file_and_line() {
    let stl = data("bicubic-hills.stl");
    let bad = temp_file("zmap-cli", "bad.csv", "x,y\n1,2\n3,oops\n");
    let out = talas(&[
        "dropcutter",
        stl.to_str().unwrap(),
        "--tool",
        "ball:d=6",
        "--points",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.csv") && err.contains("line 3"), "{err}");
    assert_eq!(err.trim().lines().count(), 1);

    let ok = temp_file("zmap-cli", "ok.csv", "x,y\n1,2\n");
    let out = talas(&[
        "dropcutter",
        stl.to_str().unwrap(),
        "--tool",
        "bull:d=10,r=6",
        "--points",
        ok.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("corner radius"));
}

#[test]
fn reduce_json_on_example_a() {
    let file = data("zmap/seed-003-example-A-zmap-20x20.csv");
    let doc = talas_json(&[
        "reduce",
        file.to_str().unwrap(),
        "--tolerance",
        "0.1",
        "--json",
    ]);
    let s: Vec<f64> = doc["singular_values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(s.len(), 20);
    assert!((s[0] - 47.545).abs() < 1e-3);
    assert_eq!(doc["rank"], 8);
    assert!(doc["max_error"].as_f64().unwrap() <= 0.1);
    assert!(doc["mean_error"].as_f64().unwrap() > 0.0);
    assert_eq!(doc["reduced_rows"], 20);

    let bad = temp_file("zmap-cli", "bad-zmap.csv", "1,2,3\n4,5\n");
    let out = talas(&["reduce", bad.to_str().unwrap(), "--tolerance", "0.1"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad-zmap.csv") && err.contains("line 2"),
        "{err}"
    );
}

/// `talas reduce --stl`: the STL reads back with the grid's triangle count, and its vertices
/// sit on the grid nodes within the reported max error of the input heights.
#[test]
fn reduce_stl_reads_back_within_the_reported_error() {
    use talas::import::stl::{StlOptions, read_stl};
    let file = data("zmap/seed-003-example-A-zmap-20x20.csv");
    let input =
        talas::geometry::zmap::Grid::parse_csv(&std::fs::read_to_string(&file).unwrap()).unwrap();
    let out_stl = temp_file("zmap-cli", "reduced-a.stl", "");
    let doc = talas_json(&[
        "reduce",
        file.to_str().unwrap(),
        "--tolerance",
        "0.2",
        "--stl",
        out_stl.to_str().unwrap(),
        "--json",
    ]);
    let max_error = doc["max_error"].as_f64().unwrap();
    // Spectral rule: σ_6 = 0.330 > 0.2 ≥ σ_7 = 0.194 (Fig. 6.3), so rank 6.
    assert_eq!(doc["rank"], 6);
    assert!(max_error > 0.0 && max_error <= 0.2, "{max_error}");
    let stl = read_stl(&out_stl, &StlOptions::default()).unwrap();
    // 19 × 19 cells, two triangles each.
    assert_eq!(stl.facet_count, 2 * 19 * 19);
    assert_eq!(stl.mesh.triangles.len(), 2 * 19 * 19);
    assert_eq!(stl.mesh.positions.len(), 20 * 20);
    let mut worst = 0.0_f64;
    for p in &stl.mesh.positions {
        // Grid step 1 mm, origin 0: the vertex is node (row = y, col = x).
        let (r, c) = (p.y.round(), p.x.round());
        assert!((p.y - r).abs() < 1e-5 && (p.x - c).abs() < 1e-5, "{p}");
        let z = input.get(r as usize, c as usize).unwrap();
        worst = worst.max((p.z - z).abs());
    }
    // Binary STL stores f32: allow its rounding (heights ≤ 5 mm → ≤ 5e-7 mm).
    assert!(
        worst <= max_error + 1e-6,
        "STL vertex off by {worst}, reported max error {max_error}"
    );
    // The reported max error is attained by some vertex (it is measured at the same nodes).
    assert!(worst >= max_error - 1e-6, "{worst} vs {max_error}");
}

/// `talas reduce PART`: a STEP part's Z-map sampled through the mesh and refined onto the exact
/// face has the singular values of a Z-map sampled from the B-spline alone (Newton on x, y:
/// no mesh), so bicubic-hills is rank 2; the same part's STL carries its tessellation error
/// into the spectrum and needs far more terms for the same tolerance.
#[test]
fn reduce_a_part_samples_its_exact_zmap() {
    use glam::DVec2;
    use talas::geometry::zmap::{Grid, zmap_from_surface};
    let run = |file: &str| -> serde_json::Value {
        talas_json(&[
            "reduce",
            data(file).to_str().unwrap(),
            "--step",
            "2",
            "--tolerance",
            "0.01",
            "--json",
        ])
    };
    let step = run("bicubic-hills.stp");
    assert_eq!(
        (step["rows"].as_u64(), step["cols"].as_u64()),
        (Some(61), Some(81))
    );
    assert_eq!(step["zmap"]["exact_nodes"], 61 * 81);
    let part = common::hills_step();
    let reference = zmap_from_surface(
        &part.faces[0].surface,
        DVec2::ZERO,
        2.0,
        61,
        81,
        -1000.0,
        1e-9,
    )
    .unwrap();
    assert_eq!(reference.misses, 0);
    let sigma = talas::reduce::svd(&Grid::new(61, 81, reference.grid.values().to_vec()).unwrap())
        .unwrap()
        .singular_values;
    let got: Vec<f64> = step["singular_values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    for (k, (a, b)) in got.iter().zip(&sigma).enumerate() {
        assert!((a - b).abs() <= 1e-6 * sigma[0], "σ_{}: {a} vs {b}", k + 1);
    }
    assert_eq!(step["rank"], 2);
    assert!(step["max_error"].as_f64().unwrap() <= 1e-6);
    let stl = run("bicubic-hills.stl");
    assert_eq!(stl["zmap"]["exact_nodes"], 0);
    let stl_rank = stl["rank"].as_u64().unwrap();
    assert!(stl_rank > 10, "{stl_rank}");
    assert!(stl["max_error"].as_f64().unwrap() <= 0.01);
    // A Z-map file is still read as before; a part with a bad step names the option.
    let out = talas(&[
        "reduce",
        data("bicubic-hills.stl").to_str().unwrap(),
        "--step",
        "0",
        "--tolerance",
        "0.01",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bicubic-hills.stl") && err.contains("--step"),
        "{err}"
    );
}

/// `talas reduce PART --path`: a raster path on the reduced model (CL Z-map by inverse offset),
/// checked by the independent remaining-height check against the part's mesh: scallop within
/// the requested height plus the reduction tolerance on ≥ 99 % of the samples, no gouge.
#[test]
fn reduce_a_part_and_machine_the_reduced_model() {
    use glam::DVec2;
    use talas::checks::oracle::raster::{RemainingOptions, ball_remaining_height};
    use talas::toolpath::{MoveKind, Toolpath};
    let out_path =
        std::env::temp_dir().join(format!("talas-zmap-path-{}.json", std::process::id()));
    let doc = talas_json(&[
        "reduce",
        data("bicubic-hills.stp").to_str().unwrap(),
        "--step",
        "0.5",
        "--tolerance",
        "0.005",
        "--path",
        out_path.to_str().unwrap(),
        "--path-tool",
        "ball:d=6",
        "--scallop",
        "0.02",
        "--json",
    ]);
    let stepover = doc["path"]["stepover_mm"].as_f64().unwrap();
    assert!((stepover - 2.0 * (2.0 * 3.0 * 0.02 - 0.0004_f64).sqrt()).abs() < 1e-12);
    let tp = Toolpath::from_json(&std::fs::read_to_string(&out_path).unwrap(), "path").unwrap();
    assert!(tp.poses.iter().any(|p| p.kind == MoveKind::Cut));
    // The reference surface: the STEP part tessellated at 2 µm (the shipped STL's chordal sag
    // alone would read as several µm of gouge).
    let part = common::hills_step();
    let mesh = talas::geometry::tessellate::tessellate_part(
        &part,
        &talas::geometry::tessellate::TessellationOptions::with_chord_tol(0.002),
    )
    .mesh;
    let check = RemainingOptions {
        sample_spacing_mm: 0.6,
        max_slope_rad: 60f64.to_radians(),
        max_height_mm: 0.5,
        march_step_mm: 0.004,
        region: Some((DVec2::new(40.0, 30.0), DVec2::new(90.0, 70.0))),
    };
    let rep = ball_remaining_height(&mesh, &tp, &check).unwrap();
    let within = rep.fraction_within(0.02 + 0.005);
    eprintln!(
        "Z-map path: {} poses, stepover {stepover:.3} mm, samples {}, p50 {:.4} p99 {:.4} mm, within {within:.4}, gouge {:.2e} mm",
        tp.poses.len(),
        rep.samples(),
        rep.quantile(0.5),
        rep.quantile(0.99),
        rep.max_gouge_mm
    );
    assert!(rep.samples() > 1000);
    assert!(within >= 0.99, "{within}");
    // Left: the reference mesh's sag (2 µm), the path's chord tolerance (half the reduction
    // tolerance, 2.5 µm) and the linear moves between CL nodes.
    assert!(rep.max_gouge_mm <= 0.006, "{}", rep.max_gouge_mm);
    let _ = std::fs::remove_file(&out_path);
}
