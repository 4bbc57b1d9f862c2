//! The setup editor (properties panel, focus [`Focus::Setup`]): one setup of the job — its name,
//! machine, work offset and program origin, the part's orientation on the table, the stock it
//! starts from, a 3+2 tilt, its workholding (vise, plate, parallels, riser, clamp) and its
//! operations in machining order (moved up, down or to another setup). Every change is one
//! [`Edit`] (undoable); the engine refuses what is invalid with the reason, which the log shows.

use super::super::command::Command;
use super::super::document::{Document, Selection};
use super::super::number_field::NumberField;
use super::super::state::Focus;
use super::super::widgets::length_field;
use super::super::widgets::{LENGTH_RANGE_MM, SIZE_RANGE_MM};
use crate::machine::Machine;
use crate::project::setups::{Orientation, Setup, SetupStock, Tilt};
use crate::project::workholding::Workholding;
use crate::project::{Edit, Project};

/// Degrees per radian, for the angle fields.
const DEG: f64 = 180.0 / std::f64::consts::PI;

/// A new vise's jaws, mm: 150 wide, 40 high, 20 thick, gripping the bottom 10 mm.
fn default_vise() -> Workholding {
    Workholding::Vise {
        jaw_width_mm: 150.0,
        jaw_height_mm: 40.0,
        jaw_thickness_mm: 20.0,
        grip_mm: 10.0,
        opening_mm: None,
        along_y: false,
    }
}

/// The workholding items the "Add" menu offers, with a machinist's starting sizes (mm).
fn starters() -> [(&'static str, Workholding); 5] {
    [
        ("Vise", default_vise()),
        (
            "Fixture plate",
            Workholding::Plate {
                size_mm: [300.0, 200.0],
                thickness_mm: 20.0,
            },
        ),
        (
            "Parallels",
            Workholding::Parallels {
                height_mm: 25.0,
                thickness_mm: 6.0,
            },
        ),
        (
            "Riser",
            Workholding::Riser {
                size_mm: [100.0, 100.0],
                height_mm: 50.0,
            },
        ),
        (
            "Strap clamp",
            Workholding::Clamp {
                at_mm: [0.0, 0.0, 0.0],
                size_mm: [80.0, 25.0, 15.0],
                angle_rad: 0.0,
            },
        ),
    ]
}

/// One line describing a setup for the project tree: work offset, orientation, stock,
/// workholding and tilt.
#[must_use]
pub fn setup_summary(setup: &Setup) -> String {
    let mut parts = vec![setup.frame.work_offset_code()];
    match setup.frame.orientation {
        Orientation::AsModelled => {}
        Orientation::Angles {
            rx_rad,
            ry_rad,
            rz_rad,
        } => parts.push(format!(
            "turned X {:.0}° Y {:.0}° Z {:.0}°",
            rx_rad * DEG,
            ry_rad * DEG,
            rz_rad * DEG
        )),
        Orientation::FaceOnTable { face, .. } => parts.push(format!("face {} down", face + 1)),
    }
    if let Some(t) = &setup.tilt {
        parts.push(format!(
            "3+2 axis ({:.2}, {:.2}, {:.2})",
            t.tool_axis[0], t.tool_axis[1], t.tool_axis[2]
        ));
    }
    if !setup.workholding.is_empty() {
        let names: Vec<&str> = setup
            .workholding
            .iter()
            .map(Workholding::kind_name)
            .collect();
        parts.push(names.join(", "));
    }
    parts.join(" · ")
}

/// The setup editor for setup `index`.
pub fn setup_editor_ui(
    ui: &mut egui::Ui,
    project: &Project,
    document: Option<&Document>,
    index: usize,
    commands: &mut Vec<Command>,
) {
    let Some(setup) = project.setups.get(index) else {
        ui.weak("No such setup.");
        return;
    };
    ui.heading(format!("Setup {} · {}", index + 1, setup.name));
    let mut next = setup.clone();
    name_ui(ui, index, &mut next);
    ui.add_space(4.0);
    egui::Grid::new(("setup fields", index))
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, |ui| {
            machine_row(ui, project, &mut next);
            ui.label("Work offset");
            egui::ComboBox::from_id_salt(("work offset", index))
                .selected_text(next.frame.work_offset_code())
                .show_ui(ui, |ui| {
                    for k in 1..=6u8 {
                        ui.selectable_value(&mut next.frame.work_offset, k, format!("G{}", 53 + k));
                    }
                });
            ui.end_row();
            ui.label("Program origin")
                .on_hover_text("Where the program's zero sits, in part coordinates");
            ui.horizontal(|ui| {
                for (k, x) in next.frame.origin_mm.iter_mut().enumerate() {
                    length_field(ui, ("Origin", index, k), x, LENGTH_RANGE_MM, 60.0);
                }
            });
            ui.end_row();
        });
    origin_buttons(ui, document, &mut next);
    ui.add_space(6.0);
    ui.label(egui::RichText::new("Orientation on the table").strong());
    orientation_ui(ui, document, index, &mut next);
    ui.add_space(6.0);
    ui.label(egui::RichText::new("Stock").strong());
    stock_ui(ui, index, &mut next);
    ui.add_space(6.0);
    ui.label(egui::RichText::new("Tool axis").strong());
    tilt_ui(ui, project, index, &mut next);
    ui.add_space(6.0);
    ui.label(egui::RichText::new("Workholding").strong());
    workholding_ui(ui, index, &mut next);
    if next != *setup {
        commands.push(Command::Edit(Edit::SetSetup { index, setup: next }));
    }
    ui.add_space(6.0);
    ui.label(egui::RichText::new("Operations").strong());
    operations_ui(ui, project, index, commands);
    ui.add_space(8.0);
    ui.separator();
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Add setup after")
            .on_hover_text("A new setup starting from what this one leaves")
            .clicked()
        {
            commands.push(add_setup_after(project, index));
        }
        let removable = project.setups.len() > 1 && setup.operations.is_empty();
        if ui
            .add_enabled(removable, egui::Button::new("Remove setup"))
            .on_disabled_hover_text("Only an empty setup can be removed, and not the only one")
            .clicked()
        {
            commands.push(Command::Edit(Edit::RemoveSetup { index }));
            commands.push(Command::Inspect(Focus::Setup(index.saturating_sub(1))));
        }
    });
    ui.weak(
        "Posted programs are written relative to the program origin (program = part − origin), \
         under the chosen work offset; `talas job` posts one program per setup.",
    );
}

