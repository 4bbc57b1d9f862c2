//! The coefficient library: a TOML file of entries, each giving a material, a tool family, a
//! milling mode (`up`, `down`, `slot` or `any`) and the coefficients of one model. The
//! workstation edits it; `talas calibrate -o` writes it; `talas forces --coefficients` reads it.
//!
//! ```toml
//! [[entry]]
//! material = "Al7075-T651"
//! tool = "carbide flat end mill, 2 flutes, helix 30 deg"
//! mode = "up"
//! model = "linear"
//! ktc_n_mm2 = 1508.5
//! krc_n_mm2 = 18.5
//! kac_n_mm2 = 0.0
//! kte_n_mm = -1.5
//! kre_n_mm = -4.2
//! kae_n_mm = 0.0
//! source = "mean-force calibration on Table 8.4"
//! ```
//!
//! An exponential entry has `model = "exponential"` and `kt_n_mm2`, `kt_exponent`, `kr`,
//! `kr_exponent`, `ka`, `ka_exponent` (K = k·h_a^(−exponent), h_a in mm).

use std::path::Path;

use super::coefficients::{ExponentialCoefficients, PowerLaw};
use super::cut::Mode;
use super::{Coefficients, LinearCoefficients};

/// One library entry as stored.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Work material.
    pub material: String,
    /// Tool family (free text).
    #[serde(default)]
    pub tool: String,
    /// `up`, `down`, `slot` or `any`.
    #[serde(default = "any")]
    pub mode: String,
    /// `linear` or `exponential`.
    pub model: String,
    /// Linear: K_tc, N/mm².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ktc_n_mm2: Option<f64>,
    /// Linear: K_rc, N/mm².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub krc_n_mm2: Option<f64>,
    /// Linear: K_ac, N/mm².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kac_n_mm2: Option<f64>,
    /// Linear: K_te, N/mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kte_n_mm: Option<f64>,
    /// Linear: K_re, N/mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kre_n_mm: Option<f64>,
    /// Linear: K_ae, N/mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kae_n_mm: Option<f64>,
    /// Exponential: K_t at h_a = 1 mm, N/mm².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kt_n_mm2: Option<f64>,
    /// Exponential: exponent of K_t.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kt_exponent: Option<f64>,
    /// Exponential: K_r at h_a = 1 mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kr: Option<f64>,
    /// Exponential: exponent of K_r.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kr_exponent: Option<f64>,
    /// Exponential: K_a at h_a = 1 mm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ka: Option<f64>,
    /// Exponential: exponent of K_a.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ka_exponent: Option<f64>,
    /// Where the numbers come from.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub source: String,
}

fn any() -> String {
    "any".into()
}

impl Entry {
    /// A library entry for `coefficients`.
    #[must_use]
    pub fn new(material: &str, tool: &str, mode: &str, coefficients: &Coefficients) -> Self {
        let mut e = Self {
            material: material.into(),
            tool: tool.into(),
            mode: mode.into(),
            model: String::new(),
            ktc_n_mm2: None,
            krc_n_mm2: None,
            kac_n_mm2: None,
            kte_n_mm: None,
            kre_n_mm: None,
            kae_n_mm: None,
            kt_n_mm2: None,
            kt_exponent: None,
            kr: None,
            kr_exponent: None,
            ka: None,
            ka_exponent: None,
            source: String::new(),
        };
        match coefficients {
            Coefficients::Linear(l) => {
                e.model = "linear".into();
                e.ktc_n_mm2 = Some(l.ktc);
                e.krc_n_mm2 = Some(l.krc);
                e.kac_n_mm2 = Some(l.kac);
                e.kte_n_mm = Some(l.kte);
                e.kre_n_mm = Some(l.kre);
                e.kae_n_mm = Some(l.kae);
            }
            Coefficients::Exponential(x) => {
                e.model = "exponential".into();
                e.kt_n_mm2 = Some(x.kt.k);
                e.kt_exponent = Some(x.kt.p);
                e.kr = Some(x.kr.k);
                e.kr_exponent = Some(x.kr.p);
                e.ka = Some(x.ka.k);
                e.ka_exponent = Some(x.ka.p);
            }
        }
        e
    }

