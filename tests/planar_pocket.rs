//! Offset pocketing of the test part's closed pocket (R5 corners, round island), measured
//! independently of the planner: the tool centre never nearer a wall than the tool radius, the
//! floor covered, no plunge (every descent below the top is a ramp within the ramp angle),
//! rapids below the top only vertical and inside the pocket, arcs written as exact arcs.

use std::path::Path;
use talas::features::regions::{RegionKind, find_regions};
use talas::geometry::DVec2;
use talas::import::step::read_step;
use talas::strategies::planar::{PocketOptions, pocket};
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
fn pocket_of_the_test_part_stays_off_the_walls_covers_the_floor_and_never_plunges() {
    let part =
        read_step(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pocket/pocket-part.stp"))
            .expect("part");
    let report = find_regions(&part);
    let pk = report
        .regions
        .iter()
        .find(|r| r.kind == RegionKind::ClosedPocket)
        .expect("the pocket");
    let tool = ToolRecord {
        spec: "flat:d=6".into(),
        cutter: parse_tool_spec("flat:d=6").expect("tool"),
    };
    let o = PocketOptions {
        top_z_mm: pk.top_z_mm,
        floor_z_mm: pk.floor_z_mm,
        step_down_mm: 3.0,
        stepover_frac: 0.5,
        wall_allowance_mm: 0.3,
        floor_allowance_mm: 0.2,
        clearance_mm: 5.0,
        ramp_angle_rad: 3f64.to_radians(),
        feed_mm_per_min: 1200.0,
        chord_tol_mm: 0.002,
    };
    let t0 = std::time::Instant::now();
    let tp = pocket(&pk.region, &tool, &o).expect("a pocket");
    eprintln!(
        "pocket: {} poses, {} exact segments, {:.3} s",
        tp.poses.len(),
        tp.exact.len(),
        t0.elapsed().as_secs_f64()
    );
    assert!(!tp.exact.is_empty(), "arcs are exact arcs");
    let r = 3.0;
    let walls: Vec<_> = pk
        .region
        .boundaries()
        .into_iter()
        .flat_map(|b| b.elements())
        .collect();
    let top = pk.top_z_mm;
    let mut floor_segments = Vec::new();
    for w in tp.poses.windows(2) {
        let (a, b) = (w[0].tip, w[1].tip);
        assert!(b.z >= pk.floor_z_mm - 1e-9, "below the floor: {b}");
        if b.z < top {
            let q = b.truncate();
            assert!(pk.region.contains(q), "outside the pocket: {b}");
            let d = walls
                .iter()
                .map(|e| e.distance(q))
                .fold(f64::INFINITY, f64::min);
            assert!(d >= r - 1e-6, "tool centre {d} mm from a wall at {b}");
        }
        let dz = b.z - a.z;
        let dxy = a.truncate().distance(b.truncate());
        if w[1].kind == MoveKind::Rapid && b.z < top {
            assert!(
                dxy < 1e-9,
                "a rapid below the top moves sideways: {a} → {b}"
            );
        }
        if dz < -1e-9 && b.z < top && w[1].kind != MoveKind::Rapid {
            assert!(
                dxy * 3f64.to_radians().tan() >= -dz * (1.0 - 1e-6),
                "a plunge {a} → {b}"
            );
        }
        if (a.z - pk.floor_z_mm).abs() < 1e-9
            && (b.z - pk.floor_z_mm).abs() < 1e-9
            && w[1].kind != MoveKind::Rapid
        {
            floor_segments.push((a.truncate(), b.truncate()));
        }
    }
    // Every point of the floor is swept by the tool at the floor level.
    let (lo, hi) = pk.region.bounds();
    let mut worst: f64 = 0.0;
    let mut n = 0;
    let mut y = lo.y + 0.25;
    while y < hi.y {
        let mut x = lo.x + 0.25;
        while x < hi.x {
            let p = DVec2::new(x, y);
            if pk.region.contains(p) {
                let d = floor_segments
                    .iter()
                    .map(|&(a, b)| seg_dist(p, a, b))
                    .fold(f64::INFINITY, f64::min);
                worst = worst.max(d);
                n += 1;
            }
            x += 0.5;
        }
        y += 0.5;
    }
    assert!(n > 5000);
    // The walls are finished: every wall point is reached by the tool's side at the floor.
    for e in &walls {
        for k in 0..=20 {
            let p = e.point_at(k as f64 / 20.0);
            let d = floor_segments
                .iter()
                .map(|&(a, b)| seg_dist(p, a, b))
                .fold(f64::INFINITY, f64::min);
            assert!(
                d <= r + 0.01,
                "wall point {p} is {d} mm from the tool centre path"
            );
        }
    }
    assert!(
        worst <= r + 1e-3,
        "a floor point {worst} mm from the tool centre path"
    );
}
