//! `talas job PROJECT.talas [--part FILE] [--setup NAME] [--post DIR] [--simulate] [--sheet
//! OUT.html] [--json]`:
//! plan every operation of every setup (or of one) in its setup's frame, post one program per
//! setup into DIR (`NN-SETUP.ngc`), simulate each setup's operations on its stock, and print
//! per setup and operation the tool, the lengths and times, the first contact of the tool
//! assembly with the setup's workholding (`checks::collide`, with its program line when
//! posted), and the program file.
//!
//! The simulation ([`crate::project::job_sim::simulate_job`]) cuts the setups in order and
//! carries the cut stock into each setup whose stock is the previous one's (`"stock_carried":
//! true`; per setup its start and end volumes); with `--setup NAME` the setups before it are
//! planned and simulated too. Each setup's simulation tests the tool against its workholding
//! along the moves it cuts, and reports the pose and line planning reports.
//!
//! Posted and simulated paths are linked (`project::job::link_setup`): each path's rapids are
//! lifted over the stock the setup's paths before it left (`project::rapids::link`, over the
//! setup's own starting stock: the carried material is not yet linked over), and the
//! per-operation output gives `rapids_lifted` and `fed_links_through_stock`.

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::diagnostics::Progress;
use crate::import::{ImportError, OpenOptions, Workpiece, open};
use crate::project::Project;
use crate::project::job::{link_setup, plan_in_setup, post_setup, program_stem};
use crate::project::job_sim::{
    self, SetupSimulation, WorkholdingHit, simulate_job, workholding_hits,
};
use crate::project::setups;
use crate::project::simulate::SimulationSettings;
use crate::toolpath::Toolpath;

/// Options of `talas job`.
#[derive(Debug, clap::Args)]
pub struct JobArgs {
    /// The project file.
    pub file: PathBuf,
    /// The part (STEP or STL); default: the part the project references (relative to the
    /// project's folder).
    #[arg(long, value_name = "FILE")]
    pub part: Option<PathBuf>,
    /// Only this setup (by name).
    #[arg(long, value_name = "NAME")]
    pub setup: Option<String>,
    /// Write one program per setup into this folder (`NN-SETUP.ngc`, written atomically).
    #[arg(long, value_name = "DIR")]
    pub post: Option<PathBuf>,
    /// Simulate each setup's operations on its stock (removed volume, collisions).
    #[arg(long)]
    pub simulate: bool,
    /// Write the job's setup sheet (one self-contained HTML file: tools, and per setup a
    /// picture of the part, stock and workholding with the work offset's axes, the stock
    /// size, and per operation feeds, speeds, heights and times).
    #[arg(long, value_name = "OUT.html")]
    pub sheet: Option<PathBuf>,
    /// Print one JSON document instead of the summary.
    #[arg(long)]
    pub json: bool,
}

fn bad(file: &Path, place: Option<String>, message: impl Into<String>) -> ImportError {
    ImportError::new(file, place, message)
}

