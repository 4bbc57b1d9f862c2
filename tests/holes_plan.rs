//! Hole operations: the tour order against 2-opt restarts, the cycles planned on the
//! Open CASCADE hole part (depths, R-plane and clearance retracts, no rapid through the part as
//! its mesh stands), the tap's spindle-synchronised feed, and the helices of helical boring and
//! thread milling measured on their poses.

mod common;

use std::time::Instant;

use common::{Lcg, data};
use talas::features::holes::{HoleOptions, recognize_holes};
use talas::geometry::DVec3;
use talas::geometry::mesh::TriMesh;
use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
use talas::import::step::read_step;
use talas::strategies::holes::{
    HolePlanOptions, HoleStrategy, HoleTarget, order_holes, plan_holes, tour_length_mm,
};
use talas::toolpath::{CycleKind, CycleRetract, ExactMove, MoveKind, ToolRecord};
use talas::tools::hole_tool::{HoleTool, HoleToolKind};

/// Plain 2-opt on an open tour from a given order (the reference: independent of the planner's).
fn two_opt(p: &[DVec3], mut t: Vec<usize>) -> Vec<usize> {
    let n = t.len();
    loop {
        let mut better = false;
        for i in 0..n - 1 {
            for j in i + 1..n {
                let old = p[t[i]].distance(p[t[i + 1]])
                    + if j + 1 < n {
                        p[t[j]].distance(p[t[j + 1]])
                    } else {
                        0.0
                    };
                let new = p[t[i]].distance(p[t[j]])
                    + if j + 1 < n {
                        p[t[i + 1]].distance(p[t[j + 1]])
                    } else {
                        0.0
                    };
                if new < old - 1e-12 {
                    t[i + 1..=j].reverse();
                    better = true;
                }
            }
        }
        if !better {
            return t;
        }
    }
}

#[test]
fn the_tour_of_200_holes_is_within_5_percent_of_the_best_of_100_two_opt_restarts() {
    let mut rng = Lcg(34);
    let pts: Vec<DVec3> = (0..200)
        .map(|_| DVec3::new(rng.range(0.0, 300.0), rng.range(0.0, 200.0), 0.0))
        .collect();
    let t0 = Instant::now();
    let ours = order_holes(&pts, Some(pts[0]));
    let took = t0.elapsed();
    let mut sorted = ours.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, (0..200).collect::<Vec<_>>(), "every hole once");
    assert_eq!(ours[0], 0, "starts at the hole nearest the start");
    let ours_mm = tour_length_mm(&pts, &ours);
    let mut best = f64::INFINITY;
    for _ in 0..100 {
        // A random order from hole 0 (Fisher–Yates on the rest).
        let mut t: Vec<usize> = (0..200).collect();
        for i in (2..200).rev() {
            let j = 1 + rng.below(i);
            t.swap(i, j);
        }
        best = best.min(tour_length_mm(&pts, &two_opt(&pts, t)));
    }
    eprintln!(
        "tour {ours_mm:.1} mm in {:.3} s; best of 100 2-opt restarts {best:.1} mm ({:+.2} %)",
        took.as_secs_f64(),
        100.0 * (ours_mm / best - 1.0)
    );
    assert!(ours_mm <= 1.05 * best, "{ours_mm} mm vs {best} mm");
    // Nearest neighbour alone is worse than the improved tour (the improvement did something).
    let mut nn = vec![0usize];
    let mut used = [false; 200];
    used[0] = true;
    for _ in 1..200 {
        let l = *nn.last().unwrap();
        let j = (0..200)
            .filter(|&j| !used[j])
            .min_by(|&a, &b| pts[l].distance(pts[a]).total_cmp(&pts[l].distance(pts[b])))
            .unwrap();
        used[j] = true;
        nn.push(j);
    }
    assert!(ours_mm < tour_length_mm(&pts, &nn));
}

