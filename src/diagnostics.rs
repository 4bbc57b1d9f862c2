//! Diagnostics and long-running-work plumbing shared by every engine module: warnings that travel
//! with results (never printed by the engine), and a progress/cancel handle that workers poll.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// How serious a diagnostic is.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    /// Informational.
    Info,
    /// Something was skipped, repaired or approximated; the result is usable.
    Warning,
    /// Something could not be done; the result is incomplete.
    Error,
}

/// One message about a result, with the place it refers to (e.g. `#123`, `line 40`, `facet 7`).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Diagnostic {
    /// Severity.
    pub severity: Severity,
    /// Where in the input (entity id, line, byte offset, face index), if known.
    pub place: Option<String>,
    /// What happened, one sentence.
    pub message: String,
}

impl Diagnostic {
    /// A warning at a place.
    #[must_use]
    pub fn warning(place: impl Into<Option<String>>, message: impl Into<String>) -> Self {
        Self {
            severity: Severity::Warning,
            place: place.into(),
            message: message.into(),
        }
    }

    /// An informational note at a place.
    #[must_use]
    pub fn info(place: impl Into<Option<String>>, message: impl Into<String>) -> Self {
        Self {
            severity: Severity::Info,
            place: place.into(),
            message: message.into(),
        }
    }

    /// An error at a place (the result is incomplete).
    #[must_use]
    pub fn error(place: impl Into<Option<String>>, message: impl Into<String>) -> Self {
        Self {
            severity: Severity::Error,
            place: place.into(),
            message: message.into(),
        }
    }
}

impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let sev = match self.severity {
            Severity::Info => "info",
            Severity::Warning => "warning",
            Severity::Error => "error",
        };
        match &self.place {
            Some(p) => write!(f, "{sev}: {p}: {}", self.message),
            None => write!(f, "{sev}: {}", self.message),
        }
    }
}

/// Progress and cancellation shared between a worker and whoever watches it (the UI thread).
///
/// Cloning shares the same state. Workers call [`Progress::set`] and check
/// [`Progress::is_cancelled`] at convenient points; the UI reads [`Progress::fraction`] and may
/// call [`Progress::cancel`].
#[derive(Clone, Debug, Default)]
pub struct Progress {
    inner: Arc<ProgressInner>,
}

#[derive(Debug, Default)]
struct ProgressInner {
    cancelled: AtomicBool,
    /// Fraction done in [0, 1], stored as f64 bits.
    fraction_bits: AtomicU64,
}

/// Returned by work that noticed a cancel request.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("cancelled")]
pub struct Cancelled;

impl Progress {
    /// A fresh handle: nothing done, not cancelled.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Ask the worker to stop.
    pub fn cancel(&self) {
        self.inner.cancelled.store(true, Ordering::Relaxed);
    }

    /// Has someone asked the worker to stop?
    #[must_use]
    pub fn is_cancelled(&self) -> bool {
        self.inner.cancelled.load(Ordering::Relaxed)
    }

    /// `Err(Cancelled)` when cancelled, for `?` in workers.
    ///
    /// # Errors
    /// [`Cancelled`] when [`Progress::cancel`] was called.
    pub fn check(&self) -> Result<(), Cancelled> {
        if self.is_cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }

    /// Record the fraction done (clamped to [0, 1]; NaN counts as 0).
    pub fn set(&self, fraction: f64) {
        let f = if fraction.is_nan() {
            0.0
        } else {
            fraction.clamp(0.0, 1.0)
        };
        self.inner
            .fraction_bits
            .store(f.to_bits(), Ordering::Relaxed);
    }

    /// The fraction done, in [0, 1].
    #[must_use]
    pub fn fraction(&self) -> f64 {
        f64::from_bits(self.inner.fraction_bits.load(Ordering::Relaxed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_is_shared_and_clamped() {
        let p = Progress::new();
        let q = p.clone();
        q.set(1.5);
        assert!((p.fraction() - 1.0).abs() < f64::EPSILON);
        q.set(f64::NAN);
        assert!(p.fraction().abs() < f64::EPSILON);
        assert!(p.check().is_ok());
        q.cancel();
        assert_eq!(p.check(), Err(Cancelled));
    }

    #[test]
    fn diagnostic_display_names_place() {
        let d = Diagnostic::warning(Some("#12".to_string()), "face skipped");
        assert_eq!(d.to_string(), "warning: #12: face skipped");
        let e = Diagnostic::error(None, "bad");
        assert_eq!(e.to_string(), "error: bad");
        assert_eq!(Diagnostic::info(None, "x").severity, Severity::Info);
    }
}
