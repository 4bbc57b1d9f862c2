//! `talas profile` through the command line: the JSON keys, G-code with arcs that the
//! interpreter reads back onto the path, and bad input giving exit code 2 with one line naming
//! the file and the row.

mod common;
use common::{talas, talas_json, temp_file};

const V_NOTCH: &str = "# a V notch\nx,y\n-6,4\n-3,4\n0,0\n3,4\n6,4\n";

#[test]
fn json_has_the_contract_keys_and_the_v_notch_plunge() {
    let f = temp_file("profile-cli", "v.csv", V_NOTCH);
    let doc = talas_json(&["profile", f.to_str().unwrap(), "--radius", "1", "--json"]);
    let cl = doc["cl"].as_array().unwrap();
    assert!(cl.len() >= 4);
    assert_eq!(doc["contacts"].as_array().unwrap().len(), cl.len());
    let plunges = doc["plunges"].as_array().unwrap();
    // The vertex at the bottom: depth R(1 − 3/5).
    let bottom = plunges
        .iter()
        .find(|p| p["x"] == 0.0 && p["y"] == 0.0)
        .unwrap();
    assert!((bottom["depth"].as_f64().unwrap() - 0.4).abs() < 1e-12);
    assert!(doc["collisions"].is_array());
    assert_eq!(doc["max_gouge_free_radius"], 0.0);
    // Every CL point is 1 mm from its contact.
    for (c, q) in cl.iter().zip(doc["contacts"].as_array().unwrap()) {
        let d = ((c[0].as_f64().unwrap() - q[0].as_f64().unwrap()).powi(2)
            + (c[1].as_f64().unwrap() - q[1].as_f64().unwrap()).powi(2))
        .sqrt();
        assert!((d - 1.0).abs() < 1e-9, "{d}");
    }
}

#[test]
fn gcode_arcs_read_back_onto_the_path_in_every_plane() {
    // A closed rounded shape: the outside path has arcs at every corner.
    let f = temp_file("profile-cli", "sq.csv", "0,0\n10,0\n10,10\n0,10\n0,0\n");
    let doc = talas_json(&[
        "profile",
        f.to_str().unwrap(),
        "--radius",
        "2",
        "--side",
        "outside",
        "--json",
    ]);
    let len: f64 = doc["pieces"][0]["length_mm"].as_f64().unwrap();
    assert!((len - (40.0 + 4.0 * std::f64::consts::PI)).abs() < 1e-9);
    for (plane, dialect) in [
        ("g17", "linuxcnc"),
        ("g18", "fanuc"),
        ("g19", "grbl"),
        ("g18", "siemens"),
    ] {
        let out = temp_file("profile-cli", &format!("sq-{plane}-{dialect}.ngc"), "");
        let o = talas(&[
            "profile",
            f.to_str().unwrap(),
            "--radius",
            "2",
            "--side",
            "outside",
            "--plane",
            plane,
            "--dialect",
            dialect,
            "-o",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(text.contains(&plane.to_uppercase()), "{text}");
        let syntax = talas::gcode::Syntax::from_name(dialect).unwrap();
        let prog =
            talas::gcode::interpret(&text, &talas::gcode::InterpretOptions::for_syntax(syntax))
                .unwrap();
        // Cutting length: the feed-in from the clearance plus the path; the path alone is the
        // feed moves after the first, which must match the exact length (a wrong arc sense
        // would go the long way round).
        let fed: Vec<_> = prog
            .blocks
            .iter()
            .filter(|b| !matches!(b.kind, talas::gcode::MotionKind::Rapid))
            .collect();
        let path_len: f64 = fed.iter().skip(1).map(|b| b.length_mm()).sum();
        assert!(
            (path_len - len).abs() < 1e-3,
            "{plane} {dialect}: {path_len} vs {len}"
        );
        let arcs = fed
            .iter()
            .filter(|b| {
                matches!(
                    b.kind,
                    talas::gcode::MotionKind::ArcCw(_) | talas::gcode::MotionKind::ArcCcw(_)
                )
            })
            .count();
        assert_eq!(arcs, 4, "{plane} {dialect}");
        // Deterministic bytes.
        let again = temp_file("profile-cli", &format!("sq-{plane}-{dialect}-2.ngc"), "");
        let _ = talas(&[
            "profile",
            f.to_str().unwrap(),
            "--radius",
            "2",
            "--side",
            "outside",
            "--plane",
            plane,
            "--dialect",
            dialect,
            "-o",
            again.to_str().unwrap(),
        ]);
        assert_eq!(text, std::fs::read_to_string(&again).unwrap());
    }
}

#[test]
fn bad_rows_name_the_file_and_row() {
    let f = temp_file("profile-cli", "bad.csv", "x,y\n0,0\n1,abc\n2,0\n");
    let o = talas(&["profile", f.to_str().unwrap(), "--radius", "1"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.csv: row 3:") && err.contains("not a number"),
        "{err}"
    );
    assert_eq!(err.lines().count(), 1);

    let f = temp_file("profile-cli", "dup.csv", "0,0\n1,1\n1,1\n");
    let o = talas(&["profile", f.to_str().unwrap(), "--radius", "1"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("row 3: repeats the previous point"));

    let f = temp_file("profile-cli", "ok.csv", V_NOTCH);
    for r in ["0", "-1", "nan", "1e9"] {
        let o = talas(&["profile", f.to_str().unwrap(), &format!("--radius={r}")]);
        assert_eq!(o.status.code(), Some(2), "radius {r}");
        assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
    }
    let o = talas(&[
        "profile",
        f.to_str().unwrap(),
        "--radius",
        "1",
        "--side",
        "inside",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("closed profile"));
}

#[test]
fn dxf_and_svg_inputs() {
    // SVG: a slot drawn with a circular arc (y down in SVG).
    let svg = temp_file(
        "profile-cli",
        "slot.svg",
        "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<path d=\"M -10 0 H -1 V 8 A 1 1 0 0 0 1 8 V 0 H 10\"/>\n</svg>\n",
    );
    let doc = talas_json(&[
        "profile",
        svg.to_str().unwrap(),
        "--radius",
        "0.5",
        "--json",
    ]);
    assert_eq!(doc["max_gouge_free_radius"], 1.0);
    // DXF written by the engine and read back by the command.
    let p = talas::profile::parse_svg(&std::fs::read_to_string(&svg).unwrap(), "slot.svg", 1e-3)
        .unwrap();
    let dxf =
        std::env::temp_dir().join(format!("talas-profile-cli-{}/slot.dxf", std::process::id()));
    talas::profile::write_profile(&p, &dxf).unwrap();
    let doc2 = talas_json(&[
        "profile",
        dxf.to_str().unwrap(),
        "--radius",
        "0.5",
        "--json",
    ]);
    assert_eq!(doc["cl"], doc2["cl"]);
}
