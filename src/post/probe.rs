//! The read-back check of a dialect: a small fixed path (a rapid, a plunge, a line, a G17
//! counter-clockwise arc, a line, a clockwise arc, a line, a rapid out) is posted with the dialect for the 3-axis mill and read back with
//! Talas's own interpreter ([`crate::gcode::interpret`]); a dialect whose program does not
//! read, or reads to other positions, move kinds, arc centres or feeds, is refused when it is
//! loaded.

use glam::DVec3;

use super::{Dialect, PostError, PostOptions, post};
use crate::gcode::{InterpretOptions, MotionKind, Syntax, interpret};
use crate::machine::Machine;
use crate::toolpath::{ExactMove, MoveKind, Pose, ToolRecord, Toolpath};
use crate::tools::parse_tool_spec;

const PROBE_FEED_MM_PER_MIN: f64 = 200.0;

/// The probe path: every kind of straight move and one arc, in G17.
fn probe_path() -> Result<Toolpath, String> {
    let cutter = parse_tool_spec("flat:d=6").map_err(|e| e.to_string())?;
    let tool = ToolRecord {
        spec: "flat:d=6".into(),
        cutter,
    };
    let p = |kind, x, y, z, f| Pose::new(kind, DVec3::new(x, y, z), DVec3::Z, f);
    let mut tp = Toolpath::new(
        tool,
        vec![
            p(MoveKind::Rapid, 0.0, 0.0, 5.0, 0.0),
            p(MoveKind::Plunge, 0.0, 0.0, -1.25, PROBE_FEED_MM_PER_MIN),
            p(MoveKind::Cut, 12.5, 0.0, -1.25, 2.0 * PROBE_FEED_MM_PER_MIN),
        ],
    );
    tp.push_arc(
        DVec3::new(12.5, 7.5, -1.25),
        DVec3::Z,
        std::f64::consts::FRAC_PI_2,
        MoveKind::Cut,
        2.0 * PROBE_FEED_MM_PER_MIN,
        0.01,
    )
    .map_err(|e| e.to_string())?;
    tp.push_pose(p(
        MoveKind::Cut,
        5.0,
        15.0,
        -1.25,
        2.0 * PROBE_FEED_MM_PER_MIN,
    ));
    tp.push_arc(
        DVec3::new(5.0, 10.0, -1.25),
        DVec3::Z,
        -std::f64::consts::FRAC_PI_2,
        MoveKind::Cut,
        2.0 * PROBE_FEED_MM_PER_MIN,
        0.01,
    )
    .map_err(|e| e.to_string())?;
    tp.push_pose(p(
        MoveKind::Cut,
        0.0,
        7.5,
        -1.25,
        2.0 * PROBE_FEED_MM_PER_MIN,
    ));
    tp.push_pose(p(MoveKind::Rapid, 0.0, 7.5, 5.0, 0.0));
    Ok(tp)
}

/// Refuse a dialect whose output Talas cannot read back to the probe path.
///
/// # Errors
/// [`PostError::Dialect`] naming `file` and what failed: the post, the interpreter's error
/// with the line it read, or the pose, move kind, feed or arc centre that came back wrong.
pub fn check_reads_back(d: &Dialect, file: &str) -> Result<(), PostError> {
    let refuse = |what: String| {
        PostError::Dialect(format!(
            "{file}: a program posted with this dialect does not read back with Talas's interpreter: {what}"
        ))
    };
    let tp = probe_path().map_err(refuse)?;
    let machine = Machine::builtin("mill-3axis").map_err(|e| refuse(e.to_string()))?;
    let options = PostOptions {
        program_name: "PROBE".into(),
        spindle_rpm: 1000.0,
        ..PostOptions::default()
    };
    let text = post(&tp, &machine, d, &options).map_err(|e| refuse(e.to_string()))?;
    let syntax = Syntax::from_name(&d.name).unwrap_or_else(|| Syntax::detect(&text));
    let program = interpret(&text, &InterpretOptions::for_syntax(syntax)).map_err(|e| {
        let line = text.lines().nth(e.line.saturating_sub(1)).unwrap_or("");
        refuse(format!("{e} (in {line:?})"))
    })?;
    let tol = 0.5 * 10f64.powi(-(d.decimals_linear as i32)) * 3f64.sqrt() + 1e-9;
    let mut blocks = program.blocks.iter();
    for (k, pose) in tp.poses.iter().enumerate().skip(1) {
        // The samples inside an arc are no block's end.
        if tp.exact.iter().any(|s| s.from < k && k < s.to) {
            continue;
        }
        let Some(b) = blocks.find(|b| b.end.xyz.distance(pose.tip) <= tol) else {
            return Err(refuse(format!(
                "no block reaches the probe's pose {k} at {:?} mm",
                pose.tip.to_array()
            )));
        };
        let rapid = matches!(b.kind, MotionKind::Rapid);
        if rapid != (pose.kind == MoveKind::Rapid) {
            return Err(refuse(format!(
                "line {} reaches pose {k} by a {} move, not a {}",
                b.source_line,
                if rapid { "rapid" } else { "feed" },
                if pose.kind == MoveKind::Rapid {
                    "rapid"
                } else {
                    "feed"
                },
            )));
        }
        if !rapid && !b.inverse_time {
            let ftol = 0.5 * 10f64.powi(-(d.decimals_feed as i32)) + 1e-9;
            if (b.feed_mm_per_min - pose.feed_mm_per_min).abs() > ftol {
                return Err(refuse(format!(
                    "line {} feeds at {} mm/min, not {} mm/min",
                    b.source_line, b.feed_mm_per_min, pose.feed_mm_per_min
                )));
            }
        }
        if let Some(seg) = tp.exact.iter().find(|s| s.to == k)
            && let ExactMove::Arc(a) = seg.exact
            && let Some(arc) = b.kind.arc()
        {
            if arc.centre.distance(a.centre) > 2.0 * tol {
                return Err(refuse(format!(
                    "line {} reads the arc's centre at {:?} mm, not {:?} mm",
                    b.source_line,
                    arc.centre.to_array(),
                    a.centre.to_array()
                )));
            }
            let ccw = matches!(b.kind, MotionKind::ArcCcw(_)) == (arc.normal.dot(a.normal) > 0.0);
            if ccw != (a.sweep_rad > 0.0) || (arc.sweep_rad - a.sweep_rad.abs()).abs() > 1e-3 {
                return Err(refuse(format!(
                    "line {} reads an arc sweeping {:.4} rad {}, not {:.4} rad {}",
                    b.source_line,
                    arc.sweep_rad,
                    if ccw {
                        "counter-clockwise"
                    } else {
                        "clockwise"
                    },
                    a.sweep_rad.abs(),
                    if a.sweep_rad > 0.0 {
                        "counter-clockwise"
                    } else {
                        "clockwise"
                    },
                )));
            }
        }
    }
    Ok(())
}
