//! The tessellation of real STEP parts against the exact surfaces and against Open CASCADE:
//! - every face kind's triangles lie within the chord tolerance of the exact surface (centroids
//!   and edge midpoints of every triangle projected onto the face's surface);
//! - the triangle count follows the tolerance (Open CASCADE's BRepMesh count at the same
//!   deflection is the yardstick);
//! - no face is lost, every face's area is within 0.01 % of Open CASCADE's, and each closed
//!   body's volume agrees with Open CASCADE's.
//!
//! Parts: `tests/data/real/freecad/` (CATIA V5 exports), `tests/data/real/made/` (made with Open
//! CASCADE by `make_parts.py`: a drilled block with 118° drill points, a thin 1148 mm tube, a
//! fan with B-spline blades, a revolved hub, extruded ribs, a cone, a torus and a sphere). The
//! references in `tests/data/real/occ/` come from `tests/data/real/occ_reference.py`
//! (cadquery-ocp-novtk 8.0.1: BRepGProp areas, volumes and centres, BRepMesh triangle counts).

mod common;

use std::collections::BTreeMap;

use common::data;
use talas::geometry::DVec3;
use talas::geometry::brep::Part;
use talas::geometry::tessellate::{
    TessellationOptions, discretize_edge, tessellate_face, tessellate_part,
};
use talas::import::step::read_step;

const PARTS: [&str; 5] = [
    "real/freecad/Schenkel.stp",
    "real/freecad/as1-ac-214_small.stp",
    "real/made/drilled-block.stp",
    "real/made/thin-tube.stp",
    "real/made/fan.stp",
];

