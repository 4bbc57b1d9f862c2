//! The one number field of the workstation: every numeric property (operation parameters, stock,
//! setup, post, tool sizes, reduction settings) is typed through it.
//!
//! - The value is typed as text; nothing changes while typing. It is applied when confirmed
//!   (Enter, Tab or a click elsewhere), so one edit is one undo step; Escape drops the typing.
//! - A value that is not a number, or lies outside the field's range, is refused: the old value
//!   stays and the reason is shown under the field (in red) until the next accepted value.
//! - Dragging over the field does nothing (it is a text field, not a drag value).
//! - The value is kept in internal units (mm, rad) and shown × `scale` in the field's unit
//!   (mm, °, mm/min, rpm); a typed unit suffix ("6 mm") is accepted.

use std::fmt::Debug;
use std::hash::Hash;
use std::ops::RangeInclusive;

use super::theme;

/// What is kept between frames for one field.
#[derive(Clone, Debug, Default)]
struct FieldState {
    /// The text being typed (while the field has focus).
    text: String,
    /// The text the field showed when typing began (unchanged text is no edit).
    original: String,
    /// Is the user typing in the field?
    editing: bool,
    /// Why the last typed value was refused.
    error: Option<String>,
}

/// A number field (see the module documentation). Build it with [`NumberField::new`], set its
/// unit, scale and range, and [`NumberField::show`] it.
#[must_use = "show the field with NumberField::show"]
pub struct NumberField<'a> {
    id: egui::Id,
    value: &'a mut f64,
    scale: f64,
    range: RangeInclusive<f64>,
    decimals: usize,
    unit: &'a str,
    width: f32,
    labelled_by: Option<egui::Id>,
}

impl<'a> NumberField<'a> {
    /// A field for `value`; `id_salt` tells it from the other fields of the same `Ui` (its label
    /// is a good salt). Defaults: no unit, scale 1, any finite value, 4 decimals.
    pub fn new(id_salt: impl Hash + Debug, value: &'a mut f64) -> Self {
        Self {
            id: egui::Id::unique(id_salt),
            value,
            scale: 1.0,
            range: f64::MIN..=f64::MAX,
            decimals: 4,
            unit: "",
            width: 80.0,
            labelled_by: None,
        }
    }

    /// The unit shown after the field ("mm", "°", "mm/min").
    pub fn unit(mut self, unit: &'a str) -> Self {
        self.unit = unit;
        self
    }

    /// Shown value = internal value × `scale` (e.g. degrees per radian).
    pub fn scale(mut self, scale: f64) -> Self {
        self.scale = scale;
        self
    }

    /// The values accepted, in the shown unit; others are refused with the reason.
    pub fn range(mut self, range: RangeInclusive<f64>) -> Self {
        self.range = range;
        self
    }

    /// Decimals shown (trailing zeros are dropped).
    pub fn decimals(mut self, decimals: usize) -> Self {
        self.decimals = decimals;
        self
    }

    /// Width of the text, points.
    pub fn width(mut self, width: f32) -> Self {
        self.width = width;
        self
    }

    /// The label that names the field (for screen readers and tests).
    pub fn labelled_by(mut self, label: egui::Id) -> Self {
        self.labelled_by = Some(label);
        self
    }

    /// Draw the field; true when a new value was accepted and written to the value this frame.
    pub fn show(self, ui: &mut egui::Ui) -> bool {
        let id = ui.make_persistent_id(self.id);
        let mut state: FieldState = ui.data(|d| d.get_temp(id)).unwrap_or_default();
        let shown = format_number(*self.value * self.scale, self.decimals);
        if !state.editing {
            state.text.clone_from(&shown);
        }
        let mut committed = false;
        ui.vertical(|ui| {
            ui.horizontal(|ui| {
                let mut r = ui.add(
                    egui::TextEdit::singleline(&mut state.text)
                        .id(id)
                        .desired_width(self.width),
                );
                if let Some(label) = self.labelled_by {
                    r = r.labelled_by(label);
                }
                let r = r.on_hover_text(range_text(&self.range, self.unit));
                if r.gained_focus() || (r.has_focus() && !state.editing) {
                    state.editing = true;
                    state.original.clone_from(&shown);
                }
                if r.lost_focus() {
                    state.editing = false;
                    let dropped = ui.input(|i| i.key_pressed(egui::Key::Escape));
                    if !dropped && state.text.trim() != state.original.trim() {
                        match parse_in_range(&state.text, self.unit, &self.range) {
                            Ok(v) => {
                                state.error = None;
                                let new = v / self.scale;
                                if new != *self.value {
                                    *self.value = new;
                                    committed = true;
                                }
                            }
                            Err(reason) => state.error = Some(reason),
                        }
                    }
                }
                if !self.unit.is_empty() {
                    ui.label(self.unit);
                }
            });
            if let Some(e) = &state.error {
                ui.colored_label(theme::ERROR, format!("Not applied: {e}"));
            }
        });
        ui.data_mut(|d| d.insert_temp(id, state));
        committed
    }
}

