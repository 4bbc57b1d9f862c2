//! The engine's machining run (post → interpret → jerk-limited plan → line ↔ pose ↔ time maps),
//! checked against the planned motion itself sampled at the run's times, against the move
//! plan the simulation takes, and against `talas feed` planning the same posted program.

mod common;

use common::{talas_json, temp_file};
use glam::DVec3;
use talas::machine::Machine;
use talas::post::{Dialect, PostOptions};
use talas::project::MachiningRun;
use talas::simulation::StepOptions;
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::parse_tool_spec;

const FEED_MM_MIN: f64 = 800.0;
const CORNER_MM: f64 = 0.01;

fn tool() -> ToolRecord {
    ToolRecord {
        spec: "ball:d=6".into(),
        cutter: parse_tool_spec("ball:d=6").unwrap(),
    }
}

/// Five zig-zag passes of 40 mm along X, 2 mm apart, with a pose every 5 mm, entered by a
/// rapid and a plunge, left by a retract.
fn zigzag() -> Toolpath {
    let mut poses = vec![Pose::new(
        MoveKind::Rapid,
        DVec3::new(0.0, 0.0, 10.0),
        DVec3::Z,
        FEED_MM_MIN,
    )];
    poses.push(Pose::new(
        MoveKind::Plunge,
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::Z,
        FEED_MM_MIN,
    ));
    for pass in 0..5 {
        let y = 2.0 * f64::from(pass);
        for k in 0..=8 {
            let x = if pass % 2 == 0 {
                5.0 * k as f64
            } else {
                40.0 - 5.0 * k as f64
            };
            if pass > 0 || k > 0 {
                poses.push(Pose::new(
                    MoveKind::Cut,
                    DVec3::new(x, y, 0.0),
                    DVec3::Z,
                    FEED_MM_MIN,
                ));
            }
        }
    }
    let last = poses.last().unwrap().tip;
    poses.push(Pose::new(
        MoveKind::Link,
        last + DVec3::new(0.0, 0.0, 10.0),
        DVec3::Z,
        FEED_MM_MIN,
    ));
    Toolpath::new(tool(), poses)
}

fn run_of(tp: &Toolpath) -> (MachiningRun, Machine) {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let dialect = Dialect::resolve("linuxcnc").unwrap();
    let run = MachiningRun::new(tp, &machine, &dialect, &PostOptions::default(), CORNER_MM)
        .expect("posts");
    (run, machine)
}

/// Is pose `k` in the middle of a straight run (the moves before and after it are collinear),
/// so the planner passes through it exactly instead of blending a corner?
fn straight_through(tp: &Toolpath, k: usize) -> bool {
    let (Some(a), Some(b), Some(c)) = (
        k.checked_sub(1).and_then(|i| tp.poses.get(i)),
        tp.poses.get(k),
        tp.poses.get(k + 1),
    ) else {
        return false;
    };
    let (u, v) = (b.tip - a.tip, c.tip - b.tip);
    u.cross(v).length() < 1e-12 && u.dot(v) > 0.0 && a.kind == b.kind && b.kind == c.kind
}

#[test]
fn the_machine_stands_at_each_pose_at_the_time_the_run_gives() {
    let tp = zigzag();
    let (run, _) = run_of(&tp);
    let motion = run.motion.as_ref().expect("planned");
    assert_eq!(motion.pose_time_s.len(), tp.poses.len());
    assert!(
        motion.pose_time_s.windows(2).all(|w| w[0] <= w[1]),
        "pose times must not decrease"
    );
    assert!(*motion.pose_time_s.last().unwrap() <= motion.cycle_time_s() + 1e-12);
    let (mut exact, mut corners) = (0, 0);
    for (k, pose) in tp.poses.iter().enumerate() {
        let Some(_) = run.line_of_pose[k] else {
            continue;
        };
        let at = motion.timed.state_at(motion.pose_time_s[k]).position;
        let d = (DVec3::new(at[0], at[1], at[2]) - pose.tip).length();
        if straight_through(&tp, k) {
            assert!(
                d < 1e-6,
                "pose {k}: the machine is {d} mm from it at its time"
            );
            exact += 1;
        } else {
            // A blended corner is left before it is reached: the blend starts within a short
            // distance of the corner (its deviation from the corner is within the tolerance).
            assert!(d < 0.5, "pose {k}: {d} mm from the corner at its time");
            corners += 1;
        }
        // The mean planned speed of the line reaching a pose never exceeds the programmed feed
        // (rapids aside).
        let feed = f64::from(motion.pose_feed_mm_min[k]);
        if pose.kind != MoveKind::Rapid {
            assert!(
                feed > 0.0 && feed <= FEED_MM_MIN * (1.0 + 1e-9),
                "pose {k}: {feed}"
            );
        }
    }
    assert!(
        exact >= 20 && corners >= 8,
        "{exact} straight, {corners} corners"
    );
    // The line running at each pose's time is that pose's line or the one after it.
    for (k, t) in motion.pose_time_s.iter().enumerate() {
        let (Some(line), Some(at)) = (run.line_of_pose[k], motion.line_at_time(*t)) else {
            continue;
        };
        assert!(
            at >= line,
            "pose {k}: line {at} runs at its time, before {line}"
        );
    }
}

