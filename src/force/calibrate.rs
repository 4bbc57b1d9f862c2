//! Calibration of the force coefficients from measured mean forces.
//!
//! - [`calibrate_linear`]: the classic mean-force calibration. The mean force per revolution
//!   is linear in the six coefficients of the linear edge-force model (Eq. 5.26), so the tests
//!   (several feeds per tooth, any immersion) give an overdetermined linear system, solved by
//!   least squares with `nalgebra`'s SVD. Each equation is divided by its measured force, so
//!   the fit minimises relative errors, the measure the thesis reports. Without `fz_n` the
//!   axial coefficients are not determined and are set to 0.
//! - [`calibrate_exponential`]: nonlinear least squares (`levenberg-marquardt`) of
//!   `K_t = K_T·h_a^(−p)`, `K_r = K_R·h_a^(−q)` (and K_a when F_z is measured) to the same
//!   mean forces, started from per-test inversions and a log–log regression (Eq. 5.5).
//! - [`distribution`]: the thesis's cutting-force-distribution method.

pub mod distribution;

use nalgebra::{DMatrix, DVector, Dyn, Owned};

use super::closed_form::mean_load;
use super::coefficients::{ExponentialCoefficients, PowerLaw};
use super::cut::DEFAULT_DISK_HEIGHT;
use super::measurements::Measurement;
use super::{Coefficients, Force, ForceError, LinearCoefficients};

/// How one test is reproduced by the calibrated coefficients.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RowFit {
    /// Line of the test in FORCES.csv.
    pub line: usize,
    /// Measured mean force, N (fz 0 when not measured).
    pub measured: Force,
    /// Predicted mean force, N.
    pub predicted: Force,
    /// |predicted − measured| / |measured| for x and y, %.
    pub error_pct: [f64; 2],
}

/// A calibration result.
#[derive(Clone, Debug, PartialEq)]
pub struct Calibration {
    /// The coefficients.
    pub coefficients: Coefficients,
    /// Each test reproduced.
    pub rows: Vec<RowFit>,
    /// Mean of the x and y errors over the tests, %.
    pub mean_error_pct: [f64; 2],
    /// Remarks (coefficients not determined, ...).
    pub notes: Vec<String>,
}

/// The mean force of each test for each unit coefficient (K_tc, K_rc, K_ac, K_te, K_re, K_ae):
/// `columns[i][c]` is test i's mean force with only coefficient c equal to 1.
fn unit_columns(rows: &[Measurement]) -> Result<Vec<[Force; 6]>, ForceError> {
    rows.iter()
        .map(|m| {
            let mill = m.mill()?;
            let engagement = m
                .cut()
                .engagement(&mill, DEFAULT_DISK_HEIGHT)
                .map_err(|e| ForceError::Input(format!("line {}: {e}", m.line)))?;
            let mut cols = [Force::default(); 6];
            for (c, col) in cols.iter_mut().enumerate() {
                let mut unit = [0.0; 6];
                unit[c] = 1.0;
                let k = Coefficients::Linear(LinearCoefficients::from_array(unit));
                *col = mean_load(&mill, &k, &engagement).force;
            }
            Ok(cols)
        })
        .collect()
}

/// Scale of an equation: its measured force (at least 1 N).
fn scale(f: f64) -> f64 {
    f.abs().max(1.0)
}

fn check_rows(rows: &[Measurement]) -> Result<bool, ForceError> {
    if rows.is_empty() {
        return Err(ForceError::Calibration("no measurements".into()));
    }
    Ok(rows.iter().any(|m| m.fz.is_some()))
}

fn row_fits(rows: &[Measurement], predict: impl Fn(usize) -> Force) -> (Vec<RowFit>, [f64; 2]) {
    let mut fits = Vec::with_capacity(rows.len());
    let mut sum = [0.0; 2];
    for (i, m) in rows.iter().enumerate() {
        let p = predict(i);
        let err = [
            100.0 * (p.fx - m.fx).abs() / scale(m.fx),
            100.0 * (p.fy - m.fy).abs() / scale(m.fy),
        ];
        sum[0] += err[0];
        sum[1] += err[1];
        fits.push(RowFit {
            line: m.line,
            measured: Force {
                fx: m.fx,
                fy: m.fy,
                fz: m.fz.unwrap_or(0.0),
            },
            predicted: p,
            error_pct: err,
        });
    }
    let n = rows.len() as f64;
    (fits, [sum[0] / n, sum[1] / n])
}

/// Linear least squares `A x ≈ b` by SVD; `Err` when A is rank deficient.
fn solve(a: DMatrix<f64>, b: DVector<f64>, what: &str) -> Result<DVector<f64>, ForceError> {
    if a.nrows() < a.ncols() {
        return Err(ForceError::Calibration(format!(
            "{} equations cannot determine the {} {what} (use at least two feeds per tooth)",
            a.nrows(),
            a.ncols()
        )));
    }
    let svd = a.svd(true, true);
    let smax = svd.singular_values.max();
    let smin = svd.singular_values.min();
    if !(smax > 0.0) || smin < 1e-10 * smax {
        return Err(ForceError::Calibration(format!(
            "the measurements do not determine the {what} (use at least two feeds per tooth, \
             or up and down milling)"
        )));
    }
    svd.solve(&b, 0.0)
        .map_err(|e| ForceError::Calibration(format!("least squares failed: {e}")))
}

