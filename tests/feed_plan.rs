//! Planner: randomised programs hold every axis limit (finite differences at 0.1 ms), end
//! exactly at the program's end point; the thesis programs plan, V8/V9 durations.

mod common;

use common::Lcg;
use talas::feed::{AxisLimit, CornerPolicy, Limits1, PlanInput, PlanOptions, machine_limits, plan};
use talas::gcode::{InterpretOptions, Joints, interpret};
use talas::machine::Machine;

fn random_program(r: &mut Lcg) -> String {
    let mut text = String::from("G90 G17 F3000\n");
    let (mut x, mut y, mut z) = (0.0f64, 0.0f64, 0.0f64);
    let n = 2 + (r.next() * 8.0) as usize;
    for _ in 0..n {
        let kind = r.next();
        if kind < 0.35 {
            let scale = if r.next() < 0.4 { 0.05 } else { 15.0 };
            x += (r.next() - 0.5) * scale;
            y += (r.next() - 0.5) * scale;
            z += (r.next() - 0.5) * scale * 0.3;
            text += &format!(
                "G1 X{x:.4} Y{y:.4} Z{z:.4} F{:.0}\n",
                300.0 + r.next() * 20_000.0
            );
        } else if kind < 0.5 {
            // A reversal: out and back.
            let (dx, dy) = ((r.next() - 0.5) * 4.0, (r.next() - 0.5) * 4.0);
            text += &format!("G1 X{:.4} Y{:.4}\nG1 X{x:.4} Y{y:.4}\n", x + dx, y + dy);
        } else if kind < 0.65 {
            // A run of collinear short segments.
            let (dx, dy) = ((r.next() - 0.5) * 0.02, (r.next() - 0.5) * 0.02);
            for _ in 0..20 {
                x += dx;
                y += dy;
                text += &format!("G1 X{x:.6} Y{y:.6}\n");
            }
        } else {
            let rad = 0.2 + r.next() * 10.0;
            let ang = r.next() * std::f64::consts::TAU;
            let (i, j) = (rad * ang.cos(), rad * ang.sin());
            let sweep = (r.next() - 0.5) * 5.0;
            let (cx, cy) = (x + i, y + j);
            let a1 = ang + std::f64::consts::PI + sweep;
            x = cx + rad * a1.cos();
            y = cy + rad * a1.sin();
            let g = if sweep < 0.0 { 2 } else { 3 };
            let dz = if r.next() < 0.3 { r.next() - 0.5 } else { 0.0 };
            z += dz;
            text += &format!("G{g} X{x:.6} Y{y:.6} Z{z:.6} I{i:.6} J{j:.6}\n");
        }
    }
    text
}

#[test]
fn random_programs_hold_axis_limits() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let axes = machine_limits(&machine);
    let mut rng = Lcg(7);
    let h = 1e-4;
    let mut worst = [0.0f64; 3];
    for case in 0..1000 {
        let text = random_program(&mut rng);
        let prog = interpret(&text, &InterpretOptions::default()).unwrap();
        let input = PlanInput {
            blocks: prog.blocks.as_slice().into(),
            axes: axes.clone(),
            options: PlanOptions::default(),
        };
        let tp = plan(&input).unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
        let end = tp.state_at(tp.cycle_time_s + 1.0).position;
        let last = prog.blocks.last().unwrap().end;
        assert_eq!(&end[..3], &last.xyz.to_array()[..], "case {case}");
        let p = |t: f64| tp.state_at(t).position;
        let steps = (tp.cycle_time_s / h).ceil() as usize;
        for i in 0..=steps {
            let t = i as f64 * h;
            let (pm2, pm1, p0, p1, p2) = (p(t - 2.0 * h), p(t - h), p(t), p(t + h), p(t + 2.0 * h));
            for (k, (_, l)) in axes.iter().enumerate() {
                let v = (p1[k] - pm1[k]) / (2.0 * h);
                let a = (p1[k] - 2.0 * p0[k] + pm1[k]) / (h * h);
                let j = (p2[k] - 2.0 * p1[k] + 2.0 * pm1[k] - pm2[k]) / (2.0 * h * h * h);
                let ratios = [
                    v.abs() / l.velocity,
                    a.abs() / l.acceleration,
                    j.abs() / l.jerk,
                ];
                for (w, r) in worst.iter_mut().zip(ratios) {
                    *w = w.max(r);
                }
                assert!(
                    ratios.iter().all(|r| *r <= 1.001),
                    "case {case} t {t} axis {k}: v {v} a {a} j {j}\n{text}"
                );
            }
        }
    }
    eprintln!("worst v/a/j ratios over 1000 programs: {worst:?}");
}