/// Run the job; the JSON document (also the source of the human summary).
///
/// # Errors
/// An [`ImportError`] naming the file (the project, the part, a program) and the setup or
/// operation.
pub fn job(args: &JobArgs) -> Result<Value, ImportError> {
    let (project, warnings) = Project::load_with_warnings(&args.file)
        .map_err(|e| bad(&args.file, None, e.to_string()))?;
    for w in warnings {
        eprintln!("talas: warning: {w}");
    }
    let base = args.file.parent().unwrap_or(Path::new("."));
    // The loader made a relative part path absolute against the project's folder.
    let part_path = match (&args.part, &project.part) {
        (Some(p), _) => p.clone(),
        (None, Some(r)) => r.path.clone(),
        (None, None) => {
            return Err(bad(
                &args.file,
                None,
                "the project uses the embedded default part: give the part with --part FILE",
            ));
        }
    };
    let part = open(&part_path, &OpenOptions::default(), &Progress::new())?;
    project
        .check_faces(part.part.as_ref().map_or(0, |p| p.faces.len()))
        .map_err(|e| bad(&args.file, None, e))?;
    let chosen: Vec<usize> = match &args.setup {
        Some(name) => vec![
            project
                .setups
                .iter()
                .position(|s| &s.name == name)
                .ok_or_else(|| {
                    let names: Vec<&str> = project.setups.iter().map(|s| s.name.as_str()).collect();
                    bad(
                        &args.file,
                        None,
                        format!(
                            "--setup: no setup '{name}' (there are: {})",
                            names.join(", ")
                        ),
                    )
                })?,
        ],
        None => (0..project.setups.len()).collect(),
    };
    let placements =
        setups::placements(&project, Some(&part)).map_err(|e| bad(&args.file, None, e))?;
    let bounds = part.mesh.bbox();
    if let Some(dir) = &args.post {
        std::fs::create_dir_all(dir)
            .map_err(|e| bad(dir, None, format!("cannot make the folder: {e}")))?;
    }
    // The simulation carries the stock from the first setup on, so every setup up to the last
    // chosen one is planned when simulating.
    let last = chosen.iter().copied().max().unwrap_or(0);
    let planned: Vec<usize> = if args.simulate {
        (0..=last).collect()
    } else {
        chosen.clone()
    };
    let mut plans: Vec<Option<(Vec<Value>, Vec<Toolpath>)>> = vec![None; last + 1];
    for &s in &planned {
        plans[s] = Some(plan_setup(args, &project, s, &part)?);
    }
    let simulated = if args.simulate {
        let paths: Vec<Vec<Toolpath>> = plans
            .iter()
            .map(|p| p.as_ref().map(|(_, t)| t.clone()).unwrap_or_default())
            .collect();
        Some(
            simulate_job(
                &project,
                &part,
                base,
                &paths,
                &SimulationSettings::default(),
                &Progress::new(),
            )
            .map_err(|e| bad(&args.file, None, e))?,
        )
    } else {
        None
    };
    let mut out = Vec::new();
    let mut pages = Vec::new();
    for &s in &chosen {
        let Some((ops, paths)) = plans[s].take() else {
            continue;
        };
        if args.sheet.is_some() {
            pages.push(
                super::job_sheet::setup_page(&project, s, &part, &placements, base, &paths)
                    .map_err(|e| {
                        bad(
                            &args.file,
                            Some(format!("setup {} ('{}')", s + 1, project.setups[s].name)),
                            e,
                        )
                    })?,
            );
        }
        let sim = simulated.as_ref().and_then(|v| v.get(s));
        out.push(run_setup(
            args,
            &project,
            s,
            ops,
            &paths,
            sim,
            &placements,
            &bounds,
            base,
        )?);
    }
    let mut sheet_file = Value::Null;
    if let Some(file) = &args.sheet {
        let sheet = crate::project::sheet::Sheet {
            project: project.name.clone(),
            part: part_path.display().to_string(),
            material: material_text(&project),
            tools: super::job_sheet::tools(&project, &chosen),
            setups: pages,
        };
        crate::storage::write_atomic(file, crate::project::sheet::html(&sheet).as_bytes())
            .map_err(|e| bad(file, None, format!("cannot write: {e}")))?;
        sheet_file = json!(file.display().to_string());
    }
    Ok(json!({
        "project": args.file.display().to_string(),
        "part": part_path.display().to_string(),
        "stock_carried": args.simulate,
        "material": project.material.as_ref().map(|m| json!({
            "key": m.key,
            "name": m.material().ok().map(|x| x.name),
            "tool_material": m.tool_material.name(),
        })),
        "setups": out,
        "sheet": sheet_file,
    }))
}

/// The work material and the tools' material, as the setup sheet names them.
fn material_text(project: &Project) -> Option<String> {
    project.material.as_ref().map(|m| {
        let name = m.material().map_or_else(|e| e, |x| x.name.to_string());
        format!("{name} ({} tools)", m.tool_material.name())
    })
}

