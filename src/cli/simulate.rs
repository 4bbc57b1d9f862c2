//! `talas simulate PROGRAM.ngc|PATH.json --tool SPEC --stock box:X0,Y0,Z0,X1,Y1,Z1
//! [--stock cylinder:CX,CY,R,Z0,Z1] [--stock mesh:FILE.stl] [--part FILE] [--machine NAME_OR_FILE]
//! --resolution R [--json] [--stl OUT.stl]`: material removal on a dexel stock, deviation from
//! the part, collisions, time and memory.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde_json::{Value, json};

use crate::diagnostics::Progress;
use crate::gcode::{InterpretOptions, Syntax, interpret};
use crate::geometry::Aabb;
use crate::geometry::mesh::TriMesh;
use crate::geometry::stock::StockSpec;
use crate::import::ImportError;
use crate::import::stl::{StlFormat, StlOptions, read_stl, save_stl};
use crate::machine::Machine;
use crate::simulation::{
    DEFAULT_MEMORY_LIMIT_BYTES, DeviationOptions, DexelMode, DexelStock, MovePlan, SimError,
    SimOptions, StepOptions, StockShape, deviation, plan_program, plan_toolpath, simulate,
    top_deviation,
};
use crate::toolpath::Toolpath;
use crate::tools::parse_tool_spec;

/// Options of `talas simulate`.
#[derive(Debug, clap::Args)]
pub struct SimulateArgs {
    /// The program: G-code (any extension) or a tool path JSON (`.json`).
    pub file: PathBuf,
    /// The tool: `ball:d=6`, `flat:d=10`, `bull:d=10,r=2`, `cone:d=10,angle=45`, optionally
    /// `,flute=20,shank=8,length=60,holder=DxL+DxL`. A tool path JSON brings its own tool
    /// when this is left out.
    #[arg(long, value_name = "SPEC")]
    pub tool: Option<String>,
    /// Stock (repeatable, union): `box:X0,Y0,Z0,X1,Y1,Z1`, `cylinder:CX,CY,R,Z0,Z1` (upright:
    /// centre, radius, bottom and top), `mesh:FILE.stl` (closed), mm, or `box`/`cylinder`: the
    /// default stock around `--part` (its box plus 2 mm on the sides and the top).
    #[arg(long, value_name = "SHAPE", required = true)]
    pub stock: Vec<String>,
    /// The design part (STL or STEP) for the deviation statistics.
    #[arg(long, value_name = "FILE")]
    pub part: Option<PathBuf>,
    /// Machine (`talas machines`) or a machine JSON file: the program is read as the virtual
    /// control reads it there (`talas control --machine`): from its home, `G28` to the home,
    /// tilted work planes and rotary moves with its kinematics, its travel checked.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: Option<String>,
    /// The tool table (G43 lengths, G41/G42 radii).
    #[command(flatten)]
    pub table: super::interpret::ToolTableArgs,
    /// Dexel spacing, mm.
    #[arg(long, value_name = "MM")]
    pub resolution: f64,
    /// Keep X, Y and Z rays even for a 3-axis program.
    #[arg(long)]
    pub tri_dexel: bool,
    /// Largest stock memory, MiB (the estimate is checked before allocating).
    #[arg(long, value_name = "MIB", default_value_t = DEFAULT_MEMORY_LIMIT_BYTES >> 20)]
    pub memory_limit_mib: u64,
    /// Write the simulated stock as binary STL (closed column mesh of the Z rays).
    #[arg(long, value_name = "OUT.stl")]
    pub stl: Option<PathBuf>,
    /// Where the tool stands before the first block of a G-code program, `X,Y,Z` (mm; default:
    /// the machine's home with `--machine`, else above the stock and the part at X0 Y0). The
    /// moves before the program has commanded all of X, Y and Z (from the start to the first
    /// fully commanded position) are not simulated: a position the program did not command is
    /// never reported as a cut, a gouge or a collision.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub start: Option<String>,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Height of the default start above the highest of the stock and the part (mm).
pub const START_CLEARANCE_MM: f64 = 10.0;

/// `X,Y,Z` (mm) as a start position.
fn parse_start(text: &str) -> Option<DVec3> {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse().ok().filter(|x: &f64| x.is_finite()))
        .collect::<Option<_>>()?;
    match v.as_slice() {
        [x, y, z] => Some(DVec3::new(*x, *y, *z)),
        _ => None,
    }
}