/// The edit that inserts a setup after `index`: "Setup N", on the same machine, turned over
/// (about X, 180°), starting from what the previous setup left.
#[must_use]
pub fn add_setup_after(project: &Project, index: usize) -> Command {
    let mut n = project.setups.len() + 1;
    let name = loop {
        let name = format!("Setup {n}");
        if project.setups.iter().all(|s| s.name != name) {
            break name;
        }
        n += 1;
    };
    let mut setup = Setup::named(&name);
    if let Some(prev) = project.setups.get(index) {
        setup.machine.clone_from(&prev.machine);
        setup.frame.work_offset = (prev.frame.work_offset % 6) + 1;
        setup.frame.orientation = Orientation::Angles {
            rx_rad: std::f64::consts::PI,
            ry_rad: 0.0,
            rz_rad: 0.0,
        };
    }
    setup.stock = SetupStock::Previous;
    Command::Edit(Edit::AddSetup {
        index: index + 1,
        setup,
    })
}

fn name_ui(ui: &mut egui::Ui, index: usize, next: &mut Setup) {
    let id = ui.make_persistent_id(("setup name", index));
    let mut text: String = ui
        .data(|d| d.get_temp::<String>(id))
        .unwrap_or_else(|| next.name.clone());
    ui.horizontal(|ui| {
        ui.label("Name");
        let r = ui.add(egui::TextEdit::singleline(&mut text).desired_width(180.0));
        if r.lost_focus() {
            let t = text.trim();
            if !t.is_empty() && t != next.name {
                next.name = t.to_string();
            }
            ui.data_mut(|d| d.remove::<String>(id));
        } else if r.has_focus() {
            ui.data_mut(|d| d.insert_temp(id, text.clone()));
        }
    });
}