/// Plan setup `s`'s operations in its frame: their JSON records and tool paths.
fn plan_setup(
    args: &JobArgs,
    project: &Project,
    s: usize,
    part: &Workpiece,
) -> Result<(Vec<Value>, Vec<Toolpath>), ImportError> {
    let setup = &project.setups[s];
    let place = Some(format!("setup {} ('{}')", s + 1, setup.name));
    let mut paths: Vec<Toolpath> = Vec::new();
    let mut ops = Vec::new();
    for &op in &setup.operations {
        let c = plan_in_setup(project, op, part, &Progress::new())
            .map_err(|e| bad(&args.file, place.clone(), e.to_string()))?;
        let o = &project.operations[op];
        let tool = project.tools.get(o.tool());
        let sm = &c.toolpath.summary;
        let speeds = crate::project::cutting::SpeedsOrigin::of(project, o);
        ops.push(json!({
            "index": op + 1,
            "name": o.name(),
            "kind": o.kind().label(),
            "tool": {
                "number": o.tool() + 1,
                "name": tool.map(|t| t.name.clone()),
                "spec": tool.map(|t| crate::tools::tool_spec(&t.cutter)),
            },
            "feed_mm_per_min": crate::project::cutting::cutting_feed(o),
            "spindle_rpm": o.common().and_then(|c| c.spindle_rpm),
            "speeds_from": {
                "kind": speeds.key(),
                "text": speeds.describe(),
            },
            "poses": sm.pose_count,
            "cut_length_mm": sm.cut_length_mm,
            "other_length_mm": sm.other_length_mm,
            "estimated_time_s": sm.estimated_time_s,
            "diagnostics": c.diagnostics.iter().map(ToString::to_string).collect::<Vec<_>>(),
        }));
        paths.push(c.toolpath);
    }
    // Posted and simulated: each path linked over the stock the paths before it left (its
    // rapids lifted above it).
    if (args.post.is_some() || args.simulate) && !paths.is_empty() {
        let (linked, _) = link_setup(project, s, part, &paths, false, &Progress::new())
            .map_err(|e| bad(&args.file, place.clone(), e))?;
        for (op, l) in ops.iter_mut().zip(&linked) {
            op["rapids_lifted"] = json!(l.lift.lifted);
            op["rapids_worst_depth_mm"] = json!(l.lift.worst_depth_mm);
            op["fed_links_through_stock"] = json!(l.fed_links_through_stock);
            if let Some(d) = op["diagnostics"].as_array_mut() {
                d.extend(l.diagnostics.iter().map(|x| json!(x.to_string())));
            }
        }
        paths = linked.into_iter().map(|l| l.toolpath).collect();
    }
    Ok((ops, paths))
}

/// A workholding contact as JSON, with the program line of its pose when posted.
fn hit_json(
    hit: Option<&WorkholdingHit>,
    k: usize,
    posted_lines: Option<&[crate::post::LineSource]>,
) -> Value {
    hit.map_or(Value::Null, |h| {
        let line = posted_lines.and_then(|l| {
            l.iter()
                .rposition(|src| src.operation == k && src.pose == Some(h.block))
                .map(|i| i + 1)
        });
        json!({
            "pose": h.block,
            "line": line,
            "obstacle": h.hit.obstacle_name,
            "tool_part": h.hit.tool_part,
            "tip_mm": [h.hit.tip.x, h.hit.tip.y, h.hit.tip.z],
        })
    })
}

#[allow(clippy::too_many_arguments)]
fn run_setup(
    args: &JobArgs,
    project: &Project,
    s: usize,
    mut ops: Vec<Value>,
    paths: &[Toolpath],
    sim: Option<&SetupSimulation>,
    placements: &[setups::Placement],
    bounds: &crate::geometry::Aabb,
    base: &Path,
) -> Result<Value, ImportError> {
    let setup = &project.setups[s];
    let place = Some(format!("setup {} ('{}')", s + 1, setup.name));
    let err = |m: String| bad(&args.file, place.clone(), m);
    let workholding =
        setups::workholding_meshes(project, s, placements, bounds, base).map_err(err)?;
    let obstacles = job_sim::obstacles(project, s, placements, bounds, base).map_err(err)?;
    let hits = workholding_hits(paths, &obstacles);
    let mut posted_lines: Option<Vec<crate::post::LineSource>> = None;
    let mut program = Value::Null;
    let mut lines = Value::Null;
    if let Some(dir) = &args.post
        && !paths.is_empty()
    {
        let posted = post_setup(project, s, paths).map_err(|e| err(e.to_string()))?;
        let file = dir.join(format!("{:02}-{}.ngc", s + 1, program_stem(&setup.name)));
        crate::storage::write_atomic(&file, posted.text.as_bytes())
            .map_err(|e| bad(&file, None, format!("cannot write: {e}")))?;
        program = json!(file.display().to_string());
        lines = json!(posted.text.lines().count());
        posted_lines = Some(posted.source_of_line);
    }
    let simulation = sim.map_or(Value::Null, |r| {
        json!({
            "carried": r.carried,
            "resolution_mm": r.resolution_mm,
            "start_volume_mm3": r.start_volume_mm3,
            "end_volume_mm3": r.end_volume_mm3,
            "initial_volume_mm3": r.start_volume_mm3,
            "removed_volume_mm3": r.removed_volume_mm3,
            "final_volume_mm3": r.end_volume_mm3,
            "carried_mesh_triangles": r.carried_triangles,
            "carried_mesh_volume_mm3": r.carried_mesh_volume_mm3,
            "collisions": r.stock_collisions,
            "max_gouge_mm": r.max_gouge_mm,
            "workholding_collisions": r.workholding.iter().enumerate()
                .map(|(k, h)| hit_json(h.as_ref(), k, posted_lines.as_deref()))
                .collect::<Vec<_>>(),
        })
    });
    for (k, (op, hit)) in ops.iter_mut().zip(&hits).enumerate() {
        op["workholding_collision"] = hit_json(hit.as_ref(), k, posted_lines.as_deref());
    }
    let axis = placements[s].tool_axis();
    Ok(json!({
        "name": setup.name,
        "machine": setup.machine_name(project),
        "work_offset": setup.frame.work_offset_code(),
        "tool_axis": [axis.x, axis.y, axis.z],
        "operations": ops,
        "estimated_time_s": paths.iter().map(|p| p.summary.estimated_time_s).sum::<f64>(),
        "workholding": setup.workholding.iter().zip(&workholding).map(|(w, m)| json!({
            "kind": w.kind_name(),
            "volume_mm3": m.signed_volume(),
        })).collect::<Vec<_>>(),
        "program": program,
        "program_lines": lines,
        "simulation": simulation,
    }))
}

