//! The interpreter's RS274NGC reading beyond plain words (issue 32): the `%` frame and dialect
//! detection, parameters and expressions, O-word subroutines and loops (bounded), canned
//! cycles, cutter compensation, tool tables and lengths, G52/G92/G10 offsets, zero feeds,
//! the refusals that name what is not read, and the line-by-line session.
//! The exact LinuxCNC equivalence of all of these is `tests/gcode_linuxcnc.rs`.

use std::time::Instant;

use glam::DVec3;
use talas::gcode::{
    InterpretOptions, Joints, LengthUnit, MotionKind, Program, Session, Syntax, ToolTable,
    interpret,
};

fn run(text: &str) -> Program {
    interpret(text, &InterpretOptions::default()).unwrap_or_else(|e| panic!("{text}\n{e}"))
}

fn err(text: &str) -> talas::gcode::GcodeError {
    interpret(text, &InterpretOptions::default()).unwrap_err()
}

fn ends(p: &Program) -> Vec<DVec3> {
    p.blocks.iter().map(|b| b.end.xyz).collect()
}

fn with_table(table: &str) -> InterpretOptions {
    InterpretOptions {
        tool_table: Some(ToolTable::parse(table, LengthUnit::Mm).unwrap()),
        ..InterpretOptions::default()
    }
}

fn near(a: DVec3, b: DVec3) -> bool {
    a.distance(b) < 1e-9
}

#[test]
fn a_closing_percent_ends_the_program() {
    // LinuxCNC's rule: the first line `%` opens, the next `%` closes; nothing after it runs.
    let p = run("%\nG1 X1 F100\n%\nG1 X100\nM2\n");
    assert_eq!(ends(&p), vec![DVec3::new(1.0, 0.0, 0.0)]);
    assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
    // A Fanuc tape end without the opening one ends it too.
    let p = run("G1 X1 F100\n%\nG1 X100\n");
    assert_eq!(p.blocks.len(), 1);
    // M2 / M30 as before: words after them are a warning, subroutines after them are not.
    let p = run("G1 X1 F100\nM2\no1 sub\nG1 X9\no1 endsub\n");
    assert_eq!(p.blocks.len(), 1);
    assert!(p.diagnostics.is_empty(), "{:?}", p.diagnostics);
}

#[test]
fn talas_posts_read_without_naming_their_syntax() {
    for (file, syntax) in [
        ("small-siemens.ngc", Syntax::Siemens),
        ("small-siemens-tcp.ngc", Syntax::Siemens),
        ("small-heidenhain.ngc", Syntax::HeidenhainIso),
        ("small-heidenhain-tcp.ngc", Syntax::HeidenhainIso),
        ("small-linuxcnc.ngc", Syntax::Rs274),
        ("small-fanuc.ngc", Syntax::Rs274),
        ("small-grbl.ngc", Syntax::Rs274),
    ] {
        let text = std::fs::read_to_string(format!("tests/data/post/{file}")).unwrap();
        assert_eq!(Syntax::detect(&text), syntax, "{file}");
        let p = interpret(&text, &InterpretOptions::for_syntax(syntax))
            .unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(p.blocks.len() > 5, "{file}");
        // The Heidenhain end frame `N99999999 %NAME G71 *` after M30 is not a stray word.
        assert!(p.diagnostics.is_empty(), "{file}: {:?}", p.diagnostics);
    }
}

#[test]
fn parameters_take_effect_after_their_line() {
    let p = run("#1=5 G0 X#1\nG0 Y#1\n#<d> = [#1 * 2] #2 = #<_x>\nG0 Z[#<d> + #2]\n");
    // Line 1 reads #1 before it is set (0: no motion); line 2 sees 5; #<_x> is 0.
    assert_eq!(
        ends(&p),
        vec![DVec3::new(0.0, 5.0, 0.0), DVec3::new(0.0, 5.0, 10.0)]
    );
    let e = err("G0 X1\nG0 X#<depth>\n");
    assert_eq!((e.line, e.column), (2, 4));
    assert!(e.message.contains("#<depth>"), "{}", e.message);
    let e = err("G0 X[1/0]");
    assert!(e.message.contains("division"), "{}", e.message);
    let e = err("#5221 = 3");
    assert!(e.message.contains("read-only"), "{}", e.message);
    // A named local of the main program is not seen inside a subroutine; a global is.
    let e = err("#<d> = 1\n#<_g> = 2\no1 call\nM2\no1 sub\nG0 X#<_g> Y#<d>\no1 endsub\n");
    assert_eq!(e.line, 6);
}

