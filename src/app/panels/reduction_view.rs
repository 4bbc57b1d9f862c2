//! The data-reduction window (seed-003): the part's Z-map reduced by truncated SVD. Settings
//! (grid step, tolerance, rank rule, resampling for a ball end mill), the singular values on a
//! log scale with the tolerance and the chosen rank, and the report (rank, error bound, max and
//! mean error, stored numbers against the Z-map's nodes). The reduced surface with its error map
//! is drawn in the viewport; Export writes it as STL.

use egui::Color32;
use egui_plot::{HLine, LineStyle, MarkerShape, Plot, Points, VLine};
use glam::DVec2;

use super::super::command::Command;
use super::super::theme;
use crate::reduce::{
    MAX_PART_ZMAP_NODES, PartReduction, RankRule, ReduceOptions, Resampling, point_spacing,
    zmap_size,
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

/// What a reduction is run with.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReductionSettings {
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

/// What the window shows besides the editable settings.
#[derive(Clone, Copy, Debug)]
pub struct ReductionView<'a> {
    /// XY extent of the part, mm (None without a part).
    pub part_size_mm: Option<DVec2>,
    /// The latest reduction, with its settings and wall time (s).
    pub result: Option<(&'a PartReduction, &'a ReductionSettings, f64)>,
    /// The result was made from another part or other settings.
    pub stale: bool,
    /// Fraction done of the running reduction.
    pub running: Option<f64>,
    /// The reduced surface is drawn in the viewport.
    pub visible: bool,
}

/// The data-reduction window; `open` goes false when its close button is clicked.
pub fn reduction_window(
    ctx: &egui::Context,
    open: &mut bool,
    settings: &mut ReductionSettings,
    view: &ReductionView<'_>,
    commands: &mut Vec<Command>,
) {
    // Right of the viewport's legends (top left), left of the properties panel.
    let right_top = ctx.content_rect().right_top();
    egui::Window::new("Data reduction (Z-map SVD)")
        .open(open)
        .default_width(460.0)
        .pivot(egui::Align2::RIGHT_TOP)
        .default_pos(right_top + egui::vec2(-340.0, 40.0))
        .show(ctx, |ui| {
            let Some(size) = view.part_size_mm else {
                ui.weak("Open a part first.");
                return;
            };
            settings_ui(ui, settings, size);
            ui.add_space(4.0);
            ui.horizontal(|ui| {
                let (rows, cols) = zmap_size(size, settings.step_mm);
                let fits = rows.saturating_mul(cols) <= MAX_PART_ZMAP_NODES;
                if let Some(f) = view.running {
                    ui.add(
                        egui::ProgressBar::new(f as f32)
                            .desired_width(160.0)
                            .show_percentage(),
                    );
                    if ui.button("Cancel").clicked() {
                        commands.push(Command::CancelJob);
                    }
                } else if ui
                    .add_enabled(fits, egui::Button::new("Reduce"))
                    .on_hover_text("Sample the part's Z-map and reduce it (in the background)")
                    .on_disabled_hover_text("Too many nodes: choose a coarser step")
                    .clicked()
                {
                    commands.push(Command::Reduce(*settings));
                }
                let has = view.result.is_some();
                let mut visible = view.visible;
                if ui
                    .add_enabled(has, egui::Checkbox::new(&mut visible, "Show in viewport"))
                    .changed()
                {
                    commands.push(Command::SetReductionVisible(visible));
                }
                if ui
                    .add_enabled(has, egui::Button::new("Export STL…"))
                    .on_hover_text("The reduced grid as a binary STL (mm)")
                    .clicked()
                {
                    commands.push(Command::ExportReductionDialog);
                }
            });
            let Some((r, used, elapsed_s)) = view.result else {
                return;
            };
            ui.separator();
            if view.stale {
                ui.colored_label(
                    theme::WARNING,
                    "stale: the part or the settings changed since this reduction",
                );
            }
            report_ui(ui, r, used, elapsed_s);
            singular_value_plot(ui, r, used);
        });
}

