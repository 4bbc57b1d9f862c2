//! The job: three setups of `plate-hole.stp` (a 30 × 30 × 5 mm plate with a Ø10 mm hole):
//! as modelled (in a vise), turned over (Rx 180°, the stock carried from the first), and a
//! 3+2 setup on trt-ac tilted 45° about X. Each setup's operations are planned in its frame and
//! posted into one program; each program is read back by Talas's interpreter (and, for
//! LinuxCNC, by LinuxCNC's `rs274` where installed) and every pose's block is put through the
//! machine's forward kinematics: the tool tip lands where the setup-frame path says (1e-4 mm).
//! Independently of the transforms, the ball's centre over the plate's top, taken back into
//! part coordinates, is one radius above the top face (z = 5 + 3 mm, within the raster's
//! 0.01 mm chord tolerance) in the setups that see the top, one radius below the bottom
//! (z = −3 mm) in the turned-over one.

use std::path::Path;

use glam::DVec3;
use talas::diagnostics::Progress;
use talas::gcode::{InterpretOptions, MotionKind, Syntax, interpret};
use talas::import::{OpenOptions, Workpiece, open};
use talas::machine::{Machine, MachineJoints};
use talas::project::job::{plan_in_setup, post_setup};
use talas::project::setups::{Placement, placements, stock_solid};
use talas::project::{
    Operation, OperationKind, Orientation, Project, Setup, SetupStock, Tilt, ToolEntry, Workholding,
};
use talas::toolpath::{MoveKind, Toolpath};
use talas::tools::parse_tool_spec;

const RS274: &str = "/usr/bin/rs274";
const R_MM: f64 = 3.0;

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

fn joints(b: &talas::gcode::MotionBlock) -> MachineJoints {
    MachineJoints {
        xyz: b.end.xyz,
        tilt_rad: b.end.a.unwrap_or(0.0),
        rotary_rad: b.end.c.unwrap_or(0.0),
    }
}

/// Plan and post setup `s`; check every pose's block through the kinematics. The tool path
/// (setup frame) and the program text.
fn plan_and_check(project: &Project, s: usize, part: &Workpiece) -> (Toolpath, String) {
    let setup = &project.setups[s];
    let paths: Vec<Toolpath> = setup
        .operations
        .iter()
        .map(|&op| {
            plan_in_setup(project, op, part, &Progress::new())
                .expect("plans")
                .toolpath
        })
        .collect();
    let posted = post_setup(project, s, &paths).expect("posts");
    assert!(
        posted.text.contains(&setup.frame.work_offset_code()),
        "{}: no work offset",
        setup.name
    );
    let machine = Machine::resolve(setup.machine_name(project)).unwrap();
    let program = interpret(
        &posted.text,
        &InterpretOptions::for_syntax(Syntax::from_name("linuxcnc").unwrap()),
    )
    .unwrap_or_else(|e| panic!("{}: {e}", setup.name));
    // The last block of each pose.
    let mut reached = vec![None; paths[0].poses.len()];
    for b in &program.blocks {
        if let Some(src) = posted.source_of_line.get(b.source_line - 1)
            && src.operation == 0
            && let Some(k) = src.pose
        {
            reached[k] = Some(b);
        }
    }
    let mut worst = 0.0f64;
    let mut checked = 0;
    for (k, pose) in paths[0].poses.iter().enumerate() {
        let Some(b) = reached[k] else { continue };
        let f = machine.forward(&joints(b));
        worst = worst.max(f.tip.distance(pose.tip));
        assert!(
            f.axis.angle_between(pose.axis) < 1e-9,
            "{}: pose {k} axis {} posted {}",
            setup.name,
            pose.axis,
            f.axis
        );
        checked += 1;
    }
    assert!(
        checked > 100,
        "{}: only {checked} poses reached",
        setup.name
    );
    assert!(worst < 1e-4, "{}: tip {worst} mm off", setup.name);
    (paths.into_iter().next().unwrap(), posted.text)
}

