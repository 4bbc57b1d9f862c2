//! Tilted work planes (3+2 machining): Fanuc `G68.2`/`G53.1`/`G69`, Sinumerik `CYCLE800`
//! (axis-by-axis) and Heidenhain `PLANE SPATIAL`/`PLANE RESET`. While a plane is active, X Y Z
//! are coordinates in the plane's frame: a point `p` is at `o + R·p` in the work coordinates
//! (`R`'s columns the plane's axes), and the machine joints are that point through the
//! machine's kinematics ([`InterpretOptions::machine`]) at the rotary axes' current angles, plus
//! the work offset: the joint-space program Talas posts with explicit A/C words for the same
//! plane reads to the same joints. Turning the tool onto the plane's +Z (`G53.1`,
//! `CYCLE800(… _DIR)`, `PLANE … TURN`) is one rapid of the rotary axes alone, to the solution
//! of the machine's inverse kinematics nearest the current angles (of the sign `_DIR`/`SEQ`
//! asks for the tilt axis, when given).
//!
//! Rotation conventions (angles in degrees):
//! - `G68.2 X Y Z I J K`: the origin, and Euler angles Z-X-Z: `R = Rz(I)·Rx(J)·Rz(K)` (Fanuc
//!   30i-B manual, "tilted working plane indexing", Eulerian angle method);
//! - `CYCLE800(_FR, _TC, _ST, _MODE, _X0, _Y0, _Z0, _A, _B, _C, _X1, _Y1, _Z1, _DIR, …)`,
//!   `_MODE` 27 (axis by axis X, Y, Z: `R = Rx(_A)·Ry(_B)·Rz(_C)`, each turn about the turned
//!   axes) or 57 (Z, Y, X: `R = Rz(_C)·Ry(_B)·Rx(_A)`); `CYCLE800()` resets the plane;
//! - `PLANE SPATIAL SPA SPB SPC`: about the fixed X, then Y, then Z: `R = Rz(SPC)·Ry(SPB)·Rx(SPA)`;
//!   `TURN` turns the axes, `STAY` only sets the plane; `PLANE RESET`.
//!
//! Under a tilted plane only straight moves are read: arcs, canned cycles, cutter
//! compensation, rotary words and a second plane on top of one are refused by name.

use glam::{DMat3, DVec3};

use super::motion::emit_line;
use super::state::{Block, Motion, State};
use super::workplane_frame::{WorkPlane, rotary_of, with_rotary};
use super::{GcodeError, InterpretOptions, Program};
use crate::machine::{MachineJoints, ToolPose};

/// How the rotary axes are turned when the plane is set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Turn {
    /// Only the frame (`STAY`, `_DIR = 0`, `G68.2` before `G53.1`).
    Stay,
    /// The solution nearest the current angles.
    Nearest,
    /// The solution whose tilt angle has this sign (−1 or +1), nearest among those.
    Sign(f64),
}

fn deg(v: f64) -> f64 {
    v.to_radians()
}

/// `Rz(i)·Rx(j)·Rz(k)`, degrees.
pub(super) fn euler_zxz(i: f64, j: f64, k: f64) -> DMat3 {
    DMat3::from_rotation_z(deg(i)) * DMat3::from_rotation_x(deg(j)) * DMat3::from_rotation_z(deg(k))
}

/// `Rz(c)·Ry(b)·Rx(a)`, degrees (PLANE SPATIAL, CYCLE800 mode 57).
pub(super) fn fixed_xyz(a: f64, b: f64, c: f64) -> DMat3 {
    DMat3::from_rotation_z(deg(c)) * DMat3::from_rotation_y(deg(b)) * DMat3::from_rotation_x(deg(a))
}

/// `Rx(a)·Ry(b)·Rz(c)`, degrees (CYCLE800 mode 27).
pub(super) fn turned_xyz(a: f64, b: f64, c: f64) -> DMat3 {
    DMat3::from_rotation_x(deg(a)) * DMat3::from_rotation_y(deg(b)) * DMat3::from_rotation_z(deg(c))
}

/// Set a tilted plane (and turn the axes onto it as `turn` says).
///
/// # Errors
/// No machine kinematics given, a plane already active, compensation on, or a tool axis the
/// machine cannot reach.
#[expect(
    clippy::too_many_arguments,
    reason = "the block and column, the interpreter's state, options and output, the plane and the turn"
)]
pub(super) fn set(
    b: &Block,
    col: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    r: DMat3,
    origin: DVec3,
    turn: Turn,
    what: &str,
) -> Result<(), GcodeError> {
    let Some(machine) = opts.machine.clone() else {
        return Err(b.err(
            col,
            format!(
                "{what}: a tilted work plane needs the machine's kinematics (give the machine: \
                 --machine)"
            ),
        ));
    };
    if machine.rotary_names().is_none() {
        return Err(b.err(
            col,
            format!(
                "{what}: machine {} has no rotary axes to tilt the plane",
                machine.name
            ),
        ));
    }
    if s.comp.side.is_some() {
        return Err(b.err(
            col,
            format!("{what}: the work plane cannot change with cutter compensation on"),
        ));
    }
    if s.work_plane.is_some() {
        return Err(b.err(
            col,
            format!("{what}: a tilted work plane is already active (cancel it first)"),
        ));
    }
    if !(r.is_finite() && origin.is_finite()) {
        return Err(b.err(col, format!("{what}: the plane's values are not finite")));
    }
    s.work_plane = Some(WorkPlane { r, origin, machine });
    if turn != Turn::Stay {
        orient(b, col, s, opts, out, turn, what)?;
    }
    Ok(())
}

