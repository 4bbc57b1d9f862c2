//! Feeds and speeds from cutting data: a material library (cutting speed and chip load by tool
//! material and diameter, the specific cutting force), the spindle speed and feed that follow
//! from it, radial chip thinning at low engagement, ramp and plunge feeds, and a load check by
//! the cutting-force model (torque, power, peak force and the tool's deflection against the
//! tool's and the machine's limits).
//!
//! The formulas (D tool diameter, z flutes, a_e radial and a_p axial depth, all mm):
//! - spindle speed `n = 1000·v_c/(π·D)` rpm, capped at the machine's top speed (the cutting
//!   speed then falls to `v_c = π·D·n/1000`);
//! - chip load `f_z(D)` from the material's table by linear interpolation between the
//!   tabulated diameters, proportional to D below the first and constant above the last;
//!   high-speed steel takes [`HSS_CHIP_LOAD_FACTOR`] of carbide's;
//! - radial chip thinning: below half the diameter the largest chip is `h_ex = f_z·sin φ_e`,
//!   with `cos φ_e = 1 − 2·a_e/D`, so the feed per tooth that restores the table's chip is
//!   `f_z / sin φ_e = f_z·D / (2·√(a_e·(D − a_e)))`, capped at [`MAX_CHIP_THINNING`];
//! - feed `v_f = f_z'·z·n` mm/min, ramp `RAMP_FACTOR·v_f`, plunge `PLUNGE_FACTOR·v_f`;
//! - power: the force model's mean torque over a revolution for a straight cut of the given
//!   engagement (exponential coefficients from the material's `k_c1.1` and `m_c`), times
//!   `ω = 2π·n/60`.
//!
//! The library's numbers are starting values, the middle of the ranges that tool makers
//! publish for solid carbide and HSS end mills (Sandvik Coromant's material groups and
//! `k_c1.1`/`m_c`, Harvey Tool and Kennametal speed and feed charts); a shop overrides them by
//! typing a value, and [`Speeds::sources`] says where every number came from.

use std::f64::consts::PI;

use super::cut::{Mode, StraightCut};
use super::deflection::{BeamSpec, Cantilever, FLUTE_DIAMETER_RATIO, peak_disk_loads};
use super::{Coefficients, EndMill, ExponentialCoefficients, ForceError, RevolutionOptions};
use crate::force::coefficients::PowerLaw;
use crate::tools::Cutter;

/// HSS chip load as a fraction of carbide's.
pub const HSS_CHIP_LOAD_FACTOR: f64 = 0.8;
/// Largest chip-thinning factor applied (at a_e/D ≈ 1 %; below it the edge rubs instead of
/// cutting and a larger feed only breaks the tool).
pub const MAX_CHIP_THINNING: f64 = 5.0;
/// Ramp feed as a fraction of the cutting feed.
pub const RAMP_FACTOR: f64 = 0.5;
/// Plunge (straight down) feed as a fraction of the cutting feed.
pub const PLUNGE_FACTOR: f64 = 0.25;
/// Tabulated diameters of the chip-load tables, mm.
pub const TABLE_DIAMETERS_MM: [f64; 6] = [3.0, 6.0, 10.0, 12.0, 16.0, 20.0];
/// Young's modulus of solid carbide (deflection check), N/mm².
pub const CARBIDE_MODULUS_N_MM2: f64 = 600_000.0;
/// Young's modulus of HSS, N/mm².
pub const HSS_MODULUS_N_MM2: f64 = 210_000.0;
/// Tool deflection above which the load check warns, mm.
pub const DEFLECTION_WARNING_MM: f64 = 0.02;

/// What the cutting edges are made of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ToolMaterial {
    /// Solid carbide.
    Carbide,
    /// High-speed steel.
    Hss,
}