fn machine_row(ui: &mut egui::Ui, project: &Project, next: &mut Setup) {
    ui.label("Machine");
    let shown = next
        .machine
        .clone()
        .map_or_else(|| format!("project's ({})", project.machine), |m| m.clone());
    egui::ComboBox::from_id_salt("setup machine")
        .selected_text(shown)
        .show_ui(ui, |ui| {
            ui.selectable_value(
                &mut next.machine,
                None,
                format!("project's ({})", project.machine),
            );
            for name in Machine::builtin_names() {
                ui.selectable_value(&mut next.machine, Some(name.to_string()), name);
            }
        });
    ui.end_row();
}

fn origin_buttons(ui: &mut egui::Ui, document: Option<&Document>, next: &mut Setup) {
    let Some(b) = document.map(|d| d.bounds).filter(|b| !b.is_empty()) else {
        return;
    };
    ui.horizontal_wrapped(|ui| {
        ui.weak("Origin at:");
        let c = 0.5 * (b.min + b.max);
        if ui.small_button("part origin").clicked() {
            next.frame.origin_mm = [0.0; 3];
        }
        if ui.small_button("top centre").clicked() {
            next.frame.origin_mm = [c.x, c.y, b.max.z];
        }
        if ui.small_button("top front-left corner").clicked() {
            next.frame.origin_mm = [b.min.x, b.min.y, b.max.z];
        }
    })
    .response
    .on_hover_text("In part coordinates (the part as modelled)");
}

fn angle_field(ui: &mut egui::Ui, salt: impl std::hash::Hash + std::fmt::Debug, v: &mut f64) {
    NumberField::new(salt, v)
        .scale(DEG)
        .unit("°")
        .range(-360.0..=360.0)
        .decimals(3)
        .width(50.0)
        .show(ui);
}

fn orientation_ui(ui: &mut egui::Ui, document: Option<&Document>, index: usize, next: &mut Setup) {
    let o = &mut next.frame.orientation;
    let label = match o {
        Orientation::AsModelled => "as modelled",
        Orientation::Angles { .. } => "turned by angles",
        Orientation::FaceOnTable { .. } => "a face on the table",
    };
    let selected_face = document.and_then(|d| match d.selection {
        Selection::Face(i) => Some(i),
        _ => None,
    });
    egui::ComboBox::from_id_salt(("orientation", index))
        .selected_text(label)
        .show_ui(ui, |ui| {
            if ui
                .selectable_label(matches!(o, Orientation::AsModelled), "as modelled")
                .clicked()
            {
                *o = Orientation::AsModelled;
            }
            if ui
                .selectable_label(matches!(o, Orientation::Angles { .. }), "turned by angles")
                .clicked()
                && !matches!(o, Orientation::Angles { .. })
            {
                *o = Orientation::Angles {
                    rx_rad: 0.0,
                    ry_rad: 0.0,
                    rz_rad: 0.0,
                };
            }
            let face_ok = selected_face.is_some() || matches!(o, Orientation::FaceOnTable { .. });
            if ui
                .add_enabled(
                    face_ok,
                    egui::Button::selectable(
                        matches!(o, Orientation::FaceOnTable { .. }),
                        "a face on the table",
                    ),
                )
                .on_disabled_hover_text("Select a planar face of the part first")
                .clicked()
                && !matches!(o, Orientation::FaceOnTable { .. })
                && let Some(face) = selected_face
            {
                *o = Orientation::FaceOnTable {
                    face,
                    x_edge: None,
                    rz_rad: 0.0,
                };
            }
        });
    match o {
        Orientation::AsModelled => {
            ui.weak("The part's axes are the table's.");
        }
        Orientation::Angles {
            rx_rad,
            ry_rad,
            rz_rad,
        } => {
            ui.horizontal(|ui| {
                ui.label("about X");
                angle_field(ui, ("rx", index), rx_rad);
                ui.label("Y");
                angle_field(ui, ("ry", index), ry_rad);
                ui.label("Z");
                angle_field(ui, ("rz", index), rz_rad);
            });
            ui.horizontal_wrapped(|ui| {
                ui.weak("Turn:");
                for (text, x, y) in [
                    ("over (X 180°)", 180.0, 0.0),
                    ("front down (X 90°)", 90.0, 0.0),
                    ("back down (X −90°)", -90.0, 0.0),
                    ("left side down (Y 90°)", 0.0, 90.0),
                    ("right side down (Y −90°)", 0.0, -90.0),
                ] {
                    if ui.small_button(text).clicked() {
                        *rx_rad = x / DEG;
                        *ry_rad = y / DEG;
                        *rz_rad = 0.0;
                    }
                }
            });
            ui.weak("Turned about the table's X, then Y, then Z.");
        }
        Orientation::FaceOnTable { face, rz_rad, .. } => {
            ui.horizontal(|ui| {
                ui.label(format!("Face {} lies on the table", *face + 1));
                if let Some(f) = selected_face
                    && f != *face
                    && ui.small_button(format!("use face {}", f + 1)).clicked()
                {
                    *face = f;
                }
            });
            ui.horizontal(|ui| {
                ui.label("then about Z");
                angle_field(ui, ("face rz", index), rz_rad);
            });
        }
    }
}