/// Turn the rotary axes so that the tool stands along the active plane's +Z: one rapid of the
/// rotary axes alone.
///
/// # Errors
/// No plane active, or a tool axis the machine cannot reach (with the asked sign).
pub(super) fn orient(
    b: &Block,
    col: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    turn: Turn,
    what: &str,
) -> Result<(), GcodeError> {
    let Some(plane) = s.work_plane.clone() else {
        return Err(b.err(col, format!("{what}: no tilted work plane is active")));
    };
    let axis = plane.r * DVec3::Z;
    let now = rotary_of(&plane.machine, &s.pos);
    let pose = ToolPose {
        tip: DVec3::ZERO,
        axis,
    };
    let unreachable = |m: String| b.err(col, format!("{what}: {m}"));
    let j = match turn {
        Turn::Sign(sign) => {
            let mut c = plane
                .machine
                .inverse_candidates(&pose, &now)
                .map_err(|e| unreachable(e.to_string()))?;
            c.retain(|j| j.tilt_rad * sign >= -1e-12);
            let cost = |j: &MachineJoints| {
                (j.tilt_rad - now.tilt_rad).abs() + (j.rotary_rad - now.rotary_rad).abs()
            };
            c.sort_by(|a, b| cost(a).total_cmp(&cost(b)));
            c.into_iter().next().ok_or_else(|| {
                unreachable(format!(
                    "no solution of {} turns the tool onto the plane with the tilt axis {}",
                    plane.machine.name,
                    if sign < 0.0 { "negative" } else { "positive" }
                ))
            })?
        }
        _ => plane
            .machine
            .inverse(&pose, &now)
            .map_err(|e| unreachable(e.to_string()))?,
    };
    let end = with_rotary(&plane.machine, s.pos, &j);
    emit_line(b, s, opts, out, Motion::Rapid, end)
}

/// Cancel the plane (`G69`, `CYCLE800()`, `PLANE RESET`): the axes stay where they are.
pub(super) fn reset(s: &mut State) {
    s.work_plane = None;
}

/// Refuse what is not read under a tilted plane.
///
/// # Errors
/// An arc, a cycle, compensation or a rotary word while a plane is active.
pub(super) fn check_block(
    b: &Block,
    s: &State,
    arc_or_cycle: Option<usize>,
) -> Result<(), GcodeError> {
    if s.work_plane.is_none() {
        return Ok(());
    }
    if let Some(col) = arc_or_cycle {
        return Err(b.err(
            col,
            "arcs, canned cycles and cutter compensation under a tilted work plane are not read \
             (cancel the plane, or write them as lines)",
        ));
    }
    for l in ['A', 'B', 'C'] {
        if let Some((_, col)) = b.get(l) {
            return Err(b.err(
                col,
                format!("{l}: rotary words under a tilted work plane are not read (the plane sets the axes)"),
            ));
        }
    }
    Ok(())
}

/// Read `CYCLE800(args)`; `args` the text in the brackets (`None`/empty: the reset).
///
/// # Errors
/// A parameter that is not a number, a mode other than 27 or 57, a retract, an additive plane
/// or an offset after the turn (not read).
pub(super) fn cycle800(
    b: &Block,
    col: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    args: Option<&str>,
) -> Result<(), GcodeError> {
    let args = args.unwrap_or("").trim();
    if args.is_empty() {
        reset(s);
        return Ok(());
    }
    let mut v: Vec<Option<f64>> = Vec::new();
    for (i, a) in args.split(',').enumerate() {
        let a = a.trim();
        if a.is_empty() || (i == 1 && a.starts_with('"')) {
            v.push(None);
            continue;
        }
        let x: f64 = a
            .parse()
            .ok()
            .filter(|x: &f64| x.is_finite())
            .ok_or_else(|| {
                b.err(
                    col,
                    format!("CYCLE800: parameter {} ({a:?}) is not a number", i + 1),
                )
            })?;
        v.push(Some(x));
    }
    let at = |i: usize| v.get(i).copied().flatten().unwrap_or(0.0);
    if at(0) != 0.0 {
        return Err(b.err(col, "CYCLE800: _FR (the retract before turning, parameter 1) is not read; give 0 and retract first"));
    }
    if at(2) != 0.0 {
        return Err(b.err(
            col,
            "CYCLE800: _ST other than 0 (a new plane) is not read (additive planes)",
        ));
    }
    if (10..13).any(|i| at(i) != 0.0) {
        return Err(b.err(
            col,
            "CYCLE800: the zero offset after the turn _X1 _Y1 _Z1 (parameters 11-13) is not read",
        ));
    }
    let (a, bb, c) = (at(7), at(8), at(9));
    let mode = at(3);
    let r = if mode == 27.0 {
        turned_xyz(a, bb, c)
    } else if mode == 57.0 {
        fixed_xyz(a, bb, c)
    } else {
        return Err(b.err(
            col,
            format!("CYCLE800: _MODE {mode} is not read (27: axis by axis XYZ, 57: ZYX)"),
        ));
    };
    let dir = at(13);
    let turn = if dir == 0.0 {
        Turn::Stay
    } else {
        Turn::Sign(dir.signum())
    };
    let origin = DVec3::new(at(4), at(5), at(6)) * scale(s);
    set(b, col, s, opts, out, r, origin, turn, "CYCLE800")
}