fn part_and_mesh() -> (Vec<talas::features::holes::Hole>, TriMesh) {
    let part = read_step(&data("holes/holes-part.stp")).expect("read");
    let pm = tessellate_part(
        &part,
        &TessellationOptions::for_size(part.rough_bbox().diagonal()),
    );
    let rep = recognize_holes(&part, Some(&pm), &HoleOptions::default());
    (rep.holes, pm.mesh)
}

fn drill_record(d: f64) -> ToolRecord {
    let tool = HoleTool {
        kind: HoleToolKind::TwistDrill {
            point_angle_rad: 118f64.to_radians(),
        },
        diameter_mm: d,
    };
    ToolRecord {
        spec: tool.spec(),
        cutter: tool.cutter().expect("drill"),
    }
}

/// The highest point of the mesh over (x, y), by dropping a vertical ray onto every triangle.
fn height_at(mesh: &TriMesh, x: f64, y: f64) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        let det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if det.abs() < 1e-15 {
            continue;
        }
        let l1 = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
        let l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
        if l1 >= -1e-12 && l2 >= -1e-12 && l1 + l2 <= 1.0 + 1e-12 {
            best = best.max(a.z + l1 * (b.z - a.z) + l2 * (c.z - a.z));
        }
    }
    best
}

#[test]
fn peck_drilling_the_test_part_goes_to_depth_and_never_rapids_through_it() {
    let (holes, mesh) = part_and_mesh();
    let targets: Vec<HoleTarget> = holes
        .iter()
        .map(|h| HoleTarget {
            top: h.top,
            direction: h.direction,
            depth_mm: h.full_depth_mm(),
            diameter_mm: h.diameter_mm,
        })
        .collect();
    let opts = HolePlanOptions {
        start: DVec3::new(0.0, 0.0, 50.0),
        ..HolePlanOptions::default()
    };
    let plan = plan_holes(
        &targets,
        &HoleStrategy::Cycle(CycleKind::Peck { peck_mm: 3.0 }),
        drill_record(4.0),
        Some(&mesh),
        &opts,
    )
    .expect("plan");
    let tp = plan.toolpath.as_ref().expect("tool path");
    tp.validate("<plan>").expect("valid");
    assert_eq!(tp.exact.len(), targets.len());
    // Each cycle reaches its hole's depth, from its hole's top.
    for (seg, &i) in tp.exact.iter().zip(&plan.order) {
        let ExactMove::Cycle(c) = seg.exact else {
            panic!("{seg:?}")
        };
        assert!((c.surface - targets[i].top).length() < 1e-12);
        let deepest = tp.poses[seg.from..=seg.to]
            .iter()
            .map(|p| p.tip.z)
            .fold(f64::INFINITY, f64::min);
        assert!((deepest - (targets[i].top.z - targets[i].depth_mm)).abs() < 1e-9);
    }
    // Retracts: from the low level (z 20) to the high one (z 30) the tool must go up to the
    // clearance; within one level with nothing between it stays at the R plane.
    let mut went_up = 0;
    for (k, seg) in tp.exact.iter().enumerate().take(tp.exact.len() - 1) {
        let ExactMove::Cycle(c) = seg.exact else {
            unreachable!()
        };
        let next = targets[plan.order[k + 1]].top;
        if next.z > c.surface.z + 1e-9 {
            assert_eq!(c.retract, CycleRetract::Initial, "hole {k} to a higher one");
            went_up += 1;
        }
    }
    assert!(
        plan.r_plane_moves > 0 && plan.clearance_moves >= went_up,
        "{plan:?}"
    );
    // No lateral rapid runs lower than the part under the tool (its rim sampled at 8 points).
    let r = 2.0;
    for w in tp.poses.windows(2) {
        let (a, b) = (w[0].tip, w[1].tip);
        if w[1].kind != MoveKind::Rapid || (a - b).truncate().length() < 1e-9 {
            continue;
        }
        let z = a.z.min(b.z);
        for s in 0..=100 {
            let p = a.lerp(b, f64::from(s) / 100.0);
            for k in 0..9 {
                let (dx, dy) = if k == 0 {
                    (0.0, 0.0)
                } else {
                    let t = f64::from(k) * std::f64::consts::TAU / 8.0;
                    (r * t.cos(), r * t.sin())
                };
                let h = height_at(&mesh, p.x + dx, p.y + dy);
                assert!(z > h, "rapid {a:?} → {b:?} at z {z} over the part at {h}");
            }
        }
    }
}

