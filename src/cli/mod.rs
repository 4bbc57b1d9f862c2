//! The command line: each subcommand is a thin shell over engine calls. Errors go to stderr as one
//! line naming the file and the place; exit code 2 for bad input, 1 for internal failure.

pub mod calibrate;
pub mod contours;
pub mod control;
pub mod dropcutter;
pub mod features;
pub mod features_regions;
pub mod feed;
pub mod forces;
pub mod forces_path;
pub mod inspect;
pub mod interpret;
pub mod job;
pub mod job_sheet;
pub mod plan;
pub mod plan_25d;
pub mod plan_group;
pub mod plan_holes;
pub mod plan_mesh;
pub mod post;
pub mod profile;
pub mod reduce;
pub mod render;
pub mod simulate;
pub mod speeds;

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Exit code for bad input (malformed or unreadable file, bad option value).
pub const EXIT_BAD_INPUT: i32 = 2;
/// Exit code for an internal failure.
pub const EXIT_INTERNAL: i32 = 1;

/// Talas: a CAM workstation. With no subcommand, opens the workstation (on FILE, or on the
/// embedded default part).
#[derive(Debug, Parser)]
#[command(name = "talas", version, about, long_about = None, args_conflicts_with_subcommands = true)]
pub struct Args {
    /// A part or project to open in the workstation.
    pub file: Option<PathBuf>,
    /// Subcommand (none: open the workstation).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Part summary: faces (kind, degrees, poles, rational, domain, area), total area, bounding
    /// box, triangles, closedness and volume; optionally surface samples of B-spline faces.
    Inspect(inspect::InspectArgs),
    /// Machining features recognised on a STEP part: holes (diameter, depth, bottom: through,
    /// flat or drill point; counterbores, countersinks, spot faces), grouped by size and
    /// direction, and the machinable regions seen from +Z (pockets, steps, slots, tops, the
    /// outer profile: floor height, depth, area, smallest corner radius, islands, open sides).
    Features(features::FeaturesArgs),
    /// A tool path written as tool-path JSON: 5-axis finishing of one face of a STEP part
    /// (iso-parametric, iso-planar, iso-scallop), or raster, waterline, steep-and-shallow
    /// finishing and Z-level roughing of a STEP or STL part, through the project pipeline.
    Plan(plan::PlanArgs),
    /// Drop-cutter against an STL mesh: the tool-tip height at every XY point of a CSV.
    Dropcutter(dropcutter::DropcutterArgs),
    /// Waterline contours of a cutter on an STL mesh at given tool-tip heights.
    Contours(contours::ContoursArgs),
    /// SVD data reduction of a Z-map (CSV of heights): singular values, rank, reduced sizes,
    /// max and mean error.
    Reduce(reduce::ReduceArgs),
    /// Post a tool path JSON into G-code for a machine and dialect.
    Post(post::PostArgs),
    /// List the built-in machines, one line each.
    Machines,
    /// Jerk-limited motion plan of a G-code program: cycle time, limits and peaks per axis.
    Feed(feed::FeedArgs),
    /// The canonical motion of a G-code program as the interpreter reads it (the form of
    /// LinuxCNC's `rs274 -g`): traverses, feeds and arcs with canned cycles expanded,
    /// subroutines and loops run and cutter compensation applied.
    Interpret(interpret::InterpretArgs),
    /// Material removal on a dexel stock: removed volume, deviation from the part,
    /// collisions, time.
    Simulate(simulate::SimulateArgs),
    /// Cutting forces of one straight cut (mean and peak F_x, F_y, F_z in N, torque, power,
    /// wall error) or along a program or tool path, with feed scheduling to a target force.
    Forces(forces::ForcesArgs),
    /// Cutting-force coefficients from measured mean forces (FORCES.csv), optionally written
    /// as a coefficient library.
    Calibrate(calibrate::CalibrateArgs),
    /// Spindle speed and feeds from the cutting-data library (material, tool, engagement),
    /// with chip thinning and the force model's torque, power and deflection check.
    Speeds(speeds::SpeedsArgs),
    /// Ball-electrode (EDM) path of a 2D profile: exact offset, plunges and side collisions
    /// of the per-point method, largest gouge-free radius, G-code.
    Profile(profile::ProfileArgs),
    /// The virtual machine control run headless from a script of operator actions (home,
    /// jog, MPG, MDI, AUTO, hold, overrides): positions, time, alarms, removed volume, peaks.
    Control(control::ControlArgs),
    /// A project's job: every setup's operations planned in its frame, one program per setup
    /// (`--post DIR`), each setup simulated on its stock (`--simulate`); per setup and
    /// operation the tool, lengths, times and program file.
    Job(job::JobArgs),
    /// Render a part (and optionally a tool path) offscreen to a PNG with the workstation's
    /// renderer (builds with the `gui` feature).
    Render(render::RenderArgs),
}

