#!/usr/bin/env bash
# Peer comparison of the stock simulation: Talas (dexels) and cutrail (mesh booleans, from
# crates.io) on the same finishing raster (6 mm ball, bumpy surface, as in
# benches/simulation.rs), in one process. Builds a scratch crate outside the repository so
# that cutrail never enters Talas's own dependencies.
#
#   benches/simulation_peer.sh [MOVES_FOR_CUTRAIL=2000] [MOVES_FOR_TALAS=100000]
#
# Prints ms per move and the removed volume of both on the first MOVES_FOR_CUTRAIL moves (the
# volumes cross-check each other), and Talas on the whole program.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
peer_moves="${1:-2000}"
talas_moves="${2:-100000}"
work="${TMPDIR:-/tmp}/talas-sim-peer"
mkdir -p "$work/src"
cat > "$work/Cargo.toml" <<TOML
[package]
name = "talas-sim-peer"
version = "0.0.0"
edition = "2024"
publish = false

[dependencies]
talas = { path = "$here", default-features = false }
cutrail = "0.1"
glam = "0.33"

[profile.release]
debug = false
TOML
cat > "$work/src/main.rs" <<'RS'
use std::time::Instant;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::simulation::{
    DexelMode, DexelStock, SimOptions, StepOptions, StockShape, plan_toolpath, simulate,
};
use talas::toolpath::{MoveKind, Pose, ToolRecord, Toolpath};
use talas::tools::{Cutter, CutterKind};

fn surface(x: f64, y: f64) -> f64 {
    1.5 * (x / 6.0).sin() * (y / 8.0).cos() + 0.5 * (x * y / 150.0).sin()
}

fn raster(moves: usize) -> Vec<DVec3> {
    let lines = 200usize;
    let per_line = moves.div_ceil(lines).max(2);
    let mut pts = vec![DVec3::new(0.0, 0.0, 10.0)];
    for j in 0..lines {
        let y = 60.0 * j as f64 / (lines - 1) as f64;
        for k in 0..per_line {
            let t = k as f64 / (per_line - 1) as f64;
            let x = if j % 2 == 0 { 60.0 * t } else { 60.0 * (1.0 - t) };
            pts.push(DVec3::new(x, y, surface(x, y)));
        }
    }
    pts
}

fn talas_run(pts: &[DVec3], res: f64) -> (f64, f64, usize) {
    let cutter = Cutter::new(CutterKind::Ball, 6.0).expect("cutter");
    let poses = pts
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let kind = if k == 0 { MoveKind::Rapid } else { MoveKind::Cut };
            Pose::new(kind, *p, DVec3::Z, 3000.0)
        })
        .collect();
    let tp = Toolpath::new(ToolRecord { spec: "ball:d=6".into(), cutter: cutter.clone() }, poses);
    let plan = plan_toolpath(&tp, &StepOptions::default()).expect("plan");
    let mut stock = DexelStock::new(
        vec![StockShape::Box { min: DVec3::new(-4.0, -4.0, -5.0), max: DVec3::new(64.0, 64.0, 3.0) }],
        res,
        DexelMode::Z,
        8 << 30,
    )
    .expect("stock");
    let t = Instant::now();
    let r = simulate(&mut stock, &cutter, &plan, &SimOptions::default(), &Progress::new())
        .expect("simulate");
    (t.elapsed().as_secs_f64(), r.removed_volume_mm3, plan.moves.len())
}

fn main() {
    let args: Vec<usize> = std::env::args().skip(1).filter_map(|a| a.parse().ok()).collect();
    let peer_moves = args.first().copied().unwrap_or(2000);
    let talas_moves = args.get(1).copied().unwrap_or(100_000);
    let full = raster(talas_moves);
    let short: Vec<DVec3> = full.iter().take(peer_moves + 1).copied().collect();
    for res in [0.1, 0.05] {
        let (s, v, n) = talas_run(&short, res);
        println!("talas   {res} mm: {n} moves, {:.4} ms/move, removed {v:.2} mm3", 1000.0 * s / n as f64);
    }
    // cutrail: 10 mm tiles, as in its README's 100 000-segment measurement.
    let stock = cutrail::StockShape::Box { min: [-4.0, -4.0, -5.0], max: [64.0, 64.0, 3.0] };
    let mut engine = cutrail::Engine::new(
        cutrail::ManifoldKernel,
        &[stock],
        cutrail::EngineOptions::default().with_tile_size(10.0),
    )
    .expect("cutrail engine");
    let v0 = engine.total_volume();
    let tool = cutrail::Tool::ball_end_mill(6.0, 18.0);
    let t = Instant::now();
    let mut n = 0usize;
    for w in short.windows(2) {
        let seg = cutrail::MotionSegment::linear(
            cutrail::Pose::vertical(w[0].to_array()),
            cutrail::Pose::vertical(w[1].to_array()),
        );
        engine.cut(&tool, &seg).expect("cutrail cut");
        n += 1;
    }
    let s = t.elapsed().as_secs_f64();
    println!(
        "cutrail       : {n} moves, {:.4} ms/move, removed {:.2} mm3",
        1000.0 * s / n as f64,
        v0 - engine.total_volume()
    );
    for res in [0.1, 0.05] {
        let (s, v, n) = talas_run(&full, res);
        println!(
            "talas   {res} mm: whole program {n} moves in {s:.2} s = {:.0} moves/s, removed {v:.2} mm3",
            n as f64 / s
        );
    }
}
RS
cd "$work"
cargo run --release --quiet -- "$peer_moves" "$talas_moves"
