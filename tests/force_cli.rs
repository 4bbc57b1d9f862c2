//! `talas forces --cut` and `talas calibrate`: the JSON contracts, the seeded coefficient
//! library, and bad input (one line naming the file or option, exit 2).

use std::process::Command;

use serde_json::Value;

const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/force/");
const LIBRARY: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/force/coefficients.toml"
);

fn talas(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(args)
        .output()
        .expect("run talas");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn talas_json(args: &[&str]) -> Value {
    let (code, out, err) = talas(args);
    assert_eq!(code, 0, "talas {args:?}: {err}");
    serde_json::from_str(&out).expect("one JSON document")
}

fn f(v: &Value) -> f64 {
    v.as_f64().expect("number")
}

#[test]
fn seeded_library_is_the_table_8_4_calibration() {
    let table = format!("{DATA}table_8_4.csv");
    let lib = talas::force::library::Library::load(std::path::Path::new(LIBRARY)).expect("asset");
    for mode in ["up", "down"] {
        let doc = talas_json(&[
            "calibrate",
            &table,
            "--model",
            "linear",
            "--mode",
            mode,
            "--json",
        ]);
        assert_eq!(doc["tests"], 6);
        let entry = lib.entries.iter().find(|e| e.mode == mode).expect("entry");
        let c = &doc["coefficients"];
        for (key, stored) in [
            ("ktc_n_mm2", entry.ktc_n_mm2),
            ("krc_n_mm2", entry.krc_n_mm2),
            ("kte_n_mm", entry.kte_n_mm),
            ("kre_n_mm", entry.kre_n_mm),
        ] {
            let (a, b) = (f(&c[key]), stored.expect(key));
            assert!(
                (a - b).abs() <= 1e-9 * b.abs().max(1.0),
                "{mode} {key}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn forces_of_table_8_4_test_1() {
    // Test 1 of Table 8.4/8.5: D = 12, 2 flutes, helix 30°, rake 15°, up milling, a_r = 6,
    // a_a = 18, f_t = 0.04; measured mean F_x −130.6, F_y 277 N; peaks −343.4, 525.4 N.
    let doc = talas_json(&[
        "forces",
        "--cut",
        "ae=6,ap=18,ft=0.04,mode=up",
        "--tool",
        "flat:d=12,flutes=2,helix=30,rake=15,flute=48,length=60",
        "--coefficients",
        LIBRARY,
        "--overhang",
        "48",
        "--rpm",
        "795.8",
        "--json",
    ]);
    let (mx, my) = (f(&doc["mean"]["fx"]), f(&doc["mean"]["fy"]));
    assert!((mx + 130.6).abs() < 0.15 * 130.6, "mean fx {mx}");
    assert!((my - 277.0).abs() < 0.1 * 277.0, "mean fy {my}");
    let (px, py) = (f(&doc["peak"]["fx"]), f(&doc["peak"]["fy"]));
    assert!(px < mx && px > -343.4, "peak fx {px}");
    assert!((py - 525.4).abs() < 0.1 * 525.4, "peak fy {py}");
    assert!(f(&doc["form_error_um"]) < 0.0, "up milling overcuts");
    assert!(f(&doc["mean_power_w"]) > 0.0);
    // Without --overhang there is no form error; down milling undercuts.
    let doc = talas_json(&[
        "forces",
        "--cut",
        "ae=6,ap=18,ft=0.04,mode=down",
        "--tool",
        "flat:d=12,flutes=2,helix=30,rake=5",
        "--coefficients",
        LIBRARY,
        "--json",
    ]);
    assert!(doc["form_error_um"].is_null());
    let doc = talas_json(&[
        "forces",
        "--cut",
        "ae=6,ap=18,ft=0.04,mode=down",
        "--tool",
        "flat:d=12,flutes=2,helix=30,rake=5",
        "--coefficients",
        LIBRARY,
        "--overhang",
        "48",
        "--json",
    ]);
    assert!(f(&doc["form_error_um"]) > 0.0, "down milling undercuts");
    // The human summary carries units.
    let (code, out, _) = talas(&[
        "forces",
        "--cut",
        "mode=slot,ap=5,ft=0.05",
        "--tool",
        "flat:d=12,flutes=3",
        "--coefficients",
        LIBRARY,
        "--material",
        "al7075-t651",
    ]);
    assert_eq!(code, 2, "no slot entry in the library: {out}");
}

#[test]
fn calibrate_writes_a_library_forces_reads() {
    let dir = std::env::temp_dir().join(format!("talas-force-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let out = dir.join("coef.toml");
    let table = format!("{DATA}table_8_4.csv");
    let doc = talas_json(&[
        "calibrate",
        &table,
        "--model",
        "exponential",
        "--mode",
        "down",
        "-o",
        out.to_str().expect("path"),
        "--material",
        "Al7075-T651",
        "--json",
    ]);
    assert_eq!(doc["coefficients"]["model"], "exponential");
    assert!(f(&doc["mean_error_pct"]["fy"]) < 15.0, "{doc}");
    let forces = talas_json(&[
        "forces",
        "--cut",
        "ae=4,ap=12,ft=0.08,mode=down",
        "--tool",
        "flat:d=8,flutes=2,helix=30,rake=15",
        "--coefficients",
        out.to_str().expect("path"),
        "--json",
    ]);
    assert_eq!(forces["model"], "exponential");
    // Test 11: measured mean F_y 373 N.
    assert!(
        (f(&forces["mean"]["fy"]) - 373.0).abs() < 0.2 * 373.0,
        "{forces}"
    );
    let (code, human, _) = talas(&["calibrate", &table, "--model", "linear"]);
    assert_eq!(code, 0);
    assert!(
        human.contains("ktc_n_mm2") && human.contains('%'),
        "{human}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let dir = std::env::temp_dir().join(format!("talas-force-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let csv = dir.join("bad.csv");
    std::fs::write(&csv, "d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n\n12,2,30,15,up,6,18,0.04,-130,277\n12,2,30,15,up,6,x,0.08,-260,520\n").expect("write");
    let lib = dir.join("lib.toml");
    std::fs::write(
        &lib,
        "[[entry]]\nmaterial = \"x\"\nmodel = \"linear\"\nktc_n_mm2 = \"a\"\n",
    )
    .expect("write");
    let csv_s = csv.to_str().expect("path");
    let lib_s = lib.to_str().expect("path");
    // A program cutting the stock with a feed but no spindle speed (no S, no --rpm).
    let ngc = dir.join("no-s.ngc");
    std::fs::write(
        &ngc,
        "G21 G90 G94\nG0 Z5\nG0 X-20 Y0\nG1 Z-3 F500\nG1 X20\nM30\n",
    )
    .expect("write");
    let ngc_s = ngc.to_str().expect("path");
    let tool = "flat:d=10,flutes=2,helix=30";
    let stock = "box:-10,-10,-10,10,10,0";
    for (args, needle) in [
        (
            vec![
                "forces",
                ngc_s,
                "--tool",
                tool,
                "--coefficients",
                LIBRARY,
                "--stock",
                stock,
            ],
            "line 5",
        ),
        (
            vec!["forces", ngc_s, "--tool", tool, "--coefficients", LIBRARY],
            "--stock",
        ),
        (
            vec![
                "forces",
                ngc_s,
                "--tool",
                tool,
                "--coefficients",
                LIBRARY,
                "--stock",
                stock,
                "--rpm",
                "3000",
                "--schedule-force",
                "100",
            ],
            "-o OUT.json",
        ),
        (
            vec![
                "forces",
                ngc_s,
                "--tool",
                tool,
                "--coefficients",
                LIBRARY,
                "--stock",
                stock,
                "--rpm",
                "3000",
                "--sample-spacing",
                "0",
            ],
            "sample spacing",
        ),
        (vec!["calibrate", csv_s, "--model", "linear"], "line 3"),
        (
            vec![
                "forces",
                "--cut",
                "ae=6,ap=18,ft=0.04",
                "--tool",
                "flat:d=12,flutes=2",
                "--coefficients",
                LIBRARY,
            ],
            "--cut",
        ),
        (
            vec![
                "forces",
                "--cut",
                "ae=16,ap=18,ft=0.04,mode=up",
                "--tool",
                "flat:d=12,flutes=2",
                "--coefficients",
                LIBRARY,
            ],
            "radial depth",
        ),
        (
            vec![
                "forces",
                "--cut",
                "ae=6,ap=18,ft=0.04,mode=up",
                "--tool",
                "flat:d=12",
                "--coefficients",
                LIBRARY,
            ],
            "flutes=N",
        ),
        (
            vec![
                "forces",
                "--cut",
                "ae=6,ap=18,ft=0.04,mode=up",
                "--tool",
                "flat:d=12,flutes=2",
                "--coefficients",
                lib_s,
            ],
            "line 4",
        ),
        (
            vec![
                "forces",
                "--cut",
                "ae=6,ap=18,ft=0.04,mode=up",
                "--tool",
                "flat:d=12,flutes=2",
                "--coefficients",
                LIBRARY,
                "--overhang=-3",
            ],
            "overhang",
        ),
    ] {
        let (code, out, err) = talas(&args);
        assert_eq!(code, 2, "{args:?}: {out}");
        assert_eq!(err.trim().lines().count(), 1, "{err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `talas forces PROGRAM`: a slot along x through a box, with the spindle speed from `--rpm`:
/// the per-move JSON (machine frame) and the totals.
#[test]
fn forces_along_a_program() {
    let dir = std::env::temp_dir().join(format!("talas-force-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let ngc = dir.join("slot.ngc");
    std::fs::write(
        &ngc,
        "G21 G90 G94\nG0 Z5\nG0 X-20 Y0\nG1 Z-3 F600\nG1 X20\nG0 Z5\nM30\n",
    )
    .expect("write");
    let doc = talas_json(&[
        "forces",
        ngc.to_str().expect("path"),
        "--tool",
        "flat:d=10,flute=20,flutes=2,helix=30,rake=10",
        "--coefficients",
        LIBRARY,
        "--stock",
        "box:-10,-10,-10,10,10,0",
        "--rpm",
        "3000",
        "--max-power",
        "1",
        "--json",
    ]);
    let moves = doc["moves"].as_array().expect("moves");
    let slot = moves.iter().find(|m| m["line"] == 5).expect("line 5");
    assert_eq!(slot["class"], "cut");
    assert!((f(&slot["feed_per_tooth_mm"]) - 0.1).abs() < 1e-12);
    // Up to 3 mm deep: six disks of 0.5 mm engaged at the heaviest piece, on the front half.
    let imm = slot["immersion"].as_array().expect("immersion");
    assert_eq!(imm.len(), 6, "{imm:?}");
    assert!(imm.iter().all(|d| {
        let (a, b) = (f(&d["entry_deg"]), f(&d["exit_deg"]));
        (0.0..b).contains(&a) && b <= 180.0 + 1e-9
    }));
    assert!(f(&slot["peak_resultant_n"]) > 0.0);
    assert!(f(&slot["mean_power_w"]) > 0.0);
    assert_eq!(slot["limits_exceeded"][0], "power");
    let plunge = moves.iter().find(|m| m["line"] == 4).expect("line 4");
    assert_eq!(plunge["class"], "plunge");
    assert_eq!(doc["totals"]["cutting_moves"], 1);
    assert_eq!(doc["totals"]["peak_resultant_block"], 5);
    std::fs::remove_dir_all(&dir).ok();
}

/// `talas speeds`: the hand-worked 6061 case (D10, 3 flutes, a_e 1 mm = 10 %, a_p 15 mm):
/// n = 300 000/(10π) = 9549.3 rpm, f_z = 0.08 × 1/√(1 − 0.8²) = 0.13333 mm, v_f = 3819.7
/// mm/min; the capped spindle; and bad options named.
#[test]
fn speeds_command_gives_the_hand_worked_numbers_and_names_bad_options() {
    let doc = talas_json(&[
        "speeds",
        "--material",
        "Al6061-T6",
        "--tool",
        "flat:d=10,flutes=3,helix=35,length=40,flute=22",
        "--ae",
        "1",
        "--ap",
        "15",
        "--json",
    ]);
    let s = &doc["speeds"];
    let rel = |got: f64, want: f64| ((got - want) / want).abs() < 1e-3;
    assert!(rel(f(&s["spindle_rpm"]), 9549.297), "{s}");
    assert!(rel(f(&s["feed_per_tooth_mm"]), 0.133_333), "{s}");
    assert!(rel(f(&s["feed_mm_min"]), 3819.719), "{s}");
    assert!(f(&doc["load"]["mean_power_w"]) > 0.0, "{doc}");
    let capped = talas_json(&[
        "speeds",
        "--material",
        "6061",
        "--tool",
        "flat:d=10,flutes=3",
        "--max-rpm",
        "6000",
        "--json",
    ]);
    assert!(rel(f(&capped["speeds"]["spindle_rpm"]), 6000.0), "{capped}");
    assert!(rel(
        f(&capped["speeds"]["cutting_speed_m_min"]),
        std::f64::consts::PI * 10.0 * 6.0
    ));
    let (code, out, _) = talas(&["speeds", "--list"]);
    assert_eq!(code, 0);
    for key in [
        "6061", "7075", "1045", "4140", "304", "ti64", "brass", "acetal",
    ] {
        assert!(out.contains(key), "{out}");
    }
    for (args, what) in [
        (
            vec!["--material", "unobtainium", "--tool", "flat:d=10"],
            "--material",
        ),
        (
            vec!["--material", "6061", "--tool", "flat:d=10", "--ae", "20"],
            "radial",
        ),
        (
            vec![
                "--material",
                "6061",
                "--tool",
                "flat:d=10",
                "--tool-material",
                "cermet",
            ],
            "--tool-material",
        ),
    ] {
        let mut a = vec!["speeds"];
        a.extend(args);
        let (code, _, err) = talas(&a);
        assert_eq!(code, 2, "{a:?}");
        assert!(
            err.contains(what) && err.lines().count() == 1,
            "{a:?}: {err}"
        );
    }
}