/// Print a subcommand's JSON document or its human summary; exit code 2 with one line on error.
/// The program text of `file` (read with the storage bound for programs) and the syntax it is
/// read in: `syntax` by name, or detected from the text; the one way `feed` and `interpret`
/// read a program.
///
/// # Errors
/// An [`crate::import::ImportError`] naming the file for a read failure or a bad `--syntax`.
pub(crate) fn read_program(
    file: &std::path::Path,
    syntax: Option<&str>,
) -> Result<(String, crate::gcode::Syntax), crate::import::ImportError> {
    let bad = |msg: String| crate::import::ImportError::new(file, None, msg);
    let text = crate::storage::read_program_text(file)
        .map_err(|e| bad(format!("cannot read file: {e}")))?;
    let syntax = match syntax {
        Some(name) => crate::gcode::Syntax::from_name(name).ok_or_else(|| {
            bad(format!(
                "--syntax must be rs274, siemens or heidenhain, got '{name}'"
            ))
        })?,
        None => crate::gcode::Syntax::detect(&text),
    };
    Ok((text, syntax))
}

fn report(
    result: Result<serde_json::Value, crate::import::ImportError>,
    json: bool,
    human: fn(&serde_json::Value) -> String,
) -> i32 {
    match result {
        Ok(doc) => {
            if json {
                emit(&format!("{doc}\n"));
            } else {
                emit(&human(&doc));
            }
            0
        }
        Err(e) => {
            eprintln!("talas: {e}");
            EXIT_BAD_INPUT
        }
    }
}

/// Run a subcommand; returns the process exit code.
#[must_use]
pub fn run(command: Command) -> i32 {
    match command {
        Command::Inspect(args) => match inspect::inspect(&args) {
            Ok(doc) => {
                if args.json {
                    emit(&format!("{doc}\n"));
                } else {
                    emit(&inspect::human(&doc));
                }
                0
            }
            Err(e) => {
                eprintln!("talas: {e}");
                EXIT_BAD_INPUT
            }
        },
        Command::Features(args) => report(features::features(&args), args.json, features::human),
        Command::Plan(args) => report(plan::plan(&args), args.json, plan::human),
        Command::Dropcutter(args) => {
            report(dropcutter::dropcutter(&args), args.json, dropcutter::human)
        }
        Command::Contours(args) => report(contours::contours(&args), args.json, contours::human),
        Command::Reduce(args) => report(reduce::reduce(&args), args.json, reduce::human),
        Command::Post(args) => match post::post(&args) {
            Ok(doc) => {
                if let Some(doc) = doc {
                    emit(&format!("{doc}\n"));
                }
                0
            }
            Err(e) => {
                eprintln!("talas: {e}");
                EXIT_BAD_INPUT
            }
        },
        Command::Machines => {
            emit(&post::machines());
            0
        }
        Command::Feed(args) => report(feed::feed(&args), args.json, feed::human),
        Command::Interpret(args) => match interpret::interpret(&args) {
            Ok(done) => {
                if args.json {
                    emit(&format!("{}\n", done.doc));
                } else {
                    emit(&interpret::human(&done.doc));
                }
                match done.error {
                    Some(e) => {
                        eprintln!("talas: {e}");
                        EXIT_BAD_INPUT
                    }
                    None => 0,
                }
            }
            Err(e) => {
                eprintln!("talas: {e}");
                EXIT_BAD_INPUT
            }
        },
        Command::Simulate(args) => {
            report(simulate::simulate_cmd(&args), args.json, simulate::human)
        }
        Command::Forces(args) => report(forces::forces(&args), args.json, forces::human),
        Command::Calibrate(args) => {
            report(calibrate::calibrate(&args), args.json, calibrate::human)
        }
        Command::Speeds(args) => report(speeds::speeds(&args), args.json, speeds::human),
        Command::Profile(args) => match profile::profile(&args) {
            Ok(doc) => {
                if args.json {
                    emit(&format!("{doc}\n"));
                } else {
                    emit(&profile::human(&doc));
                }
                0
            }
            Err(e) => {
                eprintln!("talas: {e}");
                EXIT_BAD_INPUT
            }
        },
        Command::Control(args) => report(control::control(&args), args.json, control::human),
        Command::Job(args) => report(job::job(&args), args.json, job::human),
        // The binary sends `render` to the workstation's renderer when it has one (main.rs).
        Command::Render(_) => render::unavailable(),
    }
}

/// Write `text` to standard output. A reader that went away (`talas … --json | head`) is not an
/// error of ours: the rest is dropped quietly instead of panicking as `print!` would.
fn emit(text: &str) {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    let _ = out.write_all(text.as_bytes()).and_then(|()| out.flush());
}
