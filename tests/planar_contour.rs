//! Contour of the test part's outer profile (R10 corners) with leads and tabs, measured
//! independently of the planner: never inside the part or nearer it than the tool radius, the
//! whole outline reached at the bottom except the tabs' width, climb direction (clockwise
//! around an outside profile with M3), no plunge except in the air of the lead-in, exact arcs.

use std::path::Path;
use talas::features::regions::{RegionKind, find_regions};
use talas::geometry::DVec2;
use talas::import::step::read_step;
use talas::strategies::planar::{ContourOptions, ContourSide, contour};
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::parse_tool_spec;

fn seg_dist(p: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(a + ab * t)
}

#[test]
fn outside_contour_with_tabs_of_the_test_part() {
    let part =
        read_step(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket/pocket-part.stp"))
            .expect("part");
    let report = find_regions(&part);
    let outline = report
        .regions
        .iter()
        .find(|r| r.kind == RegionKind::OuterProfile)
        .expect("outline");
    let tool = ToolRecord {
        spec: "flat:d=6".into(),
        cutter: parse_tool_spec("flat:d=6").expect("tool"),
    };
    let o = ContourOptions {
        side: ContourSide::Outside,
        climb: true,
        top_z_mm: outline.top_z_mm,
        bottom_z_mm: outline.floor_z_mm,
        step_down_mm: 8.0,
        allowance_mm: 0.0,
        lead_radius_mm: 2.0,
        tab_count: 4,
        tab_width_mm: 5.0,
        tab_height_mm: 2.0,
        ramp_angle_rad: 20f64.to_radians(),
        clearance_mm: 5.0,
        feed_mm_per_min: 1500.0,
        chord_tol_mm: 0.002,
    };
    let tp = contour(&outline.region, &tool, &o).expect("a contour");
    assert!(!tp.exact.is_empty());
    let r = 3.0;
    let edges: Vec<_> = outline
        .region
        .boundaries()
        .into_iter()
        .flat_map(|b| b.elements())
        .collect();
    let dist = |q: DVec2| {
        edges
            .iter()
            .map(|e| e.distance(q))
            .fold(f64::INFINITY, f64::min)
    };
    let top = outline.top_z_mm;
    let bottom = outline.floor_z_mm;
    let mut bottom_pass = Vec::new();
    let mut area2 = 0.0;
    for w in tp.poses.windows(2) {
        let (a, b) = (w[0].tip, w[1].tip);
        assert!(b.z >= bottom - 1e-9);
        if b.z < top {
            assert!(
                !outline.region.contains(b.truncate()),
                "inside the part at {b}"
            );
            assert!(dist(b.truncate()) >= r - 1e-6, "gouge at {b}");
        }
        let dxy = a.truncate().distance(b.truncate());
        let dz = b.z - a.z;
        if dz < -1e-9 && b.z < top {
            if dxy < 1e-9 {
                assert!(
                    dist(b.truncate()) >= r + 2.0 - 1e-6,
                    "a plunge next to the part at {b}"
                );
            } else {
                assert!(
                    dxy * 20f64.to_radians().tan() >= -dz * (1.0 - 1e-6),
                    "a ramp too steep at {b}"
                );
            }
        }
        if (a.z - bottom).abs() < 1e-9 && (b.z - bottom).abs() < 1e-9 && w[1].kind == MoveKind::Cut
        {
            bottom_pass.push((a.truncate(), b.truncate()));
            area2 += a.x * b.y - b.x * a.y;
        }
    }
    assert!(
        area2 < 0.0,
        "climb milling runs clockwise around an outside profile"
    );
    // The outline reached at the bottom everywhere except the tabs.
    let mut missed = 0.0;
    let mut total = 0.0;
    for e in &edges {
        let m = (e.length() / 0.05).ceil() as usize;
        for k in 0..m {
            let p = e.point_at((k as f64 + 0.5) / m as f64);
            let d = bottom_pass
                .iter()
                .map(|&(a, b)| seg_dist(p, a, b))
                .fold(f64::INFINITY, f64::min);
            total += e.length() / m as f64;
            if d > r + 1e-3 {
                missed += e.length() / m as f64;
            }
        }
    }
    let perimeter = 2.0 * (100.0 + 60.0) + 2.0 * std::f64::consts::PI * 10.0;
    assert!((total - perimeter).abs() < 1e-6, "{total}");
    // Four tabs keep 5 mm each on the straight walls at the bottom, and the ramp after each
    // (2 mm at 20°) leaves the outline untouched at the bottom for 2 / tan 20° more; a point
    // counts as reached within 1e-3 mm of the radius, √(2 · 3 · 1e-3) = 0.08 mm either side.
    let expected =
        4.0 * (5.0 + 2.0 / 20f64.to_radians().tan()) - 8.0 * (2.0f64 * 3.0 * 1e-3).sqrt();
    assert!(
        (missed - expected).abs() < 0.1,
        "material left along {missed} mm of the outline, {expected} mm expected"
    );
}
