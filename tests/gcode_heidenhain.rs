//! Heidenhain TNC drilling cycles in ISO programs (`G200`…`G209` with Q parameters, called by
//! `G79`, `M99`, `M89`) read to the motion of the same hole written as the G8x cycle (which
//! `tests/gcode_linuxcnc.rs` checks against LinuxCNC's `rs274`) or, where the TNC cycle moves
//! differently from every G8x cycle (cycle 200's pecks come back to Q200 above the last depth,
//! cycle 209 breaks the chip by reversing), as the explicit G0/G1 moves worked out by hand from
//! the cycle's description in the TNC manuals. Bad definitions and calls are refused naming the
//! line.

use glam::DVec3;
use talas::gcode::{GcodeError, InterpretOptions, MotionKind, Program, Syntax, interpret};

fn read(text: &str, syntax: &str) -> Program {
    interpret(
        text,
        &InterpretOptions::for_syntax(Syntax::from_name(syntax).unwrap()),
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// (rapid?, end, feed of a fed move, spindle sign) of every move that goes somewhere.
fn motion(p: &Program) -> Vec<(bool, DVec3, f64, f64)> {
    p.blocks
        .iter()
        .filter(|b| b.start.xyz.distance(b.end.xyz) > 1e-9)
        .map(|b| {
            let rapid = matches!(b.kind, MotionKind::Rapid);
            let feed = if rapid { 0.0 } else { b.feed_mm_per_min };
            (rapid, b.end.xyz, feed, b.spindle_rpm.signum())
        })
        .collect()
}

fn same(heidenhain: &str, reference: &str) {
    let tnc = format!("%T G71 *\n{heidenhain}N9999 M30 *\nN99999999 %T G71 *\n");
    let got = motion(&read(&tnc, "heidenhain"));
    let want = motion(&read(reference, "linuxcnc"));
    assert_eq!(got.len(), want.len(), "{got:?}\nwant {want:?}");
    for (i, (g, w)) in got.iter().zip(&want).enumerate() {
        assert_eq!(g.0, w.0, "move {i}: rapid/feed {g:?} {w:?}");
        assert!(g.1.distance(w.1) < 1e-9, "move {i}: {} not {}", g.1, w.1);
        assert!(
            (g.2 - w.2).abs() < 1e-9,
            "move {i}: feed {} not {}",
            g.2,
            w.2
        );
        assert_eq!(g.3, w.3, "move {i}: spindle");
    }
}

const START: &str = "N1 G17 G90 G40 *\nN2 T1 G17 S500 *\nN3 M3 *\nN4 G00 X10 Y5 Z10 *\n";
const REF_START: &str = "G17 G21 G90\nT1 M6 S500\nM3\nG0 X10 Y5 Z10\n";

#[test]
fn rigid_tapping_207_is_g84() {
    same(
        &format!("{START}N5 G207 Q200=2 Q201=-10 Q239=+1.5 Q203=0 Q204=0 *\nN6 G79 *\n"),
        &format!("{REF_START}G99 G84 X10 Y5 Z-10 R2 F750\nG80\nM30\n"),
    );
}

#[test]
fn reaming_201_called_by_m99_is_g85() {
    same(
        &format!(
            "{START}N5 G201 Q200=2 Q201=-7 Q206=120 Q211=0 Q208=0 Q203=0 Q204=10 *\nN6 G00 X20 M99 *\n"
        ),
        &format!("{REF_START}G98 G85 X20 Y5 Z-7 R2 F120\nG80\nM30\n"),
    );
}

#[test]
fn a_modal_m89_call_drills_at_every_position_as_g81() {
    same(
        &format!(
            "{START}N5 G200 Q200=2 Q201=-7 Q206=120 Q202=7 Q210=0 Q203=0 Q204=2 Q211=0 *\nN6 G00 X0 M89 *\nN7 X10 *\nN8 X20 M99 *\nN9 X30 *\n"
        ),
        &format!("{REF_START}G99 G81 X0 Y5 Z-7 R2 F120\nX10\nX20\nG80\nG0 X30\nM30\n"),
    );
}

#[test]
fn drilling_200_pecks_back_to_the_set_up_clearance_above_the_last_depth() {
    // Q202 = 3 from the surface: cuts to -3, -6, -7; after each cut a rapid to Q200 (Z2) and
    // back down to Q200 above the depth reached (Z-1, Z-4), dwell Q211 at the bottom, out to
    // Q204 (Z10).
    let tnc = format!(
        "{START}N5 G200 Q200=2 Q201=-7 Q206=100 Q202=3 Q210=0.5 Q203=0 Q204=10 Q211=0.25 *\nN6 G79 *\n"
    );
    same(
        &tnc,
        &format!(
            "{REF_START}G0 Z2\nG1 Z-3 F100\nG0 Z2\nZ-1\nG1 Z-6\nG0 Z2\nZ-4\nG1 Z-7\nG0 Z10\nM30\n"
        ),
    );
    let p = read(
        &format!("%T G71 *\n{tnc}N99999999 %T G71 *\n"),
        "heidenhain",
    );
    assert!(
        (p.dwell_s() - (2.0 * 0.5 + 0.25)).abs() < 1e-12,
        "{}",
        p.dwell_s()
    );
}

#[test]
fn tapping_209_breaks_the_chip_by_reversing() {
    // Q257 = 4 from the surface: in to -4, back Q256 = 1 to -3 reversed, in to -8, back to -7,
    // in to -10, out reversed to Q200 (Z2).
    same(
        &format!(
            "{START}N5 G209 Q200=2 Q201=-10 Q239=+1.5 Q203=0 Q204=0 Q257=4 Q256=1 Q336=0 *\nN6 G79 *\n"
        ),
        &format!(
            "{REF_START}G0 Z2\nG1 Z-4 F750\nM4\nZ-3\nM3\nZ-8\nM4\nZ-7\nM3\nZ-10\nM4\nZ2\nM3\nM30\n"
        ),
    );
}

fn refused(body: &str) -> GcodeError {
    let text = format!("%T G71 *\n{START}{body}N99999999 %T G71 *\n");
    interpret(&text, &InterpretOptions::for_syntax(Syntax::HeidenhainIso)).unwrap_err()
}

#[test]
fn bad_definitions_and_calls_name_the_line() {
    let e = refused("N5 G79 *\n");
    assert_eq!(e.line, 6, "{e}");
    assert!(e.message.contains("without a cycle defined"), "{e}");
    let e = refused("N5 G200 Q200=2 Q206=120 Q202=3 Q203=0 Q204=10 *\n");
    assert_eq!(e.line, 6, "{e}");
    assert!(e.message.contains("Q201"), "{e}");
    let e = refused("N5 G200 Q200=2 Q201=+7 Q206=120 Q202=3 Q203=0 Q204=10 *\n");
    assert!(e.message.contains("negative"), "{e}");
    let e = refused("N5 G201 Q200=2 Q201=-7 Q206=120 Q203=0 Q204=10 Q999=1 *\n");
    assert!(e.message.contains("Q999"), "{e}");
    assert_eq!(e.column, 48, "{e}");
    let e = refused("N5 G202 Q200=2 Q201=-7 Q206=120 Q203=0 Q204=10 Q214=1 *\n");
    assert!(e.message.contains("Q214"), "{e}");
    let e = refused("N5 G00 X1 Q200=2 *\n");
    assert!(e.message.contains("outside a cycle definition"), "{e}");
    let e = refused("N5 G204 Q200=2 *\n");
    assert!(e.message.contains("G204"), "{e}");
}
