//! External thread milling of two M10 × 1.5 bosses (Ø10, 15 mm tall on a 10 mm base), one with
//! a single-tooth mill, one with a three-tooth mill, 12 mm deep from the bosses' top: planned,
//! posted for LinuxCNC, the posted program read back by Talas's interpreter and cut in a
//! tri-dexel stock, then measured on the stock alone: the teeth's reach (the thread's minor
//! diameter, d − 1.226869·P = 8.15970 mm, ISO 68-1's d3) on both ends of every X and Y ray
//! through a boss from a pitch above the thread's bottom to the boss's top, the boss's
//! Ø10 untouched below the thread, and the thread's depth from the Z rays between the two
//! diameters. Nothing else lost material (no gouge of the base or the boss's core), no rapid
//! ran through material and no neck touched it.
//!
//! As in `holes_simulate.rs`, a thread mill is simulated as its teeth's envelope (a flat
//! cylinder teeth × pitch long under a narrower neck), so the stock shows the crests' reach and
//! the depth, not the flanks; the rays lie 0.2 mm apart but store their material's ends exactly.

use talas::diagnostics::Progress;
use talas::gcode::{InterpretOptions, interpret};
use talas::geometry::DVec3;
use talas::machine::Machine;
use talas::post::{Dialect, PostOptions, post};
use talas::simulation::{
    CollisionKind, DEFAULT_MEMORY_LIMIT_BYTES, DexelFamily, DexelMode, DexelStock, RayAxis,
    SimOptions, StepOptions, StockShape, plan_program, simulate,
};
use talas::strategies::holes::{HolePlanOptions, HoleStrategy, HoleTarget, plan_holes};
use talas::toolpath::ToolRecord;
use talas::tools::hole_tool::{HoleTool, HoleToolKind};

const RES: f64 = 0.2;
const PITCH: f64 = 1.5;
const BOSS_R: f64 = 5.0;
const BOSS_TOP: f64 = 25.0;
const BASE_TOP: f64 = 10.0;
const DEPTH: f64 = 12.0;

/// A thread mill as the simulation sees it: its teeth (teeth × pitch long) under a neck.
fn thread_mill(d: f64, teeth: u32, neck: f64) -> ToolRecord {
    let t = HoleTool {
        kind: HoleToolKind::ThreadMill {
            pitch_mm: PITCH,
            teeth,
        },
        diameter_mm: d,
    };
    let mut c = t.cutter().unwrap();
    c.flute_length = f64::from(teeth) * PITCH;
    c.shank_diameter = neck;
    c.overall_length = 40.0;
    ToolRecord {
        spec: t.spec(),
        cutter: c,
    }
}

/// The material interval of ray (i, j) that holds `c` (along the ray, world coordinates).
fn around(f: &DexelFamily, i: usize, j: usize, c: f64) -> Option<(f64, f64)> {
    let (_, _, wa) = f.axis.axes();
    let o = f.origin.to_array()[wa];
    f.dexels[j * f.nu + i]
        .intervals()
        .iter()
        .map(|iv| (o + f64::from(iv[0]), o + f64::from(iv[1])))
        .find(|&(a, b)| a < c && c < b)
}