#[test]
fn subroutines_loops_and_conditionals() {
    let text = "o<hole> sub\n G0 X#1 Y#2\n G1 Z-1 F100\n G0 Z1\no<hole> endsub [#1 * 10]\n\
                #3 = 0\no10 while [#3 LT 3]\n o<hole> call [#3] [1]\n #3 = [#3 + 1]\no10 endwhile\n\
                o20 if [#<_value> EQ 20]\n G0 X99\no20 elseif [1]\n G0 X-99\no20 else\n G0 X-1\no20 endif\n\
                o30 repeat [2]\n G0 Y[#<_y> + 1]\no30 endrepeat\nM2\n";
    let p = run(text);
    let xs: Vec<f64> = p.blocks.iter().map(|b| b.end.xyz.x).collect();
    assert_eq!(xs.len(), 3 * 3 + 1 + 2);
    assert_eq!(xs[9], 99.0, "the if branch ran, not elseif or else");
    assert_eq!(p.blocks[11].end.xyz.y, 3.0);
    // Arguments #1..#30 are restored after the call.
    let p = run("#1 = 7\no1 call [3]\nG0 X#1\nM2\no1 sub\nG0 Y#1\no1 endsub\n");
    assert_eq!(
        ends(&p),
        vec![DVec3::new(0.0, 3.0, 0.0), DVec3::new(7.0, 3.0, 0.0)]
    );
}

#[test]
fn o_word_structure_errors_name_their_lines() {
    for (text, line, what) in [
        ("G0 X1\no1 endif\n", 2, "if"),
        ("o1 while [1]\nG0 X1\n", 1, "never closed"),
        ("o2 do\no2 break\no3 while [0]\n", 3, "never closed"),
        ("o5 call\n", 1, "not defined"),
        ("o1 sub\no2 sub\no2 endsub\no1 endsub\n", 2, "nested"),
        ("o1 if [1]\no1 break\no1 endif\n", 2, "loop"),
        ("o1 return\n", 1, "o1 sub"),
    ] {
        let e = err(text);
        assert_eq!(e.line, line, "{text}: {e}");
        assert!(e.message.contains(what), "{text}: {e}");
    }
}

#[test]
fn runaway_loops_and_recursion_end_with_an_error() {
    for text in [
        "#1 = 0\no1 while [1]\n#1 = [#1 + 1]\no1 endwhile\n",
        "o1 do\nG1 X1 F10\nG1 X0\no1 while [1]\n",
        "o1 sub\no1 call\no1 endsub\no1 call\n",
        "o1 sub\no2 call\no2 call\no1 endsub\no2 sub\no3 call\no3 call\no2 endsub\n\
         o3 sub\no4 call\no4 call\no3 endsub\no4 sub\no4 repeat [1000]\nG1 X1 F1\no4 endrepeat\no4 endsub\n\
         o9 repeat [100000]\no1 call\no9 endrepeat\n",
    ] {
        let t = Instant::now();
        let e = err(text);
        assert!(
            t.elapsed().as_secs_f64() < 20.0,
            "{text}: {:?}",
            t.elapsed()
        );
        assert!(
            e.message.contains("more than it has") || e.message.contains("nested deeper"),
            "{text}: {e}"
        );
    }
}

