//! `talas feed` on the thesis programs: the JSON contract (`cycle_time_s`, `limits`, peaks),
//! the samples CSV, corner options, `--start`, and malformed input (one line naming the file and
//! line, exit 2).

use std::path::Path;
use std::process::Command;

use talas::gcode::{InterpretOptions, Joints, interpret};

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

/// The start position from a header comment `(Initial position X.. Y.. Z..` (origin otherwise).
fn header_start(text: &str) -> [f64; 3] {
    let mut p = [0.0; 3];
    if let Some(i) = text.find("nitial position") {
        let rest = &text[i + 15..];
        let rest = &rest[..rest.find(')').unwrap_or(rest.len())];
        for word in rest.split_whitespace() {
            let w = word.trim_end_matches([',', '.']);
            let k = match w.chars().next() {
                Some('X') => 0,
                Some('Y') => 1,
                Some('Z') => 2,
                _ => continue,
            };
            if let Ok(v) = w[1..].parse() {
                p[k] = v;
            }
        }
    }
    p
}

/// The machine file's limits (the reference for `limits`).
const MILL: [(&str, f64, f64, f64); 3] = [
    ("X", 500.0, 2000.0, 25000.0),
    ("Y", 500.0, 2000.0, 25000.0),
    ("Z", 400.0, 2000.0, 25000.0),
];

fn check_plan(file: &Path, start: [f64; 3], extra: &[&str], dir: &Path) -> f64 {
    let name = file.file_name().unwrap().to_string_lossy().to_string();
    let csv = dir.join(format!("{name}.csv"));
    let start_arg = format!("--start={},{},{}", start[0], start[1], start[2]);
    let mut args = vec![
        "feed",
        file.to_str().unwrap(),
        "--machine",
        "mill-3axis",
        "--json",
        &start_arg,
        "--samples",
        csv.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    let (code, out, err) = talas(&args);
    assert_eq!(code, 0, "{name}: {err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    let t = doc["cycle_time_s"].as_f64().unwrap();
    assert!(t.is_finite() && t > 0.0, "{name}");
    for (axis, v, a, j) in MILL {
        let lim = &doc["limits"][axis];
        assert_eq!(
            [lim["v"].as_f64(), lim["a"].as_f64(), lim["j"].as_f64()],
            [Some(v), Some(a), Some(j)],
            "{name} {axis}"
        );
        let peak = &doc["peaks"][axis];
        for (key, l) in [("v", v), ("a", a), ("j", j)] {
            let p = peak[key].as_f64().unwrap();
            assert!(p >= 0.0 && p <= l * 1.001, "{name} {axis} {key}: {p} > {l}");
        }
    }
    // Samples: header, one row per 1 ms plus the end, ending at the program's end point.
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,X,Y,Z"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let expected_rows = (t / 1e-3).ceil() as usize + 1;
    assert!(
        rows.len().abs_diff(expected_rows) <= 1,
        "{name}: {} rows for {t} s",
        rows.len()
    );
    assert!(rows.windows(2).all(|w| w[1][0] > w[0][0]), "{name}: time");
    let prog = interpret(
        &std::fs::read_to_string(file).unwrap(),
        &InterpretOptions {
            start: Joints::xyz(start[0], start[1], start[2]),
            ..InterpretOptions::default()
        },
    )
    .unwrap();
    let end = prog.blocks.last().unwrap().end.xyz;
    let last = rows.last().unwrap();
    assert!((last[0] - t).abs() < 1e-6, "{name}");
    for k in 0..3 {
        assert!(
            (last[k + 1] - end[k]).abs() <= 1e-6,
            "{name}: end {last:?} vs {end}"
        );
    }
    t
}

#[test]
fn thesis_programs_give_the_contract() {
    let dir = std::env::temp_dir().join(format!("talas-feed-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut n = 0;
    for entry in std::fs::read_dir("tests/data/gcode").unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !name.starts_with("seed-001-") || name.contains("fig4-36") {
            continue;
        }
        let start = header_start(&std::fs::read_to_string(&path).unwrap());
        let blend = check_plan(&path, start, &[], &dir);
        let exact = check_plan(&path, start, &["--corners", "exact"], &dir);
        assert!(blend <= exact * (1.0 + 1e-12), "{name}: {blend} > {exact}");
        n += 1;
    }
    assert!(n >= 10, "{n} programs");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn pocket_fragment_plans_from_a_given_start() {
    let dir = std::env::temp_dir().join(format!("talas-feed-pocket-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = Path::new("tests/data/gcode/seed-001-fig4-36-pocket-fragment.nc");
    // The header: the geometry puts the tool at X-105 Y82.501 before N310.
    let t = check_plan(file, [-105.0, 82.501, 0.0], &[], &dir);
    // Path length over the machine's top speed is a lower bound on the cycle time.
    let prog = interpret(
        &std::fs::read_to_string(file).unwrap(),
        &InterpretOptions {
            start: Joints::xyz(-105.0, 82.501, 0.0),
            ..InterpretOptions::default()
        },
    )
    .unwrap();
    assert!(t >= prog.length_mm() / 500.0, "{t}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_input_is_one_line_exit_2() {
    let dir = std::env::temp_dir().join(format!("talas-feed-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("broken.nc");
    std::fs::write(&file, "G90 G1 X1 F100\nG1 X2 Q\n").unwrap();
    let f = file.to_str().unwrap();
    let (code, out, err) = talas(&["feed", f, "--machine", "mill-3axis", "--json"]);
    assert_eq!(code, 2, "{out}{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("broken.nc") && err.contains("line 2"), "{err}");
    let good = dir.join("good.nc");
    std::fs::write(&good, "G90 G1 X1 F100\nG1 Y2\n").unwrap();
    let g = good.to_str().unwrap();
    for bad in [
        vec!["--start", "1,2"],
        vec!["--deviation=-1"],
        vec!["--limit", "X=1,2"],
    ] {
        let mut args = vec!["feed", g, "--machine", "mill-3axis"];
        args.extend(bad.iter());
        let (code, _, err) = talas(&args);
        assert_eq!(code, 2, "{bad:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
