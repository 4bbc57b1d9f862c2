//! The interpreter against LinuxCNC's: every program of the corpus in `tests/data/gcode/`
//! (`*.ngc`, written in the style of Fusion 360 and FreeCAD posts, by hand, and by Talas's own
//! posts) interprets to the canonical motion that LinuxCNC's `rs274 -g` printed for it
//! (`NAME.rs274.txt`, committed beside it): the same number and kinds of moves, every
//! traverse, feed and arc end point and every arc centre within 1e-4 mm, the same arc planes
//! and turns, the same feeds and dwells.
//!
//! How the printed calls are read (`rs274` prints program coordinates in the program's
//! units, 4 decimals):
//! - machine position = printed position × unit (25.4 after `USE_LENGTH_UNITS(INCHES)`) + the
//!   last `SET_G5X_OFFSET`, `SET_G92_OFFSET` and `USE_TOOL_LENGTH_OFFSET` (each converted
//!   to mm when printed), which is the frame Talas's blocks are in;
//! - `ARC_FEED(first_end, second_end, first_centre, second_centre, turn, axis_end, a, b, c)`
//!   names the plane's axes: X Y (Z) in G17, Z X (Y) in G18, Y Z (X) in G19;
//! - `rs274` prints moves that go nowhere (a cycle's rapid to where the tool already is);
//!   Talas emits none: moves shorter than 1e-7 mm are left out on both sides;
//! - in inch programs the print's 4 decimals are 2.54 µm: there the tolerance is half of that;
//! - inverse-time (G93) feeds are compared as moves only (rs274 prints the derived rate);
//!   dwells of 0 s are left out.
//!
//! The tool tables (`NAME.tbl`, else `no-tools.tbl`) are in inches: `rs274` run without an
//! INI file reads every table in inches.
//!
//! A second test runs `rs274` on every corpus program again when `/usr/bin/rs274` exists
//! (LinuxCNC's `linuxcnc-uspace` package, installed by `.ci/run`) and checks that it still
//! prints the committed text, so the fixtures cannot drift.

use std::path::{Path, PathBuf};

use talas::gcode::{InterpretOptions, LengthUnit, MotionKind, ToolTable, interpret};

const DIR: &str = "tests/data/gcode";
const RS274: &str = "/usr/bin/rs274";

#[derive(Clone, Debug, PartialEq)]
enum Kind {
    Rapid,
    Feed,
    /// Plane (`XY`, `ZX`, `YZ`), turn, centre in the plane's two axes (machine mm).
    Arc(&'static str, i64, [f64; 2]),
}

#[derive(Clone, Debug)]
struct Move {
    kind: Kind,
    /// X Y Z in mm, A B C in degrees.
    end: [f64; 6],
    /// mm/min; `None` for rapids and inverse-time moves.
    feed: Option<f64>,
    /// The source line (Talas's side only).
    line: usize,
}

fn corpus() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(DIR)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "ngc"))
        .collect();
    v.sort();
    v
}

fn with_ext(p: &Path, ext: &str) -> PathBuf {
    let stem = p.file_stem().unwrap().to_string_lossy().to_string();
    p.with_file_name(format!("{stem}.{ext}"))
}

fn table_of(p: &Path) -> PathBuf {
    let own = with_ext(p, "tbl");
    if own.exists() {
        own
    } else {
        Path::new(DIR).join("no-tools.tbl")
    }
}

/// The axes of a plane's (first, second, normal) coordinates in X Y Z.
fn plane_axes(plane: &str) -> (usize, usize, usize) {
    match plane {
        "ZX" => (2, 0, 1),
        "YZ" => (1, 2, 0),
        _ => (0, 1, 2),
    }
}

fn far(a: &[f64; 6], b: &[f64; 6]) -> bool {
    a.iter().zip(b).any(|(x, y)| (x - y).abs() >= 1e-7)
}

