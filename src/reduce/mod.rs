//! Z-map data reduction by truncated singular value decomposition (Yurtsever 2010):
//! Z = Σ σ_k U_k V_kᵀ, keep the first r terms, resample each kept singular vector at
//! the spacing a ball end mill's tolerance allows, multiply back, and report the error.
//!
//! **Rank.** [`RankRule::SpectralBound`] (the default) keeps the smallest r with σ_{r+1} ≤ the
//! tolerance. That is a guaranteed bound on every node: |A − B_r|_ij = |e_iᵀ(A − B_r)e_j| ≤
//! ‖A − B_r‖₂ = σ_{r+1}. [`RankRule::TermChange`] is the thesis's loop: add terms until the
//! newest one changes the model by less than the tolerance (max |σ_k U_k V_kᵀ|, which is not
//! monotone in k, so it bounds nothing).
//!
//! **Resampling.** The point spacing is l = √(4ρt − t²) (ball radius ρ, tolerance t): the one
//! form that reproduces all four spacings the thesis reports (0.773, 1.536, 0.399, 0.888 mm);
//! the printed Eqs. 6.7/6.8 do not. A vector of N points at grid step γ becomes
//! ⌊(N − 1)γ/l⌋ + 1 points (the thesis's regular cases), linearly interpolated over the same
//! physical extent ([`reduce_to_size`] resamples to a given size instead, as the thesis's
//! examples do).
//!
//! **XY-dependent Z-maps** ([`crate::geometry::zmap::XyZmap`]) are reduced matrix by matrix
//! with [`reduce_xy_zmap`]; a part's Z-map (exact heights on STEP faces) is sampled and reduced by
//! [`part_zmap`], [`reduce_part`] and [`reduce_part_xy`].
//!
//! The Z-maps themselves (grids, construction from meshes, surfaces and points) are
//! [`crate::geometry::zmap`]; tool paths on Z-maps are [`crate::strategies::zmap`].

mod part_reduction;
mod svd;
mod xy_reduction;

pub use part_reduction::{
    ExactFaces, MAX_PART_ZMAP_NODES, PartReduction, PartXyReduction, PartZmap, part_zmap,
    reduce_part, reduce_part_xy, zmap_size,
};
pub use svd::{SvdFactors, svd};
pub use xy_reduction::{XyReduction, reduce_xy_zmap};

use crate::geometry::zmap::{Grid, ZmapError};

/// Why a Z-map could not be reduced.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ReduceError {
    /// A line of the Z-map file is malformed.
    #[error("line {line}: {message}")]
    Parse {
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The grid has no values or inconsistent sizes.
    #[error("bad grid shape: {0}")]
    Shape(String),
    /// A value is NaN or infinite.
    #[error("value at row {row}, column {col} is not finite")]
    NonFinite {
        /// 1-based row.
        row: usize,
        /// 1-based column.
        col: usize,
    },
    /// An option is out of range.
    #[error("invalid option: {0}")]
    Option(String),
    /// The SVD did not converge.
    #[error("singular value decomposition failed: {0}")]
    Svd(String),
    /// The work was cancelled.
    #[error("cancelled")]
    Cancelled,
}

/// A Z-map error as the same reduction error (same variant, same message).
impl From<ZmapError> for ReduceError {
    fn from(e: ZmapError) -> Self {
        match e {
            ZmapError::Parse { line, message } => Self::Parse { line, message },
            ZmapError::Shape(m) => Self::Shape(m),
            ZmapError::NonFinite { row, col } => Self::NonFinite { row, col },
            ZmapError::Option(m) => Self::Option(m),
            ZmapError::Cancelled => Self::Cancelled,
        }
    }
}

/// How the number of kept singular values is chosen from the tolerance.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RankRule {
    /// Smallest r with σ_{r+1} ≤ tolerance: guarantees max |A − B_r| ≤ tolerance at the nodes.
    SpectralBound,
    /// The thesis's loop: r = the first k whose term has max |σ_k U_k V_kᵀ| < tolerance (that
    /// term included, as the thesis counts loop iterations).
    TermChange,
    /// A fixed rank (clamped to the number of singular values).
    Fixed(usize),
}

/// Resampling of the kept singular vectors for a ball end mill (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Resampling {
    /// Ball radius ρ, mm.
    pub tool_radius_mm: f64,
    /// Grid step γ of the Z-map, mm (rows and columns).
    pub grid_step_mm: f64,
}

