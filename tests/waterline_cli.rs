//! `talas plan --strategy waterline|steep-shallow` on a box written as an ASCII STL: every cut
//! pose of a flat end mill lies on the box offset by its radius; bad options exit with code 2
//! and one line.

mod common;

use common::{talas, temp_file};
use talas::toolpath::{MoveKind, Toolpath};

/// A 20 × 20 × 10 mm box at the origin as ASCII STL.
fn box_stl() -> String {
    let c = |i: u32| {
        [
            if i & 1 == 0 { -10.0 } else { 10.0 },
            if i & 2 == 0 { -10.0 } else { 10.0 },
            if i & 4 == 0 { 0.0 } else { 10.0 },
        ]
    };
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut s = String::from("solid box\n");
    for q in quads {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            s.push_str("facet normal 0 0 0\nouter loop\n");
            for v in t {
                let p = c(v);
                s.push_str(&format!("vertex {} {} {}\n", p[0], p[1], p[2]));
            }
            s.push_str("endloop\nendfacet\n");
        }
    }
    s.push_str("endsolid box\n");
    s
}

#[test]
fn waterline_from_the_command_line_offsets_a_box() {
    let stl = temp_file("waterline-cli", "box.stl", &box_stl());
    let out = stl.with_file_name("wl.json");
    let (stl_s, out_s) = (stl.to_str().unwrap(), out.to_str().unwrap());
    let o = talas(&[
        "plan",
        stl_s,
        "--tool",
        "flat:d=10",
        "--strategy",
        "waterline",
        "--scallop",
        "0.05",
        "--json",
        "-o",
        out_s,
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let tp = Toolpath::load(&out).unwrap();
    let cuts: Vec<_> = tp
        .poses
        .iter()
        .filter(|p| p.kind == MoveKind::Cut)
        .collect();
    assert!(cuts.len() > 50);
    for p in &cuts {
        let d = (p.tip.truncate().abs() - glam::DVec2::splat(10.0)).max(glam::DVec2::ZERO);
        assert!(
            (d.length() - 5.0).abs() < 1e-9,
            "{} off the offset box",
            p.tip
        );
        assert!(p.tip.z >= -1e-9 && p.tip.z < 10.0);
    }
    let bad: [&[&str]; 3] = [
        &["--strategy", "waterline", "--pattern", "spiral"],
        &["--strategy", "waterline", "--angle", "95"],
        &["--strategy", "steep-shallow", "--angle", "88"],
    ];
    for b in bad {
        let mut args = vec!["plan", stl_s, "--tool", "ball:d=6", "-o", out_s];
        args.extend_from_slice(b);
        let o = talas(&args);
        assert_eq!(o.status.code(), Some(2), "{b:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{b:?}: {err}");
        assert!(err.contains("box.stl"), "{err}");
    }
}

/// The box's point nearest to `p` (closed form: each coordinate clamped to the box).
fn box_nearest(p: glam::DVec3) -> glam::DVec3 {
    p.clamp(
        glam::DVec3::new(-10.0, -10.0, 0.0),
        glam::DVec3::splat(10.0),
    )
}

/// The cutting poses and the plunges onto the part (a limited path plunges onto the start of
/// each piece).
fn cut_tips(path: &std::path::Path) -> Vec<talas::toolpath::Pose> {
    Toolpath::load(path)
        .unwrap()
        .poses
        .into_iter()
        .filter(|p| p.kind == MoveKind::Cut || (p.kind == MoveKind::Plunge && p.tip.z < 10.5))
        .collect()
}

/// `--boundary`: with the tool-centre rule every cut tip of a raster lies in the drawn square,
/// cuts end on its edges, and every cut pose of the unlimited path inside it is kept; with the
/// contact rule every waterline contact (the box's closed-form nearest point to the ball's
/// centre) lies in the half-plane x ≤ 0 and the contacts reach x = 0; bad text exits 2.
#[test]
fn boundary_limits_raster_and_waterline_by_centre_and_contact() {
    let stl = temp_file("boundary-cli", "box.stl", &box_stl());
    let (full, lim) = (
        stl.with_file_name("full.json"),
        stl.with_file_name("lim.json"),
    );
    let stl_s = stl.to_str().unwrap();
    let run = |out: &std::path::Path, extra: &[&str]| {
        let mut args = vec!["plan", stl_s, "--tool", "ball:d=6", "--scallop", "0.2"];
        args.extend_from_slice(&["--tolerance", "0.05", "-o", out.to_str().unwrap()]);
        args.extend_from_slice(extra);
        let o = talas(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let square = "-15,-15;0,-15;0,15;-15,15";
    run(&full, &["--strategy", "raster"]);
    run(&lim, &["--strategy", "raster", "--boundary", square]);
    let (all, kept) = (cut_tips(&full), cut_tips(&lim));
    assert!(
        kept.len() > 20 && kept.len() < all.len(),
        "{} of {}",
        kept.len(),
        all.len()
    );
    for p in &kept {
        assert!(p.tip.x <= 1e-9 && p.tip.y.abs() <= 15.0, "{}", p.tip);
    }
    let on_edge = kept.iter().filter(|p| p.tip.x.abs() < 1e-6).count();
    assert!(on_edge >= 2, "{on_edge} cuts end on the boundary");
    for p in all.iter().filter(|p| p.tip.x < -1e-3) {
        assert!(
            kept.iter().any(|q| q.tip.distance(p.tip) < 1e-12),
            "{} dropped",
            p.tip
        );
    }

    let half = "-30,-30;0,-30;0,30;-30,30";
    run(
        &lim,
        &[
            "--strategy",
            "waterline",
            "--boundary",
            half,
            "--boundary-rule",
            "contact",
        ],
    );
    let kept = cut_tips(&lim);
    assert!(kept.len() > 20);
    let mut reach = f64::MIN;
    for p in &kept {
        let c = box_nearest(p.tip + 3.0 * glam::DVec3::Z);
        assert!(c.x <= 1e-6, "contact {c} of {} outside", p.tip);
        reach = reach.max(c.x);
    }
    assert!(reach > -1e-6, "contacts reach x = {reach}");

    let out_s = lim.to_str().unwrap();
    let bad: [&[&str]; 3] = [
        &["--boundary", "1,2;3"],
        &["--boundary", "0,0;1,0;2,0"],
        &["--boundary", square, "--boundary-rule", "edge"],
    ];
    for b in bad {
        let mut args = vec!["plan", stl_s, "--tool", "ball:d=6", "--strategy", "raster"];
        args.extend_from_slice(&["-o", out_s]);
        args.extend_from_slice(b);
        let o = talas(&args);
        assert_eq!(o.status.code(), Some(2), "{b:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(err.trim().lines().count(), 1, "{b:?}: {err}");
        assert!(
            err.contains("box.stl") && err.contains("--boundary"),
            "{err}"
        );
    }
}
