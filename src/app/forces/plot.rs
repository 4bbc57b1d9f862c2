//! The force plot: per piece of the path (a step of constant value over the piece's time),
//! F_x, F_y, F_z and the resultant in N, or the torque in N·m, or the cutting power in W, peak
//! or mean per revolution, against time in s; zero between cutting pieces (air, rapids); the
//! limit as a dashed line; a cursor at the tool's pose. A click returns the pose cut then.

use egui::Color32;
use egui_plot::{HLine, Legend, Line, LineStyle, Plot, PlotTransform, VLine};

use super::Shown;
use crate::project::forces::{ForceSample, ForceTimeline};

/// One curve: its name, colour and value of a sample.
type Series = (&'static str, Color32, fn(&ForceSample, bool) -> f64);

fn series(shown: Shown) -> Vec<Series> {
    match shown {
        Shown::Force => vec![
            ("F_x", Color32::from_rgb(235, 90, 80), |s, m| {
                if m { s.mean[0] } else { s.peak[0] }
            }),
            ("F_y", Color32::from_rgb(110, 200, 110), |s, m| {
                if m { s.mean[1] } else { s.peak[1] }
            }),
            ("F_z", Color32::from_rgb(64, 140, 230), |s, m| {
                if m { s.mean[2] } else { s.peak[2] }
            }),
            ("|F|", Color32::from_rgb(240, 240, 240), |s, m| {
                if m {
                    s.mean.iter().map(|v| v * v).sum::<f64>().sqrt()
                } else {
                    s.peak_resultant_n
                }
            }),
        ],
        Shown::Torque => vec![("torque", Color32::from_rgb(232, 180, 60), |s, m| {
            s.torque_nm[usize::from(m)]
        })],
        Shown::Power => vec![("power", Color32::from_rgb(200, 130, 230), |s, m| {
            s.power_w[usize::from(m)]
        })],
    }
}

/// Step points of `value` over the samples, dropping to zero across gaps.
#[must_use]
pub fn step_points(samples: &[ForceSample], value: impl Fn(&ForceSample) -> f64) -> Vec<[f64; 2]> {
    let mut out = Vec::with_capacity(2 * samples.len() + 2);
    let mut last_end: Option<f64> = None;
    for s in samples {
        let v = value(s);
        if last_end.is_none_or(|e| s.t_s[0] > e + 1e-9) {
            if let Some(e) = last_end {
                out.push([e, 0.0]);
            }
            out.push([s.t_s[0], 0.0]);
        }
        out.push([s.t_s[0], v]);
        out.push([s.t_s[1], v]);
        last_end = Some(s.t_s[1]);
    }
    if let Some(e) = last_end {
        out.push([e, 0.0]);
    }
    out
}

/// The unit and limit of what is shown.
fn unit_and_limit(shown: Shown, r: &ForceTimeline) -> (&'static str, Option<f64>) {
    match shown {
        Shown::Force => ("N", r.limits.max_force_n),
        Shown::Torque => ("N·m", r.limits.max_torque_nm),
        Shown::Power => ("W", r.limits.max_power_w),
    }
}

/// The summary line of a result.
#[must_use]
pub fn summary(r: &ForceTimeline) -> String {
    let t = &r.forces.totals;
    let clock = if r.planned_time {
        "planned time of the posted program"
    } else {
        "time at the programmed feeds (post the program for the planned time)"
    };
    format!(
        "peak |F| {:.1} N at pose {} · peak torque {:.2} N·m · peak power {:.0} W · mean power {:.0} W · {:.2} s cutting · {} moves over a limit · {clock}",
        t.peak_resultant_n,
        t.peak_resultant_block,
        t.peak_torque_nm,
        t.peak_power_w,
        t.mean_power_w,
        t.cutting_time_s,
        t.moves_over_limits,
    )
}

fn limit_text(label: &str, v: Option<f64>, unit: &str) -> String {
    v.map_or_else(
        || format!("{label}: none"),
        |v| format!("{label} {v:.0} {unit}"),
    )
}

/// Draw the controls and the plot; the plot's screen transform, and the pose clicked, if any.
pub fn ui(
    ui: &mut egui::Ui,
    r: &ForceTimeline,
    (shown, mean): (&mut Shown, &mut bool),
    cursor_s: Option<f64>,
) -> (PlotTransform, Option<usize>) {
    ui.label(summary(r));
    ui.horizontal(|ui| {
        ui.selectable_value(shown, Shown::Force, "Force (N)");
        ui.selectable_value(shown, Shown::Torque, "Torque (N·m)");
        ui.selectable_value(shown, Shown::Power, "Power (W)");
        ui.separator();
        ui.checkbox(mean, "Mean per revolution")
            .on_hover_text("Unticked: the peak over each revolution (signed for F_x, F_y, F_z)");
        ui.separator();
        let l = &r.limits;
        ui.label(format!(
            "Limits: {} · {} · {}",
            limit_text("force", l.max_force_n, "N"),
            limit_text("torque", l.max_torque_nm, "N·m"),
            limit_text("power", l.max_power_w, "W"),
        ));
    });
    let (unit, limit) = unit_and_limit(*shown, r);
    let t_max = r.pose_time_s.last().copied().unwrap_or(0.0);
    let mean = *mean;
    let height = ui.available_height().max(120.0);
    let response = Plot::new("talas_force_plot")
        .height(height)
        .legend(Legend::default())
        .x_axis_label("time (s)")
        .y_axis_label(format!("{} ({unit})", if mean { "mean" } else { "peak" }))
        .include_x(0.0)
        .include_x(t_max)
        .include_y(0.0)
        .allow_double_click_reset(true)
        .show(ui, |p| {
            for (name, colour, value) in series(*shown) {
                let pts = step_points(&r.samples, |s| value(s, mean));
                p.line(Line::new(name, pts).color(colour));
            }
            if let Some(l) = limit {
                p.hline(
                    HLine::new(format!("limit {l:.0} {unit}"), l)
                        .color(Color32::from_rgb(255, 70, 70))
                        .style(LineStyle::dashed_loose()),
                );
            }
            if let Some(t) = cursor_s {
                p.vline(VLine::new("tool", t).color(Color32::WHITE).width(2.0));
            }
            p.response()
                .clicked()
                .then(|| p.pointer_coordinate().map(|c| c.x))
                .flatten()
        });
    let pose = response.inner.and_then(|t| r.sample_at(t)).map(|s| s.pose);
    (response.transform, pose)
}
