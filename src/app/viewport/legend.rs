//! The colour-map legend over the viewport: a vertical bar with the field's name, unit, and the
//! values at its ends and middle, and a marked value (a limit) when asked.

use crate::render::{ColourMap, ScalarMapping};

/// Height of the colour bar, points.
const BAR_HEIGHT: f32 = 180.0;
/// Width of the colour bar, points.
const BAR_WIDTH: f32 = 16.0;
/// Bands the bar is drawn with.
const BANDS: usize = 48;

/// A value for the legend: 4 significant digits, scientific when small or large.
#[must_use]
pub fn legend_value(v: f32) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&a) {
        // Decimals for 4 significant digits (483.3 N, 0.2000 mm, 12.00 µm).
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 5) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// Height a legend takes, points (legends stack down the left edge).
pub const LEGEND_HEIGHT: f32 = BAR_HEIGHT + 52.0;

/// Draw the legend `title` (with its unit) of values mapped by `mapping` at the top-left corner
/// of `rect`, `slot` legends down.
pub fn legend_ui(
    ui: &egui::Ui,
    rect: egui::Rect,
    title: &str,
    mapping: ScalarMapping,
    slot: usize,
) {
    let painter = ui.painter();
    let origin = rect.left_top() + egui::vec2(14.0, 34.0 + slot as f32 * LEGEND_HEIGHT);
    let frame = egui::Rect::from_min_size(
        origin - egui::vec2(8.0, 26.0),
        egui::vec2(BAR_WIDTH + 110.0, BAR_HEIGHT + 44.0),
    );
    painter.rect_filled(frame, 4.0, egui::Color32::from_black_alpha(150));
    painter.text(
        origin - egui::vec2(0.0, 8.0),
        egui::Align2::LEFT_BOTTOM,
        title,
        egui::FontId::proportional(12.0),
        egui::Color32::from_gray(230),
    );
    let band = BAR_HEIGHT / BANDS as f32;
    for i in 0..BANDS {
        // Top of the bar is the maximum.
        let t = 1.0 - (i as f32 + 0.5) / BANDS as f32;
        let [r, g, b] = mapping.map.sample(t);
        let top = origin.y + i as f32 * band;
        painter.rect_filled(
            egui::Rect::from_min_size(egui::pos2(origin.x, top), egui::vec2(BAR_WIDTH, band + 0.5)),
            0.0,
            egui::Color32::from_rgb(r, g, b),
        );
    }
    let text = |y: f32, t: String| {
        painter.text(
            egui::pos2(origin.x + BAR_WIDTH + 6.0, y),
            egui::Align2::LEFT_CENTER,
            t,
            egui::FontId::monospace(11.0),
            egui::Color32::from_gray(220),
        );
    };
    let label = |y: f32, v: f32| text(y, legend_value(v));
    let mid = 0.5 * (mapping.min + mapping.max);
    let note = if mapping.map == ColourMap::Band {
        // The band's edges are at the quarter marks; beyond them the colours are flat.
        let band = 0.25 * (mapping.max - mapping.min);
        text(origin.y + 0.125 * BAR_HEIGHT, "above band".into());
        label(origin.y + 0.25 * BAR_HEIGHT, mid + band);
        label(origin.y + 0.5 * BAR_HEIGHT, mid);
        label(origin.y + 0.75 * BAR_HEIGHT, mid - band);
        text(origin.y + 0.875 * BAR_HEIGHT, "below band".into());
        format!("tolerance band ±{}", legend_value(band))
    } else {
        label(origin.y, mapping.max);
        label(origin.y + 0.5 * BAR_HEIGHT, mid);
        label(origin.y + BAR_HEIGHT, mapping.min);
        "values beyond the ends are clamped".into()
    };
    painter.text(
        egui::pos2(origin.x, origin.y + BAR_HEIGHT + 6.0),
        egui::Align2::LEFT_TOP,
        note,
        egui::FontId::proportional(10.0),
        egui::Color32::from_gray(160),
    );
}

/// Mark `value` (e.g. a limit) on the bar of the legend in `slot` (drawn by [`legend_ui`] with
/// `mapping`): a red line across the bar and `label` beside it.
pub fn legend_mark_ui(
    ui: &egui::Ui,
    rect: egui::Rect,
    mapping: ScalarMapping,
    slot: usize,
    value: f32,
    label: &str,
) {
    let origin = rect.left_top() + egui::vec2(14.0, 34.0 + slot as f32 * LEGEND_HEIGHT);
    let t = ((value - mapping.min) / (mapping.max - mapping.min).max(1e-12)).clamp(0.0, 1.0);
    let y = origin.y + (1.0 - t) * BAR_HEIGHT;
    let red = egui::Color32::from_rgb(255, 60, 60);
    let painter = ui.painter();
    painter.line_segment(
        [
            egui::pos2(origin.x - 4.0, y),
            egui::pos2(origin.x + BAR_WIDTH + 4.0, y),
        ],
        egui::Stroke::new(2.0, red),
    );
    painter.text(
        egui::pos2(origin.x + BAR_WIDTH + 52.0, y),
        egui::Align2::LEFT_CENTER,
        label,
        egui::FontId::proportional(11.0),
        red,
    );
}

#[cfg(test)]
mod tests {
    use super::legend_value;

    #[test]
    fn legend_values_keep_four_significant_digits() {
        assert_eq!(legend_value(0.2), "0.2000");
        assert_eq!(legend_value(-0.000_5), "-5.000e-4");
        assert_eq!(legend_value(0.0), "0");
        assert_eq!(legend_value(483.266_9), "483.3");
        assert_eq!(legend_value(241.633_4), "241.6");
        assert_eq!(legend_value(0.05), "0.05000");
        assert_eq!(legend_value(-0.012_345), "-0.01235");
        assert_eq!(legend_value(1234.4), "1234");
        assert_eq!(legend_value(12.0), "12.00");
        assert_eq!(legend_value(25_000.0), "2.500e4");
    }
}
