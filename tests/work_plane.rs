//! 3+2 work planes in each dialect's own words, read back: the tilted setup of the job test
//! (`plate-hole.stp` on trt-ac, tool axis (0, −1, 1), `A-45 C180` under G56) posted with
//! Fanuc `G68.2`/`G53.1`/`G69`, Sinumerik `CYCLE800`/`CYCLE800()` and Heidenhain
//! `PLANE SPATIAL … TURN`/`PLANE RESET` reads back through Talas's interpreter (with the
//! machine's kinematics) to the same machine joints, block for pose, as the explicit A/C
//! program the LinuxCNC dialect writes (which `tests/job.rs` checks against LinuxCNC's `rs274`
//! and the forward kinematics). Wrong planes are refused naming the line.

use std::path::Path;

use talas::diagnostics::Progress;
use talas::gcode::{InterpretOptions, MotionBlock, Syntax, interpret};
use talas::import::{OpenOptions, Workpiece, open};
use talas::machine::Machine;
use talas::project::job::{plan_in_setup, post_setup};
use talas::project::{
    Operation, OperationKind, Orientation, Project, Setup, SetupStock, Tilt, ToolEntry, Workholding,
};
use talas::toolpath::Toolpath;
use talas::tools::parse_tool_spec;

fn part() -> Workpiece {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plate-hole.stp");
    open(&p, &OpenOptions::default(), &Progress::new()).expect("plate-hole.stp")
}

fn raster(name: &str, angle: f64) -> Operation {
    let mut op = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster {
        name: n,
        scallop_mm,
        angle_rad,
        clearance_mm,
        ..
    } = &mut op
    {
        *n = name.into();
        *scallop_mm = 0.4;
        *angle_rad = angle;
        *clearance_mm = 5.0;
    }
    op
}

/// The three-setup job on the plate.
fn job() -> Project {
    let mut p = Project {
        name: "Plate job".into(),
        machine: "mill-3axis".into(),
        tools: vec![ToolEntry {
            name: "Ball 6".into(),
            cutter: parse_tool_spec("ball:d=6").unwrap(),
        }],
        selected_tool: Some(0),
        operations: vec![
            raster("Top", 0.0),
            raster("Bottom", 0.0),
            raster("Tilted", 0.0),
        ],
        ..Project::default()
    };
    let mut vise = Setup::named("Vise");
    vise.frame.origin_mm = [0.0, 0.0, 5.0];
    vise.stock = SetupStock::Around { margin_mm: 2.0 };
    vise.workholding = vec![Workholding::Vise {
        jaw_width_mm: 80.0,
        jaw_height_mm: 25.0,
        jaw_thickness_mm: 15.0,
        grip_mm: 1.5,
        opening_mm: None,
        along_y: false,
    }];
    vise.operations = vec![0];
    let mut flip = Setup::named("Flipped");
    flip.frame.work_offset = 2;
    flip.frame.orientation = Orientation::Angles {
        rx_rad: std::f64::consts::PI,
        ry_rad: 0.0,
        rz_rad: 0.0,
    };
    flip.stock = SetupStock::Previous;
    flip.workholding = vec![Workholding::Plate {
        size_mm: [60.0, 60.0],
        thickness_mm: 10.0,
    }];
    flip.operations = vec![1];
    let mut tilt = Setup::named("Tilted 45");
    tilt.machine = Some("trt-ac".into());
    tilt.frame.work_offset = 3;
    tilt.stock = SetupStock::Previous;
    tilt.tilt = Some(Tilt {
        tool_axis: [0.0, -1.0, 1.0],
        x_axis: None,
    });
    tilt.operations = vec![2];
    p.setups = vec![vise, flip, tilt];
    p.check().expect("a valid job");
    p
}

const TILTED: usize = 2;

fn paths(project: &Project, part: &Workpiece) -> Vec<Toolpath> {
    project.setups[TILTED]
        .operations
        .iter()
        .map(|&op| {
            plan_in_setup(project, op, part, &Progress::new())
                .expect("plans")
                .toolpath
        })
        .collect()
}

fn options(syntax: &str) -> InterpretOptions {
    InterpretOptions {
        machine: Some(Machine::builtin("trt-ac").unwrap()),
        ..InterpretOptions::for_syntax(Syntax::from_name(syntax).unwrap())
    }
}

/// The last block of each pose of the (one) operation.
fn per_pose<'a>(
    blocks: &'a [MotionBlock],
    posted: &talas::post::PostedProgram,
    n: usize,
) -> Vec<Option<&'a MotionBlock>> {
    let mut reached = vec![None; n];
    for b in blocks {
        if let Some(src) = posted.source_of_line.get(b.source_line - 1)
            && let Some(k) = src.pose
        {
            reached[k] = Some(b);
        }
    }
    reached
}