/// The classic mean-force calibration of the linear edge-force model.
///
/// # Errors
/// [`ForceError::Calibration`] when the tests do not determine the coefficients;
/// [`ForceError::Input`] for a test whose cut is invalid.
pub fn calibrate_linear(rows: &[Measurement]) -> Result<Calibration, ForceError> {
    let axial = check_rows(rows)?;
    let cols = unit_columns(rows)?;
    // Unknowns: K_tc, K_rc, K_te, K_re (and K_ac, K_ae with F_z).
    let unknowns: &[usize] = if axial {
        &[0, 1, 3, 4, 2, 5]
    } else {
        &[0, 1, 3, 4]
    };
    let mut a_rows: Vec<Vec<f64>> = Vec::new();
    let mut b = Vec::new();
    for (m, col) in rows.iter().zip(&cols) {
        let mut push = |pick: fn(&Force) -> f64, meas: f64| {
            let s = scale(meas);
            a_rows.push(unknowns.iter().map(|&c| pick(&col[c]) / s).collect());
            b.push(meas / s);
        };
        push(|f| f.fx, m.fx);
        push(|f| f.fy, m.fy);
        if let Some(fz) = m.fz {
            push(|f| f.fz, fz);
        }
    }
    let a = DMatrix::from_fn(a_rows.len(), unknowns.len(), |i, j| a_rows[i][j]);
    let x = solve(a, DVector::from_vec(b), "linear-model coefficients")?;
    let mut k = [0.0; 6];
    for (i, &c) in unknowns.iter().enumerate() {
        k[c] = x[i];
    }
    let lin = LinearCoefficients::from_array(k);
    let (fits, mean) = row_fits(rows, |i| {
        let mut f = Force::default();
        for (c, kc) in k.iter().enumerate() {
            f.fx += kc * cols[i][c].fx;
            f.fy += kc * cols[i][c].fy;
            f.fz += kc * cols[i][c].fz;
        }
        f
    });
    let mut notes = Vec::new();
    if !axial {
        notes.push("no fz_n measured: K_ac and K_ae are not determined and set to 0".into());
    }
    Ok(Calibration {
        coefficients: Coefficients::Linear(lin),
        rows: fits,
        mean_error_pct: mean,
        notes,
    })
}

/// The exponential model's least-squares problem: parameters
/// `[ln K_T, p, K_R, q (, K_A, s)]`, residuals the relative mean-force errors.
struct ExpProblem {
    /// Per test: ln h_a, unit columns for (K_tc, K_rc, K_ac), measured (fx, fy, fz?).
    tests: Vec<(f64, [Force; 3], [Option<f64>; 3])>,
    axial: bool,
    x: DVector<f64>,
}

impl ExpProblem {
    fn laws(&self, x: &DVector<f64>) -> [PowerLaw; 3] {
        let ka = if self.axial {
            PowerLaw { k: x[4], p: x[5] }
        } else {
            PowerLaw::constant(0.0)
        };
        [
            PowerLaw {
                k: x[0].exp(),
                p: x[1],
            },
            PowerLaw { k: x[2], p: x[3] },
            ka,
        ]
    }

    fn components(f: &Force) -> [f64; 3] {
        [f.fx, f.fy, f.fz]
    }

    /// Residuals and, when asked, the Jacobian.
    fn eval(&self, jac: bool) -> (DVector<f64>, DMatrix<f64>) {
        let [lt, lr, la] = self.laws(&self.x);
        let n = self.x.len();
        let mut r = Vec::new();
        let mut j: Vec<Vec<f64>> = Vec::new();
        for (lnh, cols, meas) in &self.tests {
            let h = lnh.exp();
            let (kt, kr, ka) = (lt.at(h), lr.at(h), la.at(h));
            let [ct, cr, ca] = cols.map(|c| Self::components(&c));
            for (q, m) in meas.iter().enumerate() {
                let Some(m) = *m else { continue };
                let s = scale(m);
                let pred = kt * (ct[q] + kr * cr[q] + ka * ca[q]);
                r.push((pred - m) / s);
                if jac {
                    let mut row = vec![0.0; n];
                    row[0] = pred / s;
                    row[1] = -lnh * pred / s;
                    row[2] = kt * h.powf(-lr.p) * cr[q] / s;
                    row[3] = -lnh * kt * kr * cr[q] / s;
                    if self.axial {
                        row[4] = kt * h.powf(-la.p) * ca[q] / s;
                        row[5] = -lnh * kt * ka * ca[q] / s;
                    }
                    j.push(row);
                }
            }
        }
        let m = DMatrix::from_fn(j.len(), n, |a, b| j[a][b]);
        (DVector::from_vec(r), m)
    }
}

