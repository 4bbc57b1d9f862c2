//! Planning speed: a program of 100 000 short blocks (a raster of 0.05 mm segments with
//! arcs at the row ends), reported as blocks per second.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::fmt::Write as _;
use std::hint::black_box;

use talas::feed::{PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, interpret};
use talas::machine::Machine;

fn program(blocks: usize) -> String {
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

fn bench(c: &mut Criterion) {
    let machine = Machine::builtin("mill-3axis").expect("builtin machine");
    let prog = interpret(&program(100_000), &InterpretOptions::default()).expect("program");
    let axes = machine_limits(&machine);
    let mut group = c.benchmark_group("feed");
    group.sample_size(10);
    group.throughput(Throughput::Elements(prog.blocks.len() as u64));
    group.bench_function("plan_100k_short_blocks", |b| {
        b.iter(|| {
            let input = PlanInput {
                blocks: black_box(&prog.blocks),
                axes: axes.clone(),
                options: PlanOptions::default(),
            };
            plan(&input).map(|tp| tp.cycle_time_s)
        });
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
