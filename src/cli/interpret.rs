//! `talas interpret PROGRAM [--syntax rs274|siemens|heidenhain] [--tool-table FILE.tbl]
//! [--tool-table-units mm|inch] [--json]`: the program's canonical motion as the interpreter
//! sees it, in the form LinuxCNC's `rs274 -g` prints it (traverses, feeds and arcs, with
//! canned cycles expanded, subroutines and loops run, cutter compensation applied).
//!
//! The JSON document:
//!
//! ```text
//! { "file", "syntax",
//!   "moves": [ { "line", "kind": "rapid"|"feed"|"arc",
//!                "end": { "X", "Y", "Z", and "A" "B" "C" where the program uses them },
//!                "feed",                        mm/min (1/min with "inverse_time": true); null for rapids
//!                "centre": { "X", "Y", "Z" },   arcs: the centre, at the start's height
//!                "plane": "XY"|"ZX"|"YZ",       arcs: G17, G18, G19
//!                "turn" } ],                    arcs: +n counter-clockwise, -n clockwise, n-1 full turns added
//!   "dwells": [ { "line", "seconds", "before_move" } ],
//!   "warnings": [ { "line", "message" } ],
//!   "errors": [ { "line", "column", "message" } ] }
//! ```
//!
//! With `--machine` the program is read as the virtual control reads it on that machine
//! (`talas control --machine`): from the machine's home, `G28` to the home, tilted work planes
//! with its kinematics; the document adds `"machine"` and `"travel_violations"` (`{line,
//! axis, value, limit}`, mm or degrees, at most 100) of the joint limits.
//!
//! Positions are machine coordinates (program coordinates plus the work, G92/G52 and G43
//! tool length offsets) in mm, angles in degrees. `line` is the 1-based line of the block
//! in the file. A program that does not read ends with the error on standard error (file,
//! line, column) and exit code 2; `--json` still prints the moves read before it.

use std::fmt::Write as _;
use std::path::PathBuf;

use serde_json::{Map, Value, json};

use crate::gcode::{
    InterpretOptions, LengthUnit, MotionBlock, MotionKind, Program, Syntax, ToolTable,
    interpret_partial,
};
use crate::import::ImportError;
use crate::machine::Machine;

/// Options of `talas interpret`.
#[derive(Debug, clap::Args)]
pub struct InterpretArgs {
    /// The G-code program.
    pub file: PathBuf,
    /// Program syntax: `rs274` (LinuxCNC, Fanuc, GRBL), `siemens` or `heidenhain` (ISO);
    /// default: detected from the text (see `Syntax::detect`).
    #[arg(long, value_name = "NAME")]
    pub syntax: Option<String>,
    /// The tool table.
    #[command(flatten)]
    pub table: ToolTableArgs,
    /// Machine name (`talas machines`) or machine JSON file: read the program from its home
    /// with its kinematics and check its travel (as `talas control --machine` runs it).
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: Option<String>,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// `--tool-table FILE.tbl [--tool-table-units mm|inch]`, shared by `interpret`, `feed`,
/// `simulate` and `control`.
#[derive(Debug, Default, clap::Args)]
pub struct ToolTableArgs {
    /// A LinuxCNC tool table (`T1 P1 D6 Z25 ;comment`): lengths for G43, radii for G41/G42.
    #[arg(long, value_name = "FILE.tbl")]
    pub tool_table: Option<PathBuf>,
    /// The length unit of the tool table's values (LinuxCNC: the machine's unit).
    #[arg(long, value_enum, default_value_t = TableUnit::Mm)]
    pub tool_table_units: TableUnit,
}

impl ToolTableArgs {
    /// The table, when one is named.
    ///
    /// # Errors
    /// An [`ImportError`] naming the table file (and line) when it does not read.
    pub fn read(&self) -> Result<Option<ToolTable>, ImportError> {
        let Some(path) = &self.tool_table else {
            return Ok(None);
        };
        let text = crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
            .map_err(|e| ImportError::new(path, None, format!("cannot read file: {e}")))?;
        let unit = match self.tool_table_units {
            TableUnit::Mm => LengthUnit::Mm,
            TableUnit::Inch => LengthUnit::Inch,
        };
        ToolTable::parse(&text, unit).map(Some).map_err(|e| {
            ImportError::new(
                path,
                Some(format!("line {}, column {}", e.line, e.column)),
                e.message,
            )
        })
    }
}

/// The options a program is read with: on `--machine` as the virtual control reads it there
/// ([`crate::control::machine_interpret_options`]), else the interpreter's defaults; the tool
/// table added.
///
/// # Errors
/// An [`ImportError`] for a machine or tool table that does not read.
pub(crate) fn program_options(
    machine: Option<&str>,
    syntax: Syntax,
    table: &ToolTableArgs,
) -> Result<(InterpretOptions, Option<Machine>), ImportError> {
    let machine = machine
        .map(|m| {
            Machine::resolve(m).map_err(|e| {
                ImportError::new(std::path::Path::new(m), None, format!("--machine: {e}"))
            })
        })
        .transpose()?;
    let mut options = machine.as_ref().map_or_else(
        || InterpretOptions::for_syntax(syntax),
        |m| crate::control::machine_interpret_options(m, syntax),
    );
    options.tool_table = table.read()?;
    Ok((options, machine))
}

/// Tool table units on the command line.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum TableUnit {
    /// Millimetres (default).
    #[default]
    Mm,
    /// Inches (LinuxCNC's `rs274` without an INI file reads tables in inches).
    Inch,
}

