//! `talas feed PROGRAM.ngc --machine NAME_OR_FILE [--limit AXIS=V,A,J ...]
//! [--corners blend|exact|junction] [--deviation MM] [--start X,Y,Z] [--tool-table FILE.tbl]
//! --json [--samples OUT.csv]`: jerk-limited motion plan of a G-code program, read as the
//! virtual control reads it on the machine (`talas control --machine`): from the machine's
//! home unless `--start` is given, `G28` to the home, tilted work planes with its kinematics.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;

use serde_json::{Map, Value, json};

use crate::feed::{
    AxisLimit, CornerPolicy, PlanInput, PlanOptions, machine_limits, naive_time_s, plan,
    travel_violations,
};
use crate::gcode::interpret;
use crate::import::ImportError;

/// Options of `talas feed`.
#[derive(Debug, clap::Args)]
pub struct FeedArgs {
    /// The G-code program.
    pub file: PathBuf,
    /// Machine name (`talas machines`) or machine JSON file.
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: String,
    /// Override one axis's limits: `X=V,A,J` in mm/s, mm/s², mm/s³ (repeatable).
    #[arg(long = "limit", value_name = "AXIS=V,A,J")]
    pub limits: Vec<String>,
    /// How sharp corners are passed: `blend` (clothoid blend within `--deviation` of the
    /// corner; all axis limits hold), `exact` (stop at every corner), `junction`
    /// (junction-deviation speed; axis velocities step at corners).
    #[arg(long, value_enum, default_value_t = Corners::Blend)]
    pub corners: Corners,
    /// Path-deviation tolerance at corners (mm) for `blend` and `junction`.
    #[arg(long, value_name = "MM", default_value_t = DEFAULT_DEVIATION_MM)]
    pub deviation: f64,
    /// Start position `X,Y,Z` (mm) before the first block (default the machine's home, where
    /// the homed control starts a program).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub start: Option<String>,
    /// Program syntax: `rs274` (LinuxCNC, Fanuc, GRBL), `siemens` or `heidenhain` (ISO);
    /// default: detected from the text.
    #[arg(long, value_name = "NAME")]
    pub syntax: Option<String>,
    /// The tool table (G43 lengths, G41/G42 radii).
    #[command(flatten)]
    pub table: super::interpret::ToolTableArgs,
    /// Write time samples (`t,X,Y,Z,...`, 1 ms) to this CSV file.
    #[arg(long, value_name = "OUT.csv")]
    pub samples: Option<PathBuf>,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Default corner tolerance of `talas feed` (mm).
pub const DEFAULT_DEVIATION_MM: f64 = crate::feed::DEFAULT_TOLERANCE_MM;

/// Corner handling on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Corners {
    /// Clothoid blends within the deviation (default).
    Blend,
    /// Exact stop at every sharp corner.
    Exact,
    /// Junction-deviation speed (velocity steps at corners).
    Junction,
}

fn parse_start(text: &str) -> Option<crate::gcode::Joints> {
    let v: Vec<f64> = text
        .split(',')
        .map(|x| x.trim().parse().ok().filter(|x: &f64| x.is_finite()))
        .collect::<Option<_>>()?;
    match v.as_slice() {
        [x, y, z] => Some(crate::gcode::Joints::xyz(*x, *y, *z)),
        _ => None,
    }
}

fn parse_limit(text: &str) -> Option<(char, AxisLimit)> {
    let (axis, rest) = text.split_once('=')?;
    let mut chars = axis.trim().chars();
    let name = chars.next()?.to_ascii_uppercase();
    if chars.next().is_some() {
        return None;
    }
    let v: Vec<f64> = rest
        .split(',')
        .map(|x| x.trim().parse().ok())
        .collect::<Option<_>>()?;
    match v.as_slice() {
        [v, a, j] => Some((
            name,
            AxisLimit {
                velocity: *v,
                acceleration: *a,
                jerk: *j,
            },
        )),
        _ => None,
    }
}

