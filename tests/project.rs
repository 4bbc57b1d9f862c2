//! The project document: TOML round trip, atomic save, clear errors with a place, and undo/redo
//! that restores every earlier state exactly.

mod common;

use std::path::Path;

use common::Lcg;
use talas::geometry::Aabb;
use talas::project::{
    Edit, EditError, History, Operation, OperationKind, PartRef, PartStatus, Project, ProjectError,
    Stock, ToolEntry, content_hash,
};
use talas::tools::parse_tool_spec;

fn tool(spec: &str, name: &str) -> ToolEntry {
    ToolEntry {
        name: name.into(),
        cutter: parse_tool_spec(spec).expect("valid spec"),
    }
}

#[allow(clippy::field_reassign_with_default)]
fn rich_project(dir: &Path) -> Project {
    let part_path = dir.join("part.stl");
    std::fs::write(&part_path, b"solid x\nendsolid x\n").expect("write part");
    let mut p = Project::default();
    p.name = "Bracket, op 10".into();
    p.part = Some(PartRef::from_file(&part_path).expect("part"));
    p.stock = Stock::box_around(
        &Aabb {
            min: glam::DVec3::new(-10.0, -5.0, 0.0),
            max: glam::DVec3::new(10.0, 5.0, 7.5),
        },
        2.0,
    );
    p.tools.push(tool("bull:d=10,r=2,flute=25", "Bull 10 r2"));
    p.tools.push(tool("cone:d=8,angle=30", "Chamfer"));
    p.selected_tool = Some(2);
    p.machine = "trt-ac".into();
    p.operations.push(Operation::Raster {
        name: "Finish".into(),
        tool: 0,
        scallop_mm: 0.005,
        angle_rad: 0.25,
        one_way: true,
        tolerance_mm: 0.002,
        feed_mm_per_min: 1500.0,
        clearance_mm: 7.5,
        boundary: None,
    });
    p.operations
        .push(Operation::new(OperationKind::IsoScallop, 1, 0));
    p.operations
        .push(Operation::new(OperationKind::Rough, 1, 0));
    p.setups[0].frame = talas::project::Frame {
        work_offset: 3,
        origin_mm: [-10.0, -5.0, 7.5],
        ..talas::project::Frame::default()
    };
    p.setups[0].operations = (0..p.operations.len()).collect();
    p.view.distance_mm = 123.456_789_012_345;
    p.view.orthographic = true;
    p
}

#[test]
fn default_project_has_a_selected_ball_end_mill() {
    let p = Project::default();
    let t = p.selected_tool().expect("a tool is selected");
    assert_eq!(t.cutter, parse_tool_spec("ball:d=6").expect("spec"));
    assert!(talas::machine::Machine::builtin_names().contains(&p.machine.as_str()));
}

