//! The operation editor's "Feeds and speeds" section: what the cutting-data library gives this
//! operation for the stock's material (spindle speed, feeds, chip, removal rate, each with its
//! unit), whether the operation's numbers are the library's or typed, a button writing the
//! library's in, and a line per number saying where it came from
//! ([`crate::project::cutting`]).

use super::super::super::command::Command;
use super::super::super::theme;
use super::super::super::widgets::grid;
use crate::project::cutting::{self, OperationSpeeds};
use crate::project::{Edit, Operation, Project};

/// The section for operation `index` (`current` as the project holds it).
pub fn cutting_data_ui(
    ui: &mut egui::Ui,
    project: &Project,
    index: usize,
    current: &Operation,
    commands: &mut Vec<Command>,
) {
    egui::CollapsingHeader::new("Feeds and speeds")
        .id_salt(("feeds and speeds", index))
        .default_open(project.material.is_some())
        .show(ui, |ui| {
            if project.material.is_none() {
                ui.weak(
                    "Choose the stock's material (Stock, in the project tree) for feeds and \
                     speeds from the cutting-data library; until then they are typed.",
                );
                return;
            }
            match cutting::suggest(project, index) {
                Ok(s) => suggestion_ui(ui, project, index, current, &s, commands),
                Err(e) => {
                    ui.colored_label(theme::WARNING, format!("⚠ {e}"));
                }
            }
        });
}

fn suggestion_ui(
    ui: &mut egui::Ui,
    project: &Project,
    index: usize,
    current: &Operation,
    s: &OperationSpeeds,
    commands: &mut Vec<Command>,
) {
    let material = project
        .material
        .as_ref()
        .and_then(|m| Some((m.material().ok()?.name, m.tool_material.name())));
    if let Some((name, tool)) = material {
        ui.label(format!("{name}, {tool} tool"));
    }
    let sp = &s.speeds;
    grid(
        ui,
        "library speeds",
        &[
            ("Spindle speed", format!("{:.0} rpm", sp.spindle_rpm)),
            (
                "Cutting speed",
                format!("{:.0} m/min", sp.cutting_speed_m_min),
            ),
            ("Feed", format!("{:.0} mm/min", sp.feed_mm_min)),
            ("Ramp feed", format!("{:.0} mm/min", sp.ramp_feed_mm_min)),
            (
                "Plunge feed",
                format!("{:.0} mm/min", sp.plunge_feed_mm_min),
            ),
            (
                "Feed per tooth",
                format!(
                    "{:.4} mm ({} flutes, chip thinning ×{:.2})",
                    sp.feed_per_tooth_mm, s.flutes, sp.chip_thinning
                ),
            ),
            (
                "Engagement",
                format!("a_e {:.3} mm · a_p {:.3} mm", s.radial_mm, s.axial_mm),
            ),
            ("Removal rate", format!("{:.2} cm³/min", sp.removal_cm3_min)),
        ],
    );
    if cutting::follows(current, s) {
        ui.label("✔ The operation's feeds and speeds are the library's.");
    } else {
        ui.horizontal_wrapped(|ui| {
            ui.weak("The operation's feeds are typed.");
            if ui
                .button("Use the library's feeds and speeds")
                .on_hover_text(
                    "Write the spindle speed and the feeds above into the operation (one \
                     undo step)",
                )
                .clicked()
            {
                commands.push(Command::Edit(Edit::SetOperation {
                    index,
                    operation: cutting::apply(current.clone(), s),
                }));
            }
        });
    }
    egui::CollapsingHeader::new("Where each number came from")
        .id_salt(("speeds sources", index))
        .show(ui, |ui| {
            for line in s.sources() {
                // The UI font has no arrow, root or pi glyphs.
                let from = line
                    .from
                    .replace('→', "->")
                    .replace('√', "sqrt")
                    .replace('π', "pi");
                ui.label(format!("{}: {from}", line.quantity));
            }
        });
}
