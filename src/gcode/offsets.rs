//! Coordinate offsets as LinuxCNC applies them: machine = program + work offset (G54..G59.3,
//! set with G10 L2/L20) + axis offset (G92/G52) + tool length offset (G43).
//!
//! - `G92 X..`: the axis offset that makes the current position read the given coordinates;
//!   `G52 X..` sets the axis offset itself (LinuxCNC keeps one axis offset for both). `G92.1`
//!   clears it and its parameters `#5211`..; `G92.2` clears it and keeps the parameters;
//!   `G92.3` applies the parameters again.
//! - `G10 L2 Pn X..` sets coordinate system n (1 = G54 .. 9 = G59.3, 0 = the active one);
//!   `G10 L20 Pn X..` sets it so that the current position reads the given coordinates.
//! - `G43 Hn` applies tool n's length offsets from the tool table (`H` left out: the tool in
//!   the spindle, loaded by `M6`); `G43.1 Z..` gives the offset directly; `G49` cancels.
//!   Without a tool table the offsets are zero and G43 only records its H.
//!
//! Offsets of rotary axes, G10 rotations (R) and the tool-table forms of G10 (L1, L10, L11)
//! are refused.

use glam::DVec3;

use super::state::{Block, State, u32_word};
use super::{GcodeError, InterpretOptions};

/// The X Y Z words of an offset block, scaled to mm, and a refusal of rotary words.
fn xyz_words(b: &Block, scale: f64, what: &str) -> Result<[Option<f64>; 3], GcodeError> {
    for l in ['A', 'B', 'C'] {
        if let Some((_, c)) = b.get(l) {
            return Err(b.err(
                c,
                format!("{what} offsets of rotary axes ({l}) are not supported"),
            ));
        }
    }
    Ok(['X', 'Y', 'Z'].map(|l| b.get(l).map(|(v, _)| v * scale)))
}

/// G52, G92, G92.1, G92.2, G92.3 (`code` × 10).
///
/// # Errors
/// A [`GcodeError`] with compensation on, without axis words (G52/G92) or for rotary words.
pub(super) fn axis_offset(
    b: &Block,
    s: &mut State,
    code: i32,
    col: usize,
    scale: f64,
) -> Result<(), GcodeError> {
    if s.comp.side.is_some() {
        return Err(b.err(
            col,
            "axis offsets (G52/G92) cannot change with cutter compensation on",
        ));
    }
    let o = &mut s.offsets;
    match code {
        520 | 920 => {
            let words = xyz_words(b, scale, if code == 520 { "G52" } else { "G92" })?;
            if words.iter().all(Option::is_none) {
                return Err(b.err(col, "G52/G92 needs at least one of X, Y, Z"));
            }
            let here = s.comp.programmed.unwrap_or(s.pos.xyz).to_array();
            let work = o.work.get(s.work_offset).copied().unwrap_or(DVec3::ZERO);
            let mut axis = o.axis.to_array();
            for (i, w) in words.iter().enumerate() {
                let (Some(v), Some(slot)) = (w, axis.get_mut(i)) else {
                    continue;
                };
                let base = work.to_array().get(i).copied().unwrap_or(0.0)
                    + o.tool.to_array().get(i).copied().unwrap_or(0.0);
                *slot = if code == 520 {
                    *v
                } else {
                    here.get(i).copied().unwrap_or(0.0) - base - v
                };
            }
            o.axis = DVec3::from_array(axis);
            o.axis_params = o.axis;
            o.axis_applied = true;
        }
        921 | 922 => {
            o.axis = DVec3::ZERO;
            o.axis_applied = false;
            if code == 921 {
                o.axis_params = DVec3::ZERO;
            }
        }
        _ => {
            o.axis = o.axis_params;
            o.axis_applied = o.axis != DVec3::ZERO;
        }
    }
    Ok(())
}