impl ToolMaterial {
    /// Parse `carbide` or `hss` (any case).
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        match text.trim().to_ascii_lowercase().as_str() {
            "carbide" | "vhm" | "solid carbide" => Some(Self::Carbide),
            "hss" | "hss-co" | "hsse" => Some(Self::Hss),
            _ => None,
        }
    }

    /// Its name as the library writes it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Carbide => "carbide",
            Self::Hss => "hss",
        }
    }

    fn modulus(self) -> f64 {
        match self {
            Self::Carbide => CARBIDE_MODULUS_N_MM2,
            Self::Hss => HSS_MODULUS_N_MM2,
        }
    }
}

/// One work material of the library.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Material {
    /// Short key (`6061`, `7075`, `1045`, `4140`, `304`, `ti64`, `brass`, `acetal`).
    pub key: &'static str,
    /// Full name.
    pub name: &'static str,
    /// Cutting speed with solid carbide, m/min.
    pub vc_carbide_m_min: f64,
    /// Cutting speed with HSS, m/min.
    pub vc_hss_m_min: f64,
    /// Carbide chip load per tooth at [`TABLE_DIAMETERS_MM`], mm.
    pub chip_load_mm: [f64; 6],
    /// Specific cutting force at a 1 mm chip, k_c1.1, N/mm².
    pub kc11_n_mm2: f64,
    /// Its exponent m_c (k_c = k_c1.1·h^−m_c).
    pub mc: f64,
    /// Radial over tangential cutting force.
    pub radial_ratio: f64,
}

/// The built-in library.
pub const MATERIALS: [Material; 8] = [
    Material {
        key: "6061",
        name: "aluminium 6061-T6",
        vc_carbide_m_min: 300.0,
        vc_hss_m_min: 90.0,
        chip_load_mm: [0.025, 0.05, 0.08, 0.09, 0.11, 0.13],
        kc11_n_mm2: 700.0,
        mc: 0.25,
        radial_ratio: 0.3,
    },
    Material {
        key: "7075",
        name: "aluminium 7075-T6",
        vc_carbide_m_min: 270.0,
        vc_hss_m_min: 80.0,
        chip_load_mm: [0.025, 0.05, 0.075, 0.085, 0.1, 0.12],
        kc11_n_mm2: 800.0,
        mc: 0.25,
        radial_ratio: 0.3,
    },
    Material {
        key: "1045",
        name: "steel 1045 (C45, ~200 HB)",
        vc_carbide_m_min: 150.0,
        vc_hss_m_min: 25.0,
        chip_load_mm: [0.015, 0.03, 0.045, 0.05, 0.06, 0.07],
        kc11_n_mm2: 1700.0,
        mc: 0.25,
        radial_ratio: 0.35,
    },
    Material {
        key: "4140",
        name: "steel 4140 (42CrMo4, ~230 HB)",
        vc_carbide_m_min: 120.0,
        vc_hss_m_min: 20.0,
        chip_load_mm: [0.013, 0.025, 0.04, 0.045, 0.055, 0.065],
        kc11_n_mm2: 1950.0,
        mc: 0.25,
        radial_ratio: 0.35,
    },
    Material {
        key: "304",
        name: "stainless steel 304 (X5CrNi18-10)",
        vc_carbide_m_min: 90.0,
        vc_hss_m_min: 15.0,
        chip_load_mm: [0.012, 0.025, 0.035, 0.04, 0.05, 0.06],
        kc11_n_mm2: 2100.0,
        mc: 0.21,
        radial_ratio: 0.4,
    },
    Material {
        key: "ti64",
        name: "titanium Ti-6Al-4V",
        vc_carbide_m_min: 50.0,
        vc_hss_m_min: 10.0,
        chip_load_mm: [0.012, 0.025, 0.035, 0.04, 0.05, 0.06],
        kc11_n_mm2: 1400.0,
        mc: 0.23,
        radial_ratio: 0.4,
    },
    Material {
        key: "brass",
        name: "free-cutting brass (CuZn39Pb3)",
        vc_carbide_m_min: 250.0,
        vc_hss_m_min: 60.0,
        chip_load_mm: [0.02, 0.04, 0.06, 0.07, 0.085, 0.1],
        kc11_n_mm2: 780.0,
        mc: 0.27,
        radial_ratio: 0.3,
    },
    Material {
        key: "acetal",
        name: "acetal (POM)",
        vc_carbide_m_min: 250.0,
        vc_hss_m_min: 150.0,
        chip_load_mm: [0.04, 0.08, 0.12, 0.14, 0.16, 0.2],
        kc11_n_mm2: 120.0,
        mc: 0.3,
        radial_ratio: 0.3,
    },
];

