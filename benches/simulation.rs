//! Stock simulation speed and memory on a finishing program: a zig-zag raster of a 6 mm ball
//! end mill over a bumpy surface, 60 × 60 mm, at least 100 000 moves.
//!
//! First one full run per resolution (0.1 mm and 0.05 mm) printing moves per second, stock
//! memory and the equivalent voxel count (to set beside CAMotics' 10 M-cell ceiling and
//! cutrail's "a few milliseconds per segment"); then criterion on the first 2 000 moves.
//! `TALAS_SIM_BENCH_MOVES=N` changes the program size. The peer comparison on the same
//! program is `benches/simulation_peer.sh` (cutrail from crates.io).
//!
//! Then the README's 5-axis example: iso-scallop finishing of `bicubic-hills.stp` (6 mm ball,
//! 0.05 mm scallop, axis along the normal), simulated as the workstation does it
//! (`project::simulate::simulate_toolpaths`: the part's box + 2 mm, Z dexels, at most 250 000
//! rays, deviation included), and the removal alone on a tri-dexel stock at the same
//! resolution (what `talas simulate` does with a tilted path), in moves per second.
//! Then "Stock here" at the last and the middle pose of that path from the stock keyframes
//! kept by a whole run (`project::keyframes`).
//! `TALAS_SIM_BENCH_FIVE=0` leaves it out, `TALAS_SIM_BENCH_FIVE=ws` runs only its workstation
//! line (with a digest of the result, to check that a change keeps it bit for bit), `TALAS_SIM_BENCH_FIVE_POSES=N` simulates only the
//! first N poses.

use std::hint::black_box;
use std::time::Instant;

use criterion::{BatchSize, Criterion};
use glam::DVec3;
use talas::diagnostics::Progress;
use talas::simulation::{
    DexelMode, DexelStock, MovePlan, SimOptions, StepOptions, StockShape, estimate_bytes,
    plan_toolpath, simulate,
};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::{Cutter, CutterKind};

/// The bumpy surface the raster follows (tip height), mm.
fn surface(x: f64, y: f64) -> f64 {
    1.5 * (x / 6.0).sin() * (y / 8.0).cos() + 0.5 * (x * y / 150.0).sin()
}

/// A zig-zag raster of about `moves` moves over [0, 60]².
fn raster(moves: usize) -> Toolpath {
    let lines = 200usize;
    let per_line = moves.div_ceil(lines).max(2);
    let mut poses = vec![Pose::new(
        MoveKind::Rapid,
        DVec3::new(0.0, 0.0, 10.0),
        DVec3::Z,
        0.0,
    )];
    for j in 0..lines {
        #[allow(clippy::cast_precision_loss)]
        let y = 60.0 * j as f64 / (lines - 1) as f64;
        for k in 0..per_line {
            #[allow(clippy::cast_precision_loss)]
            let t = k as f64 / (per_line - 1) as f64;
            let x = if j % 2 == 0 {
                60.0 * t
            } else {
                60.0 * (1.0 - t)
            };
            let kind = if j == 0 && k == 0 {
                MoveKind::Plunge
            } else {
                MoveKind::Cut
            };
            poses.push(Pose::new(
                kind,
                DVec3::new(x, y, surface(x, y)),
                DVec3::Z,
                3000.0,
            ));
        }
    }
    let cutter = Cutter::new(CutterKind::Ball, 6.0).unwrap_or_else(|e| panic!("{e}"));
    Toolpath::new(
        ToolRecord {
            spec: "ball:d=6".into(),
            cutter,
        },
        poses,
    )
}