impl levenberg_marquardt::LeastSquaresProblem<f64, Dyn, Dyn> for ExpProblem {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        self.x.copy_from(x);
    }

    fn params(&self) -> DVector<f64> {
        self.x.clone()
    }

    fn residuals(&self) -> Option<DVector<f64>> {
        let r = self.eval(false).0;
        r.iter().all(|v| v.is_finite()).then_some(r)
    }

    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let j = self.eval(true).1;
        j.iter().all(|v| v.is_finite()).then_some(j)
    }
}

/// Start values: per test, the exponential model's (K_t, K_r, K_a) fitted to that test alone;
/// then ln K_t regressed on ln h_a, and K_r, K_a taken as constants.
fn initial_guess(problem: &ExpProblem) -> Result<DVector<f64>, ForceError> {
    let mut pts = Vec::new();
    let (mut kr_sum, mut ka_sum, mut n_a) = (0.0, 0.0, 0usize);
    for (lnh, cols, meas) in &problem.tests {
        let comps = cols.map(|c| ExpProblem::components(&c));
        let used: Vec<usize> = (0..3).filter(|&q| meas[q].is_some()).collect();
        let vars = if problem.axial && meas[2].is_some() {
            3
        } else {
            2
        };
        let a = DMatrix::from_fn(used.len(), vars, |i, j| comps[j][used[i]]);
        let b = DVector::from_fn(used.len(), |i, _| meas[used[i]].unwrap_or(0.0));
        let Ok(x) = solve(a, b, "exponential start values") else {
            continue;
        };
        if x[0] > 0.0 {
            pts.push((*lnh, x[0].ln()));
            kr_sum += x[1] / x[0];
            if vars == 3 {
                ka_sum += x[2] / x[0];
                n_a += 1;
            }
        }
    }
    if pts.len() < 2 {
        return Err(ForceError::Calibration(
            "the exponential model needs at least two tests with a positive tangential force"
                .into(),
        ));
    }
    let n = pts.len() as f64;
    let (mx, my) = (
        pts.iter().map(|p| p.0).sum::<f64>() / n,
        pts.iter().map(|p| p.1).sum::<f64>() / n,
    );
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    if sxx < 1e-12 {
        return Err(ForceError::Calibration(
            "the exponential model needs tests at two or more mean chip thicknesses (feeds)".into(),
        ));
    }
    let slope = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>() / sxx;
    let mut x = vec![my - slope * mx, -slope, kr_sum / n, 0.0];
    if problem.axial {
        x.extend([if n_a > 0 { ka_sum / n_a as f64 } else { 0.0 }, 0.0]);
    }
    Ok(DVector::from_vec(x))
}

/// Nonlinear least squares of the exponential model to the mean forces.
///
/// # Errors
/// [`ForceError::Calibration`] when the tests do not determine the power laws or the solver
/// does not converge; [`ForceError::Input`] for an invalid test.
pub fn calibrate_exponential(rows: &[Measurement]) -> Result<Calibration, ForceError> {
    let axial = check_rows(rows)?;
    let cols = unit_columns(rows)?;
    let mut tests = Vec::new();
    for (m, c) in rows.iter().zip(&cols) {
        let mill = m.mill()?;
        let arcs = m.cut().arcs_at(mill.radius, mill.radius);
        let h_a = m.ft * arcs.mean_sin();
        if !(h_a > 0.0) {
            return Err(ForceError::Calibration(format!(
                "line {}: the cut has no chip (mean chip thickness 0)",
                m.line
            )));
        }
        tests.push((h_a.ln(), [c[0], c[1], c[2]], [Some(m.fx), Some(m.fy), m.fz]));
    }
    let mut problem = ExpProblem {
        tests,
        axial,
        x: DVector::zeros(if axial { 6 } else { 4 }),
    };
    problem.x = initial_guess(&problem)?;
    let (problem, report) = levenberg_marquardt::LevenbergMarquardt::new()
        .with_patience(500)
        .minimize(problem);
    if !report.termination.was_successful() || !problem.x.iter().all(|v| v.is_finite()) {
        return Err(ForceError::Calibration(format!(
            "the exponential fit did not converge ({:?})",
            report.termination
        )));
    }
    let [kt, kr, ka] = problem.laws(&problem.x);
    let coefficients = Coefficients::Exponential(ExponentialCoefficients { kt, kr, ka });
    let (fits, mean) = row_fits(rows, |i| {
        let (lnh, c, _) = &problem.tests[i];
        let k = coefficients.at_mean_chip(lnh.exp());
        let mut f = Force::default();
        for (col, kc) in c.iter().zip([k.ktc, k.krc, k.kac]) {
            f.fx += kc * col.fx;
            f.fy += kc * col.fy;
            f.fz += kc * col.fz;
        }
        f
    });
    let mut notes = Vec::new();
    if !axial {
        notes.push("no fz_n measured: K_a is not determined and set to 0".into());
    }
    Ok(Calibration {
        coefficients,
        rows: fits,
        mean_error_pct: mean,
        notes,
    })
}
