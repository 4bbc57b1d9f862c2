//! `talas control`: a script of operator actions run headless; the JSON contract
//! (`machine_position`, `work_position`, `time_s`, `alarms`, `removed_volume_mm3`, `peaks`,
//! `actions`), the same removed volume as `talas simulate`, and bad script lines (exit 2, one
//! line naming the script and the line).

mod common;

use common::{talas, talas_json, temp_file};

const PROGRAM: &str = "G21 G90 G17\nG0 Z10\nG0 X-20 Y-20\nM3 S8000\nG1 Z-2 F300\n\
G1 X20 F1200\nY0\nG3 X0 Y20 I-20 J0\nG1 X-20 Y0\nG2 X-20 Y-20 I0 J-10\nG0 Z10\nM30\n";

const SCRIPT: &str = "# jog, MDI, then the program with a feed hold\nhome\nmode jog\n\
jog X -0.01\njog-continuous X + 100\nmode mdi\nmdi G0 X0 Y0 Z20\nmdi G0 X500\nmode auto\n\
cycle-start\nwait 2\nhold\nwait 0.5\nresume\n";

#[test]
fn script_runs_jogs_mdi_and_auto_and_cuts_what_simulate_cuts() {
    let prog = temp_file("control-cli", "pocket.ngc", PROGRAM);
    let script = temp_file("control-cli", "script.txt", SCRIPT);
    let stock = "box:-30,-30,-10,30,30,0";
    let doc = talas_json(&[
        "control",
        "--machine",
        "mill-3axis",
        "--stock",
        stock,
        "--tool",
        "flat:d=6",
        "--resolution",
        "0.25",
        "--program",
        prog.to_str().unwrap(),
        "--script",
        script.to_str().unwrap(),
        "--json",
    ]);
    let pos = &doc["machine_position"];
    assert_eq!(
        (pos["X"].as_f64(), pos["Y"].as_f64(), pos["Z"].as_f64()),
        (Some(-20.0), Some(-20.0), Some(10.0))
    );
    assert_eq!(doc["work_position"]["Z"].as_f64(), Some(10.0));
    let actions = doc["actions"].as_array().unwrap();
    assert_eq!(actions.len(), 13);
    // The continuous jog ran into the soft limit; the MDI move beyond the travel was refused.
    assert_eq!(actions[3]["alarm"]["code"].as_u64(), Some(10));
    assert_eq!(actions[3]["alarm"]["axis"].as_str(), Some("X"));
    assert_eq!(actions[6]["alarm"]["code"].as_u64(), Some(11));
    assert!(actions[0]["alarm"].is_null());
    assert_eq!(doc["alarms"].as_array().unwrap().len(), 2);
    let peaks = &doc["peaks"];
    for (axis, v, a, j) in [("X", 500.0, 2000.0, 25000.0), ("Z", 400.0, 2000.0, 25000.0)] {
        assert!(peaks[axis]["velocity"].as_f64().unwrap() <= v * 1.001);
        assert!(peaks[axis]["acceleration"].as_f64().unwrap() <= a * 1.001);
        assert!(peaks[axis]["jerk"].as_f64().unwrap() <= j * 1.001);
    }
    let sim = talas_json(&[
        "simulate",
        prog.to_str().unwrap(),
        "--stock",
        stock,
        "--tool",
        "flat:d=6",
        "--resolution",
        "0.25",
        "--json",
    ]);
    let (got, want) = (
        doc["removed_volume_mm3"].as_f64().unwrap(),
        sim["removed_volume_mm3"].as_f64().unwrap(),
    );
    assert!(
        want > 500.0 && ((got - want) / want).abs() < 1e-3,
        "{got} vs {want} mm³"
    );
    assert!(doc["time_s"].as_f64().unwrap() > 100.0);
}

#[test]
fn bad_script_lines_name_the_script_and_line() {
    for (text, needle) in [
        ("home\njog Q 1\n", "line 2"),
        ("wait -1\n", "line 1"),
        ("override feed\n", "line 1"),
        ("fly away\n", "unknown action"),
    ] {
        let script = temp_file("control-cli-bad", "bad.txt", text);
        let out = talas(&[
            "control",
            "--machine",
            "mill-3axis",
            "--script",
            script.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("bad.txt") && err.contains(needle), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    let script = temp_file("control-cli-bad", "ok.txt", "home\n");
    let out = talas(&[
        "control",
        "--machine",
        "mill-3axis",
        "--stock",
        "box:0,0,0,1,1,1",
        "--script",
        script.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--tool"));
}
