//! `talas inspect` against Open CASCADE's own evaluation of the shared parts
//! (tests/data/*.samples.csv and the reference table in tests/data/README.md).

mod common;

use std::path::Path;

use common::data;
use std::process::Command;

use serde_json::Value;

fn inspect_json(file: &Path, extra: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .arg("inspect")
        .arg(file)
        .args(extra)
        .arg("--json")
        .output()
        .expect("run talas");
    assert!(
        out.status.success(),
        "inspect {} failed: {}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("inspect prints one JSON document")
}

fn reference_rows(name: &str) -> Vec<[f64; 10]> {
    let text = std::fs::read_to_string(data(name)).expect("reference samples");
    text.lines()
        .skip(1)
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| x.trim().parse().expect("number"))
                .collect();
            let mut row = [0.0; 10];
            row.copy_from_slice(&v[..10]);
            row
        })
        .collect()
}

/// Compare the 21×21 samples of the single face of `step` with OCCT's, returning the worst
/// position, normal and curvature differences.
fn compare_samples(step: &str, csv: &str) -> (f64, f64, f64) {
    let doc = inspect_json(&data(step), &["--samples", "21"]);
    let faces = doc["faces"].as_array().expect("faces");
    assert_eq!(faces.len(), 1);
    let samples = faces[0]["samples"].as_array().expect("samples");
    let reference = reference_rows(csv);
    assert_eq!(samples.len(), reference.len());
    let (mut dp, mut dn, mut dk) = (0.0f64, 0.0f64, 0.0f64);
    for (s, r) in samples.iter().zip(&reference) {
        let s: Vec<f64> = s
            .as_array()
            .expect("row")
            .iter()
            .map(|x| x.as_f64().expect("finite sample"))
            .collect();
        assert!(
            (s[0] - r[0]).abs() < 1e-9 && (s[1] - r[1]).abs() < 1e-9,
            "grid parameters differ: {s:?} vs {r:?}"
        );
        for k in 2..5 {
            dp = dp.max((s[k] - r[k]).abs());
        }
        // Samples report the surface normal S_u × S_v, as OCCT does: same direction expected.
        for k in 5..8 {
            dn = dn.max((s[k] - r[k]).abs());
        }
        for k in 8..10 {
            dk = dk.max((s[k] - r[k]).abs());
        }
    }
    (dp, dn, dk)
}

#[test]
fn bicubic_hills_samples_match_open_cascade() {
    let (dp, dn, dk) = compare_samples("bicubic-hills.stp", "bicubic-hills.samples.csv");
    assert!(dp < 1e-6, "position differs by {dp} mm");
    assert!(dn < 1e-6, "normal differs by {dn}");
    assert!(dk < 1e-6, "curvature differs by {dk} 1/mm");
}

#[test]
fn rational_trough_samples_match_open_cascade() {
    let (dp, dn, dk) = compare_samples("rational-trough.stp", "rational-trough.samples.csv");
    assert!(dp < 1e-6, "position differs by {dp} mm");
    assert!(dn < 1e-6, "normal differs by {dn}");
    assert!(dk < 1e-6, "curvature differs by {dk} 1/mm");
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn single_face_parts_have_reference_area_and_box() {
    for (file, area, min, max, rational) in [
        (
            "bicubic-hills.stp",
            19710.4308,
            [0.0, 0.0, -11.6358],
            [160.0, 120.0, 11.6678],
            false,
        ),
        (
            "rational-trough.stp",
            12672.0,
            [-49.2347, -74.8618, 0.0],
            [43.0414, 74.8618, 18.1976],
            true,
        ),
    ] {
        let doc = inspect_json(&data(file), &[]);
        let face = &doc["faces"][0];
        assert_eq!(face["kind"], "bspline");
        assert_eq!(face["rational"], rational, "{file}");
        let a = doc["area_mm2"].as_f64().expect("area");
        assert!(rel(a, area) < 1e-3, "{file}: area {a} vs {area}");
        let bmin: Vec<f64> = doc["bbox"]["min"]
            .as_array()
            .expect("bbox")
            .iter()
            .filter_map(Value::as_f64)
            .collect();
        let bmax: Vec<f64> = doc["bbox"]["max"]
            .as_array()
            .expect("bbox")
            .iter()
            .filter_map(Value::as_f64)
            .collect();
        for k in 0..3 {
            assert!((bmin[k] - min[k]).abs() < 0.02, "{file}: bbox min {bmin:?}");
            assert!((bmax[k] - max[k]).abs() < 0.02, "{file}: bbox max {bmax:?}");
        }
        assert!(doc["triangles"].as_u64().unwrap_or(0) > 100);
    }
    let trough = inspect_json(&data("rational-trough.stp"), &[]);
    assert_eq!(trough["faces"][0]["degree"], serde_json::json!([2, 2]));
}

#[test]
fn pocket_fillets_is_a_closed_solid_of_the_right_area_and_volume() {
    let doc = inspect_json(&data("pocket-fillets.stp"), &[]);
    let faces = doc["faces"].as_array().expect("faces");
    assert_eq!(faces.len(), 23);
    let count = |k: &str| faces.iter().filter(|f| f["kind"] == k).count();
    assert_eq!(
        (count("plane"), count("cylinder"), count("sphere")),
        (11, 8, 4)
    );
    for f in faces {
        assert!(
            f["area_mm2"].as_f64().unwrap_or(0.0) > 0.0,
            "face {} has no triangles",
            f["id"]
        );
    }
    let area = doc["area_mm2"].as_f64().expect("area");
    assert!(rel(area, 29249.3361) < 1e-3, "area {area}");
    assert_eq!(doc["closed"], true, "tessellation is not closed");
    let volume = doc["volume_mm3"].as_f64().expect("volume");
    assert!(rel(volume, 205311.2098) < 5e-3, "volume {volume}");
}

#[test]
fn human_summary_names_faces_and_units() {
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["inspect"])
        .arg(data("pocket-fillets.stp"))
        .output()
        .expect("run talas");
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("faces: 23"), "{text}");
    assert!(
        text.contains("mm²") && text.contains("closed: true"),
        "{text}"
    );
}