fn stock_ui(ui: &mut egui::Ui, index: usize, next: &mut Setup) {
    let s = &mut next.stock;
    let label = match s {
        SetupStock::Project => "the project's stock",
        SetupStock::Around { .. } => "a box around the part",
        SetupStock::Box { .. } => "a box in the setup frame",
        SetupStock::Previous => "what the previous setup left",
    };
    egui::ComboBox::from_id_salt(("setup stock", index))
        .selected_text(label)
        .show_ui(ui, |ui| {
            ui.selectable_value(s, SetupStock::Project, "the project's stock");
            if ui
                .selectable_label(
                    matches!(s, SetupStock::Around { .. }),
                    "a box around the part",
                )
                .clicked()
                && !matches!(s, SetupStock::Around { .. })
            {
                *s = SetupStock::Around { margin_mm: 2.0 };
            }
            if ui
                .selectable_label(
                    matches!(s, SetupStock::Box { .. }),
                    "a box in the setup frame",
                )
                .clicked()
                && !matches!(s, SetupStock::Box { .. })
            {
                *s = SetupStock::Box {
                    min_mm: [-50.0, -50.0, -30.0],
                    max_mm: [50.0, 50.0, 2.0],
                };
            }
            ui.add_enabled_ui(index > 0, |ui| {
                ui.selectable_value(s, SetupStock::Previous, "what the previous setup left")
                    .on_disabled_hover_text("The first setup has no previous setup");
            });
        });
    match s {
        SetupStock::Around { margin_mm } => {
            ui.horizontal(|ui| {
                ui.label("Margin (sides, top)");
                length_field(ui, ("margin", index), margin_mm, 0.0..=1e4, 60.0);
            });
        }
        SetupStock::Box { min_mm, max_mm } => {
            for (name, v) in [("Min", min_mm), ("Max", max_mm)] {
                ui.horizontal(|ui| {
                    ui.label(name);
                    for (k, x) in v.iter_mut().enumerate() {
                        length_field(ui, (name, index, k), x, LENGTH_RANGE_MM, 60.0);
                    }
                });
            }
        }
        SetupStock::Project | SetupStock::Previous => {}
    }
}

fn tilt_ui(ui: &mut egui::Ui, project: &Project, index: usize, next: &mut Setup) {
    let five_axis = Machine::resolve(next.machine_name(project))
        .ok()
        .and_then(|m| m.rotary_names())
        .is_some();
    let mut tilted = next.tilt.is_some();
    let r = ui.add_enabled(
        five_axis || tilted,
        egui::Checkbox::new(&mut tilted, "3+2: a fixed tilted tool axis"),
    );
    r.on_disabled_hover_text("A tilted setup needs a 5-axis machine");
    if tilted != next.tilt.is_some() {
        next.tilt = tilted.then_some(Tilt {
            tool_axis: [0.0, -1.0, 1.0],
            x_axis: None,
        });
    }
    let Some(t) = next.tilt.as_mut() else {
        ui.weak("+Z of the setup frame (3-axis), or per pose for 5-axis finishing.");
        return;
    };
    ui.horizontal(|ui| {
        ui.label("Axis (tip → spindle)");
        for (k, x) in t.tool_axis.iter_mut().enumerate() {
            NumberField::new(("tilt axis", index, k), x)
                .range(-1e3..=1e3)
                .decimals(4)
                .width(50.0)
                .show(ui);
        }
    });
    ui.horizontal_wrapped(|ui| {
        ui.weak("Square to:");
        for (text, a) in [
            ("front (−Y)", [0.0, -1.0, 0.0]),
            ("back (+Y)", [0.0, 1.0, 0.0]),
            ("left (−X)", [-1.0, 0.0, 0.0]),
            ("right (+X)", [1.0, 0.0, 0.0]),
            ("45° front", [0.0, -1.0, 1.0]),
        ] {
            if ui.small_button(text).clicked() {
                t.tool_axis = a;
            }
        }
    });
    let polar = polar_deg(t.tool_axis);
    ui.weak(format!(
        "{:.1}° from +Z, towards {:.1}° from +X (setup frame)",
        polar.0, polar.1
    ));
}