#[test]
fn a_tap_feeds_at_pitch_times_speed() {
    let targets = [HoleTarget {
        top: DVec3::new(5.0, 5.0, 0.0),
        direction: DVec3::Z,
        depth_mm: 10.0,
        diameter_mm: 6.0,
    }];
    let opts = HolePlanOptions {
        spindle_rpm: 750.0,
        ..HolePlanOptions::default()
    };
    let tap = HoleTool {
        kind: HoleToolKind::Tap {
            pitch_mm: 1.0,
            right_hand: true,
        },
        diameter_mm: 6.0,
    };
    let rec = ToolRecord {
        spec: tap.spec(),
        cutter: tap.cutter().unwrap(),
    };
    let plan = plan_holes(
        &targets,
        &HoleStrategy::Cycle(CycleKind::Tap { pitch_mm: 1.0 }),
        rec,
        None,
        &opts,
    )
    .unwrap();
    let tp = plan.toolpath.unwrap();
    let ExactMove::Cycle(c) = tp.exact[0].exact else {
        panic!()
    };
    assert_eq!(c.feed_mm_per_min, 750.0);
}

#[test]
fn helical_boring_and_thread_milling_follow_their_helices() {
    let targets = [HoleTarget {
        top: DVec3::new(10.0, -4.0, 5.0),
        direction: DVec3::Z,
        depth_mm: 6.5,
        diameter_mm: 11.0,
    }];
    let flat = |d: f64| ToolRecord {
        spec: format!("flat:d={d}"),
        cutter: talas::tools::Cutter::new(talas::tools::CutterKind::Flat, d).unwrap(),
    };
    let opts = HolePlanOptions::default();
    let plan = plan_holes(
        &targets,
        &HoleStrategy::HelicalBore {
            pitch_mm: 1.0,
            finish_mm: 0.2,
        },
        flat(6.0),
        None,
        &opts,
    )
    .unwrap();
    let tp = plan.toolpath.unwrap();
    let c = targets[0].top;
    let radius = |p: DVec3| (p - c).truncate().length();
    // The farthest any pose reaches from the axis is the finishing radius (11 − 6) / 2 = 2.5 mm,
    // the deepest is the hole's depth, and every exact move is a helix or circle of 1 mm pitch.
    let far = tp.poses.iter().map(|p| radius(p.tip)).fold(0.0, f64::max);
    assert!((far - 2.5).abs() < 1e-9, "{far}");
    let deep = tp
        .poses
        .iter()
        .map(|p| p.tip.z)
        .fold(f64::INFINITY, f64::min);
    assert!((deep - (5.0 - 6.5)).abs() < 1e-9, "{deep}");
    let mut rough = 0.0;
    for s in &tp.exact {
        let ExactMove::Arc(a) = s.exact else { panic!() };
        let per_turn = a.helix_mm / (a.sweep_rad / std::f64::consts::TAU);
        assert!(
            per_turn.abs() < 1e-9 || (per_turn.abs() - 1.0).abs() < 1e-9,
            "{a:?}"
        );
        assert!(a.sweep_rad > 0.0, "climb: counter-clockwise");
        if a.helix_mm < 0.0 {
            rough += -a.helix_mm;
        }
    }
    assert!((rough - 6.5).abs() < 1e-9, "{rough}");
    // Thread milling an M10 × 1.5 with a 6 mm mill: radius (10 − 6) / 2 = 2 mm, rising 1.5 mm
    // per counter-clockwise turn from the bottom to the top.
    let m10 = [HoleTarget {
        diameter_mm: 10.0,
        ..targets[0]
    }];
    let plan = plan_holes(
        &m10,
        &HoleStrategy::ThreadMill {
            pitch_mm: 1.5,
            teeth: 1,
        },
        flat(6.0),
        None,
        &opts,
    )
    .unwrap();
    let tp = plan.toolpath.unwrap();
    let mut rise = 0.0;
    for s in &tp.exact {
        let ExactMove::Arc(a) = s.exact else { panic!() };
        assert!(a.sweep_rad > 0.0 && a.helix_mm > 0.0);
        assert!((a.helix_mm / (a.sweep_rad / std::f64::consts::TAU) - 1.5).abs() < 1e-9);
        for p in &tp.poses[s.from..=s.to] {
            assert!((radius(p.tip) - 2.0).abs() < 1e-9);
        }
        rise += a.helix_mm;
    }
    assert!((rise - 6.5).abs() < 1e-9);
    // A three-tooth mill at 1.5 mm covers 4.5 mm per turn: the 6.5 mm thread takes two turns,
    // each rising one pitch, starting at the bottom and 4.5 mm above it (whole pitches, so both
    // lie on the one thread), with the teeth together reaching from the bottom past the top.
    let plan = plan_holes(
        &m10,
        &HoleStrategy::ThreadMill {
            pitch_mm: 1.5,
            teeth: 3,
        },
        flat(6.0),
        None,
        &opts,
    )
    .unwrap();
    let tp = plan.toolpath.unwrap();
    let bottom = 5.0 - 6.5;
    let mut starts = Vec::new();
    for s in &tp.exact {
        let ExactMove::Arc(a) = s.exact else { panic!() };
        assert!(a.sweep_rad > 0.0, "climb: counter-clockwise");
        assert!((a.sweep_rad - std::f64::consts::TAU).abs() < 1e-9, "{a:?}");
        assert!((a.helix_mm - 1.5).abs() < 1e-9, "{a:?}");
        for p in &tp.poses[s.from..=s.to] {
            assert!((radius(p.tip) - 2.0).abs() < 1e-9);
        }
        starts.push(tp.poses[s.from].tip.z - bottom);
    }
    assert_eq!(starts.len(), 2, "{starts:?}");
    assert!(
        starts[0].abs() < 1e-9 && (starts[1] - 4.5).abs() < 1e-9,
        "{starts:?}"
    );
    assert!(starts[1] + 4.5 >= 6.5);
    // Off the thread's radius the tool only moves along the axis (in and out at the axis).
    for w in tp.poses.windows(2) {
        let (r0, r1) = (radius(w[0].tip), radius(w[1].tip));
        if w[0].tip.z > 5.0 + 1e-9 || w[1].tip.z > 5.0 + 1e-9 {
            continue;
        }
        assert!(
            (r0 < 1e-9 && r1 < 1e-9)
                || (w[0].tip.z - w[1].tip.z).abs() < 1e-9
                || ((r0 - 2.0).abs() < 1e-9 && (r1 - 2.0).abs() < 1e-9),
            "{:?} -> {:?}",
            w[0].tip,
            w[1].tip
        );
    }
    // A tool as wide as the hole cannot bore it.
    assert!(
        plan_holes(
            &targets,
            &HoleStrategy::HelicalBore {
                pitch_mm: 1.0,
                finish_mm: 0.2
            },
            flat(11.0),
            None,
            &opts
        )
        .is_err()
    );
}

