//! Homing ends at the machine's home, above everything, on every built-in machine (issue 35):
//! with a stock on the table and a tool in the spindle, "Home all" raises no alarm and ends at
//! the home position (Z at the top of its travel, the other linear axes at their switches),
//! and jogs from there do not collide. (On trt-ac and trt-bc the homing of an axis already at
//! its switch, a motion of no length, put the tool at X0 Y0 Z0 inside the rotary table:
//! alarm 43 at t = 0.)
//!
//! `cargo test --no-default-features --test control_home`

use std::process::Command;

use serde_json::Value;

#[test]
fn home_all_ends_clear_on_every_machine() {
    let dir = std::env::temp_dir().join(format!("talas-home-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = dir.join("home.txt");
    std::fs::write(&script, "home\nmode jog\njog Z -5\njog X -10\njog Y -10\n").unwrap();
    for name in ["mill-3axis", "trt-ac", "trt-bc"] {
        let machine = talas::machine::Machine::builtin(name).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_talas"))
            .args([
                "control",
                "--machine",
                name,
                "--stock",
                "cylinder:0,0,42,-3.25,18.83",
                "--tool",
                "ball:d=6",
                "--script",
                script.to_str().unwrap(),
                "--json",
            ])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{name}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
        let alarms = doc["alarms"].as_array().unwrap();
        assert!(alarms.is_empty(), "{name}: {alarms:?}");
        for a in doc["actions"].as_array().unwrap() {
            assert!(
                a["refused"].is_null() && a["alarm"].is_null(),
                "{name}: {a}"
            );
        }
        let homed = doc["homed"].as_object().unwrap();
        assert!(homed.values().all(|h| h == true), "{name}: {homed:?}");
        // After the jogs: every linear axis 10 mm (Z 5 mm) below its top, the rotaries at 0.
        let pos = doc["machine_position"].as_object().unwrap();
        for a in &machine.axes {
            let want = match a.name {
                'Z' => a.max - 5.0,
                'X' | 'Y' => a.max - 10.0,
                _ => 0.0,
            };
            let got = pos[&a.name.to_string()].as_f64().unwrap();
            assert!(
                (got - want).abs() < 1e-6,
                "{name} {}: {got} vs {want}",
                a.name
            );
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