/// Plan the program and build the contract's JSON document.
///
/// # Errors
/// An [`ImportError`] naming the file (and line) for bad input.
pub fn feed(args: &FeedArgs) -> Result<Value, ImportError> {
    let bad = |place: Option<String>, msg: String| ImportError::new(&args.file, place, msg);
    let (text, syntax) = super::read_program(&args.file, args.syntax.as_deref())?;
    let (mut options, machine) =
        super::interpret::program_options(Some(&args.machine), syntax, &args.table)?;
    let Some(machine) = machine else {
        return Err(bad(None, "--machine: no machine".into()));
    };
    let mut axes = machine_limits(&machine);
    for l in &args.limits {
        let (name, lim) = parse_limit(l)
            .ok_or_else(|| bad(None, format!("--limit must be AXIS=V,A,J, got '{l}'")))?;
        match axes.iter_mut().find(|(n, _)| *n == name) {
            Some(slot) => slot.1 = lim,
            None => return Err(bad(None, format!("--limit: machine has no axis {name}"))),
        }
    }
    if let Some(start) = &args.start {
        options.start = parse_start(start)
            .ok_or_else(|| bad(None, format!("--start must be X,Y,Z, got '{start}'")))?;
    }
    let prog =
        interpret(&text, &options).map_err(|e| bad(Some(format!("line {}", e.line)), e.message))?;
    let t = args.deviation;
    if !(t.is_finite() && t > 0.0) {
        return Err(bad(None, format!("--deviation must be positive, got {t}")));
    }
    let corner = match args.corners {
        Corners::Blend => CornerPolicy::Blend { tolerance_mm: t },
        Corners::Exact => CornerPolicy::ExactStop,
        Corners::Junction => CornerPolicy::JunctionDeviation { tolerance_mm: t },
    };
    let input = PlanInput {
        blocks: prog.blocks.as_slice().into(),
        axes: axes.clone(),
        options: PlanOptions {
            corner,
            ..PlanOptions::default()
        },
    };
    let tp = plan(&input).map_err(|e| bad(None, e.to_string()))?;
    if let Some(out) = &args.samples {
        write_samples(&tp, &axes, out)?;
    }
    let mut limits = Map::new();
    let mut peaks = Map::new();
    for (n, l) in &axes {
        limits.insert(
            n.to_string(),
            json!({"v": l.velocity, "a": l.acceleration, "j": l.jerk}),
        );
    }
    for p in &tp.peaks() {
        peaks.insert(
            p.axis.to_string(),
            json!({"v": p.velocity, "a": p.acceleration, "j": p.jerk}),
        );
    }
    let naive = naive_time_s(&prog.blocks);
    let dwell = prog.dwell_s();
    let (travel, travel_count) = travel_violations(&prog.blocks, &machine, MAX_TRAVEL_REPORTS);
    let warnings: Vec<String> = prog.diagnostics.iter().map(ToString::to_string).collect();
    Ok(json!({
        "cycle_time_s": tp.cycle_time_s + dwell,
        "motion_time_s": tp.cycle_time_s,
        "dwell_s": dwell,
        "naive_time_s": naive + dwell,
        "blocks": prog.blocks.len(),
        "warnings": warnings,
        "travel_violations": travel,
        "travel_violation_count": travel_count,
        "limits": limits,
        "peaks": peaks,
        "sample_period_s": tp.sample_period_s,
        "corners": match args.corners {
            Corners::Blend => "blend",
            Corners::Exact => "exact",
            Corners::Junction => "junction",
        },
        "deviation_mm": t,
    }))
}

/// At most this many travel violations are listed (all are counted).
const MAX_TRAVEL_REPORTS: usize = 100;

/// At most this many rows go into `--samples` (10 million rows: about 3 hours at 1 ms, 1 GB).
const MAX_SAMPLE_ROWS: f64 = 1e7;

/// Stream the samples into an atomically written CSV file, refusing a file beyond
/// [`MAX_SAMPLE_ROWS`].
fn write_samples(
    tp: &crate::feed::TimedPath,
    axes: &[(char, AxisLimit)],
    out: &std::path::Path,
) -> Result<(), ImportError> {
    let bad = |msg: String| ImportError::new(out, None, msg);
    let rows = tp.sample_count();
    if rows > MAX_SAMPLE_ROWS {
        return Err(bad(format!(
            "--samples: the planned motion takes {:.0} s, {rows:.0} samples at {} s; at most \
             {MAX_SAMPLE_ROWS:.0} are written",
            tp.cycle_time_s, tp.sample_period_s
        )));
    }
    let mut file = crate::storage::AtomicFile::create(out)
        .map_err(|e| bad(format!("cannot write samples: {e}")))?;
    let mut header = String::from("t");
    for (n, _) in axes {
        let _ = write!(header, ",{n}");
    }
    let io = |e: std::io::Error| bad(format!("cannot write samples: {e}"));
    writeln!(file, "{header}").map_err(io)?;
    let slots: Vec<usize> = axes
        .iter()
        .map(|(n, _)| crate::feed::path::slot_of(*n).unwrap_or(0))
        .collect();
    let mut row = String::new();
    for s in tp.samples() {
        row.clear();
        let _ = write!(row, "{:.6}", s.t);
        for k in &slots {
            let _ = write!(row, ",{:.6}", s.position.get(*k).copied().unwrap_or(0.0));
        }
        writeln!(file, "{row}").map_err(io)?;
    }
    file.commit().map_err(io)
}

/// Human summary.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = format!(
        "cycle time {:.4} s (motion {:.4} s, dwell {:.4} s; length/feed estimate {:.4} s), {} blocks\npeaks {}\n",
        doc["cycle_time_s"].as_f64().unwrap_or(0.0),
        doc["motion_time_s"].as_f64().unwrap_or(0.0),
        doc["dwell_s"].as_f64().unwrap_or(0.0),
        doc["naive_time_s"].as_f64().unwrap_or(0.0),
        doc["blocks"],
        doc["peaks"]
    );
    for w in doc["warnings"].as_array().into_iter().flatten() {
        let _ = writeln!(s, "warning: {}", w.as_str().unwrap_or(""));
    }
    for v in doc["travel_violations"].as_array().into_iter().flatten() {
        let _ = writeln!(
            s,
            "travel: line {}: axis {} reaches {:.4}, beyond its limit {:.4}",
            v["line"],
            v["axis"].as_str().unwrap_or("?"),
            v["value"].as_f64().unwrap_or(0.0),
            v["limit"].as_f64().unwrap_or(0.0)
        );
    }
    s
}