/// Ball centres along the cutting moves (every 0.25 mm: the moves are straight, the axis
/// fixed), in part coordinates.
fn centres(tp: &Toolpath, pl: &Placement) -> Vec<DVec3> {
    let mut out = Vec::new();
    for w in tp.poses.windows(2) {
        if w[1].kind != MoveKind::Cut {
            continue;
        }
        let (a, b) = (w[0].tip + w[0].axis * R_MM, w[1].tip + w[1].axis * R_MM);
        let n = ((b - a).length() / 0.25).ceil().max(1.0) as usize;
        out.extend((0..=n).map(|i| pl.to_part(a.lerp(b, i as f64 / n as f64))));
    }
    out
}

/// Ball centres over the plate's top (away from its edges and the hole), in part coordinates.
fn centres_over_top(tp: &Toolpath, pl: &Placement) -> Vec<DVec3> {
    centres(tp, pl)
        .into_iter()
        .filter(|c| {
            c.x.abs() < 15.0 - R_MM - 0.5
                && c.y.abs() < 15.0 - R_MM - 0.5
                && c.truncate().length() > 5.0 + R_MM + 0.5
                && c.z > 5.0
        })
        .collect()
}

#[test]
fn three_setups_post_programs_whose_tips_land_on_the_part_frame_path() {
    let part = part();
    let project = job();
    let pls = placements(&project, Some(&part)).unwrap();
    // Setup 1 (as modelled) and setup 3 (tilted 45°) see the top: its ball centres sit one
    // radius above it. Setup 2 (turned over) sees the bottom: centres at z = −3 in part
    // coordinates over the plate.
    for s in [0, 2] {
        let (tp, _) = plan_and_check(&project, s, &part);
        let c = centres_over_top(&tp, &pls[s]);
        assert!(
            c.len() > 20,
            "setup {}: {} centres over the top",
            s + 1,
            c.len()
        );
        let worst = c.iter().map(|c| (c.z - 8.0).abs()).fold(0.0, f64::max);
        assert!(
            worst < 1e-2,
            "setup {}: a centre {worst} mm off z = 8",
            s + 1
        );
    }
    let (tp, text) = plan_and_check(&project, 1, &part);
    let under: Vec<DVec3> = centres(&tp, &pls[1])
        .into_iter()
        .filter(|c| c.x.abs() < 11.5 && c.y.abs() < 11.5 && c.truncate().length() > 8.5)
        .collect();
    assert!(under.len() > 20);
    assert!(under.iter().all(|c| (c.z + 3.0).abs() < 1e-2));
    assert!(text.contains("G55"));
}

