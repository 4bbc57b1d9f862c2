//! The data-reduction window: the part's Z-map reduced by truncated SVD. Settings
//! (grid step, tolerance, rank rule, resampling for a ball end mill), the singular values on a
//! log scale with the tolerance and the chosen rank, and the report (rank, error bound, max and
//! mean error, stored numbers against the Z-map's nodes). The reduced surface with its error map
//! is drawn in the viewport; Export writes it as STL.

use egui::Color32;
use egui_plot::{HLine, LineStyle, MarkerShape, Plot, Points, VLine};
use glam::DVec2;

use super::DataReduction;
use super::settings::{RankChoice, ReductionResult, ReductionSettings, ZmapSource};
use crate::app::command::Command;
use crate::app::number_field::NumberField;
use crate::app::theme;
use crate::reduce::{
    MAX_PART_ZMAP_NODES, PartReduction, PartXyReduction, point_spacing, zmap_size,
};

/// What the window shows besides the editable settings.
#[derive(Clone, Copy, Debug)]
pub struct ReductionView<'a> {
    /// XY extent of the part, mm (None without a part).
    pub part_size_mm: Option<DVec2>,
    /// The latest reduction, with its settings and wall time (s).
    pub result: Option<(&'a ReductionResult, &'a ReductionSettings, f64)>,
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
                    commands.push(DataReduction::command("reduce"));
                }
                let has = view.result.is_some();
                let mut visible = view.visible;
                if ui
                    .add_enabled(has, egui::Checkbox::new(&mut visible, "Show in viewport"))
                    .changed()
                {
                    commands.push(DataReduction::command(if visible {
                        "show"
                    } else {
                        "hide"
                    }));
                }
                if ui
                    .add_enabled(has, egui::Button::new("Export STL…"))
                    .on_hover_text("The reduced grid as a binary STL (mm)")
                    .clicked()
                {
                    commands.push(DataReduction::command("export"));
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
            ui.label("Z-map");
            ui.horizontal(|ui| {
                ui.radio_value(&mut s.source, ZmapSource::Regular, "Regular grid")
                    .on_hover_text("Heights at grid nodes over the part's XY box");
                ui.radio_value(&mut s.source, ZmapSource::XyDependent, "XY-dependent")
                    .on_hover_text(
                        "The mesh's vertices binned into a reference grid: X, Y and Z matrices \
                         reduced separately (keeps sharp edges where a regular grid blurs them)",
                    );
            });
            ui.end_row();
            ui.label(match s.source {
                ZmapSource::Regular => "Grid step",
                ZmapSource::XyDependent => "Reference step",
            });
            NumberField::new("step", &mut s.step_mm)
                .range(0.001..=100.0)
                .decimals(3)
                .unit("mm")
                .show(ui);
            ui.end_row();
            let (rows, cols) = zmap_size(size, s.step_mm);
            let nodes = rows.saturating_mul(cols);
            ui.label("Nodes");
            let text = format!(
                "{}{cols} × {rows} nodes (X × Y) over {:.1} × {:.1} mm",
                if s.source == ZmapSource::XyDependent {
                    "at most "
                } else {
                    ""
                },
                size.x,
                size.y
            );
            if nodes > MAX_PART_ZMAP_NODES {
                ui.colored_label(theme::ERROR, format!("{text} (more than 4 M)"));
            } else {
                ui.label(text);
            }
            ui.end_row();
            let l = ui.label("Tolerance");
            NumberField::new("tolerance", &mut s.tolerance_mm)
                .labelled_by(l.id)
                .range(1e-6..=10.0)
                .decimals(6)
                .unit("mm")
                .show(ui);
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
                    ui.add_enabled_ui(s.rank == RankChoice::Fixed, |ui| {
                        let mut terms = s.fixed_rank as f64;
                        if NumberField::new("terms", &mut terms)
                            .range(1.0..=10_000.0)
                            .decimals(0)
                            .unit("terms")
                            .width(60.0)
                            .show(ui)
                        {
                            // In range and rounded: a whole number from 1 to 10 000.
                            s.fixed_rank = terms.round() as usize;
                        }
                    });
                });
            });
            ui.end_row();
            ui.label("Resample");
            ui.horizontal(|ui| {
                ui.checkbox(&mut s.resample, "for a ball of radius");
                ui.add_enabled_ui(s.resample, |ui| {
                    NumberField::new("ball radius", &mut s.ball_radius_mm)
                        .range(0.01..=100.0)
                        .decimals(3)
                        .unit("mm")
                        .width(60.0)
                        .show(ui);
                });
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

/// One report row: a label and a monospace value.
fn report_row(ui: &mut egui::Ui, key: &str, value: String) {
    ui.label(key);
    ui.monospace(value);
    ui.end_row();
}

/// `2.1 µm  (within tolerance)`.
fn error_text(mm: f64, tolerance_mm: f64) -> String {
    let verdict = if mm <= tolerance_mm {
        "  (within tolerance)"
    } else {
        "  (over tolerance)"
    };
    format!("{}{verdict}", length_text(mm))
}

fn report_ui(
    ui: &mut egui::Ui,
    result: &ReductionResult,
    used: &ReductionSettings,
    elapsed_s: f64,
) {
    egui::Grid::new("reduction report")
        .num_columns(2)
        .striped(true)
        .spacing([12.0, 3.0])
        .show(ui, |ui| {
            match result {
                ReductionResult::Regular(r) => regular_rows(ui, r, used),
                ReductionResult::Xy(r) => xy_rows(ui, r, used),
            }
            report_row(ui, "Time", format!("{elapsed_s:.2} s"));
        });
}

fn regular_rows(ui: &mut egui::Ui, r: &PartReduction, used: &ReductionSettings) {
    let red = &r.reduction;
    let (m, n) = (r.zmap.grid.rows(), r.zmap.grid.cols());
    let nodes = m * n;
    report_row(
        ui,
        "Z-map",
        format!("{n} × {m} nodes (X × Y) at {} mm", r.zmap.step_mm),
    );
    let from_mesh = nodes - r.zmap.exact_nodes - r.zmap.misses;
    report_row(
        ui,
        "Heights",
        format!(
            "{} exact, {from_mesh} from the mesh, {} off the part (floor)",
            r.zmap.exact_nodes, r.zmap.misses
        ),
    );
    report_row(
        ui,
        "Rank",
        format!(
            "{} of {} singular values",
            red.rank,
            red.singular_values.len()
        ),
    );
    report_row(ui, "Bound σ(r+1)", length_text(red.rank_error_bound));
    report_row(
        ui,
        "Max error",
        error_text(red.max_error, used.tolerance_mm),
    );
    report_row(ui, "Mean error", length_text(red.mean_error));
    report_row(
        ui,
        "Reduced grid",
        format!(
            "{} × {} nodes (X × Y)",
            red.reduced.cols(),
            red.reduced.rows()
        ),
    );
    if let Some(l) = red.spacing_mm {
        report_row(ui, "Point spacing", format!("{l:.4} mm"));
    }
    report_row(
        ui,
        "Point reduction",
        reduction_ratio_text(nodes, red.reduced.rows() * red.reduced.cols()),
    );
    report_row(
        ui,
        "Stored",
        format!(
            "{} numbers for {} nodes ({:.2} % of the Z-map)",
            red.stored_numbers,
            nodes,
            100.0 * red.stored_numbers as f64 / nodes.max(1) as f64
        ),
    );
}

fn xy_rows(ui: &mut egui::Ui, r: &PartXyReduction, used: &ReductionSettings) {
    let red = &r.reduction;
    let (m, n) = (r.map.z.rows(), r.map.z.cols());
    report_row(
        ui,
        "Z-map",
        format!(
            "XY-dependent, {n} × {m} nodes (X × Y), reference step {} mm",
            used.step_mm
        ),
    );
    report_row(
        ui,
        "Ranks",
        format!(
            "X {}, Y {}, Z {} of {} singular values",
            red.x.rank,
            red.y.rank,
            red.z.rank,
            red.z.singular_values.len()
        ),
    );
    report_row(
        ui,
        "Max error",
        format!(
            "{} (vertical)",
            error_text(red.max_error, used.tolerance_mm)
        ),
    );
    report_row(ui, "Mean error", length_text(red.mean_error));
    if red.uncovered > 0 {
        report_row(
            ui,
            "Not covered",
            format!("{} nodes outside the reduced surface", red.uncovered),
        );
    }
    report_row(
        ui,
        "Reduced grid",
        format!(
            "{} × {} nodes (X × Y)",
            red.reduced.z.cols(),
            red.reduced.z.rows()
        ),
    );
    report_row(
        ui,
        "Point reduction",
        reduction_ratio_text(m * n, red.reduced.z.rows() * red.reduced.z.cols()),
    );
    let numbers = 3 * m * n;
    report_row(
        ui,
        "Stored",
        format!(
            "{} numbers for {numbers} (X, Y, Z of {} nodes; {:.2} %)",
            r.stored_numbers(),
            m * n,
            100.0 * r.stored_numbers() as f64 / numbers.max(1) as f64
        ),
    );
}

/// The thesis's data-reduction ratio (N − N′)/N of the point counts (negative when the data
/// grows), with the counts.
fn reduction_ratio_text(before: usize, after: usize) -> String {
    let ratio = (before as f64 - after as f64) / before.max(1) as f64;
    format!("{before} → {after} points ({:+.1} %)", -100.0 * ratio)
}

/// Colour of a matrix's spectrum.
fn spectrum_colour(name: &str) -> Color32 {
    match name {
        "X" => Color32::from_rgb(235, 90, 80),
        "Y" => Color32::from_rgb(110, 200, 110),
        _ => theme::ACCENT,
    }
}

/// The singular values on a log₁₀ scale: kept terms filled, dropped ones hollow, the tolerance as
/// a dashed line and the cut after each matrix's r-th term.
fn singular_value_plot(ui: &mut egui::Ui, result: &ReductionResult, used: &ReductionSettings) {
    let spectra = result.spectra();
    // Values below σ_1 · 1e-16 are rounding noise (exactly separable data gives them): they sit
    // on a floor under the smaller of that level and the tolerance instead of going to −∞.
    let sigma1 = spectra
        .iter()
        .filter_map(|(_, r)| r.singular_values.first().copied())
        .fold(1e-300, f64::max);
    let floor = (sigma1 * 1e-16).min(used.tolerance_mm).max(1e-300).log10() - 1.0;
    let point = |k: usize, s: f64| {
        [
            (k + 1) as f64,
            if s > 0.0 { s.log10().max(floor) } else { floor },
        ]
    };
    let tol = used.tolerance_mm.log10();
    Plot::new("singular values")
        .height(220.0)
        .legend(egui_plot::Legend::default())
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
            for (name, red) in &spectra {
                let colour = spectrum_colour(name);
                let (kept, dropped): (Vec<_>, Vec<_>) = red
                    .singular_values
                    .iter()
                    .enumerate()
                    .map(|(k, s)| (k < red.rank, point(k, *s)))
                    .partition(|(keep, _)| *keep);
                let strip = |v: Vec<(bool, [f64; 2])>| -> Vec<[f64; 2]> {
                    v.into_iter().map(|(_, p)| p).collect()
                };
                p.points(
                    Points::new(format!("{name} kept"), strip(kept))
                        .color(colour)
                        .shape(MarkerShape::Circle)
                        .filled(true)
                        .radius(2.5),
                );
                p.points(
                    Points::new(format!("{name} dropped"), strip(dropped))
                        .color(colour.gamma_multiply(0.5))
                        .shape(MarkerShape::Circle)
                        .filled(false)
                        .radius(2.0),
                );
                p.vline(
                    VLine::new(format!("{name} rank"), red.rank as f64 + 0.5)
                        .color(colour.gamma_multiply(0.8)),
                );
            }
            p.hline(
                HLine::new("tolerance", tol)
                    .color(theme::WARNING)
                    .style(LineStyle::dashed_loose()),
            );
        });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reduce::RankRule;

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
    fn reduction_ratio_as_the_thesis_counts_it() {
        // The thesis's example: 241 × 241 → 156 × 156, 58.1 % fewer points.
        assert_eq!(
            reduction_ratio_text(241 * 241, 156 * 156),
            "58081 → 24336 points (-58.1 %)"
        );
        assert_eq!(reduction_ratio_text(10, 12), "10 → 12 points (+20.0 %)");
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