/// A tool axis as angles: from +Z and its direction in XY from +X, degrees.
fn polar_deg([x, y, z]: [f64; 3]) -> (f64, f64) {
    let l = (x * x + y * y + z * z).sqrt();
    if l < 1e-12 {
        return (0.0, 0.0);
    }
    ((z / l).clamp(-1.0, 1.0).acos() * DEG, y.atan2(x) * DEG)
}

fn workholding_ui(ui: &mut egui::Ui, index: usize, next: &mut Setup) {
    let mut remove = None;
    for (k, w) in next.workholding.iter_mut().enumerate() {
        egui::CollapsingHeader::new(format!("{}. {}", k + 1, w.kind_name()))
            .id_salt(("workholding", index, k))
            .default_open(true)
            .show(ui, |ui| {
                item_ui(ui, (index, k), w);
                if ui.small_button("Remove").clicked() {
                    remove = Some(k);
                }
            });
    }
    if let Some(k) = remove {
        next.workholding.remove(k);
    }
    if next.workholding.is_empty() {
        ui.weak("Nothing holds the stock: the collision check sees no fixture.");
    }
    ui.menu_button("Add workholding", |ui| {
        for (name, item) in starters() {
            if ui.button(name).clicked() {
                next.workholding.push(item);
                ui.close();
            }
        }
    });
}

fn item_ui(ui: &mut egui::Ui, salt: (usize, usize), w: &mut Workholding) {
    let size = |ui: &mut egui::Ui, name: &str, v: &mut f64| {
        ui.label(name);
        length_field(ui, (name, salt), v, SIZE_RANGE_MM, 60.0);
        ui.end_row();
    };
    egui::Grid::new(("workholding fields", salt))
        .num_columns(2)
        .spacing([8.0, 4.0])
        .show(ui, |ui| match w {
            Workholding::Vise {
                jaw_width_mm,
                jaw_height_mm,
                jaw_thickness_mm,
                grip_mm,
                opening_mm,
                along_y,
            } => {
                size(ui, "Jaw width", jaw_width_mm);
                size(ui, "Jaw height", jaw_height_mm);
                size(ui, "Jaw thickness", jaw_thickness_mm);
                size(ui, "Grip", grip_mm);
                ui.label("Opening");
                ui.horizontal(|ui| {
                    let mut given = opening_mm.is_some();
                    ui.checkbox(&mut given, "")
                        .on_hover_text("Off: the jaws close on the stock");
                    match (given, opening_mm.as_mut()) {
                        (true, Some(o)) => {
                            length_field(ui, ("opening", salt), o, SIZE_RANGE_MM, 60.0);
                        }
                        (true, None) => *opening_mm = Some(100.0),
                        (false, _) => {
                            *opening_mm = None;
                            ui.weak("on the stock");
                        }
                    }
                });
                ui.end_row();
                ui.label("Closes along");
                ui.horizontal(|ui| {
                    ui.radio_value(along_y, false, "X");
                    ui.radio_value(along_y, true, "Y");
                });
                ui.end_row();
            }
            Workholding::Plate {
                size_mm,
                thickness_mm,
            }
            | Workholding::Riser {
                size_mm,
                height_mm: thickness_mm,
            } => {
                size(ui, "Size X", &mut size_mm[0]);
                size(ui, "Size Y", &mut size_mm[1]);
                size(ui, "Thickness", thickness_mm);
            }
            Workholding::Parallels {
                height_mm,
                thickness_mm,
            } => {
                size(ui, "Height", height_mm);
                size(ui, "Thickness", thickness_mm);
            }
            Workholding::Clamp {
                at_mm,
                size_mm,
                angle_rad,
            } => {
                ui.label("At (bottom centre)");
                ui.horizontal(|ui| {
                    for (k, x) in at_mm.iter_mut().enumerate() {
                        length_field(ui, ("clamp at", salt, k), x, LENGTH_RANGE_MM, 50.0);
                    }
                });
                ui.end_row();
                size(ui, "Length", &mut size_mm[0]);
                size(ui, "Width", &mut size_mm[1]);
                size(ui, "Height", &mut size_mm[2]);
                ui.label("Turn about Z");
                angle_field(ui, ("clamp angle", salt), angle_rad);
                ui.end_row();
            }
            Workholding::Body {
                path,
                offset_mm,
                angle_rad,
            } => {
                ui.label("File");
                ui.monospace(path.display().to_string());
                ui.end_row();
                ui.label("Offset");
                ui.horizontal(|ui| {
                    for (k, x) in offset_mm.iter_mut().enumerate() {
                        length_field(ui, ("body offset", salt, k), x, LENGTH_RANGE_MM, 50.0);
                    }
                });
                ui.end_row();
                ui.label("Turn about Z");
                angle_field(ui, ("body angle", salt), angle_rad);
                ui.end_row();
            }
        });
}

