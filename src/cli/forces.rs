//! `talas forces --cut ae=MM,ap=MM,ft=MM,mode=up|down|slot --tool SPEC --coefficients FILE
//! [--overhang MM] [--rpm N] [--material NAME] [--json]`: cutting forces of one straight cut.
//! With a program or tool path instead of `--cut`, the forces along it
//! ([`super::forces_path`]).
//! JSON: `{"mean": {"fx","fy","fz"}, "peak": {"fx","fy","fz"}, "form_error_um", ...}` in N
//! (x along the feed, y normal to it, forces on the tool); a peak is the value of largest
//! magnitude over a revolution, with its sign; `form_error_um` is the wall error at the tool
//! tip (negative: overcut) when `--overhang` is given, else null.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::force::cut::DEFAULT_DISK_HEIGHT;
use crate::force::deflection::{
    BeamSpec, CARBIDE_E, Cantilever, FLUTE_DIAMETER_RATIO, wall_profile,
};
use crate::force::library::Library;
use crate::force::{EndMill, Force, Mode, RevolutionOptions, StraightCut, revolution};
use crate::import::ImportError;
use crate::tools::parse_tool_spec;

/// Options of `talas forces`.
#[derive(Debug, clap::Args)]
pub struct ForcesArgs {
    /// A program (G-code) or tool path (`.json`): forces along it, move by move (instead of
    /// `--cut`).
    #[arg(value_name = "PROGRAM|PATH.json", conflicts_with = "cut")]
    pub file: Option<PathBuf>,
    /// One straight cut: `ae=MM,ap=MM,ft=MM,mode=up|down|slot` (radial depth, axial depth,
    /// feed per tooth; a slot's ae is the diameter and may be left out).
    #[arg(long, value_name = "SPEC", required_unless_present = "file")]
    pub cut: Option<String>,
    /// The tool, with its flutes: e.g. `flat:d=12,flutes=2,helix=30,rake=15` (a tool path
    /// JSON brings its own when this is left out).
    #[arg(long, value_name = "SPEC")]
    pub tool: Option<String>,
    /// Tool library (TOML, the workstation's `tools.toml`): `--tool` then names one of its
    /// entries, whose flutes and load limits are used.
    #[arg(long, value_name = "FILE")]
    pub tool_library: Option<PathBuf>,
    /// Coefficient library (TOML), e.g. assets/force/coefficients.toml.
    #[arg(long, value_name = "FILE")]
    pub coefficients: PathBuf,
    /// Material of the library entry to use (default: the first entry for the mode).
    #[arg(long, value_name = "NAME")]
    pub material: Option<String>,
    /// Tool overhang from the holder face to the tip, mm: adds the wall (form) error.
    #[arg(long, value_name = "MM")]
    pub overhang: Option<f64>,
    /// Young's modulus of the tool, GPa (default 600, cemented carbide).
    #[arg(long, value_name = "GPA", default_value_t = CARBIDE_E / 1000.0)]
    pub youngs_modulus: f64,
    /// Spindle speed, rev/min: adds the spindle power.
    #[arg(long, value_name = "N")]
    pub rpm: Option<f64>,
    /// Stock for a program (repeatable, union): `box:X0,Y0,Z0,X1,Y1,Z1`,
    /// `cylinder:CX,CY,R,Z0,Z1` (centre, radius, bottom and top) or `mesh:FILE.stl`, mm.
    #[arg(long, value_name = "SHAPE")]
    pub stock: Vec<String>,
    /// Dexel spacing of the stock, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.2)]
    pub resolution: f64,
    /// Machine (`talas machines`) or machine JSON: rotary programs, and the feed limits and
    /// timing of `--schedule-force` (default mill-3axis).
    #[arg(long, value_name = "NAME_OR_FILE")]
    pub machine: Option<String>,
    /// Longest piece of a move whose engagement is read once, mm.
    #[arg(long, value_name = "MM", default_value_t = 0.5)]
    pub sample_spacing: f64,
    /// Flag moves whose peak resultant force exceeds this, N (default: the tool's limit).
    #[arg(long, value_name = "N")]
    pub max_force: Option<f64>,
    /// Flag moves whose peak torque exceeds this, N·m (default: the tool's limit).
    #[arg(long, value_name = "NM")]
    pub max_torque: Option<f64>,
    /// Flag moves whose peak spindle power exceeds this, W (default: the lower of the tool's
    /// limit and the machine's spindle power).
    #[arg(long, value_name = "W")]
    pub max_power: Option<f64>,
    /// Rewrite the feeds so the peak resultant force stays at this target, N (needs -o).
    #[arg(long, value_name = "N")]
    pub schedule_force: Option<f64>,
    /// Lowest feed the schedule may set, mm/min.
    #[arg(long, value_name = "MM_PER_MIN", default_value_t = 10.0)]
    pub min_feed: f64,
    /// Highest feed the schedule may set, mm/min (default and cap: the machine's X/Y limit).
    #[arg(long, value_name = "MM_PER_MIN")]
    pub max_feed: Option<f64>,
    /// Where the scheduled tool path is written (tool path JSON).
    #[arg(short = 'o', long = "output", value_name = "OUT.json")]
    pub output: Option<PathBuf>,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// Parse `ae=..,ap=..,ft=..,mode=..` against the tool's diameter.
fn parse_cut(text: &str, diameter: f64) -> Result<StraightCut, String> {
    let (mut ae, mut ap, mut ft, mut mode) = (None, None, None, None);
    for part in text.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (k, v) = part
            .split_once('=')
            .ok_or_else(|| format!("'{part}' is not KEY=VALUE"))?;
        let num = || {
            v.trim()
                .parse::<f64>()
                .map_err(|_| format!("{}={v} is not a number", k.trim()))
        };
        match k.trim() {
            "ae" => ae = Some(num()?),
            "ap" => ap = Some(num()?),
            "ft" => ft = Some(num()?),
            "mode" => {
                mode = Some(
                    Mode::parse(v).ok_or_else(|| format!("mode={v} is not up, down or slot"))?,
                );
            }
            other => return Err(format!("unknown key '{other}' (keys: ae, ap, ft, mode)")),
        }
    }
    let mode = mode.ok_or("missing mode=up|down|slot")?;
    let ae = match (ae, mode) {
        (Some(v), _) => v,
        (None, Mode::Slot) => diameter,
        (None, _) => return Err("missing ae=MM".into()),
    };
    Ok(StraightCut {
        radial_depth: ae,
        axial_depth: ap.ok_or("missing ap=MM")?,
        feed_per_tooth: ft.ok_or("missing ft=MM")?,
        mode,
    })
}