/// At most this many travel violations are listed (all are counted).
const MAX_TRAVEL_REPORTS: usize = 100;

/// What `talas interpret` read: the JSON document, and the error that stopped it.
pub struct Interpreted {
    /// The document (moves read before an error included).
    pub doc: Value,
    /// The error, if the program does not read to its end.
    pub error: Option<ImportError>,
}

/// The plane of an arc from its normal: `XY` (G17), `ZX` (G18), `YZ` (G19).
fn plane_name(normal: glam::DVec3) -> &'static str {
    if normal.z.abs() > 0.5 {
        "XY"
    } else if normal.y.abs() > 0.5 {
        "ZX"
    } else {
        "YZ"
    }
}

fn point(xyz: glam::DVec3, rotary: Option<&crate::gcode::Joints>) -> Value {
    let mut m = Map::new();
    m.insert("X".into(), json!(xyz.x));
    m.insert("Y".into(), json!(xyz.y));
    m.insert("Z".into(), json!(xyz.z));
    if let Some(j) = rotary {
        for (name, v) in [("A", j.a), ("B", j.b), ("C", j.c)] {
            if let Some(v) = v {
                m.insert(name.into(), json!(v.to_degrees()));
            }
        }
    }
    Value::Object(m)
}

/// The LinuxCNC turn count of an arc: the sign is the sense (+ counter-clockwise), the
/// magnitude one more than the full turns added.
fn turn(sweep_rad: f64, ccw: bool) -> i64 {
    let n = ((sweep_rad / std::f64::consts::TAU) - 1e-9).ceil().max(1.0) as i64;
    if ccw { n } else { -n }
}

fn move_json(b: &MotionBlock) -> Value {
    let mut m = Map::new();
    m.insert("line".into(), json!(b.source_line));
    let kind = match b.kind {
        MotionKind::Rapid => "rapid",
        MotionKind::Linear => "feed",
        MotionKind::ArcCw(_) | MotionKind::ArcCcw(_) => "arc",
    };
    m.insert("kind".into(), json!(kind));
    m.insert("end".into(), point(b.end.xyz, Some(&b.end)));
    if b.kind == MotionKind::Rapid {
        m.insert("feed".into(), Value::Null);
    } else {
        m.insert("feed".into(), json!(b.feed_mm_per_min));
        if b.inverse_time {
            m.insert("inverse_time".into(), json!(true));
        }
    }
    if let Some(a) = b.kind.arc() {
        m.insert("centre".into(), point(a.centre, None));
        m.insert("plane".into(), json!(plane_name(a.normal)));
        let ccw = matches!(b.kind, MotionKind::ArcCcw(_));
        m.insert("turn".into(), json!(turn(a.sweep_rad, ccw)));
    }
    Value::Object(m)
}

