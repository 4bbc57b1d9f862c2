//! Hostile input through the command line (the files in `tests/data/adversarial/`, found by
//! mutation fuzzing, and hand-made options): each gives a result or one clear error within
//! 10 s and 2 GiB of address space; silent wrong results are now reported.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A file under `tests/data/adversarial`.
fn adversarial(name: &str) -> PathBuf {
    common::data(&format!("adversarial/{name}"))
}

fn temp(name: &str) -> PathBuf {
    common::temp_path("hostile", name)
}

/// Run `talas ARGS` under a 2 GiB address-space limit; kill it after `limit`. Returns the output
/// and the wall time, or panics naming the command when it ran past the limit.
fn talas_bounded(args: &[&str], limit: Duration) -> (Output, Duration) {
    let mut child = Command::new("sh")
        .arg("-c")
        .arg("ulimit -v 2097152; exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_talas"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run talas");
    let started = Instant::now();
    // Drain both pipes while the command runs: a document larger than a pipe's buffer (the
    // JSON of a 30 000-point profile) would otherwise block the command until the limit.
    let drain = |pipe: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let stdout = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn std::io::Read + Send>),
    );
    let stderr = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn std::io::Read + Send>),
    );
    loop {
        if let Some(status) = child.try_wait().expect("wait") {
            let out = Output {
                status,
                stdout: stdout.join().unwrap_or_default(),
                stderr: stderr.join().unwrap_or_default(),
            };
            return (out, started.elapsed());
        }
        if started.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("talas {} ran past {limit:?}", args.join(" "));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// A clean outcome: a result (0) or one error line naming the file (2); never a crash. The
/// 30 s bound is a hang guard, not a timing: the inputs here once ran past 60 s, or for ever
/// (a loaded CI runner takes 4 s where an idle one takes 1 s).
fn assert_clean(args: &[&str], named: &str) -> Output {
    let (out, took) = talas_bounded(args, Duration::from_secs(30));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let code = out.status.code();
    assert!(
        code == Some(0) || code == Some(2),
        "talas {}: exit {code:?} after {took:?}, stderr {stderr}",
        args.join(" ")
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    if code == Some(2) {
        let lines: Vec<&str> = stderr.lines().filter(|l| !l.contains("warning:")).collect();
        assert_eq!(lines.len(), 1, "one error line: {stderr}");
        assert!(
            lines[0].contains(named),
            "the error names {named}: {stderr}"
        );
    }
    out
}

fn json(out: &Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout)
        .unwrap_or_else(|e| panic!("not JSON ({e}): {}", String::from_utf8_lossy(&out.stdout)))
}

#[test]
fn every_mutated_step_file_gives_a_result_or_an_error_within_bounds() {
    let dir = common::data("adversarial");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "stp"))
        .collect();
    files.sort();
    assert!(files.len() >= 15, "{} files", files.len());
    for f in &files {
        let name = f.file_name().unwrap().to_str().unwrap();
        let out = assert_clean(&["inspect", f.to_str().unwrap(), "--json"], name);
        if out.status.code() == Some(0) {
            // A face may never vanish silently: every face has triangles or a diagnostic.
            let doc = json(&out);
            let faces = doc["faces"].as_array().cloned().unwrap_or_default();
            let diagnostics = doc["diagnostics"].as_array().map_or(0, Vec::len);
            for (k, face) in faces.iter().enumerate() {
                let triangles = face["triangles"].as_u64().unwrap_or(1);
                assert!(
                    triangles > 0 || diagnostics > 0,
                    "{name}: face {k} has no triangles and no diagnostic"
                );
            }
        }
    }
}

#[test]
fn mutated_five_axis_programs_simulate_or_fail_within_bounds() {
    for name in ["hang-simulate-00083.nc", "hang-simulate-00279.nc"] {
        let f = adversarial(name);
        assert_clean(
            &[
                "simulate",
                f.to_str().unwrap(),
                "--tool",
                "ball:d=6",
                "--stock",
                "box:0,0,0,100,100,50",
                "--resolution",
                "0.5",
                "--machine",
                "trt-ac",
                "--json",
            ],
            name,
        );
    }
}

