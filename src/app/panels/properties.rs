//! Properties of what the project tree or the viewport points at (right panel), every number
//! with its unit: the part or a face (with the picked surface point), a tool (editable), the
//! stock, the setup, an operation, the machine.

use glam::DVec3;

use super::super::command::Command;
use super::super::document::{Document, Selection};
use super::super::number_field::NumberField;
pub use super::super::state::Focus;
use super::super::viewport::picking::SurfacePick;
use super::super::widgets::grouped;
pub use super::super::widgets::{LENGTH_RANGE_MM, SIZE_RANGE_MM, grid, length_field, mm3};
use super::machine_panel::{MachinePanel, MachinePanelEvent, PostSettings};
use super::operation_editor::{OperationForm, OperationView, operation_editor_ui};
use super::tool_library::{ToolForm, tool_editor_ui};
use crate::diagnostics::Severity;
use crate::project::{DEFAULT_MARGIN_MM, Edit, Project, Stock};

/// What the properties panel reads.
pub struct PropertiesView<'a> {
    /// What to show.
    pub focus: Focus,
    /// The loaded part.
    pub document: Option<&'a Document>,
    /// The project document.
    pub project: &'a Project,
    /// The last surface point clicked in the viewport.
    pub pick: Option<&'a SurfacePick>,
    /// The operation shown (when the focus is an operation).
    pub operation: Option<OperationView<'a>>,
}

/// The editors' working copies.
#[derive(Debug, Default)]
pub struct Forms {
    /// The tool editor's texts.
    pub tool: ToolForm,
    /// The operation editor's draft.
    pub operation: OperationForm,
    /// The machine panel (rebuilt when the project's machine or post settings change).
    pub machine: Option<MachinePanel>,
}

impl std::fmt::Debug for MachinePanel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MachinePanel")
            .field("machine", &self.machine().name)
            .finish_non_exhaustive()
    }
}

/// The properties panel.
pub fn properties_ui(
    ui: &mut egui::Ui,
    view: &PropertiesView<'_>,
    forms: &mut Forms,
    commands: &mut Vec<Command>,
) {
    ui.add_space(4.0);
    ui.label(egui::RichText::new("PROPERTIES").small().strong().weak());
    ui.separator();
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| match view.focus {
            Focus::Selection => {
                selection_ui(ui, view);
                super::super::face_group::group_ui(ui, view.document, view.project, commands);
            }
            Focus::Tool(i) => tool_editor_ui(ui, view.project, i, &mut forms.tool, commands),
            Focus::Stock => stock_ui(ui, view, commands),
            Focus::Setup(i) => {
                super::setup_editor::setup_editor_ui(ui, view.project, view.document, i, commands)
            }
            Focus::Operation(i) => match &view.operation {
                Some(op) if op.index == i => {
                    operation_editor_ui(ui, op, &mut forms.operation, commands);
                }
                _ => {
                    ui.weak("No such operation.");
                }
            },
            Focus::Machine => machine_ui(ui, view.project, &mut forms.machine, commands),
        });
}

fn selection_ui(ui: &mut egui::Ui, view: &PropertiesView<'_>) {
    let Some(doc) = view.document else { return };
    match doc.selection {
        Selection::None => {
            ui.weak("Select the part or a face (click it in the viewport or the project tree).");
        }
        Selection::Part => part_ui(ui, doc),
        Selection::Face(i) => face_ui(ui, doc, i),
    }
    if let Some(pick) = view.pick {
        ui.add_space(8.0);
        pick_ui(ui, pick);
    }
}

/// A length in mm with 3 decimals, or "flat" for an infinite radius.
fn radius_text(k: f64) -> String {
    if k.abs() < 1e-9 {
        "infinite (flat)".to_string()
    } else {
        format!("{:.3} mm", 1.0 / k)
    }
}

fn pick_ui(ui: &mut egui::Ui, pick: &SurfacePick) {
    ui.label(egui::RichText::new("Picked point").strong());
    let mut rows = vec![
        ("Face", format!("{}", pick.face + 1)),
        ("(u, v)", format!("({:.6}, {:.6})", pick.uv.x, pick.uv.y)),
        ("Point", mm3(pick.point)),
        ("Distance to mesh", format!("{:.4} mm", pick.distance_mm)),
    ];
    match pick.normal {
        Some(n) => rows.push(("Normal", format!("{:.4}, {:.4}, {:.4}", n.x, n.y, n.z))),
        None => rows.push(("Normal", "undefined (degenerate point)".into())),
    }
    if let Some((k_min, k_max)) = pick.curvature {
        rows.push(("k_min", format!("{k_min:.5} 1/mm")));
        rows.push(("k_max", format!("{k_max:.5} 1/mm")));
        rows.push(("Radius (k_min)", radius_text(k_min)));
        rows.push(("Radius (k_max)", radius_text(k_max)));
    }
    grid(ui, "pick", &rows);
    ui.weak("Curvatures are signed about the face normal: positive where the surface bends toward it (a pocket's fillet), negative where it bends away (a convex edge).");
}