fn settings_ui(ui: &mut egui::Ui, s: &mut ReductionSettings, size: DVec2) {
    egui::Grid::new("reduction settings")
        .num_columns(2)
        .spacing([12.0, 4.0])
        .show(ui, |ui| {
            ui.label("Grid step");
            ui.add(
                egui::DragValue::new(&mut s.step_mm)
                    .range(0.001..=100.0)
                    .speed(0.01)
                    .max_decimals(3)
                    .suffix(" mm"),
            );
            ui.end_row();
            let (rows, cols) = zmap_size(size, s.step_mm);
            let nodes = rows.saturating_mul(cols);
            ui.label("Z-map");
            let text = format!(
                "{cols} × {rows} nodes (X × Y) over {:.1} × {:.1} mm",
                size.x, size.y
            );
            if nodes > MAX_PART_ZMAP_NODES {
                ui.colored_label(theme::ERROR, format!("{text} (more than 4 M)"));
            } else {
                ui.label(text);
            }
            ui.end_row();
            ui.label("Tolerance");
            ui.add(
                egui::DragValue::new(&mut s.tolerance_mm)
                    .range(1e-6..=10.0)
                    .speed(0.0005)
                    .max_decimals(5)
                    .suffix(" mm"),
            );
            ui.end_row();
            ui.label("Rank");
            ui.vertical(|ui| {
                ui.radio_value(&mut s.rank, RankChoice::Spectral, "σ(r+1) ≤ tolerance")
                    .on_hover_text(
                        "Guarantees |model − Z-map| ≤ tolerance at every node (2-norm bound)",
                    );
                ui.radio_value(
                    &mut s.rank,
                    RankChoice::TermChange,
                    "Thesis: last term changes < tolerance",
                )
                .on_hover_text("Yurtsever's loop; it bounds nothing (terms are not monotone)");
                ui.horizontal(|ui| {
                    ui.radio_value(&mut s.rank, RankChoice::Fixed, "Fixed");
                    ui.add_enabled(
                        s.rank == RankChoice::Fixed,
                        egui::DragValue::new(&mut s.fixed_rank)
                            .range(1..=10_000)
                            .suffix(" terms"),
                    );
                });
            });
            ui.end_row();
            ui.label("Resample");
            ui.horizontal(|ui| {
                ui.checkbox(&mut s.resample, "for a ball of radius");
                ui.add_enabled(
                    s.resample,
                    egui::DragValue::new(&mut s.ball_radius_mm)
                        .range(0.01..=100.0)
                        .speed(0.05)
                        .max_decimals(3)
                        .suffix(" mm"),
                );
            });
            ui.end_row();
            if s.resample {
                ui.label("Point spacing");
                ui.label(format!(
                    "l = sqrt(4ρt − t²) = {:.4} mm",
                    point_spacing(s.ball_radius_mm, s.tolerance_mm)
                ));
                ui.end_row();
            }
        });
}

/// `1.234 mm` from 1 mm, `12.34 µm` down to 0.01 µm, `3.21e-8 mm` below, `0 mm`.
fn length_text(mm: f64) -> String {
    let a = mm.abs();
    if a == 0.0 {
        "0 mm".into()
    } else if a < 1e-5 {
        format!("{mm:.2e} mm")
    } else if a < 1.0 {
        format!("{:.2} µm", mm * 1000.0)
    } else {
        format!("{mm:.4} mm")
    }
}

fn report_ui(ui: &mut egui::Ui, r: &PartReduction, used: &ReductionSettings, elapsed_s: f64) {
    let red = &r.reduction;
    let (m, n) = (r.zmap.grid.rows(), r.zmap.grid.cols());
    let nodes = m * n;
    egui::Grid::new("reduction report")
        .num_columns(2)
        .striped(true)
        .spacing([12.0, 3.0])
        .show(ui, |ui| {
            let mut row = |k: &str, v: String| {
                ui.label(k);
                ui.monospace(v);
                ui.end_row();
            };
            row(
                "Z-map",
                format!("{n} × {m} nodes (X × Y) at {} mm", r.zmap.step_mm),
            );
            let from_mesh = nodes - r.zmap.exact_nodes - r.zmap.misses;
            row(
                "Heights",
                format!(
                    "{} exact, {from_mesh} from the mesh, {} off the part (floor)",
                    r.zmap.exact_nodes, r.zmap.misses
                ),
            );
            row(
                "Rank",
                format!(
                    "{} of {} singular values",
                    red.rank,
                    red.singular_values.len()
                ),
            );
            row("Bound σ(r+1)", length_text(red.rank_error_bound));
            row(
                "Max error",
                format!(
                    "{}{}",
                    length_text(red.max_error),
                    if red.max_error <= used.tolerance_mm {
                        "  (within tolerance)"
                    } else {
                        "  (over tolerance)"
                    }
                ),
            );
            row("Mean error", length_text(red.mean_error));
            row(
                "Reduced grid",
                format!(
                    "{} × {} nodes (X × Y)",
                    red.reduced.cols(),
                    red.reduced.rows()
                ),
            );
            if let Some(l) = red.spacing_mm {
                row("Point spacing", format!("{l:.4} mm"));
            }
            row(
                "Stored",
                format!(
                    "{} numbers for {} nodes ({:.2} % of the Z-map)",
                    red.stored_numbers,
                    nodes,
                    100.0 * red.stored_numbers as f64 / nodes.max(1) as f64
                ),
            );
            row("Time", format!("{elapsed_s:.2} s"));
        });
}

