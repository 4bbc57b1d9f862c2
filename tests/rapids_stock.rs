//! Rapids above the in-process stock, end to end (issue 35, "heights from the stock"): on the
//! pocket-fillets part (Open CASCADE's tessellation of `tests/data/pocket-fillets.stp`), a
//! Z-level roughing that leaves 1 mm, then raster finishing with a 6 mm ball. The finishing's
//! stored path links with rapids at heights from the part only; its linked path
//! (`Results::linked`: the stored path with the rapids lifted over the stock before it) is
//! what the store posts, runs and cuts.
//!
//! Two independent checks of "a rapid passes through the stock", neither using
//! `project::rapids`: (1) this file's own test of the tool's lower surface against every Z
//! dexel under it, sampled along each rapid; (2) the simulation's rapid-collision report
//! (`simulate` of the moves into a copy of the stock before the finishing), of the tool path
//! and of its posted run. Before the link both find rapids through the stock (printed); after
//! it the own check and both simulations find none, and the posted run's simulation reports
//! what the tool path's does (its steps used to be named by the moves `lead_in_blocks` later,
//! so cutting steps at the end of a pass were counted as the retract's: 220 and 110 "rapid
//! collisions"). `cargo test --no-default-features --test rapids_stock -- --nocapture` prints
//! them.

mod common;

use std::path::Path;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::import::Workpiece;
use talas::project::results::{RUN_CORNER_TOLERANCE_MM, operation_moves};
use talas::project::{InProcessStock, Operation, OperationKind, Project, Results, ToolEntry};
use talas::simulation::{
    CollisionKind, DexelStock, MovePlan, RayAxis, SimOptions, StepOptions, plan_toolpath, simulate,
};
use talas::toolpath::{MoveKind, Toolpath};
use talas::tools::parse_tool_spec;

fn project() -> Project {
    let entry = |name: &str, s: &str| ToolEntry {
        name: name.into(),
        cutter: parse_tool_spec(s).unwrap(),
    };
    let mut rough = Operation::new(OperationKind::Rough, 0, 0);
    if let Operation::Rough {
        stock_to_leave_mm,
        step_down_mm,
        ..
    } = &mut rough
    {
        *stock_to_leave_mm = 1.0;
        *step_down_mm = 3.0;
    }
    let mut finish = Operation::new(OperationKind::Raster, 1, 0);
    if let Operation::Raster {
        scallop_mm,
        one_way,
        ..
    } = &mut finish
    {
        // One way: every pass ends in a retract, a rapid back and a rapid down to the next
        // pass's feed height, which the planner puts 1 mm (its own clearance) above the part.
        *scallop_mm = 0.05;
        *one_way = true;
    }
    Project {
        tools: vec![
            entry("T1", "flat:d=10,flute=30,length=60"),
            entry("T2", "ball:d=6,flute=30,length=60"),
        ],
        selected_tool: Some(0),
        operations: vec![rough, finish],
        ..Project::default()
    }
}

/// Rapids of `tp` (all but retracts straight up) whose tool, vertical, has material of
/// `stock` above its lower surface (more than 0.01 mm) anywhere along them: how many, and the
/// deepest, mm. Every Z ray within the tool radius of each sample point is tested.
fn rapids_through(tp: &Toolpath, stock: &DexelStock) -> (usize, f64) {
    let fam = stock
        .families
        .iter()
        .find(|f| f.axis == RayAxis::Z)
        .expect("Z dexels");
    let cutter = &tp.tool.cutter;
    let r = cutter.radius();
    let h = fam.spacing;
    let (mut count, mut worst) = (0, 0.0_f64);
    for w in tp.poses.windows(2) {
        let (a, b) = (w[0].tip, w[1].tip);
        let retract = (b - a).truncate().length() < 1e-6 && b.z >= a.z;
        if w[1].kind != MoveKind::Rapid || retract {
            continue;
        }
        let n = ((b - a).length() / (0.5 * h)).ceil().max(1.0) as usize;
        let mut deepest = 0.0_f64;
        for k in 0..=n {
            let p = a.lerp(b, k as f64 / n as f64);
            let i0 = (((p.x - r - fam.origin.x) / h).floor().max(0.0)) as usize;
            let j0 = (((p.y - r - fam.origin.y) / h).floor().max(0.0)) as usize;
            let i1 = ((((p.x + r - fam.origin.x) / h).ceil()) as usize).min(fam.nu);
            let j1 = ((((p.y + r - fam.origin.y) / h).ceil()) as usize).min(fam.nv);
            for j in j0..j1 {
                for i in i0..i1 {
                    let o = fam.ray_origin(i, j);
                    let d = (o.truncate() - p.truncate()).length();
                    let Some(lift) = cutter.height_at_radius(d) else {
                        continue;
                    };
                    if let Some(iv) = fam.dexels[j * fam.nu + i].intervals().last() {
                        let top = fam.origin.z + f64::from(iv[1]);
                        deepest = deepest.max(top - (p.z + lift));
                    }
                }
            }
        }
        if deepest > 0.01 {
            count += 1;
            worst = worst.max(deepest);
        }
    }
    (count, worst)
}