/// The start position of a G-code program (see [`SimulateArgs::start`]).
fn start_position(
    args: &SimulateArgs,
    machine: Option<&Machine>,
    shapes: &[StockShape],
    part_bounds: Option<&Aabb>,
) -> Result<DVec3, ImportError> {
    Ok(match (&args.start, machine) {
        (Some(t), _) => parse_start(t).ok_or_else(|| {
            ImportError::new(
                Path::new("--start"),
                None,
                format!("--start must be X,Y,Z in mm, got '{t}'"),
            )
        })?,
        (None, Some(m)) => {
            let home = crate::control::ControlConfig::new(m.clone()).home_position;
            DVec3::new(home[0], home[1], home[2])
        }
        (None, None) => {
            let top = shapes
                .iter()
                .map(|s| s.bounds().max.z)
                .chain(part_bounds.iter().map(|b| b.max.z))
                .fold(0.0_f64, f64::max);
            DVec3::new(0.0, 0.0, top + START_CLEARANCE_MM)
        }
    })
}

/// Interpret `text` from `start` and leave out the moves from the start to the first position
/// the program commands in every one of X, Y and Z.
///
/// Those are found by interpreting the program again from another start: a block whose end
/// does not depend on the start is commanded; the blocks up to the first such one (the move
/// into it included) are the lead-in from wherever the machine stood. A program that never
/// commands an absolute position (all incremental) keeps every block, from `start`.
fn interpret_from(
    text: &str,
    start: DVec3,
    base: &InterpretOptions,
) -> Result<crate::gcode::Program, crate::gcode::GcodeError> {
    let options = |p: DVec3| InterpretOptions {
        start: crate::gcode::Joints {
            xyz: p,
            ..base.start
        },
        ..base.clone()
    };
    let mut prog = interpret(text, &options(start))?;
    let other = start + DVec3::new(1234.5, -2345.25, 3456.125);
    let Ok(moved) = interpret(text, &options(other)) else {
        return Ok(prog);
    };
    let first = prog
        .blocks
        .iter()
        .zip(&moved.blocks)
        .position(|(a, b)| a.end.xyz == b.end.xyz);
    if let Some(i) = first
        && prog.blocks.len() == moved.blocks.len()
    {
        let dropped = i + 1;
        prog.blocks.drain(..dropped);
        for d in &mut prog.dwells {
            d.before_block = d.before_block.saturating_sub(dropped);
        }
    }
    Ok(prog)
}

/// The G-code program read on `--machine` with `--tool-table` (as the control reads it) from
/// `start`, its lead-in left out ([`interpret_from`]).
fn read_gcode(
    args: &SimulateArgs,
    text: &str,
    start: DVec3,
) -> Result<crate::gcode::Program, ImportError> {
    let syntax = Syntax::detect(text);
    let (base, _) =
        super::interpret::program_options(args.machine.as_deref(), syntax, &args.table)?;
    interpret_from(text, start, &base).map_err(|e| {
        ImportError::new(
            &args.file,
            Some(format!("line {}, column {}", e.line, e.column)),
            e.message,
        )
    })
}

/// One `--stock` text ([`StockSpec::parse`], the syntax every subcommand shares) as the
/// simulation's shape; the bare `box`/`cylinder` need the part's bounds `part`.
pub(crate) fn parse_stock(spec: &str, part: Option<&Aabb>) -> Result<StockShape, ImportError> {
    let bad = |msg: String| ImportError::new(Path::new("--stock"), None, msg);
    match StockSpec::parse(spec, part).map_err(bad)? {
        StockSpec::Shape(stock) => {
            StockShape::sized(&stock).ok_or_else(|| bad(format!("stock '{spec}' has no size")))
        }
        StockSpec::Mesh(path) => {
            let stl = read_stl(&path, &StlOptions::default())?;
            StockShape::mesh(stl.mesh).map_err(|e| ImportError::new(&path, None, e.to_string()))
        }
    }
}