#[test]
#[expect(
    clippy::too_many_lines,
    reason = "one job: the stock, the two bosses planned, posted and cut, then each measured"
)]
fn external_threads_milled_on_two_bosses_measure_their_minor_diameter_and_depth() {
    let minor = 10.0 - 1.226_869 * PITCH;
    // (centre x, teeth, mill Ø, neck Ø).
    // Away from the origin, where the interpreted program starts.
    let bosses = [(30.0, 1_u32, 8.0, 6.0), (50.0, 3, 8.0, 6.0)];
    let cy = 40.0;
    let mut shapes = vec![StockShape::Box {
        min: DVec3::new(20.0, 20.0, 0.0),
        max: DVec3::new(60.0, 65.0, BASE_TOP),
    }];
    for &(cx, ..) in &bosses {
        shapes.push(StockShape::Cylinder {
            base: DVec3::new(cx, cy, BASE_TOP),
            radius: BOSS_R,
            height: BOSS_TOP - BASE_TOP,
        });
    }
    let mut stock =
        DexelStock::new(shapes, RES, DexelMode::Tri, DEFAULT_MEMORY_LIMIT_BYTES).expect("stock");
    let opts = HolePlanOptions {
        chord_tol_mm: 0.001,
        feed_mm_per_min: 300.0,
        start: DVec3::new(0.0, 0.0, 50.0),
        ..HolePlanOptions::default()
    };
    let step = StepOptions {
        chord_tolerance_mm: 0.001,
        ..StepOptions::default()
    };
    let machine = Machine::builtin("mill-3axis").unwrap();
    let dialect = Dialect::resolve("linuxcnc").unwrap();
    for &(cx, teeth, d, neck) in &bosses {
        let tool = thread_mill(d, teeth, neck);
        let target = HoleTarget {
            top: DVec3::new(cx, cy, BOSS_TOP),
            direction: DVec3::Z,
            depth_mm: DEPTH,
            diameter_mm: minor,
        };
        let plan = plan_holes(
            &[target],
            &HoleStrategy::ExternalThreadMill {
                pitch_mm: PITCH,
                teeth,
            },
            tool.clone(),
            None,
            &opts,
        )
        .unwrap();
        let tp = plan.toolpath.unwrap();
        let text = post(&tp, &machine, &dialect, &PostOptions::default()).unwrap();
        // Climb on an external thread: clockwise arcs (G2, modal), falling a pitch per turn: a
        // single-tooth mill 12 / 1.5 = 8 turns, three teeth ⌈12 / 4.5⌉ = 3 (an arc block is
        // one with a J word: every turn starts on the +Y side of the axis).
        let turns = if teeth == 1 { 8 } else { 3 };
        let words = |w: &str| {
            text.lines()
                .filter(|l| l.split_whitespace().any(|x| x.starts_with(w)))
                .count()
        };
        assert_eq!(
            (words("J"), words("G3"), words("G2") > 0),
            (turns, 0, true),
            "{teeth} teeth:\n{text}"
        );
        let program = interpret(&text, &InterpretOptions::default()).expect("interpret");
        let moves = plan_program(&program, None, &step).expect("moves");
        let report = simulate(
            &mut stock,
            &tool.cutter,
            &moves,
            &SimOptions::default(),
            &Progress::new(),
        )
        .expect("simulate");
        assert!(
            !report
                .collisions
                .iter()
                .any(|c| c.kind == CollisionKind::Rapid || c.kind == CollisionKind::Shank),
            "{teeth} teeth: {:?}",
            report.collisions
        );
    }
    let (z, x, y) = (&stock.families[0], &stock.families[1], &stock.families[2]);
    let tol = 0.01;
    let bottom = BOSS_TOP - DEPTH;
    let mut worst: f64 = 0.0;
    for &(cx, teeth, ..) in &bosses {
        let what = format!("boss at x = {cx} mm ({teeth} teeth)");
        // Both ends of the X ray row through the axis (y ≈ cy) and of the Y ray row (x ≈ cx).
        let mut levels = 0;
        for fam in [x, y] {
            let along_x = fam.axis == RayAxis::X;
            let o = fam.origin;
            let (k, n, centre) = if along_x {
                (
                    ((cy - o.y) / fam.spacing - 0.5).round() as usize,
                    fam.nv,
                    cx,
                )
            } else {
                (
                    ((cx - o.x) / fam.spacing - 0.5).round() as usize,
                    fam.nu,
                    cy,
                )
            };
            for l in 0..n {
                let (i, j) = if along_x { (k, l) } else { (l, k) };
                let ray = fam.ray_origin(i, j);
                let delta = if along_x { ray.y - cy } else { ray.x - cx };
                let want = if ray.z > bottom + PITCH && ray.z < BOSS_TOP {
                    0.5 * minor
                } else if ray.z > BASE_TOP && ray.z < bottom - 1e-6 {
                    BOSS_R
                } else {
                    continue;
                };
                let (lo, hi) = around(fam, i, j, centre)
                    .unwrap_or_else(|| panic!("{what}: no material at z {}", ray.z));
                for e in [lo - centre, hi - centre] {
                    let r = e.hypot(delta);
                    worst = worst.max((r - want).abs());
                    assert!(
                        (r - want).abs() <= tol,
                        "{what}: radius {r} mm at z {} (want {want} mm)",
                        ray.z
                    );
                }
                levels += 1;
            }
        }
        assert!(levels > 100, "{what}: {levels}");
        // The depth: the Z rays between the minor diameter and the boss's: the lowest top at
        // the thread's bottom (where the teeth went out), none lower, none a pitch higher.
        let (mut lowest, mut highest, mut rays) = (f64::INFINITY, f64::NEG_INFINITY, 0);
        for j in 0..z.nv {
            for i in 0..z.nu {
                let p = z.ray_origin(i, j);
                let rho = (p.x - cx).hypot(p.y - cy);
                if rho < 0.5 * minor + 0.1 || rho > BOSS_R - 0.1 {
                    continue;
                }
                let top = z.dexels[j * z.nu + i]
                    .intervals()
                    .iter()
                    .map(|iv| z.origin.z + f64::from(iv[1]))
                    .fold(f64::NEG_INFINITY, f64::max);
                lowest = lowest.min(top);
                highest = highest.max(top);
                rays += 1;
            }
        }
        assert!(rays > 50, "{what}: {rays}");
        worst = worst.max((lowest - bottom).abs());
        assert!(
            (lowest - bottom).abs() <= tol,
            "{what}: lowest {lowest} mm, bottom {bottom} mm"
        );
        assert!(
            highest <= bottom + PITCH + tol,
            "{what}: a ring ray's top at {highest} mm, over a pitch above {bottom} mm"
        );
    }
    eprintln!("worst deviation of a measured radius or depth: {worst:.5} mm");
    // No gouge: the base outside the bosses and every boss's core keep their material whole.
    let mut checked = 0;
    for j in 0..z.nv {
        for i in 0..z.nu {
            let p = z.ray_origin(i, j);
            let rho = bosses
                .iter()
                .map(|b| (p.x - b.0).hypot(p.y - cy))
                .fold(f64::INFINITY, f64::min);
            let want = if rho > BOSS_R + 0.3 {
                BASE_TOP
            } else if rho < 0.5 * minor - 0.3 {
                BOSS_TOP
            } else {
                continue;
            };
            let ivs = z.dexels[j * z.nu + i].intervals();
            assert_eq!(ivs.len(), 1, "ray at ({}, {}): {ivs:?}", p.x, p.y);
            let (lo, hi) = (
                z.origin.z + f64::from(ivs[0][0]),
                z.origin.z + f64::from(ivs[0][1]),
            );
            assert!(
                lo.abs() < 1e-4 && (hi - want).abs() < 1e-4,
                "ray at ({}, {}): {lo}..{hi}",
                p.x,
                p.y
            );
            checked += 1;
        }
    }
    assert!(checked > 30_000, "{checked}");
}