fn document(args: &InterpretArgs, syntax: Syntax, p: &Program, errors: Vec<Value>) -> Value {
    let warnings: Vec<Value> = p
        .diagnostics
        .iter()
        .map(|d| {
            let line = d
                .place
                .as_deref()
                .and_then(|pl| pl.strip_prefix("line "))
                .and_then(|rest| rest.split(',').next())
                .and_then(|n| n.trim().parse::<u64>().ok());
            json!({ "line": line, "message": d.message })
        })
        .collect();
    let dwells: Vec<Value> = p
        .dwells
        .iter()
        .map(|d| json!({ "line": d.line, "seconds": d.seconds, "before_move": d.before_block }))
        .collect();
    json!({
        "file": args.file.display().to_string(),
        "syntax": match syntax {
            Syntax::Rs274 => "rs274",
            Syntax::Siemens => "siemens",
            Syntax::HeidenhainIso => "heidenhain",
        },
        "moves": p.blocks.iter().map(move_json).collect::<Vec<Value>>(),
        "dwells": dwells,
        "warnings": warnings,
        "errors": errors,
    })
}

/// Read the program (and the tool table) and interpret it.
///
/// # Errors
/// An [`ImportError`] for a file that cannot be read, a bad `--syntax` or a tool table that
/// does not read; a program error comes back in [`Interpreted::error`] with the document.
pub fn interpret(args: &InterpretArgs) -> Result<Interpreted, ImportError> {
    let bad = |place: Option<String>, msg: String| ImportError::new(&args.file, place, msg);
    let (text, syntax) = super::read_program(&args.file, args.syntax.as_deref())?;
    let (options, machine) = program_options(args.machine.as_deref(), syntax, &args.table)?;
    let (program, error) = interpret_partial(&text, &options);
    let errors = error
        .iter()
        .map(|e| json!({ "line": e.line, "column": e.column, "message": e.message }))
        .collect();
    let mut doc = document(args, syntax, &program, errors);
    if let Some(m) = &machine {
        let (travel, count) =
            crate::feed::travel_violations(&program.blocks, m, MAX_TRAVEL_REPORTS);
        doc["machine"] = json!(m.name);
        doc["travel_violations"] = json!(travel);
        doc["travel_violation_count"] = json!(count);
    }
    let error = error.map(|e| {
        bad(
            Some(format!("line {}, column {}", e.line, e.column)),
            e.message,
        )
    });
    Ok(Interpreted { doc, error })
}

/// The human summary.
#[must_use]
pub fn human(doc: &Value) -> String {
    let moves = doc["moves"].as_array().map_or(&[][..], Vec::as_slice);
    let count = |k: &str| moves.iter().filter(|m| m["kind"] == k).count();
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for m in moves {
        for (i, a) in ["X", "Y", "Z"].iter().enumerate() {
            if let (Some(v), Some(l), Some(h)) =
                (m["end"][a].as_f64(), lo.get_mut(i), hi.get_mut(i))
            {
                *l = l.min(v);
                *h = h.max(v);
            }
        }
    }
    let dwell: f64 = doc["dwells"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|d| d["seconds"].as_f64())
        .fold(0.0, |a, b| a + b);
    let mut s = format!(
        "{} moves ({} rapid, {} feed, {} arc), {} dwells ({dwell:.3} s), syntax {}\n",
        moves.len(),
        count("rapid"),
        count("feed"),
        count("arc"),
        doc["dwells"].as_array().map_or(0, Vec::len),
        doc["syntax"].as_str().unwrap_or("?"),
    );
    if !moves.is_empty() {
        let _ = writeln!(
            s,
            "extent X {:.4}..{:.4} Y {:.4}..{:.4} Z {:.4}..{:.4} mm",
            lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
        );
    }
    for v in doc["travel_violations"].as_array().into_iter().flatten() {
        let _ = writeln!(
            s,
            "travel: line {}: axis {} reaches {:.4}, beyond its limit {:.4} (mm or °)",
            v["line"],
            v["axis"].as_str().unwrap_or("?"),
            v["value"].as_f64().unwrap_or(0.0),
            v["limit"].as_f64().unwrap_or(0.0)
        );
    }
    for w in doc["warnings"].as_array().into_iter().flatten() {
        let _ = writeln!(
            s,
            "warning: line {}: {}",
            w["line"],
            w["message"].as_str().unwrap_or("")
        );
    }
    s
}