/// Options of [`reduce`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ReduceOptions {
    /// Tolerance t, mm (> 0).
    pub tolerance_mm: f64,
    /// How the rank is chosen.
    pub rank_rule: RankRule,
    /// Resample the singular vectors (None: keep the grid size).
    pub resampling: Option<Resampling>,
}

/// The result of [`reduce`].
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Reduction {
    /// All singular values, descending.
    pub singular_values: Vec<f64>,
    /// Number of kept singular values r.
    pub rank: usize,
    /// σ_{r+1} (0 when every term is kept): the bound on the node error of the rank-r model.
    pub rank_error_bound: f64,
    /// Point spacing l used for resampling, mm (None without resampling).
    pub spacing_mm: Option<f64>,
    /// The reduced grid (reduced_rows × reduced_cols).
    pub reduced: Grid,
    /// Numbers stored by the reduced model: r·(m′ + n′ + 1).
    pub stored_numbers: usize,
    /// Max |Z − Z′| over the original nodes, Z′ interpolated bilinearly from the reduced grid.
    pub max_error: f64,
    /// Mean |Z − Z′| over the original nodes.
    pub mean_error: f64,
}

impl Reduction {
    /// The reduced model at the nodes of the original `rows`×`cols` grid: the reduced grid
    /// stretched over the same extent and interpolated bilinearly (the values the error report
    /// compares with the original).
    #[must_use]
    pub fn at_nodes(&self, rows: usize, cols: usize) -> Grid {
        let scale = |reduced: usize, original: usize| {
            if original > 1 {
                (reduced.saturating_sub(1)) as f64 / (original - 1) as f64
            } else {
                0.0
            }
        };
        let row_scale = scale(self.reduced.rows(), rows);
        let col_scale = scale(self.reduced.cols(), cols);
        Grid::from_fn(rows, cols, |r, c| {
            self.reduced
                .bilinear(r as f64 * row_scale, c as f64 * col_scale)
        })
    }
}

/// Point spacing for a ball of radius ρ at tolerance t: l = √(4ρt − t²), mm.
#[must_use]
pub fn point_spacing(tool_radius_mm: f64, tolerance_mm: f64) -> f64 {
    (4.0 * tool_radius_mm * tolerance_mm - tolerance_mm * tolerance_mm)
        .max(0.0)
        .sqrt()
}

/// Points of a vector of `n` points at step γ after resampling at spacing l:
/// ⌊(n − 1)γ/l⌋ + 1, at least 2 and at most `n`.
#[must_use]
pub fn resampled_count(n: usize, grid_step_mm: f64, spacing_mm: f64) -> usize {
    if n < 2 || !(spacing_mm > 0.0) {
        return n;
    }
    let k = (((n - 1) as f64) * grid_step_mm / spacing_mm).floor();
    if k.is_finite() {
        ((k as usize) + 1).clamp(2, n)
    } else {
        n
    }
}

/// Choose the rank for `tolerance` under `rule` (see [`RankRule`]).
#[must_use]
pub fn choose_rank(f: &SvdFactors, tolerance: f64, rule: RankRule) -> usize {
    let s = &f.singular_values;
    match rule {
        RankRule::Fixed(r) => r.min(s.len()),
        RankRule::SpectralBound => s.iter().position(|&v| v <= tolerance).unwrap_or(s.len()),
        RankRule::TermChange => (0..s.len())
            .find(|&k| f.term_max(k) < tolerance)
            .map_or(s.len(), |k| k + 1),
    }
}

/// Linear resampling of `v` at `n` equally spaced points over the same extent.
fn resample_linear(v: &[f64], n: usize) -> Vec<f64> {
    if n == v.len() || v.len() < 2 || n < 2 {
        return v.to_vec();
    }
    let scale = (v.len() - 1) as f64 / (n - 1) as f64;
    (0..n)
        .map(|i| {
            let x = i as f64 * scale;
            let i0 = (x.floor() as usize).min(v.len() - 2);
            let f = x - i0 as f64;
            let a = v.get(i0).copied().unwrap_or(0.0);
            let b = v.get(i0 + 1).copied().unwrap_or(a);
            a + f * (b - a)
        })
        .collect()
}

