//! Properties of the selection (right panel), every number with its unit.

use glam::DVec3;

use super::super::document::{Document, Selection};
use super::grouped;
use crate::diagnostics::Severity;

/// The properties panel.
pub fn properties_ui(ui: &mut egui::Ui, document: Option<&Document>) {
    ui.add_space(4.0);
    ui.label(egui::RichText::new("PROPERTIES").small().strong().weak());
    ui.separator();
    let Some(doc) = document else { return };
    match doc.selection {
        Selection::None => {
            ui.weak("Select the part or a face (click it in the viewport or the project tree).");
        }
        Selection::Part => part_ui(ui, doc),
        Selection::Face(i) => face_ui(ui, doc, i),
    }
}

fn grid(ui: &mut egui::Ui, id: &str, rows: &[(&str, String)]) {
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

fn mm3(v: DVec3) -> String {
    format!("{:.3}, {:.3}, {:.3} mm", v.x, v.y, v.z)
}

fn part_ui(ui: &mut egui::Ui, doc: &Document) {
    let part = &doc.part;
    ui.heading(&part.name);
    let size = doc.bounds.max - doc.bounds.min;
    let mut rows = vec![
        (
            "File",
            part.path
                .file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
        ),
        ("Format", part.format.to_string()),
    ];
    if !part.product_name.is_empty() {
        rows.push(("Product", part.product_name.clone()));
    }
    if !part.faces.is_empty() {
        rows.push(("Faces", grouped(part.faces.len())));
    }
    rows.extend([
        ("Triangles", grouped(part.mesh.triangles.len())),
        ("Vertices", grouped(part.mesh.positions.len())),
        ("Surface area", format!("{:.2} mm²", doc.area_mm2)),
    ]);
    grid(ui, "part", &rows);
    if !doc.bounds.is_empty() {
        ui.add_space(8.0);
        ui.label(egui::RichText::new("Bounding box").strong());
        grid(
            ui,
            "part-bounds",
            &[
                ("Size X", format!("{:.3} mm", size.x)),
                ("Size Y", format!("{:.3} mm", size.y)),
                ("Size Z", format!("{:.3} mm", size.z)),
                ("Min", mm3(doc.bounds.min)),
                ("Max", mm3(doc.bounds.max)),
            ],
        );
    }
    let warnings = part
        .diagnostics
        .iter()
        .filter(|d| d.severity >= Severity::Warning)
        .count();
    if !part.diagnostics.is_empty() {
        ui.add_space(8.0);
        ui.label(format!(
            "Import notes: {} ({warnings} warnings), see the log",
            part.diagnostics.len()
        ));
    }
    ui.add_space(8.0);
    ui.weak(part.path.display().to_string());
}

fn face_ui(ui: &mut egui::Ui, doc: &Document, i: usize) {
    let Some(face) = doc.part.faces.get(i) else {
        return;
    };
    ui.heading(format!("Face {}", i + 1));
    let mut rows = vec![("Surface", face.kind.clone())];
    if face.source_id > 0 {
        rows.push(("STEP entity", format!("#{}", face.source_id)));
    }
    rows.push((
        "Triangles",
        grouped(doc.face_triangles.get(i).copied().unwrap_or(0)),
    ));
    rows.push((
        "Area",
        format!(
            "{:.2} mm²",
            doc.face_area_mm2.get(i).copied().unwrap_or(0.0)
        ),
    ));
    grid(ui, "face", &rows);
}
