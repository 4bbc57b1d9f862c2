//! The project tree (left panel): the part and its faces. Shows only what exists.

use super::super::command::Command;
use super::super::document::{Document, Selection};
use super::grouped;

/// The project tree.
pub fn project_tree_ui(
    ui: &mut egui::Ui,
    document: Option<&Document>,
    commands: &mut Vec<Command>,
) {
    ui.add_space(4.0);
    ui.label(egui::RichText::new("PROJECT").small().strong().weak());
    ui.separator();
    let Some(doc) = document else {
        ui.weak("No part open. File → Open… (Ctrl+O) or drop a STEP or STL file here.");
        return;
    };
    let part = &doc.part;
    let part_selected = doc.selection == Selection::Part;
    egui::CollapsingHeader::new(egui::RichText::new(part.name.as_str()).strong())
        .id_salt("part")
        .default_open(true)
        .show(ui, |ui| {
            if ui
                .selectable_label(
                    part_selected,
                    format!("Part · {} triangles", grouped(part.mesh.triangles.len())),
                )
                .clicked()
            {
                commands.push(Command::Select(Selection::Part));
            }
            if part.faces.is_empty() {
                return;
            }
            egui::CollapsingHeader::new(format!("Faces ({})", part.faces.len()))
                .id_salt("faces")
                .default_open(true)
                .show(ui, |ui| {
                    let row_height = ui.spacing().interact_size.y;
                    egui::ScrollArea::vertical()
                        .max_height(ui.available_height().max(120.0))
                        .auto_shrink([false, true])
                        .show_rows(ui, row_height, part.faces.len(), |ui, rows| {
                            for i in rows {
                                let Some(face) = part.faces.get(i) else {
                                    continue;
                                };
                                let id = if face.source_id > 0 {
                                    format!("  #{}", face.source_id)
                                } else {
                                    String::new()
                                };
                                let selected = doc.selection == Selection::Face(i);
                                if ui
                                    .selectable_label(
                                        selected,
                                        format!("Face {}  {}{id}", i + 1, face.kind),
                                    )
                                    .clicked()
                                {
                                    commands.push(Command::Select(Selection::Face(i)));
                                }
                            }
                        });
                });
        });
    if part_selected || matches!(doc.selection, Selection::Face(_)) {
        ui.add_space(6.0);
    }
}
