//! `talas interpret`: the canonical motion as JSON (moves with their lines, kinds, ends,
//! arc centres, planes and turns; dwells, warnings, errors) or a summary; a program that does
//! not read gives one line on stderr naming the file, line and column, and exit code 2.

use std::process::Command;

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

#[test]
fn talas_interpret_prints_the_canonical_motion() {
    let (code, out, err) = talas(&[
        "interpret",
        "tests/data/gcode/hand-comp-g41-square.ngc",
        "--tool-table",
        "tests/data/gcode/hand-comp-g41-square.tbl",
        "--tool-table-units",
        "inch",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    let moves = doc["moves"].as_array().unwrap();
    assert_eq!(doc["syntax"], "rs274");
    assert!(
        moves
            .iter()
            .any(|m| m["kind"] == "arc" && m["plane"] == "XY" && m["turn"] == -1)
    );
    assert!(
        moves
            .iter()
            .all(|m| m["line"].as_u64().is_some() && m["end"]["X"].is_f64())
    );
    assert!(
        moves.iter().all(|m| m["end"].get("A").is_none()),
        "no rotary axis used"
    );
    assert!(doc["errors"].as_array().unwrap().is_empty());
    // The human summary.
    let (code, out, _) = talas(&["interpret", "tests/data/gcode/hand-oword-loops.ngc"]);
    assert_eq!(code, 0);
    assert!(out.contains("moves"), "{out}");
    // Talas's Siemens output reads without --syntax.
    let (code, out, err) = talas(&["interpret", "tests/data/post/small-siemens.ngc", "--json"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("\"syntax\":\"siemens\""), "{out}");
    // A program that does not read: one line on stderr naming file, line and column, exit 2,
    // and the moves before the error still in the JSON.
    let dir = std::env::temp_dir().join(format!("talas-interpret-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.ngc");
    std::fs::write(&bad, "G0 X1\nG1 X100 F0\n").unwrap();
    let (code, out, err) = talas(&["interpret", bad.to_str().unwrap(), "--json"]);
    assert_eq!(code, 2);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.contains("bad.ngc") && err.contains("line 2, column 9"),
        "{err}"
    );
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(doc["moves"].as_array().unwrap().len(), 1);
    assert_eq!(doc["errors"][0]["line"], 2);
    let (code, _, err) = talas(&["interpret", bad.to_str().unwrap(), "--syntax", "mazak"]);
    assert_eq!(code, 2);
    assert!(err.contains("--syntax"), "{err}");
    let tbl = dir.join("bad.tbl");
    std::fs::write(&tbl, "T1 D6\nX3\n").unwrap();
    let (code, _, err) = talas(&[
        "interpret",
        bad.to_str().unwrap(),
        "--tool-table",
        tbl.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("bad.tbl") && err.contains("line 2"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
