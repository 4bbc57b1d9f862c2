//! The panels around the viewport. Each reads the state it shows and returns [`super::command::Command`]s;
//! none changes the document itself.

pub mod gcode_view;
pub mod log_panel;
pub mod machine_panel;
pub mod menu_bar;
pub mod motion_plots;
pub mod operation_editor;
pub mod playback;
pub mod project_dialogs;
pub mod project_tree;
pub mod properties;
pub mod reduction_view;
pub mod status_bar;
pub mod tool_library;

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

#[cfg(test)]
mod tests {
    #[test]
    fn thousands_are_grouped() {
        assert_eq!(super::grouped(21_450), "21\u{2009}450");
        assert_eq!(super::grouped(999), "999");
        assert_eq!(super::grouped(1_000_000), "1\u{2009}000\u{2009}000");
    }
}