/// G10 L2 / L20.
///
/// # Errors
/// A [`GcodeError`] for another L, a P outside 0..=9, an R rotation or rotary words.
pub(super) fn g10(b: &Block, s: &mut State, col: usize, scale: f64) -> Result<(), GcodeError> {
    let l = b.get('L').map(|(v, _)| v);
    let l = match l {
        Some(v) if v == 2.0 || v == 20.0 => v as u32,
        Some(v) => {
            return Err(b.err(
                col,
                format!("G10 L{v} is not supported (only L2 and L20 set work offsets; the tool table forms L1, L10, L11 are not read)"),
            ));
        }
        None => return Err(b.err(col, "G10 needs L2 or L20")),
    };
    if let Some((_, c)) = b.get('R') {
        return Err(b.err(c, "G10 R (a rotated coordinate system) is not supported"));
    }
    let p = match b.get('P') {
        Some((p, pc)) => u32_word(p).filter(|p| *p <= 9).ok_or_else(|| {
            b.err(
                pc,
                "G10 P must be 0 (the active system) or 1..9 (G54..G59.3)",
            )
        })?,
        None => return Err(b.err(col, "G10 needs P (the coordinate system)")),
    };
    let system = if p == 0 {
        s.work_offset
    } else {
        (p - 1) as usize
    };
    let words = xyz_words(b, scale, "G10")?;
    let here = s.comp.programmed.unwrap_or(s.pos.xyz).to_array();
    let o = &mut s.offsets;
    let Some(slot) = o.work.get_mut(system) else {
        return Ok(());
    };
    let mut w = slot.to_array();
    for (i, v) in words.iter().enumerate() {
        let (Some(v), Some(axis)) = (v, w.get_mut(i)) else {
            continue;
        };
        *axis = if l == 2 {
            *v
        } else {
            here.get(i).copied().unwrap_or(0.0)
                - o.axis.to_array().get(i).copied().unwrap_or(0.0)
                - o.tool.to_array().get(i).copied().unwrap_or(0.0)
                - v
        };
    }
    *slot = DVec3::from_array(w);
    Ok(())
}

/// The tool-table entry of tool `number` for an H or D word: its offsets and diameter.
/// Without a table, `None`; tool 0 means the tool in the spindle.
///
/// # Errors
/// A [`GcodeError`] at `col` when a table is given and does not list the tool.
pub(super) fn tool_entry(
    b: &Block,
    s: &State,
    opts: &InterpretOptions,
    number: u32,
    col: usize,
) -> Result<Option<(DVec3, f64)>, GcodeError> {
    let Some(table) = &opts.tool_table else {
        return Ok(None);
    };
    let number = if number == 0 { s.loaded_tool } else { number };
    if number == 0 {
        return Ok(Some((DVec3::ZERO, 0.0)));
    }
    match table.get(number) {
        Some(t) => Ok(Some((t.offset_mm, t.diameter_mm))),
        None => Err(b.err(
            col,
            format!("requested tool {number} is not in the tool table"),
        )),
    }
}

/// G43 (`code` 430), G43.1 (431), G43.4 (434), G49 (490).
///
/// # Errors
/// A [`GcodeError`] with compensation on, for an H that is not a tool number or a tool not
/// in the table.
pub(super) fn tool_length(
    b: &Block,
    s: &mut State,
    opts: &InterpretOptions,
    code: i32,
    col: usize,
    scale: f64,
) -> Result<(), GcodeError> {
    if s.comp.side.is_some() {
        return Err(b.err(
            col,
            "the tool length offset cannot change with cutter compensation on",
        ));
    }
    match code {
        490 => {
            s.tool_length_h = None;
            s.tcp = false;
            s.offsets.tool = DVec3::ZERO;
        }
        431 => {
            let words = xyz_words(b, scale, "G43.1")?;
            let mut t = s.offsets.tool.to_array();
            for (slot, w) in t.iter_mut().zip(words) {
                if let Some(v) = w {
                    *slot = v;
                }
            }
            s.offsets.tool = DVec3::from_array(t);
        }
        _ => {
            let (h, hc) = match b.get('H') {
                Some((h, hc)) => (
                    u32_word(h).ok_or_else(|| b.err(hc, "H must be a non-negative integer"))?,
                    hc,
                ),
                None => (s.tool, col),
            };
            s.tool_length_h = Some(h);
            if code == 434 {
                s.tcp = true;
                return Ok(());
            }
            let number = if b.get('H').is_some() {
                h
            } else {
                s.loaded_tool
            };
            let entry = tool_entry(b, s, opts, number, hc)?;
            s.offsets.tool = entry.map_or(DVec3::ZERO, |(o, _)| o);
        }
    }
    Ok(())
}
