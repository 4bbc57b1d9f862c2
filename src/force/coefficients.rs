//! Cutting-force coefficients: the linear edge-force model (Eq. 5.21 of the thesis) and the
//! exponential model (Eqs. 5.2, 5.5), which becomes a linear model without edge terms once the
//! mean chip thickness is known.

use super::ForceError;

/// Linear edge-force model: `dF_t = (K_tc·h + K_te)·dS` and likewise for r and a (h chip
/// thickness in mm, dS edge length in mm). Cutting coefficients in N/mm², edge coefficients
/// in N/mm.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LinearCoefficients {
    /// Tangential cutting coefficient K_tc, N/mm².
    pub ktc: f64,
    /// Radial cutting coefficient K_rc, N/mm².
    pub krc: f64,
    /// Axial cutting coefficient K_ac, N/mm².
    pub kac: f64,
    /// Tangential edge coefficient K_te, N/mm.
    pub kte: f64,
    /// Radial edge coefficient K_re, N/mm.
    pub kre: f64,
    /// Axial edge coefficient K_ae, N/mm.
    pub kae: f64,
}

impl LinearCoefficients {
    /// The six values in the order K_tc, K_rc, K_ac, K_te, K_re, K_ae.
    #[must_use]
    pub fn to_array(&self) -> [f64; 6] {
        [self.ktc, self.krc, self.kac, self.kte, self.kre, self.kae]
    }

    /// From K_tc, K_rc, K_ac, K_te, K_re, K_ae.
    #[must_use]
    pub fn from_array(k: [f64; 6]) -> Self {
        Self {
            ktc: k[0],
            krc: k[1],
            kac: k[2],
            kte: k[3],
            kre: k[4],
            kae: k[5],
        }
    }
}

/// `K = k·h_a^(−p)` with h_a in mm.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PowerLaw {
    /// Value at h_a = 1 mm (N/mm² for K_t, a ratio for K_r and K_a).
    pub k: f64,
    /// Exponent p (dimensionless).
    pub p: f64,
}

impl PowerLaw {
    /// A constant (p = 0).
    #[must_use]
    pub fn constant(k: f64) -> Self {
        Self { k, p: 0.0 }
    }

    /// The value at mean chip thickness `h_a` (mm).
    #[must_use]
    pub fn at(&self, h_a: f64) -> f64 {
        self.k * h_a.powf(-self.p)
    }
}

/// Exponential model: `dF_t = K_t·h·dS`, `dF_r = K_r·dF_t`, `dF_a = K_a·dF_t`, with K_t (N/mm²)
/// and the ratios K_r, K_a power laws of the mean chip thickness h_a.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ExponentialCoefficients {
    /// K_t(h_a), N/mm².
    pub kt: PowerLaw,
    /// K_r(h_a), dimensionless.
    pub kr: PowerLaw,
    /// K_a(h_a), dimensionless.
    pub ka: PowerLaw,
}

/// Either model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Coefficients {
    /// Linear edge-force model.
    Linear(LinearCoefficients),
    /// Exponential model.
    Exponential(ExponentialCoefficients),
}

/// The smallest mean chip thickness the exponential model is evaluated at, mm (its power laws
/// grow without bound as h_a → 0).
pub const MIN_MEAN_CHIP_MM: f64 = 1e-4;

impl Coefficients {
    /// The linear coefficients that give this model's elemental forces at mean chip thickness
    /// `h_a` (mm): the linear model itself, or `K_tc = K_t(h_a)`, `K_rc = K_r(h_a)·K_t(h_a)`,
    /// `K_ac = K_a(h_a)·K_t(h_a)` and no edge terms.
    #[must_use]
    pub fn at_mean_chip(&self, h_a: f64) -> LinearCoefficients {
        match self {
            Self::Linear(l) => *l,
            Self::Exponential(e) => {
                let h = h_a.max(MIN_MEAN_CHIP_MM);
                let kt = e.kt.at(h);
                LinearCoefficients {
                    ktc: kt,
                    krc: e.kr.at(h) * kt,
                    kac: e.ka.at(h) * kt,
                    ..LinearCoefficients::default()
                }
            }
        }
    }

    /// Whether the model's coefficients depend on the mean chip thickness.
    #[must_use]
    pub fn is_exponential(&self) -> bool {
        matches!(self, Self::Exponential(_))
    }

    /// Check that every number is finite and within a sane range (|K| ≤ 10⁶ N/mm² or N/mm,
    /// exponents within ±3, K_t's factor positive).
    ///
    /// # Errors
    /// [`ForceError::Input`] naming the first bad coefficient.
    pub fn validate(&self) -> Result<(), ForceError> {
        let check = |name: &str, v: f64, bound: f64| super::check_range(name, v, -bound, bound, "");
        match self {
            Self::Linear(l) => {
                let names = ["K_tc", "K_rc", "K_ac", "K_te", "K_re", "K_ae"];
                for (n, v) in names.iter().zip(l.to_array()) {
                    check(n, v, 1e6)?;
                }
            }
            Self::Exponential(e) => {
                for (n, law) in [("K_t", e.kt), ("K_r", e.kr), ("K_a", e.ka)] {
                    check(n, law.k, 1e6)?;
                    check(&format!("{n} exponent"), law.p, 3.0)?;
                }
                if !(e.kt.k > 0.0) {
                    return Err(ForceError::Input(format!(
                        "K_t must be positive, got {} N/mm²",
                        e.kt.k
                    )));
                }
            }
        }
        Ok(())
    }
}
