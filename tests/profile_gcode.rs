//! The EDM profile's G-code goes through the one post: in every dialect the post knows and in
//! each plane, the program interprets back (Talas's interpreter, with the dialect's syntax)
//! to the profile's centre path: the feed into each piece ends at its first vertex, every
//! fed block ends on the path element it belongs to and every vertex is reached, within
//! 1e-4 mm; an arc block has the element's centre, radius and sense within 1e-4 mm, and a
//! dialect that cannot write the arc in that plane writes lines whose middles stay within the
//! chord tolerance; the axis normal to the plane stays at its value and every rapid is at the
//! clearance height. The path is measured with the independent geometry of `profile_common`.
//!
//! The LinuxCNC form is also read by LinuxCNC's own interpreter: `tests/data/profile/*.ngc`
//! are the programs (the test checks that the post still writes them byte for byte), and
//! `*.rs274.txt` what `rs274 -g -t ball.tbl` printed for them (re-run where `/usr/bin/rs274`
//! is installed); the printed motion meets the same centre path within 1e-4 mm.

#[path = "profile_common/mod.rs"]
mod profile_common;

use std::path::Path;

use glam::{DVec2, DVec3};
use profile_common::{Seg, point_dist, seg, seg_point};
use talas::gcode::{InterpretOptions, MotionKind, Syntax, interpret};
use talas::post::Dialect;
use talas::profile::{
    ClPath, GcodeOptions, ProfileOptions, ProfilePlane, Side, compute_opt, parse_csv, write_gcode,
};

const TOL: f64 = 1e-4;
const DATA: &str = "tests/data/profile";
const RS274: &str = "/usr/bin/rs274";

/// Name, CSV, radius, side: lines and arcs of both senses, a V notch the path bridges.
const CASES: [(&str, &str, f64, Side); 3] = [
    (
        "square",
        "0,0\n10,0\n10,10\n0,10\n0,0\n",
        2.0,
        Side::Outside,
    ),
    (
        "s-curve",
        "x,y,bulge\n0,0,0\n3,0,-0.5\n6,0,0.5\n9,0,0\n12,3,0\n",
        0.8,
        Side::Above,
    ),
    (
        "v-notch",
        "x,y\n-6,4\n-3,4\n0,0\n3,4\n6,4\n",
        1.0,
        Side::Above,
    ),
];

const PLANES: [(&str, ProfilePlane); 3] = [
    ("g17", ProfilePlane::G17),
    ("g18", ProfilePlane::G18),
    ("g19", ProfilePlane::G19),
];

fn paths(csv: &str, radius: f64, side: Side) -> Vec<ClPath> {
    let profile = parse_csv(csv, "case.csv").unwrap();
    let opts = ProfileOptions {
        radius_mm: radius,
        side,
        gouge_tolerance_mm: 1e-3,
    };
    compute_opt(&profile, &opts).unwrap().paths
}

/// The path's pieces as independent segments (from the vertices and bulges alone).
fn pieces(paths: &[ClPath]) -> Vec<Vec<Seg>> {
    paths
        .iter()
        .map(|p| {
            let n = p.vertices.len();
            let m = if p.closed { n } else { n - 1 };
            (0..m)
                .map(|i| {
                    let (a, b) = (&p.vertices[i], &p.vertices[(i + 1) % n]);
                    seg(a.centre, b.centre, a.bulge)
                })
                .collect()
        })
        .collect()
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Rapid,
    Feed,
    /// Centre (machine mm) and the signed normal the arc turns counter-clockwise about.
    Arc(DVec3, DVec3),
}

#[derive(Clone, Copy, Debug)]
struct Mv {
    kind: Kind,
    start: DVec3,
    end: DVec3,
}

/// The profile-plane coordinates of a machine point, and its coordinate normal to the plane.
fn in_plane(plane: ProfilePlane, p: DVec3) -> (DVec2, f64) {
    match plane {
        ProfilePlane::G17 => (DVec2::new(p.x, p.y), p.z),
        ProfilePlane::G18 => (DVec2::new(p.x, p.z), p.y),
        ProfilePlane::G19 => (DVec2::new(p.y, p.z), p.x),
    }
}

/// The machine direction of the profile's +x × +y (the sense a counter-clockwise profile arc
/// turns about).
fn profile_normal(plane: ProfilePlane) -> DVec3 {
    match plane {
        ProfilePlane::G17 => DVec3::Z,
        ProfilePlane::G18 => DVec3::NEG_Y,
        ProfilePlane::G19 => DVec3::X,
    }
}

