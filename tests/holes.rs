//! Hole recognition on a part made with Open CASCADE (`tests/data/holes/make_part.py`): through
//! holes, blind holes with 118° drill points and with a flat floor, a counterbore, a countersink
//! and a hole whose wall is two half cylinders, on two heights. The script's own record of what
//! it cut (`holes-part.json`) is the reference; Open CASCADE's BRepGProp area is the reference
//! for the tessellation (every cone, the drill points closing at their apex included).

mod common;

use common::data;
use talas::features::holes::{HoleBottom, HoleKind, HoleOptions, HoleStep, recognize_holes};
use talas::geometry::DVec3;
use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
use talas::import::step::read_step;

fn reference() -> serde_json::Value {
    let text = std::fs::read_to_string(data("holes/holes-part.json")).expect("reference");
    serde_json::from_str(&text).expect("reference JSON")
}

fn f(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

#[test]
fn every_face_of_the_hole_part_tessellates_with_open_cascades_area() {
    let part = read_step(&data("holes/holes-part.stp")).expect("read");
    let r = reference();
    assert_eq!(part.faces.len() as u64, r["occ_faces"].as_u64().unwrap());
    let pm = tessellate_part(
        &part,
        &TessellationOptions::for_size(part.rough_bbox().diagonal()),
    );
    assert!(pm.diagnostics.is_empty(), "{:?}", pm.diagnostics);
    assert!(pm.faces.iter().all(|f| f.count > 0));
    let occ = f(&r, "occ_area_mm2");
    let rel = (pm.area_mm2() - occ).abs() / occ;
    assert!(
        rel < 1e-4,
        "area {} mm² vs Open CASCADE {occ} mm² ({rel:e})",
        pm.area_mm2()
    );
    let vol = pm.volume_mm3().expect("closed");
    let occ_v = f(&r, "occ_volume_mm3");
    assert!(
        (vol - occ_v).abs() / occ_v < 1e-4,
        "volume {vol} vs {occ_v}"
    );
}

#[test]
fn every_hole_of_the_test_part_is_found_with_its_diameter_depth_and_bottom_and_nothing_else() {
    let part = read_step(&data("holes/holes-part.stp")).expect("read");
    let pm = tessellate_part(
        &part,
        &TessellationOptions::for_size(part.rough_bbox().diagonal()),
    );
    let rep = recognize_holes(&part, Some(&pm), &HoleOptions::default());
    let r = reference();
    let want = r["holes"].as_array().unwrap();
    assert_eq!(rep.holes.len(), want.len(), "{:#?}", rep.holes);
    let tol = 1e-6;
    for w in want {
        let (x, y, top) = (f(w, "x"), f(w, "y"), f(w, "top"));
        let h = rep
            .holes
            .iter()
            .find(|h| (h.top - DVec3::new(x, y, top)).length() < tol)
            .unwrap_or_else(|| panic!("no hole at ({x}, {y}, {top}): {:#?}", rep.holes));
        let what = format!("hole at ({x}, {y}, {top})");
        assert!(
            (h.direction - DVec3::Z).length() < 1e-9,
            "{what}: {:?}",
            h.direction
        );
        assert!(
            (h.diameter_mm - f(w, "diameter")).abs() < tol,
            "{what}: {h:?}"
        );
        assert!(
            (h.depth_mm - f(w, "depth")).abs() < tol,
            "{what}: depth {}",
            h.depth_mm
        );
        assert_eq!(h.split, w["split"].as_bool().unwrap(), "{what}");
        match (w["bottom"].as_str().unwrap(), h.bottom) {
            ("through", HoleBottom::Through) | ("flat", HoleBottom::Flat) => {}
            (
                "point",
                HoleBottom::Point {
                    angle_rad,
                    tip_depth_mm,
                },
            ) => {
                let a = f(w, "point_angle").to_radians();
                assert!((angle_rad - a).abs() < 1e-9, "{what}: angle {angle_rad}");
                // The cone's height from the script's construction: r / tan(59°).
                let tip = f(w, "depth") + 0.5 * f(w, "diameter") / (0.5 * a).tan();
                assert!(
                    (tip_depth_mm - tip).abs() < tol,
                    "{what}: tip {tip_depth_mm} vs {tip}"
                );
            }
            (b, got) => panic!("{what}: bottom {got:?}, made as {b}"),
        }
        let steps = w["steps"].as_array().unwrap();
        assert_eq!(h.steps.len(), steps.len(), "{what}: {:?}", h.steps);
        for (s, g) in steps.iter().zip(&h.steps) {
            match (s["kind"].as_str().unwrap(), g) {
                (
                    "cylinder",
                    HoleStep::Cylinder {
                        diameter_mm,
                        depth_mm,
                    },
                ) => {
                    assert!(
                        (diameter_mm - f(s, "diameter")).abs() < tol,
                        "{what}: {g:?}"
                    );
                    assert!((depth_mm - f(s, "depth")).abs() < tol, "{what}: {g:?}");
                    assert_eq!(h.kind, HoleKind::Counterbore, "{what}");
                }
                (
                    "cone",
                    HoleStep::Cone {
                        top_diameter_mm,
                        bottom_diameter_mm,
                        angle_rad,
                        depth_mm,
                    },
                ) => {
                    let half = (0.5 * f(s, "angle")).to_radians();
                    assert!(
                        (top_diameter_mm - f(s, "diameter")).abs() < tol,
                        "{what}: {g:?}"
                    );
                    assert!(
                        (bottom_diameter_mm - f(w, "diameter")).abs() < tol,
                        "{what}: {g:?}"
                    );
                    assert!((angle_rad - 2.0 * half).abs() < 1e-9, "{what}: {g:?}");
                    let d = 0.5 * (f(s, "diameter") - f(w, "diameter")) / half.tan();
                    assert!((depth_mm - d).abs() < tol, "{what}: {g:?} vs depth {d}");
                    assert_eq!(h.kind, HoleKind::Countersink, "{what}");
                }
                (k, g) => panic!("{what}: step {g:?}, made as {k}"),
            }
        }
        if steps.is_empty() {
            assert_eq!(h.kind, HoleKind::Simple, "{what}");
        }
    }
    // Groups: by diameter and direction; the two Ø6 through holes share one.
    let six = rep
        .groups
        .iter()
        .find(|g| (g.diameter_mm - 6.0).abs() < tol)
        .expect("Ø6 group");
    assert_eq!(six.holes.len(), 2);
    assert_eq!(rep.groups.len(), want.len() - 1);
    // Tap-drill suggestions: Ø8.5 is M10's, Ø5 M6's, Ø4.2 M5's.
    let sugg = |d: f64| {
        rep.holes
            .iter()
            .find(|h| (h.diameter_mm - d).abs() < tol)
            .and_then(|h| h.thread_suggestion)
            .map(|t| t.name)
    };
    assert_eq!(sugg(8.5), Some("M10"));
    assert_eq!(sugg(5.0), Some("M6"));
    assert_eq!(sugg(4.2), Some("M5"));
    assert_eq!(sugg(10.0), None);
}

/// The same part turned upside down and with every face's sense flipped (as a CAD system that
/// writes reversed normals would): with the mesh, the flip is seen and the holes are the same,
/// entered from -z.
#[test]
fn reversed_normals_are_read_from_the_mesh() {
    let mut part = read_step(&data("holes/holes-part.stp")).expect("read");
    for face in &mut part.faces {
        face.same_sense = !face.same_sense;
    }
    let pm = tessellate_part(
        &part,
        &TessellationOptions::for_size(part.rough_bbox().diagonal()),
    );
    let rep = recognize_holes(&part, Some(&pm), &HoleOptions::default());
    assert_eq!(
        rep.holes.len(),
        reference()["holes"].as_array().unwrap().len()
    );
    // Without the mesh the flipped part's walls look convex: no holes, and none made up.
    let rep = recognize_holes(&part, None, &HoleOptions::default());
    assert!(rep.holes.is_empty(), "{:#?}", rep.holes);
}

/// The real parts Talas carries (CATIA V5 exports, Open CASCADE-made parts, the adversarial and
/// dodgy STEP files): recognition never panics, and what it finds is a hole of the part's size.
/// The drilled block (`tests/data/real/made/make_parts.py`) is checked against its script: three
/// drilled holes with 118° points (one counterbored) and one ball-ended hole.
#[test]
fn real_parts_give_plausible_holes() {
    let mut files = Vec::new();
    let mut stack = vec![data("real"), data("adversarial")];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .and_then(|x| x.to_str())
                .is_some_and(|x| x.eq_ignore_ascii_case("stp") || x.eq_ignore_ascii_case("step"))
            {
                files.push(p);
            }
        }
    }
    files.sort();
    assert!(files.len() > 10, "{files:?}");
    let mut found = 0;
    for f in &files {
        let Ok(part) = read_step(f) else { continue };
        let diag = part.rough_bbox().diagonal();
        let pm = tessellate_part(
            &part,
            &TessellationOptions::with_chord_tol(1e-3 * diag.max(1e-3)),
        );
        let rep = recognize_holes(&part, Some(&pm), &HoleOptions::default());
        for h in &rep.holes {
            assert!(
                h.diameter_mm > 0.0 && h.diameter_mm <= diag,
                "{}: {h:?}",
                f.display()
            );
            assert!(
                h.depth_mm > 0.0 && h.depth_mm <= diag,
                "{}: {h:?}",
                f.display()
            );
            assert!(
                (h.direction.length() - 1.0).abs() < 1e-9,
                "{}: {h:?}",
                f.display()
            );
            assert!(
                h.full_depth_mm() >= h.depth_mm - 1e-9,
                "{}: {h:?}",
                f.display()
            );
        }
        found += rep.holes.len();
    }
    assert!(found > 10, "{found} holes in {} files", files.len());

    let part = read_step(&data("real/made/drilled-block.stp")).expect("read");
    let pm = tessellate_part(&part, &TessellationOptions::default());
    let rep = recognize_holes(&part, Some(&pm), &HoleOptions::default());
    assert_eq!(rep.holes.len(), 4, "{:#?}", rep.holes);
    // (x, y, diameter, depth) from make_parts.py: drill(x, y, top 25, r, depth).
    for (x, y, d, depth, point) in [
        (12.0, 12.0, 8.5, 14.0, true),
        (30.0, 20.0, 6.6, 18.0, true),
        (48.0, 12.0, 5.5, 16.0, true),
        (48.0, 30.0, 6.0, 10.0, false),
    ] {
        let h = rep
            .holes
            .iter()
            .find(|h| (h.top - DVec3::new(x, y, 25.0)).length() < 1e-6)
            .unwrap_or_else(|| panic!("no hole at ({x}, {y}): {:#?}", rep.holes));
        assert!(
            (h.diameter_mm - d).abs() < 1e-6 && (h.depth_mm - depth).abs() < 1e-6,
            "{h:?}"
        );
        match h.bottom {
            HoleBottom::Point { tip_depth_mm, .. } if point => {
                let tip = depth + 0.5 * d / 59f64.to_radians().tan();
                assert!((tip_depth_mm - tip).abs() < 1e-6, "{h:?}");
            }
            // The ball end: a sphere of the bore's radius, 3 mm below the cylinder's end.
            HoleBottom::Other { tip_depth_mm } if !point => {
                assert!((tip_depth_mm - (depth + 3.0)).abs() < 1e-6, "{h:?}");
            }
            b => panic!("({x}, {y}): bottom {b:?}"),
        }
    }
    let cb = rep
        .holes
        .iter()
        .find(|h| h.kind == HoleKind::Counterbore)
        .expect("counterbore");
    assert_eq!(
        cb.steps,
        vec![HoleStep::Cylinder {
            diameter_mm: 9.0,
            depth_mm: 5.0
        }],
        "{cb:?}"
    );
}
