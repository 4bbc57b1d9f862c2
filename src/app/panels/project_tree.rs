//! The project tree (left panel): the project's part (and its faces), stock, setup and work
//! offset, tools, operations and machine, read from the project document and the loaded part.

use super::super::command::Command;
use super::super::document::{Document, Selection};
use super::super::state::Focus;
use super::super::widgets::grouped;
use super::operation_editor::add_operation_ui;
use super::setup_editor::{add_setup_after, setup_summary};
use super::tool_library::tool_list_ui;
use crate::project::{Project, Stock};

/// One-line description of the stock.
#[must_use]
pub fn stock_summary(stock: &Stock) -> String {
    match *stock {
        Stock::None => "none".into(),
        Stock::Box { min_mm, max_mm } => format!(
            "box {:.1} × {:.1} × {:.1} mm",
            max_mm[0] - min_mm[0],
            max_mm[1] - min_mm[1],
            max_mm[2] - min_mm[2]
        ),
        Stock::Cylinder {
            radius_mm,
            height_mm,
            ..
        } => format!("cylinder Ø{:.1} × {:.1} mm", 2.0 * radius_mm, height_mm),
    }
}

/// The project tree.
pub fn project_tree_ui(
    ui: &mut egui::Ui,
    document: Option<&Document>,
    project: &Project,
    focus: Focus,
    commands: &mut Vec<Command>,
) {
    ui.add_space(4.0);
    ui.label(egui::RichText::new("PROJECT").small().strong().weak());
    ui.separator();
    ui.label(egui::RichText::new(project.name.as_str()).strong());
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            part_ui(ui, document, project, focus, commands);
            let mut leaf = |ui: &mut egui::Ui, f: Focus, text: String| {
                if ui.selectable_label(focus == f, text).clicked() {
                    commands.push(Command::Inspect(f));
                }
            };
            leaf(
                ui,
                Focus::Stock,
                format!("Stock · {}", stock_summary(&project.stock)),
            );
            egui::CollapsingHeader::new(format!("Tools ({})", project.tools.len()))
                .id_salt("tools")
                .default_open(true)
                .show(ui, |ui| tool_list_ui(ui, project, focus, commands));
            egui::CollapsingHeader::new(format!(
                "Job · {} setups, {} operations",
                project.setups.len(),
                project.operations.len()
            ))
            .id_salt("operations")
            .default_open(true)
            .show(ui, |ui| {
                if project.operations.is_empty() {
                    first_job_ui(ui, document, project);
                }
                job_ui(ui, project, focus, commands);
                add_operation_ui(
                    ui,
                    document.is_some_and(|d| !d.part.faces.is_empty()),
                    commands,
                );
            });
            let mut leaf = |ui: &mut egui::Ui, f: Focus, text: String| {
                if ui.selectable_label(focus == f, text).clicked() {
                    commands.push(Command::Inspect(f));
                }
            };
            leaf(ui, Focus::Machine, format!("Machine · {}", project.machine));
        });
}

/// The steps of a first job, each ticked once done (shown while the project has no operation).
#[must_use]
pub fn first_job_steps(document: Option<&Document>, project: &Project) -> Vec<(bool, String)> {
    let has_faces = document.is_some_and(|d| !d.part.faces.is_empty());
    let picked = document.is_some_and(|d| matches!(d.selection, Selection::Face(_)));
    let face = if has_faces {
        "Pick a face in the view (a click) or under Part: 5-axis finishing machines it, the \
         3-axis kinds the whole part"
    } else {
        "A mesh part: the 3-axis operations machine the whole part (5-axis finishing needs a \
         STEP part's faces)"
    };
    let tool = match project.selected_tool.and_then(|i| project.tools.get(i)) {
        Some(t) => format!("Choose the tool under Tools: {} is chosen", t.name),
        None => "Choose the tool under Tools (+ Tool adds one)".to_string(),
    };
    vec![
        (
            document.is_some(),
            "Open a part: File > Open… or drop a STEP or STL file".into(),
        ),
        (picked || (document.is_some() && !has_faces), face.into()),
        (project.selected_tool.is_some(), tool),
        (false, "+ Operation below: choose a strategy".into()),
        (
            false,
            "Calculate in its editor (F5), then Simulate (F6) and Post G-code (F7)".into(),
        ),
    ]
}

/// The first-job guide: what to do next, each step ticked once done.
fn first_job_ui(ui: &mut egui::Ui, document: Option<&Document>, project: &Project) {
    egui::Frame::group(ui.style()).show(ui, |ui| {
        ui.label(egui::RichText::new("First job").strong());
        for (k, (done, text)) in first_job_steps(document, project).into_iter().enumerate() {
            let mark = if done { "✔" } else { " " };
            let text = format!("{mark} {}. {text}", k + 1);
            if done {
                ui.weak(text);
            } else {
                ui.label(text);
            }
        }
    });
}

