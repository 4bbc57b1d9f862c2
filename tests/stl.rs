//! STL reader and writer against the Open CASCADE reference files (tests/data/README.md), round
//! trips through the writers, and malformed files (tests/data/bad-stl) that must give an error
//! naming the file and the place.

mod common;

use std::path::Path;

use common::data;

use talas::diagnostics::Severity;
use talas::import::stl::{
    StlFormat, StlOptions, parse_stl, read_stl, save_stl, write_stl_ascii, write_stl_binary,
};

/// The facet count in a binary STL's header, read independently of the reader under test.
fn header_count(bytes: &[u8]) -> usize {
    let b: [u8; 4] = bytes[80..84].try_into().unwrap();
    u32::from_le_bytes(b) as usize
}

/// The 36 vertex bytes (three f32 points) of facet `k` of a binary STL.
fn vertex_bytes(bytes: &[u8], k: usize) -> &[u8] {
    let off = 84 + 50 * k + 12;
    &bytes[off..off + 36]
}

fn rel_err(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn reference_files_have_their_header_facet_counts() {
    for name in ["bicubic-hills.stl", "pocket-fillets.stl"] {
        let bytes = std::fs::read(data(name)).unwrap();
        let count = header_count(&bytes);
        assert_eq!(
            bytes.len(),
            84 + 50 * count,
            "{name} is a well-formed binary STL"
        );
        let stl = read_stl(&data(name), &StlOptions::default()).unwrap();
        assert_eq!(stl.format, StlFormat::Binary);
        assert_eq!(stl.facet_count, count, "{name}");
        // Facets with two bit-identical corners (pocket-fillets has four, at the sphere poles of
        // the pocket's corners), found from the raw bytes: zero area, and collapsed by welding.
        let collapsed: Vec<usize> = (0..count)
            .filter(|&k| {
                let v = vertex_bytes(&bytes, k);
                v[..12] == v[12..24] || v[12..24] == v[24..] || v[..12] == v[24..]
            })
            .collect();
        assert_eq!(stl.degenerate_facets, collapsed, "{name}");
        assert_eq!(stl.mesh.triangles.len(), count - collapsed.len(), "{name}");
        assert_eq!(stl.mesh.normals.len(), stl.mesh.positions.len());
    }
}

#[test]
fn pocket_fillets_is_closed_with_open_cascade_volume_and_area() {
    let stl = read_stl(&data("pocket-fillets.stl"), &StlOptions::default()).unwrap();
    let mesh = &stl.mesh;
    assert!(
        mesh.is_closed(),
        "boundary edges: {}",
        mesh.boundary_edges().len()
    );
    assert!(mesh.bad_edges().is_empty());
    // Open CASCADE: volume 205311.2098 mm³, area 29249.3361 mm² (tests/data/README.md).
    let v = mesh.signed_volume();
    let a = mesh.area();
    assert!(rel_err(v, 205_311.209_8) < 0.005, "volume {v}");
    assert!(rel_err(a, 29_249.336_1) < 0.001, "area {a}");
    let b = mesh.bbox();
    assert!(b.min.abs_diff_eq(glam::DVec3::ZERO, 1e-4), "{b:?}");
    assert!(
        b.max.abs_diff_eq(glam::DVec3::new(100.0, 80.0, 30.0), 1e-4),
        "{b:?}"
    );
    // A closed mesh: the reader adds no "open" note.
    assert!(
        stl.diagnostics.iter().all(|d| !d.message.contains("open")),
        "{:?}",
        stl.diagnostics
    );
}

#[test]
fn bicubic_hills_matches_open_cascade_area_and_box() {
    let stl = read_stl(&data("bicubic-hills.stl"), &StlOptions::default()).unwrap();
    // Open CASCADE: area 19710.4308 mm², box (0, 0, −11.6358) – (160, 120, 11.6678); the mesh
    // was made with a 0.01 mm chord deflection.
    let a = stl.mesh.area();
    assert!(rel_err(a, 19_710.430_8) < 0.001, "area {a}");
    let b = stl.mesh.bbox();
    let (lo, hi) = (
        glam::DVec3::new(0.0, 0.0, -11.6358),
        glam::DVec3::new(160.0, 120.0, 11.6678),
    );
    assert!(b.min.abs_diff_eq(lo, 0.011), "{b:?}");
    assert!(b.max.abs_diff_eq(hi, 0.011), "{b:?}");
    // One open sheet: its boundary is the four sides.
    assert!(!stl.mesh.is_closed());
    assert!(stl.diagnostics.iter().any(|d| d.message.contains("open")));
}

#[test]
fn unit_scale_scales_coordinates() {
    let opts = StlOptions {
        unit_scale: 25.4,
        ..StlOptions::default()
    };
    let stl = read_stl(&data("pocket-fillets.stl"), &opts).unwrap();
    let b = stl.mesh.bbox();
    assert!(
        b.max
            .abs_diff_eq(glam::DVec3::new(2540.0, 2032.0, 762.0), 1e-2),
        "{b:?}"
    );
    let bad = StlOptions {
        unit_scale: 0.0,
        ..StlOptions::default()
    };
    assert!(read_stl(&data("pocket-fillets.stl"), &bad).is_err());
    let bad = StlOptions {
        weld_tol_mm: f64::NAN,
        ..StlOptions::default()
    };
    assert!(read_stl(&data("pocket-fillets.stl"), &bad).is_err());
}

#[test]
fn binary_round_trip_is_bit_exact() {
    let original = std::fs::read(data("bicubic-hills.stl")).unwrap();
    let count = header_count(&original);
    let stl = parse_stl(
        &original,
        Path::new("bicubic-hills.stl"),
        &StlOptions::default(),
    )
    .unwrap();
    let mut written = Vec::new();
    write_stl_binary(&stl.mesh, &mut written).unwrap();
    assert_eq!(written.len(), original.len());
    assert_eq!(header_count(&written), count);
    assert!(!written.starts_with(b"solid"));
    for k in 0..count {
        assert_eq!(
            vertex_bytes(&written, k),
            vertex_bytes(&original, k),
            "facet {k}"
        );
    }
    // And written → read → written again is byte for byte the same file.
    let again = parse_stl(&written, Path::new("x.stl"), &StlOptions::default()).unwrap();
    let mut rewritten = Vec::new();
    write_stl_binary(&again.mesh, &mut rewritten).unwrap();
    assert_eq!(rewritten, written);
}

#[test]
fn ascii_round_trip_keeps_facets_and_coordinates() {
    let stl = read_stl(&data("pocket-fillets.stl"), &StlOptions::default()).unwrap();
    let mut text = Vec::new();
    write_stl_ascii(&stl.mesh, "pocket fillets", &mut text).unwrap();
    assert!(text.starts_with(b"solid pocket fillets\n"));
    let back = parse_stl(&text, Path::new("pocket.stl"), &StlOptions::default()).unwrap();
    assert_eq!(back.format, StlFormat::Ascii);
    assert_eq!(back.name, "pocket fillets");
    assert_eq!(back.facet_count, stl.mesh.triangles.len());
    assert_eq!(
        back.mesh.positions, stl.mesh.positions,
        "shortest f64 text reads back exactly"
    );
    assert_eq!(back.mesh.triangles, stl.mesh.triangles);
}

#[test]
fn binary_whose_header_starts_with_solid_is_read_as_binary() {
    let mut bytes = std::fs::read(data("pocket-fillets.stl")).unwrap();
    let count = header_count(&bytes);
    bytes[..80].copy_from_slice(
        b"solid pocket exported by a careless tool                                        ",
    );
    let stl = parse_stl(&bytes, Path::new("solid.stl"), &StlOptions::default()).unwrap();
    assert_eq!(stl.format, StlFormat::Binary);
    assert_eq!(stl.facet_count, count);
    assert_eq!(stl.name, "solid pocket exported by a careless tool");
    // With a few stray bytes at the end it is still binary, with a warning.
    bytes.extend_from_slice(b"\0\0\0");
    let stl = parse_stl(&bytes, Path::new("solid.stl"), &StlOptions::default()).unwrap();
    assert_eq!(stl.format, StlFormat::Binary);
    assert!(
        stl.diagnostics
            .iter()
            .any(|d| d.severity == Severity::Warning && d.message.contains("stray"))
    );
}

#[test]
fn ascii_dialects_are_accepted() {
    let text = "SOLID Part 1\nFACET NORMAL 0 0 -1\nOUTER LOOP\nVERTEX 0 0 0\nVERTEX 0 1 0\n\
                VERTEX 1 0 0\nENDLOOP\nENDFACET\nENDSOLID\nsolid second\r\n facet outer loop \
                vertex 0 0 1 vertex 1 0 1 vertex 0 1 1 endloop endfacet\r\n";
    let stl = parse_stl(text.as_bytes(), Path::new("d.stl"), &StlOptions::default()).unwrap();
    assert_eq!(stl.format, StlFormat::Ascii);
    assert_eq!(stl.facet_count, 2);
    assert_eq!(stl.name, "Part 1");
    assert!(
        stl.diagnostics
            .iter()
            .any(|d| d.message.contains("endsolid")),
        "missing endsolid noted"
    );
    // Stored normal (0, 0, -1) agrees with the first facet's winding; nothing flipped.
    assert!(
        stl.diagnostics
            .iter()
            .all(|d| !d.message.contains("opposite"))
    );
}

#[test]
fn save_is_atomic_and_reads_back() {
    let dir = std::env::temp_dir().join(format!("talas-stl-save-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let stl = read_stl(&data("pocket-fillets.stl"), &StlOptions::default()).unwrap();
    for (format, name) in [(StlFormat::Binary, "b.stl"), (StlFormat::Ascii, "a.stl")] {
        let path = dir.join(name);
        save_stl(&path, &stl.mesh, format).unwrap();
        let back = read_stl(&path, &StlOptions::default()).unwrap();
        assert_eq!(back.format, format);
        assert_eq!(back.mesh.positions, stl.mesh.positions);
    }
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 2, "no temporary file left: {left:?}");
    let missing = dir.join("no-such-dir/x.stl");
    let err = save_stl(&missing, &stl.mesh, StlFormat::Binary).unwrap_err();
    assert_eq!(err.file, missing);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every malformed file gives an error naming the file, the expected place, and what is wrong.
#[test]
fn malformed_files_give_errors_with_places() {
    let cases: &[(&str, &str, &str)] = &[
        ("empty.stl", "byte 0", "empty"),
        ("short.stl", "byte 40", "too short"),
        ("truncated-binary.stl", "facet 3, byte 234", "truncated"),
        (
            "absurd-count.stl",
            "facet 18, byte 984",
            "4000000000 facets",
        ),
        ("extra-facets.stl", "byte 134", "mismatch"),
        ("nan-binary.stl", "facet 2, byte 212", "NaN"),
        ("inf-binary.stl", "facet 0, byte 128", "infinite"),
        ("ascii-truncated.stl", "line 5", "unexpected end of file"),
        ("ascii-bad-number.stl", "line 5", "\"abc\""),
        ("ascii-nan.stl", "line 6", "not finite"),
        ("ascii-overflow.stl", "line 4", "not finite"),
        ("ascii-four-vertices.stl", "line 7", "more than 3 vertices"),
        ("ascii-two-vertices.stl", "line 6", "2 vertices"),
        ("ascii-non-utf8.stl", "line 4", "UTF-8"),
        ("ascii-missing-loop.stl", "line 4", "expected \"loop\""),
        ("ascii-inner-loop.stl", "line 3", "expected \"outer\""),
        ("ascii-junk-after-endsolid.stl", "line 10", "garbage"),
        ("ascii-junk-in-solid.stl", "line 9", "\"hello\""),
        (
            "solid-binary-garbage.stl",
            "line 1",
            "not a binary STL either",
        ),
    ];
    for (name, place, message) in cases {
        let path = data(&format!("bad-stl/{name}"));
        let err = match read_stl(&path, &StlOptions::default()) {
            Ok(stl) => panic!(
                "{name}: read as {:?} with {} facets",
                stl.format, stl.facet_count
            ),
            Err(e) => e,
        };
        assert_eq!(err.file, path, "{name}");
        assert_eq!(err.place.as_deref(), Some(*place), "{name}: {err}");
        assert!(err.message.contains(message), "{name}: {err}");
        assert!(err.to_string().contains(name), "{name}: {err}");
    }
}

#[test]
fn random_bytes_give_a_binary_error() {
    let path = data("bad-stl/random-bytes.stl");
    let bytes = std::fs::read(&path).unwrap();
    let err = read_stl(&path, &StlOptions::default()).unwrap_err();
    // Independent expectation: the header's count against the 1000-byte length.
    let expected = 84 + 50 * header_count(&bytes) as u64;
    let place = err.place.clone().unwrap();
    if expected > 1000 {
        assert_eq!(place, "facet 18, byte 984", "{err}");
    } else {
        assert_eq!(place, format!("byte {expected}"), "{err}");
    }
}

#[test]
fn every_prefix_of_a_small_file_is_handled() {
    // Truncation at every byte of both encodings: an error or a mesh, never a panic.
    let stl = read_stl(&data("pocket-fillets.stl"), &StlOptions::default()).unwrap();
    let mut small = stl.mesh.clone();
    small.triangles.truncate(4);
    let mut bin = Vec::new();
    write_stl_binary(&small, &mut bin).unwrap();
    let mut text = Vec::new();
    write_stl_ascii(&small, "s", &mut text).unwrap();
    for bytes in [&bin, &text] {
        for n in 0..bytes.len() {
            let _ = parse_stl(&bytes[..n], Path::new("p.stl"), &StlOptions::default());
        }
    }
    let full = parse_stl(&bin, Path::new("p.stl"), &StlOptions::default()).unwrap();
    assert_eq!(full.facet_count, 4);
}
