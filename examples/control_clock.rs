//! What `Control::advance` costs per frame of the operator panel's clock on a real program
//! (issue 36): AUTO of PROGRAM.ngc on `mill-3axis` with a box stock, frames of 1/60 s × the
//! clock factor of simulated time, 1/60 s of wall time apart (the rest of a frame sleeps, as
//! the panel's frames draw), the stock cut in the frame, by the worker paced (the panel's way
//! today: the clock waits for the cutting) or unpaced (the frame waits for it).
//!
//! `cargo run --no-default-features --example control_clock -- PROGRAM.ngc TOOL X0,Y0,Z0,X1,Y1,Z1 [FACTOR [FRAMES]]`

use std::time::Instant;

use talas::control::{Action, Control, ControlConfig, LiveStock, Mode};
use talas::machine::Machine;
use talas::simulation::{DEFAULT_MEMORY_LIMIT_BYTES, DexelMode, DexelStock, StockShape};
use talas::tools::parse_tool_spec;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let (Some(program), Some(tool), Some(boxs)) = (args.get(1), args.get(2), args.get(3)) else {
        eprintln!("usage: control_clock PROGRAM.ngc TOOL X0,Y0,Z0,X1,Y1,Z1 [FACTOR [FRAMES]]");
        std::process::exit(2);
    };
    let factor: f64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(100.0);
    let frames: usize = args.get(5).and_then(|s| s.parse().ok()).unwrap_or(600);
    let text = std::fs::read_to_string(program).expect("program");
    let v: Vec<f64> = boxs.split(',').map(|s| s.parse().expect("box")).collect();
    assert_eq!(v.len(), 6, "box X0,Y0,Z0,X1,Y1,Z1");
    for way in ["in the frame", "worker, paced", "worker, unpaced"] {
        let mut cfg = ControlConfig::new(Machine::builtin("mill-3axis").expect("machine"));
        cfg.home_feed_mm_per_min = 30000.0;
        let stock = DexelStock::new(
            vec![StockShape::Box {
                min: glam::DVec3::new(v[0], v[1], v[2]),
                max: glam::DVec3::new(v[3], v[4], v[5]),
            }],
            0.5,
            DexelMode::Z,
            DEFAULT_MEMORY_LIMIT_BYTES,
        )
        .expect("stock");
        cfg.stock = Some(LiveStock::new(
            stock,
            parse_tool_spec(tool).expect("tool"),
            0.5,
        ));
        let mut c = Control::new(cfg).expect("control");
        c.apply(Action::Home).expect("home");
        c.advance_until_idle(600.0);
        c.apply(Action::SetMode(Mode::Auto)).expect("auto");
        c.apply(Action::LoadProgram {
            name: program.clone(),
            text: text.clone(),
        })
        .expect("load");
        if way != "in the frame" {
            c.start_cutting_worker();
            c.pace_motion_by_cutting(way == "worker, paced");
        }
        c.apply(Action::CycleStart).expect("start");
        let t0 = c.time_s();
        let mut ms = Vec::new();
        for _ in 0..frames {
            if c.is_idle() {
                break;
            }
            let w = Instant::now();
            c.advance(factor / 60.0);
            let took = w.elapsed();
            ms.push(took.as_secs_f64() * 1e3);
            std::thread::sleep(std::time::Duration::from_secs_f64(1.0 / 60.0).saturating_sub(took));
        }
        let n = ms.len().max(1) as f64;
        let mean = ms.iter().sum::<f64>() / n;
        let worst = ms.iter().copied().fold(0.0, f64::max);
        let sim = c.time_s() - t0;
        println!(
            "x{factor} {way}: {} frames, advance mean {mean:.3} ms, worst {worst:.3} ms; \
             {sim:.1} s simulated = {:.1} s per second of 60 fps frames",
            ms.len(),
            sim / (n / 60.0)
        );
    }
}
