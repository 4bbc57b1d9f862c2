//! `talas forces PROGRAM.ngc|PATH.json --tool SPEC --coefficients FILE --stock SHAPE
//! [--machine NAME_OR_FILE] [--rpm N] [--max-force N] [--max-torque NM] [--max-power W]
//! [--schedule-force N -o OUT.json] [--json]`: cutting forces along a program or tool path,
//! move by move, with the engagement read from the simulated stock before each move; with
//! `--schedule-force`, the feeds rewritten so that the peak resultant force stays at the
//! target, written as a tool path, and the cycle time (jerk-limited feed planner) and the
//! force spread before and after.

use std::path::Path;

use serde_json::{Value, json};

use super::forces::ForcesArgs;
use crate::diagnostics::Progress;
use crate::force::library::Library;
use crate::force::path::{
    Limits, ModeCoefficients, MoveClass, PathForces, PathMove, PathOptions, path_forces,
};
use crate::force::stock::{SampleOptions, SimulatedStock, path_moves};
use crate::force::{EndMill, Force, ForceError};
use crate::gcode::{InterpretOptions, Syntax, interpret};
use crate::import::ImportError;
use crate::machine::Machine;
use crate::project::force_schedule::{CORNER_TOLERANCE_MM, ScheduleInput, schedule_path};
use crate::simulation::{
    DEFAULT_MEMORY_LIMIT_BYTES, DexelMode, DexelStock, MovePlan, StepOptions, plan_program,
    plan_toolpath,
};
use crate::toolpath::{ToolRecord, Toolpath};
use crate::tools::parse_tool_spec;

/// The program or tool path as read.
struct Input {
    plan: MovePlan,
    moves: Vec<PathMove>,
    tool: ToolRecord,
    is_json: bool,
}

fn read_input(args: &ForcesArgs, file: &Path) -> Result<Input, ImportError> {
    let bad = |place: Option<String>, msg: String| ImportError::new(file, place, msg);
    let is_json = file
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("json"));
    let text = crate::storage::read_text_bounded(file, crate::storage::PROGRAM_LIMIT_BYTES)
        .and_then(|t| {
            if is_json {
                Ok(t)
            } else {
                crate::storage::check_line_count(&t, crate::storage::PROGRAM_LINE_LIMIT).map(|()| t)
            }
        })
        .map_err(|e| bad(None, format!("cannot read file: {e}")))?;
    let (toolpath, program) = if is_json {
        let (tp, _) = Toolpath::from_json_with_warnings(&text, &file.display().to_string())
            .map_err(|e| bad(Some(e.place.clone()), e.message.clone()))?;
        (Some(tp), None)
    } else {
        let prog = interpret(&text, &InterpretOptions::for_syntax(Syntax::detect(&text))).map_err(
            |e| {
                bad(
                    Some(format!("line {}, column {}", e.line, e.column)),
                    e.message,
                )
            },
        )?;
        (None, Some(prog))
    };
    let tool = match (&args.tool, &toolpath) {
        (Some(name), _) if args.tool_library.is_some() => library_tool(args, name)?,
        (Some(spec), _) => ToolRecord {
            spec: spec.clone(),
            cutter: parse_tool_spec(spec)
                .map_err(|e| ImportError::new(Path::new("--tool"), None, e.to_string()))?,
        },
        (None, Some(tp)) => tp.tool.clone(),
        (None, None) => {
            return Err(ImportError::new(
                Path::new("--tool"),
                None,
                "a G-code program needs --tool SPEC",
            ));
        }
    };
    let machine = match &args.machine {
        Some(m) => Some(
            Machine::resolve(m).map_err(|e| ImportError::new(Path::new(m), None, e.to_string()))?,
        ),
        None => None,
    };
    let step_opts = StepOptions::for_resolution(args.resolution, tool.cutter.flute_length);
    let plan = match (&toolpath, &program) {
        (Some(tp), _) => plan_toolpath(tp, &step_opts),
        (None, Some(p)) => plan_program(p, machine.as_ref(), &step_opts),
        (None, None) => Ok(MovePlan::default()),
    }
    .map_err(|e| super::simulate::sim_err(file, &e, is_json))?;
    let rpm = args.rpm.unwrap_or(0.0);
    let moves = path_moves(&plan, |i| {
        program
            .as_ref()
            .and_then(|p| p.blocks.get(i))
            .map(|b| b.spindle_rpm.abs())
            .filter(|s| *s > 0.0)
            .unwrap_or(rpm)
    });
    Ok(Input {
        plan,
        moves,
        tool,
        is_json,
    })
}

