//! Sinumerik 840D drilling cycles (CYCLE81–CYCLE86, CYCLE840, once or with `MCALL` and a
//! position list) read to the same canonical motion as the G8x program that does the same
//! (issue 32). The G8x forms are themselves checked against LinuxCNC's `rs274` in
//! `tests/gcode_linuxcnc.rs`; the peck depths here are also counted in closed form.

use glam::DVec3;
use talas::gcode::{InterpretOptions, MotionKind, Program, Syntax, interpret};

fn siemens(text: &str) -> Program {
    let opts = InterpretOptions::for_syntax(Syntax::Siemens);
    interpret(text, &opts).unwrap_or_else(|e| panic!("{text}\n{e}"))
}

fn rs274(text: &str) -> Program {
    interpret(text, &InterpretOptions::default()).unwrap_or_else(|e| panic!("{text}\n{e}"))
}

/// (rapid?, end, feed, spindle rpm × direction) of every move that goes somewhere.
fn motion(p: &Program) -> Vec<(bool, DVec3, f64)> {
    p.blocks
        .iter()
        .filter(|b| b.start.xyz.distance(b.end.xyz) > 1e-9)
        .map(|b| {
            let rapid = matches!(b.kind, MotionKind::Rapid);
            (
                rapid,
                b.end.xyz,
                if rapid { 0.0 } else { b.feed_mm_per_min },
            )
        })
        .collect()
}

fn same(sie: &str, iso: &str) {
    let (a, b) = (siemens(sie), rs274(iso));
    let (ma, mb) = (motion(&a), motion(&b));
    assert_eq!(ma.len(), mb.len(), "{sie}\n{ma:?}\n{mb:?}");
    for (i, (x, y)) in ma.iter().zip(&mb).enumerate() {
        assert_eq!(x.0, y.0, "move {i} rapid/feed\n{ma:?}\n{mb:?}");
        assert!(x.1.distance(y.1) < 1e-4, "move {i}: {} not {}", x.1, y.1);
        assert!(
            (x.2 - y.2).abs() < 1e-9,
            "move {i}: feed {} not {}",
            x.2,
            y.2
        );
    }
    assert!(
        (a.dwell_s() - b.dwell_s()).abs() < 1e-9,
        "dwell {} not {}",
        a.dwell_s(),
        b.dwell_s()
    );
}

const START: &str = "G17 G90 G94 G71\nS1000 M3\nG0 X10 Y5 Z20\nF100\n";
const START_ISO: &str = "G17 G90 G94 G21\nS1000 M3\nG0 X10 Y5 Z20\nF100\n";

#[test]
fn each_cycle_reads_as_its_g8x() {
    let cases = [
        // RTP=RFP+SDIS: retract to the R plane (G99).
        ("CYCLE81(2, 0, 2, -7)", "G99 G81 X10 Y5 Z-7 R2"),
        // RTP above: G98 from a start at RTP.
        ("CYCLE81(20, 0, 2, -7, )", "G98 G81 X10 Y5 Z-7 R2"),
        ("CYCLE82(20, 0, 2, , 7, 0.5)", "G98 G82 X10 Y5 Z-7 R2 P0.5"),
        // Deep hole, chip removal: first depth R - 3 then 3 each.
        (
            "CYCLE83(20, 0, 2, -7, , -1, , 3, 0, 0, 1, 1)",
            "G98 G83 X10 Y5 Z-7 R2 Q3",
        ),
        // Chip break.
        (
            "CYCLE83(2, 0, 2, -7, , -1, , 3, 0, 0, 1, 0)",
            "G99 G73 X10 Y5 Z-7 R2 Q3",
        ),
        (
            "CYCLE84(2, 0, 2, -7, , 0, 3, , 1, 0, 1000, 1000)",
            "G99 G84 X10 Y5 Z-7 R2 P0",
        ),
        (
            "CYCLE840(2, 0, 2, -7, , 0.2, 3, 0, 0, , 1)",
            "G99 G84 X10 Y5 Z-7 R2 P0.2",
        ),
        (
            "CYCLE85(2, 0, 2, -7, , 0, 100, 100)",
            "G99 G85 X10 Y5 Z-7 R2",
        ),
        (
            "CYCLE85(2, 0, 2, -7, , 0.3, 100, 100)",
            "G99 G89 X10 Y5 Z-7 R2 P0.3",
        ),
        (
            "CYCLE86(20, 0, 2, -7, , 0.3, 3, 0, 0, 0, 0)",
            "G98 G86 X10 Y5 Z-7 R2 P0.3",
        ),
    ];
    for (sie, iso) in cases {
        same(
            &format!("{START}{sie}\nM30\n"),
            &format!("{START_ISO}{iso}\nG80\nM30\n"),
        );
    }
}