fn force_json(f: &Force) -> Value {
    json!({"fx": f.fx, "fy": f.fy, "fz": f.fz})
}

/// Compute the forces of the cut and build the JSON document.
///
/// # Errors
/// An [`ImportError`] naming `--cut`, `--tool`, `--overhang`, `--rpm` or the coefficients file
/// (with line and column) for bad input.
pub fn forces(args: &ForcesArgs) -> Result<Value, ImportError> {
    let opt = |name: &str, msg: String| ImportError::new(Path::new(name), None, msg);
    let (Some(cut_spec), None) = (&args.cut, &args.file) else {
        return match &args.file {
            Some(file) => super::forces_path::path_cmd(args, file),
            None => Err(opt("--cut", "give --cut SPEC or a program".into())),
        };
    };
    let tool = args
        .tool
        .as_deref()
        .ok_or_else(|| opt("--tool", "--cut needs --tool SPEC".into()))?;
    let cutter = if args.tool_library.is_some() {
        super::forces_path::library_tool(args, tool)?.cutter
    } else {
        parse_tool_spec(tool).map_err(|e| opt("--tool", e.to_string()))?
    };
    let mill = EndMill::from_cutter(&cutter).map_err(|e| opt("--tool", e.to_string()))?;
    let cut = parse_cut(cut_spec, cutter.diameter).map_err(|m| opt("--cut", m))?;
    let engagement = cut
        .engagement(&mill, DEFAULT_DISK_HEIGHT)
        .map_err(|e| opt("--cut", e.to_string()))?;
    let library = Library::load(&args.coefficients).map_err(|m| {
        // `Library::load` names the file first; keep the rest as the message.
        let prefix = format!("{}: ", args.coefficients.display());
        ImportError::new(
            &args.coefficients,
            None,
            m.strip_prefix(&prefix).unwrap_or(&m).to_string(),
        )
    })?;
    let entry = library
        .select(cut.mode, args.material.as_deref())
        .ok_or_else(|| {
            ImportError::new(
                &args.coefficients,
                None,
                format!(
                    "no entry for mode {}{}",
                    cut.mode.name(),
                    args.material
                        .as_ref()
                        .map_or(String::new(), |m| format!(" and material {m}"))
                ),
            )
        })?;
    let coefficients = entry
        .coefficients()
        .map_err(|m| ImportError::new(&args.coefficients, None, m))?;
    let options = RevolutionOptions {
        steps: 720,
        spindle_rpm: args.rpm,
    };
    let rev = revolution(&mill, &coefficients, &engagement, &options)
        .map_err(|e| opt("--rpm", e.to_string()))?;
    let form_error_um = match args.overhang {
        None => None,
        Some(overhang) => {
            let beam = Cantilever::end_mill(&BeamSpec {
                diameter: cutter.diameter,
                flute_length: cutter.flute_length,
                shank_diameter: cutter.shank_diameter,
                overhang,
                youngs_modulus: args.youngs_modulus * 1000.0,
                flute_diameter_ratio: FLUTE_DIAMETER_RATIO,
            })
            .map_err(|e| opt("--overhang", e.to_string()))?;
            let profile = wall_profile(&mill, &coefficients, &engagement, &beam, cut.mode, 2)
                .map_err(|e| opt("--overhang", e.to_string()))?;
            profile.first().map(|p| p.error_um)
        }
    };
    let (st, ex) = cut.immersion(mill.radius);
    Ok(json!({
        "units": "N",
        "mean": force_json(&rev.mean),
        "peak": force_json(&rev.peak),
        "form_error_um": form_error_um,
        "peak_resultant_n": rev.peak_resultant_n,
        "mean_torque_nm": rev.mean_torque_nm,
        "peak_torque_nm": rev.peak_torque_nm,
        "mean_power_w": rev.mean_power_w,
        "peak_power_w": rev.peak_power_w,
        "immersion_deg": [st.to_degrees(), ex.to_degrees()],
        "mode": cut.mode.name(),
        "model": if coefficients.is_exponential() { "exponential" } else { "linear" },
        "material": entry.material,
        "beam": args.overhang.map(|l| json!({
            "overhang_mm": l,
            "youngs_modulus_gpa": args.youngs_modulus,
            "flute_section_diameter_mm": FLUTE_DIAMETER_RATIO * cutter.diameter,
            "flute_length_mm": cutter.flute_length,
            "shank_diameter_mm": cutter.shank_diameter,
        })),
    }))
}