fn operations_ui(ui: &mut egui::Ui, project: &Project, index: usize, commands: &mut Vec<Command>) {
    let setup = &project.setups[index];
    if setup.operations.is_empty() {
        ui.weak("None: move operations here from another setup.");
    }
    let n = setup.operations.len();
    for (position, &op) in setup.operations.iter().enumerate() {
        let Some(o) = project.operations.get(op) else {
            continue;
        };
        ui.horizontal(|ui| {
            if ui
                .selectable_label(false, format!("{}. {}", op + 1, o.name()))
                .on_hover_text(o.kind().label())
                .clicked()
            {
                commands.push(Command::Inspect(Focus::Operation(op)));
            }
            let mv = |setup: usize, position: usize| {
                Command::Edit(Edit::MoveOperation {
                    operation: op,
                    setup,
                    position,
                })
            };
            if ui
                .add_enabled(position > 0, egui::Button::new("up").small())
                .on_hover_text("Machine it earlier")
                .clicked()
            {
                commands.push(mv(index, position - 1));
            }
            if ui
                .add_enabled(position + 1 < n, egui::Button::new("down").small())
                .on_hover_text("Machine it later")
                .clicked()
            {
                commands.push(mv(index, position + 1));
            }
            if project.setups.len() > 1 {
                ui.menu_button("to setup…", |ui| {
                    for (s, other) in project.setups.iter().enumerate() {
                        if s != index && ui.button(format!("{}. {}", s + 1, other.name)).clicked() {
                            commands.push(mv(s, other.operations.len()));
                            ui.close();
                        }
                    }
                });
            }
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_setup_added_after_the_first_is_turned_over_and_starts_from_it() {
        let project = Project::default();
        let Command::Edit(edit) = add_setup_after(&project, 0) else {
            panic!("an edit");
        };
        let mut p = project.clone();
        p.apply(edit).expect("a valid setup");
        assert_eq!(p.setups.len(), 2);
        let s = &p.setups[1];
        assert_eq!(s.stock, SetupStock::Previous);
        assert_eq!(s.frame.work_offset, 2, "the next work offset, G55");
        assert!(matches!(
            s.frame.orientation,
            Orientation::Angles { rx_rad, .. } if (rx_rad - std::f64::consts::PI).abs() < 1e-12
        ));
        assert!(setup_summary(s).starts_with("G55 · turned X 180°"));
        // A second one gets a name of its own.
        let Command::Edit(edit) = add_setup_after(&p, 1) else {
            panic!("an edit");
        };
        p.apply(edit).expect("a unique name");
        assert_eq!(p.setups[2].name, "Setup 3");
    }

    #[test]
    fn polar_angles_of_the_tool_axis() {
        let (from_z, towards) = polar_deg([0.0, -1.0, 1.0]);
        assert!((from_z - 45.0).abs() < 1e-9);
        assert!((towards + 90.0).abs() < 1e-9);
    }
}