fn thesis(name: &str, start: Joints) -> f64 {
    let text = std::fs::read_to_string(format!("tests/data/gcode/{name}")).unwrap();
    let opts = InterpretOptions {
        start,
        ..InterpretOptions::default()
    };
    let prog = interpret(&text, &opts).unwrap();
    let big = AxisLimit {
        velocity: 1e6,
        acceleration: 1e9,
        jerk: 1e12,
    };
    let input = PlanInput {
        blocks: prog.blocks.as_slice().into(),
        axes: vec![('X', big), ('Y', big), ('Z', big)],
        options: PlanOptions {
            path_limits: Some(Limits1 {
                velocity: 1e6,
                acceleration: 1000.0,
                jerk: 20_000.0,
            }),
            ..PlanOptions::default()
        },
    };
    plan(&input).unwrap().cycle_time_s
}

#[test]
fn thesis_single_line_and_arc() {
    let t8 = thesis("seed-001-eq3-17-g01-single.nc", Joints::default());
    let t9 = thesis(
        "seed-001-eq3-25-g02-single.nc",
        Joints::xyz(0.2407, 1.533, 0.0),
    );
    eprintln!("V8 line: {t8:.5} s (thesis 0.63852), V9 arc: {t9:.5} s (thesis 0.37853)");
    assert!(t8 <= 0.63852 + 5e-6, "{t8}");
    assert!(t9 <= 0.37853 + 5e-6, "{t9}");
}

#[test]
fn thesis_programs_plan() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    for entry in std::fs::read_dir("tests/data/gcode").unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        // The pocket fragment needs a start the thesis does not give (the interpreter rejects
        // its first R arc from any header start), so it is left to the gcode tests.
        if !name.starts_with("seed-001-") || name.contains("fig4-36") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let opts = InterpretOptions {
            start: header_start(&text),
            ..InterpretOptions::default()
        };
        let prog = interpret(&text, &opts).unwrap_or_else(|e| panic!("{name}: {e}"));
        let input = PlanInput {
            blocks: prog.blocks.as_slice().into(),
            axes: machine_limits(&machine),
            options: PlanOptions::default(),
        };
        let tp = plan(&input).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            tp.cycle_time_s.is_finite() && tp.cycle_time_s > 0.0,
            "{name}"
        );
    }
}

/// The start position from a header comment `(Initial position X.. Y.. Z..` (0 otherwise).
fn header_start(text: &str) -> Joints {
    let mut p = [0.0; 3];
    if let Some(i) = text.find("nitial position") {
        let rest = &text[i + 15..];
        let rest = &rest[..rest.find(')').unwrap_or(rest.len())];
        for word in rest.split_whitespace() {
            let w = word.trim_end_matches([',', '.']);
            let k = match w.chars().next() {
                Some('X') => 0,
                Some('Y') => 1,
                Some('Z') => 2,
                _ => continue,
            };
            if let Ok(v) = w[1..].parse() {
                p[k] = v;
            }
        }
    }
    Joints::xyz(p[0], p[1], p[2])
}

/// Lines with sharp corners (random turns in 3-D, some reversals, some collinear runs and
/// very short moves).
fn corner_program(r: &mut Lcg) -> String {
    let mut text = String::from("G90 G17 F6000\n");
    let (mut x, mut y, mut z) = (0.0f64, 0.0f64, 0.0f64);
    let n = 3 + (r.next() * 8.0) as usize;
    let mut dir = [1.0f64, 0.0, 0.0];
    for _ in 0..n {
        let kind = r.next();
        let len = if r.next() < 0.3 {
            0.02 + r.next() * 0.3
        } else {
            1.0 + r.next() * 20.0
        };
        if kind < 0.1 {
            dir = [-dir[0], -dir[1], -dir[2]];
        } else if kind < 0.2 {
            // Collinear continuation.
        } else {
            let flat = r.next() < 0.6;
            let d = [
                r.next() - 0.5,
                r.next() - 0.5,
                if flat { 0.0 } else { r.next() - 0.5 },
            ];
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-3);
            dir = [d[0] / l, d[1] / l, d[2] / l];
        }
        x += dir[0] * len;
        y += dir[1] * len;
        z += dir[2] * len;
        let feed = if r.next() < 0.5 {
            6000.0
        } else {
            300.0 + r.next() * 30_000.0
        };
        text += &format!("G1 X{x:.6} Y{y:.6} Z{z:.6} F{feed:.0}\n");
    }
    text
}

