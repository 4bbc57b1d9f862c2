//! The curves of the motion plots: quantities, horizontal axes, decimated curves per axis.

use crate::feed::AxisLimit;
use egui_plot::PlotPoint;

/// The quantity shown.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Path speed (feed), mm/s.
    Feed,
    /// Axis velocities.
    Velocity,
    /// Axis accelerations.
    Acceleration,
    /// Axis jerks.
    Jerk,
}

impl Quantity {
    /// All quantities, in tab order.
    pub const ALL: [Self; 4] = [Self::Feed, Self::Velocity, Self::Acceleration, Self::Jerk];

    /// The tab label.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Feed => "Feed",
            Self::Velocity => "Velocity",
            Self::Acceleration => "Acceleration",
            Self::Jerk => "Jerk",
        }
    }

    /// The unit for a linear (`mm`) or rotary (`deg`) axis.
    #[must_use]
    pub fn unit(self, rotary: bool) -> String {
        let base = if rotary { "deg" } else { "mm" };
        match self {
            Self::Feed | Self::Velocity => format!("{base}/s"),
            Self::Acceleration => format!("{base}/s²"),
            Self::Jerk => format!("{base}/s³"),
        }
    }
}

/// What the horizontal axis shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum XAxis {
    /// Time from the program start, s.
    Time,
    /// Path length from the program start (sum of block lengths), mm.
    PathLength,
}

impl XAxis {
    /// The axis label with its unit.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::Time => "time (s)",
            Self::PathLength => "path length (mm)",
        }
    }
}

/// One decimated curve, against time and against path length (the same points).
#[derive(Clone, Debug, Default)]
pub struct Curve {
    /// Points (t, value).
    pub by_time: Vec<PlotPoint>,
    /// Points (path position, value).
    pub by_path: Vec<PlotPoint>,
}

impl Curve {
    pub(super) fn from_tagged(points: Vec<[f64; 3]>) -> Self {
        Self {
            by_time: points.iter().map(|p| PlotPoint::new(p[0], p[1])).collect(),
            by_path: points.iter().map(|p| PlotPoint::new(p[2], p[1])).collect(),
        }
    }

    /// The points against `x`.
    #[must_use]
    pub fn points(&self, x: XAxis) -> &[PlotPoint] {
        match x {
            XAxis::Time => &self.by_time,
            XAxis::PathLength => &self.by_path,
        }
    }

    /// The largest |value| (the decimation keeps it).
    #[must_use]
    pub fn peak(&self) -> f64 {
        self.by_time.iter().fold(0.0, |m, p| m.max(p.y.abs()))
    }
}

/// Maps `x` through a monotone table: finds `x` among `from[i].x` and interpolates linearly
/// between the matching `to[i].x` (clamped at the ends). Time ↔ path length conversions.
#[must_use]
pub fn interpolate_x(from: &[PlotPoint], to: &[PlotPoint], x: f64) -> f64 {
    let n = from.len().min(to.len());
    let (Some(first), Some(last)) = (from.first(), from.get(n.wrapping_sub(1))) else {
        return x;
    };
    let tx = |i: usize| to.get(i).map_or(x, |p| p.x);
    if x <= first.x {
        return tx(0);
    }
    if x >= last.x {
        return tx(n - 1);
    }
    let i = from[..n].partition_point(|p| p.x <= x).clamp(1, n - 1);
    let (a, b) = (&from[i - 1], &from[i]);
    let f = if b.x > a.x {
        (x - a.x) / (b.x - a.x)
    } else {
        0.0
    };
    tx(i - 1) + f * (tx(i) - tx(i - 1))
}

/// The decimated curves of one axis, in display units (mm or deg).
#[derive(Clone, Debug)]
pub struct AxisCurves {
    /// Axis letter.
    pub axis: char,
    /// A rotary axis (values in degrees).
    pub rotary: bool,
    /// The machine's limits, display units.
    pub limit: AxisLimit,
    /// Velocity.
    pub velocity: Curve,
    /// Acceleration.
    pub acceleration: Curve,
    /// Jerk.
    pub jerk: Curve,
}

impl AxisCurves {
    /// The curve of a quantity (`Feed` has none per axis).
    #[must_use]
    pub fn curve(&self, q: Quantity) -> Option<&Curve> {
        match q {
            Quantity::Feed => None,
            Quantity::Velocity => Some(&self.velocity),
            Quantity::Acceleration => Some(&self.acceleration),
            Quantity::Jerk => Some(&self.jerk),
        }
    }

    /// The largest |value| of a quantity's curve (display units; the decimation keeps it).
    #[must_use]
    pub fn peak_of(&self, q: Quantity) -> f64 {
        self.curve(q).map_or(0.0, Curve::peak)
    }

    /// The limit of a quantity (display units).
    #[must_use]
    pub fn limit_of(&self, q: Quantity) -> Option<f64> {
        match q {
            Quantity::Feed => None,
            Quantity::Velocity => Some(self.limit.velocity),
            Quantity::Acceleration => Some(self.limit.acceleration),
            Quantity::Jerk => Some(self.limit.jerk),
        }
    }
}
