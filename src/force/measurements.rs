//! FORCES.csv: measured mean forces, one test a row, with the header
//! `d_mm,flutes,helix_deg,rake_deg,mode,ae_mm,ap_mm,ft_mm,fx_n,fy_n` and optionally `fz_n`.
//!
//! The reader is generous: columns in any order (found by header name, case-insensitive),
//! separators `,`, `;` or tab, surrounding spaces, blank lines, `#` comment lines and extra
//! columns are accepted. Every error names the line (1-based, as an editor shows it).

use std::f64::consts::PI;

use super::cut::{Mode, StraightCut};
use super::mill::{EndMill, Profile};

/// One measured test: a straight cut with a flat end mill and its mean forces.
#[derive(Clone, Debug, PartialEq)]
pub struct Measurement {
    /// Line of the row in the file (1-based).
    pub line: usize,
    /// Tool diameter, mm.
    pub diameter: f64,
    /// Flutes.
    pub flutes: u32,
    /// Helix angle, rad.
    pub helix: f64,
    /// Rake angle, rad.
    pub rake: f64,
    /// Mode.
    pub mode: Mode,
    /// Radial depth, mm.
    pub ae: f64,
    /// Axial depth, mm.
    pub ap: f64,
    /// Feed per tooth, mm.
    pub ft: f64,
    /// Mean F_x, N.
    pub fx: f64,
    /// Mean F_y, N.
    pub fy: f64,
    /// Mean F_z, N, when measured.
    pub fz: Option<f64>,
}

impl Measurement {
    /// The tool of this test (flat end mill).
    ///
    /// # Errors
    /// [`super::ForceError`] if the geometry is out of range (the reader has checked it).
    pub fn mill(&self) -> Result<EndMill, super::ForceError> {
        EndMill::new(
            Profile::Flat,
            self.diameter,
            self.flutes,
            self.helix,
            self.rake,
        )
    }

    /// The cut of this test.
    #[must_use]
    pub fn cut(&self) -> StraightCut {
        StraightCut {
            radial_depth: self.ae,
            axial_depth: self.ap,
            feed_per_tooth: self.ft,
            mode: self.mode,
        }
    }
}

/// A malformed FORCES.csv.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("line {line}: {message}")]
pub struct MeasurementError {
    /// 1-based line.
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

const COLUMNS: [&str; 10] = [
    "d_mm",
    "flutes",
    "helix_deg",
    "rake_deg",
    "mode",
    "ae_mm",
    "ap_mm",
    "ft_mm",
    "fx_n",
    "fy_n",
];

/// Parse FORCES.csv text.
///
/// # Errors
/// [`MeasurementError`] naming the line: a missing header column, a row with too few fields,
/// a value that is not a number or out of range, or no rows at all.
pub fn parse_forces_csv(text: &str) -> Result<Vec<Measurement>, MeasurementError> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let (hline, header) = lines.next().ok_or_else(|| MeasurementError {
        line: 1,
        message: "empty file: expected the header d_mm,flutes,helix_deg,...".into(),
    })?;
    let sep = [',', ';', '\t']
        .into_iter()
        .max_by_key(|c| header.matches(*c).count())
        .unwrap_or(',');
    let names: Vec<String> = header
        .split(sep)
        .map(|h| h.trim().trim_matches('"').to_ascii_lowercase())
        .collect();
    let find = |name: &str| names.iter().position(|n| n == name);
    let mut idx = [0usize; 10];
    for (slot, name) in idx.iter_mut().zip(COLUMNS) {
        *slot = find(name).ok_or_else(|| MeasurementError {
            line: hline,
            message: format!(
                "header has no column '{name}' (needs {})",
                COLUMNS.join(",")
            ),
        })?;
    }
    let fz_col = find("fz_n");
    let mut rows = Vec::new();
    for (line, text) in lines {
        rows.push(parse_row(line, text, sep, &idx, fz_col, names.len())?);
    }
    if rows.is_empty() {
        return Err(MeasurementError {
            line: hline,
            message: "no measurements after the header".into(),
        });
    }
    Ok(rows)
}

fn parse_row(
    line: usize,
    text: &str,
    sep: char,
    idx: &[usize; 10],
    fz_col: Option<usize>,
    width: usize,
) -> Result<Measurement, MeasurementError> {
    let bad = |message: String| MeasurementError { line, message };
    let fields: Vec<&str> = text
        .split(sep)
        .map(|f| f.trim().trim_matches('"'))
        .collect();
    if fields.len() < width {
        return Err(bad(format!(
            "{} fields, the header has {width}",
            fields.len()
        )));
    }
    let num = |col: usize, lo: f64, hi: f64| -> Result<f64, MeasurementError> {
        let name = COLUMNS[col];
        let v: f64 = fields[idx[col]]
            .parse()
            .map_err(|_| bad(format!("{name} '{}' is not a number", fields[idx[col]])))?;
        if v.is_finite() && v >= lo && v <= hi {
            Ok(v)
        } else {
            Err(bad(format!("{name} = {v} is outside [{lo}, {hi}]")))
        }
    };
    let d = num(0, 1e-3, 1000.0)?;
    let flutes = num(1, 1.0, 16.0)?;
    if flutes.fract() != 0.0 {
        return Err(bad(format!("flutes = {flutes} is not a whole number")));
    }
    let mode_text = fields[idx[4]];
    let mode = Mode::parse(mode_text)
        .ok_or_else(|| bad(format!("mode '{mode_text}' is not up, down or slot")))?;
    let ae = num(5, 1e-6, d)?;
    if mode == Mode::Slot && (ae - d).abs() > 1e-9 {
        return Err(bad(format!("a slot has ae_mm = d_mm = {d}, got {ae}")));
    }
    let fz = match fz_col {
        Some(c) if !fields.get(c).is_none_or(|f| f.is_empty()) => {
            let f = fields[c];
            let v: f64 = f
                .parse()
                .map_err(|_| bad(format!("fz_n '{f}' is not a number")))?;
            if !(v.is_finite() && v.abs() <= 1e6) {
                return Err(bad(format!("fz_n = {v} is outside [-1e6, 1e6]")));
            }
            Some(v)
        }
        _ => None,
    };
    Ok(Measurement {
        line,
        diameter: d,
        // A whole number in 1..=16.
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        flutes: flutes as u32,
        helix: num(2, 0.0, 59.999)? * PI / 180.0,
        rake: num(3, -30.0, 45.0)? * PI / 180.0,
        mode,
        ae,
        ap: num(6, 1e-6, 500.0)?,
        ft: num(7, 1e-6, 2.0)?,
        fx: num(8, -1e6, 1e6)?,
        fy: num(9, -1e6, 1e6)?,
        fz,
    })
}