#[test]
fn tilted_planes_read_back_to_the_explicit_programs_joints() {
    let part = part();
    let mut project = job();
    let tps = paths(&project, &part);
    let n = tps[0].poses.len();
    let explicit = post_setup(&project, TILTED, &tps).unwrap();
    assert!(explicit.text.contains("A-45 C180"), "{}", explicit.text);
    let reference = interpret(&explicit.text, &options("linuxcnc")).unwrap();
    let want = per_pose(&reference.blocks, &explicit, n);
    for (dialect, on, off) in [
        ("fanuc", "G68.2 X0. Y0. Z0. I0. J45. K0.", "G69"),
        (
            "siemens",
            "CYCLE800(0, \"TABLE\", 0, 27, 0, 0, 0, 45, 0, 0, 0, 0, 0, -1, 100, 1)",
            "CYCLE800()",
        ),
        (
            "heidenhain",
            "PLANE SPATIAL SPA+45 SPB+0 SPC+0 TURN MB0 FMAX SEQ-",
            "PLANE RESET STAY",
        ),
    ] {
        project.post.dialect = dialect.into();
        let posted = post_setup(&project, TILTED, &tps).unwrap();
        let text = &posted.text;
        assert!(text.contains(on), "{dialect}: no {on}\n{text}");
        assert!(text.contains(off), "{dialect}: no {off}");
        // No rotary word but the final return to zero.
        assert_eq!(text.matches("A-45").count(), 0, "{dialect}:\n{text}");
        let program =
            interpret(text, &options(dialect)).unwrap_or_else(|e| panic!("{dialect}: {e}"));
        let got = per_pose(&program.blocks, &posted, n);
        let machine = Machine::builtin("trt-ac").unwrap();
        let mut worst = 0.0f64;
        let mut worst_tip = 0.0f64;
        let mut checked = 0;
        for (k, (g, w)) in got.iter().zip(&want).enumerate() {
            let (Some(g), Some(w)) = (g, w) else {
                assert_eq!(
                    g.is_some(),
                    w.is_some(),
                    "{dialect}: pose {k} reached in one only"
                );
                continue;
            };
            worst = worst.max(g.end.xyz.distance(w.end.xyz));
            let tip = machine
                .forward(&talas::machine::MachineJoints {
                    xyz: g.end.xyz,
                    tilt_rad: g.end.a.unwrap_or(0.0),
                    rotary_rad: g.end.c.unwrap_or(0.0),
                })
                .tip;
            worst_tip = worst_tip.max(tip.distance(tps[0].poses[k].tip));
            for (a, b) in [(g.end.a, w.end.a), (g.end.c, w.end.c)] {
                assert!(
                    (a.unwrap_or(0.0) - b.unwrap_or(0.0)).abs() < 1e-9,
                    "{dialect}: pose {k} rotary {a:?} not {b:?}"
                );
            }
            checked += 1;
        }
        assert!(checked > 100, "{dialect}: {checked} poses");
        eprintln!(
            "{dialect}: {checked} poses, tips within {worst_tip:.2e} mm of the path, joints within \
             {worst:.2e} mm of the explicit program"
        );
        // Each program is within its own rounding (0.5e-4 mm per written coordinate) of the
        // exact joints: the tips land on the path within 1e-4 mm, and the two programs'
        // joints differ by at most both roundings, sqrt(3)·1e-4 mm.
        assert!(
            worst_tip < 1e-4,
            "{dialect}: a tip {worst_tip} mm off the path"
        );
        assert!(
            worst < 3f64.sqrt() * 1e-4 + 1e-9,
            "{dialect}: {worst} mm from the explicit program"
        );
        // The whole machine motion ends where the explicit program's does (A0 C0, Z clear).
        let (end, end_ref) = (
            program.blocks.last().unwrap(),
            reference.blocks.last().unwrap(),
        );
        assert!(end.end.xyz.distance(end_ref.end.xyz) < 1e-4);
        // Without the machine's kinematics the plane is refused, naming its line.
        let e = interpret(
            text,
            &InterpretOptions::for_syntax(Syntax::from_name(dialect).unwrap()),
        )
        .unwrap_err();
        let line = text.lines().position(|l| l.contains(on)).unwrap() + 1;
        assert_eq!(e.line, line, "{dialect}: {e}");
        assert!(e.message.contains("kinematics"), "{e}");
    }
}

fn refused(text: &str, syntax: &str) -> talas::gcode::GcodeError {
    interpret(text, &options(syntax)).unwrap_err()
}

#[test]
fn bad_planes_and_moves_under_them_are_refused_naming_the_line() {
    let e = refused(
        "G21 G90\nG68.2 X0 Y0 Z0 I0 J45 K0\nG53.1\nG2 X1 Y0 I0.5 J0 F100\n",
        "fanuc",
    );
    assert_eq!(e.line, 4, "{e}");
    assert!(e.message.contains("tilted work plane"), "{e}");
    let e = refused("G21 G90\nG68.2 X0 Y0 Z0 I0 J45 K0\nG0 A10\n", "fanuc");
    assert_eq!(e.line, 3, "{e}");
    let e = refused(
        "G21 G90\nG68.2 X0 Y0 Z0 I0 J45 K0\nG68.2 X0 Y0 Z0 I0 J10 K0\n",
        "fanuc",
    );
    assert_eq!(e.line, 3, "{e}");
    assert!(e.message.contains("already active"), "{e}");
    let e = refused(
        "G71 G90\nCYCLE800(0, \"T\", 0, 99, 0, 0, 0, 45, 0, 0, 0, 0, 0, -1)\n",
        "siemens",
    );
    assert_eq!(e.line, 2, "{e}");
    assert!(e.message.contains("_MODE 99"), "{e}");
    // The trt-ac tilt (A) reaches -120…+30°: a +45° tilt about X needs A = -45, and SEQ+
    // (a positive A) has no solution.
    let e = refused(
        "%P G71 *\nN10 G90 *\nN20 PLANE SPATIAL SPA+45 SPB+0 SPC+0 TURN MB0 FMAX SEQ+ *\n",
        "heidenhain",
    );
    assert_eq!(e.line, 3, "{e}");
    let e = refused("%P G71 *\nN10 PLANE AXIAL B+45 *\n", "heidenhain");
    assert!(e.message.contains("PLANE AXIAL"), "{e}");
}
