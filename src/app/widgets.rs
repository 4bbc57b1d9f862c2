//! Small widgets and formatters the panels share: grouped thousands, two-column value grids,
//! points in mm, durations and the length field.

use glam::DVec3;

use super::number_field::NumberField;

/// A number with thousands separated by thin spaces (`21 450`).
#[must_use]
pub fn grouped(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
}

/// A length in mm typed in a [`NumberField`] `width` points wide: applied (true) when confirmed
/// with Enter or by leaving the field, refused with the reason outside `range`.
pub fn length_field(
    ui: &mut egui::Ui,
    salt: impl std::hash::Hash + std::fmt::Debug,
    value: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    width: f32,
) -> bool {
    NumberField::new(salt, value)
        .range(range)
        .decimals(4)
        .unit("mm")
        .width(width)
        .show(ui)
}

/// Rows of (name, value) in two columns, the values monospaced.
pub fn grid(ui: &mut egui::Ui, id: &str, rows: &[(&str, String)]) {
    egui::Grid::new(id)
        .num_columns(2)
        .spacing([12.0, 4.0])
        .striped(true)
        .show(ui, |ui| {
            for (name, value) in rows {
                ui.weak(*name);
                ui.label(egui::RichText::new(value).monospace());
                ui.end_row();
            }
        });
}

/// A point or vector in mm with 3 decimals.
pub fn mm3(v: DVec3) -> String {
    format!("{:.3}, {:.3}, {:.3} mm", v.x, v.y, v.z)
}

/// Seconds as `1 h 02 min`, `3 min 05 s` or `12.3 s`.
#[must_use]
pub fn duration_text(s: f64) -> String {
    if !s.is_finite() {
        return "—".into();
    }
    let whole = s.round() as u64;
    if whole >= 3600 {
        format!("{} h {:02} min", whole / 3600, (whole % 3600) / 60)
    } else if whole >= 60 {
        format!("{} min {:02} s", whole / 60, whole % 60)
    } else {
        format!("{s:.1} s")
    }
}

/// Coordinates accepted for the stock and the work offset, mm (±100 m).
pub const LENGTH_RANGE_MM: std::ops::RangeInclusive<f64> = -1e5..=1e5;
/// Sizes accepted for the stock, mm (1 µm to 100 m).
pub const SIZE_RANGE_MM: std::ops::RangeInclusive<f64> = 1e-3..=1e5;

#[cfg(test)]
mod tests {
    #[test]
    fn thousands_are_grouped() {
        assert_eq!(super::grouped(21_450), "21\u{2009}450");
        assert_eq!(super::grouped(999), "999");
        assert_eq!(super::grouped(1_000_000), "1\u{2009}000\u{2009}000");
    }
}