/// How closely a dialect's program can follow the path.
#[derive(Clone, Copy, Debug)]
struct Reading {
    /// Largest distance of a written point from the path, mm: 1e-4, or the dialect's
    /// resolution where it writes fewer than 4 decimals (GRBL: 0.001 mm, so √2 · 0.0005).
    tol: f64,
    /// Arcs are written with R: the centre the control finds from R and the rounded end
    /// points moves by the rounding over the sine of half the sweep (ill-conditioned for a
    /// short arc), so the arc's middle is checked instead of its centre.
    radius_form: bool,
}

impl Reading {
    fn of(d: &Dialect) -> Self {
        Self {
            tol: TOL.max(0.5 * 10f64.powi(-(d.decimals_linear as i32)) * 2f64.sqrt() + 1e-9),
            radius_form: d.arc_centre == talas::post::ArcCentre::Radius,
        }
    }
}

/// Every way the moves miss the path (empty when they follow it).
fn misses(
    what: &str,
    moves: &[Mv],
    pieces: &[Vec<Seg>],
    plane: ProfilePlane,
    o: &GcodeOptions,
    read: Reading,
) -> Vec<String> {
    let tol = read.tol;
    let mut out: Vec<String> = Vec::new();
    let mut it = moves.iter().enumerate().peekable();
    macro_rules! fail {
        ($($t:tt)*) => { out.push(format!("{what}: {}", format!($($t)*))) };
    }
    for (p, piece) in pieces.iter().enumerate() {
        // Rapids at the clearance height, then the feed down onto the first vertex.
        while let Some((i, mv)) = it.next_if(|(_, m)| matches!(m.kind, Kind::Rapid)) {
            if (mv.end.z - o.clearance_z_mm).abs() > tol {
                fail!("rapid {i} ends at Z {} below the clearance", mv.end.z);
            }
        }
        let Some(first) = piece.first() else { continue };
        let start = match *first {
            Seg::Line(a, _) | Seg::Arc(a, ..) => a,
        };
        match it.next() {
            Some((i, mv)) if matches!(mv.kind, Kind::Feed) => {
                let (q, fixed) = in_plane(plane, mv.end);
                if q.distance(start) > tol || (fixed - o.fixed_mm).abs() > tol {
                    fail!("piece {p}: the feed in (move {i}) ends at {:?}", mv.end);
                }
            }
            other => {
                fail!("piece {p}: no feed in but {other:?}");
                return out;
            }
        }
        for (k, s) in piece.iter().enumerate() {
            let end = match *s {
                Seg::Line(_, b) | Seg::Arc(_, b, ..) => b,
            };
            loop {
                let Some((i, mv)) = it.next() else {
                    fail!("piece {p}: the program ends before element {k}");
                    return out;
                };
                let (q, fixed) = in_plane(plane, mv.end);
                let d = point_dist(s, q);
                if d > tol || (fixed - o.fixed_mm).abs() > tol {
                    fail!(
                        "piece {p} element {k}: move {i} ends {d:.2e} mm off the path ({:?})",
                        mv.end
                    );
                }
                match (mv.kind, *s) {
                    (Kind::Rapid, _) => fail!("piece {p} element {k}: move {i} is a rapid"),
                    (Kind::Feed, Seg::Line(..)) => {}
                    (Kind::Feed, Seg::Arc(..)) => {
                        // An arc written as lines: the chord's middle within the tolerance.
                        let (a, _) = in_plane(plane, mv.start);
                        let mid = (a + q) * 0.5;
                        if point_dist(s, mid) > o.tolerance_mm + tol {
                            fail!(
                                "piece {p} element {k}: chord {i} leaves the arc by {:.2e} mm",
                                point_dist(s, mid)
                            );
                        }
                    }
                    (Kind::Arc(..), Seg::Line(..)) => {
                        fail!("piece {p} element {k}: move {i} is an arc on a line");
                    }
                    (Kind::Arc(c, turn), Seg::Arc(_, _, centre, r, _, sweep)) => {
                        let (cq, _) = in_plane(plane, c);
                        let sense = profile_normal(plane) * sweep.signum();
                        let centre_off = cq.distance(centre) > tol && !read.radius_form;
                        if centre_off
                            || ((q - cq).length() - r).abs() > tol
                            || turn.dot(sense) < 0.5
                        {
                            fail!(
                                "piece {p} element {k}: arc {i} about {cq:?} turning about {turn:?}, the path's about {centre:?} (r {r}, sweep {sweep})"
                            );
                        }
                        // And its middle on the element.
                        let (a, _) = in_plane(plane, mv.start);
                        let (u, w) = (a - cq, q - cq);
                        let mut block_sweep = u.perp_dot(w).atan2(u.dot(w));
                        if block_sweep * sweep < 0.0 {
                            block_sweep += std::f64::consts::TAU * sweep.signum();
                        }
                        let a0 = u.y.atan2(u.x);
                        let mid = seg_point(&Seg::Arc(a, q, cq, u.length(), a0, block_sweep), 0.5);
                        if point_dist(s, mid) > tol {
                            fail!("piece {p} element {k}: arc {i} leaves the path");
                        }
                    }
                }
                if q.distance(end) <= tol {
                    break;
                }
            }
        }
    }
    for (i, mv) in it {
        if !matches!(mv.kind, Kind::Rapid) || (mv.end.z - o.clearance_z_mm).abs() > tol {
            fail!("move {i} after the path: {mv:?}");
        }
    }
    out
}