/// The job: each setup (selectable: its editor) with its operations in machining order.
fn job_ui(ui: &mut egui::Ui, project: &Project, focus: Focus, commands: &mut Vec<Command>) {
    for (s, setup) in project.setups.iter().enumerate() {
        let id = ui.make_persistent_id(("setup row", s));
        egui::collapsing_header::CollapsingState::load_with_default_open(ui.ctx(), id, true)
            .show_header(ui, |ui| {
                if ui
                    .selectable_label(
                        focus == Focus::Setup(s),
                        egui::RichText::new(format!("{}. {}", s + 1, setup.name)).strong(),
                    )
                    .on_hover_text(format!(
                        "{} · machine {}",
                        setup_summary(setup),
                        setup.machine_name(project)
                    ))
                    .clicked()
                {
                    commands.push(Command::Inspect(Focus::Setup(s)));
                }
                ui.weak(setup.frame.work_offset_code());
            })
            .body(|ui| {
                if setup.operations.is_empty() {
                    ui.weak("No operation yet");
                }
                for &i in &setup.operations {
                    let Some(op) = project.operations.get(i) else {
                        continue;
                    };
                    let tool = project
                        .tools
                        .get(op.tool())
                        .map_or_else(|| "no tool".to_string(), |t| t.name.clone());
                    if ui
                        .selectable_label(
                            focus == Focus::Operation(i),
                            format!("{}. {}", i + 1, op.name()),
                        )
                        .on_hover_text(format!("{} · T{} {tool}", op.kind().label(), op.tool() + 1))
                        .clicked()
                    {
                        commands.push(Command::Inspect(Focus::Operation(i)));
                    }
                }
            });
    }
    if ui
        .small_button("+ Setup")
        .on_hover_text("A new setup after the last, turned over, from what the last one leaves")
        .clicked()
    {
        let last = project.setups.len().saturating_sub(1);
        commands.push(add_setup_after(project, last));
        commands.push(Command::Inspect(Focus::Setup(last + 1)));
    }
}

fn part_ui(
    ui: &mut egui::Ui,
    document: Option<&Document>,
    project: &Project,
    focus: Focus,
    commands: &mut Vec<Command>,
) {
    let Some(doc) = document else {
        let what = project.part.as_ref().map_or_else(
            || "the default part".to_string(),
            |p| p.path.display().to_string(),
        );
        ui.weak(format!("Part · {what} (not loaded)"));
        ui.weak("File > Open… (Ctrl+O) or drop a STEP or STL file here.");
        return;
    };
    let part = &doc.part;
    let part_selected = focus == Focus::Selection && doc.selection == Selection::Part;
    let features_ui = |ui: &mut egui::Ui, commands: &mut Vec<Command>| {
        if part.features.is_empty() {
            return;
        }
        egui::CollapsingHeader::new(format!("Features ({})", part.features.len()))
            .id_salt("features")
            .default_open(part.features.len() <= 12)
            .show(ui, |ui| {
                for f in &part.features {
                    let Some(&first) = f.faces.first() else {
                        continue;
                    };
                    let selected = doc.selection == Selection::Face(first);
                    let faces: Vec<String> = f.faces.iter().map(|i| (i + 1).to_string()).collect();
                    if ui
                        .selectable_label(selected, f.text.as_str())
                        .on_hover_text(format!(
                            "Faces {} (a click selects the first)",
                            faces.join(", ")
                        ))
                        .clicked()
                    {
                        commands.push(Command::Select(Selection::Face(first)));
                    }
                }
            });
    };
    if ui
        .selectable_label(
            part_selected,
            format!(
                "Part · {} · {} triangles",
                part.name,
                grouped(part.mesh().triangles.len())
            ),
        )
        .clicked()
    {
        commands.push(Command::Select(Selection::Part));
    }
    if part.faces.is_empty() {
        return;
    }
    // A face selected elsewhere (picked in the viewport) is brought into view: the list opens
    // and scrolls to it when it is not among the rows drawn last frame.
    let memory = ui.scope_id().with("face list rows");
    let (last_selection, shown_rows): (Option<Selection>, std::ops::Range<usize>) =
        ui.data(|d| d.get_temp(memory)).unwrap_or((None, 0..0));
    let reveal = match doc.selection {
        Selection::Face(i) if last_selection != Some(doc.selection) => {
            (!shown_rows.contains(&i)).then_some(i)
        }
        _ => None,
    };
    let header_id = ui.make_persistent_id("faces");
    if reveal.is_some() {
        let mut state = egui::collapsing_header::CollapsingState::load_with_default_open(
            ui.ctx(),
            header_id,
            part.faces.len() <= 30,
        );
        state.set_open(true);
        state.store(ui.ctx());
    }
    let mut drawn = 0..0;
    egui::CollapsingHeader::new(format!("Faces ({})", part.faces.len()))
        .id_salt("faces")
        .default_open(part.faces.len() <= 30)
        .show(ui, |ui| {
            let row_height = ui.spacing().interact_size.y;
            let mut scroll = egui::ScrollArea::vertical()
                .id_salt("face list")
                .max_height(FACE_LIST_HEIGHT)
                .auto_shrink([false, true]);
            if let Some(i) = reveal {
                let step = row_height + ui.spacing().item_spacing.y;
                let top = i as f32 * step - 0.5 * (FACE_LIST_HEIGHT - step);
                scroll = scroll.vertical_scroll_offset(top.max(0.0));
            }
            scroll.show_rows(ui, row_height, part.faces.len(), |ui, rows| {
                drawn = rows.clone();
                for i in rows {
                    let Some(face) = part.faces.get(i) else {
                        continue;
                    };
                    let id = if face.source_id > 0 {
                        format!("  #{}", face.source_id)
                    } else {
                        String::new()
                    };
                    let selected = (focus == Focus::Selection
                        && doc.selection == Selection::Face(i))
                        || crate::app::face_group::in_group(ui.ctx(), i);
                    if ui
                        .selectable_label(selected, format!("Face {}  {}{id}", i + 1, face.kind))
                        .clicked()
                    {
                        crate::app::face_group::click(ui.ctx(), i);
                        commands.push(Command::Select(Selection::Face(i)));
                    }
                }
            });
        });
    ui.data_mut(|d| d.insert_temp(memory, (Some(doc.selection), drawn)));
    features_ui(ui, commands);
}

/// Height of the face list, points.
const FACE_LIST_HEIGHT: f32 = 240.0;