#[test]
fn save_and_load_round_trip_exactly() {
    let dir = common::temp_dir("project-roundtrip");
    let p = rich_project(&dir);
    let path = dir.join("a.talas");
    p.save(&path).expect("save");
    let back = Project::load(&path).expect("load");
    assert_eq!(back, p, "every field, floats bit for bit");
    // The stock is the bbox grown by 2 mm.
    assert_eq!(
        back.stock,
        Stock::Box {
            min_mm: [-12.0, -7.0, -2.0],
            max_mm: [12.0, 7.0, 9.5]
        }
    );
    // No temporary file is left behind.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(|e| e.ok().map(|e| e.file_name()))
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn cylinder_stock_encloses_the_box_corners() {
    let b = Aabb {
        min: glam::DVec3::new(0.0, 0.0, 0.0),
        max: glam::DVec3::new(6.0, 8.0, 3.0),
    };
    // Half-diagonal of the 6 × 8 rectangle is 5 mm.
    assert_eq!(
        Stock::cylinder_around(&b, 1.0),
        Stock::Cylinder {
            base_mm: [3.0, 4.0, -1.0],
            radius_mm: 6.0,
            height_mm: 5.0
        }
    );
}

#[test]
fn part_reference_notices_a_changed_or_moved_file() {
    let dir = common::temp_dir("project-partref");
    let path = dir.join("p.stl");
    std::fs::write(&path, b"abc").expect("write");
    let r = PartRef::from_file(&path).expect("ref");
    // FNV-1a 64 of "abc" (published test vector).
    assert_eq!(r.content_hash, "e71fa2190541574b");
    assert_eq!(content_hash(b""), "cbf29ce484222325");
    assert_eq!(r.status(), PartStatus::Unchanged);
    std::fs::write(&path, b"abd").expect("write");
    assert_eq!(r.status(), PartStatus::Changed);
    std::fs::remove_file(&path).expect("rm");
    assert!(matches!(r.status(), PartStatus::Missing(m) if m.contains("p.stl")));
}

#[test]
fn a_failed_save_keeps_the_old_file() {
    let dir = common::temp_dir("project-failsave");
    let path = dir.join("keep.talas");
    let old = rich_project(&dir);
    old.save(&path).expect("first save");
    let old_bytes = std::fs::read(&path).expect("read");

    // The rename target is a non-empty directory: the rename fails.
    let blocked = dir.join("blocked.talas");
    std::fs::create_dir_all(blocked.join("inside")).expect("mkdir");
    let err = Project::default()
        .save(&blocked)
        .expect_err("cannot replace a directory");
    assert!(err.to_string().contains("blocked.talas"), "{err}");
    assert!(blocked.join("inside").is_dir());

    // A folder that does not exist: the temporary file cannot be created.
    let nowhere = dir.join("no-such-dir").join("x.talas");
    assert!(matches!(
        Project::default().save(&nowhere),
        Err(ProjectError::Io { .. })
    ));

    // The first file is untouched and no temporary files remain.
    assert_eq!(std::fs::read(&path).expect("read"), old_bytes);
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty());
}

fn parse_err(text: &str) -> ProjectError {
    Project::from_toml(text, Path::new("bad.talas")).expect_err("must fail")
}

#[test]
fn malformed_files_give_one_error_with_a_place() {
    let good = Project::default().to_toml().expect("toml");
    // Syntax error on line 3.
    let text = "version = 1\nname = \"x\"\nmachine = = \"mill\"\n";
    match parse_err(text) {
        ProjectError::Parse {
            line,
            column,
            path,
            message,
        } => {
            assert_eq!((line, column), (3, 11), "{message}");
            assert_eq!(path, Path::new("bad.talas"));
        }
        e => panic!("{e:?}"),
    }
    // A mistyped field: the place of the value.
    let text = good.replacen("name = \"Untitled\"", "name = 5", 1);
    let line = text.lines().position(|l| l == "name = 5").expect("line") + 1;
    match parse_err(&text) {
        ProjectError::Parse {
            line: l, column, ..
        } => assert_eq!((l, column), (line, 8)),
        e => panic!("{e:?}"),
    }
    // A wrongly typed field names it.
    let e = parse_err("version = 1\nname = \"x\"\nmachine = 3\n");
    assert!(e.to_string().starts_with("bad.talas:"), "{e}");
    assert!(e.to_string().contains(":3:"), "{e}");
    // Newer version.
    let text = good.replacen("version = 1", "version = 99", 1);
    assert!(matches!(
        parse_err(&text),
        ProjectError::Version { found: 99, .. }
    ));
    // A tool with a bad size: refused where the tool is read, with its line.
    let text = good.replacen("diameter = 6.0", "diameter = -6.0", 1);
    let e = parse_err(&text);
    assert!(matches!(e, ProjectError::Parse { line: 10, .. }), "{e:?}");
    assert!(e.to_string().contains("diameter"), "{e}");
    // Selection past the end.
    let text = good.replacen("selected_tool = 0", "selected_tool = 4", 1);
    assert!(matches!(parse_err(&text), ProjectError::Invalid { .. }));
    // Missing file.
    let e = Project::load(Path::new("/nonexistent/x.talas")).expect_err("missing");
    assert!(e.to_string().contains("/nonexistent/x.talas"));
}