#[test]
fn the_simulated_moves_take_the_planned_time() {
    let tp = zigzag();
    let (run, machine) = run_of(&tp);
    let motion = run.motion.as_ref().expect("planned");
    let plan = motion
        .move_plan(&machine, &StepOptions::default())
        .expect("simulation plan");
    let total: f64 = plan.moves.iter().map(|m| m.duration_s).sum();
    assert!(
        (total - motion.cycle_time_s()).abs() < 1e-9 * motion.cycle_time_s(),
        "moves {total} s, plan {} s",
        motion.cycle_time_s()
    );
    // Jerk-limited motion is never faster than the programmed feed (path length / feed).
    let at_feed: f64 = plan
        .moves
        .iter()
        .filter(|m| !m.rapid)
        .map(|m| m.length_mm / FEED_MM_MIN * 60.0)
        .sum();
    let planned_fed: f64 = plan
        .moves
        .iter()
        .filter(|m| !m.rapid)
        .map(|m| m.duration_s)
        .sum();
    assert!(
        planned_fed >= at_feed * (1.0 - 1e-9),
        "{planned_fed} < {at_feed}"
    );
}

#[test]
fn talas_post_reports_the_cycle_time_talas_feed_plans() {
    let tp = zigzag();
    let input = temp_file("run", "zigzag.json", "");
    tp.save(&input).unwrap();
    let output = input.with_extension("ngc");
    let doc = talas_json(&[
        "post",
        input.to_str().unwrap(),
        "--machine",
        "mill-3axis",
        "--dialect",
        "linuxcnc",
        "--corner-tolerance",
        "0.01",
        "-o",
        output.to_str().unwrap(),
        "--json",
    ]);
    let cycle = doc["cycle_time_s"].as_f64().expect("cycle time");
    let times: Vec<f64> = doc["pose_time_s"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t.as_f64().unwrap())
        .collect();
    assert_eq!(times.len(), tp.poses.len());
    assert_eq!(doc["poses"].as_u64(), Some(tp.poses.len() as u64));
    assert!(times.windows(2).all(|w| w[0] <= w[1]));
    // The same program planned by `talas feed` with the same corner tolerance, from the same
    // start: the run reads the program from machine zero, `feed --machine` from the machine's
    // home unless told.
    let feed = talas_json(&[
        "feed",
        output.to_str().unwrap(),
        "--machine",
        "mill-3axis",
        "--start",
        "0,0,0",
        "--corners",
        "blend",
        "--deviation",
        "0.01",
        "--json",
    ]);
    let motion = feed["motion_time_s"].as_f64().unwrap();
    assert!(
        (cycle - motion).abs() < 1e-9 * motion,
        "post {cycle} s, feed {motion} s"
    );
    // The line of each pose (1-based) holds its X.
    let text = std::fs::read_to_string(&output).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let line = doc["line_of_pose"][5].as_u64().expect("pose 5 has a line") as usize;
    let x = lines[line - 1]
        .split_whitespace()
        .find_map(|w| w.strip_prefix('X').and_then(|v| v.parse::<f64>().ok()))
        .expect("pose 5 moves along X");
    assert!((x - tp.poses[5].tip.x).abs() < 1e-3, "{}", lines[line - 1]);
    // A bad tolerance is refused with exit 2.
    let out = common::talas(&[
        "post",
        input.to_str().unwrap(),
        "--machine",
        "mill-3axis",
        "--dialect",
        "linuxcnc",
        "--corner-tolerance",
        "-1",
        "-o",
        output.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(2));
}