/// The human summary of a job document.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = String::new();
    let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    for setup in doc["setups"].as_array().into_iter().flatten() {
        s.push_str(&format!(
            "setup '{}' on {} ({}), {:.1} s estimated\n",
            setup["name"].as_str().unwrap_or(""),
            setup["machine"].as_str().unwrap_or(""),
            setup["work_offset"].as_str().unwrap_or(""),
            num(&setup["estimated_time_s"]),
        ));
        for op in setup["operations"].as_array().into_iter().flatten() {
            s.push_str(&format!(
                "  {}. {} ({}), tool T{} {}: {} poses, cut {:.1} mm, {:.1} s\n",
                op["index"],
                op["name"].as_str().unwrap_or(""),
                op["kind"].as_str().unwrap_or(""),
                op["tool"]["number"],
                op["tool"]["spec"].as_str().unwrap_or(""),
                op["poses"],
                num(&op["cut_length_mm"]),
                num(&op["estimated_time_s"]),
            ));
        }
        for w in setup["workholding"].as_array().into_iter().flatten() {
            s.push_str(&format!(
                "  workholding: {} ({:.0} mm³)\n",
                w["kind"].as_str().unwrap_or(""),
                num(&w["volume_mm3"])
            ));
        }
        for op in setup["operations"].as_array().into_iter().flatten() {
            let c = &op["workholding_collision"];
            if c.is_object() {
                s.push_str(&format!(
                    "  COLLISION: operation {} hits the {} with the {} at pose {} (line {}), tip ({:.3}, {:.3}, {:.3}) mm\n",
                    op["index"],
                    c["obstacle"].as_str().unwrap_or(""),
                    c["tool_part"].as_str().unwrap_or(""),
                    c["pose"],
                    c["line"],
                    num(&c["tip_mm"][0]),
                    num(&c["tip_mm"][1]),
                    num(&c["tip_mm"][2]),
                ));
            }
        }
        if let Some(p) = setup["program"].as_str() {
            s.push_str(&format!(
                "  program: {p} ({} lines)\n",
                setup["program_lines"]
            ));
        }
        if setup["simulation"].is_object() {
            let sim = &setup["simulation"];
            s.push_str(&format!(
                "  simulated{}: {:.1} mm³ at the start, removed {:.1} mm³, {:.1} mm³ left, {} collisions, deepest gouge {:.4} mm\n",
                if sim["carried"] == true { " (stock carried from the previous setup)" } else { "" },
                num(&sim["start_volume_mm3"]),
                num(&sim["removed_volume_mm3"]),
                num(&sim["end_volume_mm3"]),
                sim["collisions"],
                num(&sim["max_gouge_mm"]),
            ));
            for (k, c) in sim["workholding_collisions"]
                .as_array()
                .into_iter()
                .flatten()
                .enumerate()
            {
                if c.is_object() {
                    s.push_str(&format!(
                        "  SIMULATION COLLISION: operation {} hits the {} with the {} at pose {} (line {})\n",
                        setup["operations"][k]["index"],
                        c["obstacle"].as_str().unwrap_or(""),
                        c["tool_part"].as_str().unwrap_or(""),
                        c["pose"],
                        c["line"],
                    ));
                }
            }
        }
    }
    if let Some(f) = doc["sheet"].as_str() {
        s.push_str(&format!("setup sheet: {f}\n"));
    }
    s
}