/// Rapid collisions the simulation reports cutting `plan` into a copy of `stock`.
fn rapid_collisions(stock: &InProcessStock, tp: &Toolpath, plan: &MovePlan) -> (usize, f64) {
    let mut dexels = stock.dexels.clone();
    let report = simulate(
        &mut dexels,
        &tp.tool.cutter,
        plan,
        &SimOptions::default(),
        &Progress::new(),
    )
    .unwrap();
    let rapid: Vec<_> = report
        .collisions
        .iter()
        .filter(|c| c.kind == CollisionKind::Rapid)
        .collect();
    for c in rapid.iter().take(2) {
        for k in c.move_index.saturating_sub(3)..(c.move_index + 2).min(plan.moves.len()) {
            let m = &plan.moves[k];
            eprintln!(
                "  {} move {k} block {} rapid {} from {:?} to {:?}",
                if k == c.move_index { "*" } else { " " },
                m.block,
                m.rapid,
                m.start.tip,
                m.end.tip
            );
        }
        eprintln!("  collision at {:?}, {:.3} mm", c.position, c.depth_mm);
    }
    (
        rapid.len(),
        rapid.iter().map(|c| c.depth_mm).fold(0.0, f64::max),
    )
}

#[test]
fn finishing_after_roughing_links_above_the_stock_the_roughing_left() {
    let part = Workpiece::from_mesh(
        Path::new("pocket-fillets.stl"),
        common::pocket_fillets_stl(),
        Vec::new(),
    );
    let project = project();
    let store = Results::new();
    let p = Progress::new();
    let stored = store.get_or_compute(&project, &part, 1, &p).unwrap();
    let before = store.stock_before(&project, &part, 1, &p).unwrap();
    let linked = store.linked(&project, &part, 1, &p).unwrap();
    let res = before.resolution_mm();
    let step = StepOptions::for_resolution(res, stored.toolpath.tool.cutter.flute_length);

    // (1) The tool's lower surface against the dexels, along every rapid.
    let (n0, d0) = rapids_through(&stored.toolpath, &before.dexels);
    let (n1, d1) = rapids_through(&linked.toolpath, &before.dexels);
    // (2) The simulation's rapid collisions, of the tool path and of its posted run.
    let plan = |tp: &Toolpath| plan_toolpath(tp, &step).unwrap();
    let posted = |tp: &Toolpath| operation_moves(&project, 1, tp, &step).unwrap().0;
    // Every step of the posted run names the move it belongs to.
    let run = posted(&linked.toolpath);
    for (k, m) in run.moves.iter().enumerate() {
        let end = run
            .moves
            .get(k + 1)
            .map_or(run.steps.len(), |n| n.first_step);
        for st in &run.steps[m.first_step..end] {
            assert_eq!(
                st.move_index, k,
                "a step of move {k} names move {}",
                st.move_index
            );
        }
    }
    let (s0, sd0) = rapid_collisions(&before, &stored.toolpath, &plan(&stored.toolpath));
    let (s1, _) = rapid_collisions(&before, &linked.toolpath, &plan(&linked.toolpath));
    let (q0, qd0) = rapid_collisions(&before, &stored.toolpath, &posted(&stored.toolpath));
    let (q1, _) = rapid_collisions(&before, &linked.toolpath, &posted(&linked.toolpath));
    // Cycle times of the posted runs, stored and linked.
    let time = |tp: &Toolpath| {
        talas::project::posting::run_operation(&project, 1, tp, 2, RUN_CORNER_TOLERANCE_MM)
            .unwrap()
            .motion
            .unwrap()
            .cycle_time_s()
    };
    let (t0, t1) = (time(&stored.toolpath), time(&linked.toolpath));
    eprintln!(
        "stock grid {res} mm; rapids through the stock (own check): stored {n0} (deepest \
         {d0:.3} mm), linked {n1} ({d1:.3}); simulated rapid collisions: tool path {s0} \
         ({sd0:.3} mm) -> {s1}, posted run {q0} ({qd0:.3} mm) -> {q1}; lifted {} (deepest \
         {:.3} mm), fed down {}, fed up {}, fed links through stock {}; cycle time {t0:.2} s -> {t1:.2} s \
         ({:+.2} s); {} -> {} poses",
        linked.lift.lifted,
        linked.lift.worst_depth_mm,
        linked.lift.fed_down,
        linked.lift.fed_up,
        linked.fed_links_through_stock,
        t1 - t0,
        stored.toolpath.poses.len(),
        linked.toolpath.poses.len(),
    );
    assert!(
        n0 > 0,
        "the stored path's rapids should run into the roughing's stock"
    );
    assert!(s0 + q0 > 0, "the simulation should see them too");
    assert_eq!(n1, 0, "linked rapids through the stock");
    assert_eq!(s1, 0, "simulated rapid collisions of the linked tool path");
    // The posted run is simulated as its tool path is: the same rapid collisions before the
    // link, none after.
    assert_eq!(q0, s0, "posted run and tool path, stored");
    assert_eq!(q1, 0, "posted run of the linked path");
    assert!(linked.lift.fed_down > 0 && linked.lift.fed_up > 0);

    // The store cuts the linked path's posted run (the same moves as `posted` above).
    let after = store.stock_after(&project, &part, 1, &p).unwrap();
    let last = after.last_cut.as_ref().expect("the finishing's cut");
    let store_rapid = last
        .collisions
        .iter()
        .filter(|c| c.kind == CollisionKind::Rapid)
        .count();
    assert_eq!(store_rapid, q1, "the store cuts the linked path's run");
    // The cutting moves are the stored path's: only the links changed.
    let cuts = |tp: &Toolpath| -> Vec<DVec3> {
        tp.poses
            .iter()
            .filter(|q| q.kind == MoveKind::Cut)
            .map(|q| q.tip)
            .collect()
    };
    assert_eq!(cuts(&stored.toolpath), cuts(&linked.toolpath));
    // The linked path is memoised under the two digests.
    let again = store.linked(&project, &part, 1, &p).unwrap();
    assert!(std::sync::Arc::ptr_eq(&linked, &again));
}

/// The first operation is linked over the raw stock box: a finishing alone on a stock 5 mm
/// above the part gets its rapids lifted over that stock.
#[test]
fn the_first_operation_links_over_the_raw_stock() {
    let part = Workpiece::from_mesh(
        Path::new("pocket-fillets.stl"),
        common::pocket_fillets_stl(),
        Vec::new(),
    );
    let mut project = project();
    project.operations.remove(0);
    project.stock = talas::project::Stock::Box {
        min_mm: [-2.0, -2.0, 0.0],
        max_mm: [102.0, 82.0, 37.0],
    };
    let store = Results::new();
    let p = Progress::new();
    let stored = store.get_or_compute(&project, &part, 0, &p).unwrap();
    let before = store.stock_before(&project, &part, 0, &p).unwrap();
    let linked = store.linked(&project, &part, 0, &p).unwrap();
    let (n0, _) = rapids_through(&stored.toolpath, &before.dexels);
    let (n1, _) = rapids_through(&linked.toolpath, &before.dexels);
    eprintln!("raw stock: rapids through it {n0} -> {n1}");
    assert!(n0 > 0);
    assert_eq!(n1, 0);
}
