//! `talas simulate` starts where the machine does (issue 35): a posted program's first `G0 Z100`
//! from an uncommanded start at the origin, inside the stock, was a phantom rapid collision
//! and gouge. The moves from the start to the first position the program commands in X, Y
//! and Z are not simulated; `--start X,Y,Z` sets the start (it matters to a program that only
//! moves incrementally).
//!
//! `cargo test --no-default-features --test simulate_start`

use std::process::Command;

use serde_json::Value;

fn simulate(dir: &std::path::Path, program: &str, extra: &[&str]) -> Value {
    let file = dir.join("p.ngc");
    std::fs::write(&file, program).unwrap();
    let mut args = vec![
        "simulate",
        file.to_str().unwrap(),
        "--tool",
        "flat:d=6",
        "--stock",
        "box:-20,-20,0,40,40,10",
        "--resolution",
        "0.5",
        "--json",
    ];
    args.extend_from_slice(extra);
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(&args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn the_lead_in_from_the_start_is_not_a_cut() {
    let dir = std::env::temp_dir().join(format!("talas-simstart-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The origin lies inside the stock: a rapid from there up to Z100 would cross it.
    let program = "G21 G90 G17\nG0 Z100\nG0 X10 Y10\nG0 Z12\nG1 Z8 F300\nG1 X20\nG0 Z100\n";
    for extra in [&[][..], &["--start", "0,0,50"][..], &["--start=-5,3,2"][..]] {
        let doc = simulate(&dir, program, extra);
        let collisions = doc["collisions"].as_array().unwrap();
        assert!(collisions.is_empty(), "{extra:?}: {collisions:?}");
        // G0 Z100 and G0 X10 Y10 (the move into the first commanded position) are left out.
        assert_eq!(doc["moves"].as_u64(), Some(4), "{extra:?}");
        // The cut is there: a 6 mm slot 10 mm long and 2 mm deep, plus the plunge.
        let removed = doc["removed_volume_mm3"].as_f64().unwrap();
        let want = 2.0 * (6.0 * 10.0 + std::f64::consts::PI * 9.0);
        assert!(
            (removed - want).abs() < 0.1 * want,
            "{extra:?}: {removed} vs {want} mm³"
        );
    }
    // An incremental program commands no absolute position: it runs from --start.
    let doc = simulate(&dir, "G91 G1 X5 F300\n", &["--start", "0,0,8"]);
    assert_eq!(doc["moves"].as_u64(), Some(1));
    assert!(doc["removed_volume_mm3"].as_f64().unwrap() > 0.0);
    // A bad --start is one clear error.
    let file = dir.join("p.ngc");
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["simulate", file.to_str().unwrap(), "--tool", "flat:d=6"])
        .args([
            "--stock",
            "box:0,0,0,1,1,1",
            "--resolution",
            "0.5",
            "--start",
            "1,2",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--start"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}