#[test]
fn refused_edits_change_nothing() {
    let mut p = Project::default();
    let before = p.clone();
    let mut bad = tool("ball:d=6", "bad");
    bad.cutter.diameter = f64::NAN;
    assert!(matches!(
        p.apply(Edit::SetTool {
            index: 0,
            tool: bad
        }),
        Err(EditError::Invalid(_))
    ));
    assert!(matches!(
        p.apply(Edit::RemoveTool { index: 7 }),
        Err(EditError::NoSuchItem {
            index: 7,
            count: 1,
            ..
        })
    ));
    // A batch that fails half way is rolled back.
    let r = p.apply(Edit::Batch(vec![
        Edit::Rename("new".into()),
        Edit::SelectTool(Some(9)),
    ]));
    assert!(r.is_err());
    assert_eq!(p, before);
}

fn random_edit(rng: &mut Lcg, p: &Project) -> Edit {
    let n = p.tools.len();
    let specs = [
        "ball:d=3",
        "flat:d=10",
        "bull:d=8,r=1.5",
        "cone:d=6,angle=45",
    ];
    match rng.below(9) {
        0 => Edit::Rename(format!("name {}", rng.next())),
        1 => Edit::AddTool {
            index: rng.below(n + 1),
            tool: tool(specs[rng.below(4)], "t"),
        },
        // Only tools no operation uses can be deleted.
        2 if (0..n).any(|i| p.operations.iter().all(|op| op.tool() != i)) => {
            let free: Vec<usize> = (0..n)
                .filter(|&i| p.operations.iter().all(|op| op.tool() != i))
                .collect();
            Edit::RemoveTool {
                index: free[rng.below(free.len())],
            }
        }
        3 if n > 0 => {
            let mut t = tool(specs[rng.below(4)], "edited");
            let extra = rng.below(10) as f64;
            t.cutter.flute_length += extra;
            t.cutter.overall_length += extra;
            Edit::SetTool {
                index: rng.below(n),
                tool: t,
            }
        }
        4 => Edit::SelectTool(if n > 0 && rng.below(4) > 0 {
            Some(rng.below(n))
        } else {
            None
        }),
        5 if n > 0 => Edit::duplicate_tool(p, rng.below(n)).expect("valid index"),
        6 => Edit::SetMachine(["mill-3axis", "trt-ac", "trt-bc"][rng.below(3)].into()),
        7 => Edit::SetStock(Stock::Box {
            min_mm: [0.0; 3],
            max_mm: [1.0 + rng.below(50) as f64, 2.0, 3.0],
        }),
        8 if n > 0 => Edit::AddOperation {
            index: rng.below(p.operations.len() + 1),
            operation: Operation::new(OperationKind::Raster, rng.below(n), 0),
        },
        _ => Edit::Rename(format!("renamed {}", rng.next())),
    }
}

#[test]
fn undo_and_redo_restore_every_state_exactly() {
    let mut rng = Lcg(20_261_122);
    for _run in 0..50 {
        let mut p = Project::default();
        let mut h = History::new();
        // states[k] = the project after k steps.
        let mut states = vec![p.clone()];
        let mut at = 0usize;
        for _ in 0..120 {
            match rng.below(5) {
                0 => {
                    if h.undo(&mut p).is_some() {
                        at -= 1;
                    } else {
                        assert_eq!(at, 0);
                    }
                }
                1 => {
                    if h.redo(&mut p).is_some() {
                        at += 1;
                    } else {
                        assert_eq!(at + 1, states.len());
                    }
                }
                _ => {
                    let e = random_edit(&mut rng, &p);
                    h.apply(&mut p, e).expect("generated edits are valid");
                    states.truncate(at + 1);
                    states.push(p.clone());
                    at += 1;
                }
            }
            assert_eq!(p, states[at], "state {at}");
            let sel_ok = p.selected_tool.is_none_or(|s| s < p.tools.len());
            assert!(sel_ok, "selection points at a tool");
        }
        // Undo everything: back to the start, and clean again.
        while h.undo(&mut p).is_some() {}
        assert_eq!(p, states[0]);
        assert!(!h.is_dirty());
    }
}

