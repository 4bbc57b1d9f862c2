//! Region recognition from +Z on the Open CASCADE test part (`tests/data/pocket/`, values from
//! its closed forms, checked there against BRepGProp), and on real parts: never a panic.

use std::path::Path;
use talas::features::regions::{RegionKind, find_regions};
use talas::import::step::read_step;

fn data(p: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(p)
}

fn kind_of(s: &str) -> RegionKind {
    match s {
        "closed_pocket" => RegionKind::ClosedPocket,
        "open_pocket" => RegionKind::OpenPocket,
        "slot" => RegionKind::Slot,
        "step" => RegionKind::Step,
        "outer_profile" => RegionKind::OuterProfile,
        other => panic!("unknown kind {other}"),
    }
}

#[test]
fn every_region_of_the_test_part_with_its_floor_depth_area_and_corners() {
    let part = read_step(&data("pocket/pocket-part.stp")).expect("the test part reads");
    let known: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(data("pocket/pocket-part.json")).expect("json"),
    )
    .expect("json");
    let report = find_regions(&part);
    assert!(report.skipped.is_empty(), "{:?}", report.skipped);
    let expected = known["regions"].as_array().expect("regions");
    for e in expected {
        let kind = kind_of(e["kind"].as_str().expect("kind"));
        let floor = e["floor_z_mm"].as_f64().expect("floor");
        let found: Vec<_> = report
            .regions
            .iter()
            .filter(|r| r.kind == kind && (r.floor_z_mm - floor).abs() <= 1e-6)
            .collect();
        assert_eq!(
            found.len(),
            1,
            "{kind:?} at z = {floor}: {:#?}",
            report.regions
        );
        let r = found[0];
        assert!(
            (r.depth_mm - e["depth_mm"].as_f64().expect("depth")).abs() <= 1e-6,
            "{kind:?} depth {}",
            r.depth_mm
        );
        assert!((r.top_z_mm - e["top_z_mm"].as_f64().expect("top")).abs() <= 1e-6);
        let area = e["floor_area_mm2"].as_f64().expect("area");
        assert!(
            (r.area_mm2 - area).abs() <= 1e-6 * area,
            "{kind:?} area {} vs {area}",
            r.area_mm2
        );
        assert_eq!(
            r.islands as u64,
            e["islands"].as_u64().expect("islands"),
            "{kind:?} islands"
        );
        assert_eq!(
            r.open_sides as u64,
            e["open_sides"].as_u64().expect("open"),
            "{kind:?} open sides"
        );
        match e["min_corner_radius_mm"].as_f64() {
            Some(rc) => {
                let got = r.smallest_corner_radius_mm.expect("a corner radius");
                assert!((got - rc).abs() <= 1e-6, "{kind:?} corner {got} vs {rc}");
            }
            None => assert_eq!(r.smallest_corner_radius_mm, None, "{kind:?}"),
        }
        let bb = e["bbox_mm"].as_array().expect("bbox");
        for (k, v) in bb.iter().enumerate() {
            assert!(
                (r.bbox_mm[k] - v.as_f64().expect("bbox")).abs() <= 1e-6,
                "{kind:?} bbox {:?}",
                r.bbox_mm
            );
        }
    }
    // Nothing else below the top: the top faces are the only other regions.
    let others = report
        .regions
        .iter()
        .filter(|r| r.kind != RegionKind::Top)
        .count();
    assert_eq!(others, expected.len(), "{:#?}", report.regions);
    let top_area: f64 = report
        .regions
        .iter()
        .filter(|r| r.kind == RegionKind::Top)
        .map(|r| r.area_mm2)
        .sum();
    let known_top = known["up_facing_area_by_z_mm2"]["30.0"]
        .as_f64()
        .expect("top area");
    assert!(
        (top_area - known_top).abs() <= 1e-6 * known_top,
        "{top_area} vs {known_top}"
    );
}

#[test]
fn real_parts_give_plausible_regions_and_never_panic() {
    let dir = data("real");
    let mut files = Vec::new();
    let mut stack = vec![dir];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("dir").filter_map(Result::ok) {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .is_some_and(|x| x.eq_ignore_ascii_case("stp") || x.eq_ignore_ascii_case("step"))
            {
                files.push(p);
            }
        }
    }
    files.sort();
    assert!(!files.is_empty());
    for f in &files {
        let Ok(part) = read_step(f) else { continue };
        let report = find_regions(&part);
        let bb = part.rough_bbox();
        for r in &report.regions {
            assert!(
                r.area_mm2.is_finite() && r.area_mm2 > 0.0,
                "{}: {r:?}",
                f.display()
            );
            assert!(r.depth_mm >= -1e-9, "{}: {r:?}", f.display());
            assert!(
                r.floor_z_mm >= bb.min.z - 1e-3 && r.floor_z_mm <= bb.max.z + 1e-3,
                "{}: {r:?}",
                f.display()
            );
        }
    }
}

/// The job part (`tests/data/job/make_part.py`): a 30 × 16 × 5 mm pocket at (0, 0) and two
/// flat-bottomed Ø6 holes 8 mm deep at x = ±22 on the top (z = 25). The holes' floors are
/// discs walled by one full cylinder that hole recognition finds: they are holes, left out of
/// the regions (with a note), so `--features auto` pockets only the pocket.
#[test]
fn flat_bottomed_drilled_holes_are_holes_not_closed_pockets() {
    let part = read_step(&data("job/job-part.stp")).expect("the job part reads");
    let report = find_regions(&part);
    let pockets: Vec<_> = report
        .regions
        .iter()
        .filter(|r| r.kind == RegionKind::ClosedPocket && (r.floor_z_mm - 20.0).abs() < 1e-6)
        .collect();
    assert_eq!(pockets.len(), 1, "{:#?}", report.regions);
    assert!((pockets[0].area_mm2 - 30.0 * 16.0).abs() < 1e-6);
    assert!(
        !report
            .regions
            .iter()
            .any(|r| (r.floor_z_mm - 17.0).abs() < 1e-6),
        "a hole floor listed as a region: {:#?}",
        report.regions
    );
    let notes: Vec<_> = report
        .skipped
        .iter()
        .filter(|s| s.contains("flat-bottomed hole Ø6.0000 mm"))
        .collect();
    assert_eq!(notes.len(), 2, "{:?}", report.skipped);
    for x in ["(-22.0000, 0.0000)", "(22.0000, 0.0000)"] {
        assert!(notes.iter().any(|n| n.contains(x)), "{x}: {notes:?}");
    }
}
