//! Planning speed on programs of 100 000 short blocks, reported as blocks per second
//! (criterion's throughput):
//! - `raster_exact`: a raster of collinear 0.05 mm segments with arcs at the row ends (exact
//!   stop at the non-smooth joins);
//! - `curve_blend` / `curve_exact`: a posted-looking free-form curve (a 3-D Lissajous sweep) cut
//!   into segments of 0.01–0.5 mm with small direction changes at every block, planned with
//!   clothoid corner blends (δ = 0.05 mm; every junction gets a blend) and with exact stop.
//!
//! With `FEED_DIGEST=1` in the environment it instead prints four hashes of everything the
//! planner outputs (every segment's geometry, limits and cap, every profile's phases and span,
//! states sampled across the cycle, the peaks) over 1 500 random programs, the thesis programs
//! in `tests/data/gcode` and 20 000-block versions of the two bench programs, each under exact
//! stop, junction deviation and blends of 0.05 and 1 mm: two builds that print the same hashes
//! plan the same, bit for bit. Run it from the repository root (the thesis programs are read
//! from there): `FEED_DIGEST=1 cargo bench --no-default-features --bench feed`.
//! `FEED_ONLY=curve_blend` times only the programs whose name contains it. `FEED_VALUES=<file>`
//! with `FEED_DIGEST=1` also writes every hashed value to the file (compare two builds' files
//! with `benches/feed_values_diff.py`).

use criterion::{Criterion, Throughput, criterion_group};
use std::fmt::Write as _;
use std::hint::black_box;

/// The `talas` binary's allocator (src/main.rs), so that these figures are the binary's.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

use talas::feed::{AxisLimit, CornerPolicy, Limits1, PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, Joints, MotionBlock, interpret};
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
    // `FEED_ONLY=curve_blend` runs only the programs whose name contains it (for profiling).
    if let Some(only) = std::env::var_os("FEED_ONLY")
        && !name.contains(only.to_string_lossy().as_ref())
    {
        return;
    }
    let machine = Machine::builtin("mill-3axis").expect("builtin machine");
    let axes = machine_limits(&machine);
    // The CPU figure counts the input built from the interpreter's blocks (one copy into the
    // shared `Arc`, as `project::run` and the CLI pay it) with every plan; criterion's figure
    // below shares one input's blocks across its plans (a caller that replans one program).
    let shared: std::sync::Arc<[MotionBlock]> = blocks.into();
    let (t0, mut runs) = (cpu_seconds(), 0);
    let mut segments = 0;
    while cpu_seconds() - t0 < 3.0 && runs < 200 {
        let input = PlanInput {
            blocks: black_box(blocks).into(),
            axes: axes.clone(),
            options: PlanOptions {
                corner,
                ..PlanOptions::default()
            },
        };
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
                blocks: black_box(std::sync::Arc::clone(&shared)),
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

/// With `FEED_VALUES=<file>` (and `FEED_DIGEST=1`) every value hashed is also written to the
/// file, one per line (`f <value>`, `u <integer>`, `s <text>`, `plan` between plans), so that
/// two builds' outputs can be compared value by value where their digests differ.
static VALUES: std::sync::Mutex<Option<std::io::BufWriter<std::fs::File>>> =
    std::sync::Mutex::new(None);

fn record(line: std::fmt::Arguments<'_>) {
    use std::io::Write as _;
    if let Some(w) = VALUES.lock().unwrap().as_mut() {
        w.write_fmt(line).unwrap();
    }
}

/// FNV-1a over the bits of what the planner outputs.
struct H(u64);

impl H {
    fn f(&mut self, x: f64) {
        record(format_args!("f {x:e}\n"));
        self.hash(x.to_bits());
    }
    fn u(&mut self, x: u64) {
        record(format_args!("u {x}\n"));
        self.hash(x);
    }
    fn hash(&mut self, x: u64) {
        for b in x.to_le_bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x100000001b3);
        }
    }
    fn s(&mut self, s: &str) {
        record(format_args!("s {s}\n"));
        for b in s.bytes() {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x100000001b3);
        }
    }
}