#[test]
fn canned_cycles_expand_into_moves() {
    // G81 with G98 from Z10, a work offset, then a second hole at the initial level.
    let mut opts = InterpretOptions::default();
    opts.work_offsets[1] = DVec3::new(100.0, 0.0, -50.0);
    let p = interpret(
        "G55 G0 X0 Y0 Z10\nG98 G81 X5 Y5 Z-3 R2 F100\nX8\nG80\n",
        &opts,
    )
    .unwrap();
    let want = [
        DVec3::new(105.0, 5.0, -40.0),
        DVec3::new(105.0, 5.0, -48.0),
        DVec3::new(105.0, 5.0, -53.0),
        DVec3::new(105.0, 5.0, -40.0),
        DVec3::new(108.0, 5.0, -40.0),
        DVec3::new(108.0, 5.0, -48.0),
        DVec3::new(108.0, 5.0, -53.0),
        DVec3::new(108.0, 5.0, -40.0),
    ];
    let got = ends(&p);
    assert_eq!(got.len(), want.len() + 1, "{got:?}");
    for (g, w) in got.iter().skip(1).zip(want) {
        assert!(near(*g, w), "{g} != {w}");
    }
    assert!(matches!(p.blocks[3].kind, MotionKind::Linear));
    assert_eq!(p.blocks[3].feed_mm_per_min, 100.0);
    // G83: pecks of 2 from R1 to Z-5, back to R between, 0.254 mm above the last depth.
    let p = run("G0 Z5\nG99 G83 X0 Y0 Z-5 R1 Q2 F50\n");
    let z: Vec<f64> = p.blocks.iter().map(|b| b.end.xyz.z).collect();
    let want = [5.0, 1.0, -1.0, 1.0, -0.746, -3.0, 1.0, -2.746, -5.0, 1.0];
    assert_eq!(z.len(), want.len(), "{z:?}");
    for (a, b) in z.iter().zip(want) {
        assert!((a - b).abs() < 1e-9, "{z:?}");
    }
    // G82 and G89 dwell at the bottom.
    let p = run("G0 Z5\nG82 X0 Y0 Z-1 R1 P0.5 F50\nG80\n");
    assert_eq!(p.dwells.len(), 1);
    assert_eq!((p.dwells[0].before_block, p.dwells[0].seconds), (3, 0.5));
    // G84 reverses the spindle on the way out.
    let p = run("S500 M3\nG0 Z5\nG84 X0 Y0 Z-4 R1 F500\n");
    let out = p.blocks.last().unwrap();
    assert!(matches!(out.kind, MotionKind::Linear) && out.spindle_rpm < 0.0);
}

#[test]
fn canned_cycle_errors() {
    for (text, what) in [
        ("G0 Z5\nG81 X0 Y0 Z-1 F10\n", "R (the retract plane)"),
        ("G0 Z5\nG81 X0 Y0 R1 F10\n", "Z (the bottom"),
        ("G0 Z5\nG81 X0 Y0 Z3 R1 F10\n", "below the bottom"),
        ("G0 Z5\nG83 X0 Y0 Z-3 R1 F10\n", "Q (the peck depth)"),
        ("G0 Z5\nG82 X0 Y0 Z-3 R1 F10\n", "P (the dwell"),
        ("G0 Z5\nG84 X0 Y0 Z-3 R1 F10\n", "spindle"),
        ("G0 Z5\nG81 X0 Y0 Z-3 R1\n", "zero feed"),
        ("G0 Z5\nG81 X0 Y0 Z-3 R1 F10 L0\n", "L (cycle repeats)"),
        ("G93 G81 X0 Y0 Z-3 R1 F10\n", "inverse-time"),
        ("G81 X0 Y0 Z-3 R1 F10 A5\n", "rotary"),
        ("G87 X0 Y0 Z-3 R1 F10\n", "G87"),
        ("G76 P1 Z-3\n", "G76"),
        ("G81 R1 F10\n", "axis words"),
        ("G81 X1 Z-1 R1 F10 Q2\n", "Q word"),
    ] {
        let e = err(text);
        assert!(e.message.contains(what), "{text}: {e}");
    }
}

const TABLE: &str = "T1 P1 D6 Z25 ;6 mm\nT2 P2 D10 Z-3 X1\n";