/// `talas features` lists the part's nine holes; `talas plan --strategy peck` drills the two
/// Ø6 through holes with G83 and posts them; bad hole selections are one clear error (exit 2).
#[test]
fn the_command_line_lists_the_holes_and_plans_a_peck_drilling() {
    let part = data("holes/holes-part.stp");
    let part = part.to_str().unwrap();
    let doc = common::talas_json(&["features", part, "--json"]);
    let holes = doc["holes"].as_array().unwrap();
    assert_eq!(holes.len(), 9, "{doc}");
    assert!(holes.iter().any(|h| h["bottom"]["kind"] == "point"
        && (h["bottom"]["angle_deg"].as_f64().unwrap() - 118.0).abs() < 1e-9));
    let out = common::temp_path("holes-cli", "peck.json");
    let o = out.to_str().unwrap();
    let doc = common::talas_json(&[
        "plan",
        part,
        "--strategy",
        "peck",
        "--tool",
        "drill:d=6",
        "--peck",
        "3",
        "--post",
        "linuxcnc",
        "-o",
        o,
        "--json",
    ]);
    assert_eq!(doc["holes"].as_array().unwrap().len(), 2, "{doc}");
    let nc = std::fs::read_to_string(out.with_extension("nc")).unwrap();
    assert_eq!(nc.matches("G83").count(), 2, "{nc}");
    assert!(nc.contains("Q3"), "{nc}");
    // A 90° spot drill spots every hole, the countersink (Ø10 at the top) 5 mm deep.
    let doc = common::talas_json(&[
        "plan",
        part,
        "--strategy",
        "spot",
        "--tool",
        "spot:d=12",
        "-o",
        o,
        "--json",
    ]);
    let spots = doc["holes"].as_array().unwrap();
    assert_eq!(spots.len(), 9, "{doc}");
    let csk = spots
        .iter()
        .find(|h| h["top_mm"][0] == 70.0 && h["top_mm"][1] == 45.0)
        .unwrap();
    assert!(
        (csk["depth_mm"].as_f64().unwrap() - 5.0).abs() < 1e-9,
        "{csk}"
    );
    // By position: the counterbored hole only.
    let doc = common::talas_json(&[
        "plan",
        part,
        "--strategy",
        "drill",
        "--tool",
        "drill:d=6.6",
        "--holes",
        "25,45;",
        "-o",
        o,
        "--json",
    ]);
    assert_eq!(doc["holes"].as_array().unwrap().len(), 1, "{doc}");
    for (holes, says) in [
        ("999", "face 999 belongs to no hole"),
        ("3,3;", "no hole within"),
    ] {
        let r = common::talas(&[
            "plan",
            part,
            "--strategy",
            "drill",
            "--tool",
            "drill:d=6",
            "--holes",
            holes,
            "-o",
            o,
        ]);
        assert_eq!(r.status.code(), Some(2));
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(err.contains(says) && err.lines().count() == 1, "{err}");
    }
}