fn stock(res: f64) -> DexelStock {
    DexelStock::new(
        vec![StockShape::Box {
            min: DVec3::new(-4.0, -4.0, -5.0),
            max: DVec3::new(64.0, 64.0, 3.0),
        }],
        res,
        DexelMode::Z,
        8 << 30,
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// CPU time of this process so far (user + system, all threads), s; `None` off Linux. On the
/// shared build machine the wall clock counts the time other processes hold the cores; the
/// CPU time counts only this run's work.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = stat.rsplit_once(')')?.1;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    // Fields 14 and 15 of proc(5) (utime, stime) in clock ticks of 1/100 s.
    let ticks = |k: usize| fields.get(k).and_then(|v| v.parse::<f64>().ok());
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// "CPU c s, m moves per CPU second" for `moves` moves done since `cpu0`.
fn cpu_note(cpu0: Option<f64>, moves: f64) -> String {
    match (cpu0, cpu_seconds()) {
        (Some(a), Some(b)) if b > a => format!(
            "CPU {:.2} s = {:.0} moves per CPU second",
            b - a,
            moves / (b - a)
        ),
        _ => "CPU time not available".into(),
    }
}

fn full_run(tp: &Toolpath, plan: &MovePlan, res: f64) {
    let mut s = stock(res);
    let cpu0 = cpu_seconds();
    let started = Instant::now();
    let report = simulate(
        &mut s,
        &tp.tool.cutter,
        plan,
        &SimOptions::default(),
        &Progress::new(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let secs = started.elapsed().as_secs_f64();
    #[allow(clippy::cast_precision_loss)]
    let moves = plan.moves.len() as f64;
    let cpu = cpu_note(cpu0, moves);
    let voxels = (68.0 / res) * (68.0 / res) * (8.0 / res);
    let estimate = estimate_bytes(&s.bounds, res, DexelMode::Z).unwrap_or(0);
    println!(
        "simulation {res} mm: {} moves in {secs:.2} s = {:.0} moves/s ({:.3} ms/move), \
         removed {:.1} mm³, stock {:.1} MiB (estimate {:.1} MiB), {} rays = {:.0} M voxels at \
         this resolution, {} threads, {cpu}",
        plan.moves.len(),
        moves / secs,
        1000.0 * secs / moves,
        report.removed_volume_mm3,
        report.memory_bytes as f64 / f64::from(1 << 20),
        estimate as f64 / f64::from(1 << 20),
        s.ray_count(),
        voxels / 1e6,
        rayon::current_num_threads(),
    );
}

/// The README's 5-axis example, as the workstation and `talas simulate` run it.
fn five_axis() {
    use std::path::Path;
    use talas::geometry::tessellate::{TessellationOptions, tessellate_part};
    use talas::import::step::read_step;
    use talas::project::Stock;
    use talas::project::simulate::{SimulationSettings, simulate_toolpath};
    use talas::strategies::finish::face::FacePatch;
    use talas::strategies::finish::plan::plan_finish;
    use talas::strategies::finish::{FinishOptions, Strategy};
    use talas::tools::parse_tool_spec;

    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bicubic-hills.stp");
    let part = read_step(&path).unwrap_or_else(|e| panic!("{e}"));
    let mesh = tessellate_part(&part, &TessellationOptions::default()).mesh;
    let face = part.faces.first().unwrap_or_else(|| panic!("no face"));
    let patch = FacePatch::from_face(face).unwrap_or_else(|e| panic!("{e}"));
    let cutter = parse_tool_spec("ball:d=6").unwrap_or_else(|e| panic!("{e}"));
    let opts = FinishOptions {
        scallop: 0.05,
        ..FinishOptions::default()
    };
    let started = Instant::now();
    let plan = plan_finish(patch, &cutter, "ball:d=6", Strategy::IsoScallop, &opts)
        .unwrap_or_else(|e| panic!("{e}"));
    let mut tp = plan.toolpath;
    let all = tp.poses.len();
    if let Some(n) = std::env::var("TALAS_SIM_BENCH_FIVE_POSES")
        .ok()
        .and_then(|v| v.parse::<usize>().ok())
    {
        tp = Toolpath::new(tp.tool.clone(), tp.poses.into_iter().take(n).collect());
    }
    let tp = &tp;
    println!(
        "5-axis path: {all} poses planned, the first {} simulated",
        tp.poses.len()
    );
    println!(
        "5-axis iso-scallop bicubic-hills h 0.05 ball d6: {} poses, planned in {:.2} s",
        tp.poses.len(),
        started.elapsed().as_secs_f64()
    );
    let settings = SimulationSettings {
        max_rays: 250_000,
        ..SimulationSettings::default()
    };
    let cpu0 = cpu_seconds();
    let started = Instant::now();
    let sim = simulate_toolpath(
        &Stock::None,
        &mesh,
        tp,
        &cutter,
        &settings,
        &Progress::new(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let secs = started.elapsed().as_secs_f64();
    #[allow(clippy::cast_precision_loss)]
    let cpu = cpu_note(cpu0, sim.report.moves as f64);
    println!(
        "  workstation (Z dexels, {} mm, deviation included): {secs:.2} s, {} moves in {} steps \
         = {:.0} moves/s, removed {:.1} mm³, max gouge {:.4} mm, remaining p99 {:.4} mm, {cpu}",
        sim.resolution_mm,
        sim.report.moves,
        sim.report.steps,
        sim.report.moves as f64 / secs,
        sim.report.removed_volume_mm3,
        sim.max_gouge_mm,
        sim.remaining_p99_mm,
    );
    println!(
        "  workstation digest (stock mesh, deviations, collisions) {:016x}",
        digest(&sim)
    );
    if std::env::var("TALAS_SIM_BENCH_FIVE").is_ok_and(|v| v == "ws") {
        return;
    }
    stock_here_at_the_end(&mesh, tp, &cutter, &settings);
    let res = sim.resolution_mm;
    let step = StepOptions {
        reach_mm: cutter.flute_length,
        chord_tolerance_mm: (0.05 * res).clamp(1e-4, 0.01),
        axis_tolerance_mm: (0.1 * res).clamp(1e-4, 0.02),
        ..StepOptions::default()
    };
    let moves = plan_toolpath(tp, &step).unwrap_or_else(|e| panic!("{e}"));
    let b = mesh.bbox();
    let shape = StockShape::Box {
        min: b.min - DVec3::splat(2.0),
        max: b.max + DVec3::splat(2.0),
    };
    let mut s = DexelStock::new(vec![shape], res, DexelMode::Tri, 8 << 30)
        .unwrap_or_else(|e| panic!("{e}"));
    let cpu0 = cpu_seconds();
    let started = Instant::now();
    let report = simulate(
        &mut s,
        &cutter,
        &moves,
        &SimOptions::default(),
        &Progress::new(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let secs = started.elapsed().as_secs_f64();
    #[allow(clippy::cast_precision_loss)]
    let cpu = cpu_note(cpu0, report.moves as f64);
    println!(
        "  tri-dexel {res} mm (removal only): {} moves in {} steps, {secs:.2} s = {:.0} moves/s, \
         removed {:.1} mm³, stock {:.1} MiB, {cpu}",
        report.moves,
        report.steps,
        report.moves as f64 / secs,
        report.removed_volume_mm3,
        report.memory_bytes as f64 / f64::from(1 << 20),
    );
}

/// A hash (FNV-1a over the f64 bits) of what a simulation shows: the stock mesh, the
/// deviations, the collisions and the volumes; equal digests mean bit-identical results.
fn digest(sim: &talas::project::simulate::Simulated) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325_u64;
    let mut eat = |x: u64| {
        for b in x.to_le_bytes() {
            h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    };
    for p in &sim.stock_mesh.positions {
        p.to_array().iter().for_each(|v| eat(v.to_bits()));
    }
    sim.deviation_mm.iter().for_each(|v| eat(v.to_bits()));
    for c in &sim.report.collisions {
        eat(c.move_index as u64);
        eat(c.depth_mm.to_bits());
        c.position.to_array().iter().for_each(|v| eat(v.to_bits()));
    }
    eat(sim.report.removed_volume_mm3.to_bits());
    eat(sim.report.collisions.len() as u64);
    h
}

/// "Stock here" at the last pose as the workstation runs it: before keyframes, the whole path
/// from the start (the workstation figure above); with keyframes, the whole run keeping them,
/// then the stock at the last pose and at the middle one from them.
fn stock_here_at_the_end(
    mesh: &talas::geometry::mesh::TriMesh,
    tp: &Toolpath,
    cutter: &Cutter,
    settings: &talas::project::simulate::SimulationSettings,
) {
    use talas::project::Stock;
    use talas::project::keyframes::{DEFAULT_KEYFRAME_BYTES, simulate_with_keyframes, stock_here};
    let cpu0 = cpu_seconds();
    let started = Instant::now();
    let (whole, frames) = simulate_with_keyframes(
        &Stock::None,
        mesh,
        &[(tp, cutter)],
        settings,
        DEFAULT_KEYFRAME_BYTES,
        &Progress::new(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    #[allow(clippy::cast_precision_loss)]
    let cpu = cpu_note(cpu0, whole.report.moves as f64);
    println!(
        "  whole run keeping keyframes: {:.2} s, {} keyframes, {:.1} MiB, at most {} of {} steps \
         re-cut, removed {:.1} mm³, {cpu}",
        started.elapsed().as_secs_f64(),
        frames.len(),
        frames.memory_bytes() as f64 / f64::from(1 << 20),
        frames.max_gap_steps(),
        whole.report.steps,
        whole.report.removed_volume_mm3,
    );
    let last = tp.poses.len().saturating_sub(1);
    for pose in [last, last / 2] {
        let cpu0 = cpu_seconds();
        let started = Instant::now();
        let here =
            stock_here(&frames, mesh, pose, &Progress::new()).unwrap_or_else(|e| panic!("{e}"));
        let secs = started.elapsed().as_secs_f64();
        #[allow(clippy::cast_precision_loss)]
        let cpu = cpu_note(cpu0, here.report.moves as f64);
        println!(
            "  stock here at pose {pose} from keyframes (deviation included): {secs:.2} s, \
             removed {:.1} mm³, max gouge {:.4} mm, {cpu}",
            here.report.removed_volume_mm3, here.max_gouge_mm,
        );
    }
}

fn main() {
    if std::env::var("TALAS_SIM_BENCH_FIVE").map_or(true, |v| v != "0") {
        five_axis();
    }
    if std::env::var("TALAS_SIM_BENCH_FIVE").is_ok_and(|v| v == "ws") {
        return;
    }
    let moves = std::env::var("TALAS_SIM_BENCH_MOVES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(100_000usize);
    let tp = raster(moves);
    let plan = plan_toolpath(&tp, &StepOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    for res in [0.1, 0.05] {
        full_run(&tp, &plan, res);
    }
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    let short = raster(2_000);
    let short_plan =
        plan_toolpath(&short, &StepOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    for res in [0.1, 0.05] {
        let fresh = stock(res);
        c.bench_function(&format!("simulate 2000 raster moves at {res} mm"), |b| {
            b.iter_batched(
                || fresh.clone(),
                |mut s| {
                    black_box(simulate(
                        &mut s,
                        &short.tool.cutter,
                        &short_plan,
                        &SimOptions::default(),
                        &Progress::new(),
                    ))
                },
                BatchSize::LargeInput,
            );
        });
    }
    c.final_summary();
}