#[test]
fn cutter_compensation_offsets_by_the_tool_radius() {
    let text = "T1 M6\nG0 X-10 Y-10\nF100\nG41 G1 X0 Y0\nG1 Y20\nG1 X20\nG40 G1 X30 Y30\nM2\n";
    let p = interpret(text, &with_table(TABLE)).unwrap();
    let e = ends(&p);
    // Entry perpendicular to the entry move, the left side of Y20 at X-3, an arc around the
    // outside corner (0, 20), the top edge at Y23, then the exit to the programmed point.
    // The entry ends where its offset line meets the next one (an inside corner), as rs274
    // prints it: (-3, 1.2426).
    assert!(
        near(e[1], DVec3::new(-3.0, 3.0 * 2f64.sqrt() - 3.0, 0.0)),
        "{e:?}"
    );
    assert!(
        e.iter().any(|p| near(*p, DVec3::new(-3.0, 20.0, 0.0))),
        "{e:?}"
    );
    assert!(
        e.iter().any(|p| near(*p, DVec3::new(0.0, 23.0, 0.0))),
        "{e:?}"
    );
    assert!(
        p.blocks
            .iter()
            .any(|b| matches!(b.kind, MotionKind::ArcCw(_))),
        "corner arc"
    );
    assert!(near(*e.last().unwrap(), DVec3::new(30.0, 30.0, 0.0)));
    // G41.1 needs no table; G41 without one is refused (its radius is unknown).
    assert!(
        interpret(
            "G0 X-10\nG41.1 D6 G1 X0 F100\nG1 Y10\nG40 G1 X-10\n",
            &InterpretOptions::default()
        )
        .is_ok()
    );
    let e = err("G0 X-10\nG41 G1 X0 F100\n");
    assert!(e.message.contains("tool table"), "{e}");
    // A notch narrower than the tool cannot be reached: an error, not a gouge.
    let e = interpret(
        "T2 M6\nG0 X-20 Y0\nF100\nG41 G1 X0 Y0\nG1 X10\nG1 Y-2\nG1 X12\nG1 Y0\nG1 X30\nG40 G1 X40 Y10\n",
        &with_table(TABLE),
    )
    .unwrap_err();
    assert!(e.message.contains("gouging"), "{e}");
    // Cycles, G92 and tool changes are refused while compensation is on.
    let e = interpret(
        "T1 M6\nG41 G0 X10 Y10\nG81 X0 Y0 Z-1 R1 F10\n",
        &with_table(TABLE),
    )
    .unwrap_err();
    assert!(e.message.contains("compensation"), "{e}");
}

#[test]
fn tool_tables_and_lengths() {
    let p = interpret(
        "T2 M6\nG43 H2\nG0 X0 Y0 Z10\nG49\nG0 Z10\n",
        &with_table(TABLE),
    )
    .unwrap();
    assert!(
        near(p.blocks[0].end.xyz, DVec3::new(1.0, 0.0, 7.0)),
        "{:?}",
        ends(&p)
    );
    assert!(near(p.blocks[1].end.xyz, DVec3::new(1.0, 0.0, 10.0)));
    // G43 without H: the tool in the spindle; G43.1 gives the length itself.
    let p = interpret("T1 M6\nG43\nG0 Z0\nG43.1 Z-2\nG0 Z0\n", &with_table(TABLE)).unwrap();
    assert_eq!(p.blocks[0].end.xyz.z, 25.0);
    assert_eq!(p.blocks[1].end.xyz.z, -2.0);
    // A tool the table does not list is an error naming it; without a table, G43 moves nothing.
    let e = interpret("T7 M6\n", &with_table(TABLE)).unwrap_err();
    assert!(e.message.contains("tool 7"), "{e}");
    let p = run("T7 M6\nG43 H7\nG0 Z0\n");
    assert!(p.blocks.is_empty());
    // The table's unit: rs274 without an INI reads inches.
    let t = ToolTable::parse(TABLE, LengthUnit::Inch).unwrap();
    assert!((t.get(1).unwrap().diameter_mm - 152.4).abs() < 1e-12);
}

#[test]
fn g52_g92_and_g10_offsets() {
    let p = run(
        "G10 L2 P1 X100\nG0 X0 Y0\nG52 X5\nG0 X0\nG52 X0\nG0 X10\nG92 X0\nG0 X1\nG92.1\nG0 X0\n\
         G10 L20 P2 X0 Y0\nG55 G0 X1\n",
    );
    let xs: Vec<f64> = p.blocks.iter().map(|b| b.end.xyz.x).collect();
    assert_eq!(xs, vec![100.0, 105.0, 110.0, 111.0, 100.0, 101.0]);
    let e = err("G92 A10");
    assert!(e.message.contains("rotary"), "{e}");
    let e = err("G10 L1 P1 R2");
    assert!(e.message.contains("L1"), "{e}");
}

