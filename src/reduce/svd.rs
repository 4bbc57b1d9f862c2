//! The thin SVD of a grid (faer), kept as plain vectors.

use super::ReduceError;
use crate::geometry::zmap::Grid;

/// Thin SVD A = U S Vᵀ of an m×n grid, k = min(m, n) terms.
#[derive(Clone, Debug, PartialEq)]
pub struct SvdFactors {
    /// σ_1 ≥ σ_2 ≥ … ≥ σ_k ≥ 0.
    pub singular_values: Vec<f64>,
    /// Left singular vectors U_k (each of length m).
    u: Vec<Vec<f64>>,
    /// Right singular vectors V_k (each of length n).
    v: Vec<Vec<f64>>,
}

impl SvdFactors {
    /// The k-th left singular vector (0-based); empty past the last.
    #[must_use]
    pub fn u(&self, k: usize) -> &[f64] {
        self.u.get(k).map_or(&[], Vec::as_slice)
    }

    /// The k-th right singular vector (0-based); empty past the last.
    #[must_use]
    pub fn v(&self, k: usize) -> &[f64] {
        self.v.get(k).map_or(&[], Vec::as_slice)
    }

    /// max |σ_k U_k V_kᵀ| = σ_k · max|U_k| · max|V_k|: how much term k (0-based) changes the model.
    #[must_use]
    pub fn term_max(&self, k: usize) -> f64 {
        let amax = |x: &[f64]| x.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
        self.singular_values.get(k).copied().unwrap_or(0.0) * amax(self.u(k)) * amax(self.v(k))
    }
}

/// The thin SVD of `z` (faer's divide-and-conquer SVD).
///
/// # Errors
/// [`ReduceError::Svd`] when faer reports no convergence.
pub fn svd(z: &Grid) -> Result<SvdFactors, ReduceError> {
    let (m, n) = (z.rows(), z.cols());
    let a = faer::Mat::<f64>::from_fn(m, n, |r, c| z.get(r, c).unwrap_or(0.0));
    let d = a
        .thin_svd()
        .map_err(|e| ReduceError::Svd(format!("{e:?}")))?;
    let k = m.min(n);
    let s = d.S().column_vector();
    let (u, v) = (d.U(), d.V());
    let singular_values = (0..k).map(|i| s[i]).collect();
    let u = (0..k)
        .map(|j| (0..m).map(|i| u[(i, j)]).collect())
        .collect();
    let v = (0..k)
        .map(|j| (0..n).map(|i| v[(i, j)]).collect())
        .collect();
    Ok(SvdFactors {
        singular_values,
        u,
        v,
    })
}
