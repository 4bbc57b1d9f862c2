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
    loop {
        if child.try_wait().expect("wait").is_some() {
            let out = child.wait_with_output().expect("output");
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

/// A clean outcome: a result (0) or one error line naming the file (2); never a crash.
fn assert_clean(args: &[&str], named: &str) -> Output {
    let (out, took) = talas_bounded(args, Duration::from_secs(10));
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
