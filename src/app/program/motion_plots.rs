//! Motion plots of a planned program ([`TimedPath`]): path speed, and every axis's velocity,
//! acceleration and jerk against time, with the machine limits as dashed lines, a cursor at
//! the playback time, and the cycle time next to the naive length/feed estimate.
//!
//! The samples are read once at construction and decimated (min/max per bucket, at most
//! [`MAX_POINTS`] points a curve), so drawing costs the same for a one-second and a one-hour
//! program and no peak disappears.

mod curves;
mod decimation;

pub use curves::{AxisCurves, Curve, Quantity, XAxis, interpolate_x};
pub use decimation::MinMaxDecimator;

use crate::feed::path::slot_of;
use crate::feed::{AxisLimit, TimedPath, naive_time_s};
use egui::Color32;
use egui_plot::{HLine, Legend, Line, LineStyle, Plot, VLine, uniform_grid_spacer};

/// Largest number of points kept per curve.
pub const MAX_POINTS: usize = 20_000;

/// What the user did in the plots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlotEvent {
    /// The user clicked a plot at this time (s), clamped to the program.
    TimeClicked(f64),
    /// The pointer is over a plot at this time (s), clamped to the program.
    TimeHovered(f64),
}

/// State of the motion plots.
#[derive(Clone, Debug)]
pub struct MotionPlots {
    /// Path speed, mm/s.
    pub feed: Curve,
    /// The axes, machine order.
    pub axes: Vec<AxisCurves>,
    /// Planned cycle time, s.
    pub cycle_time_s: f64,
    /// The program at its programmed feeds ([`naive_time_s`]), s.
    pub naive_time_s: f64,
    /// Samples read from the plan.
    pub sample_count: usize,
    quantity: Quantity,
    x_axis: XAxis,
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
            let at = s.path_position;
            feed.push_tagged(s.t, s.feed, at);
            for ((slot, scale), c) in slots.iter().zip(&mut curves) {
                let (Some(v), Some(a), Some(j)) = (
                    s.velocity.get(*slot),
                    s.acceleration.get(*slot),
                    s.jerk.get(*slot),
                ) else {
                    continue;
                };
                let [cv, ca, cj] = c;
                cv.push_tagged(s.t, v * scale, at);
                ca.push_tagged(s.t, a * scale, at);
                cj.push_tagged(s.t, j * scale, at);
            }
        }
        let points = |d: MinMaxDecimator| Curve::from_tagged(d.finish_tagged());
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
            x_axis: XAxis::Time,
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

    /// What the horizontal axis shows.
    #[must_use]
    pub fn x_axis(&self) -> XAxis {
        self.x_axis
    }

    /// Plot against time or path length.
    pub fn set_x_axis(&mut self, x: XAxis) {
        self.x_axis = x;
    }

    /// The path position (mm) at time `t_s`, read from the decimated plan.
    #[must_use]
    pub fn path_at_time(&self, t_s: f64) -> f64 {
        interpolate_x(&self.feed.by_time, &self.feed.by_path, t_s)
    }

    /// The time (s) at path position `s_mm`, up to the decimation; where the path stands
    /// still (a rotary-only move) the end of that stretch.
    #[must_use]
    pub fn time_at_path(&self, s_mm: f64) -> f64 {
        interpolate_x(&self.feed.by_path, &self.feed.by_time, s_mm)
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
            ui.selectable_value(&mut self.x_axis, XAxis::Time, "vs time");
            ui.selectable_value(&mut self.x_axis, XAxis::PathLength, "vs path");
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
        let x = self.x_axis;
        let to_x = |t: f64| match x {
            XAxis::Time => t,
            XAxis::PathLength => self.path_at_time(t),
        };
        let cursor = self.cursor_s.map(to_x);
        let t_max = self.cycle_time_s;
        // Separate plots (and link groups) per horizontal axis, so each keeps its own zoom.
        let link = link.with(x);
        let response = Plot::new(("motion_plot", id, x))
            .height(height.max(60.0))
            .legend(Legend::default())
            .x_axis_label(x.label())
            .y_axis_label(y_label)
            .link_axis(link, [true, false])
            .link_cursor(link, [true, false])
            .include_x(0.0)
            .include_x(to_x(t_max))
            .include_y(0.0)
            .y_grid_spacer(uniform_grid_spacer(|g| grid_steps(g.base_step_size)))
            .allow_double_click_reset(true)
            .show(ui, |p| {
                if q == Quantity::Feed {
                    p.line(
                        Line::new("feed", self.feed.points(x))
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
                        let points = a.curve(q).map_or(&[][..], |c| c.points(x));
                        p.line(Line::new(name.clone(), points).color(colour));
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
                let clicked = p.response().clicked();
                if clicked || p.response().hovered() {
                    p.pointer_coordinate().map(|c| (c.x, clicked))
                } else {
                    None
                }
            });
        response.inner.map(|(at, clicked)| {
            let t = match x {
                XAxis::Time => at,
                XAxis::PathLength => self.time_at_path(at),
            }
            .clamp(0.0, t_max);
            if clicked {
                PlotEvent::TimeClicked(t)
            } else {
                PlotEvent::TimeHovered(t)
            }
        })
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

/// Grid steps 1-2-5 × 10ᵏ (the finest at least `base`), each dividing the next, so the
/// labels stay dense where limits widen the range (egui_plot's default steps by 10 only).
fn grid_steps(base: f64) -> [f64; 3] {
    let base = base.abs();
    if !(base.is_finite() && base > 0.0) {
        return [1.0, 5.0, 10.0];
    }
    let p = 10f64.powf(base.log10().floor());
    let m = base / p;
    let (s0, k) = if m <= 1.0 {
        (p, 5.0)
    } else if m <= 2.0 {
        (2.0 * p, 5.0)
    } else if m <= 5.0 {
        (5.0 * p, 2.0)
    } else {
        (10.0 * p, 5.0)
    };
    [s0, s0 * k, s0 * 10.0]
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
