//! Helpers the command-line tests share: run the `talas` binary, parse its JSON, write
//! temporary inputs.

#![allow(dead_code)] // each test file uses its own subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A file under `tests/data`.
pub fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(p)
}

/// Run `talas` with `args`.
pub fn talas(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(args)
        .output()
        .unwrap()
}

/// Run `talas` with `args` (ending in `--json`), require success, and parse its JSON.
pub fn talas_json(args: &[&str]) -> serde_json::Value {
    let out = talas(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// Write `text` to `name` in a folder of this test process (`tag` keeps test files apart).
pub fn temp_file(tag: &str, name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("talas-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}