/// The bench's LCG as uniform numbers in [0, 1).
struct Rng(u64);
impl Rng {
    fn f(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A short random program: lines long and short, reversals, dense runs, rapids, arcs and
/// helices, and rotary moves when `rot`.
fn random_program(r: &mut Rng, rot: bool) -> String {
    let mut text = String::from("G90 G17 F3000\n");
    let (mut x, mut y, mut z, mut a) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let n = 2 + (r.f() * 12.0) as usize;
    for _ in 0..n {
        let kind = r.f();
        if kind < 0.35 {
            let scale = if r.f() < 0.4 { 0.05 } else { 15.0 };
            x += (r.f() - 0.5) * scale;
            y += (r.f() - 0.5) * scale;
            z += (r.f() - 0.5) * scale * 0.3;
            if rot && r.f() < 0.5 {
                a += (r.f() - 0.5) * 20.0;
                text += &format!(
                    "G1 X{x:.4} Y{y:.4} Z{z:.4} A{a:.3} F{:.0}\n",
                    300.0 + r.f() * 20_000.0
                );
            } else {
                text += &format!(
                    "G1 X{x:.4} Y{y:.4} Z{z:.4} F{:.0}\n",
                    300.0 + r.f() * 20_000.0
                );
            }
        } else if kind < 0.45 {
            let (dx, dy) = ((r.f() - 0.5) * 4.0, (r.f() - 0.5) * 4.0);
            text += &format!("G1 X{:.4} Y{:.4}\nG1 X{x:.4} Y{y:.4}\n", x + dx, y + dy);
        } else if kind < 0.55 {
            let (dx, dy) = ((r.f() - 0.5) * 0.02, (r.f() - 0.5) * 0.02);
            for _ in 0..20 {
                x += dx;
                y += dy;
                text += &format!("G1 X{x:.6} Y{y:.6}\n");
            }
        } else if kind < 0.75 {
            let len = if r.f() < 0.3 {
                0.02 + r.f() * 0.3
            } else {
                1.0 + r.f() * 20.0
            };
            let d = [
                r.f() - 0.5,
                r.f() - 0.5,
                if r.f() < 0.6 { 0.0 } else { r.f() - 0.5 },
            ];
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
            x += d[0] / l * len;
            y += d[1] / l * len;
            z += d[2] / l * len;
            text += &format!("G1 X{x:.6} Y{y:.6} Z{z:.6}\n");
        } else if kind < 0.78 {
            text += "G0 X0 Y0 Z5\n";
            x = 0.0;
            y = 0.0;
            z = 5.0;
        } else {
            let rad = 0.2 + r.f() * 10.0;
            let ang = r.f() * std::f64::consts::TAU;
            let (i, j) = (rad * ang.cos(), rad * ang.sin());
            let sweep = (r.f() - 0.5) * 5.0;
            let (cx, cy) = (x + i, y + j);
            let a1 = ang + std::f64::consts::PI + sweep;
            x = cx + rad * a1.cos();
            y = cy + rad * a1.sin();
            let g = if sweep < 0.0 { 2 } else { 3 };
            let dz = if r.f() < 0.3 { r.f() - 0.5 } else { 0.0 };
            z += dz;
            text += &format!("G{g} X{x:.6} Y{y:.6} Z{z:.6} I{i:.6} J{j:.6}\n");
        }
    }
    text
}

/// Hash every output of the plans of `text` under the four corner policies.
fn digest(
    h: &mut H,
    text: &str,
    start: Joints,
    axes: &[(char, AxisLimit)],
    path_limits: Option<Limits1>,
    samples: usize,
) {
    let opts = InterpretOptions {
        start,
        ..InterpretOptions::default()
    };
    let Ok(prog) = interpret(text, &opts) else {
        h.s("interp-err");
        return;
    };
    for corner in [
        CornerPolicy::ExactStop,
        CornerPolicy::JunctionDeviation { tolerance_mm: 0.01 },
        CornerPolicy::Blend { tolerance_mm: 0.05 },
        CornerPolicy::Blend { tolerance_mm: 1.0 },
    ] {
        let input = PlanInput {
            blocks: prog.blocks.as_slice().into(),
            axes: axes.to_vec(),
            options: PlanOptions {
                corner,
                path_limits,
                ..PlanOptions::default()
            },
        };
        record(format_args!("plan\n"));
        match plan(&input) {
            Err(e) => h.s(&format!("{e}")),
            Ok(tp) => {
                h.f(tp.cycle_time_s);
                h.u(tp.block_count() as u64);
                for (k, s) in tp.segments().iter().enumerate() {
                    h.u(s.block as u64);
                    h.f(s.length);
                    h.f(s.limits.velocity);
                    h.f(s.limits.acceleration);
                    h.f(s.limits.jerk);
                    h.s(&format!("{:?}", s.cap));
                    for u in [0.0, 0.37, 1.0] {
                        for d in s.derivatives(u * s.length) {
                            for x in d {
                                h.f(x);
                            }
                        }
                    }
                    for t in s.tangent(false).iter().chain(s.tangent(true).iter()) {
                        h.f(*t);
                    }
                    let p = tp.profile(k).unwrap();
                    h.f(p.distance);
                    h.f(p.peak_velocity);
                    h.f(p.duration_s());
                    for ph in p.phases {
                        h.f(ph.duration_s);
                        h.f(ph.jerk);
                        h.f(ph.s0);
                        h.f(ph.v0);
                        h.f(ph.a0);
                    }
                    let (a, b) = tp.segment_span_s(k).unwrap();
                    h.f(a);
                    h.f(b);
                }
                let n = samples;
                for i in 0..=n {
                    let smp = tp.state_at(tp.cycle_time_s * i as f64 / n as f64 * 1.01 - 0.001);
                    h.f(smp.t);
                    h.u(smp.block as u64);
                    h.f(smp.path_position);
                    h.f(smp.feed);
                    for v in [smp.position, smp.velocity, smp.acceleration, smp.jerk] {
                        for x in v {
                            h.f(x);
                        }
                    }
                    h.s(&format!("{:?}", smp.active));
                }
                if tp.cycle_time_s < 5.0 {
                    for p in tp.peaks() {
                        h.f(p.velocity);
                        h.f(p.acceleration);
                        h.f(p.jerk);
                    }
                }
            }
        }
    }
}

/// Print the four digests (random programs, thesis programs, curve, raster).
fn digest_all() {
    if let Some(path) = std::env::var_os("FEED_VALUES") {
        let file = std::fs::File::create(path).expect("FEED_VALUES names a writable file");
        *VALUES.lock().unwrap() = Some(std::io::BufWriter::new(file));
    }
    let m3 = machine_limits(&Machine::builtin("mill-3axis").unwrap());
    let m5 = machine_limits(&Machine::builtin("trt-ac").unwrap());
    let mut rng = Rng(7);
    let mut h = H(0xcbf29ce484222325);
    for case in 0..1500 {
        let rot = case % 3 == 0;
        let text = random_program(&mut rng, rot);
        let pl = if case % 5 == 0 {
            Some(Limits1 {
                velocity: 50.0,
                acceleration: 500.0,
                jerk: 20000.0,
            })
        } else {
            None
        };
        digest(
            &mut h,
            &text,
            Joints::default(),
            if rot { &m5 } else { &m3 },
            pl,
            50,
        );
    }
    println!("random: {:016x}", h.0);
    let mut h = H(0xcbf29ce484222325);
    let mut files: Vec<_> = std::fs::read_dir("tests/data/gcode")
        .expect("run from the repository root")
        .map(|e| e.expect("directory entry").path())
        .collect();
    files.sort();
    for p in files {
        let text = std::fs::read_to_string(&p).unwrap();
        digest(&mut h, &text, Joints::default(), &m3, None, 200);
        digest(
            &mut h,
            &text,
            Joints::xyz(0.2407, 1.533, 0.0),
            &m3,
            Some(Limits1 {
                velocity: 1e6,
                acceleration: 1000.0,
                jerk: 20000.0,
            }),
            200,
        );
    }
    println!("thesis: {:016x}", h.0);
    let mut h = H(0xcbf29ce484222325);
    digest(&mut h, &curve(20_000), Joints::default(), &m3, None, 20_000);
    println!("curve: {:016x}", h.0);
    let mut h = H(0xcbf29ce484222325);
    digest(
        &mut h,
        &raster(12_000),
        Joints::default(),
        &m3,
        None,
        20_000,
    );
    println!("raster: {:016x}", h.0);
    if let Some(mut w) = VALUES.lock().unwrap().take() {
        use std::io::Write as _;
        w.flush().unwrap();
    }
}

fn main() {
    if std::env::var_os("FEED_DIGEST").is_some() {
        digest_all();
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