/// The singular values on a log₁₀ scale: kept terms in the accent colour, dropped ones grey,
/// the tolerance as a dashed line and the cut after the r-th term.
fn singular_value_plot(ui: &mut egui::Ui, r: &PartReduction, used: &ReductionSettings) {
    let red = &r.reduction;
    // Values below σ_1 · 1e-16 are rounding noise (exactly separable data gives them): they sit
    // on a floor under the smaller of that level and the tolerance instead of going to −∞.
    let sigma1 = red
        .singular_values
        .first()
        .copied()
        .unwrap_or(1.0)
        .max(1e-300);
    let floor = (sigma1 * 1e-16).min(used.tolerance_mm).max(1e-300).log10() - 1.0;
    let point = |k: usize, s: f64| {
        [
            (k + 1) as f64,
            if s > 0.0 { s.log10().max(floor) } else { floor },
        ]
    };
    let kept: Vec<[f64; 2]> = red
        .singular_values
        .iter()
        .take(red.rank)
        .enumerate()
        .map(|(k, s)| point(k, *s))
        .collect();
    let dropped: Vec<[f64; 2]> = red
        .singular_values
        .iter()
        .enumerate()
        .skip(red.rank)
        .map(|(k, s)| point(k, *s))
        .collect();
    let tol = used.tolerance_mm.log10();
    Plot::new("singular values")
        .height(220.0)
        .x_axis_label("term k")
        .y_axis_label("σ_k (mm, log scale)")
        .y_axis_formatter(|mark, _| format!("1e{:.0}", mark.value))
        .label_formatter(|hover| {
            let p = match hover {
                egui_plot::HoverPosition::NearDataPoint { position, .. } => position,
                egui_plot::HoverPosition::Elsewhere { position } => position,
            };
            Some(format!("k = {:.0}\nσ = {:.3e} mm", p.x, 10f64.powf(p.y)))
        })
        .allow_double_click_reset(true)
        .show(ui, |p| {
            p.points(
                Points::new("kept", kept)
                    .color(theme::ACCENT)
                    .shape(MarkerShape::Circle)
                    .filled(true)
                    .radius(2.5),
            );
            p.points(
                Points::new("dropped", dropped)
                    .color(Color32::from_gray(140))
                    .shape(MarkerShape::Circle)
                    .radius(2.0),
            );
            p.hline(
                HLine::new("tolerance", tol)
                    .color(theme::WARNING)
                    .style(LineStyle::dashed_loose()),
            );
            p.vline(VLine::new("rank", red.rank as f64 + 0.5).color(Color32::WHITE));
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_step_gives_about_two_hundred_nodes() {
        let s = ReductionSettings::for_part(DVec2::new(100.0, 60.0), Some(2.0));
        assert!((s.step_mm - 0.5).abs() < 1e-12, "{}", s.step_mm);
        assert_eq!(s.ball_radius_mm, 2.0);
        let s = ReductionSettings::for_part(DVec2::new(7.3, 2.0), None);
        assert!((s.step_mm - 0.05).abs() < 1e-12, "{}", s.step_mm);
        let (rows, cols) = zmap_size(DVec2::new(7.3, 2.0), s.step_mm);
        assert_eq!((rows, cols), (41, 147));
    }

    #[test]
    fn lengths_keep_their_digits() {
        assert_eq!(length_text(0.0), "0 mm");
        assert_eq!(length_text(3.2e-8), "3.20e-8 mm");
        assert_eq!(length_text(0.0123), "12.30 µm");
        assert_eq!(length_text(2.5), "2.5000 mm");
    }

    #[test]
    fn options_follow_the_choice() {
        let mut s = ReductionSettings {
            rank: RankChoice::Fixed,
            fixed_rank: 7,
            resample: true,
            ..ReductionSettings::default()
        };
        let o = s.options();
        assert_eq!(o.rank_rule, RankRule::Fixed(7));
        assert_eq!(o.resampling.map(|r| r.tool_radius_mm), Some(3.0));
        s.rank = RankChoice::TermChange;
        s.resample = false;
        assert_eq!(s.options().rank_rule, RankRule::TermChange);
        assert!(s.options().resampling.is_none());
    }
}