/// A short human summary.
#[must_use]
pub fn human(doc: &Value) -> String {
    if doc.get("totals").is_some() {
        return super::forces_path::human(doc);
    }
    let num = |v: &Value| v.as_f64().unwrap_or(f64::NAN);
    let mut s = String::new();
    for key in ["mean", "peak"] {
        let f = &doc[key];
        let _ = writeln!(
            s,
            "{key:<5} F_x {:9.1} N  F_y {:9.1} N  F_z {:9.1} N",
            num(&f["fx"]),
            num(&f["fy"]),
            num(&f["fz"])
        );
    }
    let _ = writeln!(s, "peak resultant {:.1} N", num(&doc["peak_resultant_n"]));
    let _ = writeln!(
        s,
        "torque mean {:.3} N·m, peak {:.3} N·m",
        num(&doc["mean_torque_nm"]),
        num(&doc["peak_torque_nm"])
    );
    if let Some(p) = doc["mean_power_w"].as_f64() {
        let _ = writeln!(
            s,
            "spindle power mean {p:.1} W, peak {:.1} W",
            num(&doc["peak_power_w"])
        );
    }
    if let Some(e) = doc["form_error_um"].as_f64() {
        let _ = writeln!(s, "wall error at the tool tip {e:.1} µm");
    }
    s
}
