//! `talas calibrate FORCES.csv --model linear|exponential [-o COEFFICIENTS] [--material NAME]
//! [--tool TEXT] [--json]`: cutting-force coefficients from measured mean forces (one test a
//! row, header `d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n[,fz_n]`); with
//! `-o`, a coefficient library (TOML) that `talas forces --coefficients` reads.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{Value, json};

use crate::force::calibrate::{Calibration, calibrate_exponential, calibrate_linear};
use crate::force::library::{Entry, Library};
use crate::force::measurements::parse_forces_csv;
use crate::force::{Coefficients, Mode};
use crate::import::ImportError;

/// The force model to calibrate.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Model {
    /// Linear edge-force model (K_tc, K_rc, K_ac, K_te, K_re, K_ae).
    Linear,
    /// Exponential model (K_t, K_r, K_a power laws of the mean chip thickness).
    Exponential,
}

/// Options of `talas calibrate`.
#[derive(Debug, clap::Args)]
pub struct CalibrateArgs {
    /// Measured mean forces (CSV).
    pub file: PathBuf,
    /// Which model to fit.
    #[arg(long, value_enum)]
    pub model: Model,
    /// Write the coefficients as a library file (TOML).
    #[arg(short = 'o', long = "output", value_name = "COEFFICIENTS")]
    pub output: Option<PathBuf>,
    /// Use only the tests of this mode (`up`, `down` or `slot`).
    #[arg(long, value_name = "MODE")]
    pub mode: Option<String>,
    /// Work material recorded in the library entry.
    #[arg(long, value_name = "NAME", default_value = "unknown")]
    pub material: String,
    /// Tool family recorded in the library entry.
    #[arg(long, value_name = "TEXT", default_value = "")]
    pub tool: String,
    /// Print one JSON document instead of the human summary.
    #[arg(long)]
    pub json: bool,
}

/// The coefficients as JSON with units in the names.
#[must_use]
pub fn coefficients_json(c: &Coefficients) -> Value {
    match c {
        Coefficients::Linear(l) => json!({
            "model": "linear",
            "ktc_n_mm2": l.ktc, "krc_n_mm2": l.krc, "kac_n_mm2": l.kac,
            "kte_n_mm": l.kte, "kre_n_mm": l.kre, "kae_n_mm": l.kae,
        }),
        Coefficients::Exponential(e) => json!({
            "model": "exponential",
            "kt_n_mm2": e.kt.k, "kt_exponent": e.kt.p,
            "kr": e.kr.k, "kr_exponent": e.kr.p,
            "ka": e.ka.k, "ka_exponent": e.ka.p,
        }),
    }
}

/// Fit the model and build the JSON document (and write the library when asked).
///
/// # Errors
/// An [`ImportError`] naming the file and line for bad input, or the file for a calibration
/// the measurements do not determine or an output that cannot be written.
pub fn calibrate(args: &CalibrateArgs) -> Result<Value, ImportError> {
    let bad = |place: Option<String>, msg: String| ImportError::new(&args.file, place, msg);
    let text = crate::storage::read_text_bounded(&args.file, crate::storage::TEXT_LIMIT_BYTES)
        .map_err(|e| bad(None, format!("cannot read file: {e}")))?;
    let mut rows =
        parse_forces_csv(&text).map_err(|e| bad(Some(format!("line {}", e.line)), e.message))?;
    if let Some(name) = &args.mode {
        let mode = Mode::parse(name)
            .ok_or_else(|| bad(None, format!("--mode {name} is not up, down or slot")))?;
        rows.retain(|r| r.mode == mode);
        if rows.is_empty() {
            return Err(bad(None, format!("no tests in {} milling", mode.name())));
        }
    }
    let cal: Calibration = match args.model {
        Model::Linear => calibrate_linear(&rows),
        Model::Exponential => calibrate_exponential(&rows),
    }
    .map_err(|e| bad(None, e.to_string()))?;
    let first = rows[0].mode;
    let mode = if rows.iter().all(|r| r.mode == first) {
        first.name()
    } else {
        "any"
    };
    if let Some(out) = &args.output {
        let mut entry = Entry::new(&args.material, &args.tool, mode, &cal.coefficients);
        entry.source = format!(
            "talas calibrate {} --model {:?}",
            file_name(&args.file),
            args.model
        )
        .to_lowercase();
        let lib = Library {
            entries: vec![entry],
        };
        let text = lib
            .to_toml()
            .map_err(|e| ImportError::new(out, None, format!("cannot write: {e}")))?;
        crate::storage::write_atomic(out, text.as_bytes())
            .map_err(|e| ImportError::new(out, None, format!("cannot write: {e}")))?;
    }
    let tests: Vec<Value> = cal
        .rows
        .iter()
        .map(|r| {
            json!({
                "line": r.line,
                "measured_n": {"fx": r.measured.fx, "fy": r.measured.fy},
                "predicted_n": {"fx": r.predicted.fx, "fy": r.predicted.fy, "fz": r.predicted.fz},
                "error_pct": {"fx": r.error_pct[0], "fy": r.error_pct[1]},
            })
        })
        .collect();
    Ok(json!({
        "file": args.file.display().to_string(),
        "tests": rows.len(),
        "mode": mode,
        "coefficients": coefficients_json(&cal.coefficients),
        "mean_error_pct": {"fx": cal.mean_error_pct[0], "fy": cal.mean_error_pct[1]},
        "fits": tests,
        "notes": cal.notes,
        "output": args.output.as_ref().map(|p| p.display().to_string()),
    }))
}

fn file_name(p: &Path) -> String {
    p.file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
}

/// A short human summary.
#[must_use]
pub fn human(doc: &Value) -> String {
    let mut s = String::new();
    let c = &doc["coefficients"];
    let _ = writeln!(
        s,
        "{} tests, model {}",
        doc["tests"],
        c["model"].as_str().unwrap_or("?")
    );
    if let Some(map) = c.as_object() {
        for (k, v) in map.iter().filter(|(k, _)| *k != "model") {
            let _ = writeln!(s, "  {k:<12} {:.4}", v.as_f64().unwrap_or(f64::NAN));
        }
    }
    let _ = writeln!(
        s,
        "mean error of the fit: F_x {:.2} %, F_y {:.2} %",
        doc["mean_error_pct"]["fx"].as_f64().unwrap_or(f64::NAN),
        doc["mean_error_pct"]["fy"].as_f64().unwrap_or(f64::NAN)
    );
    if let Some(notes) = doc["notes"].as_array() {
        for n in notes {
            let _ = writeln!(s, "note: {}", n.as_str().unwrap_or(""));
        }
    }
    if let Some(o) = doc["output"].as_str() {
        let _ = writeln!(s, "wrote {o}");
    }
    s
}
