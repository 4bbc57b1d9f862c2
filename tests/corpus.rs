//! Real CAD exports and adversarial STEP files (tests/data/real, see its README and MANIFEST.csv):
//! Talas reads every file Open CASCADE reads, with the same faces and area, and fails cleanly
//! (exit code 2, one line naming the file) on the rest.

use std::path::{Path, PathBuf};
use std::process::Command;

fn real_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/real")
}

/// Split one CSV line, honouring double quotes.
fn csv_fields(line: &str) -> Vec<String> {
    let mut fields = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => fields.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    fields.push(cur);
    fields
}

struct Row {
    path: String,
    status: String,
    faces: Option<usize>,
    area: Option<f64>,
}

fn manifest() -> Vec<Row> {
    let text = std::fs::read_to_string(real_dir().join("MANIFEST.csv")).expect("manifest");
    let mut lines = text.lines();
    let header = csv_fields(lines.next().expect("header"));
    let col = |name: &str| header.iter().position(|h| h == name).expect("column");
    let (cp, cs, cf, ca) = (
        col("path"),
        col("occt_status"),
        col("occt_faces"),
        col("occt_area_mm2"),
    );
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let f = csv_fields(l);
            Row {
                path: f[cp].clone(),
                status: f[cs].clone(),
                faces: f[cf].parse().ok(),
                area: f[ca].parse().ok(),
            }
        })
        .collect()
}

#[test]
fn manifest_parses() {
    assert_eq!(csv_fields(r#"a,"b, c",d"#), vec!["a", "b, c", "d"]);
    let rows = manifest();
    assert_eq!(rows.len(), 52);
}

#[test]
fn every_file_open_cascade_reads_is_read_with_the_same_faces_and_area() {
    let mut failures = Vec::new();
    for row in manifest() {
        let file = real_dir().join(&row.path);
        let out = Command::new(env!("CARGO_BIN_EXE_talas"))
            .arg("inspect")
            .arg(&file)
            .arg("--json")
            .output()
            .expect("run talas");
        let stderr = String::from_utf8_lossy(&out.stderr);
        if row.status == "read_ok" {
            if !out.status.success() {
                failures.push(format!(
                    "{}: OCCT reads it, Talas failed: {stderr}",
                    row.path
                ));
                continue;
            }
            let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
            let faces = doc["faces"].as_array().map_or(0, Vec::len);
            if Some(faces) != row.faces {
                failures.push(format!("{}: {faces} faces, OCCT {:?}", row.path, row.faces));
            }
            let area = doc["area_mm2"].as_f64().unwrap_or(0.0);
            if let Some(ref_area) = row.area
                && (area - ref_area).abs() > 1e-3 * ref_area
            {
                failures.push(format!(
                    "{}: area {area:.4} mm², OCCT {ref_area:.4} mm²",
                    row.path
                ));
            }
        } else {
            let lines: Vec<&str> = stderr.lines().collect();
            let named = lines.first().is_some_and(|l| {
                l.contains(file.file_name().and_then(|n| n.to_str()).unwrap_or("?"))
            });
            if out.status.code() != Some(2) || lines.len() != 1 || !named {
                failures.push(format!(
                    "{}: OCCT status {}, Talas exit {:?}, stderr {stderr:?}",
                    row.path,
                    row.status,
                    out.status.code()
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} mismatches:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