#[test]
fn dirty_flag_follows_the_saved_state() {
    let mut p = Project::default();
    let mut h = History::new();
    assert!(!h.is_dirty());
    h.apply(&mut p, Edit::Rename("a".into())).expect("ok");
    assert!(h.is_dirty());
    h.mark_saved();
    assert!(!h.is_dirty());
    assert_eq!(h.undo(&mut p), Some("Rename project"));
    assert!(h.is_dirty(), "undo past the save is a change");
    h.redo(&mut p);
    assert!(!h.is_dirty(), "redo back to the saved state is clean");
    h.undo(&mut p);
    h.apply(&mut p, Edit::Rename("b".into())).expect("ok");
    assert!(!h.can_redo());
    assert!(h.is_dirty());
    h.mark_unsaved();
    while h.undo(&mut p).is_some() {}
    assert!(h.is_dirty(), "never saved");
}

#[test]
fn operations_keep_their_tools_when_the_library_changes() {
    let mut p = Project::default();
    p.tools.push(tool("flat:d=10", "Flat 10"));
    let mut h = History::new();
    h.apply(
        &mut p,
        Edit::AddOperation {
            index: 0,
            operation: Operation::new(OperationKind::Rough, 1, 0),
        },
    )
    .expect("operation added");
    let before = p.clone();
    // A tool inserted before the operation's tool: the operation follows it.
    h.apply(
        &mut p,
        Edit::AddTool {
            index: 0,
            tool: tool("ball:d=3", "Ball 3"),
        },
    )
    .expect("tool added");
    assert_eq!(p.operations[0].tool(), 2);
    assert_eq!(p.tools[2].name, "Flat 10");
    // The tool in use cannot be deleted; another can, and the index follows.
    assert!(h.apply(&mut p, Edit::RemoveTool { index: 2 }).is_err());
    h.apply(&mut p, Edit::RemoveTool { index: 0 })
        .expect("unused tool removed");
    assert_eq!(p.operations[0].tool(), 1);
    h.undo(&mut p);
    h.undo(&mut p);
    assert_eq!(p, before);
    // A setup outside G54…G59 or with a non-finite origin is refused.
    let bad_setup = talas::project::Frame {
        work_offset: 7,
        ..talas::project::Frame::default()
    };
    assert!(
        h.apply(
            &mut p,
            Edit::SetFrame {
                setup: 0,
                frame: bad_setup
            }
        )
        .is_err()
    );
    let nan_setup = talas::project::Frame {
        work_offset: 2,
        origin_mm: [0.0, f64::NAN, 0.0],
        ..talas::project::Frame::default()
    };
    assert!(
        h.apply(
            &mut p,
            Edit::SetFrame {
                setup: 0,
                frame: nan_setup
            }
        )
        .is_err()
    );
    assert_eq!(talas::project::Frame::default().work_offset_code(), "G54");
    // An operation naming a missing tool or with a bad number is refused.
    let bad = Operation::new(OperationKind::Raster, 9, 0);
    assert!(
        h.apply(
            &mut p,
            Edit::AddOperation {
                index: 0,
                operation: bad
            }
        )
        .is_err()
    );
    let mut neg = Operation::new(OperationKind::Raster, 0, 0);
    if let Operation::Raster { scallop_mm, .. } = &mut neg {
        *scallop_mm = -1.0;
    }
    let e = h
        .apply(
            &mut p,
            Edit::SetOperation {
                index: 0,
                operation: neg,
            },
        )
        .expect_err("negative scallop refused");
    assert!(e.to_string().contains("scallop"), "{e}");
    assert_eq!(p, before);
}