/// Reduce `z`: SVD, rank from the tolerance, resampling, reconstruction and error.
///
/// # Errors
/// [`ReduceError::Option`] for a non-positive tolerance, tool radius or grid step;
/// [`ReduceError::Svd`] when the decomposition fails.
pub fn reduce(z: &Grid, opts: &ReduceOptions) -> Result<Reduction, ReduceError> {
    if !(opts.tolerance_mm > 0.0 && opts.tolerance_mm.is_finite()) {
        return Err(ReduceError::Option(format!(
            "tolerance must be a positive length in mm, got {}",
            opts.tolerance_mm
        )));
    }
    let (m, n) = (z.rows(), z.cols());
    let mut spacing = None;
    let (m2, n2) = match opts.resampling {
        None => (m, n),
        Some(rs) => {
            for (what, v) in [
                ("tool radius", rs.tool_radius_mm),
                ("grid step", rs.grid_step_mm),
            ] {
                if !(v > 0.0 && v.is_finite()) {
                    return Err(ReduceError::Option(format!(
                        "{what} must be a positive length in mm, got {v}"
                    )));
                }
            }
            let l = point_spacing(rs.tool_radius_mm, opts.tolerance_mm);
            spacing = Some(l);
            (
                resampled_count(m, rs.grid_step_mm, l),
                resampled_count(n, rs.grid_step_mm, l),
            )
        }
    };
    let f = svd(z)?;
    let rank = choose_rank(&f, opts.tolerance_mm, opts.rank_rule);
    Ok(rebuild(z, &f, rank, m2, n2, spacing))
}

/// Reduce `z` to exactly `rows`×`cols` nodes (each kept singular vector linearly resampled
/// to that count over the same extent), as the thesis's Sec. 6.4/6.7 examples do (20 → 16).
///
/// # Errors
/// [`ReduceError::Option`] for a non-positive tolerance or a target size of 0, or larger than
/// the grid; [`ReduceError::Svd`] when the decomposition fails.
pub fn reduce_to_size(
    z: &Grid,
    tolerance_mm: f64,
    rank_rule: RankRule,
    rows: usize,
    cols: usize,
) -> Result<Reduction, ReduceError> {
    if !(tolerance_mm > 0.0 && tolerance_mm.is_finite()) {
        return Err(ReduceError::Option(format!(
            "tolerance must be a positive length in mm, got {tolerance_mm}"
        )));
    }
    if rows == 0 || cols == 0 || rows > z.rows() || cols > z.cols() {
        return Err(ReduceError::Option(format!(
            "target size {rows}×{cols} must be between 1×1 and the grid's {}×{}",
            z.rows(),
            z.cols()
        )));
    }
    let f = svd(z)?;
    let rank = choose_rank(&f, tolerance_mm, rank_rule);
    Ok(rebuild(z, &f, rank, rows, cols, None))
}

/// Multiply back the first `rank` terms with vectors resampled to `m2`×`n2`, and measure the
/// error at the original nodes.
fn rebuild(
    z: &Grid,
    f: &SvdFactors,
    rank: usize,
    m2: usize,
    n2: usize,
    spacing: Option<f64>,
) -> Reduction {
    let (m, n) = (z.rows(), z.cols());
    let us: Vec<Vec<f64>> = (0..rank).map(|k| resample_linear(f.u(k), m2)).collect();
    let vs: Vec<Vec<f64>> = (0..rank).map(|k| resample_linear(f.v(k), n2)).collect();
    let s = &f.singular_values;
    let reduced = Grid::from_fn(m2, n2, |r, c| {
        (0..rank)
            .map(|k| {
                s.get(k).copied().unwrap_or(0.0)
                    * us.get(k).and_then(|u| u.get(r)).copied().unwrap_or(0.0)
                    * vs.get(k).and_then(|v| v.get(c)).copied().unwrap_or(0.0)
            })
            .sum()
    });
    let mut out = Reduction {
        rank_error_bound: s.get(rank).copied().unwrap_or(0.0),
        singular_values: s.clone(),
        rank,
        spacing_mm: spacing,
        stored_numbers: rank * (m2 + n2 + 1),
        reduced,
        max_error: 0.0,
        mean_error: 0.0,
    };
    let approx = out.at_nodes(m, n);
    let (mut max_error, mut sum) = (0.0_f64, 0.0);
    for (a, b) in z.values().iter().zip(approx.values()) {
        let e = (a - b).abs();
        max_error = max_error.max(e);
        sum += e;
    }
    out.max_error = max_error;
    out.mean_error = sum / (m * n) as f64;
    out
}
