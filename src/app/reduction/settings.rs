//! What a data reduction is run with (the window's settings, turned into the engine's
//! [`ReduceOptions`]) and what it produced (a regular or an XY-dependent Z-map, reduced).

use glam::DVec2;

use crate::reduce::{
    PartReduction, PartXyReduction, RankRule, ReduceOptions, Reduction, Resampling,
};

/// How the rank is chosen, as the window offers it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RankChoice {
    /// σ_{r+1} ≤ tolerance (a guaranteed bound at the nodes).
    Spectral,
    /// The thesis's loop (stop when a term changes the model by less than the tolerance).
    TermChange,
    /// Keep a fixed number of terms.
    Fixed,
}

/// Which Z-map of the part is reduced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ZmapSource {
    /// A regular grid over the part's XY box (heights exact on STEP faces).
    Regular,
    /// The thesis's XY-dependent Z-map: the mesh's vertices binned into a reference grid.
    XyDependent,
}

/// What a reduction is run with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReductionSettings {
    /// Which Z-map is reduced.
    pub source: ZmapSource,
    /// Z-map grid step, mm.
    pub step_mm: f64,
    /// Tolerance t, mm.
    pub tolerance_mm: f64,
    /// Rank rule.
    pub rank: RankChoice,
    /// Terms kept with [`RankChoice::Fixed`].
    pub fixed_rank: usize,
    /// Resample the kept singular vectors at the spacing a ball end mill allows.
    pub resample: bool,
    /// Ball radius ρ for the resampling, mm.
    pub ball_radius_mm: f64,
}

impl Default for ReductionSettings {
    fn default() -> Self {
        Self {
            source: ZmapSource::Regular,
            step_mm: 0.5,
            tolerance_mm: 0.01,
            rank: RankChoice::Spectral,
            fixed_rank: 5,
            resample: false,
            ball_radius_mm: 3.0,
        }
    }
}

impl ReductionSettings {
    /// Settings for a part of XY extent `size` (mm): a step giving about 200 nodes along the
    /// longer side (rounded to 1-2-5 × 10ᵏ mm), the ball radius of the selected tool if given.
    #[must_use]
    pub fn for_part(size: DVec2, ball_radius_mm: Option<f64>) -> Self {
        let raw = (size.max_element() / 200.0).max(1e-3);
        let p = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * p)
            .find(|s| *s >= raw)
            .unwrap_or(10.0 * p);
        Self {
            step_mm: step,
            ball_radius_mm: ball_radius_mm.unwrap_or(3.0),
            ..Self::default()
        }
    }

    /// The engine's options (the resampling's grid step is the Z-map's).
    #[must_use]
    pub fn options(&self) -> ReduceOptions {
        ReduceOptions {
            tolerance_mm: self.tolerance_mm,
            rank_rule: match self.rank {
                RankChoice::Spectral => RankRule::SpectralBound,
                RankChoice::TermChange => RankRule::TermChange,
                RankChoice::Fixed => RankRule::Fixed(self.fixed_rank),
            },
            resampling: self.resample.then_some(Resampling {
                tool_radius_mm: self.ball_radius_mm,
                grid_step_mm: self.step_mm,
            }),
        }
    }
}

/// A finished reduction of either kind of Z-map.
#[derive(Clone, Debug, PartialEq)]
pub enum ReductionResult {
    /// A regular Z-map (grid nodes).
    Regular(Box<PartReduction>),
    /// An XY-dependent Z-map (mesh vertices), reduced matrix by matrix.
    Xy(Box<PartXyReduction>),
}

impl ReductionResult {
    /// Largest |model − part| over the original nodes, mm.
    #[must_use]
    pub fn max_error(&self) -> f64 {
        match self {
            Self::Regular(r) => r.reduction.max_error,
            Self::Xy(r) => r.reduction.max_error,
        }
    }

    /// Numbers the reduced model stores.
    #[must_use]
    pub fn stored_numbers(&self) -> usize {
        match self {
            Self::Regular(r) => r.reduction.stored_numbers,
            Self::Xy(r) => r.stored_numbers(),
        }
    }

    /// The spectra shown: one per reduced matrix, with its name.
    #[must_use]
    pub fn spectra(&self) -> Vec<(&'static str, &Reduction)> {
        match self {
            Self::Regular(r) => vec![("Z", &r.reduction)],
            Self::Xy(r) => vec![
                ("X", &r.reduction.x),
                ("Y", &r.reduction.y),
                ("Z", &r.reduction.z),
            ],
        }
    }
}
