//! The workstation's look: a dark theme with quiet panels and one accent colour.

use egui::{Color32, CornerRadius, Stroke, Visuals};

/// The accent colour (selection, progress).
pub const ACCENT: Color32 = Color32::from_rgb(64, 140, 230);
/// Colour for warnings.
pub const WARNING: Color32 = Color32::from_rgb(232, 180, 60);
/// Colour for errors.
pub const ERROR: Color32 = Color32::from_rgb(235, 90, 80);

/// Apply the dark theme to every style of `ctx`.
pub fn apply(ctx: &egui::Context) {
    let mut v = Visuals::dark();
    v.panel_fill = Color32::from_rgb(30, 32, 36);
    v.window_fill = Color32::from_rgb(36, 38, 43);
    v.extreme_bg_color = Color32::from_rgb(20, 21, 24);
    v.faint_bg_color = Color32::from_rgb(35, 37, 42);
    v.window_stroke = Stroke::new(1.0, Color32::from_rgb(55, 58, 65));
    v.selection.bg_fill = ACCENT.gamma_multiply(0.55);
    v.selection.stroke = Stroke::new(1.0, Color32::from_rgb(210, 230, 255));
    v.hyperlink_color = ACCENT;
    v.warn_fg_color = WARNING;
    v.error_fg_color = ERROR;
    v.widgets.noninteractive.bg_stroke = Stroke::new(1.0, Color32::from_rgb(48, 51, 57));
    v.widgets.noninteractive.fg_stroke = Stroke::new(1.0, Color32::from_rgb(200, 203, 210));
    v.widgets.inactive.fg_stroke = Stroke::new(1.0, Color32::from_rgb(210, 213, 220));
    v.widgets.inactive.weak_bg_fill = Color32::from_rgb(44, 47, 53);
    v.widgets.hovered.weak_bg_fill = Color32::from_rgb(56, 60, 68);
    v.widgets.active.weak_bg_fill = ACCENT.gamma_multiply(0.7);
    for w in [
        &mut v.widgets.noninteractive,
        &mut v.widgets.inactive,
        &mut v.widgets.hovered,
        &mut v.widgets.active,
    ] {
        w.corner_radius = CornerRadius::same(3);
    }
    v.window_corner_radius = CornerRadius::same(6);
    v.menu_corner_radius = CornerRadius::same(4);
    v.striped = true;
    ctx.all_styles_mut(|style| {
        style.visuals = v.clone();
        style.spacing.item_spacing = egui::vec2(8.0, 5.0);
        style.spacing.button_padding = egui::vec2(8.0, 3.0);
    });
    ctx.set_theme(egui::Theme::Dark);
}
