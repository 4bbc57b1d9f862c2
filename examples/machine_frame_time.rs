//! Frame time of the virtual machine: the machine's bodies (and a riser and stock on its
//! table) drawn through the workstation's offscreen renderer at 1600 × 1000 while the axes
//! move as in a jog, with the per-frame cost of placing the bodies; then the cost of one
//! frame's `Control::advance` (1/60 s of real time at clock ×10) while AUTO cuts a pocket into
//! a 0.5 mm dexel stock, once cut inside the frame (as the command line does) and once by the
//! cutting worker thread (as the operator panel does), frames 1/60 s apart. Prints mean,
//! median and worst ms, and how much simulated time the frames played.
//!
//! `cargo run --example machine_frame_time [FRAMES]` (software renderer: `WGPU_BACKEND=vulkan`
//! with lavapipe, e.g. under `xvfb-run`).

#[cfg(feature = "gui")]
fn main() {
    measure::run();
}

#[cfg(not(feature = "gui"))]
fn main() {
    eprintln!("machine_frame_time needs the `gui` feature");
}

#[cfg(feature = "gui")]
mod measure {
    use std::time::Instant;

    use glam::DVec3;
    use talas::app::operator_panel::machine_view::{MachineView, machine_sphere};
    use talas::control::{Action, Control, ControlConfig, LiveStock, Mode, collide};
    use talas::machine::{Machine, MachineJoints};
    use talas::render::{Camera, DisplayOptions, OffscreenRenderer, Scene, StandardView};
    use talas::simulation::{DexelMode, DexelStock, StockShape};
    use talas::tools::parse_tool_spec;

    fn stats(label: &str, mut times: Vec<f64>) {
        times.sort_by(f64::total_cmp);
        let mean = times.iter().sum::<f64>() / times.len().max(1) as f64;
        let median = times.get(times.len() / 2).copied().unwrap_or(0.0);
        let worst = times.last().copied().unwrap_or(0.0);
        println!(
            "{label:>34}: {} frames: mean {mean:.2} ms, median {median:.2}, worst {worst:.2}",
            times.len()
        );
    }

    fn draw_machine(renderer: &mut OffscreenRenderer, name: &str, frames: usize) {
        let (w, h) = (1600_u32, 1000_u32);
        let Ok(machine) = Machine::builtin(name) else {
            return;
        };
        let (lo, hi) = (DVec3::new(-40.0, -40.0, -20.0), DVec3::new(40.0, 40.0, 0.0));
        let mut cfg = ControlConfig::new(machine.clone());
        cfg.fixtures.extend(collide::riser_under(&machine, lo, hi));
        let Ok(control) = Control::new(cfg) else {
            return;
        };
        let mut view = MachineView::default();
        let ids = talas::app::feature::RenderIds::default();
        let mut camera = Camera::default();
        let mut place = Vec::new();
        let mut draw = Vec::new();
        for i in 0..frames {
            let u = i as f64 / frames.max(1) as f64;
            let joints = MachineJoints {
                xyz: DVec3::new(200.0 * (u * 6.0).sin(), 150.0 * u, 50.0 - 100.0 * u),
                tilt_rad: -(90.0 * u).to_radians(),
                rotary_rad: (360.0 * u).to_radians(),
            };
            let t = Instant::now();
            let mut meshes = view.instances(&machine, &joints, 120.0, &ids);
            meshes.extend(view.fixture_meshes(control.fixtures(), &ids));
            place.push(t.elapsed().as_secs_f64() * 1e3);
            if i == 0
                && let Some(s) = machine_sphere(&meshes)
            {
                camera.set_view(StandardView::Iso);
                camera.fit(s, w as f32 / h as f32);
            }
            let scene = Scene {
                camera,
                meshes,
                lines: Vec::new(),
                options: DisplayOptions::default(),
            };
            let t = Instant::now();
            if let Err(e) = renderer.draw(w, h, &scene) {
                eprintln!("machine_frame_time: {e}");
                std::process::exit(1);
            }
            draw.push(t.elapsed().as_secs_f64() * 1e3);
        }
        stats(&format!("{name}: place bodies"), place);
        stats(&format!("{name}: draw {w}x{h}"), draw);
    }

    fn advance_per_frame(frames: usize, worker: bool) {
        let Ok(machine) = Machine::builtin("mill-3axis") else {
            return;
        };
        let mut cfg = ControlConfig::new(machine);
        cfg.home_feed_mm_per_min = 30000.0;
        let shape = StockShape::Box {
            min: DVec3::new(-40.0, -40.0, -20.0),
            max: DVec3::new(40.0, 40.0, 0.0),
        };
        let (Ok(stock), Ok(cutter)) = (
            DexelStock::new(vec![shape], 0.5, DexelMode::Z, 1 << 30),
            parse_tool_spec("flat:d=6"),
        ) else {
            return;
        };
        cfg.stock = Some(LiveStock::new(stock, cutter, 0.5));
        let Ok(mut c) = Control::new(cfg) else {
            return;
        };
        if worker {
            c.start_cutting_worker();
            c.pace_motion_by_cutting(true);
        }
        let program = "G90 G0 X-30 Y-30 Z5\nM3 S8000\nG1 Z-3 F600\nG1 X30 F1500\nY-20\nX-30\n\
                       Y-10\nX30\nY0\nX-30\nY10\nX30\nY20\nX-30\nY30\nX30\nG0 Z10\nM30\n";
        let _ = c.apply(Action::Home);
        c.advance_until_idle(60.0);
        let _ = c.apply(Action::SetMode(Mode::Auto));
        let _ = c.apply(Action::LoadProgram {
            name: "pocket".into(),
            text: program.into(),
        });
        let _ = c.apply(Action::CycleStart);
        let mut times = Vec::new();
        let wall = Instant::now();
        let t_start = c.time_s();
        for _ in 0..frames {
            if c.is_idle() {
                break;
            }
            let t = Instant::now();
            c.advance(10.0 / 60.0);
            times.push(t.elapsed().as_secs_f64() * 1e3);
            // The rest of a 60 Hz frame (drawing), in which the worker cuts.
            std::thread::sleep(std::time::Duration::from_secs_f64(1.0 / 60.0));
        }
        let label = if worker {
            "advance, AUTO cut by the worker, x10"
        } else {
            "advance, AUTO cut in the frame, x10"
        };
        println!(
            "{label}: simulated {:.2} s in {:.2} s of frames",
            c.time_s() - t_start,
            wall.elapsed().as_secs_f64()
        );
        stats(label, times);
        if worker {
            c.stop_cutting_worker();
        }
        println!(
            "removed {:.1} mm³, alarms {:?}",
            c.snapshot().removed_volume_mm3,
            c.alarms()
        );
    }

    pub fn run() {
        let frames: usize = std::env::args()
            .nth(1)
            .and_then(|a| a.parse().ok())
            .unwrap_or(60);
        let mut renderer = match OffscreenRenderer::new() {
            Ok(r) => r,
            Err(e) => {
                eprintln!("machine_frame_time: {e}");
                std::process::exit(1);
            }
        };
        println!(
            "adapter: {} ({}x MSAA)",
            renderer.gpu.adapter_description, renderer.gpu.samples
        );
        for name in ["mill-3axis", "trt-ac"] {
            draw_machine(&mut renderer, name, frames);
        }
        advance_per_frame(frames * 10, false);
        advance_per_frame(frames * 10, true);
    }
}