fn simulate_removed(name: &str) -> f64 {
    let f = adversarial(name);
    let out = assert_clean(
        &[
            "simulate",
            f.to_str().unwrap(),
            "--machine",
            "trt-ac",
            "--tool",
            "ball:d=6",
            "--stock",
            "box:-50,-50,0,50,50,40",
            "--resolution",
            "1",
            "--json",
        ],
        name,
    );
    assert_eq!(out.status.code(), Some(0));
    json(&out)["removed_volume_mm3"].as_f64().unwrap()
}

#[test]
fn traori_alone_on_its_line_switches_tool_centre_point_control_on() {
    let alone = simulate_removed("siemens-traori-alone.nc");
    let numbered = simulate_removed("siemens-traori-numbered.nc");
    assert!(
        (alone - numbered).abs() <= 1e-9 * numbered.max(1.0),
        "alone {alone} mm³, numbered {numbered} mm³"
    );
}

#[test]
fn feed_reports_travel_violations_dwells_and_warnings() {
    let f = adversarial("overtravel.nc");
    let out = assert_clean(
        &["feed", f.to_str().unwrap(), "--machine", "trt-ac", "--json"],
        "overtravel.nc",
    );
    let doc = json(&out);
    let v = doc["travel_violations"].as_array().unwrap();
    let a = v
        .iter()
        .find(|v| v["axis"] == "A")
        .expect("A beyond its travel");
    assert_eq!(a["line"], 3);
    assert!((a["value"].as_f64().unwrap() + 200.0).abs() < 1e-9, "{a}");
    assert!((a["limit"].as_f64().unwrap() + 120.0).abs() < 1e-9, "{a}");
    // X5000 Y5000 is beyond the linear travel too.
    assert!(
        v.iter().any(|v| v["axis"] == "X" && v["line"] == 4),
        "{v:?}"
    );

    let cycle = |name: &str| {
        let f = adversarial(name);
        let out = assert_clean(
            &[
                "feed",
                f.to_str().unwrap(),
                "--machine",
                "mill-3axis",
                "--json",
            ],
            name,
        );
        json(&out)
    };
    let (d0, d10) = (cycle("dwell0.nc"), cycle("dwell10.nc"));
    let t0 = d0["cycle_time_s"].as_f64().unwrap();
    let t10 = d10["cycle_time_s"].as_f64().unwrap();
    assert!((t10 - t0 - 10.0).abs() < 1e-9, "{t0} s and {t10} s");
    assert_eq!(d10["dwell_s"], 10.0);

    // The interpreter's warnings reach the JSON (M99 unknown, a feed move without F).
    let p = temp("warn.nc");
    std::fs::write(&p, "G21 G90\nG1 X10\nM99\n").unwrap();
    let doc = json(&assert_clean(
        &[
            "feed",
            p.to_str().unwrap(),
            "--machine",
            "mill-3axis",
            "--json",
        ],
        "warn.nc",
    ));
    let warnings = doc["warnings"].as_array().unwrap();
    assert!(
        warnings.iter().any(|w| w.as_str().unwrap().contains("M99")),
        "{warnings:?}"
    );
}

#[test]
fn unknown_keywords_are_errors_and_known_ones_warnings() {
    let run = |text: &str| {
        let p = temp("kw.mpf");
        std::fs::write(&p, text).unwrap();
        talas_bounded(
            &[
                "feed",
                p.to_str().unwrap(),
                "--machine",
                "trt-ac",
                "--syntax",
                "siemens",
                "--json",
            ],
            Duration::from_secs(10),
        )
        .0
    };
    for bad in ["GX1\n", "TRAFOF\n", "CYCLE800(0,\"TC1\",200000,57)\n"] {
        let out = run(&format!("G71 G90\n{bad}G1 X1 F100\n"));
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {stderr}");
        assert!(stderr.contains("line 2"), "{bad}: {stderr}");
    }
    let out = run("G71 G90\nMSG(\"roughing\")\nG1 X1 F100\n");
    assert_eq!(out.status.code(), Some(0));
    let doc = json(&out);
    assert!(doc["warnings"].to_string().contains("MSG"), "{doc}");
}