/// The entry `name` of the tool library `--tool-library` (names compared without case).
pub(crate) fn library_tool(args: &ForcesArgs, name: &str) -> Result<ToolRecord, ImportError> {
    #[derive(serde::Deserialize)]
    struct Tools {
        #[serde(default)]
        tools: Vec<crate::project::ToolEntry>,
    }
    let Some(file) = args.tool_library.as_deref() else {
        return Err(ImportError::new(
            Path::new("--tool-library"),
            None,
            "no file given",
        ));
    };
    let text = crate::storage::read_text_bounded(file, crate::storage::PROGRAM_LIMIT_BYTES)
        .map_err(|e| ImportError::new(file, None, e.to_string()))?;
    let lib: Tools = toml::from_str(&text).map_err(|e| {
        let at = e.span().map_or(0, |s| s.start).min(text.len());
        let line = text.get(..at).unwrap_or("").matches('\n').count() + 1;
        ImportError::new(file, Some(format!("line {line}")), e.message().trim())
    })?;
    let entry = lib
        .tools
        .iter()
        .find(|t| t.name.trim().eq_ignore_ascii_case(name.trim()))
        .ok_or_else(|| {
            let names: Vec<&str> = lib.tools.iter().map(|t| t.name.as_str()).collect();
            ImportError::new(
                file,
                None,
                format!("no tool named '{name}' (tools: {})", names.join(", ")),
            )
        })?;
    Ok(ToolRecord {
        spec: crate::tools::tool_spec(&entry.cutter),
        cutter: entry.cutter.clone(),
    })
}

/// Where each limit comes from: the flag, else the tool (its record, or its library entry),
/// else (power) the machine's spindle; the power limit is the lower of the tool's and the
/// spindle's.
fn limits(args: &ForcesArgs, tool: &ToolRecord) -> Result<(Limits, Value), ImportError> {
    let t = tool.cutter.limits;
    let spindle = match &args.machine {
        Some(m) => {
            Machine::resolve(m)
                .map_err(|e| ImportError::new(Path::new(m), None, e.to_string()))?
                .spindle_power_w
        }
        None => None,
    };
    let pick = |flag: Option<f64>, tool: Option<f64>| match (flag, tool) {
        (Some(v), _) => (Some(v), "option"),
        (None, Some(v)) => (Some(v), "tool"),
        (None, None) => (None, "none"),
    };
    let (force, fs) = pick(args.max_force, t.max_force_n);
    let (torque, ts) = pick(args.max_torque, t.max_torque_nm);
    let (mut power, mut ps) = pick(args.max_power, t.max_power_w);
    if args.max_power.is_none()
        && let Some(s) = spindle
        && power.is_none_or(|p| s < p)
    {
        (power, ps) = (Some(s), "machine spindle");
    }
    for (flag, v) in [
        ("--max-force", args.max_force),
        ("--max-torque", args.max_torque),
        ("--max-power", args.max_power),
    ] {
        if let Some(v) = v
            && !(v.is_finite() && v > 0.0)
        {
            return Err(ImportError::new(
                Path::new(flag),
                None,
                format!("must be a positive number, got {v}"),
            ));
        }
    }
    Ok((
        Limits {
            max_force_n: force,
            max_torque_nm: torque,
            max_power_w: power,
        },
        json!({"force": fs, "torque": ts, "power": ps}),
    ))
}

/// The coefficients per mode from the library: a slot uses the slot (or any-mode) entry, else
/// the up one, else the down one.
fn mode_coefficients(args: &ForcesArgs) -> Result<(ModeCoefficients, String), ImportError> {
    let file = &args.coefficients;
    let library = Library::load(file).map_err(|m| {
        let prefix = format!("{}: ", file.display());
        ImportError::new(
            file,
            None,
            m.strip_prefix(&prefix).unwrap_or(&m).to_string(),
        )
    })?;
    library
        .mode_coefficients(args.material.as_deref())
        .map_err(|m| ImportError::new(file, None, m))
}