/// The thread-mill arcs of a tool path: (start height above `bottom`, rise, sweep).
fn thread_arcs(tp: &talas::toolpath::Toolpath, bottom: f64) -> Vec<(f64, f64, f64)> {
    tp.exact
        .iter()
        .map(|s| {
            let ExactMove::Arc(a) = s.exact else {
                panic!("{:?}", s.exact)
            };
            (tp.poses[s.from].tip.z - bottom, a.helix_mm, a.sweep_rad)
        })
        .collect()
}

/// `talas plan --strategy thread-mill --tool threadmill:d=6.5,pitch=1.5,teeth=3` threads the
/// M10 tap drill (Ø8.5, 15 mm deep, top at z = 30) in ⌈15 / 4.5⌉ = 4 turns started 4.5 mm
/// apart, against 10 for the single-tooth mill; a tooth count that is not a whole number from 1,
/// or an unknown key, is one clear error naming `--tool` (exit 2).
#[test]
fn the_command_line_thread_mill_takes_its_teeth() {
    let part = data("holes/holes-part.stp");
    let part = part.to_str().unwrap();
    let out = common::temp_path("holes-cli", "thread.json");
    let o = out.to_str().unwrap();
    for (spec, teeth, turns) in [
        ("threadmill:d=6.5,pitch=1.5", 1, 10),
        ("threadmill:d=6.5,pitch=1.5,teeth=3", 3, 4),
    ] {
        let doc = common::talas_json(&[
            "plan",
            part,
            "--strategy",
            "thread-mill",
            "--tool",
            spec,
            "-o",
            o,
            "--json",
        ]);
        assert_eq!(doc["thread_mill_teeth"], teeth, "{doc}");
        let holes = doc["holes"].as_array().unwrap();
        assert_eq!(holes.len(), 1, "{doc}");
        assert_eq!(holes[0]["diameter_mm"], 10.0, "{doc}");
        let tp = talas::toolpath::Toolpath::load(&out).unwrap();
        let arcs = thread_arcs(&tp, 30.0 - 15.0);
        assert_eq!(arcs.len(), turns, "{spec}: {arcs:?}");
        for (k, &(start, rise, sweep)) in arcs.iter().enumerate() {
            assert!(
                (rise - 1.5).abs() < 1e-9 && (sweep - std::f64::consts::TAU).abs() < 1e-9,
                "{arcs:?}"
            );
            let span = if teeth == 1 { 1.5 } else { 4.5 };
            assert!((start - span * k as f64).abs() < 1e-9, "{spec}: {arcs:?}");
        }
    }
    for (spec, says) in [
        ("threadmill:d=6.5,pitch=1.5,teeth=0", "teeth=0"),
        ("threadmill:d=6.5,pitch=1.5,teeth=2.5", "teeth=2.5"),
        ("threadmill:d=6.5,pitch=1.5,teth=3", "unknown key 'teth'"),
    ] {
        let r = common::talas(&[
            "plan",
            part,
            "--strategy",
            "thread-mill",
            "--tool",
            spec,
            "-o",
            o,
        ]);
        assert_eq!(r.status.code(), Some(2), "{spec}");
        let err = String::from_utf8_lossy(&r.stderr);
        assert!(
            err.contains(says) && err.contains("--tool") && err.lines().count() == 1,
            "{err}"
        );
    }
}