#[test]
fn hostile_options_are_refused_or_bounded() {
    let hills = common::data("bicubic-hills.stp");
    let hills = hills.to_str().unwrap();
    // A tessellation tolerance far below any machine's resolution is refused with the reason.
    let out = assert_clean(&["inspect", hills, "--tolerance", "1e-12"], "tolerance");
    assert_eq!(out.status.code(), Some(2));

    let prog = temp("slow.nc");
    std::fs::write(&prog, "G21 G90\nG1 X10 F0.000000001\nM30\n").unwrap();
    let p = prog.to_str().unwrap();
    // A program that would take millennia: planned, its peaks bounded, samples refused.
    let out = assert_clean(&["feed", p, "--machine", "mill-3axis", "--json"], "slow.nc");
    assert_eq!(out.status.code(), Some(0));
    let csv = temp("slow.csv");
    let out = assert_clean(
        &[
            "feed",
            p,
            "--machine",
            "mill-3axis",
            "--samples",
            csv.to_str().unwrap(),
        ],
        "slow.csv",
    );
    assert_eq!(out.status.code(), Some(2));
    // Limits near zero are refused.
    let out = assert_clean(
        &[
            "feed",
            p,
            "--machine",
            "mill-3axis",
            "--limit",
            "X=1e-300,1e-300,1e-300",
        ],
        "slow.nc",
    );
    assert_eq!(out.status.code(), Some(2));
    // A memory limit that lets a huge allocation through gives an error, not an abort.
    let out = assert_clean(
        &[
            "simulate",
            p,
            "--tool",
            "ball:d=6",
            "--stock",
            "box:0,0,0,100,100,50",
            "--resolution",
            "0.001",
            "--memory-limit-mib",
            "100000000",
        ],
        "stock",
    );
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn a_heidenhain_program_name_cannot_inject_blocks() {
    let tp = temp("p.json");
    std::fs::write(
        &tp,
        r#"{"tool": {"spec": "ball:d=6"}, "poses": [
            {"tip": [0, 0, 10], "kind": "rapid"},
            {"tip": [10, 0, 0], "kind": "cut", "feed_mm_per_min": 500}]}"#,
    )
    .unwrap();
    let out = temp("p.h");
    let (o, _) = talas_bounded(
        &[
            "post",
            tp.to_str().unwrap(),
            "--machine",
            "mill-3axis",
            "--dialect",
            "heidenhain",
            "--program",
            "P1 G71 *\nG00 Z-500 *",
            "-o",
            out.to_str().unwrap(),
        ],
        Duration::from_secs(10),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("program name"));
    assert!(!out.exists());
}

#[test]
fn a_part_in_metres_or_kilometres_tessellates_within_a_budget() {
    let text = std::fs::read_to_string(common::data("pocket-fillets.stp")).unwrap();
    for (unit, name) in [
        ("SI_UNIT($,.METRE.)", "m.stp"),
        ("SI_UNIT(.KILO.,.METRE.)", "km.stp"),
    ] {
        let scaled = text.replacen("SI_UNIT(.MILLI.,.METRE.)", unit, 1);
        assert_ne!(scaled, text);
        let p = temp(name);
        std::fs::write(&p, scaled).unwrap();
        let out = assert_clean(&["inspect", p.to_str().unwrap(), "--json"], name);
        assert_eq!(out.status.code(), Some(0));
        let doc = json(&out);
        let triangles = doc["triangles"].as_u64().unwrap();
        assert!(triangles < 2_000_000, "{name}: {triangles} triangles");
        assert!(
            doc["diagnostics"]
                .to_string()
                .contains("chord tolerance raised"),
            "{name}: {}",
            doc["diagnostics"]
        );
    }
}