/// A project written by hand or another program: missing fields take their documented
/// defaults; every value an edit would refuse is refused on load too, naming it.
#[test]
fn loading_validates_like_editing_and_fills_defaults() {
    let p = Project::from_toml("", Path::new("empty.talas")).expect("defaults");
    assert_eq!(
        (p.version, p.name.as_str(), p.machine.as_str()),
        (1, "Untitled", "mill-3axis")
    );
    let good = Project::default().to_toml().expect("toml");
    let with_op = |op: Operation| {
        let mut p = Project::default();
        p.operations.push(op);
        p.to_toml().expect("toml")
    };
    let raster = Operation::new(OperationKind::Raster, 0, 0);
    let nan_scallop = match raster.clone() {
        Operation::Raster {
            name,
            tool,
            angle_rad,
            one_way,
            tolerance_mm,
            feed_mm_per_min,
            clearance_mm,
            ..
        } => Operation::Raster {
            name,
            tool,
            scallop_mm: f64::NAN,
            angle_rad,
            one_way,
            tolerance_mm,
            feed_mm_per_min,
            clearance_mm,
            boundary: None,
        },
        other => other,
    };
    let cases: Vec<(String, &str)> = vec![
        (
            good.replacen("work_offset = 1", "work_offset = 200", 1),
            "work offset",
        ),
        (
            good.replacen("origin_mm = [\n    0.0,", "origin_mm = [\n    nan,", 1),
            "origin",
        ),
        (
            good.replacen("machine = \"mill-3axis\"", "machine = \"no-such-mill\"", 1),
            "no-such-mill",
        ),
        (
            good.replacen("dialect = \"linuxcnc\"", "dialect = \"klingon\"", 1),
            "klingon",
        ),
        (
            good.replacen("spindle_rpm = 10000.0", "spindle_rpm = nan", 1),
            "spindle",
        ),
        (with_op(raster.with_tool(99)), "tool 100"),
        (with_op(nan_scallop), "operation 1"),
    ];
    for (text, named) in cases {
        assert_ne!(text, good, "the case {named} changed nothing");
        let e = parse_err(&text);
        assert!(matches!(e, ProjectError::Invalid { .. }), "{named}: {e:?}");
        assert!(e.to_string().contains(named), "{named}: {e}");
    }
    let mut p = Project::default();
    p.operations
        .push(Operation::new(OperationKind::IsoScallop, 0, 9999));
    let e = p.check_faces(30).expect_err("face 10000 of 30");
    assert!(e.contains("face 10000"), "{e}");
    assert!(p.check_faces(10_000).is_ok());
}

/// A tool library or project written by another program may give a tool by its spec alone, or
/// by kind and diameter; contradictions are refused.
#[test]
fn tools_are_read_from_a_spec_or_the_fewest_fields() {
    let text = "machine = \"mill-3axis\"\n\
                [[tools]]\nspec = \"bull:d=10,r=2\"\n\
                [[tools]]\nname = \"Flat 8\"\n[tools.cutter]\nkind = { type = \"flat\" }\ndiameter = 8.0\n";
    let p = Project::from_toml(text, Path::new("other.talas")).expect("generous");
    assert_eq!(p.tools.len(), 2);
    assert_eq!(p.tools[0].name, "bull:d=10,r=2");
    assert_eq!(p.tools[0].cutter, parse_tool_spec("bull:d=10,r=2").unwrap());
    assert_eq!(p.tools[1].cutter.diameter, 8.0);
    assert_eq!(p.tools[1].cutter, parse_tool_spec("flat:d=8").unwrap());
    let bad = "[[tools]]\nspec = \"ball:d=6\"\n[tools.cutter]\ndiameter = 8.0\n";
    let e = Project::from_toml(bad, Path::new("other.talas")).expect_err("contradiction");
    assert!(e.to_string().contains("diameter 8"), "{e}");
    assert!(e.to_string().contains("other.talas"), "{e}");
}

#[test]
fn undo_and_redo_labels_name_the_step_the_user_took() {
    let mut p = Project::default();
    let mut h = History::new();
    let operation = Operation::new(OperationKind::Raster, 0, 0);
    h.apply(
        &mut p,
        Edit::AddOperation {
            index: 0,
            operation,
        },
    )
    .expect("added");
    assert_eq!(h.undo_label(), Some("Add operation"));
    assert_eq!(h.undo(&mut p), Some("Add operation"));
    assert_eq!(h.redo_label(), Some("Add operation"));
    assert_eq!(h.redo(&mut p), Some("Add operation"));
    h.apply(&mut p, Edit::RemoveOperation { index: 0 })
        .expect("removed");
    assert_eq!(h.undo_label(), Some("Delete operation"));
    h.undo(&mut p);
    assert_eq!(h.redo_label(), Some("Delete operation"));
    assert_eq!(h.undo_label(), Some("Add operation"));
}
