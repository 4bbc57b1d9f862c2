//! A Z-map as a dense matrix of heights: one grid row a line, row index ↔ y, column index ↔ x
//! (the thesis's orientation), row-major storage.

use super::error::ZmapError;

/// A regular grid of heights (mm), row-major.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Grid {
    rows: usize,
    cols: usize,
    values: Vec<f64>,
}

impl Grid {
    /// A grid from row-major values.
    ///
    /// # Errors
    /// [`ZmapError::Shape`] when `values.len() != rows·cols` or the grid is empty,
    /// [`ZmapError::NonFinite`] for a NaN or infinite value.
    pub fn new(rows: usize, cols: usize, values: Vec<f64>) -> Result<Self, ZmapError> {
        if rows == 0 || cols == 0 || rows.checked_mul(cols) != Some(values.len()) {
            return Err(ZmapError::Shape(format!(
                "{} values do not make a {rows}×{cols} grid",
                values.len()
            )));
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(ZmapError::NonFinite {
                row: i / cols + 1,
                col: i % cols + 1,
            });
        }
        Ok(Self { rows, cols, values })
    }

    /// A grid with `f(row, col)` at every node (values are not checked).
    pub(crate) fn from_fn(rows: usize, cols: usize, f: impl Fn(usize, usize) -> f64) -> Self {
        let mut values = Vec::with_capacity(rows * cols);
        for r in 0..rows {
            for c in 0..cols {
                values.push(f(r, c));
            }
        }
        Self { rows, cols, values }
    }

    /// Parse CSV text: one grid row a line, values separated by commas (or blanks), no header;
    /// blank lines are skipped.
    ///
    /// # Errors
    /// [`ZmapError::Parse`] naming the 1-based line for a value that is not a finite number or a
    /// row of a different length; [`ZmapError::Shape`] for a file without values.
    pub fn parse_csv(text: &str) -> Result<Self, ZmapError> {
        let mut values = Vec::new();
        let mut cols = 0;
        let mut rows = 0;
        for (i, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() {
                continue;
            }
            let mut n = 0;
            for field in line
                .split(|ch: char| ch == ',' || ch == ';' || ch.is_whitespace())
                .filter(|f| !f.is_empty())
            {
                let v: f64 = field.parse().map_err(|_| ZmapError::Parse {
                    line: i + 1,
                    message: format!("'{field}' is not a number"),
                })?;
                if !v.is_finite() {
                    return Err(ZmapError::Parse {
                        line: i + 1,
                        message: format!("'{field}' is not a finite number"),
                    });
                }
                values.push(v);
                n += 1;
            }
            if rows == 0 {
                cols = n;
            } else if n != cols {
                return Err(ZmapError::Parse {
                    line: i + 1,
                    message: format!("row has {n} values, the first row has {cols}"),
                });
            }
            rows += 1;
        }
        Self::new(rows, cols, values)
    }

    /// Number of rows (grid points along y).
    #[must_use]
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns (grid points along x).
    #[must_use]
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The value at (`row`, `col`); `None` outside the grid.
    #[must_use]
    pub fn get(&self, row: usize, col: usize) -> Option<f64> {
        if row < self.rows && col < self.cols {
            self.values.get(row * self.cols + col).copied()
        } else {
            None
        }
    }

    /// All values, row-major.
    #[must_use]
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Bilinear interpolation at fractional indices (`row`, `col`), clamped to the grid.
    #[must_use]
    pub fn bilinear(&self, row: f64, col: f64) -> f64 {
        let r = row.clamp(0.0, (self.rows - 1) as f64);
        let c = col.clamp(0.0, (self.cols - 1) as f64);
        let r0 = (r.floor() as usize).min(self.rows.saturating_sub(2));
        let c0 = (c.floor() as usize).min(self.cols.saturating_sub(2));
        let r1 = (r0 + 1).min(self.rows - 1);
        let c1 = (c0 + 1).min(self.cols - 1);
        let fr = r - r0 as f64;
        let fc = c - c0 as f64;
        let at = |rr, cc| self.get(rr, cc).unwrap_or(0.0);
        (1.0 - fr) * ((1.0 - fc) * at(r0, c0) + fc * at(r0, c1))
            + fr * ((1.0 - fc) * at(r1, c0) + fc * at(r1, c1))
    }
}