#[test]
fn meshes_far_out_or_without_area_and_files_without_faces_are_reported() {
    // 30 000 facets a petametre out: welding stays linear.
    let mut stl = String::from("solid far\n");
    for k in 0..30_000 {
        let x = 1e15 + f64::from(k) * 8.0;
        stl.push_str(&format!(
            "facet normal 0 0 1\nouter loop\nvertex {x} 0 0\nvertex {} 0 0\nvertex {x} 8 0\nendloop\nendfacet\n",
            x + 8.0
        ));
    }
    stl.push_str("endsolid far\n");
    let far = temp("far.stl");
    std::fs::write(&far, stl).unwrap();
    assert_clean(&["inspect", far.to_str().unwrap(), "--json"], "far.stl");

    let flat = temp("flat.stl");
    std::fs::write(
        &flat,
        "solid z\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 2 0 0\n\
         endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 0 0 0\n\
         vertex 0 0 0\nendloop\nendfacet\nendsolid z\n",
    )
    .unwrap();
    let out = assert_clean(&["inspect", flat.to_str().unwrap()], "flat.stl");
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("all 2 facets have zero area"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let points = temp("points.stp");
    std::fs::write(
        &points,
        "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('p','',(''),(''),'','','');\n\
         FILE_SCHEMA(('AUTOMOTIVE_DESIGN'));\nENDSEC;\nDATA;\n#1=CARTESIAN_POINT('',(0.,0.,0.));\n\
         #2=CARTESIAN_POINT('',(1.,0.,0.));\n#3=DIRECTION('',(0.,0.,1.));\nENDSEC;\nEND-ISO-10303-21;\n",
    )
    .unwrap();
    let out = assert_clean(&["inspect", points.to_str().unwrap()], "points.stp");
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("2 CARTESIAN_POINT") && stderr.contains("1 DIRECTION"),
        "{stderr}"
    );
}