/// The part as a mesh (through [`crate::import::open`]), a B-rep tessellated at 1 µm so the
/// deviation measures the stock, not the tessellation.
fn read_part(path: &Path) -> Result<TriMesh, ImportError> {
    let options = crate::import::OpenOptions {
        chord_tol_mm: Some(0.001),
    };
    Ok(crate::import::open(path, &options, &Progress::new())?.mesh)
}

pub(crate) fn sim_err(file: &Path, e: &SimError, json: bool) -> ImportError {
    match e {
        SimError::Program { block, message } => {
            let place = if json { "pose" } else { "line" };
            ImportError::new(file, Some(format!("{place} {block}")), message.clone())
        }
        other => ImportError::new(file, None, other.to_string()),
    }
}

/// Run the simulation and build the JSON document.
///
/// # Errors
/// An [`ImportError`] naming the file and place for bad input.
pub fn simulate_cmd(args: &SimulateArgs) -> Result<Value, ImportError> {
    let file = &args.file;
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
    let machine = match &args.machine {
        Some(m) => Some(
            Machine::resolve(m).map_err(|e| ImportError::new(Path::new(m), None, e.to_string()))?,
        ),
        None => None,
    };
    // The part is read first: the bare `box`/`cylinder` stocks are sized around it.
    let part_mesh = args.part.as_deref().map(read_part).transpose()?;
    let part_bounds = part_mesh.as_ref().map(TriMesh::bbox);
    let shapes = args
        .stock
        .iter()
        .map(|s| parse_stock(s, part_bounds.as_ref()))
        .collect::<Result<Vec<_>, _>>()?;
    let start = start_position(args, machine.as_ref(), &shapes, part_bounds.as_ref())?;
    let (toolpath, program) = if is_json {
        let (tp, warnings) = Toolpath::from_json_with_warnings(&text, &file.display().to_string())
            .map_err(|e| bad(Some(e.place.clone()), e.message.clone()))?;
        for w in warnings {
            eprintln!("talas: warning: {w}");
        }
        (Some(tp), None)
    } else {
        (None, Some(read_gcode(args, &text, start)?))
    };
    let cutter = match (&args.tool, &toolpath) {
        (Some(spec), _) => parse_tool_spec(spec)
            .map_err(|e| ImportError::new(Path::new("--tool"), None, e.to_string()))?,
        (None, Some(tp)) => tp.tool.cutter.clone(),
        (None, None) => {
            return Err(ImportError::new(
                Path::new("--tool"),
                None,
                "a G-code program needs --tool SPEC",
            ));
        }
    };
    let step_opts = StepOptions::for_resolution(args.resolution, cutter.flute_length);
    let plan: MovePlan = match (&toolpath, &program) {
        (Some(tp), _) => plan_toolpath(tp, &step_opts),
        (None, Some(p)) => plan_program(p, machine.as_ref(), &step_opts),
        (None, None) => Ok(MovePlan::default()),
    }
    .map_err(|e| sim_err(file, &e, is_json))?;
    let mode = if args.tri_dexel || plan.tilted() {
        DexelMode::Tri
    } else {
        DexelMode::Z
    };
    let mut stock = DexelStock::new(
        shapes,
        args.resolution,
        mode,
        args.memory_limit_mib.saturating_mul(1 << 20),
    )
    .map_err(|e| ImportError::new(Path::new("--stock"), None, e.to_string()))?;
    let progress = Progress::new();
    let started = std::time::Instant::now();
    let report = simulate(
        &mut stock,
        &cutter,
        &plan,
        &SimOptions::default(),
        &progress,
    )
    .map_err(|e| sim_err(file, &e, is_json))?;
    let wall_s = started.elapsed().as_secs_f64();
    let (dev, top) = match (&args.part, &part_mesh) {
        (Some(p), Some(mesh)) => {
            let d = deviation(&stock, mesh, &DeviationOptions::default(), &progress)
                .map_err(|e| ImportError::new(p, None, e.to_string()))?;
            let top = top_deviation(&stock, mesh, &progress)
                .map_err(|e| ImportError::new(p, None, e.to_string()))?;
            (Some(d), Some(top))
        }
        _ => (None, None),
    };
    if let Some(out) = &args.stl {
        save_stl(out, &stock.closed_mesh(), StlFormat::Binary)?;
    }
    let collisions: Vec<Value> = report
        .collisions
        .iter()
        .map(|c| {
            json!({
                "kind": c.kind,
                "line": c.block,
                "move": c.move_index,
                "position": c.position.to_array(),
                "depth_mm": c.depth_mm,
            })
        })
        .collect();
    let mut diagnostics: Vec<String> = program
        .iter()
        .flat_map(|p| p.diagnostics.iter())
        .chain(plan.diagnostics.iter())
        .map(ToString::to_string)
        .collect();
    let travel = match (&program, &machine) {
        (Some(p), Some(m)) => crate::feed::travel_violations(&p.blocks, m, 100).0,
        _ => Vec::new(),
    };
    for v in &travel {
        diagnostics.push(format!(
            "line {}: axis {} reaches {:.4}, beyond its travel limit {:.4}",
            v.line, v.axis, v.value, v.limit
        ));
    }
    Ok(json!({
        "units": "mm",
        "input": if is_json { "toolpath" } else { "gcode" },
        "tool": cutter,
        "resolution_mm": args.resolution,
        "dexels": match stock.mode() { DexelMode::Z => "z", DexelMode::Tri => "tri" },
        "rays": stock.ray_count(),
        "moves": report.moves,
        "steps": report.steps,
        "initial_volume_mm3": report.initial_volume_mm3,
        "final_volume_mm3": report.final_volume_mm3,
        "removed_volume_mm3": report.removed_volume_mm3,
        "time_s": report.time_s,
        "memory_bytes": report.memory_bytes,
        "wall_s": wall_s,
        "collisions": collisions,
        "travel_violations": travel,
        "deviation": dev,
        "top_deviation": top,
        "diagnostics": diagnostics,
    }))
}