#[test]
fn the_tilted_program_reads_the_same_in_linuxcnc() {
    let part = part();
    let project = job();
    let (_, text) = plan_and_check(&project, 2, &part);
    assert!(text.contains("G56"));
    if !Path::new(RS274).exists() {
        eprintln!("{RS274} is not installed: the program is read by Talas only");
        return;
    }
    let dir = std::env::temp_dir().join(format!("talas-job-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let ngc = dir.join("tilted.ngc");
    std::fs::write(&ngc, &text).unwrap();
    let tbl = dir.join("tools.tbl");
    std::fs::write(&tbl, "T1 P1 Z0 D0.2362 ;ball 6\n").unwrap();
    let out = std::process::Command::new(RS274)
        .arg("-g")
        .arg("-t")
        .arg(&tbl)
        .arg(&ngc)
        .env("HOME", &dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "rs274: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    // End points of every straight move rs274 prints: X Y Z (mm) A B C (deg).
    let printed = String::from_utf8_lossy(&out.stdout);
    let lcnc: Vec<[f64; 6]> = printed
        .lines()
        .filter_map(|l| {
            let (_, call) = l.split_once("STRAIGHT_")?;
            let args = call.split_once('(')?.1.trim_end().trim_end_matches(')');
            let v: Vec<f64> = args
                .split([',', ' '])
                .filter(|t| !t.is_empty())
                .filter_map(|t| t.parse().ok())
                .collect();
            (v.len() >= 6).then(|| [v[0], v[1], v[2], v[3], v[4], v[5]])
        })
        .collect();
    let ours = interpret(
        &text,
        &InterpretOptions::for_syntax(Syntax::from_name("linuxcnc").unwrap()),
    )
    .unwrap();
    let talas: Vec<[f64; 6]> = ours
        .blocks
        .iter()
        .filter(|b| matches!(b.kind, MotionKind::Rapid | MotionKind::Linear))
        .map(|b| {
            [
                b.end.xyz.x,
                b.end.xyz.y,
                b.end.xyz.z,
                b.end.a.unwrap_or(0.0).to_degrees(),
                b.end.b.unwrap_or(0.0).to_degrees(),
                b.end.c.unwrap_or(0.0).to_degrees(),
            ]
        })
        .collect();
    // rs274 prints moves that go nowhere; leave them out on both sides.
    let moving = |v: Vec<[f64; 6]>| {
        let mut out: Vec<[f64; 6]> = Vec::new();
        for m in v {
            let same = out
                .last()
                .is_some_and(|l| l.iter().zip(&m).all(|(a, b)| (a - b).abs() < 1e-7));
            if !same {
                out.push(m);
            }
        }
        out
    };
    let (lcnc, talas) = (moving(lcnc), moving(talas));
    assert!(lcnc.len() > 100);
    assert_eq!(
        lcnc.len(),
        talas.len(),
        "rs274 and Talas count different moves"
    );
    for (i, (a, b)) in lcnc.iter().zip(&talas).enumerate() {
        for k in 0..6 {
            assert!(
                (a[k] - b[k]).abs() < 1e-4,
                "move {i} axis {k}: rs274 {a:?}, Talas {b:?}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_stock_of_each_setup_starts_where_the_previous_ended() {
    let part = part();
    let project = job();
    let pls = placements(&project, Some(&part)).unwrap();
    let bounds = part.mesh.bbox();
    let v: Vec<f64> = (0..3)
        .map(|s| {
            stock_solid(&project, s, &pls, &bounds)
                .unwrap()
                .signed_volume()
        })
        .collect();
    // A 34 × 34 × 7 mm box (2 mm margin on the sides and the top).
    let box_v = 34.0 * 34.0 * 7.0;
    for (s, vol) in v.iter().enumerate() {
        assert!(
            (vol - box_v).abs() < 1e-3 * box_v,
            "setup {}: {vol} mm³",
            s + 1
        );
    }
    // The vise's jaws touch the stock's sides in setup 1's frame.
    let jaws =
        talas::project::setups::workholding_meshes(&project, 0, &pls, &bounds, Path::new("."))
            .unwrap();
    let b = jaws[0].bbox();
    assert!(
        (b.min.x + 17.0 + 15.0).abs() < 1e-9 && (b.max.x - 32.0).abs() < 1e-9,
        "{b:?}"
    );
}

#[test]
fn talas_job_posts_one_program_per_setup_and_reports_each_operation() {
    let dir = std::env::temp_dir().join(format!("talas-job-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let project_file = dir.join("plate.talas");
    job().save(&project_file).unwrap();
    let part_file = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/plate-hole.stp");
    let programs = dir.join("programs");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_talas"))
        .arg("job")
        .arg(&project_file)
        .arg("--part")
        .arg(&part_file)
        .arg("--post")
        .arg(&programs)
        .arg("--simulate")
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).expect("strict JSON");
    let setups = doc["setups"].as_array().unwrap();
    assert_eq!(setups.len(), 3);
    let project = job();
    let part = part();
    for (s, setup) in setups.iter().enumerate() {
        assert_eq!(setup["name"], project.setups[s].name);
        // The program on disk is the library's post of the setup …
        let file = setup["program"].as_str().unwrap();
        let text = std::fs::read_to_string(file).unwrap();
        let paths: Vec<Toolpath> = project.setups[s]
            .operations
            .iter()
            .map(|&op| {
                plan_in_setup(&project, op, &part, &Progress::new())
                    .unwrap()
                    .toolpath
            })
            .collect();
        // … of its paths linked over the setup's stock (rapids above it).
        let (linked, _) =
            talas::project::job::link_setup(&project, s, &part, &paths, false, &Progress::new())
                .unwrap();
        let paths: Vec<Toolpath> = linked.into_iter().map(|l| l.toolpath).collect();
        assert_eq!(text, post_setup(&project, s, &paths).unwrap().text);
        let op = &setup["operations"][0];
        assert!(
            op["tool"]["spec"]
                .as_str()
                .unwrap()
                .starts_with("ball:d=6,")
        );
        assert!(op["estimated_time_s"].as_f64().unwrap() > 0.0);
        let sim = &setup["simulation"];
        let removed = sim["removed_volume_mm3"].as_f64().unwrap();
        let initial = sim["initial_volume_mm3"].as_f64().unwrap();
        assert!(
            removed > 0.0 && removed < initial,
            "setup {}: {removed} of {initial}",
            s + 1
        );
    }
    assert_eq!(doc["stock_carried"], true);
    // Each setup after the first starts from what the one before it left (0.1 %).
    for w in setups.windows(2) {
        let (end, start) = (
            w[0]["simulation"]["end_volume_mm3"].as_f64().unwrap(),
            w[1]["simulation"]["start_volume_mm3"].as_f64().unwrap(),
        );
        assert_eq!(w[1]["simulation"]["carried"], true);
        assert!((start - end).abs() < 1e-3 * end, "{start} vs {end}");
    }
    assert!(setups[0]["workholding"][0]["kind"] == "vise");
    assert!(
        setups
            .iter()
            .all(|s| s["operations"][0]["workholding_collision"].is_null())
    );
    // One setup by name; an unknown name is one line naming the setups there are.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["job", project_file.to_str().unwrap(), "--part"])
        .arg(&part_file)
        .args(["--setup", "Nope"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no setup 'Nope' (there are: Vise, Flipped, Tilted 45)"),
        "{err}"
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_talas"))
        .args(["job", project_file.to_str().unwrap(), "--part"])
        .arg(&part_file)
        .args(["--setup", "Flipped"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.starts_with("setup 'Flipped' on mill-3axis (G55)"),
        "{text}"
    );
    assert!(
        text.contains("tool T1 ball:d=6") && text.contains(" mm, "),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The first contact of the tool with the setup's workholding along `placements`.
fn jaw_hit(
    project: &Project,
    part: &Workpiece,
    placements_: &[(DVec3, DVec3)],
) -> Option<talas::checks::collide::Hit> {
    let pls = placements(project, Some(part)).unwrap();
    let meshes = talas::project::setups::workholding_meshes(
        project,
        0,
        &pls,
        &part.mesh.bbox(),
        Path::new("."),
    )
    .unwrap();
    let obstacles: Vec<_> = meshes
        .iter()
        .map(|m| talas::checks::collide::Obstacle::new("vise", m).unwrap())
        .collect();
    let tool = talas::checks::collide::assembly(&project.tools[0].cutter);
    talas::checks::collide::first_hit(&tool, &obstacles, placements_, 0.25)
}

#[test]
fn a_vise_jaw_in_the_way_is_found_at_the_same_line_on_the_path_and_on_its_program() {
    let part = part();
    let mut project = job();
    // Jaws gripping 6.5 mm of the 7 mm stock: their tops 1.5 mm above the part's top, in the
    // way of the raster's passes over the part's X edges.
    if let Workholding::Vise { grip_mm, .. } = &mut project.setups[0].workholding[0] {
        *grip_mm = 6.5;
    }
    let tp = plan_in_setup(&project, 0, &part, &Progress::new())
        .unwrap()
        .toolpath;
    let on_path: Vec<(DVec3, DVec3)> = tp.poses.iter().map(|p| (p.tip, p.axis)).collect();
    let hit = jaw_hit(&project, &part, &on_path).expect("the jaw is in the way");
    let posted = post_setup(&project, 0, std::slice::from_ref(&tp)).unwrap();
    let line_of_pose = posted
        .source_of_line
        .iter()
        .rposition(|s| s.operation == 0 && s.pose == Some(hit.index))
        .expect("the pose's line");
    // The program as the control runs it: its blocks through the kinematics.
    let machine = Machine::resolve("mill-3axis").unwrap();
    let program = interpret(
        &posted.text,
        &InterpretOptions::for_syntax(Syntax::from_name("linuxcnc").unwrap()),
    )
    .unwrap();
    let blocks = &program.blocks;
    let mut run: Vec<(DVec3, DVec3)> = Vec::new();
    let start = machine.forward(&MachineJoints {
        xyz: blocks[0].start.xyz,
        tilt_rad: 0.0,
        rotary_rad: 0.0,
    });
    run.push((start.tip, start.axis));
    for b in blocks {
        let f = machine.forward(&joints(b));
        run.push((f.tip, f.axis));
    }
    let on_run = jaw_hit(&project, &part, &run).expect("the run hits the jaw");
    let block = &blocks[on_run.index - 1];
    assert_eq!(
        block.source_line - 1,
        line_of_pose,
        "plan: pose {} (line {}), run: line {}",
        hit.index,
        line_of_pose + 1,
        block.source_line
    );
    assert!(
        hit.tip.distance(on_run.tip) < 0.3,
        "{} vs {}",
        hit.tip,
        on_run.tip
    );
    // With the jaws gripping 1.5 mm (tops 3.5 mm below the part's top) nothing is hit (at 3 mm
    // the ball's side still touches a jaw where the passes run down past the part's corner).
    let clear = job();
    let tp = plan_in_setup(&clear, 0, &part, &Progress::new())
        .unwrap()
        .toolpath;
    let on_path: Vec<(DVec3, DVec3)> = tp.poses.iter().map(|p| (p.tip, p.axis)).collect();
    assert_eq!(jaw_hit(&clear, &part, &on_path), None);
}

/// The job test part (`tests/data/job/make_part.py`, Open CASCADE): Talas reads the volume
/// the closed form gives (block less the top pocket, two holes, the front pocket with its boss
/// added back, and the side slot; Open CASCADE prints the same, 55 778.407 mm³) and the 26
/// faces Open CASCADE counts, and laying its back face on the table turns the front up.
#[test]
fn the_job_part_reads_as_made_and_turns_its_front_up() {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/job/job-part.stp");
    let part = open(&p, &OpenOptions::default(), &Progress::new()).expect("job-part.stp");
    let pi = std::f64::consts::PI;
    let closed = 60.0 * 40.0 * 25.0 - 30.0 * 16.0 * 5.0 - 2.0 * pi * 9.0 * 8.0 - 20.0 * 4.0 * 10.0
        + pi * 16.0 * 3.0
        - 3.0 * 40.0 * 6.0;
    let v = part.mesh.signed_volume();
    assert!(
        (v - closed).abs() < 1e-3 * closed,
        "{v} mm³ vs {closed} mm³"
    );
    assert_eq!(part.part.as_ref().unwrap().faces.len(), 26);
    // The back face: planar, every corner at y = 20.
    let back = (0..26)
        .find(|&f| {
            let ys: Vec<f64> = part
                .face_of_triangle
                .iter()
                .enumerate()
                .filter(|(_, ff)| **ff as usize == f)
                .flat_map(|(t, _)| part.mesh.triangle_corners(t).unwrap())
                .map(|c| c.y)
                .collect();
            !ys.is_empty() && ys.iter().all(|y| (y - 20.0).abs() < 1e-9)
        })
        .expect("the back face");
    let mut s = Setup::named("Front up");
    s.frame.orientation = Orientation::FaceOnTable {
        face: back,
        x_edge: None,
        rz_rad: 0.0,
    };
    let pl = Placement::of(&s, Some(&part)).unwrap();
    assert!((pl.rotation * DVec3::new(0.0, -1.0, 0.0) - DVec3::Z).length() < 1e-9);
    // The front pocket's floor (y = −16) is 4 mm below the front (y = −20) as it lies.
    let floor = pl.to_setup(DVec3::new(0.0, -16.0, 9.0)).z;
    let front = pl.to_setup(DVec3::new(20.0, -20.0, 3.0)).z;
    assert!((front - floor - 4.0).abs() < 1e-9);
}

/// An operation of the second setup (turned over, G55) posts in that setup's frame and work
/// offset, not the first setup's: every feed end point of its program, taken back through the
/// flipped placement, is the part-frame point it was given (program = R·(part − origin)).
#[test]
fn an_operation_of_the_second_setup_posts_in_its_own_frame() {
    use talas::project::posting::post_operation;
    let project = job();
    let part = part();
    let (pls, _) = talas::project::job::placements(&project, &part).expect("placements");
    let flipped = pls[1];
    // The setup's +Z (the spindle axis) in part coordinates: the part's −Z.
    let axis = flipped.rotation.transpose() * DVec3::Z;
    assert!((axis + DVec3::Z).length() < 1e-12);
    let pose = |kind, x: f64, y: f64, z: f64| {
        talas::toolpath::Pose::new(kind, DVec3::new(x, y, z), axis, 600.0)
    };
    let given = [(-10.0, -5.0, -1.0), (10.0, -5.0, -1.0), (10.0, 5.0, -1.5)];
    let mut poses = vec![pose(MoveKind::Rapid, -10.0, -5.0, -10.0)];
    poses.extend(given.iter().map(|&(x, y, z)| pose(MoveKind::Cut, x, y, z)));
    let tp = Toolpath::new(
        talas::toolpath::ToolRecord {
            spec: "ball:d=6".into(),
            cutter: parse_tool_spec("ball:d=6").unwrap(),
        },
        poses,
    );
    let posted = post_operation(&project, 1, &tp, 1).expect("posts");
    assert!(posted.text.contains("G55"), "{}", posted.text);
    let program = interpret(&posted.text, &InterpretOptions::default()).expect("reads back");
    let ends: Vec<DVec3> = program
        .blocks
        .iter()
        .filter(|b| b.kind == MotionKind::Linear)
        .map(|b| flipped.to_part(b.end.xyz))
        .collect();
    assert_eq!(ends.len(), given.len(), "{}", posted.text);
    for (e, &(x, y, z)) in ends.iter().zip(&given) {
        assert!(
            (*e - DVec3::new(x, y, z)).length() < 1e-4,
            "{e} vs ({x}, {y}, {z})"
        );
    }
    // The same path as an operation of the first setup (not turned over) cannot be posted on
    // the 3-axis machine: its tool axis points up from below.
    assert!(post_operation(&project, 0, &tp, 1).is_err());
}

/// Setup 1's raster planned and linked over its stock box (its rapids lifted over the
/// stock, as `talas job --post` posts it).
fn linked(project: &Project, part: &Workpiece) -> Toolpath {
    let tp = plan_in_setup(project, 0, part, &Progress::new())
        .unwrap()
        .toolpath;
    let (mut l, _) =
        talas::project::job::link_setup(project, 0, part, &[tp], false, &Progress::new()).unwrap();
    l.remove(0).toolpath
}

/// Where setup 1's program zero sits on the machine (G54): the post's safe height is 100 mm
/// in program coordinates and Z travels to 100 mm, so the part sits 60 mm lower than in its
/// own coordinates.
fn work_offset() -> DVec3 {
    DVec3::new(0.0, 0.0, -60.0)
}

/// The virtual control of setup 1 as the operator panel builds it: mill-3axis homed, the
/// setup's work offset, its stock box cut by the tool and its vise on the table (machine =
/// program + offset), the posted program loaded in AUTO.
fn control_for_setup(
    project: &Project,
    part: &Workpiece,
    program: &str,
) -> talas::control::Control {
    use talas::control::{Action, Control, ControlConfig, LiveStock, Mode};
    use talas::simulation::{DexelMode, DexelStock, StockShape};
    let pls = placements(project, Some(part)).unwrap();
    let origin = work_offset();
    let mut cfg = ControlConfig::new(Machine::resolve("mill-3axis").unwrap());
    cfg.work_offsets[0] = origin;
    cfg.fixtures = talas::project::job_sim::control_fixtures(
        project,
        0,
        &pls,
        &part.mesh.bbox(),
        Path::new("."),
        origin,
    )
    .unwrap();
    let b = stock_solid(project, 0, &pls, &part.mesh.bbox())
        .unwrap()
        .bbox();
    let shape = StockShape::Box {
        min: b.min + origin,
        max: b.max + origin,
    };
    let stock = DexelStock::new(vec![shape], 0.5, DexelMode::Z, 1 << 28).unwrap();
    cfg.stock = Some(LiveStock::new(stock, project.tools[0].cutter.clone(), 0.5));
    let mut c = Control::new(cfg).unwrap();
    c.apply(Action::Home).unwrap();
    c.advance_until_idle(1e4);
    c.apply(Action::SetMode(Mode::Auto)).unwrap();
    c.apply(Action::LoadProgram {
        name: "setup 1".into(),
        text: program.into(),
    })
    .unwrap();
    c
}

#[test]
fn the_virtual_control_stops_at_the_vise_jaw_on_the_line_planning_names() {
    use talas::control::{Action, codes};
    let part = part();
    let mut project = job();
    if let Workholding::Vise { grip_mm, .. } = &mut project.setups[0].workholding[0] {
        *grip_mm = 6.5;
    }
    let tp = linked(&project, &part);
    let on_path: Vec<(DVec3, DVec3)> = tp.poses.iter().map(|p| (p.tip, p.axis)).collect();
    let hit = jaw_hit(&project, &part, &on_path).expect("the jaw is in the way");
    let posted = post_setup(&project, 0, std::slice::from_ref(&tp)).unwrap();
    let line_of_pose = posted
        .source_of_line
        .iter()
        .rposition(|s| s.operation == 0 && s.pose == Some(hit.index))
        .expect("the pose's line")
        + 1;
    let mut c = control_for_setup(&project, &part, &posted.text);
    c.apply(Action::CycleStart).unwrap();
    c.advance_until_idle(1e5);
    let alarm = c
        .alarms()
        .iter()
        .find(|a| a.code == codes::COLLISION_MACHINE)
        .unwrap_or_else(|| panic!("no collision alarm: {:?}", c.alarms()));
    assert_eq!(alarm.line, Some(line_of_pose), "{}", alarm.text);
    assert!(
        alarm.bodies.iter().any(|b| b == "vise"),
        "{:?}",
        alarm.bodies
    );
    // Where the control saw the contact (machine coordinates) is planning's tip moved by the
    // work offset, within the planning check's 0.25 mm step.
    let at = DVec3::from(alarm.position.unwrap());
    let want = hit.tip + work_offset();
    assert!(at.distance(want) < 0.3, "control {at}, planning {want}");
    // The vise gripping 1.5 mm: the same control runs the program to its end, no alarm.
    let clear = job();
    let tp = linked(&clear, &part);
    let posted = post_setup(&clear, 0, std::slice::from_ref(&tp)).unwrap();
    let mut c = control_for_setup(&clear, &part, &posted.text);
    c.apply(Action::CycleStart).unwrap();
    c.advance_until_idle(1e5);
    assert!(c.alarms().is_empty(), "{:?}", c.alarms());
    c.flush_cutting();
    let removed = c.snapshot().removed_volume_mm3;
    assert!(removed > 100.0, "{removed} mm³");
}