fn stock_ui(ui: &mut egui::Ui, view: &PropertiesView<'_>, commands: &mut Vec<Command>) {
    ui.heading("Stock");
    // Every size is editable (drag or type; applied when the drag ends or the value is typed);
    // the edit is refused with the reason when the stock would be empty.
    let mut next = view.project.stock;
    egui::Grid::new("stock fields")
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, |ui| match &mut next {
            Stock::None => {
                ui.label("Kind");
                ui.label("none (roughing and simulation use the part's box + 2 mm)");
                ui.end_row();
            }
            Stock::Box { min_mm, max_mm } => {
                ui.label("Kind");
                ui.label("box");
                ui.end_row();
                for (name, v) in [("Min", min_mm), ("Max", max_mm)] {
                    ui.label(name);
                    ui.horizontal(|ui| {
                        for (k, x) in v.iter_mut().enumerate() {
                            length_field(ui, (name, k), x, LENGTH_RANGE_MM, 60.0);
                        }
                    });
                    ui.end_row();
                }
            }
            Stock::Cylinder {
                base_mm,
                radius_mm,
                height_mm,
            } => {
                ui.label("Kind");
                ui.label("cylinder (axis +Z)");
                ui.end_row();
                ui.label("Base centre");
                ui.horizontal(|ui| {
                    for (k, x) in base_mm.iter_mut().enumerate() {
                        length_field(ui, ("Base", k), x, LENGTH_RANGE_MM, 60.0);
                    }
                });
                ui.end_row();
                ui.label("Radius");
                length_field(ui, "Radius", radius_mm, SIZE_RANGE_MM, 80.0);
                ui.end_row();
                ui.label("Height");
                length_field(ui, "Height", height_mm, SIZE_RANGE_MM, 80.0);
                ui.end_row();
            }
        });
    if let Stock::Box { min_mm, max_mm } = view.project.stock {
        grid(
            ui,
            "stock size",
            &[(
                "Size",
                mm3(DVec3::from_array(max_mm) - DVec3::from_array(min_mm)),
            )],
        );
    }
    if next != view.project.stock {
        commands.push(Command::Edit(Edit::SetStock(next)));
    }
    ui.add_space(8.0);
    let bounds = view.document.map(|d| d.bounds).filter(|b| !b.is_empty());
    ui.add_enabled_ui(bounds.is_some(), |ui| {
        ui.horizontal_wrapped(|ui| {
            if let Some(b) = bounds {
                if ui.button("Box around part +2 mm (sides, top)").clicked() {
                    commands.push(Command::Edit(Edit::SetStock(
                        Stock::None.or_default_for(&b),
                    )));
                }
                if ui
                    .button("Cylinder around part +2 mm (sides, top)")
                    .on_hover_text("The smallest upright cylinder around the part's mesh")
                    .clicked()
                {
                    let points = view.document.map(|d| d.part.mesh().positions.as_slice());
                    let cylinder = points
                        .and_then(|p| Stock::cylinder_enclosing(p, DEFAULT_MARGIN_MM))
                        .unwrap_or_else(|| Stock::default_cylinder_for(&b));
                    commands.push(Command::Edit(Edit::SetStock(cylinder)));
                }
            }
        });
    });
    if view.project.stock != Stock::None && ui.button("No stock").clicked() {
        commands.push(Command::Edit(Edit::SetStock(Stock::None)));
    }
    ui.add_space(8.0);
    material_ui(ui, view.project, commands);
}