fn force_json(f: &Force) -> Value {
    json!({"fx": f.fx, "fy": f.fy, "fz": f.fz})
}

fn force_err(file: &Path, is_json: bool, e: ForceError) -> ImportError {
    match e {
        ForceError::Move { block, message } => {
            let place = if is_json { "pose" } else { "line" };
            ImportError::new(file, Some(format!("{place} {block}")), message)
        }
        other => ImportError::new(file, None, other.to_string()),
    }
}

/// Forces along the program or tool path `file`, and the feed schedule when asked.
///
/// # Errors
/// An [`ImportError`] naming the file and place, or the option, for bad input.
pub fn path_cmd(args: &ForcesArgs, file: &Path) -> Result<Value, ImportError> {
    let input = read_input(args, file)?;
    let mill = EndMill::from_cutter(&input.tool.cutter)
        .map_err(|e| ImportError::new(Path::new("--tool"), None, e.to_string()))?;
    let (coefficients, material) = mode_coefficients(args)?;
    if args.stock.is_empty() {
        return Err(ImportError::new(
            Path::new("--stock"),
            None,
            "forces along a program need the stock (--stock box:X0,Y0,Z0,X1,Y1,Z1 ...)",
        ));
    }
    let shapes = args
        .stock
        .iter()
        .map(|s| super::simulate::parse_stock(s, None))
        .collect::<Result<Vec<_>, _>>()?;
    let mode = if input.plan.tilted() {
        DexelMode::Tri
    } else {
        DexelMode::Z
    };
    let stock = DexelStock::new(shapes, args.resolution, mode, DEFAULT_MEMORY_LIMIT_BYTES)
        .map_err(|e| ImportError::new(Path::new("--stock"), None, e.to_string()))?;
    let (limits, limit_sources) = limits(args, &input.tool)?;
    let options = PathOptions {
        sample_spacing_mm: args.sample_spacing,
        flute_length_mm: input.tool.cutter.flute_length,
        sample: SampleOptions::default(),
        limits,
        ..PathOptions::default()
    };
    let mut work = SimulatedStock::new(stock, &input.tool.cutter, &input.plan);
    let forces = path_forces(&mut work, &mill, &coefficients, &input.moves, &options)
        .map_err(|e| force_err(file, input.is_json, e))?;
    let mut doc = forces_json(&forces, &input, &options, &material);
    doc["limit_sources"] = limit_sources;
    if let Some(target) = args.schedule_force {
        let out = args.output.as_deref().ok_or_else(|| {
            ImportError::new(
                Path::new("--schedule-force"),
                None,
                "feed scheduling writes a tool path: give -o OUT.json",
            )
        })?;
        doc["schedule"] = schedule(args, &input, &coefficients, &forces, target, out)?;
    }
    Ok(doc)
}

fn forces_json(f: &PathForces, input: &Input, o: &PathOptions, material: &str) -> Value {
    let place = if input.is_json { "pose" } else { "line" };
    let moves: Vec<Value> = f
        .moves
        .iter()
        .filter(|m| m.class != MoveClass::Rapid)
        .map(|m| {
            json!({
                "move": m.move_index,
                place: m.block,
                "class": m.class,
                "length_mm": m.length_mm,
                "time_s": m.time_s,
                "feed_per_tooth_mm": m.feed_per_tooth_mm,
                "mean": force_json(&m.mean),
                "peak": force_json(&m.peak),
                "mean_resultant_n": m.mean_resultant_n,
                "peak_resultant_n": m.peak_resultant_n,
                "mean_torque_nm": m.mean_torque_nm,
                "peak_torque_nm": m.peak_torque_nm,
                "mean_power_w": m.mean_power_w,
                "peak_power_w": m.peak_power_w,
                "axial_depth_mm": m.axial_depth_mm,
                "immersion": m.immersion.iter().filter(|d| d.arcs > 0).collect::<Vec<_>>(),
                "limits_exceeded": m.limits_exceeded,
            })
        })
        .collect();
    json!({
        "units": {"force": "N", "torque": "N·m", "power": "W", "length": "mm", "time": "s",
                  "angle": "deg"},
        "frame": "machine: forces on the tool along X, Y, Z; immersion angles clockwise from \
                  the left normal of the feed",
        "input": if input.is_json { "toolpath" } else { "gcode" },
        "tool": input.tool.spec,
        "material": material,
        "sample_spacing_mm": o.sample_spacing_mm,
        "disk_height_mm": o.sample.disk_height,
        "limits": o.limits,
        "totals": f.totals,
        "moves": moves,
    })
}