fn part(name: &str) -> Part {
    read_step(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// One row of an Open CASCADE reference table.
struct OccRow {
    what: String,
    kind: String,
    value: f64,
    centre: DVec3,
}

fn occ_reference(name: &str) -> Vec<OccRow> {
    let stem = std::path::Path::new(name)
        .file_stem()
        .and_then(|s| s.to_str())
        .expect("stem");
    let text = std::fs::read_to_string(data(&format!("real/occ/{stem}.csv"))).expect("reference");
    text.lines()
        .skip(1)
        .map(|l| {
            let c: Vec<&str> = l.split(',').collect();
            let num = |i: usize| c[i].trim().parse::<f64>().expect("number");
            OccRow {
                what: c[0].to_string(),
                kind: c[1].to_string(),
                value: num(2),
                centre: DVec3::new(num(3), num(4), num(5)),
            }
        })
        .collect()
}

/// Worst distance (mm) from the exact surface of the interior points of the face's triangles
/// (centroid and edge midpoints), per surface kind, over all faces of `part`. The distance is
/// that to a point found on the surface, so it can only overstate the true one.
fn deviations(part: &Part, tol: f64) -> BTreeMap<&'static str, (f64, usize, u64)> {
    let opts = TessellationOptions::with_chord_tol(tol);
    let polylines: Vec<Vec<DVec3>> = part
        .edges
        .iter()
        .map(|e| discretize_edge(e, &part.vertices, &opts))
        .collect();
    let mut worst: BTreeMap<&'static str, (f64, usize, u64)> = BTreeMap::new();
    for face in &part.faces {
        let s = &face.surface;
        let rect = s.domain();
        let fm = tessellate_face(face, part, &polylines, &opts)
            .unwrap_or_else(|e| panic!("face #{}: {e}", face.source_id));
        let entry = worst.entry(s.kind()).or_insert((0.0, 0, 0));
        for t in &fm.triangles {
            let [a, b, c] = t.map(|i| i as usize);
            let probes = [
                (
                    vec![a, b, c],
                    (fm.positions[a] + fm.positions[b] + fm.positions[c]) / 3.0,
                ),
                (vec![a, b], 0.5 * (fm.positions[a] + fm.positions[b])),
                (vec![b, c], 0.5 * (fm.positions[b] + fm.positions[c])),
                (vec![c, a], 0.5 * (fm.positions[c] + fm.positions[a])),
            ];
            for (vs, p) in probes {
                let hint =
                    vs.iter().map(|&i| fm.uv[i]).sum::<talas::geometry::DVec2>() / vs.len() as f64;
                let mut d = s.closest_point_near(p, rect, hint).distance;
                if d > 0.5 * tol {
                    d = d.min(s.closest_point(p, rect, Some(hint)).distance);
                }
                if d > entry.0 {
                    *entry = (d, entry.1, face.source_id);
                }
            }
        }
        entry.1 += fm.triangles.len();
    }
    worst
}

#[test]
fn every_face_kind_lies_within_the_chord_tolerance_of_its_surface() {
    let mut kinds_seen = std::collections::BTreeSet::new();
    let mut failures = Vec::new();
    for name in PARTS {
        let p = part(name);
        for tol in [0.01, 0.1] {
            for (kind, (dev, tris, id)) in deviations(&p, tol) {
                kinds_seen.insert(kind);
                eprintln!(
                    "{name} tol {tol} mm: {kind}: {tris} triangles, worst {dev:.3e} mm (#{id})"
                );
                if dev > tol * 1.0001 {
                    failures.push(format!("{name} at {tol} mm: {kind} #{id} {dev:.4e} mm"));
                }
            }
        }
    }
    for k in [
        "plane",
        "cylinder",
        "cone",
        "sphere",
        "torus",
        "extrusion",
        "revolution",
        "bspline",
    ] {
        assert!(kinds_seen.contains(k), "no {k} face among the parts");
    }
    assert!(
        failures.is_empty(),
        "beyond the chord tolerance:\n{}",
        failures.join("\n")
    );
}

/// Talas's triangle count against Open CASCADE's BRepMesh at the same deflection (0.01 mm).
#[test]
fn triangle_count_follows_the_chord_tolerance() {
    for name in PARTS {
        let p = part(name);
        let pm = tessellate_part(&p, &TessellationOptions::with_chord_tol(0.01));
        let occ = occ_reference(name)
            .into_iter()
            .find(|r| r.what == "mesh")
            .expect("mesh row")
            .value;
        let n = pm.mesh.triangles.len() as f64;
        eprintln!(
            "{name}: {n} triangles at 0.01 mm, Open CASCADE {occ} ({:.2}x)",
            n / occ
        );
        assert!(n <= 4.0 * occ, "{name}: {n} triangles, Open CASCADE {occ}");
    }
    // The thin tube: a few dozen to hundreds of triangles.
    let pm = tessellate_part(
        &part("real/made/thin-tube.stp"),
        &TessellationOptions::with_chord_tol(0.01),
    );
    let n = pm.mesh.triangles.len();
    assert!((24..=1000).contains(&n), "thin tube: {n} triangles");
}

/// Talas's face of each Open CASCADE face: the one whose triangles' centroid is nearest the
/// reference's centre of mass (`None` where none is within 0.05 mm + 1e-4 of the part's size).
fn match_faces(
    pm: &talas::geometry::tessellate::PartMesh,
    occ: &[&OccRow],
    size: f64,
) -> Vec<Option<usize>> {
    let centroids: Vec<DVec3> = pm
        .faces
        .iter()
        .map(|r| {
            let (mut c, mut a) = (DVec3::ZERO, 0.0);
            for t in &pm.mesh.triangles[r.first..r.first + r.count] {
                let [p, q, s] = t.map(|i| pm.mesh.positions[i as usize]);
                let w = 0.5 * (q - p).cross(s - p).length();
                c += w * (p + q + s) / 3.0;
                a += w;
            }
            if a > 0.0 {
                c / a
            } else {
                DVec3::splat(f64::NAN)
            }
        })
        .collect();
    occ.iter()
        .map(|r| {
            let best = centroids
                .iter()
                .enumerate()
                .filter(|(i, _)| ((pm.faces[*i].area_mm2 - r.value) / r.value).abs() < 0.05)
                .map(|(i, c)| (i, c.distance(r.centre)))
                .filter(|(_, d)| d.is_finite())
                .min_by(|a, b| a.1.total_cmp(&b.1));
            best.filter(|(_, d)| *d < 0.05 + 1e-4 * size)
                .map(|(i, _)| i)
        })
        .collect()
}

#[test]
fn every_face_is_kept_with_its_area_and_every_body_its_volume() {
    let mut failures = Vec::new();
    for name in PARTS {
        let p = part(name);
        let size = p.rough_bbox().diagonal();
        let pm = tessellate_part(&p, &TessellationOptions::with_chord_tol(0.01));
        for d in &pm.diagnostics {
            let id = d
                .place
                .as_deref()
                .and_then(|p| p.strip_prefix('#'))
                .and_then(|p| p.parse::<u64>().ok());
            failures.push(format!(
                "{name}: {:?} {:?} (#{id:?}): {}",
                d.severity, d.place, d.message
            ));
        }
        let occ = occ_reference(name);
        let faces: Vec<&OccRow> = occ.iter().filter(|r| r.what == "face").collect();
        assert_eq!(pm.faces.len(), faces.len(), "{name}: face count");
        let matched = match_faces(&pm, &faces, size);
        let mut used = vec![false; pm.faces.len()];
        let mut worst = 0.0f64;
        for (r, m) in faces.iter().zip(&matched) {
            let Some(i) = *m else {
                failures.push(format!(
                    "{name}: no face matches Open CASCADE's {} of {} mm² at {:?}",
                    r.kind, r.value, r.centre
                ));
                continue;
            };
            if used[i] {
                failures.push(format!("{name}: face {i} matched twice"));
            }
            used[i] = true;
            let rel = (pm.faces[i].area_mm2 - r.value).abs() / r.value;
            worst = worst.max(rel);
            if rel > 1e-4 {
                failures.push(format!(
                    "{name}: face {i} (#{} {}) area {:.6} mm², Open CASCADE {:.6} mm² ({:.3e})",
                    p.faces[i].source_id,
                    p.faces[i].surface.kind(),
                    pm.faces[i].area_mm2,
                    r.value,
                    rel
                ));
            }
        }
        // Bodies: every one closed, volumes equal to Open CASCADE's solids (matched by volume).
        let solids: Vec<f64> = occ
            .iter()
            .filter(|r| r.what == "solid")
            .map(|r| r.value)
            .collect();
        let mut ours: Vec<f64> = pm.bodies.iter().filter_map(|b| b.volume_mm3).collect();
        if ours.len() != pm.bodies.len() {
            failures.push(format!("{name}: a body is not closed: {:?}", pm.bodies));
        }
        let mut theirs = solids.clone();
        ours.sort_by(f64::total_cmp);
        theirs.sort_by(f64::total_cmp);
        let vol_ok = ours.len() == theirs.len()
            && ours
                .iter()
                .zip(&theirs)
                .all(|(a, b)| ((a - b) / b).abs() < 1e-4);
        let total: f64 = ours.iter().sum();
        let occ_total: f64 = theirs.iter().sum();
        eprintln!(
            "{name}: worst face area {worst:.2e}; bodies {:?} mm³ (Open CASCADE {:?}); total {total:.3} (Open CASCADE {occ_total:.3}) mm³",
            ours, theirs
        );
        if !vol_ok {
            failures.push(format!(
                "{name}: volumes {ours:?} mm³, Open CASCADE {theirs:?} mm³"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// What `talas inspect FILE --samples N --json` prints (the command's own function, so that the
/// test runs this build's code).
fn inspect_doc(path: &str, samples: usize) -> serde_json::Value {
    talas::cli::inspect::inspect(&talas::cli::inspect::InspectArgs {
        file: path.into(),
        samples: Some(samples),
        tolerance: Some(0.01),
        json: true,
    })
    .unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// `inspect --samples` gives the face's outward normal: on a `.F.` face the normal and the
/// curvatures change sign against the same surface on a `.T.` face.
#[test]
fn sample_normals_are_the_faces_outward_normals() {
    let text = std::fs::read_to_string(data("bicubic-hills.stp")).expect("hills");
    let flipped = text.replace(
        "ADVANCED_FACE('',(#18),#37,.T.)",
        "ADVANCED_FACE('',(#18),#37,.F.)",
    );
    assert_ne!(text, flipped, "the face line changed");
    let f = common::temp_file("tess-normals", "hills-reversed.stp", &flipped);
    let rows = |path: &str| -> Vec<Vec<f64>> {
        let doc = inspect_doc(path, 5);
        doc["faces"][0]["samples"]
            .as_array()
            .expect("samples")
            .iter()
            .map(|r| {
                r.as_array()
                    .expect("row")
                    .iter()
                    .map(|x| x.as_f64().expect("finite"))
                    .collect()
            })
            .collect()
    };
    let a = rows(data("bicubic-hills.stp").to_str().expect("utf-8"));
    let b = rows(f.to_str().expect("utf-8"));
    assert_eq!(a.len(), 25);
    for (ra, rb) in a.iter().zip(&b) {
        for k in 0..5 {
            assert!(
                (ra[k] - rb[k]).abs() < 1e-12,
                "position differs: {ra:?} {rb:?}"
            );
        }
        for k in 5..8 {
            assert!(
                (ra[k] + rb[k]).abs() < 1e-12,
                "normal not reversed: {ra:?} {rb:?}"
            );
        }
        assert!(
            (ra[8] + rb[9]).abs() < 1e-9 && (ra[9] + rb[8]).abs() < 1e-9,
            "curvatures: {ra:?} {rb:?}"
        );
    }
    // On a closed solid (the fan's B-spline blades, some .T., some .F.), every sample on a face
    // has a normal along the outward winding of the nearest triangle of the face; the winding
    // is outward because the closed mesh's signed volume is positive.
    let fan = data("real/made/fan.stp");
    let doc = inspect_doc(fan.to_str().expect("utf-8"), 9);
    let p = part("real/made/fan.stp");
    let pm = tessellate_part(&p, &TessellationOptions::with_chord_tol(0.01));
    assert!(
        pm.mesh.signed_volume() > 0.0,
        "the fan's mesh winds outward"
    );
    let mut checked = [0usize; 2];
    for (i, face) in doc["faces"].as_array().expect("faces").iter().enumerate() {
        let Some(samples) = face["samples"].as_array() else {
            continue;
        };
        let r = pm.faces[i];
        for s in samples {
            let s: Vec<f64> = s
                .as_array()
                .expect("row")
                .iter()
                .map(|x| x.as_f64().unwrap_or(f64::NAN))
                .collect();
            let (q, n) = (DVec3::new(s[2], s[3], s[4]), DVec3::new(s[5], s[6], s[7]));
            let mut best = (f64::INFINITY, DVec3::ZERO);
            for t in &pm.mesh.triangles[r.first..r.first + r.count] {
                let [a, b, c] = t.map(|k| pm.mesh.positions[k as usize]);
                let d = q.distance((a + b + c) / 3.0);
                if d < best.0 {
                    best = (d, (b - a).cross(c - a).normalize_or_zero());
                }
            }
            if best.0 < 0.5 {
                assert!(
                    n.dot(best.1) > 0.9,
                    "face {i}: sample normal {n:?} against the winding {:?}",
                    best.1
                );
                checked[usize::from(face["same_sense"] == true)] += 1;
            }
        }
    }
    eprintln!("samples checked on .F. / .T. faces: {checked:?}");
    assert!(checked[0] + checked[1] > 20, "{checked:?}");
}