/// The stock's work material and the tools' material: the operations' feeds and speeds come
/// from the cutting-data library for them (each operation's editor shows how).
fn material_ui(ui: &mut egui::Ui, project: &Project, commands: &mut Vec<Command>) {
    use crate::force::cutting_data::{MATERIALS, ToolMaterial};
    use crate::project::cutting::WorkMaterial;
    let current = project.material.clone();
    let mut next = current.clone();
    egui::Grid::new("work material")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Material");
            let shown = current.as_ref().map_or_else(
                || "None (feeds typed)".to_string(),
                |m| {
                    m.material().map_or_else(
                        |_| format!("{} (not in the library)", m.key),
                        |l| l.name.to_string(),
                    )
                },
            );
            egui::ComboBox::from_id_salt("work material")
                .selected_text(shown)
                .show_ui(ui, |ui| {
                    if ui
                        .selectable_label(next.is_none(), "None (feeds typed)")
                        .clicked()
                    {
                        next = None;
                    }
                    for m in &MATERIALS {
                        let on = next.as_ref().is_some_and(|w| w.key == m.key);
                        if ui.selectable_label(on, m.name).clicked() {
                            next = Some(WorkMaterial {
                                key: m.key.to_string(),
                                tool_material: next
                                    .as_ref()
                                    .map_or(ToolMaterial::Carbide, |w| w.tool_material),
                            });
                        }
                    }
                });
            ui.end_row();
            if let Some(w) = next.as_mut() {
                ui.label("Tool material");
                ui.horizontal(|ui| {
                    ui.radio_value(&mut w.tool_material, ToolMaterial::Carbide, "Carbide");
                    ui.radio_value(&mut w.tool_material, ToolMaterial::Hss, "HSS");
                });
                ui.end_row();
            }
        });
    if next != current {
        commands.push(Command::Edit(Edit::SetMaterial(next)));
    }
}

fn machine_ui(
    ui: &mut egui::Ui,
    project: &Project,
    panel: &mut Option<MachinePanel>,
    commands: &mut Vec<Command>,
) {
    ui.heading("Machine");
    let settings = PostSettings {
        dialect: project.post.dialect.clone(),
        tcp: project.post.tcp,
        work_offset: 53 + project.first_setup().frame.work_offset,
    };
    let stale = panel
        .as_ref()
        .is_none_or(|p| p.machine().name != project.machine || *p.settings() != settings);
    if stale {
        match crate::machine::Machine::resolve(&project.machine) {
            Ok(m) => *panel = Some(MachinePanel::new(m, settings.clone())),
            Err(e) => {
                ui.colored_label(
                    super::super::theme::ERROR,
                    format!("Machine '{}' not found: {e}", project.machine),
                );
                *panel = None;
            }
        }
    }
    let Some(p) = panel.as_mut() else {
        return;
    };
    let apply = |s: PostSettings| {
        let mut edits = Vec::new();
        if s.dialect != project.post.dialect || s.tcp != project.post.tcp {
            edits.push(Edit::SetPost(crate::project::PostConfig {
                dialect: s.dialect.clone(),
                tcp: s.tcp,
                ..project.post.clone()
            }));
        }
        let offset = s.work_offset.saturating_sub(53);
        let frame = project.first_setup().frame;
        if offset != frame.work_offset {
            edits.push(Edit::SetFrame {
                setup: 0,
                frame: crate::project::Frame {
                    work_offset: offset,
                    ..frame
                },
            });
        }
        edits
    };
    match p.ui(ui) {
        Some(MachinePanelEvent::MachineChosen { name, settings }) => {
            let mut edits = vec![Edit::SetMachine(name)];
            edits.extend(apply(settings));
            commands.push(Command::Edit(Edit::Batch(edits)));
        }
        Some(MachinePanelEvent::PostSettingsChanged(settings)) => {
            let edits = apply(settings);
            if !edits.is_empty() {
                commands.push(Command::Edit(Edit::Batch(edits)));
            }
        }
        Some(MachinePanelEvent::OpenMachineFile) => {
            commands.push(Command::OpenMachineFileDialog);
        }
        None => {}
    }
    ui.add_space(6.0);
    let mut rpm = project.post.spindle_rpm;
    ui.horizontal(|ui| {
        let l = ui.label("Spindle speed");
        let typed = NumberField::new("Spindle speed", &mut rpm)
            .labelled_by(l.id)
            .range(0.0..=100_000.0)
            .decimals(0)
            .unit("rpm")
            .show(ui);
        if typed && rpm != project.post.spindle_rpm {
            commands.push(Command::Edit(Edit::SetPost(crate::project::PostConfig {
                spindle_rpm: rpm,
                ..project.post.clone()
            })));
        }
    });
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
        ("Triangles", grouped(part.mesh().triangles.len())),
        ("Vertices", grouped(part.mesh().positions.len())),
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