/// Human summary.
#[must_use]
pub fn human(doc: &Value) -> String {
    let num = |k: &str| doc.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
    let mut s = format!(
        "removed {:.3} mm³ of {:.3} mm³ in {} moves ({} steps), {:.1} s at programmed feeds\n\
         stock: {} rays ({}), {:.1} MiB\n",
        num("removed_volume_mm3"),
        num("initial_volume_mm3"),
        doc.get("moves").and_then(Value::as_u64).unwrap_or(0),
        doc.get("steps").and_then(Value::as_u64).unwrap_or(0),
        num("time_s"),
        doc.get("rays").and_then(Value::as_u64).unwrap_or(0),
        doc.get("dexels").and_then(Value::as_str).unwrap_or("?"),
        num("memory_bytes") / f64::from(1 << 20),
    );
    if let Some(d) = doc.get("deviation").filter(|d| !d.is_null()) {
        let g = |k: &str| d.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
        s.push_str(&format!(
            "deviation: max gouge {:.4} mm, max remaining {:.4} mm, mean remaining {:.4} mm\n",
            g("max_gouge_mm"),
            g("max_remaining_mm"),
            g("mean_remaining_mm")
        ));
    }
    if let Some(d) = doc.get("top_deviation").filter(|d| !d.is_null()) {
        let g = |k: &str| d.get(k).and_then(Value::as_f64).unwrap_or(f64::NAN);
        s.push_str(&format!(
            "top of the stock over the part: max gouge {:.4} mm, remaining p99 {:.4} mm\n",
            g("max_gouge_mm"),
            g("remaining_p99_mm")
        ));
    }
    let cols = doc
        .get("collisions")
        .and_then(Value::as_array)
        .map_or(&[][..], Vec::as_slice);
    s.push_str(&format!("collisions: {}\n", cols.len()));
    for c in cols.iter().take(20) {
        s.push_str(&format!(
            "  {} at line {}: {} (depth {:.3} mm)\n",
            c.get("kind").and_then(Value::as_str).unwrap_or("?"),
            c.get("line").and_then(Value::as_u64).unwrap_or(0),
            c.get("position").map_or(String::new(), ToString::to_string),
            c.get("depth_mm")
                .and_then(Value::as_f64)
                .unwrap_or(f64::NAN),
        ));
    }
    s
}