fn point_segment_distance(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let ap = [p[0] - a[0], p[1] - a[1], p[2] - a[2]];
    let ll = ab.iter().map(|x| x * x).sum::<f64>();
    let t = if ll > 0.0 {
        (ab.iter().zip(&ap).map(|(u, v)| u * v).sum::<f64>() / ll).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (0..3)
        .map(|k| (ap[k] - t * ab[k]).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn blended_corners_hold_limits_and_tolerance() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let axes = machine_limits(&machine);
    let tol = 0.05;
    let mut rng = Lcg(11);
    let h = 1e-4;
    let mut worst = [0.0f64; 3];
    let mut worst_dev = 0.0f64;
    let (mut t_blend, mut t_stop) = (0.0, 0.0);
    let mut blends = 0;
    for case in 0..300 {
        let text = corner_program(&mut rng);
        let prog = interpret(&text, &InterpretOptions::default()).unwrap();
        let mut input = PlanInput {
            blocks: prog.blocks.as_slice().into(),
            axes: axes.clone(),
            options: PlanOptions {
                corner: CornerPolicy::Blend { tolerance_mm: tol },
                ..PlanOptions::default()
            },
        };
        let tp = plan(&input).unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
        blends += tp.segments().iter().filter(|s| s.blend().is_some()).count();
        input.options.corner = CornerPolicy::ExactStop;
        let stop = plan(&input).unwrap().cycle_time_s;
        assert!(
            tp.cycle_time_s <= stop * (1.0 + 1e-12),
            "case {case}: {} > {stop}\n{text}",
            tp.cycle_time_s
        );
        t_blend += tp.cycle_time_s;
        t_stop += stop;
        let end = tp.state_at(tp.cycle_time_s + 1.0).position;
        let last = prog.blocks.last().unwrap().end;
        assert_eq!(&end[..3], &last.xyz.to_array()[..], "case {case}");
        // Positions on a grid from −2h to the end + 2h, then central differences.
        let steps = (tp.cycle_time_s / h).ceil() as usize;
        let samples: Vec<_> = (0..steps + 5)
            .map(|i| tp.state_at((i as f64 - 2.0) * h))
            .collect();
        // A sample's block is the first of a run merged into one line: the run's blocks
        // follow it.
        let run = tp
            .segments()
            .iter()
            .map(|g| g.last_block - g.block)
            .max()
            .unwrap_or(0);
        for i in 2..steps + 3 {
            let s = &samples[i];
            // Distance from the programmed polyline (the blocks around the sample's block).
            let p = [s.position[0], s.position[1], s.position[2]];
            let dev = (s.block.saturating_sub(1)..(s.block + 2 + run).min(prog.blocks.len()))
                .map(|b| {
                    let blk = &prog.blocks[b];
                    point_segment_distance(p, blk.start.xyz.to_array(), blk.end.xyz.to_array())
                })
                .fold(f64::INFINITY, f64::min);
            worst_dev = worst_dev.max(dev);
            assert!(
                dev <= tol + 1e-9,
                "case {case} t {}: deviation {dev}\n{text}",
                s.t
            );
            let q = |j: usize, k: usize| samples[j].position[k];
            for (k, (_, l)) in axes.iter().enumerate() {
                let v = (q(i + 1, k) - q(i - 1, k)) / (2.0 * h);
                let a = (q(i + 1, k) - 2.0 * q(i, k) + q(i - 1, k)) / (h * h);
                let j = (q(i + 2, k) - 2.0 * q(i + 1, k) + 2.0 * q(i - 1, k) - q(i - 2, k))
                    / (2.0 * h * h * h);
                let ratios = [
                    v.abs() / l.velocity,
                    a.abs() / l.acceleration,
                    j.abs() / l.jerk,
                ];
                for (w, r) in worst.iter_mut().zip(ratios) {
                    *w = w.max(r);
                }
                assert!(
                    ratios.iter().all(|r| *r <= 1.001),
                    "case {case} t {} axis {k}: v {v} a {a} j {j}\n{text}",
                    s.t
                );
            }
        }
    }
    eprintln!(
        "300 corner programs, {blends} blends: worst v/a/j ratios {worst:?}, worst deviation \
         {worst_dev:.6} mm (δ {tol}), cycle time blend/exact stop {:.4}",
        t_blend / t_stop
    );
    assert!(blends > 150);
    assert!(t_blend < t_stop);
}

/// Regular polygons of 5 mm sides at F6000 (turns of 10°, 30°, 60°, 90°, 120°): blending
/// against exact stop, all limits held (peaks at 1 ms against the machine's limits).
#[test]
fn blending_beats_exact_stop_on_polygons() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let axes = machine_limits(&machine);
    let mut report = String::new();
    for sides in [36usize, 12, 6, 4, 3] {
        let mut text = String::from("G90 G17 F6000\n");
        let r = 2.5 / (std::f64::consts::PI / sides as f64).sin();
        // Three laps so that corners dominate.
        for i in 1..=3 * sides {
            let a = std::f64::consts::TAU * i as f64 / sides as f64;
            text += &format!("G1 X{:.9} Y{:.9}\n", r * a.cos() - r, r * a.sin());
        }
        let prog = interpret(&text, &InterpretOptions::default()).unwrap();
        let times: Vec<f64> = [
            CornerPolicy::ExactStop,
            CornerPolicy::Blend { tolerance_mm: 0.05 },
            CornerPolicy::Blend { tolerance_mm: 0.01 },
        ]
        .iter()
        .map(|c| {
            let input = PlanInput {
                blocks: prog.blocks.as_slice().into(),
                axes: axes.clone(),
                options: PlanOptions {
                    corner: *c,
                    ..PlanOptions::default()
                },
            };
            let tp = plan(&input).unwrap();
            for p in tp.peaks() {
                let l = axes.iter().find(|(n, _)| *n == p.axis).unwrap().1;
                assert!(
                    p.velocity <= l.velocity * 1.001 && p.acceleration <= l.acceleration * 1.001
                );
                assert!(p.jerk <= l.jerk * 1.001, "{sides}: {p:?}");
            }
            tp.cycle_time_s
        })
        .collect();
        let turn = 360 / sides;
        report += &format!(
            "turn {turn}°: exact {:.3} s, blend δ 0.05 {:.3} s (ratio {:.3}), δ 0.01 ratio {:.3}\n",
            times[0],
            times[1],
            times[1] / times[0],
            times[2] / times[0]
        );
        assert!(times[1] <= times[0] && times[2] <= times[0], "{report}");
        if turn <= 10 {
            assert!(times[1] < 0.8 * times[0], "{report}");
        }
    }
    eprintln!("{report}");
}

/// A run of 3000 very short blocks (0.01–0.5 mm) along a free-form 3-D curve, as a posted
/// 5-axis or raster program gives: it plans with blends and with exact stop, every block ends
/// at the speed the next one starts with (the look-ahead's speeds are all reachable under the
/// jerk limit), and every axis holds its limits (finite differences at 0.1 ms).
#[test]
fn short_block_runs_reach_their_planned_speeds() {
    let machine = Machine::builtin("mill-3axis").unwrap();
    let axes = machine_limits(&machine);
    let mut rng = Lcg(5);
    let mut text = String::from("G90 G17 F3000\n");
    let mut u = 0.0f64;
    for _ in 0..3000 {
        u += (0.01 + 0.49 * rng.next()) / 60.0;
        let (x, y, z) = (
            40.0 * (1.3 * u).sin(),
            30.0 * (2.1 * u).sin(),
            5.0 * (0.7 * u).cos(),
        );
        text += &format!("G1 X{x:.5} Y{y:.5} Z{z:.5}\n");
    }
    let prog = interpret(&text, &InterpretOptions::default()).unwrap();
    let h = 1e-4;
    for corner in [
        CornerPolicy::Blend { tolerance_mm: 0.05 },
        CornerPolicy::ExactStop,
    ] {
        let input = PlanInput {
            blocks: prog.blocks.as_slice().into(),
            axes: axes.clone(),
            options: PlanOptions {
                corner,
                ..PlanOptions::default()
            },
        };
        let tp = plan(&input).unwrap();
        let n = tp.block_count();
        for k in 0..n {
            let p = tp.profile(k).unwrap();
            let (_, v_end, a_end, _) = p.at_time(p.duration_s());
            let next_start = tp.profile(k + 1).map_or(0.0, |q| q.phases[0].v0);
            assert!(
                (v_end - next_start).abs() <= 1e-9 * (1.0 + v_end) && a_end.abs() < 1e-6,
                "{corner:?} segment {k}: ends at {v_end}, next starts at {next_start}"
            );
        }
        let steps = (tp.cycle_time_s / h).ceil() as usize;
        let pos: Vec<_> = (0..steps + 5)
            .map(|i| tp.state_at((i as f64 - 2.0) * h).position)
            .collect();
        let mut worst = [0.0f64; 3];
        for i in 2..steps + 3 {
            for (k, (_, l)) in axes.iter().enumerate() {
                let q = |j: usize| pos[j][k];
                let v = (q(i + 1) - q(i - 1)) / (2.0 * h);
                let a = (q(i + 1) - 2.0 * q(i) + q(i - 1)) / (h * h);
                let j = (q(i + 2) - 2.0 * q(i + 1) + 2.0 * q(i - 1) - q(i - 2)) / (2.0 * h * h * h);
                let r = [
                    v.abs() / l.velocity,
                    a.abs() / l.acceleration,
                    j.abs() / l.jerk,
                ];
                for (w, x) in worst.iter_mut().zip(r) {
                    *w = w.max(x);
                }
            }
        }
        eprintln!(
            "{corner:?}: {n} segments, cycle {:.3} s, worst v/a/j ratios {worst:?}",
            tp.cycle_time_s
        );
        assert!(worst.iter().all(|r| *r <= 1.001), "{corner:?}: {worst:?}");
    }
}

/// `peaks` and `samples_every` (issue 36: each segment's profile built once, straight
/// segments' peaks from the profile's |v|, |a|, |j| times the joint direction) give, to the
/// bit, what `state_at` (the segment searched and its profile built per sample) gives at every
/// sample time, on random programs of lines, arcs and collinear runs with corner blends, on
/// 3 and 5 axes.
#[test]
fn peaks_and_samples_are_those_of_state_at_to_the_bit() {
    let mut rng = Lcg(36);
    for (name, five) in [("mill-3axis", false), ("trt-ac", true)] {
        let machine = Machine::builtin(name).unwrap();
        let axes = machine_limits(&machine);
        for case in 0..60 {
            let mut text = if case % 2 == 0 {
                random_program(&mut rng)
            } else {
                corner_program(&mut rng)
            };
            if five {
                // Rotary moves on some blocks (the tilt and the table with X Y Z).
                text = text
                    .lines()
                    .enumerate()
                    .map(|(i, l)| {
                        if l.starts_with("G1") && i % 3 == 1 {
                            format!("{l} A{:.3} C{:.3}\n", -(i as f64), 7.0 * i as f64)
                        } else {
                            format!("{l}\n")
                        }
                    })
                    .collect();
            }
            let prog = interpret(&text, &InterpretOptions::default()).unwrap();
            let input = PlanInput {
                blocks: prog.blocks.as_slice().into(),
                axes: axes.clone(),
                options: PlanOptions {
                    corner: CornerPolicy::Blend { tolerance_mm: 0.05 },
                    ..PlanOptions::default()
                },
            };
            let tp = plan(&input).unwrap_or_else(|e| panic!("case {case}: {e}\n{text}"));
            let period = tp.sample_period_s;
            let n = (tp.cycle_time_s / period).floor() as usize;
            let times = (0..=n)
                .map(|i| i as f64 * period)
                .filter(|t| *t < tp.cycle_time_s)
                .chain(std::iter::once(tp.cycle_time_s));
            let mut want = vec![[0.0f64; 3]; axes.len()];
            let mut count = 0;
            for (t, got) in times.zip(tp.samples_every(period)) {
                let s = tp.state_at(t);
                assert_eq!(s, got, "{name} case {case} t {t}\n{text}");
                for (w, (c, _)) in want.iter_mut().zip(&axes) {
                    let k = "XYZABC".find(*c).unwrap();
                    w[0] = w[0].max(s.velocity[k].abs());
                    w[1] = w[1].max(s.acceleration[k].abs());
                    w[2] = w[2].max(s.jerk[k].abs());
                }
                count += 1;
            }
            assert_eq!(count, tp.samples_every(period).count());
            for (p, w) in tp.peaks().iter().zip(&want) {
                assert_eq!(
                    [p.velocity, p.acceleration, p.jerk],
                    *w,
                    "{name} case {case} axis {}\n{text}",
                    p.axis
                );
            }
        }
    }
}