#[test]
fn a_zero_feed_on_a_fed_move_is_an_error() {
    // Issue 35: `G1 X100 F0` was planned at the rapid rate without a word.
    let e = err("G1 X100 F0");
    assert_eq!((e.line, e.column), (1, 9));
    assert!(e.message.contains("zero feed"), "{e}");
    let e = err("G1 X1 F0\n");
    assert!(e.message.contains("zero feed"), "{e}");
    let e = err("G1 X1 F100\nF0\nG2 X2 Y1 R1\n");
    assert_eq!(e.line, 3);
    // A rapid is fine with F0.
    assert_eq!(run("F0\nG0 X5\n").blocks.len(), 1);
}

#[test]
fn what_is_not_read_is_named() {
    for (text, what) in [
        ("G33 Z-10 K1.5", "G33"),
        ("G38.2 Z-10 F10", "G38.2"),
        ("G30", "G30"),
        ("G5.1 X1 I1 J1", "G5.1"),
        ("M98 P100", "M98"),
        ("G10 L2 P1 R45", "rotated"),
        ("G43.2 H1", "G43.2"),
        ("G95 F0.1", "G95"),
    ] {
        let e = err(text);
        assert!(e.message.contains(what), "{text}: {e}");
    }
}

#[test]
fn the_session_reads_parameters_and_holds_compensated_moves() {
    let mut s = Session::new(InterpretOptions::default()).unwrap();
    s.run_line("#1 = 4", 1).unwrap();
    let r = s.run_line("G0 X#1", 2).unwrap();
    assert_eq!(r.program.blocks[0].end.xyz.x, 4.0);
    let e = s.run_line("o1 if [1]", 3).unwrap_err();
    assert!(e.message.contains("whole program"), "{e}");
    // A compensated move comes out with the next line.
    let mut s = Session::new(InterpretOptions::default()).unwrap();
    s.run_line("G0 X-10 Y0", 1).unwrap();
    let r = s.run_line("G41.1 D4 G1 X0 F100", 2).unwrap();
    assert!(r.program.blocks.is_empty());
    let r = s.run_line("G1 Y10", 3).unwrap();
    assert_eq!(r.program.blocks.len(), 1);
    let r = s.run_line("M2", 4).unwrap();
    assert!(r.program_end && !r.program.blocks.is_empty());
    assert!(s.modal().codes().iter().any(|c| c == "G1"));
}

#[test]
fn hostile_expressions_are_errors_not_crashes() {
    let deep = format!("G0 X{}1{}", "[".repeat(5000), "]".repeat(5000));
    let e = err(&deep);
    assert!(e.message.contains("nested"), "{e}");
    let signs = format!("G0 X{}1", "-".repeat(5000));
    assert!(interpret(&signs, &InterpretOptions::default()).is_err());
    let hashes = format!("G0 X{}1", "#".repeat(5000));
    assert!(interpret(&hashes, &InterpretOptions::default()).is_err());
    assert!(interpret("G0 X[1e300 * 1e300]", &InterpretOptions::default()).is_err());
    assert!(interpret("G0 X#<", &InterpretOptions::default()).is_err());
    assert!(interpret("o<a", &InterpretOptions::default()).is_err());
    let start = Joints::xyz(0.0, 0.0, 0.0);
    assert!(interpret("G0 X[2**1000]", &InterpretOptions::starting_at(start)).is_err());
}

#[test]
fn block_delete_skips_o_word_lines_too() {
    let text = "/o1 if [0]\nG0 X1\n/o1 endif\n";
    assert_eq!(run(text).blocks.len(), 1);
    let off = InterpretOptions {
        block_delete: false,
        ..InterpretOptions::default()
    };
    assert!(interpret(text, &off).unwrap().blocks.is_empty());
    let e = interpret("T1 M6\nG41 G0 X10 Y10\nG28\n", &with_table(TABLE)).unwrap_err();
    assert!(e.message.contains("G28"), "{e}");
}
