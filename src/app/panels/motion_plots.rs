//! Motion plots of a planned program ([`TimedPath`]): path speed, and every axis's velocity,
//! acceleration and jerk against time, with the machine limits as dashed lines, a cursor at
//! the playback time, and the cycle time next to the naive length/feed estimate.
//!
//! The samples are read once at construction and decimated (min/max per bucket, at most
//! [`MAX_POINTS`] points a curve), so drawing costs the same for a one-second and a one-hour
//! program and no peak disappears.

mod decimation;

pub use decimation::MinMaxDecimator;

use crate::feed::path::slot_of;
use crate::feed::{AxisLimit, TimedPath, naive_time_s};
use egui::Color32;
use egui_plot::{HLine, Legend, Line, LineStyle, Plot, PlotPoint, VLine};

/// Largest number of points kept per curve.
pub const MAX_POINTS: usize = 20_000;

/// What the user did in the plots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlotEvent {
    /// The user clicked a plot at this time (s), clamped to the program.
    TimeClicked(f64),
}

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

/// The decimated curves of one axis, in display units (mm or deg).
#[derive(Clone, Debug)]
pub struct AxisCurves {
    /// Axis letter.
    pub axis: char,
    /// A rotary axis (values in degrees).
    pub rotary: bool,
    /// The machine's limits, display units.
    pub limit: AxisLimit,
    /// Velocity against time.
    pub velocity: Vec<PlotPoint>,
    /// Acceleration against time.
    pub acceleration: Vec<PlotPoint>,
    /// Jerk against time.
    pub jerk: Vec<PlotPoint>,
}

impl AxisCurves {
    /// The curve of a quantity (`Feed` has none per axis).
    #[must_use]
    pub fn curve(&self, q: Quantity) -> &[PlotPoint] {
        match q {
            Quantity::Feed => &[],
            Quantity::Velocity => &self.velocity,
            Quantity::Acceleration => &self.acceleration,
            Quantity::Jerk => &self.jerk,
        }
    }