/// The feed schedule at `target` N ([`crate::project::force_schedule::schedule_path`]),
/// the scheduled path written to `out`; its JSON report.
fn schedule(
    args: &ForcesArgs,
    input: &Input,
    coefficients: &ModeCoefficients,
    forces: &PathForces,
    target: f64,
    out: &Path,
) -> Result<Value, ImportError> {
    let opt = |e: String| ImportError::new(Path::new("--schedule-force"), None, e);
    if input.plan.tilted() {
        return Err(opt(
            "feed scheduling handles 3-axis paths (a vertical tool) only".into(),
        ));
    }
    let name = args.machine.clone().unwrap_or_else(|| "mill-3axis".into());
    let machine = Machine::resolve(&name)
        .map_err(|e| ImportError::new(Path::new(&name), None, e.to_string()))?;
    let sc = schedule_path(
        &ScheduleInput {
            moves: &input.moves,
            forces,
            tool: &input.tool,
            coefficients,
            machine: &machine,
            target_n: target,
            min_feed_mm_per_min: args.min_feed,
            max_feed_mm_per_min: args.max_feed,
        },
        &Progress::new(),
    )
    .map_err(|e| opt(e.to_string()))?;
    sc.toolpath
        .save(out)
        .map_err(|e| ImportError::new(out, None, e.message))?;
    Ok(json!({
        "target_n": target,
        "machine": machine.name,
        "corner_tolerance_mm": CORNER_TOLERANCE_MM,
        "feed_range_mm_per_min": sc.feed_range_mm_per_min,
        "before": sc.before,
        "after": sc.after,
        "output": out.display().to_string(),
    }))
}

/// A short human summary of the path forces (and the schedule).
#[must_use]
pub fn human(doc: &Value) -> String {
    use std::fmt::Write as _;
    let t = &doc["totals"];
    let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{} cutting moves, {:.2} s in material at the programmed feeds",
        t["cutting_moves"].as_u64().unwrap_or(0),
        num(&t["cutting_time_s"])
    );
    let _ = writeln!(
        s,
        "peak resultant {:.1} N (block {}), peak torque {:.3} N·m, peak power {:.1} W, mean \
         power {:.1} W, energy {:.1} J",
        num(&t["peak_resultant_n"]),
        t["peak_resultant_block"].as_u64().unwrap_or(0),
        num(&t["peak_torque_nm"]),
        num(&t["peak_power_w"]),
        num(&t["mean_power_w"]),
        num(&t["energy_j"])
    );
    let _ = writeln!(
        s,
        "{} moves over a limit, {} moves not modelled (plunges, tilted axes)",
        t["moves_over_limits"].as_u64().unwrap_or(0),
        t["moves_not_modelled"].as_u64().unwrap_or(0)
    );
    if let Some(sc) = doc.get("schedule") {
        for key in ["before", "after"] {
            let p = &sc[key];
            let sp = &p["force_spread"];
            let _ = writeln!(
                s,
                "{key:<6} cycle {:.2} s, peak force within ±5 % of {:.1} N for {:.1} % of the \
                 cutting time (median {:.1} N, 5–95 % {:.1}–{:.1} N)",
                num(&p["cycle_time_s"]),
                num(&sc["target_n"]),
                100.0 * num(&sp["within_5_percent"]),
                num(&sp["p50_n"]),
                num(&sp["p05_n"]),
                num(&sp["p95_n"])
            );
        }
    }
    s
}
