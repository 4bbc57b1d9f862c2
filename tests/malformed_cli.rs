//! Malformed input through the command line: every bad file gives exit code 2 and one line on
//! stderr naming the file and the place (line, #id, byte offset or facet); nothing panics.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bad_files() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
    let mut files = Vec::new();
    for dir in ["bad", "bad-stl"] {
        if let Ok(entries) = std::fs::read_dir(root.join(dir)) {
            files.extend(
                entries
                    .filter_map(Result::ok)
                    .map(|e| e.path())
                    .filter(|p| p.is_file()),
            );
        }
    }
    files.sort();
    files
}

fn names_a_place(line: &str) -> bool {
    let after = |key: &str| {
        line.match_indices(key)
            .any(|(i, _)| line[i + key.len()..].starts_with(|c: char| c.is_ascii_digit()))
    };
    after("line ") || after("byte ") || after("facet ") || after("#")
}

#[test]
fn at_least_thirty_bad_files_each_fail_cleanly_with_a_place() {
    let files = bad_files();
    assert!(files.len() >= 30, "only {} malformed files", files.len());
    let mut failures = Vec::new();
    for file in &files {
        let out = Command::new(env!("CARGO_BIN_EXE_talas"))
            .arg("inspect")
            .arg(file)
            .output()
            .expect("run talas");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let lines: Vec<&str> = stderr.lines().collect();
        let name = file.file_name().and_then(|n| n.to_str()).unwrap_or("?");
        let ok = out.status.code() == Some(2)
            && lines.len() == 1
            && lines[0].contains(name)
            && names_a_place(lines[0])
            && !stderr.contains("panicked");
        if !ok {
            failures.push(format!(
                "{name}: exit {:?}, stderr {stderr:?}",
                out.status.code()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn the_place_check_can_fail() {
    assert!(names_a_place("talas: a.stp: line 3, #12: bad"));
    assert!(names_a_place("talas: a.stl: byte 84: truncated"));
    assert!(!names_a_place("talas: a.stp: something went wrong"));
}

#[test]
fn missing_file_is_bad_input() {
    let out = Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["inspect", "/nonexistent/part.stp"])
        .output()
        .expect("run talas");
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(String::from_utf8_lossy(&out.stderr).lines().count(), 1);
}
