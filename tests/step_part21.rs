//! ISO 10303-21 reader against real files (Open CASCADE references and the adversarial corpus),
//! hand-made malformed files, and every syntax feature.

use std::path::{Path, PathBuf};

use talas::import::step::part21::parse;

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(rel)
}

fn read(rel: &str) -> Vec<u8> {
    std::fs::read(data(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"))
}

#[test]
fn reference_parts_parse() {
    for (file, count) in [
        ("pocket-fillets.stp", 0),
        ("bicubic-hills.stp", 0),
        ("rational-trough.stp", 0),
    ] {
        let ex = parse(&read(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(ex.instances.len() > count, "{file}");
        assert!(ex.dangling_refs().is_empty(), "{file}");
    }
}

/// The adversarial files this reader refuses at parse level although Open CASCADE reads them
/// (they are all `transfer_empty` there: OCCT reads the text, finds no shape), with the reason:
///
/// - `Ad002`: aggregates nested about 120 deep; we stop at `MAX_DEPTH` = 64 instead of risking
///   the stack.
/// - `Ad014`: `1.0E+999999` is not a finite real; we never hand NaN/inf to the geometry.
/// - `Ad049`: `1.0D0` (Fortran exponent) and `1_000.0` are not Part 21 reals; guessing their
///   value would hide unit-corruption bugs.
/// - `Ad051`: `#-1` is not an instance name.
/// - `Ad080`: a second DATA section redefines `#1`..`#7`; which definition wins is a guess, and
///   Open CASCADE itself refuses duplicate ids.
/// - `Ad089`: `(1.0,2.0,3.0,)` has a missing parameter after the trailing comma.
///
/// `Ad001` (a 32 768-byte string) is `read_failed` in Open CASCADE and refused here too; every
/// `read_ok` file parses. The remaining `transfer_empty` files are syntactically fine (their
/// defects are semantic: dangling refs, cycles, bad B-spline data) and parse.
const REJECTED_TRANSFER_EMPTY: [&str; 6] = ["Ad002", "Ad014", "Ad049", "Ad051", "Ad080", "Ad089"];

#[test]
fn manifest_corpus_matches_open_cascade() {
    let manifest = std::fs::read_to_string(data("real/MANIFEST.csv")).expect("manifest");
    let mut counts = [0_usize; 3];
    for line in manifest.lines().skip(1) {
        let path = line.split(',').next().unwrap_or_default();
        let status = ["read_ok", "read_failed", "transfer_empty"]
            .into_iter()
            .find(|s| line.contains(&format!(",{s},")))
            .unwrap_or_else(|| panic!("no OCCT status in {line}"));
        let result = parse(&read(&format!("real/{path}")));
        let stem = Path::new(path)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or_default();
        match status {
            "read_ok" => {
                let ex = result.unwrap_or_else(|e| panic!("{path} (OCCT read_ok): {e}"));
                assert!(!ex.instances.is_empty(), "{path}");
                counts[0] += 1;
            }
            "read_failed" => {
                let e = result.expect_err(path);
                assert!(e.line > 0, "{path}: {e}");
                counts[1] += 1;
            }
            _ => {
                assert_eq!(
                    result.is_err(),
                    REJECTED_TRANSFER_EMPTY.contains(&stem),
                    "{path}: {result:?}"
                );
                counts[2] += 1;
            }
        }
    }
    assert_eq!(counts, [20, 1, 31]);
}
