//! G-code interpreter tests: the Kelekçi (2021) thesis programs against the digest's derived
//! values (shared/spec/seed-001-jerk-limited-trajectory.md §4, V7–V11, V14), hand-checked
//! arcs in every plane and sense, modes, errors with positions, and a mutation fuzz.

mod common;

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use common::{assert_near, data};
use glam::DVec3;
use talas::gcode::{InterpretOptions, Joints, MotionBlock, MotionKind, Program, interpret};

fn run_at(text: &str, x: f64, y: f64, z: f64) -> Program {
    interpret(text, &InterpretOptions::starting_at(Joints::xyz(x, y, z)))
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// The text of `tests/data/gcode/<name>`.
fn program_text(name: &str) -> String {
    let path = data(&format!("gcode/{name}"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn arc_of(b: &MotionBlock) -> talas::gcode::Arc {
    *b.kind.arc().expect("an arc block")
}

/// Digest V7: "Eq. 2.21 (`G17 G02 X9.019 Y2.975 R5` from (0.24, 1.53)): centre (5.0002,
/// 0.0002), sweep 125.674°, L = 10.967. With R−5 (Fig. 2.14): centre (4.2588, 4.5048),
/// sweep 234.33°, L = 20.449."
#[test]
fn eq2_21_g17_g02_r5() {
    let p = run_at(
        &program_text("seed-001-eq2-21-g17-g02-r5.nc"),
        0.24,
        1.53,
        0.0,
    );
    assert_eq!(p.blocks.len(), 1);
    let b = &p.blocks[0];
    assert!(matches!(b.kind, MotionKind::ArcCw(_)));
    let a = arc_of(b);
    assert_near!(a.centre.x, 5.0002, 1.5e-4, "xc");
    assert_near!(a.centre.y, 0.0002, 1.5e-4, "yc");
    assert_near!(a.radius_mm, 5.0, 1e-3, "r");
    assert_near!(a.sweep_rad.to_degrees(), 125.674, 1e-3, "sweep");
    assert_near!(b.length_mm(), 10.967, 1e-3, "L");
    assert_eq!(b.source_line, 4);

    let p = run_at("G17 G02 X9.019 Y2.975 R-5", 0.24, 1.53, 0.0);
    let a = arc_of(&p.blocks[0]);
    assert_near!(a.centre.x, 4.2588, 1.5e-4, "xc");
    assert_near!(a.centre.y, 4.5048, 1.5e-4, "yc");
    assert_near!(a.sweep_rad.to_degrees(), 234.33, 1e-2, "sweep");
    assert_near!(p.blocks[0].length_mm(), 20.449, 1e-3, "L");
}

/// Digest V7: "Eq. 2.22/2.23 use the same numbers in the XZ and YZ planes; note the G18
/// orientation caveat in §2.3" ("ISO/Fanuc defines the G18 plane as ZX, with the first axis Z.
/// A plain X→x, Z→y mapping therefore mirrors the CW/CCW sense"). Talas follows ISO, so the
/// G18 G2 arc takes the other centre of the pair: the one the thesis's XY mapping gives for
/// R−5 (4.2588, 4.5048), with the same short sweep 125.674° and L = 10.967.
#[test]
fn eq2_22_g18_and_eq2_23_g19() {
    let p = run_at(
        &program_text("seed-001-eq2-22-g18-g02-r5.nc"),
        0.24,
        0.0,
        1.53,
    );
    let b = &p.blocks[0];
    let a = arc_of(b);
    assert_eq!(a.normal, DVec3::Y);
    assert_near!(a.centre.x, 4.2588, 1.5e-4, "xc");
    assert_near!(a.centre.z, 4.5048, 1.5e-4, "zc");
    assert_near!(a.sweep_rad.to_degrees(), 125.674, 1e-3, "sweep");
    assert_near!(b.length_mm(), 10.967, 1e-3, "L");
    // The ISO sense: the midpoint, seen from +Y, lies clockwise from the start.
    let mid = b.point_at(0.5).xyz - a.centre;
    let st = b.start.xyz - a.centre;
    assert!(st.cross(mid).y < 0.0, "G2 in G18 turns negatively about +Y");

    let p = run_at(
        &program_text("seed-001-eq2-23-g19-g02-r5.nc"),
        0.0,
        0.24,
        1.53,
    );
    let b = &p.blocks[0];
    let a = arc_of(b);
    assert_eq!(a.normal, DVec3::X);
    assert_near!(a.centre.y, 5.0002, 1.5e-4, "yc");
    assert_near!(a.centre.z, 0.0002, 1.5e-4, "zc");
    assert_near!(a.sweep_rad.to_degrees(), 125.674, 1e-3, "sweep");
    assert_near!(b.length_mm(), 10.967, 1e-3, "L");
}

/// Digest V7: "Eq. 2.24 (`G17 G03 X14.94 Y1.749 Z2 R14.976` from (14.32, 5.66, 0)): centre
/// (29.2915, 6.0287), sweep 15.194°, planar length 3.9715, helix length 4.4466. With R < 0:
/// centre (−0.0315, 1.3803), sweep 344.81°."
#[test]
fn eq2_24_helix() {
    let p = run_at(
        &program_text("seed-001-eq2-24-g17-g03-helix.nc"),
        14.32,
        5.66,
        0.0,
    );
    let b = &p.blocks[0];
    assert!(matches!(b.kind, MotionKind::ArcCcw(_)));
    let a = arc_of(b);
    assert_near!(a.centre.x, 29.2915, 1.5e-4, "xc");
    assert_near!(a.centre.y, 6.0287, 1.5e-4, "yc");
    assert_near!(a.sweep_rad.to_degrees(), 15.194, 1e-3, "sweep");
    assert_near!(a.radius_mm * a.sweep_rad, 3.9715, 1e-4, "planar L");
    assert_near!(a.helix_mm, 2.0, 1e-12, "helix");
    assert_near!(b.length_mm(), 4.4466, 1e-4, "helix L");
    assert_near!(b.point_at(1.0).xyz.distance(b.end.xyz), 0.0, 1e-9, "end");

    let p = run_at("G17 G03 X14.94 Y1.749 Z2 R-14.976", 14.32, 5.66, 0.0);
    let a = arc_of(&p.blocks[0]);
    assert_near!(a.centre.x, -0.0315, 1.5e-4, "xc");
    assert_near!(a.centre.y, 1.3803, 1.5e-4, "yc");
    assert_near!(a.sweep_rad.to_degrees(), 344.81, 1e-2, "sweep");
}

/// Digest V7/V9: "Eq. 3.25: centre (6.9479, −11.8571), θ02 = 243.393°, sweep 34.556°,
/// L = 9.0322", from (0.2407, 1.533, 0) with F1800.
#[test]
fn eq3_25_single_arc() {
    let p = run_at(
        &program_text("seed-001-eq3-25-g02-single.nc"),
        0.2407,
        1.533,
        0.0,
    );
    let b = &p.blocks[0];
    let a = arc_of(b);
    assert_near!(a.centre.x, 6.9479, 1.5e-4, "xc");
    assert_near!(a.centre.y, -11.8571, 1.5e-4, "yc");
    let start_angle = (b.start.xyz.y - a.centre.y).atan2(b.start.xyz.x - a.centre.x);
    // θ02 is measured clockwise (Eq. 2.14): θ02 = −(counter-clockwise angle) mod 360.
    assert_near!(
        (-start_angle.to_degrees()).rem_euclid(360.0),
        243.393,
        1e-3,
        "θ02"
    );
    assert_near!(a.sweep_rad.to_degrees(), 34.556, 1e-3, "sweep");
    assert_near!(b.length_mm(), 9.0322, 1e-4, "L");
    assert_near!(b.feed_mm_per_min, 1800.0, 0.0, "F");
}

/// Digest V8, V10, V11: line lengths.
#[test]
fn line_programs() {
    let cases: [(&str, [f64; 3], &[f64]); 6] = [
        (
            "seed-001-eq2-6-g01-no-planning.nc",
            [2.0, -1.0, 3.0],
            &[13.7477],
        ),
        (
            "seed-001-eq2-7-g01-no-planning.nc",
            [6.0, 0.0, 0.0],
            &[55.4617],
        ),
        (
            "seed-001-eq2-8-g01-no-planning.nc",
            [30.0, 15.0, 10.0],
            &[20.0],
        ),
        ("seed-001-eq3-17-g01-single.nc", [0.0; 3], &[26.9258]),
        (
            "seed-001-eq3-20-g01-sharp-corners.nc",
            [0.0; 3],
            &[48.218, 85.732, 107.355],
        ),
        (
            "seed-001-eq3-21-g01-smooth-corners.nc",
            [0.0; 3],
            &[48.990, 43.875, 41.533],
        ),
    ];
    for (name, [x, y, z], lengths) in cases {
        let p = run_at(&program_text(name), x, y, z);
        let got: Vec<f64> = p.blocks.iter().map(MotionBlock::length_mm).collect();
        assert_eq!(got.len(), lengths.len(), "{name}");
        for (g, e) in got.iter().zip(lengths) {
            assert_near!(*g, *e, 1e-3, "{}", name);
        }
        let no_f = name.contains("eq2-");
        // Programs without F get a warning, never silence; F3000 is modal over the blocks.
        assert_eq!(
            !p.diagnostics.is_empty(),
            no_f,
            "{name}: {:?}",
            p.diagnostics
        );
        if !no_f {
            assert!(p.blocks.iter().all(|b| b.feed_mm_per_min == 3000.0));
        }
    }
}

/// Digest V14: the Fig. 4.36 pocket fragment from the implied start (−105, 82.501): "All
/// arc/line joins are tangent", corner radius 12.499, notch radius 3.125.
#[test]
fn fig4_36_pocket_fragment_is_tangent() {
    let p = run_at(
        &program_text("seed-001-fig4-36-pocket-fragment.nc"),
        -105.0,
        82.501,
        0.0,
    );
    assert_eq!(p.blocks.len(), 18);
    let arcs: Vec<f64> = p
        .blocks
        .iter()
        .filter_map(|b| b.kind.arc())
        .map(|a| a.radius_mm)
        .collect();
    assert_eq!(arcs.len(), 9);
    for r in arcs {
        assert!(
            (r - 12.499).abs() < 1e-3 || (r - 3.125).abs() < 2e-3,
            "radius {r}"
        );
    }
    // Tangents by finite differences along each block.
    let dir = |b: &MotionBlock, t: f64| {
        let h = 1e-7;
        (b.point_at((t + h).min(1.0)).xyz - b.point_at((t - h).max(0.0)).xyz).normalize()
    };
    for w in p.blocks.windows(2) {
        let angle = dir(&w[0], 1.0).angle_between(dir(&w[1], 0.0));
        assert!(
            angle < 2e-3,
            "join at line {}: {angle} rad",
            w[1].source_line
        );
    }
    assert_eq!(p.blocks[0].source_line, 5);
}

/// Quarter circles of radius 10 about the origin, hand-checked: CCW is a positive rotation
/// about the plane normal (G17 +Z, G18 +Y, G19 +X); the same end with G2 sweeps 270°.
#[test]
fn planes_and_senses() {
    // (program, start, end of G3 quarter, normal)
    let cases = [
        ("G17 G3 X0 Y10 I-10 J0", [10.0, 0.0, 0.0], DVec3::Z),
        ("G18 G3 X0 Z-10 I-10 K0", [10.0, 0.0, 0.0], DVec3::Y),
        ("G19 G3 Y0 Z10 J-10 K0", [0.0, 10.0, 0.0], DVec3::X),
    ];
    for (text, [x, y, z], normal) in cases {
        let p = run_at(text, x, y, z);
        let b = &p.blocks[0];
        let a = arc_of(b);
        assert_eq!(a.normal, normal);
        assert_near!(a.sweep_rad, FRAC_PI_2, 1e-12, "{}", text);
        assert_near!(b.length_mm(), 5.0 * PI, 1e-9, "{}", text);
        let mid = b.point_at(0.5).xyz;
        let start = DVec3::new(x, y, z);
        // Rotating the start by +45° about the normal (Rodrigues) gives the midpoint.
        let c = std::f64::consts::FRAC_PI_4;
        let expect = start * c.cos() + normal.cross(start) * c.sin();
        assert!(mid.distance(expect) < 1e-9, "{text}: mid {mid}");
        let cw = text.replace("G3", "G2");
        let b = &run_at(&cw, x, y, z).blocks[0];
        assert!(matches!(b.kind, MotionKind::ArcCw(_)));
        assert_near!(arc_of(b).sweep_rad, 3.0 * FRAC_PI_2, 1e-12, "{}", &cw);
        // A third of 270° clockwise: the start turned by −90° about the normal.
        let mid = b.point_at(1.0 / 3.0).xyz;
        let expect = -normal.cross(start);
        assert!(mid.distance(expect) < 1e-9, "{cw}: mid {mid}");
    }
}

/// R > 0 takes the short arc, R < 0 the long one: from (10, 0) to (0, 10) clockwise, the
/// short arc's centre is (10, 10) and the long one's (0, 0).
#[test]
fn r_format_signs() {
    let b = &run_at("G2 X0 Y10 R10", 10.0, 0.0, 0.0).blocks[0];
    let a = arc_of(b);
    assert!(a.centre.distance(DVec3::new(10.0, 10.0, 0.0)) < 1e-9);
    assert_near!(a.sweep_rad, FRAC_PI_2, 1e-12, "short");
    let b = &run_at("G2 X0 Y10 R-10", 10.0, 0.0, 0.0).blocks[0];
    let a = arc_of(b);
    assert!(a.centre.length() < 1e-9);
    assert_near!(a.sweep_rad, 3.0 * FRAC_PI_2, 1e-12, "long");
    // A half circle: the chord equals the diameter.
    let a = arc_of(&run_at("G3 X-10 Y0 R10", 10.0, 0.0, 0.0).blocks[0]);
    assert!(a.centre.length() < 1e-9);
    assert_near!(a.sweep_rad, PI, 1e-12, "half");
}

#[test]
fn full_circles_and_helices() {
    let b = &run_at("G2 X10 Y0 I-10 J0 F100", 10.0, 0.0, 0.0).blocks[0];
    assert_near!(arc_of(b).sweep_rad, TAU, 0.0, "full");
    assert_near!(b.length_mm(), 20.0 * PI, 1e-9, "circumference");
    // A two-turn helix dropping 5 mm: length = √((2·2π·10)² + 5²).
    let b = &run_at("G3 X10 Y0 Z-5 I-10 J0 P2 F100", 10.0, 0.0, 0.0).blocks[0];
    let a = arc_of(b);
    assert_near!(a.sweep_rad, 2.0 * TAU, 1e-12, "two turns");
    assert_near!(b.length_mm(), (40.0 * PI).hypot(5.0), 1e-9, "helix");
    assert_near!(b.point_at(0.25).xyz.z, -1.25, 1e-12, "helix z");
    assert!(b.point_at(0.25).xyz.distance(DVec3::new(-10.0, 0.0, -1.25)) < 1e-9);
    // A full circle in R format is impossible.
    let e = interpret("G2 X0 Y0 R5", &InterpretOptions::default()).unwrap_err();
    assert_eq!((e.line, e.column), (1, 1));
}

#[test]
fn incremental_inch_offsets_and_modes() {
    let text = "G91 G1 X1 Y2 F100\nX1 Y2\nG3 X-2 Y0 I-1 J0\nG90 G0 Z5";
    let p = run_at(text, 1.0, 1.0, 0.0);
    let ends: Vec<DVec3> = p.blocks.iter().map(|b| b.end.xyz).collect();
    assert_eq!(
        ends,
        vec![
            DVec3::new(2.0, 3.0, 0.0),
            DVec3::new(3.0, 5.0, 0.0),
            DVec3::new(1.0, 5.0, 0.0),
            DVec3::new(1.0, 5.0, 5.0)
        ]
    );
    let a = arc_of(&p.blocks[2]);
    assert!(a.centre.distance(DVec3::new(2.0, 5.0, 0.0)) < 1e-12);
    assert!(matches!(p.blocks[3].kind, MotionKind::Rapid));

    // Inches: coordinates, arc offsets and feed scale by 25.4; angles stay degrees.
    let p = run_at("G20 G1 X1 A90 F10\nG2 X2 Y0 I0.5 J0", 0.0, 0.0, 0.0);
    assert_near!(p.blocks[0].end.xyz.x, 25.4, 1e-12, "x");
    assert_near!(p.blocks[0].feed_mm_per_min, 254.0, 1e-12, "F");
    assert_near!(p.blocks[0].end.a.unwrap(), FRAC_PI_2, 1e-15, "A");
    assert_eq!(p.blocks[0].start.a, Some(0.0));
    assert_near!(arc_of(&p.blocks[1]).radius_mm, 12.7, 1e-12, "r");

    // Work offsets, G53, G90.1 absolute centres, G43/G49, spindle and tool state.
    let mut opts = InterpretOptions::default();
    opts.work_offsets[1] = DVec3::new(100.0, 200.0, 300.0);
    let text = "T3 M6 S1200 M3 G55 G43 H3\nG0 X1 Y0 Z0\nG90.1 G3 X-1 Y0 I0 J0 F50\nG53 G0 Z0\nG49 M5 G1 X0 F20";
    let p = interpret(text, &opts).unwrap();
    assert_eq!(p.blocks[0].end.xyz, DVec3::new(101.0, 200.0, 300.0));
    assert_eq!(
        (
            p.blocks[0].tool,
            p.blocks[0].tool_length_h,
            p.blocks[0].spindle_rpm
        ),
        (3, Some(3), 1200.0)
    );
    let a = arc_of(&p.blocks[1]);
    assert_eq!(a.centre, DVec3::new(100.0, 200.0, 300.0));
    assert_near!(a.sweep_rad, PI, 1e-12, "G90.1 half circle");
    assert_eq!(p.blocks[2].end.xyz, DVec3::new(99.0, 200.0, 0.0));
    assert_eq!(
        (p.blocks[3].tool_length_h, p.blocks[3].spindle_rpm),
        (None, 0.0)
    );

    // G93 inverse time and G28 through an intermediate point.
    let p = run_at("G93 G1 X10 C90 F2\nG94 G28 Z5", 0.0, 0.0, 0.0);
    assert!(p.blocks[0].inverse_time);
    assert_near!(
        p.blocks[0].inverse_time_duration_s().unwrap(),
        30.0,
        1e-12,
        "1/F min"
    );
    assert_near!(p.blocks[0].rotary_travel_rad(), FRAC_PI_2, 1e-15, "C");
    assert_eq!(p.blocks[1].end.xyz, DVec3::new(10.0, 0.0, 5.0));
    assert_eq!(p.blocks[2].end.xyz, DVec3::new(10.0, 0.0, 0.0));

    // Comments, block delete, N/O numbers, %, M30 ends.
    let text = "%\nO1234 (prog)\nN10 G1 X1 F5 ; one\n/ G1 X99\nN20 X2\nM30\nG1 X50\n%";
    let p = interpret(text, &InterpretOptions::default()).unwrap();
    assert_eq!(p.blocks.len(), 2);
    assert_eq!(p.blocks[1].source_line, 5);
    assert!(
        p.diagnostics
            .iter()
            .any(|d| d.message.contains("after the program end"))
    );
}

#[test]
fn errors_name_line_and_column() {
    let cases = [
        ("G1 X1 F10\n   G41 X2", 2, 4, "G41"),
        ("G1 X1 Q3 F1", 1, 7, "Q"),
        ("G1 X1 F1\nG2 X2 Y0", 2, 1, "I/J/K"),
        ("G1 X1 X2", 1, 7, "twice"),
        ("G0 G1 X1", 1, 4, "two motion"),
        // Parameters are read now (#1=2 is a valid line): an undefined one is the error.
        ("G1 X1 F1\nG1 X#<depth>", 2, 4, "parameter"),
        ("G3 X0 Y10 I-10 J1 F1", 1, 1, "radius"),
        ("G2 X30 Y0 R5 F1", 1, 1, "smaller"),
        ("X5", 1, 1, "motion mode"),
        ("G93 G1 X5", 1, 1, "inverse-time"),
        ("G1 X5 F1 (unclosed", 1, 10, "not closed"),
        ("G81 X1 Y1 R2 Z-1", 1, 1, "G81"),
        ("G91 G53 G0 X1", 1, 5, "G53"),
        ("G1 X1 F1 R3", 1, 10, "outside an arc"),
    ];
    for (text, line, column, what) in cases {
        let e = interpret(text, &InterpretOptions::default()).unwrap_err();
        assert_eq!((e.line, e.column), (line, column), "{text}: {e}");
        assert!(e.to_string().contains(what), "{text}: {e}");
    }
    // Unknown M codes are warnings, with the place.
    let p = interpret("M3 S100\nM51\nG1 X1 F1", &InterpretOptions::default()).unwrap();
    assert_eq!(p.blocks.len(), 1);
    let d = &p.diagnostics[0];
    assert!(
        d.message.contains("M51") && d.place.as_deref() == Some("line 2, column 1"),
        "{d}"
    );
}

/// xorshift64* with a fixed seed.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

/// Thousands of mutated programs: never a panic, and every block of a program that is accepted
/// is finite.
#[test]
fn mutated_programs_never_panic() {
    let mut bases: Vec<String> = [
        "seed-001-fig4-36-pocket-fragment.nc",
        "seed-001-eq2-24-g17-g03-helix.nc",
        "seed-001-eq3-20-g01-sharp-corners.nc",
    ]
    .iter()
    .map(|n| program_text(n))
    .collect();
    bases.push("G20 G91 G18 G2 X1 Z1 I1 K0 P3 F5\nG90.1 G19 G3 Y1 Z0 J0 K0\nG93 G1 A30 C-90 F3\nG28 X0\nG53 G0 Z0 M30".into());
    let alphabet: Vec<char> = "GMXYZABCIJKRFPHSTNO0123456789.-+ ()#;/%\n\t[]QéU"
        .chars()
        .collect();
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut accepted = 0;
    for _ in 0..4000 {
        let mut text: Vec<char> = bases[rng.below(bases.len())].chars().collect();
        for _ in 0..1 + rng.below(6) {
            let at = rng.below(text.len() + 1);
            let c = alphabet[rng.below(alphabet.len())];
            match rng.below(3) {
                0 if at < text.len() => text[at] = c,
                1 if at < text.len() => {
                    text.remove(at);
                }
                _ => text.insert(at, c),
            }
        }
        let text: String = text.into_iter().collect();
        if let Ok(p) = interpret(&text, &InterpretOptions::default()) {
            accepted += 1;
            for b in &p.blocks {
                assert!(b.start.is_finite() && b.end.is_finite(), "{text}");
                assert!(
                    b.length_mm().is_finite() && b.feed_mm_per_min.is_finite(),
                    "{text}"
                );
                assert!(b.point_at(0.5).is_finite(), "{text}");
            }
        }
    }
    assert!(
        accepted > 500,
        "the mutations should leave many programs valid: {accepted}"
    );
}

/// Random text (not only mutations of valid programs) never panics either.
#[test]
fn random_text_never_panics() {
    let alphabet: Vec<char> = "GMXYZIJKRFP0123456789.-  \n()%/;#ABCNTSH".chars().collect();
    let mut rng = Rng(42);
    for _ in 0..3000 {
        let n = rng.below(120);
        let text: String = (0..n)
            .map(|_| alphabet[rng.below(alphabet.len())])
            .collect();
        if let Ok(p) = interpret(&text, &InterpretOptions::default()) {
            assert!(
                p.blocks
                    .iter()
                    .all(|b| b.end.is_finite() && b.length_mm().is_finite()),
                "{text}"
            );
        }
    }
}

/// Every arc block ends where its words say, through the helix parametrisation.
#[test]
fn arcs_end_at_their_end_points() {
    let text = "G91 G18 G2 X4 Z4 I2 K2 F10\nG19 G3 Y-3 Z3 R3\nG90 G17 G2 X4 Y-3 Z8 I0 J5 P3";
    let p = run_at(text, 0.0, 0.0, 0.0);
    assert_eq!(p.blocks.len(), 3);
    for b in &p.blocks {
        assert!(
            b.point_at(1.0).xyz.distance(b.end.xyz) < 1e-9,
            "line {}",
            b.source_line
        );
        assert!(b.point_at(0.0).xyz.distance(b.start.xyz) < 1e-12);
    }
    // G18 G91: centre at start + (I, K) = (2, 0, 2), a half circle about +Y clockwise.
    let a = arc_of(&p.blocks[0]);
    assert!(a.centre.distance(DVec3::new(2.0, 0.0, 2.0)) < 1e-12);
    assert_near!(a.sweep_rad, PI, 1e-12, "half");
    // Three full turns plus the helix rise of 1 mm.
    let a = arc_of(&p.blocks[2]);
    assert_near!(a.sweep_rad, 3.0 * TAU, 1e-9, "P3");
    // G43 without H takes the tool selected in the same block.
    let p = run_at("T7 M6 G43\nG1 X1 F1", 0.0, 0.0, 0.0);
    assert_eq!((p.blocks[0].tool, p.blocks[0].tool_length_h), (7, Some(7)));
}

/// The Can (2010) thesis sample format (digest seed-000 §4.7, EK-D/EK-E): `%123`, `T1;`,
/// `M3 S1250;`, `G1 X.. Y.. Z.. A.. C.. ;`, `M30;` with `;` as the ISO end of block. The first
/// and last EK-E blocks are quoted; C runs from −164.463° to −310.74°.
#[test]
fn thesis_post_format_with_semicolon_end_of_block() {
    let text = "%123\nT1; M3 S1250;\nG1 X166.195 Y110.138 Z-71.527 A40.277 C-164.463 F100;\nG1 X-245.379 Y112.129 Z-116.893 A48.547 C-310.74 ;  M30;";
    let opts = InterpretOptions {
        semicolon_ends_block: true,
        ..InterpretOptions::default()
    };
    let p = interpret(text, &opts).unwrap();
    assert_eq!(p.blocks.len(), 2);
    let b = &p.blocks[1];
    assert_eq!((b.tool, b.spindle_rpm), (1, 1250.0));
    assert_near!(b.start.c.unwrap().to_degrees(), -164.463, 1e-9, "C0");
    assert_near!(b.end.c.unwrap().to_degrees(), -310.74, 1e-9, "C1");
    assert_near!(b.end.a.unwrap().to_degrees(), 48.547, 1e-9, "A1");
    assert_eq!(b.end.xyz, DVec3::new(-245.379, 112.129, -116.893));
    // Columns count from the start of the whole line.
    let e = interpret("G1 X1 F1; G1 Q2", &opts).unwrap_err();
    assert_eq!((e.line, e.column), (1, 14));
    // With the RS274NGC default, `;` starts a comment: only T1 is read on that line.
    let p = interpret(
        text.replace(" F100", "").as_str(),
        &InterpretOptions::default(),
    );
    assert!(p.is_ok());
}

#[test]
fn dialect_syntaxes_and_tcp_modes() {
    use talas::gcode::Syntax;
    // Sinumerik: D tool edge, G71 metric, TRAORI / TRAFOOF around the fed blocks.
    let siemens = "N10 G17 G71 G90 G94\nN20 T1 D1\nN30 M6\nN40 TRAORI\nN50 G1 X10 Y0 Z5 A10 C20 F500\nN60 TRAFOOF\nN70 G0 Z50\n";
    let p = interpret(siemens, &InterpretOptions::for_syntax(Syntax::Siemens)).unwrap();
    assert_eq!(p.blocks.len(), 2);
    assert!(p.blocks[0].tcp && !p.blocks[1].tcp);
    assert!((p.blocks[0].end.a.unwrap() - 10f64.to_radians()).abs() < 1e-12);
    // Read as RS274, G71 is not a unit code, and a keyword is named with its column.
    let e = interpret(siemens, &InterpretOptions::default()).unwrap_err();
    assert_eq!((e.line, e.column), (1, 9));
    let e = interpret("N10 G1 X1 F100\nN20 TRAORI\n", &InterpretOptions::default()).unwrap_err();
    assert_eq!((e.line, e.column), (2, 5));
    assert!(e.message.contains("TRAORI"), "{}", e.message);
    // Heidenhain ISO: `*` block ends, the %-frame's G70 selects inch, M128 / M129.
    let tnc = "%P G70 *\nN10 T1 G17 S1000 *\nN20 M128 *\nN30 G01 X1 Y0 Z0 F10 *\nN40 M129 *\nN50 G00 Z2 *\nN99999999 %P G70 *\n";
    let p = interpret(tnc, &InterpretOptions::for_syntax(Syntax::HeidenhainIso)).unwrap();
    assert_eq!(p.blocks.len(), 2);
    assert!(
        (p.blocks[0].end.xyz.x - 25.4).abs() < 1e-12,
        "inch from the frame"
    );
    assert!((p.blocks[0].feed_mm_per_min - 254.0).abs() < 1e-9);
    assert!(p.blocks[0].tcp && !p.blocks[1].tcp);
    // RS274: G43.4 switches TCP on (with a tool length), G49 off.
    let ngc = "G21 G90\nT1 M6\nG43.4 H1\nG1 X1 F100\nG49\nG0 Z5\n";
    let p = interpret(ngc, &InterpretOptions::default()).unwrap();
    assert!(p.blocks[0].tcp && p.blocks[0].tool_length_h == Some(1) && !p.blocks[1].tcp);
    // Detection picks the right syntax for each.
    assert_eq!(Syntax::detect(siemens), Syntax::Siemens);
    assert_eq!(Syntax::detect(tnc), Syntax::HeidenhainIso);
    assert_eq!(Syntax::detect(ngc), Syntax::Rs274);
}