/// Find a material by key or by a word of its name (`al6061`, `6061-t6`, `Ti-6Al-4V`,
/// `stainless`, `POM`, …).
#[must_use]
pub fn material(name: &str) -> Option<&'static Material> {
    let norm: String = name
        .to_ascii_lowercase()
        .chars()
        .filter(char::is_ascii_alphanumeric)
        .collect();
    if norm.is_empty() {
        return None;
    }
    let aliases: [(&str, &str); 8] = [
        ("c45", "1045"),
        ("42crmo4", "4140"),
        ("stainless", "304"),
        ("ti6al4v", "ti64"),
        ("titanium", "ti64"),
        ("pom", "acetal"),
        ("delrin", "acetal"),
        ("cuzn39pb3", "brass"),
    ];
    // An exact key, then a key inside the name (`al6061t6`, `aisi304`, `ss304`), then an
    // alias inside it.
    MATERIALS
        .iter()
        .find(|m| m.key == norm)
        .or_else(|| MATERIALS.iter().find(|m| norm.contains(m.key)))
        .or_else(|| {
            aliases
                .iter()
                .find(|(a, _)| norm.contains(a))
                .and_then(|(_, k)| MATERIALS.iter().find(|m| m.key == *k))
        })
}

impl Material {
    /// The cutting speed for a tool material, m/min.
    #[must_use]
    pub fn cutting_speed_m_min(&self, tool: ToolMaterial) -> f64 {
        match tool {
            ToolMaterial::Carbide => self.vc_carbide_m_min,
            ToolMaterial::Hss => self.vc_hss_m_min,
        }
    }

    /// The table's chip load per tooth for a diameter and tool material, mm.
    #[must_use]
    pub fn chip_load_mm(&self, diameter_mm: f64, tool: ToolMaterial) -> f64 {
        let d = TABLE_DIAMETERS_MM;
        let f = self.chip_load_mm;
        let carbide = if diameter_mm <= d[0] {
            f[0] * diameter_mm / d[0]
        } else if diameter_mm >= d[5] {
            f[5]
        } else {
            let i = d.windows(2).position(|w| diameter_mm <= w[1]).unwrap_or(4);
            let t = (diameter_mm - d[i]) / (d[i + 1] - d[i]);
            f[i] + t * (f[i + 1] - f[i])
        };
        match tool {
            ToolMaterial::Carbide => carbide,
            ToolMaterial::Hss => carbide * HSS_CHIP_LOAD_FACTOR,
        }
    }

    /// The exponential force coefficients of this material: `K_t = k_c1.1·h^−m_c`,
    /// `K_r = radial_ratio`, `K_a = 0`.
    #[must_use]
    pub fn coefficients(&self) -> Coefficients {
        Coefficients::Exponential(ExponentialCoefficients {
            kt: PowerLaw {
                k: self.kc11_n_mm2,
                p: self.mc,
            },
            kr: PowerLaw::constant(self.radial_ratio),
            ka: PowerLaw::constant(0.0),
        })
    }
}

/// The radial chip-thinning factor at radial depth `ae` of a tool of diameter `d` (1 at or
/// above half the diameter, at most [`MAX_CHIP_THINNING`]).
#[must_use]
pub fn chip_thinning_factor(ae_mm: f64, d_mm: f64) -> f64 {
    if !(ae_mm > 0.0 && d_mm > 0.0) || ae_mm >= 0.5 * d_mm {
        return 1.0;
    }
    let s = 2.0 * (ae_mm * (d_mm - ae_mm)).sqrt() / d_mm;
    (1.0 / s).min(MAX_CHIP_THINNING)
}