    /// The entry's coefficients (missing axial terms are 0).
    ///
    /// # Errors
    /// A message for an unknown model or mode, a missing coefficient or one out of range.
    pub fn coefficients(&self) -> Result<Coefficients, String> {
        if self.mode_filter().is_err() {
            return Err(format!("mode '{}' is not up, down, slot or any", self.mode));
        }
        let need = |v: Option<f64>, name: &str| {
            v.ok_or_else(|| format!("a {} entry needs {name}", self.model))
        };
        let c = match self.model.as_str() {
            "linear" => Coefficients::Linear(LinearCoefficients {
                ktc: need(self.ktc_n_mm2, "ktc_n_mm2")?,
                krc: need(self.krc_n_mm2, "krc_n_mm2")?,
                kac: self.kac_n_mm2.unwrap_or(0.0),
                kte: need(self.kte_n_mm, "kte_n_mm")?,
                kre: need(self.kre_n_mm, "kre_n_mm")?,
                kae: self.kae_n_mm.unwrap_or(0.0),
            }),
            "exponential" => Coefficients::Exponential(ExponentialCoefficients {
                kt: PowerLaw {
                    k: need(self.kt_n_mm2, "kt_n_mm2")?,
                    p: self.kt_exponent.unwrap_or(0.0),
                },
                kr: PowerLaw {
                    k: need(self.kr, "kr")?,
                    p: self.kr_exponent.unwrap_or(0.0),
                },
                ka: PowerLaw {
                    k: self.ka.unwrap_or(0.0),
                    p: self.ka_exponent.unwrap_or(0.0),
                },
            }),
            other => return Err(format!("model '{other}' is not linear or exponential")),
        };
        c.validate().map_err(|e| e.to_string())?;
        Ok(c)
    }

    /// `Ok(None)` for `any`, `Ok(Some(mode))`, or `Err` for an unknown mode.
    fn mode_filter(&self) -> Result<Option<Mode>, ()> {
        if self.mode.eq_ignore_ascii_case("any") {
            Ok(None)
        } else {
            Mode::parse(&self.mode).map(Some).ok_or(())
        }
    }
}

/// A coefficient library.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Library {
    /// Entries in file order.
    #[serde(default, rename = "entry")]
    pub entries: Vec<Entry>,
}

impl Library {
    /// Parse library text; errors say `line L, column C: ...` or `entry K: ...`.
    ///
    /// # Errors
    /// A one-line message naming the place.
    pub fn parse(text: &str) -> Result<Self, String> {
        let lib: Self = toml::from_str(text).map_err(|e| {
            let at = e.span().map_or(0, |s| s.start).min(text.len());
            let line = text[..at].matches('\n').count() + 1;
            let column = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
            format!("line {line}, column {column}: {}", e.message())
        })?;
        if lib.entries.is_empty() {
            return Err("line 1: the library has no [[entry]]".into());
        }
        for (i, e) in lib.entries.iter().enumerate() {
            e.coefficients()
                .map_err(|m| format!("entry {}: {m}", i + 1))?;
        }
        Ok(lib)
    }

    /// Read a library file.
    ///
    /// # Errors
    /// A one-line message naming the file and the place.
    pub fn load(path: &Path) -> Result<Self, String> {
        let text = crate::storage::read_text_bounded(path, crate::storage::TEXT_LIMIT_BYTES)
            .map_err(|e| format!("{}: cannot read file: {e}", path.display()))?;
        Self::parse(&text).map_err(|m| format!("{}: {m}", path.display()))
    }

    /// The TOML text of the library.
    ///
    /// # Errors
    /// A message if serialisation fails.
    pub fn to_toml(&self) -> Result<String, String> {
        toml::to_string_pretty(self).map_err(|e| e.to_string())
    }

    /// The first entry for `mode` (an exact mode first, then `any`), optionally of `material`.
    #[must_use]
    pub fn select(&self, mode: Mode, material: Option<&str>) -> Option<&Entry> {
        let fits = |e: &&Entry| material.is_none_or(|m| e.material.eq_ignore_ascii_case(m));
        let exact = self
            .entries
            .iter()
            .filter(fits)
            .find(|e| e.mode_filter() == Ok(Some(mode)));
        exact.or_else(|| {
            self.entries
                .iter()
                .filter(fits)
                .find(|e| e.mode_filter() == Ok(None))
        })
    }
}

impl Library {
    /// The coefficients per milling mode for a path: up and down from their entries (each
    /// standing in for the other when missing), a slot from the slot entry, else the up one,
    /// else the down one; with the material of the up entry.
    ///
    /// # Errors
    /// A message when no entry fits (of `material`, when given) or an entry is invalid.
    pub fn mode_coefficients(
        &self,
        material: Option<&str>,
    ) -> Result<(super::path::ModeCoefficients, String), String> {
        let pick = |mode: Mode| self.select(mode, material);
        let (up, down) = (pick(Mode::Up), pick(Mode::Down));
        let slot = pick(Mode::Slot).or(up).or(down);
        let (Some(up), Some(down), Some(slot)) = (up.or(down), down.or(up), slot) else {
            return Err(format!(
                "no entry{}",
                material.map_or(String::new(), |m| format!(" for material {m}"))
            ));
        };
        Ok((
            super::path::ModeCoefficients {
                up: up.coefficients()?,
                down: down.coefficients()?,
                slot: slot.coefficients()?,
            },
            up.material.clone(),
        ))
    }
}