    /// The largest |value| of a quantity's curve (display units; the decimation keeps it).
    #[must_use]
    pub fn peak_of(&self, q: Quantity) -> f64 {
        self.curve(q).iter().fold(0.0, |m, p| m.max(p.y.abs()))
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

/// State of the motion plots.
#[derive(Clone, Debug)]
pub struct MotionPlots {
    /// Path speed against time, mm/s.
    pub feed: Vec<PlotPoint>,
    /// The axes, machine order.
    pub axes: Vec<AxisCurves>,
    /// Planned cycle time, s.
    pub cycle_time_s: f64,
    /// The program at its programmed feeds ([`naive_time_s`]), s.
    pub naive_time_s: f64,
    /// Samples read from the plan.
    pub sample_count: usize,
    quantity: Quantity,
    cursor_s: Option<f64>,
    /// Draw every limit line, also those far above the curve (they squash it).
    all_limits: bool,
}

impl MotionPlots {
    /// Read the plan's samples (at its sample period) once and decimate them.
    #[must_use]
    pub fn new(timed: &TimedPath) -> Self {
        let t1 = timed.cycle_time_s;
        let dec = || MinMaxDecimator::new(0.0, t1, MAX_POINTS);
        let mut feed = dec();
        let slots: Vec<(usize, f64)> = timed
            .axes
            .iter()
            .map(|(c, _)| {
                let slot = slot_of(*c).unwrap_or(usize::MAX);
                (
                    slot,
                    if slot >= 3 {
                        180.0 / std::f64::consts::PI
                    } else {
                        1.0
                    },
                )
            })
            .collect();
        let mut curves: Vec<[MinMaxDecimator; 3]> =
            slots.iter().map(|_| [dec(), dec(), dec()]).collect();
        let mut sample_count = 0usize;
        for s in timed.samples() {
            sample_count += 1;
            feed.push(s.t, s.feed);
            for ((slot, scale), c) in slots.iter().zip(&mut curves) {
                let (Some(v), Some(a), Some(j)) = (
                    s.velocity.get(*slot),
                    s.acceleration.get(*slot),
                    s.jerk.get(*slot),
                ) else {
                    continue;
                };
                let [cv, ca, cj] = c;
                cv.push(s.t, v * scale);
                ca.push(s.t, a * scale);
                cj.push(s.t, j * scale);
            }
        }
        let points = |d: MinMaxDecimator| {
            d.finish()
                .into_iter()
                .map(|[x, y]| PlotPoint::new(x, y))
                .collect::<Vec<_>>()
        };
        let axes = timed
            .axes
            .iter()
            .zip(slots)
            .zip(curves)
            .map(|(((axis, limit), (slot, scale)), [v, a, j])| AxisCurves {
                axis: *axis,
                rotary: slot >= 3 && slot != usize::MAX,
                limit: AxisLimit {
                    velocity: limit.velocity * scale,
                    acceleration: limit.acceleration * scale,
                    jerk: limit.jerk * scale,
                },
                velocity: points(v),
                acceleration: points(a),
                jerk: points(j),
            })
            .collect();
        Self {
            feed: points(feed),
            axes,
            cycle_time_s: t1,
            naive_time_s: naive_time_s(timed.blocks()),
            sample_count,
            quantity: Quantity::Feed,
            cursor_s: None,
            all_limits: false,
        }
    }

    /// The quantity shown.
    #[must_use]
    pub fn quantity(&self) -> Quantity {
        self.quantity
    }

    /// Show another quantity.
    pub fn set_quantity(&mut self, q: Quantity) {
        self.quantity = q;
    }

    /// Put the vertical cursor at time `t_s` (`None`: no cursor).
    pub fn set_cursor_time(&mut self, t_s: Option<f64>) {
        self.cursor_s = t_s.filter(|t| t.is_finite());
    }

    /// The cursor time.
    #[must_use]
    pub fn cursor_time(&self) -> Option<f64> {
        self.cursor_s
    }

    /// The header line: cycle time against the naive estimate.
    #[must_use]
    pub fn summary(&self) -> String {
        let mut s = format!("cycle time {}", duration_text(self.cycle_time_s));
        if self.naive_time_s > 0.0 {
            let ratio = self.cycle_time_s / self.naive_time_s;
            s.push_str(&format!(
                " · at programmed feed {} (×{ratio:.2})",
                duration_text(self.naive_time_s)
            ));
        }
        s
    }

    /// Draw the header, the quantity tabs and the plots.
    pub fn ui(&mut self, ui: &mut egui::Ui) -> Option<PlotEvent> {
        ui.horizontal(|ui| {
            ui.label(egui::RichText::new("MOTION").small().strong().weak());
            ui.label(self.summary());
        });
        ui.horizontal(|ui| {
            for q in Quantity::ALL {
                ui.selectable_value(&mut self.quantity, q, q.label());
            }
            ui.separator();
            ui.checkbox(&mut self.all_limits, "All limits")
                .on_hover_text(
                    "Draw every axis limit; by default only limits the curve comes within 4× of",
                );
        });
        let q = self.quantity;
        let link = egui::Id::unique("talas_motion_plots_time");
        if q == Quantity::Feed {
            let height = ui.available_height();
            return self.plot(ui, "feed", q, false, height, link);
        }
        let has_rotary = self.axes.iter().any(|a| a.rotary);
        let height = if has_rotary {
            (ui.available_height() - ui.spacing().item_spacing.y) / 2.0
        } else {
            ui.available_height()
        };
        let linear = self.plot(ui, "linear", q, false, height, link);
        let rotary = if has_rotary {
            self.plot(ui, "rotary", q, true, height, link)
        } else {
            None
        };
        linear.or(rotary)
    }

    /// One plot: the feed, or the linear or rotary axes of `q`.
    fn plot(
        &self,
        ui: &mut egui::Ui,
        id: &str,
        q: Quantity,
        rotary: bool,
        height: f32,
        link: egui::Id,
    ) -> Option<PlotEvent> {
        let unit = q.unit(rotary);
        let y_label = if q == Quantity::Feed {
            format!("path speed ({unit})")
        } else {
            format!("{} ({unit})", q.label().to_lowercase())
        };
        let cursor = self.cursor_s;
        let t_max = self.cycle_time_s;
        let response = Plot::new(("motion_plot", id))
            .height(height.max(60.0))
            .legend(Legend::default())
            .x_axis_label("time (s)")
            .y_axis_label(y_label)
            .link_axis(link, [true, false])
            .link_cursor(link, [true, false])
            .include_x(0.0)
            .include_x(t_max)
            .include_y(0.0)
            .allow_double_click_reset(true)
            .show(ui, |p| {
                if q == Quantity::Feed {
                    p.line(
                        Line::new("feed", self.feed.as_slice())
                            .color(Color32::from_rgb(64, 140, 230)),
                    );
                } else {
                    for a in self.axes.iter().filter(|a| a.rotary == rotary) {
                        let colour = axis_colour(a.axis);
                        let peak = a.peak_of(q);
                        let limit = a.limit_of(q).filter(|l| *l > 0.0);
                        let name = match limit {
                            Some(l) => format!("{}  peak {} of limit", a.axis, percent(peak / l)),
                            None => a.axis.to_string(),
                        };
                        p.line(Line::new(name.clone(), a.curve(q)).color(colour));
                        let near = |l: &f64| self.all_limits || peak >= 0.25 * l;
                        if let Some(limit) = limit.filter(near) {
                            for y in [limit, -limit] {
                                p.hline(
                                    HLine::new(format!("{} limit", a.axis), y)
                                        .color(colour.gamma_multiply(0.7))
                                        .style(LineStyle::dashed_loose()),
                                );
                            }
                        }
                    }
                }
                if let Some(t) = cursor {
                    p.vline(VLine::new("cursor", t).color(Color32::WHITE).width(2.0));
                }
                if p.response().clicked() {
                    p.pointer_coordinate().map(|c| c.x.clamp(0.0, t_max))
                } else {
                    None
                }
            });
        response.inner.map(PlotEvent::TimeClicked)
    }
}

/// Colour of an axis's curve.
fn axis_colour(axis: char) -> Color32 {
    match axis.to_ascii_uppercase() {
        'X' => Color32::from_rgb(235, 90, 80),
        'Y' => Color32::from_rgb(110, 200, 110),
        'Z' => Color32::from_rgb(64, 140, 230),
        'A' => Color32::from_rgb(232, 180, 60),
        'B' => Color32::from_rgb(200, 130, 230),
        _ => Color32::from_rgb(100, 200, 210),
    }
}

/// `0.4 %`, `12 %`.
fn percent(fraction: f64) -> String {
    let p = 100.0 * fraction;
    if p < 10.0 {
        format!("{p:.1} %")
    } else {
        format!("{p:.0} %")
    }
}

/// `12.345 s`, `4 min 05.2 s`, `1 h 02 min`.
#[must_use]
pub fn duration_text(s: f64) -> String {
    if !s.is_finite() || s < 0.0 {
        return "—".into();
    }
    if s < 60.0 {
        format!("{s:.3} s")
    } else if s < 3600.0 {
        let m = (s / 60.0).floor();
        format!("{m:.0} min {:04.1} s", s - m * 60.0)
    } else {
        let h = (s / 3600.0).floor();
        format!("{h:.0} h {:02.0} min", ((s - h * 3600.0) / 60.0).floor())
    }
}

#[cfg(test)]
mod tests;