/// What a speeds-and-feeds recommendation is for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case<'a> {
    /// Work material.
    pub material: &'a Material,
    /// Tool material.
    pub tool_material: ToolMaterial,
    /// Tool diameter, mm.
    pub diameter_mm: f64,
    /// Flute count.
    pub flutes: u32,
    /// Radial depth of cut (width) a_e, mm.
    pub radial_mm: f64,
    /// Axial depth of cut a_p, mm.
    pub axial_mm: f64,
    /// The machine's top spindle speed, rpm (`None`: no cap).
    pub max_rpm: Option<f64>,
}

/// Where one number of a recommendation came from.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Source {
    /// The quantity (`spindle speed`, `feed`, …).
    pub quantity: &'static str,
    /// How it was found, in words with the numbers used.
    pub from: String,
}

/// A recommendation: spindle speed, feeds and the chip they give.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Speeds {
    /// The material's key.
    pub material: &'static str,
    /// Cutting speed used, m/min (below the table's when the spindle caps it).
    pub cutting_speed_m_min: f64,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// The table's chip load per tooth, mm.
    pub table_chip_load_mm: f64,
    /// Radial chip-thinning factor applied.
    pub chip_thinning: f64,
    /// Programmed feed per tooth (table chip load × chip thinning), mm.
    pub feed_per_tooth_mm: f64,
    /// Largest chip thickness of that feed at this engagement, mm.
    pub max_chip_mm: f64,
    /// Cutting feed, mm/min.
    pub feed_mm_min: f64,
    /// Ramp feed, mm/min.
    pub ramp_feed_mm_min: f64,
    /// Plunge feed, mm/min.
    pub plunge_feed_mm_min: f64,
    /// Material removal rate, cm³/min.
    pub removal_cm3_min: f64,
    /// Where each number came from.
    pub sources: Vec<Source>,
}

/// Why a recommendation or a load check cannot be made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CuttingDataError {
    /// A value out of range.
    #[error("{0}")]
    Input(String),
    /// The force model refused the cut.
    #[error("force model: {0}")]
    Force(#[from] ForceError),
}

fn positive(what: &str, v: f64, hi: f64, unit: &str) -> Result<(), CuttingDataError> {
    if v.is_finite() && v > 0.0 && v <= hi {
        Ok(())
    } else {
        Err(CuttingDataError::Input(format!(
            "{what} must be above 0 and at most {hi} {unit}, got {v}"
        )))
    }
}

