//! Facing the test part's outline from a stock 1.5 mm above its top: the top covered at the
//! face height (every point within the tool radius of a pass at that height), levels no deeper
//! than the step-down with the finishing depth last, the tool entering only beside the stock.

use talas::geometry::DVec2;
use talas::geometry::planar::Region;
use talas::strategies::planar::{FacingOptions, facing};
use talas::toolpath::{MoveKind, ToolRecord};
use talas::tools::parse_tool_spec;

#[test]
fn facing_covers_the_top_in_levels_and_enters_beside_the_stock() {
    let outline = Region::rectangle(DVec2::ZERO, DVec2::new(120.0, 80.0))
        .offset(10.0)
        .offset(-10.0);
    assert!(
        (outline.area_mm2() - (9600.0 - 4.0 * (100.0 - 25.0 * std::f64::consts::PI))).abs() < 1e-6
    );
    let tool = ToolRecord {
        spec: "flat:d=10".into(),
        cutter: parse_tool_spec("flat:d=10").expect("tool"),
    };
    let o = FacingOptions {
        stock_top_z_mm: 31.5,
        face_z_mm: 30.0,
        step_down_mm: 1.0,
        finish_depth_mm: 0.2,
        stepover_frac: 0.7,
        overrun_mm: 2.0,
        zigzag: true,
        clearance_mm: 5.0,
        feed_mm_per_min: 2000.0,
    };
    let tp = facing(&outline, &tool, &o).expect("facing");
    let r = 5.0;
    let mut levels: Vec<f64> = tp
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .map(|p| p.tip.z)
        .collect();
    levels.dedup();
    // 1.3 mm of roughing in two levels of 0.65, then the 0.2 mm finish.
    assert_eq!(levels.len(), 3, "{levels:?}");
    assert!(
        (levels[0] - 30.85).abs() < 1e-9
            && (levels[1] - 30.2).abs() < 1e-9
            && (levels[2] - 30.0).abs() < 1e-9,
        "{levels:?}"
    );
    let mut finish = Vec::new();
    for w in tp.poses.windows(2) {
        let (a, b) = (w[0].tip, w[1].tip);
        if b.z < o.stock_top_z_mm && (w[1].kind == MoveKind::Plunge || w[1].kind == MoveKind::Link)
        {
            // Entries and step-overs beside the stock, the tool clear of the outline's box.
            assert!(
                b.x + r < 0.0 || b.x - r > 120.0,
                "an entry over the stock at {b}"
            );
        }
        if w[1].kind == MoveKind::Rapid && b.z < o.stock_top_z_mm {
            panic!("a rapid below the stock top at {b}");
        }
        if w[1].kind == MoveKind::Cut && (b.z - 30.0).abs() < 1e-9 {
            finish.push((a.truncate(), b.truncate()));
        }
    }
    let mut worst: f64 = 0.0;
    for i in 0..=240 {
        for j in 0..=160 {
            let p = DVec2::new(i as f64 * 0.5, j as f64 * 0.5);
            let d = finish
                .iter()
                .map(|&(a, b)| {
                    let ab = b - a;
                    let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                    p.distance(a + ab * t)
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    assert!(worst < r, "a point of the top {worst} mm from the passes");
}