/// A project's thread-mill operation (`talas job`) takes `"teeth"`: absent it is a
/// single-tooth mill (10 turns on the M10 tap drill), with 3 it cuts 4 turns 4.5 mm apart;
/// the key round-trips and is left out when absent; 0 teeth is refused.
#[test]
fn a_project_thread_mill_operation_takes_its_teeth() {
    use talas::project::op_holes::{HoleCycle, HolesOp};
    let part = talas::import::open(
        &data("holes/holes-part.stp"),
        &talas::import::OpenOptions::default(),
        &talas::diagnostics::Progress::new(),
    )
    .unwrap();
    let tool = ToolRecord {
        spec: "flat:d=6.5".into(),
        cutter: talas::tools::Cutter::new(talas::tools::CutterKind::Flat, 6.5).unwrap(),
    };
    let mut op = HolesOp::new("thread".into(), 0);
    op.cycle = HoleCycle::ThreadMill;
    op.pitch_mm = Some(1.5);
    assert!(!serde_json::to_string(&op).unwrap().contains("teeth"));
    let single = op.compute(&part, &tool, None).unwrap();
    assert_eq!(thread_arcs(&single.toolpath, 15.0).len(), 10);
    op.teeth = Some(3);
    let text = serde_json::to_string(&op).unwrap();
    assert!(text.contains("\"teeth\":3"), "{text}");
    let back: HolesOp = serde_json::from_str(&text).unwrap();
    assert_eq!(back, op);
    let three = back.compute(&part, &tool, None).unwrap();
    let arcs = thread_arcs(&three.toolpath, 15.0);
    assert_eq!(arcs.len(), 4, "{arcs:?}");
    for (k, &(start, rise, _)) in arcs.iter().enumerate() {
        assert!(
            (start - 4.5 * k as f64).abs() < 1e-9 && (rise - 1.5).abs() < 1e-9,
            "{arcs:?}"
        );
    }
    op.teeth = Some(0);
    assert!(op.validate().unwrap_err().contains("teeth"));
}