/// The spindle speed, feeds and chip for a case.
///
/// # Errors
/// [`CuttingDataError::Input`] for a diameter outside (0, 200] mm, flutes outside 1–16, a
/// radial depth outside (0, D], an axial depth outside (0, 500] mm or a top speed that is not
/// positive.
pub fn recommend(case: &Case<'_>) -> Result<Speeds, CuttingDataError> {
    let d = case.diameter_mm;
    positive("tool diameter", d, 200.0, "mm")?;
    positive("radial depth", case.radial_mm, d, "mm")?;
    positive("axial depth", case.axial_mm, 500.0, "mm")?;
    if !(1..=16).contains(&case.flutes) {
        return Err(CuttingDataError::Input(format!(
            "flutes must be 1 to 16, got {}",
            case.flutes
        )));
    }
    if let Some(m) = case.max_rpm {
        positive("top spindle speed", m, 1e6, "rpm")?;
    }
    let m = case.material;
    let vc_table = m.cutting_speed_m_min(case.tool_material);
    let n_table = 1000.0 * vc_table / (PI * d);
    let mut sources = Vec::new();
    let (n, vc) = match case.max_rpm {
        Some(max) if n_table > max => {
            sources.push(Source {
                quantity: "spindle speed",
                from: format!(
                    "capped at the machine's {max:.0} rpm (the table's {vc_table:.0} m/min \
                     would need {n_table:.0} rpm); cutting speed falls to {:.1} m/min",
                    PI * d * max / 1000.0
                ),
            });
            (max, PI * d * max / 1000.0)
        }
        _ => {
            sources.push(Source {
                quantity: "spindle speed",
                from: format!(
                    "{} with {}: {vc_table:.0} m/min → n = 1000·v_c/(π·D) = {n_table:.0} rpm",
                    m.name,
                    case.tool_material.name()
                ),
            });
            (n_table, vc_table)
        }
    };
    let fz0 = m.chip_load_mm(d, case.tool_material);
    sources.push(Source {
        quantity: "chip load",
        from: format!(
            "{} table at D = {d} mm ({}): {fz0:.4} mm/tooth",
            m.name,
            case.tool_material.name()
        ),
    });
    let thin = chip_thinning_factor(case.radial_mm, d);
    let fz = fz0 * thin;
    let phi_e = (1.0 - 2.0 * (case.radial_mm / d).min(1.0))
        .clamp(-1.0, 1.0)
        .acos();
    let max_chip = if phi_e >= 0.5 * PI {
        fz
    } else {
        fz * phi_e.sin()
    };
    sources.push(Source {
        quantity: "feed per tooth",
        from: if thin > 1.0 {
            format!(
                "radial chip thinning at a_e/D = {:.1} %: ×{thin:.3} → {fz:.4} mm/tooth",
                100.0 * case.radial_mm / d
            )
        } else {
            "no chip thinning (a_e ≥ D/2)".into()
        },
    });
    let feed = fz * f64::from(case.flutes) * n;
    sources.push(Source {
        quantity: "feed",
        from: format!(
            "v_f = f_z·z·n = {fz:.4} × {} × {n:.0} = {feed:.0} mm/min",
            case.flutes
        ),
    });
    sources.push(Source {
        quantity: "ramp and plunge feeds",
        from: format!(
            "{:.0} % and {:.0} % of the cutting feed",
            RAMP_FACTOR * 100.0,
            PLUNGE_FACTOR * 100.0
        ),
    });
    Ok(Speeds {
        material: m.key,
        cutting_speed_m_min: vc,
        spindle_rpm: n,
        table_chip_load_mm: fz0,
        chip_thinning: thin,
        feed_per_tooth_mm: fz,
        max_chip_mm: max_chip,
        feed_mm_min: feed,
        ramp_feed_mm_min: RAMP_FACTOR * feed,
        plunge_feed_mm_min: PLUNGE_FACTOR * feed,
        removal_cm3_min: case.radial_mm * case.axial_mm * feed / 1000.0,
        sources,
    })
}

/// The limits a load check compares against (each optional).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Limits {
    /// The machine's rated spindle power, W.
    pub spindle_power_w: Option<f64>,
    /// The tool's largest resultant force, N.
    pub max_force_n: Option<f64>,
    /// The tool's largest torque, N·m.
    pub max_torque_nm: Option<f64>,
    /// The tool's largest power, W.
    pub max_power_w: Option<f64>,
}

/// What the force model says about a recommendation.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LoadCheck {
    /// Mean torque over a revolution, N·m.
    pub mean_torque_nm: f64,
    /// Mean cutting power, W.
    pub mean_power_w: f64,
    /// Peak torque over a revolution, N·m.
    pub peak_torque_nm: f64,
    /// Peak resultant force, N.
    pub peak_force_n: f64,
    /// Largest static deflection of the tool at the peak force, mm (`None` when the cutter has
    /// no overhang to model).
    pub deflection_mm: Option<f64>,
    /// What the machine or the tool cannot take, in words (empty: nothing).
    pub flags: Vec<String>,
}

