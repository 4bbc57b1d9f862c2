//! Planning speed on programs of 100 000 short blocks, reported as blocks per second
//! (criterion's throughput):
//! - `raster_exact`: a raster of collinear 0.05 mm segments with arcs at the row ends (exact
//!   stop at the non-smooth joins);
//! - `curve_blend` / `curve_exact`: a posted-looking free-form curve (a 3-D Lissajous sweep) cut
//!   into segments of 0.01–0.5 mm with small direction changes at every block, planned with
//!   clothoid corner blends (δ = 0.05 mm; every junction gets a blend) and with exact stop.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::fmt::Write as _;
use std::hint::black_box;

use talas::feed::{CornerPolicy, PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, MotionBlock, interpret};
use talas::machine::Machine;

fn raster(blocks: usize) -> String {
    let mut text = String::from("G90 G17 F6000\nG1 X0 Y0 Z0\n");
    let mut n = 1;
    let mut row = 0;
    while n < blocks {
        let y = f64::from(row) * 0.5;
        for i in 0..1000 {
            let x = if row % 2 == 0 {
                f64::from(i + 1) * 0.05
            } else {
                50.0 - f64::from(i + 1) * 0.05
            };
            let z = 0.01 * (x * 0.3).sin();
            let _ = writeln!(text, "G1 X{x:.4} Y{y:.4} Z{z:.4}");
        }
        let (x, dir, i) = if row % 2 == 0 {
            (50.0, 3, 0.0)
        } else {
            (0.0, 2, 0.0)
        };
        let _ = writeln!(text, "G{dir} X{x:.4} Y{:.4} I{i} J0.25", y + 0.5);
        n += 1001;
        row += 1;
    }
    text
}

/// A free-form 3-D curve in blocks of 0.01–0.5 mm (deterministic pseudo-random lengths).
fn curve(blocks: usize) -> String {
    let mut text = String::from("G90 G17 F3000\n");
    let mut state = 1u64;
    let mut u = 0.0f64;
    for _ in 0..blocks {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        let r = (state >> 11) as f64 / (1u64 << 53) as f64;
        // About 0.01–0.5 mm per block along a curve of speed ≈ 60 mm per unit of u.
        u += (0.01 + 0.49 * r) / 60.0;
        let (x, y, z) = (
            40.0 * (1.3 * u).sin(),
            30.0 * (2.1 * u).sin(),
            5.0 * (0.7 * u).cos(),
        );
        let _ = writeln!(text, "G1 X{x:.5} Y{y:.5} Z{z:.5}");
    }
    text
}

/// CPU seconds of this process so far (user + system, from /proc; 0 where unavailable). On a
/// loaded shared machine wall time is noise; CPU time is what the planner costs.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which is in parentheses): utime is the 12th, stime 13th.
    let rest = stat.rsplit(')').next().unwrap_or("");
    let fields: Vec<f64> = rest
        .split_whitespace()
        .map(|f| f.parse().unwrap_or(0.0))
        .collect();
    let ticks = fields.get(11).copied().unwrap_or(0.0) + fields.get(12).copied().unwrap_or(0.0);
    ticks / 100.0
}

fn bench_one(c: &mut Criterion, name: &str, blocks: &[MotionBlock], corner: CornerPolicy) {
    let machine = Machine::builtin("mill-3axis").expect("builtin machine");
    let axes = machine_limits(&machine);
    let input = PlanInput {
        blocks,
        axes: axes.clone(),
        options: PlanOptions {
            corner,
            ..PlanOptions::default()
        },
    };
    let (t0, mut runs) = (cpu_seconds(), 0);
    let mut segments = 0;
    while cpu_seconds() - t0 < 3.0 && runs < 200 {
        segments = plan(black_box(&input)).map_or(0, |tp| tp.block_count());
        runs += 1;
    }
    let cpu = (cpu_seconds() - t0) / f64::from(runs);
    eprintln!(
        "feed/{name}: {} blocks ({segments} segments) in {:.1} ms CPU per plan: {:.0} blocks per \
         CPU second",
        blocks.len(),
        cpu * 1e3,
        blocks.len() as f64 / cpu
    );
    let mut group = c.benchmark_group("feed");
    group.sample_size(10);
    group.throughput(Throughput::Elements(blocks.len() as u64));
    group.bench_function(name, |b| {
        b.iter(|| {
            let input = PlanInput {
                blocks: black_box(blocks),
                axes: axes.clone(),
                options: PlanOptions {
                    corner,
                    ..PlanOptions::default()
                },
            };
            plan(&input).map(|tp| tp.cycle_time_s)
        });
    });
    group.finish();
}

fn bench(c: &mut Criterion) {
    let opts = InterpretOptions::default();
    let r = interpret(&raster(100_000), &opts).expect("raster");
    let k = interpret(&curve(100_000), &opts).expect("curve");
    let blend = CornerPolicy::Blend { tolerance_mm: 0.05 };
    bench_one(c, "raster_exact_100k", &r.blocks, CornerPolicy::ExactStop);
    bench_one(c, "curve_blend_100k", &k.blocks, blend);
    bench_one(c, "curve_exact_100k", &k.blocks, CornerPolicy::ExactStop);
}

criterion_group!(benches, bench);
criterion_main!(benches);