/// The moves and dwells (before which move, seconds) of an `rs274 -g` print.
fn parse_rs274(text: &str) -> (Vec<Move>, Vec<(usize, f64)>) {
    let mut unit = 1.0;
    let mut offsets = [[0.0; 6]; 3]; // G5x, G92, tool
    let mut plane = "XY";
    let mut feed = 0.0;
    let mut moves: Vec<Move> = Vec::new();
    let mut dwells = Vec::new();
    let mut pos = [0.0; 6];
    for line in text.lines() {
        let mut parts = line.split_whitespace();
        let (Some(_), Some(_)) = (parts.next(), parts.next()) else {
            continue;
        };
        let call: String = parts.collect::<Vec<_>>().join(" ");
        let Some((name, rest)) = call.split_once('(') else {
            continue;
        };
        let args = rest.trim_end().trim_end_matches(')');
        let nums = || -> Vec<f64> {
            args.split([',', ' '])
                .filter(|t| !t.is_empty())
                .filter_map(|t| t.parse().ok())
                .collect()
        };
        let machine = |v: &[f64], unit: f64, offsets: &[[f64; 6]; 3]| {
            let mut m = [0.0; 6];
            for (i, slot) in m.iter_mut().enumerate() {
                let k = if i < 3 { unit } else { 1.0 };
                *slot = v.get(i).copied().unwrap_or(0.0) * k
                    + offsets.iter().map(|o| o[i]).sum::<f64>();
            }
            m
        };
        let set = |v: &[f64], unit: f64| {
            let mut o = [0.0; 6];
            for (i, slot) in o.iter_mut().enumerate() {
                *slot = v.get(i).copied().unwrap_or(0.0) * if i < 3 { unit } else { 1.0 };
            }
            o
        };
        match name {
            "USE_LENGTH_UNITS" => unit = if args.contains("INCHES") { 25.4 } else { 1.0 },
            "SET_G5X_OFFSET" => offsets[0] = set(nums().get(1..).unwrap_or(&[]), unit),
            "SET_G92_OFFSET" => offsets[1] = set(&nums(), unit),
            "USE_TOOL_LENGTH_OFFSET" => offsets[2] = set(&nums(), unit),
            "SELECT_PLANE" => {
                plane = match args {
                    "CANON_PLANE_XZ" => "ZX",
                    "CANON_PLANE_YZ" => "YZ",
                    _ => "XY",
                }
            }
            "SET_FEED_RATE" => feed = nums()[0] * unit,
            "DWELL" => {
                let t = nums()[0];
                if t > 0.0 {
                    dwells.push((moves.len(), t));
                }
            }
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => {
                let end = machine(&nums(), unit, &offsets);
                if !far(&end, &pos) {
                    continue;
                }
                let rapid = name == "STRAIGHT_TRAVERSE";
                moves.push(Move {
                    kind: if rapid { Kind::Rapid } else { Kind::Feed },
                    end,
                    feed: (!rapid).then_some(feed),
                    line: 0,
                });
                pos = end;
            }
            "ARC_FEED" => {
                let v = nums();
                let (u, w, n) = plane_axes(plane);
                let mut prog = [0.0; 6];
                prog[u] = v[0];
                prog[w] = v[1];
                prog[n] = v[5];
                prog[3..6].copy_from_slice(&v[6..9]);
                let end = machine(&prog, unit, &offsets);
                let off = |i: usize| offsets.iter().map(|o| o[i]).sum::<f64>();
                let centre = [v[2] * unit + off(u), v[3] * unit + off(w)];
                moves.push(Move {
                    kind: Kind::Arc(plane, v[4] as i64, centre),
                    end,
                    feed: Some(feed),
                    line: 0,
                });
                pos = end;
            }
            _ => {}
        }
    }
    (moves, dwells)
}

fn interpret_corpus(p: &Path) -> (Vec<Move>, Vec<(usize, f64)>) {
    let text = std::fs::read_to_string(p).unwrap();
    let table = std::fs::read_to_string(table_of(p)).unwrap();
    let opts = InterpretOptions {
        tool_table: Some(ToolTable::parse(&table, LengthUnit::Inch).unwrap()),
        ..InterpretOptions::default()
    };
    let program = interpret(&text, &opts).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    let mut moves = Vec::new();
    let mut pos = [0.0; 6];
    let mut kept = Vec::new();
    for (i, b) in program.blocks.iter().enumerate() {
        let deg = |v: Option<f64>| v.unwrap_or(0.0).to_degrees();
        let end = [
            b.end.xyz.x,
            b.end.xyz.y,
            b.end.xyz.z,
            deg(b.end.a),
            deg(b.end.b),
            deg(b.end.c),
        ];
        let kind = match b.kind {
            MotionKind::Rapid => Kind::Rapid,
            MotionKind::Linear => Kind::Feed,
            MotionKind::ArcCw(a) | MotionKind::ArcCcw(a) => {
                let plane = if a.normal.z.abs() > 0.5 {
                    "XY"
                } else if a.normal.y.abs() > 0.5 {
                    "ZX"
                } else {
                    "YZ"
                };
                let (u, w, _) = plane_axes(plane);
                let c = a.centre.to_array();
                let n = ((a.sweep_rad / std::f64::consts::TAU) - 1e-9)
                    .ceil()
                    .max(1.0) as i64;
                let turn = if matches!(b.kind, MotionKind::ArcCcw(_)) {
                    n
                } else {
                    -n
                };
                Kind::Arc(plane, turn, [c[u], c[w]])
            }
        };
        if kind != Kind::Rapid && kind != Kind::Feed || far(&end, &pos) {
            kept.push(i);
            moves.push(Move {
                kind,
                end,
                feed: (b.kind != MotionKind::Rapid && !b.inverse_time).then_some(b.feed_mm_per_min),
                line: b.source_line,
            });
            pos = end;
        }
    }
    let dwells = program
        .dwells
        .iter()
        .filter(|d| d.seconds > 0.0)
        .map(|d| {
            (
                kept.iter().filter(|k| **k < d.before_block).count(),
                d.seconds,
            )
        })
        .collect();
    (moves, dwells)
}

