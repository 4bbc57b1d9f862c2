//! Helpers the integration tests share: `assert_near!` and `assert_rel_near!`, a seeded
//! random-number generator, the files under `tests/data` (bicubic-hills as STL mesh and as STEP
//! part), temporary folders, and running the `talas` binary. `geometry` holds the geometry
//! tests' reference builders (finite differences, Cox–de Boor, exact conics); `app` (GUI
//! builds) the workstation tests' accessors of the stock simulation and the posted program.
//!
//! A test file takes them with `mod common;` and `use common::…`.

#![allow(dead_code, unused_imports, unused_macros)] // each test file uses its own subset

#[cfg(feature = "gui")]
pub mod app;
pub mod geometry;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Asserts `|value − expected| ≤ tolerance`; the message names the value, the expected value,
/// the difference and the tolerance, after an optional `format!`-style description.
macro_rules! assert_near {
    ($value:expr, $expected:expr, $tolerance:expr $(,)?) => {{
        let (value, expected, tolerance): (f64, f64, f64) = ($value, $expected, $tolerance);
        assert!(
            (value - expected).abs() <= tolerance,
            "got {value}, expected {expected} (difference {:e}, tolerance {tolerance:e})",
            (value - expected).abs(),
        );
    }};
    ($value:expr, $expected:expr, $tolerance:expr, $($what:tt)+) => {{
        let (value, expected, tolerance): (f64, f64, f64) = ($value, $expected, $tolerance);
        assert!(
            (value - expected).abs() <= tolerance,
            "{}: got {value}, expected {expected} (difference {:e}, tolerance {tolerance:e})",
            format_args!($($what)+),
            (value - expected).abs(),
        );
    }};
}
pub(crate) use assert_near;

/// Asserts `|value − expected| ≤ relative · max(|expected|, 1e-12)`, through `assert_near!`.
macro_rules! assert_rel_near {
    ($value:expr, $expected:expr, $relative:expr $(,)?) => {{
        let expected: f64 = $expected;
        $crate::common::assert_near!($value, expected, $relative * expected.abs().max(1e-12))
    }};
}
pub(crate) use assert_rel_near;

/// Deterministic pseudo-random numbers from a 64-bit linear congruential generator (Knuth's
/// MMIX constants) with a fixed seed: the same seed gives the same sequence on every run.
pub struct Lcg(pub u64);

impl Lcg {
    fn step(&mut self) -> u64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        self.0
    }
    /// Uniform in [0, 1) (the state's top 53 bits).
    pub fn next(&mut self) -> f64 {
        (self.step() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
    /// The state's top 31 bits.
    pub fn bits(&mut self) -> u64 {
        self.step() >> 33
    }
    /// An index in 0..n (0 when n is 0), from `bits`.
    pub fn below(&mut self, n: usize) -> usize {
        (self.bits() % n.max(1) as u64) as usize
    }
}

/// A file under `tests/data`.
pub fn data(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(p)
}

/// The bicubic-hills triangle mesh (`tests/data/bicubic-hills.stl`).
pub fn hills_stl() -> talas::geometry::mesh::TriMesh {
    use talas::import::stl::{StlOptions, read_stl};
    read_stl(&data("bicubic-hills.stl"), &StlOptions::default())
        .expect("bicubic-hills.stl reads")
        .mesh
}

/// The pocket-fillets part as Open CASCADE tessellated it (`tests/data/pocket-fillets.stl`).
pub fn pocket_fillets_stl() -> talas::geometry::mesh::TriMesh {
    use talas::import::stl::{StlOptions, read_stl};
    read_stl(&data("pocket-fillets.stl"), &StlOptions::default())
        .expect("pocket-fillets.stl reads")
        .mesh
}

/// The bicubic-hills part, one B-spline face (`tests/data/bicubic-hills.stp`).
pub fn hills_step() -> talas::geometry::brep::Part {
    talas::import::step::read_step(&data("bicubic-hills.stp")).expect("bicubic-hills.stp reads")
}

/// An empty folder of this test process under the system's temporary folder (`tag` keeps test
/// files and tests apart); whatever an earlier run left there is removed.
pub fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("talas-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The path `name` in a folder of this test process (`tag` keeps test files apart); the folder
/// exists, the file is not written.
pub fn temp_path(tag: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("talas-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

/// Write `text` to `name` in a folder of this test process (`tag` keeps test files apart).
pub fn temp_file(tag: &str, name: &str, text: &str) -> PathBuf {
    let p = temp_path(tag, name);
    std::fs::write(&p, text).unwrap();
    p
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