/// The force model's torque, power, peak force and deflection for the recommendation `speeds`
/// of `case`, and what exceeds the limits. The cutter must carry flutes (count, helix, rake)
/// for the force model; `mode` is up (conventional), down (climb) or slot (taken when the
/// radial depth is the whole diameter).
///
/// # Errors
/// [`CuttingDataError::Force`] when the force model cannot model the tool or the cut.
pub fn check_load(
    case: &Case<'_>,
    cutter: &Cutter,
    speeds: &Speeds,
    mode: Mode,
    limits: &Limits,
) -> Result<LoadCheck, CuttingDataError> {
    let (material, tool_material) = (case.material, case.tool_material);
    let (radial_mm, axial_mm) = (case.radial_mm, case.axial_mm);
    let mill = EndMill::from_cutter(cutter)?;
    let mode = if radial_mm >= mill.diameter() - 1e-9 {
        Mode::Slot
    } else {
        mode
    };
    let cut = StraightCut {
        radial_depth: radial_mm.min(mill.diameter()),
        axial_depth: axial_mm,
        feed_per_tooth: speeds.feed_per_tooth_mm,
        mode,
    };
    let engagement = cut.engagement(&mill, super::cut::DEFAULT_DISK_HEIGHT)?;
    let coefficients = material.coefficients();
    let rev = super::revolution(
        &mill,
        &coefficients,
        &engagement,
        &RevolutionOptions {
            steps: 360,
            spindle_rpm: Some(speeds.spindle_rpm),
        },
    )?;
    let mean_power = rev.mean_power_w.unwrap_or(0.0).abs();
    let deflection = if cutter.overall_length > 0.0 {
        let beam = Cantilever::end_mill(&BeamSpec {
            diameter: cutter.diameter,
            flute_length: cutter.flute_length.min(cutter.overall_length),
            shank_diameter: cutter.shank_diameter,
            overhang: cutter.overall_length,
            youngs_modulus: tool_material.modulus(),
            flute_diameter_ratio: FLUTE_DIAMETER_RATIO,
        })?;
        let (_, loads) = peak_disk_loads(&mill, &coefficients, &engagement, 360);
        let (mut dx, mut dy) = (0.0, 0.0);
        for &(zm, fx, fy) in &loads {
            let c = beam.influence(0.0, zm);
            dx += fx * c;
            dy += fy * c;
        }
        Some(f64::hypot(dx, dy))
    } else {
        None
    };
    let mut flags = Vec::new();
    let over = |flags: &mut Vec<String>, what: &str, v: f64, lim: Option<f64>, unit: &str| {
        if let Some(l) = lim
            && v > l
        {
            flags.push(format!(
                "{what} {v:.1} {unit} is above the limit of {l:.1} {unit}"
            ));
        }
    };
    over(
        &mut flags,
        "mean cutting power",
        mean_power,
        limits.spindle_power_w,
        "W (spindle)",
    );
    over(
        &mut flags,
        "mean cutting power",
        mean_power,
        limits.max_power_w,
        "W (tool)",
    );
    over(
        &mut flags,
        "peak torque",
        rev.peak_torque_nm.abs(),
        limits.max_torque_nm,
        "N·m",
    );
    over(
        &mut flags,
        "peak force",
        rev.peak_resultant_n,
        limits.max_force_n,
        "N",
    );
    if let Some(d) = deflection
        && d > DEFLECTION_WARNING_MM
    {
        flags.push(format!(
            "tool deflection {:.3} mm at the peak force is above {DEFLECTION_WARNING_MM} mm: \
             shorten the stick-out or lower the engagement",
            d
        ));
    }
    Ok(LoadCheck {
        mean_torque_nm: rev.mean_torque_nm.abs(),
        mean_power_w: mean_power,
        peak_torque_nm: rev.peak_torque_nm.abs(),
        peak_force_n: rev.peak_resultant_n,
        deflection_mm: deflection,
        flags,
    })
}

#[cfg(test)]
mod tests;
