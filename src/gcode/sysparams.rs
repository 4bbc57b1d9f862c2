//! The parameters the controller owns (see [`super::params`]): offsets, tool and position as
//! `#5161`.. and `#<_x>`.., computed from the modal state, in program units.

use glam::DVec3;

use super::arc::Plane;
use super::params::FIRST_SYSTEM;
use super::state::{Cycle, Motion, Side, State};
use crate::units::MM_PER_INCH;

fn scale(s: &State) -> f64 {
    if s.inch { MM_PER_INCH } else { 1.0 }
}

fn axis(v: DVec3, i: usize) -> f64 {
    v.to_array().get(i).copied().unwrap_or(0.0)
}

/// The current position in program coordinates: X Y Z in program units, A B C in degrees.
fn position(s: &State) -> [f64; 6] {
    let k = scale(s);
    let p = (s.comp.programmed.unwrap_or(s.pos.xyz) - s.total_offset()) / k;
    let deg = |v: Option<f64>| v.unwrap_or(0.0).to_degrees();
    [p.x, p.y, p.z, deg(s.pos.a), deg(s.pos.b), deg(s.pos.c)]
}

/// A numbered parameter: the controller's value from `#5161` on, else the stored one.
///
/// # Errors
/// A message for reading the position (`#5420`..) while cutter compensation is on.
pub(super) fn numbered(s: &State, index: usize) -> Result<f64, String> {
    if index < FIRST_SYSTEM {
        return Ok(s.params.get(index));
    }
    let k = scale(s);
    let o = &s.offsets;
    Ok(match index {
        // The G28 home comes from the options: not known here, 0 as in LinuxCNC's default.
        5161..=5169 => 0.0,
        5210 => f64::from(u8::from(o.axis_applied)),
        5211..=5213 => axis(o.axis_params, index - 5211) / k,
        5220 => (s.work_offset + 1) as f64,
        5221..=5399 => {
            let system = (index - 5221) / 20;
            let i = (index - 5221) % 20;
            if i < 3 {
                axis(o.work.get(system).copied().unwrap_or(DVec3::ZERO), i) / k
            } else {
                0.0
            }
        }
        5400 => f64::from(s.loaded_tool),
        5401..=5403 => axis(o.tool, index - 5401) / k,
        5420..=5425 => {
            if s.comp.side.is_some() {
                return Err(
                    "the current position (#5420..#5428) cannot be read with cutter \
                     compensation on"
                        .into(),
                );
            }
            position(s).get(index - 5420).copied().unwrap_or(0.0)
        }
        _ => s.params.get(index),
    })
}

/// A predefined named parameter (`None`: not one of them).
pub(super) fn named(s: &State, name: &str) -> Option<f64> {
    let flag = |b: bool| f64::from(u8::from(b));
    let p = || position(s);
    Some(match name {
        "_x" => p()[0],
        "_y" => p()[1],
        "_z" => p()[2],
        "_a" => p()[3],
        "_b" => p()[4],
        "_c" => p()[5],
        "_feed" => s
            .feed
            .map_or(0.0, |f| if s.inverse_time { f } else { f / scale(s) }),
        "_rpm" => s.spindle_speed,
        "_current_tool" => f64::from(s.loaded_tool),
        "_selected_tool" => f64::from(s.tool),
        "_metric" => flag(!s.inch),
        "_imperial" => flag(s.inch),
        "_absolute" => flag(s.absolute),
        "_incremental" => flag(!s.absolute),
        "_inverse_time" => flag(s.inverse_time),
        "_units_per_minute" => flag(!s.inverse_time),
        "_plane" => match s.plane {
            Plane::Xy => 170.0,
            Plane::Zx => 180.0,
            Plane::Yz => 190.0,
        },
        "_motion_mode" => match s.motion {
            None => 800.0,
            Some(Motion::Rapid) => 0.0,
            Some(Motion::Linear) => 10.0,
            Some(Motion::Cw) => 20.0,
            Some(Motion::Ccw) => 30.0,
            Some(Motion::Cycle(c)) => match c {
                Cycle::G73 => 730.0,
                Cycle::G74 => 740.0,
                Cycle::G81 => 810.0,
                Cycle::G82 => 820.0,
                Cycle::G83 => 830.0,
                Cycle::G84 => 840.0,
                Cycle::G85 => 850.0,
                Cycle::G86 => 860.0,
                Cycle::G89 => 890.0,
            },
        },
        "_ccomp" => match s.comp.side {
            None => 400.0,
            Some(Side::Left) => 410.0,
            Some(Side::Right) => 420.0,
        },
        "_coord_system" => match s.work_offset {
            n @ 0..=5 => 540.0 + 10.0 * n as f64,
            n => 590.0 + (n - 5) as f64,
        },
        "_tool_offset" => flag(s.offsets.tool != DVec3::ZERO),
        "_retract_r_plane" => flag(s.retract_r_plane),
        "_retract_old_z" => flag(!s.retract_r_plane),
        "_line" => s.line as f64,
        _ => return None,
    })
}
