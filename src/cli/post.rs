//! `talas post PATH.json --machine NAME_OR_FILE --dialect NAME_OR_FILE [--tcp] -o OUT.ngc
//! [--json]` and `talas machines`. With `--json` the posted program is also planned on the
//! machine (the engine's machining run) and the planned cycle time and the time each pose is
//! reached are printed.

use std::path::PathBuf;

use crate::machine::Machine;
use crate::post::{Dialect, PostOptions, post_mapped};
use crate::project::MachiningRun;
use crate::toolpath::Toolpath;

/// Options of `talas post`.
#[derive(Debug, clap::Args)]
pub struct PostArgs {
    /// The tool path (the contract's Tool path JSON).
    pub file: PathBuf,
    /// A built-in machine (`talas machines`) or a machine JSON file.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: String,
    /// Dialect: linuxcnc, fanuc, siemens, heidenhain, grbl, or a dialect JSON file.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub dialect: String,
    /// Tool-centre-point output (G43.4 / TRAORI / M128): tip coordinates and rotary angles.
    #[arg(long)]
    pub tcp: bool,
    /// Largest tip deviation of a linearised 5-axis move, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.01)]
    pub tolerance: f64,
    /// Tool and length-offset number.
    #[arg(long, value_name = "N", default_value_t = 1)]
    pub tool_number: u32,
    /// Spindle speed, rpm.
    #[arg(long, value_name = "RPM", default_value_t = 10_000.0)]
    pub rpm: f64,
    /// Safe retract height (program Z, mm) at start and end.
    #[arg(long, value_name = "MM", default_value_t = 100.0)]
    pub clearance: f64,
    /// Number the blocks (default: as the dialect says).
    #[arg(long)]
    pub line_numbers: bool,
    /// Work offset (G54 … G59).
    #[arg(long, value_name = "G5X", default_value = "G54")]
    pub work_offset: String,
    /// Program name in the header.
    #[arg(long, value_name = "NAME", default_value = "TALAS")]
    pub program: String,
    /// Output file (written atomically).
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: PathBuf,
    /// Corner blending tolerance of the motion plan (`--json`), mm.
    #[arg(long, value_name = "MM", default_value_t = 0.01)]
    pub corner_tolerance: f64,
    /// Print one JSON document: lines, planned cycle time, and per pose the planned time it is
    /// reached and the (1-based) line that reaches it.
    #[arg(long)]
    pub json: bool,
}

/// Post the file; with `--json`, the document to print. `Err` is the one line to print.
///
/// # Errors
/// A line naming the file and the place.
pub fn post(args: &PostArgs) -> Result<Option<serde_json::Value>, String> {
    if args.json && !(args.corner_tolerance.is_finite() && args.corner_tolerance > 0.0) {
        return Err(format!(
            "--corner-tolerance: {} is not a positive length in mm",
            args.corner_tolerance
        ));
    }
    let offset = args.work_offset.trim().to_ascii_uppercase();
    if !matches!(
        offset.as_str(),
        "G54" | "G55" | "G56" | "G57" | "G58" | "G59"
    ) {
        return Err(format!(
            "--work-offset: '{}' is not one of G54 … G59",
            args.work_offset
        ));
    }
    let (tp, warnings) = Toolpath::load_with_warnings(&args.file).map_err(|e| e.to_string())?;
    for w in warnings {
        eprintln!("talas: warning: {w}");
    }
    let machine = Machine::resolve(&args.machine).map_err(|e| format!("{}: {e}", args.machine))?;
    let dialect = Dialect::resolve(&args.dialect).map_err(|e| e.to_string())?;
    let options = PostOptions {
        tcp: args.tcp,
        tolerance_mm: args.tolerance,
        program_name: args.program.clone(),
        tool_number: args.tool_number,
        spindle_rpm: args.rpm,
        clearance_z_mm: args.clearance,
        line_numbers: args.line_numbers.then_some(true),
        work_offset: offset,
        ..PostOptions::default()
    };
    let posted = post_mapped(&tp, &machine, &dialect, &options)
        .map_err(|e| format!("{}: {e}", args.file.display()))?;
    let out = args.output.display().to_string();
    crate::storage::write_atomic(&args.output, posted.text.as_bytes())
        .map_err(|e| format!("{out}: {e}"))?;
    if !args.json {
        return Ok(None);
    }
    let run = MachiningRun::from_posted(posted, tp.poses.len(), &machine, args.corner_tolerance);
    Ok(Some(run_json(&run, &out)))
}

/// The `--json` document of a run.
fn run_json(run: &MachiningRun, output: &str) -> serde_json::Value {
    let lines: Vec<Option<usize>> = run.line_of_pose.iter().map(|l| l.map(|l| l + 1)).collect();
    let (cycle, times, error) = match &run.motion {
        Ok(m) => (Some(m.cycle_time_s()), Some(m.pose_time_s.clone()), None),
        Err(e) => (None, None, Some(e.to_string())),
    };
    serde_json::json!({
        "output": output,
        "lines": run.text.lines().count(),
        "poses": run.line_of_pose.len(),
        "cycle_time_s": cycle,
        "motion_error": error,
        "pose_time_s": times,
        "line_of_pose": lines,
    })
}

/// The lines of `talas machines`: name and description.
#[must_use]
pub fn machines() -> String {
    let mut s = String::new();
    for name in Machine::builtin_names() {
        let description = Machine::builtin(name)
            .map(|m| m.description)
            .unwrap_or_else(|e| e.to_string());
        s.push_str(&format!("{name}\t{description}\n"));
    }
    s
}