/// The differences between the two, one line each (empty when they agree).
fn differences(name: &str, inch: bool, lcnc: &[Move], ours: &[Move]) -> Vec<String> {
    let tol = if inch { 0.5e-4 * 25.4 + 1e-6 } else { 1e-4 };
    let mut out = Vec::new();
    if lcnc.len() != ours.len() {
        out.push(format!(
            "{name}: {} moves in rs274, {} in Talas",
            lcnc.len(),
            ours.len()
        ));
    }
    for (i, (a, b)) in lcnc.iter().zip(ours).enumerate() {
        let mut why = Vec::new();
        let d = (0..3)
            .map(|k| (a.end[k] - b.end[k]).abs())
            .fold(0.0, f64::max);
        let da = (3..6)
            .map(|k| (a.end[k] - b.end[k]).abs())
            .fold(0.0, f64::max);
        if d > tol || da > 1e-4 {
            why.push(format!("end {:?} vs {:?}", a.end, b.end));
        }
        match (&a.kind, &b.kind) {
            (Kind::Arc(pa, ta, ca), Kind::Arc(pb, tb, cb)) => {
                if pa != pb || ta != tb {
                    why.push(format!("arc {pa} turn {ta} vs {pb} turn {tb}"));
                }
                if (ca[0] - cb[0]).abs() > tol || (ca[1] - cb[1]).abs() > tol {
                    why.push(format!("centre {ca:?} vs {cb:?}"));
                }
            }
            (ka, kb) if std::mem::discriminant(ka) != std::mem::discriminant(kb) => {
                why.push(format!("kind {ka:?} vs {kb:?}"));
            }
            _ => {}
        }
        if let (Some(fa), Some(fb)) = (a.feed, b.feed)
            && (fa - fb).abs() > 1e-3 * fa.max(1.0)
        {
            why.push(format!("feed {fa} vs {fb}"));
        }
        if !why.is_empty() {
            out.push(format!(
                "{name}: move {i} (line {}): {}",
                b.line,
                why.join("; ")
            ));
        }
    }
    out
}

#[test]
fn corpus_interprets_as_linuxcnc_does() {
    let programs = corpus();
    assert!(
        programs.len() >= 20,
        "the corpus has {} programs",
        programs.len()
    );
    let mut failures = Vec::new();
    let mut total = 0;
    for p in &programs {
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        let fixture = with_ext(p, "rs274.txt");
        let printed = std::fs::read_to_string(&fixture)
            .unwrap_or_else(|e| panic!("{}: {e}", fixture.display()));
        let (lcnc, lcnc_dwells) = parse_rs274(&printed);
        assert!(!lcnc.is_empty(), "{name}: rs274 printed no motion");
        let (ours, our_dwells) = interpret_corpus(p);
        let inch = std::fs::read_to_string(p)
            .unwrap()
            .to_ascii_uppercase()
            .contains("G20");
        failures.extend(differences(&name, inch, &lcnc, &ours));
        let same_dwells = lcnc_dwells.len() == our_dwells.len()
            && lcnc_dwells
                .iter()
                .zip(&our_dwells)
                .all(|(a, b)| a.0 == b.0 && (a.1 - b.1).abs() < 1e-9);
        if !same_dwells {
            failures.push(format!("{name}: dwells {lcnc_dwells:?} vs {our_dwells:?}"));
        }
        total += lcnc.len();
    }
    assert!(
        failures.is_empty(),
        "{} differences:\n{}",
        failures.len(),
        failures.join("\n")
    );
    assert!(total > 500, "{total} moves compared");
}

/// The fixtures are what LinuxCNC prints today (run only where `rs274` is installed).
#[test]
fn fixtures_are_what_rs274_prints() {
    if !Path::new(RS274).exists() {
        eprintln!("{RS274} is not installed: the fixtures are not re-checked");
        return;
    }
    let home = std::env::temp_dir().join(format!("talas-rs274-{}", std::process::id()));
    std::fs::create_dir_all(&home).unwrap();
    for p in corpus() {
        let out = std::process::Command::new(RS274)
            .arg("-g")
            .arg("-t")
            .arg(table_of(&p))
            .arg(&p)
            // rs274 keeps a tool memory map in $HOME.
            .env("HOME", &home)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}: rs274 failed: {}",
            p.display(),
            String::from_utf8_lossy(&out.stderr)
        );
        let fixture = std::fs::read_to_string(with_ext(&p, "rs274.txt")).unwrap();
        assert_eq!(
            String::from_utf8_lossy(&out.stdout),
            fixture,
            "{}: rs274 prints something else now: regenerate the fixture (tests/data/gcode/README.md)",
            p.display()
        );
    }
    let _ = std::fs::remove_dir_all(&home);
}