fn scale(s: &State) -> f64 {
    if s.inch {
        crate::units::MM_PER_INCH
    } else {
        1.0
    }
}

/// Read a Heidenhain `PLANE …` block (`text` from `PLANE` on, upper case).
///
/// # Errors
/// A `PLANE` function other than `SPATIAL` and `RESET`, a malformed angle, a missing `TURN` or
/// `STAY`.
pub(super) fn plane(
    b: &Block,
    col: usize,
    s: &mut State,
    opts: &InterpretOptions,
    out: &mut Program,
    text: &str,
) -> Result<(), GcodeError> {
    let words: Vec<&str> = text.split_whitespace().collect();
    let kind = words.get(1).copied().unwrap_or("");
    let turn_word = words.iter().find(|w| matches!(**w, "TURN" | "STAY"));
    match kind {
        "RESET" => {
            reset(s);
            Ok(())
        }
        "SPATIAL" => {
            let mut angle = [None; 3];
            let mut sign = None;
            for w in &words[2..] {
                for (i, name) in ["SPA", "SPB", "SPC"].iter().enumerate() {
                    if let Some(v) = w.strip_prefix(name) {
                        let x: f64 =
                            v.parse()
                                .ok()
                                .filter(|x: &f64| x.is_finite())
                                .ok_or_else(|| {
                                    b.err(col, format!("PLANE SPATIAL: {name}{v} is not an angle"))
                                })?;
                        if let Some(slot) = angle.get_mut(i) {
                            *slot = Some(x);
                        }
                    }
                }
                if let Some(v) = w.strip_prefix("SEQ").or_else(|| w.strip_prefix("SYM")) {
                    sign = match v {
                        "+" => Some(1.0),
                        "-" => Some(-1.0),
                        _ => {
                            return Err(b.err(col, format!("PLANE SPATIAL: {w} (SEQ+ or SEQ-)")));
                        }
                    };
                }
                if w.starts_with("MB") && *w != "MB" && *w != "MB0" {
                    return Err(b.err(col, "PLANE SPATIAL: a retract MB before turning is not read; retract first and give MB0"));
                }
            }
            let [Some(a), Some(bb), Some(c)] = angle else {
                return Err(b.err(col, "PLANE SPATIAL needs SPA, SPB and SPC"));
            };
            let turn = match turn_word {
                Some(&"TURN") => sign.map_or(Turn::Nearest, Turn::Sign),
                Some(_) => Turn::Stay,
                None => {
                    return Err(b.err(col, "PLANE SPATIAL needs TURN or STAY"));
                }
            };
            set(
                b,
                col,
                s,
                opts,
                out,
                fixed_xyz(a, bb, c),
                DVec3::ZERO,
                turn,
                "PLANE SPATIAL",
            )
        }
        other => Err(b.err(
            col,
            format!("PLANE {other} is not read (PLANE SPATIAL and PLANE RESET are)"),
        )),
    }
}

/// Take a Heidenhain `PLANE …` function out of one block's text: the text before it, and the
/// function (upper case) with its 1-based column.
pub(super) fn take_plane(text: &str) -> (String, Option<(String, usize)>) {
    let upper = text.to_ascii_uppercase();
    let Some(at) = upper.find("PLANE") else {
        return (text.to_string(), None);
    };
    let before_ok = upper[..at]
        .chars()
        .next_back()
        .is_none_or(|c| !c.is_ascii_alphanumeric());
    let comment = upper[..at].contains(';') || upper[..at].contains('(');
    if !before_ok || comment {
        return (text.to_string(), None);
    }
    let end = upper[at..].find(';').map_or(upper.len(), |e| at + e);
    let func = upper[at..end].trim().to_string();
    let col = text[..at].chars().count() + 1;
    let mut rest: String = text[..at].to_string();
    rest.push_str(&" ".repeat(upper[at..end].chars().count()));
    rest.push_str(&text[end..]);
    (rest, Some((func, col)))
}