/// `v` with `decimals` decimals, trailing zeros dropped ("0.07", "10000", "-2.5").
#[must_use]
pub fn format_number(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".into() } else { s }
}

/// The typed `text` (a number, optionally followed by `unit`) if it lies in `range`; else why not.
///
/// # Errors
/// Not a number, not finite, below the smallest or above the largest value allowed.
pub fn parse_in_range(text: &str, unit: &str, range: &RangeInclusive<f64>) -> Result<f64, String> {
    let t = text.trim();
    let t = t.strip_suffix(unit.trim()).unwrap_or(t).trim();
    let unit_text = |v: f64| {
        if unit.is_empty() {
            format_number(v, 6)
        } else {
            format!("{} {unit}", format_number(v, 6))
        }
    };
    let v: f64 = t
        .parse()
        .map_err(|_| format!("'{}' is not a number", text.trim()))?;
    if !v.is_finite() {
        return Err(format!("'{}' is not a finite number", text.trim()));
    }
    if v < *range.start() {
        return Err(format!(
            "{} is below the smallest value allowed, {}",
            unit_text(v),
            unit_text(*range.start())
        ));
    }
    if v > *range.end() {
        return Err(format!(
            "{} is above the largest value allowed, {}",
            unit_text(v),
            unit_text(*range.end())
        ));
    }
    Ok(v)
}

/// "Type a value from 0.0001 to 5 mm; Enter applies it" (or without limits).
fn range_text(range: &RangeInclusive<f64>, unit: &str) -> String {
    if *range.start() <= f64::MIN && *range.end() >= f64::MAX {
        return format!("Type a value in {unit}; Enter applies it, Escape drops it");
    }
    format!(
        "Type a value from {} to {} {unit}; Enter applies it, Escape drops it",
        format_number(*range.start(), 6),
        format_number(*range.end(), 6)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_shown_without_binary_noise_or_trailing_zeros() {
        assert_eq!(format_number(10_000.0, 4), "10000");
        assert_eq!(format_number(0.07, 4), "0.07");
        assert_eq!(format_number(45.000_000_000_01, 2), "45");
        assert_eq!(format_number(-0.000_01, 3), "0");
        assert_eq!(format_number(-2.5, 3), "-2.5");
    }

    #[test]
    fn typed_values_outside_the_range_are_refused_with_the_reason() {
        let feed = 1.0..=100_000.0;
        assert_eq!(parse_in_range(" 2500 ", "mm/min", &feed), Ok(2500.0));
        assert_eq!(parse_in_range("2500 mm/min", "mm/min", &feed), Ok(2500.0));
        let e = parse_in_range("250000", "mm/min", &feed).expect_err("too fast");
        assert_eq!(
            e,
            "250000 mm/min is above the largest value allowed, 100000 mm/min"
        );
        let e = parse_in_range("0", "mm/min", &feed).expect_err("too slow");
        assert!(
            e.contains("below the smallest value allowed, 1 mm/min"),
            "{e}"
        );
        let e = parse_in_range("fast", "mm/min", &feed).expect_err("text");
        assert_eq!(e, "'fast' is not a number");
        assert!(parse_in_range("NaN", "", &feed).is_err());
        assert!(parse_in_range("inf", "", &(f64::MIN..=f64::MAX)).is_err());
    }
}
