//! Dialect files that would crash the post or write programs Talas cannot read are refused when
//! they are loaded, with the file and the field or the failure named (issue 36's findings);
//! every dialect that loads posts programs that read back.

use glam::DVec3;
use std::f64::consts::FRAC_PI_2;
use talas::gcode::{InterpretOptions, Syntax, interpret};
use talas::machine::Machine;
use talas::post::{Dialect, PostOptions, post};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::parse_tool_spec;

fn refused(text: &str) -> String {
    match Dialect::from_json(text, "shop.json") {
        Ok(d) => panic!("{text} loaded: {d:?}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn dialect_numbers_out_of_bounds_are_refused_naming_file_and_field() {
    // Issue 36: 65 536 places panicked in the number formatter.
    let e = refused(r#"{"name": "x", "decimals_inverse_time": 65536}"#);
    assert!(
        e.contains("shop.json") && e.contains("decimals_inverse_time = 65536"),
        "{e}"
    );
    // Issue 36: 0 places rounded every coordinate to 1 mm without a word.
    let e = refused(r#"{"name": "x", "decimals_linear": 0}"#);
    assert!(
        e.contains("decimals_linear = 0") && e.contains("1 mm"),
        "{e}"
    );
    for (field, value) in [
        ("decimals_angle", "7"),
        ("decimals_feed", "5"),
        ("line_number_step", "0"),
        ("arc_max_sweep_deg", "720"),
        ("arc_max_radius_mm", "-1"),
    ] {
        let e = refused(&format!(r#"{{"name": "x", "{field}": {value}}}"#));
        assert!(e.contains(field) && e.contains("shop.json"), "{e}");
    }
    let e = refused(r#"{"name": "x", "arc_planes": ["G17", "G20"]}"#);
    assert!(e.contains("arc_planes"), "{e}");
    let e = refused(r#"{"name": "x", "rapid": "G0\nM30"}"#);
    assert!(e.contains("rapid"), "{e}");
    let e = refused(r#"{"name": "x", "decimals_linear": 18446744073709551616}"#);
    assert!(e.contains("shop.json"), "{e}");
}

#[test]
fn dialects_whose_programs_do_not_read_back_are_refused() {
    for (text, what) in [
        // Feed moves written as rapids: the kinds come back wrong.
        (r#"{"name": "x", "linear": "G0"}"#, "rapid"),
        // Comments without marks are read as words.
        (
            r#"{"name": "x", "comment_open": "", "comment_close": ""}"#,
            "line",
        ),
        // An arc code the reader takes for something else.
        (r#"{"name": "x", "arc_ccw": "G2"}"#, "clockwise"),
        // A setup the reader refuses.
        (r#"{"name": "x", "setup": ["G20"]}"#, "pose"),
        (r#"{"name": "x", "rapid": "G5"}"#, "G5"),
    ] {
        let e = refused(text);
        assert!(
            e.contains("shop.json") && e.contains("does not read back") && e.contains(what),
            "{text}: {e}"
        );
    }
}

/// Lines, arcs in G17 both ways and a rapid, for the 3-axis mill.
fn path() -> Toolpath {
    let p = |kind, x, y, z| Pose::new(kind, DVec3::new(x, y, z), DVec3::Z, 500.0);
    let mut tp = Toolpath::new(
        ToolRecord {
            spec: "ball:d=6".into(),
            cutter: parse_tool_spec("ball:d=6").unwrap(),
        },
        vec![
            p(MoveKind::Rapid, 3.0, 4.0, 8.0),
            p(MoveKind::Plunge, 3.0, 4.0, -2.0),
        ],
    );
    tp.push_arc(
        DVec3::new(3.0, 0.0, -2.0),
        DVec3::Z,
        FRAC_PI_2,
        MoveKind::Cut,
        500.0,
        0.01,
    )
    .unwrap();
    tp.push_arc(
        DVec3::new(-7.0, 0.0, -2.0),
        DVec3::Z,
        -FRAC_PI_2,
        MoveKind::Cut,
        500.0,
        0.01,
    )
    .unwrap();
    tp.push_pose(p(MoveKind::Cut, -7.0, -7.0, -2.0));
    tp.push_pose(p(MoveKind::Rapid, -7.0, -7.0, 8.0));
    tp
}

#[test]
fn every_mutated_dialect_either_is_refused_or_posts_what_reads_back() {
    let mill = Machine::builtin("mill-3axis").unwrap();
    let strings = [
        "", "G1", "G0", "G2", "G3", "X", "(", ")", ";", "*", "%", "M30", "G93", "G94", "G71",
    ];
    let fields = [
        "comment_open",
        "comment_close",
        "block_end",
        "rapid",
        "linear",
        "feed_per_minute",
        "inverse_time",
        "arc_cw",
        "arc_ccw",
    ];
    let lists = [
        "header",
        "setup",
        "tool_change",
        "spindle_on",
        "coolant_on",
        "footer",
        "trailer",
    ];
    let mut loaded = 0;
    let mut refused_count = 0;
    let mut cases: Vec<String> = Vec::new();
    for f in fields {
        for s in strings {
            cases.push(format!(r#"{{"name": "m", "{f}": {s:?}}}"#));
        }
    }
    for f in lists {
        for s in strings {
            cases.push(format!(r#"{{"name": "m", "{f}": [{s:?}]}}"#));
        }
    }
    for n in [
        "decimals_linear",
        "decimals_feed",
        "decimals_angle",
        "decimals_inverse_time",
    ] {
        for v in ["0", "1", "6", "7", "9", "65536"] {
            cases.push(format!(r#"{{"name": "m", "{n}": {v}}}"#));
        }
    }
    for (f, v) in [
        ("arc_centre", "\"radius\""),
        ("strip_trailing_zeros", "false"),
        ("keep_decimal_point", "true"),
        ("line_numbers", "true"),
    ] {
        cases.push(format!(r#"{{"name": "m", "{f}": {v}}}"#));
    }
    for text in &cases {
        let d = match Dialect::from_json(text, "m.json") {
            Ok(d) => d,
            Err(e) => {
                assert!(e.to_string().contains("m.json"), "{e}");
                refused_count += 1;
                continue;
            }
        };
        loaded += 1;
        let program = post(&path(), &mill, &d, &PostOptions::default()).unwrap();
        let syntax = Syntax::from_name(&d.name).unwrap_or_else(|| Syntax::detect(&program));
        let read = interpret(&program, &InterpretOptions::for_syntax(syntax)).unwrap_or_else(|e| {
            panic!("{text} loaded but its program does not read: {e}\n{program}")
        });
        let tol = 0.5 * 10f64.powi(-(d.decimals_linear as i32)) * 3f64.sqrt() + 1e-9;
        let tp = path();
        for (k, pose) in tp.poses.iter().enumerate().skip(1) {
            if tp.exact.iter().any(|s| s.from < k && k < s.to) {
                continue;
            }
            assert!(
                read.blocks
                    .iter()
                    .any(|b| b.end.xyz.distance(pose.tip) <= tol),
                "{text}: pose {} not reached\n{program}",
                pose.tip
            );
        }
    }
    assert!(
        loaded > 20 && refused_count > 20,
        "{loaded} loaded, {refused_count} refused"
    );
}