#[test]
fn cycle85_feeds_in_and_out_at_its_own_rates_and_rapids_to_rtp() {
    let p = siemens(&format!(
        "{START}CYCLE85(20, 0, 2, -7, , 0, 50, 300)\nM30\n"
    ));
    let m = motion(&p);
    let tail: Vec<_> = m.iter().rev().take(3).rev().copied().collect();
    assert_eq!(
        tail,
        vec![
            (false, DVec3::new(10.0, 5.0, -7.0), 50.0),
            (false, DVec3::new(10.0, 5.0, 2.0), 300.0),
            (true, DVec3::new(10.0, 5.0, 20.0), 0.0),
        ]
    );
}

#[test]
fn cycle83_pecks_are_fdep_then_dam() {
    // RFP 0, SDIS 1, first depth -2, then 2.5 each to DP -10: -2, -4.5, -7, -9.5, then -10.
    let p = siemens(&format!(
        "{START}CYCLE83(20, 0, 1, -10, , -2, , 2.5, 0, 0, 1, 1)\nM30\n"
    ));
    let feeds: Vec<f64> = motion(&p).iter().filter(|m| !m.0).map(|m| m.1.z).collect();
    let want = [-2.0, -4.5, -7.0, -9.5, -10.0];
    assert_eq!(feeds.len(), want.len(), "{feeds:?}");
    for (f, w) in feeds.iter().zip(want) {
        // Each feed starts 0.254 mm above the last depth.
        assert!((f - w).abs() < 1e-12, "{feeds:?}");
    }
}

#[test]
fn mcall_runs_the_cycle_at_every_position_until_a_bare_mcall() {
    let sie =
        format!("{START}MCALL CYCLE81(20, 0, 2, -7)\nX10 Y5\nX30\nY25\nMCALL\nG0 X0 Y0\nM30\n");
    let iso = format!("{START_ISO}G98 G81 X10 Y5 Z-7 R2\nX30\nY25\nG80\nG0 X0 Y0\nM30\n");
    same(&sie, &iso);
}

#[test]
fn g4_f_dwells_seconds_and_keeps_the_feed() {
    let p = siemens("G71 G90 G94\nG1 X1 F200\nG4 F1.5\nX2\nM30\n");
    assert!((p.dwell_s() - 1.5).abs() < 1e-12);
    assert!(
        p.blocks
            .iter()
            .all(|b| (b.feed_mm_per_min - 200.0).abs() < 1e-9)
    );
}

#[test]
fn bad_calls_name_the_place() {
    let opts = InterpretOptions::for_syntax(Syntax::Siemens);
    for (text, says) in [
        ("F100\nCYCLE81(, 0, 2, -7)\n", "RTP"),
        ("F100\nCYCLE81(20, 0, 2)\n", "DP or DPR"),
        ("F100\nCYCLE81(20, 0, 2, R1)\n", "not a number"),
        ("F100\nCYCLE81(1, 0, 2, -7)\n", "below RFP + SDIS"),
        ("G0 X0\nCYCLE81(20, 0, 2, -7)\n", "zero feed"),
        ("F100\nCYCLE81(20, 0, 2, -7\n", "not closed"),
        (
            "S100 M3 F100\nCYCLE86(20, 0, 2, -7, , 0, 3, 1, 0, 0, 0)\n",
            "lift-off",
        ),
        (
            "F100\nCYCLE84(2, 0, 2, -7, , 0, 3, , 1, 0, 1000, 1000)\n",
            "spindle",
        ),
        ("F100\nHOLES1(0, 0, 0, 10, 10, 3)\n", "HOLES1"),
    ] {
        let e = interpret(text, &opts).unwrap_err().to_string();
        assert!(e.contains(says) && e.contains("line 2"), "{text}: {e}");
    }
}