/// The done-when of "reading what other programs write": a path with only the spec, null rapid
/// feeds and no summary posts and simulates exactly like the same path written by Talas.
#[test]
fn a_foreign_path_posts_and_simulates_like_the_path_talas_writes() {
    let foreign = temp("foreign.json");
    std::fs::write(
        &foreign,
        r#"{"tool": {"spec": "ball:d=6"}, "generator": "other", "poses": [
            {"tip": [0, 0, 20], "kind": "rapid", "feed_mm_per_min": null},
            {"tip": [0, 0, 8], "kind": "plunge", "feed_mm_per_min": 300},
            {"tip": [30, 0, 8], "kind": "cut", "feed_mm_per_min": 800},
            {"tip": [30, 10, 8], "kind": "cut"},
            {"tip": [0, 10, 8], "kind": "cut"},
            {"tip": [0, 10, 20], "kind": "rapid"}]}"#,
    )
    .unwrap();
    // Written by Talas: read and saved through the library's own writer.
    let tp = talas::toolpath::Toolpath::load(&foreign).unwrap();
    let native = temp("native.json");
    tp.save(&native).unwrap();
    let post = |input: &Path, out: &str| {
        let out = temp(out);
        let (o, _) = talas_bounded(
            &[
                "post",
                input.to_str().unwrap(),
                "--machine",
                "mill-3axis",
                "--dialect",
                "fanuc",
                "-o",
                out.to_str().unwrap(),
            ],
            Duration::from_secs(10),
        );
        assert_eq!(
            o.status.code(),
            Some(0),
            "{}",
            String::from_utf8_lossy(&o.stderr)
        );
        (
            std::fs::read_to_string(out).unwrap(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (a, warnings) = post(&foreign, "foreign.nc");
    let (b, none) = post(&native, "native.nc");
    assert_eq!(a, b);
    assert!(
        warnings.contains("unknown key 'generator' ignored"),
        "{warnings}"
    );
    assert!(none.is_empty(), "{none}");
    let removed = |input: &Path| {
        let out = assert_clean(
            &[
                "simulate",
                input.to_str().unwrap(),
                "--stock",
                "box:-5,-5,0,35,15,10",
                "--resolution",
                "0.5",
                "--json",
            ],
            "json",
        );
        json(&out)["removed_volume_mm3"].as_f64().unwrap()
    };
    let (va, vb) = (removed(&foreign), removed(&native));
    assert!(va > 100.0 && va == vb, "{va} mm³ and {vb} mm³");
}

// ---- Issue 36, "found by hostile input": one reproducer per finding, in the issue's order.

/// The profile runs of the tests below take a CPU-second or more each: one at a time, so that
/// the 10 s bound measures each command, not the one beside it.
static HEAVY: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The error text of a clean refusal (exit 2, one line naming `named`).
fn refused(args: &[&str], named: &str) -> String {
    let out = assert_clean(args, named);
    assert_eq!(
        out.status.code(),
        Some(2),
        "talas {} was not refused",
        args.join(" ")
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Finding 1: A 4 KB SVG of 200 degenerate cubic Béziers (control points on the x axis, each walking
/// 1 m out and back) flattened to 346 000 points and ran `profile` past 60 s. Collinear curves
/// are now their turning points: the closed form gives each at most two turns, so the profile
/// has at most 3 points a curve.
#[test]
fn a_svg_of_degenerate_beziers_profiles_within_bounds() {
    let _one = HEAVY
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let d: Vec<String> = (0..200)
        .map(|i| {
            let x = i * 10;
            format!("C{},0 {},0 {},0", x + 1000, x - 1000, x + 10)
        })
        .collect();
    let svg = temp("degenerate.svg");
    std::fs::write(
        &svg,
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0,0 {}\"/></svg>",
            d.join(" ")
        ),
    )
    .unwrap();
    assert!(std::fs::metadata(&svg).unwrap().len() < 5_000);
    let out = assert_clean(
        &["profile", svg.to_str().unwrap(), "--radius", "1", "--json"],
        "degenerate.svg",
    );
    assert_eq!(out.status.code(), Some(0));
    let points = json(&out)["naive_cl"].as_array().unwrap().len();
    assert!(points <= 3 * 200 + 1, "{points} points");
    // Each curve's turning points: s(t) = 3(1−t)²t·s1 + 3(1−t)t²·s2 + t³·s3 from s0 = 0, here
    // s1 = 1000, s2 = −1000, s3 = 10 (relative): two turns inside (0, 1), so 3 points a curve.
    assert_eq!(points, 3 * 200 + 1);
}

/// Finding 2: `profile` was quadratic in the point count (30 000 points over 60 s); the nearest-element
/// queries, the flags' walks and the reach's pairs are now near-linear. The sampled concave
/// radius of y = 5 sin(x/3) is the closed form's 1/(5/9) = 1.8 mm at the crests.
#[test]
fn a_profile_of_30000_points_is_computed_within_bounds() {
    let _one = HEAVY
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut csv = String::new();
    for i in 0..30_000 {
        let x = f64::from(i) * 0.01;
        csv.push_str(&format!("{x:.12},{:.12}\n", 5.0 * (x / 3.0).sin()));
    }
    let f = temp("sine30k.csv");
    std::fs::write(&f, csv).unwrap();
    let out = assert_clean(
        &["profile", f.to_str().unwrap(), "--radius", "1", "--json"],
        "sine30k.csv",
    );
    assert_eq!(out.status.code(), Some(0));
    let doc = json(&out);
    assert_eq!(doc["naive_cl"].as_array().unwrap().len(), 30_000);
    let r = doc["min_concave_radius_sampled"].as_f64().unwrap();
    assert!((r - 1.8).abs() < 1e-3, "{r}");
    // An electrode of 2 mm plunges at the crests, where the concave radius is below 2.
    let out = assert_clean(
        &["profile", f.to_str().unwrap(), "--radius", "2", "--json"],
        "sine30k.csv",
    );
    let doc = json(&out);
    let plunges = doc["plunges"].as_array().map_or(0, Vec::len);
    assert!(plunges > 0, "{}", doc["plunges"]);
    assert_eq!(doc["collisions"].as_array().map(Vec::len), Some(0));
}

/// Finding 3: `profile --tolerance 1e-12` hung (each curve flattened to 100 000 points): the tolerance
/// now has the bounds of every tolerance, and the error names it.
#[test]
fn a_profile_tolerance_far_below_any_machine_is_refused() {
    let svg = temp("curve.svg");
    std::fs::write(
        &svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\"><path d=\"M0,0 C10,20 30,20 40,0\"/></svg>",
    )
    .unwrap();
    let s = svg.to_str().unwrap();
    let e = refused(
        &["profile", s, "--radius", "1", "--tolerance", "1e-12"],
        "tolerance",
    );
    assert!(e.contains("1e-12"), "{e}");
    let out = assert_clean(&["profile", s, "--radius", "1", "--json"], "curve.svg");
    assert_eq!(out.status.code(), Some(0));
}

/// A 10 mm cube with one vertex moved to 10¹⁵ mm.
fn far_cube() -> PathBuf {
    let v = |k: usize| -> (f64, f64, f64) {
        let p = (
            10.0 * (k & 4 != 0) as u8 as f64,
            10.0 * (k & 2 != 0) as u8 as f64,
            10.0 * (k & 1 != 0) as u8 as f64,
        );
        if k == 7 { (1e15, p.1, p.2) } else { p }
    };
    let faces = [
        [0, 1, 3],
        [0, 3, 2],
        [4, 6, 7],
        [4, 7, 5],
        [0, 4, 5],
        [0, 5, 1],
        [2, 3, 7],
        [2, 7, 6],
        [0, 2, 6],
        [0, 6, 4],
        [1, 5, 7],
        [1, 7, 3],
    ];
    let mut stl = String::from("solid far\n");
    for f in faces {
        stl.push_str("facet normal 0 0 0\nouter loop\n");
        for k in f {
            let (x, y, z) = v(k);
            stl.push_str(&format!("vertex {x:e} {y} {z}\n"));
        }
        stl.push_str("endloop\nendfacet\n");
    }
    stl.push_str("endsolid far\n");
    let p = temp("far-cube.stl");
    std::fs::write(&p, stl).unwrap();
    p
}

/// Finding 4: A cube with one vertex at 10¹⁵ mm hung `plan raster` (now refused by its sample
/// budget) and aborted `plan --strategy pencil` on a 21 PB allocation: every mesh strategy
/// refuses a part beyond ±10 m, naming the file.
#[test]
fn a_mesh_with_a_vertex_far_out_is_refused_by_every_mesh_strategy() {
    let cube = far_cube();
    let c = cube.to_str().unwrap();
    let out = temp("far.json");
    let o = out.to_str().unwrap();
    for strategy in ["raster", "pencil", "waterline", "steep-shallow", "rest"] {
        let mut args = vec![
            "plan",
            c,
            "--tool",
            "ball:d=6",
            "--strategy",
            strategy,
            "-o",
            o,
        ];
        if strategy == "rest" {
            args.extend(["--reference-tool", "ball:d=10"]);
        }
        refused(&args, "far-cube.stl");
    }
}

/// Finding 5: `plan raster --tolerance 1e-300` hung and `zlevel-rough --step-down 1e-300` aborted on
/// allocation: every length of an operation lies in bounds, and the error names it.
#[test]
fn lengths_of_an_operation_out_of_bounds_are_refused_naming_them() {
    let hills = common::data("bicubic-hills.stl");
    let h = hills.to_str().unwrap();
    let out = temp("bounds.json");
    let o = out.to_str().unwrap();
    let plan = |strategy: &str, option: &str, value: &str| {
        refused(
            &[
                "plan",
                h,
                "--tool",
                "ball:d=6",
                "--strategy",
                strategy,
                option,
                value,
                "-o",
                o,
            ],
            "bicubic-hills.stl",
        )
    };
    assert!(plan("raster", "--tolerance", "1e-300").contains("chord tolerance"));
    assert!(plan("raster", "--scallop", "1e300").contains("scallop height"));
    assert!(plan("zlevel-rough", "--step-down", "1e-300").contains("step-down"));
    assert!(plan("zlevel-rough", "--step-down", "1e300").contains("step-down"));
    assert!(plan("zlevel-rough", "--stock-to-leave", "1e300").contains("stock to leave"));
    assert!(plan("waterline", "--tolerance", "1e-300").contains("chord tolerance"));
    assert!(plan("raster", "--clearance", "1e300").contains("clearance"));
}

/// Finding 6: `feed` on a 5-million-line program, a huge control script and a CSV profile of more
/// points than any profile has aborted on allocation: each is refused, naming the file and
/// the limit, before it is parsed.
#[test]
fn programs_scripts_and_profiles_beyond_their_line_limits_are_refused() {
    let _one = HEAVY
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner);
    let mut text = String::with_capacity(40_000_000);
    text.push_str("G21 G90\nG1 F1000\n");
    for i in 0..5_000_000u32 {
        text.push_str(if i % 2 == 0 { "X1\n" } else { "X0\n" });
    }
    text.push_str("M30\n");
    let prog = temp("five-million.ngc");
    std::fs::write(&prog, &text).unwrap();
    drop(text);
    let p = prog.to_str().unwrap();
    let e = refused(&["feed", p, "--machine", "mill-3axis"], "five-million.ngc");
    assert!(e.contains("4000000 lines"), "{e}");
    refused(
        &[
            "simulate",
            p,
            "--tool",
            "ball:d=6",
            "--stock",
            "box:0,0,-5,10,10,0",
            "--resolution",
            "0.5",
        ],
        "five-million.ngc",
    );
    let script = temp("long-script.txt");
    std::fs::write(&script, "home\n".repeat(200_000)).unwrap();
    let e = refused(
        &[
            "control",
            "--machine",
            "mill-3axis",
            "--script",
            script.to_str().unwrap(),
        ],
        "long-script.txt",
    );
    assert!(e.contains("100000 lines"), "{e}");
    let mut csv = String::with_capacity(20_000_000);
    for i in 0..1_000_001u32 {
        csv.push_str(&format!("{i},0\n"));
    }
    let f = temp("million.csv");
    std::fs::write(&f, csv).unwrap();
    let e = refused(
        &["profile", f.to_str().unwrap(), "--radius", "1"],
        "million.csv",
    );
    assert!(e.contains("1000000"), "{e}");
    for p in [&prog, &f] {
        let _ = std::fs::remove_file(p);
    }
}

/// Finding 7: Tool sizes had no upper bound (a ball of 10³⁰⁰ mm removed 0 mm³, one of 10²⁰ mm exactly
/// half the stock): every size lies in 0.001–1000 mm (lengths to 5000 mm), in the tool spec
/// and in a project's tools.
#[test]
fn tool_sizes_out_of_bounds_are_refused_in_specs_and_projects() {
    let prog = temp("square.nc");
    std::fs::write(&prog, "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nX10\nM30\n").unwrap();
    let p = prog.to_str().unwrap();
    for tool in [
        "ball:d=1e300",
        "ball:d=1e20",
        "flat:d=1e-9",
        "flat:d=6,flute=1e9",
    ] {
        let e = refused(
            &[
                "simulate",
                p,
                "--tool",
                tool,
                "--stock",
                "box:0,0,-5,10,10,0",
                "--resolution",
                "0.5",
            ],
            "tool",
        );
        assert!(e.contains("mm"), "{e}");
    }
    // The largest ball accepted still cuts what a ball of that size cuts: its lowest point
    // under the path, a slot 1 mm deep along X (10 mm × 10 mm wide stock, all of the top
    // within the ball's reach): 10 × 10 × 1 mm³ less nothing.
    let out = assert_clean(
        &[
            "simulate",
            p,
            "--tool",
            "ball:d=1000",
            "--stock",
            "box:0,0,-5,10,10,0",
            "--resolution",
            "0.5",
            "--json",
        ],
        "square.nc",
    );
    assert_eq!(out.status.code(), Some(0));
    let removed = json(&out)["removed_volume_mm3"].as_f64().unwrap();
    assert!(removed > 0.0 && removed <= 100.0 + 1e-6, "{removed}");
    // A project's tool is checked by the same rule.
    let text = "version = 1\nname = \"t\"\nmachine = \"mill-3axis\"\n\n[[tools]]\nname = \"Huge\"\nspec = \"ball:d=1e20\"\n\n[post]\ndialect = \"linuxcnc\"\ntcp = false\n";
    let e = talas::project::Project::from_toml(text, Path::new("huge.talas")).unwrap_err();
    let e = e.to_string();
    assert!(e.contains("huge.talas") && e.contains("diameter"), "{e}");
}

/// A minimal project, with `extra` lines in its first operation.
fn project_text(part: &str, extra: &str) -> String {
    format!(
        "version = 1\nname = \"p\"\nmachine = \"mill-3axis\"\nselected_tool = 0\n\n[part]\npath = \"{part}\"\n\n\
         [[tools]]\nname = \"Ball 6\"\nspec = \"ball:d=6\"\n\n[post]\ndialect = \"linuxcnc\"\ntcp = false\n\n\
         [[operations]]\nkind = \"raster\"\nname = \"Top\"\ntool = 0\nscallop_mm = 0.4\nangle_rad = 0.0\n\
         clearance_mm = 5.0\n{extra}"
    )
}

/// Finding 8: A project's unknown keys are warned about (the key and the file), a relative part path
/// resolves against the project's folder (not the working directory), and a scallop of
/// 1e-300 or a stock of ±1e300 is refused with the field named.
#[test]
fn projects_warn_of_unknown_keys_resolve_parts_beside_them_and_refuse_wild_numbers() {
    use talas::project::Project;
    let dir = temp("project-dir");
    let dir = dir.with_extension("d");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy(common::data("plate-hole.stp"), dir.join("part.stp")).unwrap();
    let file = dir.join("p.talas");
    std::fs::write(&file, project_text("part.stp", "scalop_mm = 0.1\n")).unwrap();
    // The working directory of the tests is the crate, not the project's folder.
    assert!(!Path::new("part.stp").exists());
    let (project, warnings) = Project::load_with_warnings(&file).expect("loads");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(
        warnings[0].contains("p.talas") && warnings[0].contains("scalop_mm"),
        "{warnings:?}"
    );
    let part = project.part.expect("a part");
    assert_eq!(
        std::fs::canonicalize(&part.path).unwrap(),
        std::fs::canonicalize(dir.join("part.stp")).unwrap()
    );
    assert_eq!(part.status(), talas::project::PartStatus::Unchanged);
    // `talas job` prints the warning.
    let (out, _) = talas_bounded(
        &["job", file.to_str().unwrap(), "--json"],
        Duration::from_secs(10),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("warning") && stderr.contains("scalop_mm"),
        "{stderr}"
    );
    assert_eq!(out.status.code(), Some(0), "{stderr}");
    // Wild numbers are refused, naming the field.
    let tiny = project_text("part.stp", "").replace("scallop_mm = 0.4", "scallop_mm = 1e-300");
    let e = Project::from_toml(&tiny, &file).unwrap_err().to_string();
    assert!(e.contains("p.talas") && e.contains("scallop"), "{e}");
    let wide = project_text("part.stp", "")
        + "\n[stock]\nkind = \"box\"\nmin_mm = [-1e300, 0.0, 0.0]\nmax_mm = [1e300, 10.0, 10.0]\n";
    let e = Project::from_toml(&wide, &file).unwrap_err().to_string();
    assert!(e.contains("stock"), "{e}");
}

/// Finding 10: `talas control` exited 0 when its program could not be read (AUTO raised an alarm and
/// the run went on): it now exits 2 naming the program and the line.
#[test]
fn control_refuses_a_program_it_cannot_read() {
    let script = temp("auto.txt");
    std::fs::write(&script, "home\nmode auto\ncycle-start\nwait-idle\n").unwrap();
    let s = script.to_str().unwrap();
    let bad = temp("unreadable.ngc");
    std::fs::write(&bad, "G21 G90\nG1 X10 F100\nG99999\nM30\n").unwrap();
    let e = refused(
        &[
            "control",
            "--machine",
            "mill-3axis",
            "--script",
            s,
            "--program",
            bad.to_str().unwrap(),
        ],
        "unreadable.ngc",
    );
    assert!(e.contains("line 3"), "{e}");
    let missing = temp("missing.ngc");
    refused(
        &[
            "control",
            "--machine",
            "mill-3axis",
            "--script",
            s,
            "--program",
            missing.to_str().unwrap(),
        ],
        "missing.ngc",
    );
    // A program it can read runs.
    let good = temp("good.ngc");
    std::fs::write(&good, "G21 G90\nG0 X10 Y10 Z50\nM30\n").unwrap();
    let out = assert_clean(
        &[
            "control",
            "--machine",
            "mill-3axis",
            "--script",
            s,
            "--program",
            good.to_str().unwrap(),
            "--json",
        ],
        "good.ngc",
    );
    assert_eq!(out.status.code(), Some(0));
}