/// Talas's interpreter on a program, as moves (those that go nowhere left out).
fn talas_moves(text: &str, syntax: Syntax) -> Vec<Mv> {
    let program = interpret(text, &InterpretOptions::for_syntax(syntax)).unwrap();
    program
        .blocks
        .iter()
        .filter(|b| b.start.xyz.distance(b.end.xyz) > 1e-7)
        .map(|b| Mv {
            kind: match b.kind {
                MotionKind::Rapid => Kind::Rapid,
                MotionKind::Linear => Kind::Feed,
                MotionKind::ArcCcw(a) => Kind::Arc(a.centre, a.normal),
                MotionKind::ArcCw(a) => Kind::Arc(a.centre, -a.normal),
            },
            start: b.start.xyz,
            end: b.end.xyz,
        })
        .collect()
}

fn options(plane: ProfilePlane, radius: f64) -> GcodeOptions {
    GcodeOptions {
        plane,
        radius_mm: radius,
        ..GcodeOptions::default()
    }
}

#[test]
fn every_dialect_reads_back_to_the_centre_path_in_every_plane() {
    let mut failures = Vec::new();
    let mut arcs = 0;
    for (name, csv, radius, side) in CASES {
        let ps = paths(csv, radius, side);
        let segs = pieces(&ps);
        for dialect_name in Dialect::builtin_names() {
            let dialect = Dialect::builtin(dialect_name).unwrap();
            let syntax = Syntax::from_name(dialect_name).unwrap();
            for (plane_name, plane) in PLANES {
                let o = options(plane, radius);
                let text = write_gcode(&ps, &dialect, &o).unwrap();
                assert_eq!(
                    text,
                    write_gcode(&ps, &dialect, &o).unwrap(),
                    "deterministic"
                );
                let moves = talas_moves(&text, syntax);
                arcs += moves
                    .iter()
                    .filter(|m| matches!(m.kind, Kind::Arc(..)))
                    .count();
                failures.extend(misses(
                    &format!("{name} {dialect_name} {plane_name}"),
                    &moves,
                    &segs,
                    plane,
                    &o,
                    Reading::of(&dialect),
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The arcs are arcs wherever the dialect allows (not all lines).
    assert!(arcs > 50, "{arcs} arc blocks");
}

#[test]
fn a_dialect_without_the_plane_writes_the_arcs_as_lines_within_the_tolerance() {
    // Heidenhain writes arcs in G17 only (R form): in G18 the corner arcs are lines.
    let (_, csv, radius, side) = CASES[0];
    let ps = paths(csv, radius, side);
    let dialect = Dialect::builtin("heidenhain").unwrap();
    let g18 = write_gcode(&ps, &dialect, &options(ProfilePlane::G18, radius)).unwrap();
    assert!(!g18.contains("G02") && !g18.contains("G03"), "{g18}");
    let g17 = write_gcode(&ps, &dialect, &options(ProfilePlane::G17, radius)).unwrap();
    assert_eq!(g17.matches("G03").count(), 4, "{g17}");
    assert_eq!(g17.matches(" R2 *").count(), 4, "{g17}");
}

/// `rs274 -g` print → moves (millimetre programs without offsets: what the profile writes).
fn rs274_moves(text: &str) -> Vec<Mv> {
    let mut plane = ProfilePlane::G17;
    let mut pos = DVec3::ZERO;
    let mut out = Vec::new();
    for line in text.lines() {
        let Some((name, rest)) = line.split_whitespace().nth(2).and_then(|_| {
            let call = line
                .split_whitespace()
                .skip(2)
                .collect::<Vec<_>>()
                .join(" ");
            call.split_once('(')
                .map(|(a, b)| (a.to_string(), b.to_string()))
        }) else {
            continue;
        };
        let v: Vec<f64> = rest
            .trim_end()
            .trim_end_matches(')')
            .split([',', ' '])
            .filter_map(|t| t.parse().ok())
            .collect();
        match name.as_str() {
            "SELECT_PLANE" => {
                plane = if rest.contains("XZ") {
                    ProfilePlane::G18
                } else if rest.contains("YZ") {
                    ProfilePlane::G19
                } else {
                    ProfilePlane::G17
                }
            }
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => {
                let end = DVec3::new(v[0], v[1], v[2]);
                if end.distance(pos) > 1e-7 {
                    let kind = if name == "STRAIGHT_FEED" {
                        Kind::Feed
                    } else {
                        Kind::Rapid
                    };
                    out.push(Mv {
                        kind,
                        start: pos,
                        end,
                    });
                }
                pos = end;
            }
            "ARC_FEED" => {
                // first_end, second_end, first_centre, second_centre, turn, axis_end: the
                // plane's axes are X Y (Z), Z X (Y), Y Z (X).
                let (end, centre, normal) = match plane {
                    ProfilePlane::G17 => (
                        DVec3::new(v[0], v[1], v[5]),
                        DVec3::new(v[2], v[3], v[5]),
                        DVec3::Z,
                    ),
                    ProfilePlane::G18 => (
                        DVec3::new(v[1], v[5], v[0]),
                        DVec3::new(v[3], v[5], v[2]),
                        DVec3::Y,
                    ),
                    ProfilePlane::G19 => (
                        DVec3::new(v[5], v[0], v[1]),
                        DVec3::new(v[5], v[2], v[3]),
                        DVec3::X,
                    ),
                };
                let turn = normal * v[4].signum();
                out.push(Mv {
                    kind: Kind::Arc(centre, turn),
                    start: pos,
                    end,
                });
                pos = end;
            }
            _ => {}
        }
    }
    out
}

#[test]
fn the_linuxcnc_form_reads_back_in_linuxcncs_interpreter() {
    let dialect = Dialect::builtin("linuxcnc").unwrap();
    let mut failures = Vec::new();
    let mut checked = 0;
    for (name, csv, radius, side) in CASES {
        let ps = paths(csv, radius, side);
        let segs = pieces(&ps);
        for (plane_name, plane) in PLANES {
            let o = options(plane, radius);
            let stem = format!("{name}-{plane_name}");
            let ngc = Path::new(DATA).join(format!("{stem}.ngc"));
            let text = write_gcode(&ps, &dialect, &o).unwrap();
            assert_eq!(
                std::fs::read_to_string(&ngc).unwrap(),
                text,
                "{stem}: the post writes another program now: regenerate tests/data/profile (make_rs274.sh)"
            );
            let printed =
                std::fs::read_to_string(Path::new(DATA).join(format!("{stem}.rs274.txt"))).unwrap();
            let moves = rs274_moves(&printed);
            checked += moves.len();
            failures.extend(misses(
                &format!("rs274 {stem}"),
                &moves,
                &segs,
                plane,
                &o,
                Reading::of(&dialect),
            ));
            if Path::new(RS274).exists() {
                let home =
                    std::env::temp_dir().join(format!("talas-rs274-p-{}", std::process::id()));
                std::fs::create_dir_all(&home).unwrap();
                let out = std::process::Command::new(RS274)
                    .arg("-g")
                    .arg("-t")
                    .arg(Path::new(DATA).join("ball.tbl"))
                    .arg(&ngc)
                    .env("HOME", &home)
                    .output()
                    .unwrap();
                assert!(out.status.success(), "{stem}: rs274 failed");
                assert_eq!(
                    String::from_utf8_lossy(&out.stdout),
                    printed,
                    "{stem}: rs274 prints something else now"
                );
            }
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(checked > 50, "{checked} moves");
}
