//! The G words of a block sorted into RS274NGC's modal groups, two of one group in a block
//! refused, unknown codes named.

use super::arc::Plane;
use super::state::{Block, Cycle, Motion};
use super::{GcodeError, Syntax};

/// Group 1: a motion mode or G80.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum MotionCode {
    Move(Motion),
    Cancel,
}

/// The G words of one block, by group, each with the column of its word.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct GCodes {
    /// Group 1: G0 G1 G2 G3 G73 G74 G81–G86 G89 G80.
    pub(super) motion: Option<(MotionCode, usize)>,
    /// Group 2: G17 G18 G19.
    pub(super) plane: Option<(Plane, usize)>,
    /// Group 3: G90 (true) G91.
    pub(super) absolute: Option<(bool, usize)>,
    /// Group 4: G90.1 (true) G91.1.
    pub(super) arc_absolute: Option<(bool, usize)>,
    /// Group 5: G93 (true) G94.
    pub(super) inverse_time: Option<(bool, usize)>,
    /// Group 6: G20 (true) G21, and G70/G71 (G700/G710) in Sinumerik and Heidenhain syntax.
    pub(super) inch: Option<(bool, usize)>,
    /// Group 7: G40 G41 G42 G41.1 G42.1 (code × 10).
    pub(super) comp: Option<(i32, usize)>,
    /// Group 8: G43 G43.1 G43.4 G49 (code × 10).
    pub(super) length: Option<(i32, usize)>,
    /// Group 10: G98 (false) G99 (true: retract to the R plane).
    pub(super) retract_r: Option<(bool, usize)>,
    /// Group 12: G54..G59.3 as 0..8.
    pub(super) coord: Option<(usize, usize)>,
    /// Group 0: G4 G10 G28 G52 G53 G92 G92.1 G92.2 G92.3 (code × 10).
    pub(super) non_modal: Option<(i32, usize)>,
}

fn name(g: i32) -> String {
    if g % 10 == 0 {
        format!("G{}", g / 10)
    } else {
        format!("G{}.{}", g / 10, g % 10)
    }
}

/// What a G word that is refused is, in the refusal.
fn refusal(g: i32) -> String {
    let n = name(g);
    let what = match g {
        300 | 281 | 301 => "second home and stored home positions",
        330 | 331 => "spindle-synchronised motion",
        382..=385 => "probing",
        760 => "the lathe threading cycle",
        870 => "the back boring cycle",
        880 => "the boring cycle with a manual retract",
        50..=53 => "splines and NURBS",
        70 | 80 | 700 | 710 | 720 => "lathe modes and cycles",
        950 | 960 | 970 => "feed per revolution and constant surface speed",
        432 => "added tool length offsets",
        171 | 181 | 191 => "the UVW planes",
        _ => "",
    };
    if what.is_empty() {
        format!("unsupported G code {n}")
    } else {
        format!("unsupported G code {n} ({what})")
    }
}

/// Sort a block's G words into their groups.
///
/// # Errors
/// A [`GcodeError`] at the column of an unknown code or of the second code of a group.
pub(super) fn classify(b: &Block, syntax: Syntax) -> Result<GCodes, GcodeError> {
    let mut g = GCodes::default();
    for &(code, col) in &b.g {
        let conflict = |other: usize| {
            if other == 0 {
                return b.err(col, "two motion codes in one block".to_string());
            }
            b.err(
                col,
                format!(
                    "{} and another code of its modal group cannot share a block",
                    name(code)
                ),
            )
        };
        macro_rules! set {
            ($slot:expr, $v:expr) => {{
                if $slot.is_some() {
                    return Err(conflict(1));
                }
                $slot = Some(($v, col));
            }};
        }
        let motion = |m: MotionCode, g: &mut GCodes| {
            if g.motion.is_some() {
                return Err(conflict(0));
            }
            g.motion = Some((m, col));
            Ok(())
        };
        match code {
            0 => motion(MotionCode::Move(Motion::Rapid), &mut g)?,
            10 => motion(MotionCode::Move(Motion::Linear), &mut g)?,
            20 => motion(MotionCode::Move(Motion::Cw), &mut g)?,
            30 => motion(MotionCode::Move(Motion::Ccw), &mut g)?,
            800 => motion(MotionCode::Cancel, &mut g)?,
            c if Cycle::from_code(c).is_some() => {
                let cycle = Cycle::from_code(c).unwrap_or(Cycle::G81);
                motion(MotionCode::Move(Motion::Cycle(cycle)), &mut g)?;
            }
            170 => set!(g.plane, Plane::Xy),
            180 => set!(g.plane, Plane::Zx),
            190 => set!(g.plane, Plane::Yz),
            900 => set!(g.absolute, true),
            910 => set!(g.absolute, false),
            901 => set!(g.arc_absolute, true),
            911 => set!(g.arc_absolute, false),
            930 => set!(g.inverse_time, true),
            940 => set!(g.inverse_time, false),
            200 => set!(g.inch, true),
            210 => set!(g.inch, false),
            700 | 7000 if syntax.g70_g71_are_units() => set!(g.inch, true),
            710 | 7100 if syntax.g70_g71_are_units() => set!(g.inch, false),
            400 | 410 | 420 | 411 | 421 => set!(g.comp, code),
            430 | 431 | 434 | 490 => set!(g.length, code),
            980 => set!(g.retract_r, false),
            990 => set!(g.retract_r, true),
            540..=590 if code % 10 == 0 => set!(g.coord, ((code - 540) / 10) as usize),
            591..=593 => set!(g.coord, (code - 591 + 6) as usize),
            40 | 100 | 280 | 520 | 530 | 920..=923 => {
                if let Some((other, _)) = g.non_modal {
                    return Err(b.err(
                        col,
                        format!("{} and {} cannot share a block", name(other), name(code)),
                    ));
                }
                g.non_modal = Some((code, col));
            }
            // Heidenhain cycle definitions and the cycle call: read by `heidenhain`.
            c if syntax == Syntax::HeidenhainIso
                && (c == 790 || super::heidenhain::is_definition(c)) => {}
            // Fanuc's tilted work plane: read by `workplane` (through the interpreter).
            682 | 531 | 690 if syntax == Syntax::Rs274 => {}
            // Path control modes: accepted, no effect on the path.
            610 | 611 | 640 => {}
            _ => return Err(b.err(col, refusal(code))),
        }
    }
    Ok(g)
}
