//! The operation editor (properties panel): tool, face, strategy and its parameters with their
//! units, Calculate with progress and Cancel, the computed path's summary (lengths, poses, time at
//! feed, predicted scallop, gouge report) and the pose picked in the viewport.
//!
//! Numbers are typed in [`NumberField`]s: a value is applied (one undo step) when the typing is
//! confirmed, and refused with the reason when out of range. Values are shown in mm, mm/min and
//! degrees; the document keeps rad.

mod boundary;
mod cutting_data;
mod planar;

use glam::DVec3;

use super::super::command::Command;
use super::super::document::{Document, Selection};
use super::super::number_field::NumberField;
use super::super::state::Focus;
use super::super::theme;
use super::super::toolpaths::ComputedOp;
pub use super::super::widgets::duration_text;
use super::super::widgets::{grid, grouped, mm3};
use crate::diagnostics::Severity;
use crate::project::{Edit, Operation, OperationKind, Project};
use crate::strategies::finish::axis::AxisMode;
use crate::strategies::finish::{Direction, Pattern, Strategy};
use crate::strategies::waterline::{Cut, Entry, RAMP_DEFAULT_ANGLE_DEG};
use crate::toolpath::MoveKind;

/// The working copy of the operation being edited (so a drag shows its value at once and is
/// applied as one edit when it ends).
#[derive(Clone, Debug, Default)]
pub struct OperationForm {
    source: Option<(usize, Operation)>,
    draft: Option<Operation>,
    name: String,
}

/// Draws the features' sections of the operation editor, returning their commands.
pub type Sections<'a> = &'a dyn Fn(&mut egui::Ui, &mut Vec<Command>);

/// What the operation editor reads.
pub struct OperationView<'a> {
    /// The project.
    pub project: &'a Project,
    /// Which operation.
    pub index: usize,
    /// The loaded part (faces, selection).
    pub document: Option<&'a Document>,
    /// The latest result for this operation and whether it matches the current parameters.
    pub result: Option<(&'a ComputedOp, bool)>,
    /// The running calculation of this operation: fraction done, seconds running.
    pub running: Option<(f64, f64)>,
    /// The pose picked in the viewport (index into the result's tool path).
    pub picked_pose: Option<usize>,
    /// The pose the playback shows.
    pub playback_pose: Option<usize>,
    /// The features' sections under the computed path's summary (the stock simulation).
    pub sections: Option<Sections<'a>>,
    /// Is the path drawn in the viewport (not hidden for this operation)?
    pub path_shown: bool,
}

/// The operation editor.
pub fn operation_editor_ui(
    ui: &mut egui::Ui,
    view: &OperationView<'_>,
    form: &mut OperationForm,
    commands: &mut Vec<Command>,
) {
    let Some(current) = view.project.operations.get(view.index) else {
        ui.weak("No such operation.");
        return;
    };
    if form.source.as_ref() != Some(&(view.index, current.clone())) {
        form.source = Some((view.index, current.clone()));
        form.draft = Some(current.clone());
        form.name = current.name().to_string();
    }
    let Some(mut draft) = form.draft.clone() else {
        return;
    };
    let mut commit = false;
    ui.horizontal(|ui| {
        let r = ui.add(egui::TextEdit::singleline(&mut form.name).desired_width(200.0));
        if r.lost_focus() && form.name.trim() != current.name() && !form.name.trim().is_empty() {
            draft = draft.clone().with_name(form.name.trim());
            commit = true;
        }
    });
    ui.weak(current.kind().label());
    ui.add_space(4.0);
    egui::Grid::new(("operation fields", view.index))
        .num_columns(2)
        .spacing([10.0, 6.0])
        .show(ui, |ui| {
            commit |= tool_row(ui, view.project, &mut draft);
            commit |= reference_row(ui, view.project, &mut draft);
            commit |= kind_rows(ui, view.document, &mut draft);
            commit |= boundary::boundary_rows(ui, view.document, &mut draft);
        });
    if let (
        Operation::Rough {
            stock_to_leave_mm,
            stock_to_leave_axial_mm,
            ..
        },
        Some(document),
        Some(tool),
    ) = (&draft, view.document, view.project.tools.get(draft.tool()))
        && let Some(note) = crate::strategies::zlevel::reach_note(
            &tool.cutter,
            &view.project.stock,
            &document.bounds,
            stock_to_leave_axial_mm.unwrap_or(*stock_to_leave_mm),
        )
    {
        ui.colored_label(theme::WARNING, format!("⚠ {note}"));
    }
    if commit && draft != *current {
        commands.push(Command::Edit(Edit::SetOperation {
            index: view.index,
            operation: draft.clone(),
        }));
    }
    form.draft = Some(draft);
    ui.add_space(4.0);
    cutting_data::cutting_data_ui(ui, view.project, view.index, current, commands);

    ui.add_space(8.0);
    ui.horizontal(|ui| {
        match view.running {
            Some((fraction, elapsed)) => {
                ui.add(
                    egui::ProgressBar::new(fraction as f32)
                        .desired_width(140.0)
                        .text(format!("{:.0} % · {elapsed:.1} s", fraction * 100.0)),
                );
                if ui.button("Cancel").clicked() {
                    commands.push(Command::CancelJob);
                }
            }
            None => {
                let fresh = view.result.is_some_and(|(_, fresh)| fresh);
                let label = if fresh { "Recalculate" } else { "Calculate" };
                if ui
                    .button(egui::RichText::new(label).strong())
                    .on_hover_text("Plan the tool path in the background (F5)")
                    .clicked()
                {
                    commands.push(Command::Calculate(view.index));
                }
            }
        }
        if ui.button("Duplicate").clicked() {
            commands.push(Command::Edit(Edit::AddOperation {
                index: view.index + 1,
                operation: current
                    .clone()
                    .with_name(format!("{} (copy)", current.name())),
            }));
            commands.push(Command::Inspect(Focus::Operation(view.index + 1)));
        }
        if ui.button("Delete").clicked() {
            commands.push(Command::Edit(Edit::RemoveOperation { index: view.index }));
            commands.push(Command::Inspect(Focus::Selection));
        }
    });
    if let Some((result, fresh)) = view.result {
        ui.add_space(8.0);
        summary_ui(ui, result, fresh);
        let mut shown = view.path_shown;
        if ui
            .checkbox(&mut shown, "Show the path in the view")
            .on_hover_text("Hide this operation's path (it is then not drawn and clicks pass it)")
            .changed()
        {
            commands.push(Command::SetPathShown {
                operation: view.index,
                shown,
            });
        }
        super::super::findings_list::findings_ui(ui, view.index, &result.computed, commands);
        if let Some(sections) = view.sections {
            sections(ui, commands);
        }
        if let Some(i) = view.picked_pose.or(view.playback_pose) {
            ui.add_space(8.0);
            pose_ui(ui, result, i, view.picked_pose.is_some());
        }
    } else if view.running.is_none() {
        ui.add_space(6.0);
        ui.weak("Not calculated yet.");
    }
}

/// A number field named by the label `label` (see [`NumberField`]): `value` in internal units
/// shown × `scale` in `unit`, values outside `range` (shown units) refused; true when a typed
/// value was accepted (apply it now: one undo step).
fn number(
    ui: &mut egui::Ui,
    label: egui::Id,
    value: &mut f64,
    scale: f64,
    range: std::ops::RangeInclusive<f64>,
    decimals: usize,
    unit: &str,
) -> bool {
    NumberField::new(label, value)
        .labelled_by(label)
        .scale(scale)
        .range(range)
        .decimals(decimals)
        .unit(unit)
        .show(ui)
}

/// A field's label with its hint; its id names the field that follows.
fn label(ui: &mut egui::Ui, text: &str, hint: &str) -> egui::Id {
    ui.label(text).on_hover_text(hint).id
}

fn tool_row(ui: &mut egui::Ui, project: &Project, draft: &mut Operation) -> bool {
    label(ui, "Tool", "The cutter, from the project's tool library");
    let mut tool = draft.tool();
    let name = |i: usize| {
        project.tools.get(i).map_or_else(
            || format!("T{} (missing)", i + 1),
            |t| format!("T{} {}", i + 1, t.name),
        )
    };
    egui::ComboBox::from_id_salt("operation tool")
        .selected_text(name(tool))
        .width(190.0)
        .show_ui(ui, |ui| {
            for i in 0..project.tools.len() {
                ui.selectable_value(&mut tool, i, name(i));
            }
        });
    ui.end_row();
    if tool != draft.tool() {
        *draft = draft.clone().with_tool(tool);
        return true;
    }
    false
}

/// Rest finishing's reference tool: the earlier, larger cutter whose leftovers are finished.
fn reference_row(ui: &mut egui::Ui, project: &Project, draft: &mut Operation) -> bool {
    let Operation::Rest { reference_tool, .. } = draft else {
        return false;
    };
    label(
        ui,
        "Reference tool",
        "The earlier, larger tool: where it left more than the scallop height is finished",
    );
    let name = |i: usize| {
        project.tools.get(i).map_or_else(
            || format!("T{} (missing)", i + 1),
            |t| format!("T{} {}", i + 1, t.name),
        )
    };
    let mut chosen = *reference_tool;
    egui::ComboBox::from_id_salt("operation reference tool")
        .selected_text(name(chosen))
        .width(190.0)
        .show_ui(ui, |ui| {
            for i in 0..project.tools.len() {
                ui.selectable_value(&mut chosen, i, name(i));
            }
        });
    ui.end_row();
    if chosen == *reference_tool {
        return false;
    }
    *reference_tool = chosen;
    true
}

/// The rows of the operation kind's own parameters; whether one was changed.
fn kind_rows(ui: &mut egui::Ui, document: Option<&Document>, draft: &mut Operation) -> bool {
    let mut commit = false;
    match draft {
        Operation::Finish { .. } => commit = finish_rows(ui, document, draft),
        Operation::Raster { .. } => commit = raster_rows(ui, draft),
        Operation::Rough { .. } => commit = rough_rows(ui, draft),
        Operation::Waterline {
            scallop_mm,
            tolerance_mm,
            angle_rad,
            cut,
            feed_mm_per_min,
            clearance_mm,
            entry,
            ..
        } => {
            let angle = (
                "Slope limit",
                "Contacts flatter than this set no limit on the step-down",
                0.0..=89.0,
            );
            let fields = Finish3Fields {
                scallop_mm,
                tolerance_mm,
                angle_rad,
                cut,
                feed_mm_per_min,
                clearance_mm,
                entry,
            };
            commit |= finish_3axis_rows(ui, fields, angle);
        }
        Operation::SteepShallow {
            scallop_mm,
            tolerance_mm,
            angle_rad,
            cut,
            feed_mm_per_min,
            clearance_mm,
            entry,
            ..
        } => {
            let angle = (
                "Steep angle",
                "Slopes steeper than this are finished with waterline, the rest with raster",
                5.0..=80.0,
            );
            let fields = Finish3Fields {
                scallop_mm,
                tolerance_mm,
                angle_rad,
                cut,
                feed_mm_per_min,
                clearance_mm,
                entry,
            };
            commit |= finish_3axis_rows(ui, fields, angle);
        }
        Operation::Pencil { .. } => commit = pencil_rows(ui, draft),
        Operation::Rest { .. } => commit = rest_rows(ui, draft),
        Operation::Face(_) | Operation::Pocket(_) | Operation::Contour(_) | Operation::Holes(_) => {
            commit = planar::planar_rows(ui, draft);
        }
    }
    commit
}

/// The rows of a face-finishing operation.
fn finish_rows(ui: &mut egui::Ui, document: Option<&Document>, draft: &mut Operation) -> bool {
    let Operation::Finish {
        face,
        strategy,
        options,
        group,
        tilt_away,
        ..
    } = draft
    else {
        return false;
    };
    let mut commit = false;
    commit |= face_row(ui, document, face);
    commit |= group_rows(ui, group, tilt_away);
    commit |= strategy_rows(ui, strategy);
    let l = label(ui, "Scallop height", "Largest cusp left between passes");
    commit |= number(ui, l, &mut options.scallop, 1.0, 1e-4..=5.0, 4, "mm");
    ui.end_row();
    let l = label(
        ui,
        "Chord tolerance",
        "Largest deviation of the straight tool-tip moves from the true tip curve",
    );
    commit |= number(ui, l, &mut options.tolerance, 1.0, 1e-4..=2.0, 4, "mm");
    ui.end_row();
    commit |= axis_rows(ui, &mut options.axis);
    label(ui, "Direction", "Parameter the passes run along");
    let mut d = options.direction;
    ui.horizontal(|ui| {
        ui.selectable_value(&mut d, Direction::V, "along v");
        ui.selectable_value(&mut d, Direction::U, "along u");
    });
    ui.end_row();
    if d != options.direction {
        options.direction = d;
        commit = true;
    }
    let l = label(
        ui,
        "Clearance plane",
        "Height of retracts between passes (z)",
    );
    ui.horizontal(|ui| {
        let mut auto = options.clearance.is_none();
        if ui.checkbox(&mut auto, "auto").changed() {
            options.clearance = if auto { None } else { Some(50.0) };
            commit = true;
        }
        if let Some(c) = options.clearance.as_mut() {
            commit |= number(ui, l, c, 1.0, -1e4..=1e4, 3, "mm");
        }
    });
    ui.end_row();
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(ui, l, &mut options.feed, 1.0, 1.0..=1e5, 0, "mm/min");
    ui.end_row();
    let l = label(
        ui,
        "Lead-in/out arc",
        "Radius of the tangential arcs into and out of each pass (0: none)",
    );
    commit |= number(ui, l, &mut options.lead_arc_mm, 1.0, 0.0..=50.0, 2, "mm");
    ui.end_row();
    let l = label(
        ui,
        "Largest axis step",
        "Largest tool-axis change between poses",
    );
    commit |= number(
        ui,
        l,
        &mut options.max_axis_step,
        1f64.to_degrees(),
        0.1..=45.0,
        2,
        "°",
    );
    ui.end_row();
    label(
        ui,
        "Exact gouge check",
        "Check every pose and move against the exact surface (slower)",
    );
    commit |= ui.checkbox(&mut options.exact_check, "").changed();
    ui.end_row();
    commit
}

/// The rows of a raster operation.
fn raster_rows(ui: &mut egui::Ui, draft: &mut Operation) -> bool {
    let Operation::Raster {
        scallop_mm,
        angle_rad,
        one_way,
        tolerance_mm,
        feed_mm_per_min,
        clearance_mm,
        ..
    } = draft
    else {
        return false;
    };
    let mut commit = false;
    let l = label(
        ui,
        "Scallop height",
        "Largest cusp between passes on slopes",
    );
    commit |= number(ui, l, scallop_mm, 1.0, 1e-4..=5.0, 4, "mm");
    ui.end_row();
    let l = label(ui, "Angle", "Direction of the passes from +X");
    commit |= number(ui, l, angle_rad, 1f64.to_degrees(), -180.0..=180.0, 2, "°");
    ui.end_row();
    label(ui, "One way", "Cut every pass in the same direction");
    commit |= ui.checkbox(one_way, "").changed();
    ui.end_row();
    let l = label(
        ui,
        "Chord tolerance",
        "Deviation of the cutter-location polyline",
    );
    commit |= number(ui, l, tolerance_mm, 1.0, 1e-4..=2.0, 4, "mm");
    ui.end_row();
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(ui, l, feed_mm_per_min, 1.0, 1.0..=1e5, 0, "mm/min");
    ui.end_row();
    commit |= clearance_row(ui, clearance_mm, "Rapid plane above the part");
    commit
}

/// The rows of a roughing operation.
fn rough_rows(ui: &mut egui::Ui, draft: &mut Operation) -> bool {
    let Operation::Rough {
        step_down_mm,
        step_over_fraction,
        stock_to_leave_mm,
        stock_to_leave_axial_mm,
        tolerance_mm,
        feed_mm_per_min,
        flat_levels,
        clearance_mm,
        ..
    } = draft
    else {
        return false;
    };
    let mut commit = false;
    let l = label(ui, "Step-down", "Depth of each level");
    commit |= number(ui, l, step_down_mm, 1.0, 0.01..=100.0, 3, "mm");
    ui.end_row();
    let l = label(
        ui,
        "Step-over",
        "Distance between contours, % of the tool diameter",
    );
    commit |= number(ui, l, step_over_fraction, 100.0, 1.0..=100.0, 1, "%");
    ui.end_row();
    let l = label(
        ui,
        "Stock to leave",
        "Material left for finishing on the walls (and the floors unless set apart)",
    );
    commit |= number(ui, l, stock_to_leave_mm, 1.0, 0.0..=20.0, 3, "mm");
    ui.end_row();
    commit |= floor_allowance_row(ui, stock_to_leave_axial_mm, *stock_to_leave_mm);
    label(
        ui,
        "Flat levels",
        "A level of its own at each flat floor between two levels",
    );
    commit |= ui.checkbox(flat_levels, "").changed();
    ui.end_row();
    let l = label(ui, "Tolerance", "Contour tolerance (the roughing grid)");
    commit |= number(ui, l, tolerance_mm, 1.0, 1e-3..=5.0, 3, "mm");
    ui.end_row();
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(ui, l, feed_mm_per_min, 1.0, 1.0..=1e5, 0, "mm/min");
    ui.end_row();
    commit |= clearance_row(ui, clearance_mm, "Rapid plane above the stock");
    commit
}

/// The rows of a pencil operation.
fn pencil_rows(ui: &mut egui::Ui, draft: &mut Operation) -> bool {
    let Operation::Pencil {
        angle_rad,
        tolerance_mm,
        feed_mm_per_min,
        clearance_mm,
        ..
    } = draft
    else {
        return false;
    };
    let mut commit = false;
    let l = label(
        ui,
        "Corner angle",
        "Smallest angle between the ball's two contact normals that makes a pencil line",
    );
    commit |= number(ui, l, angle_rad, 1f64.to_degrees(), 1.0..=170.0, 1, "°");
    ui.end_row();
    let l = label(ui, "Chord tolerance", "Deviation of the pencil lines");
    commit |= number(ui, l, tolerance_mm, 1.0, 1e-4..=2.0, 4, "mm");
    ui.end_row();
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(ui, l, feed_mm_per_min, 1.0, 1.0..=1e5, 0, "mm/min");
    ui.end_row();
    commit |= clearance_row(ui, clearance_mm, "Rapid plane above the part");
    commit
}

/// The rows of a rest-finishing operation.
fn rest_rows(ui: &mut egui::Ui, draft: &mut Operation) -> bool {
    let Operation::Rest {
        from_stock,
        scallop_mm,
        tolerance_mm,
        feed_mm_per_min,
        clearance_mm,
        ..
    } = draft
    else {
        return false;
    };
    let mut commit = false;
    label(
        ui,
        "Rest of",
        "What is finished: what the earlier operations left in the simulated stock, or \
         (unticked) what the reference tool alone would leave",
    );
    commit |= ui.checkbox(from_stock, "from simulated stock").changed();
    ui.end_row();
    let l = label(
        ui,
        "Scallop height",
        "Rest thicker than this is finished; also the cusp between the passes",
    );
    commit |= number(ui, l, scallop_mm, 1.0, 1e-4..=5.0, 4, "mm");
    ui.end_row();
    let l = label(ui, "Chord tolerance", "Deviation of the passes");
    commit |= number(ui, l, tolerance_mm, 1.0, 1e-4..=2.0, 4, "mm");
    ui.end_row();
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(ui, l, feed_mm_per_min, 1.0, 1.0..=1e5, 0, "mm/min");
    ui.end_row();
    commit |= clearance_row(ui, clearance_mm, "Rapid plane above the part");
    commit
}
/// The fields of a waterline or steep-and-shallow operation.
struct Finish3Fields<'a> {
    scallop_mm: &'a mut f64,
    tolerance_mm: &'a mut f64,
    angle_rad: &'a mut f64,
    cut: &'a mut Cut,
    feed_mm_per_min: &'a mut f64,
    clearance_mm: &'a mut f64,
    entry: &'a mut Entry,
}

/// The clearance plane's row (mm above the part or the stock).
fn clearance_row(ui: &mut egui::Ui, clearance_mm: &mut f64, hint: &str) -> bool {
    let l = label(ui, "Clearance", hint);
    let commit = number(ui, l, clearance_mm, 1.0, 0.0..=500.0, 2, "mm");
    ui.end_row();
    commit
}

/// Roughing's floor allowance: the wall allowance unless set apart.
fn floor_allowance_row(ui: &mut egui::Ui, axial: &mut Option<f64>, radial: f64) -> bool {
    let l = label(
        ui,
        "Floor stock",
        "Material left on floors, when it differs from the walls",
    );
    let mut commit = false;
    ui.horizontal(|ui| {
        let mut apart = axial.is_some();
        if ui.checkbox(&mut apart, "apart").changed() {
            *axial = apart.then_some(radial);
            commit = true;
        }
        if let Some(v) = axial.as_mut() {
            commit |= number(ui, l, v, 1.0, 0.0..=20.0, 3, "mm");
        }
    });
    ui.end_row();
    commit
}

/// Rows of waterline and steep-and-shallow finishing; `angle` is the angle's label, hint and
/// range (degrees).
fn finish_3axis_rows(
    ui: &mut egui::Ui,
    f: Finish3Fields<'_>,
    angle: (&str, &str, std::ops::RangeInclusive<f64>),
) -> bool {
    let mut commit = false;
    let l = label(
        ui,
        "Scallop height",
        "Largest cusp left between levels and passes",
    );
    commit |= number(ui, l, f.scallop_mm, 1.0, 1e-4..=5.0, 4, "mm");
    ui.end_row();
    let l = label(
        ui,
        "Chord tolerance",
        "Deviation of the contours and passes from the exact cutter locations",
    );
    commit |= number(ui, l, f.tolerance_mm, 1.0, 1e-4..=2.0, 4, "mm");
    ui.end_row();
    let l = label(ui, angle.0, angle.1);
    commit |= number(ui, l, f.angle_rad, 1f64.to_degrees(), angle.2, 1, "°");
    ui.end_row();
    label(
        ui,
        "Direction",
        "Climb: the part on the right of the travel",
    );
    let mut c = *f.cut;
    ui.horizontal(|ui| {
        ui.selectable_value(&mut c, Cut::Climb, "climb");
        ui.selectable_value(&mut c, Cut::Conventional, "conventional");
    });
    ui.end_row();
    if c != *f.cut {
        *f.cut = c;
        commit = true;
    }
    commit |= entry_row(ui, f.entry);
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(ui, l, f.feed_mm_per_min, 1.0, 1.0..=1e5, 0, "mm/min");
    ui.end_row();
    commit |= clearance_row(ui, f.clearance_mm, "Rapid plane above the part");
    commit
}

/// How the waterline's loops are entered, with the arc's radius (mm; unticked: the tool's) or
/// the ramp's angle (°).
fn entry_row(ui: &mut egui::Ui, entry: &mut Entry) -> bool {
    let l = label(
        ui,
        "Entry",
        "How each loop is entered: a plunge, a tangential arc lead-in and lead-out on the \
         free side, or a ramp down along the loop from 1 mm above",
    );
    let mut commit = false;
    ui.horizontal(|ui| {
        let before = std::mem::discriminant(entry);
        let mut pick = *entry;
        ui.selectable_value(&mut pick, Entry::Plunge, "plunge");
        let arc = match *entry {
            e @ Entry::Arc { .. } => e,
            _ => Entry::Arc { radius_mm: None },
        };
        ui.selectable_value(&mut pick, arc, "arc");
        let ramp = match *entry {
            e @ Entry::Ramp { .. } => e,
            _ => Entry::Ramp {
                angle_rad: RAMP_DEFAULT_ANGLE_DEG.to_radians(),
            },
        };
        ui.selectable_value(&mut pick, ramp, "ramp");
        if std::mem::discriminant(&pick) != before {
            *entry = pick;
            commit = true;
        }
        match entry {
            Entry::Arc { radius_mm } => {
                let mut own = radius_mm.is_some();
                let tick = ui
                    .checkbox(&mut own, "radius")
                    .on_hover_text("Unticked: the tool's radius");
                if tick.changed() {
                    *radius_mm = own.then_some(3.0);
                    commit = true;
                }
                if let Some(r) = radius_mm.as_mut() {
                    commit |= number(ui, l, r, 1.0, 0.01..=1000.0, 2, "mm");
                }
            }
            Entry::Ramp { angle_rad } => {
                commit |= number(ui, l, angle_rad, 1f64.to_degrees(), 0.5..=45.0, 1, "°");
            }
            Entry::Plunge => {}
        }
    });
    ui.end_row();
    commit
}

/// The face group (further faces finished with the face, in order) and the tilt-away limits.
fn group_rows(
    ui: &mut egui::Ui,
    group: &mut Vec<usize>,
    tilt: &mut crate::project::operation::TiltAwaySettings,
) -> bool {
    let mut commit = false;
    label(
        ui,
        "Face group",
        "Further faces finished with this one, in this order (ctrl-click faces, then a group button in Properties)",
    );
    ui.horizontal(|ui| {
        if group.is_empty() {
            ui.weak("this face only");
        } else {
            let names: Vec<String> = group.iter().map(|g| format!("{}", g + 1)).collect();
            ui.label(format!("+ faces {}", names.join(", ")));
            if ui
                .button("Clear group")
                .on_hover_text("Finish this face alone")
                .clicked()
            {
                group.clear();
                commit = true;
            }
        }
    });
    ui.end_row();
    label(
        ui,
        "Tilt away",
        "Where the shank or holder would touch the part, tilt the tool axis away within these limits; spans no tilt frees are left out and reported",
    );
    commit |= ui
        .checkbox(&mut tilt.enabled, "tilt away from walls")
        .changed();
    ui.end_row();
    if tilt.enabled {
        let l = label(
            ui,
            "Largest tilt",
            "Largest tilt from the planned axis (0: never tilt, leave out and report); the machine's tilt travel also limits it",
        );
        commit |= number(
            ui,
            l,
            &mut tilt.max_angle_rad,
            1f64.to_degrees(),
            0.0..=90.0,
            1,
            "°",
        );
        ui.end_row();
        let l = label(
            ui,
            "Steep tilt",
            "Where no tilt within the largest tilt frees the tool (a hole's wall, a pin between plates), tilt up to this angle instead of leaving the span out (0: never beyond the largest tilt)",
        );
        commit |= number(
            ui,
            l,
            &mut tilt.steep_angle_rad,
            1f64.to_degrees(),
            0.0..=90.0,
            1,
            "°",
        );
        ui.end_row();
        let l = label(ui, "Tilt rate", "Largest change of the tilt along the path");
        commit |= number(
            ui,
            l,
            &mut tilt.rate_rad_per_mm,
            1f64.to_degrees(),
            0.01..=90.0,
            2,
            "°/mm",
        );
        ui.end_row();
    }
    commit
}

fn face_row(ui: &mut egui::Ui, document: Option<&Document>, face: &mut usize) -> bool {
    label(
        ui,
        "Face",
        "The face to finish (click one in the viewport, then 'use selected')",
    );
    let mut commit = false;
    ui.horizontal(|ui| {
        let faces = document.map_or(0, |d| d.part.faces.len());
        let text = document.and_then(|d| d.part.faces.get(*face)).map_or_else(
            || format!("Face {} (missing)", *face + 1),
            |f| format!("Face {} {}", *face + 1, f.kind),
        );
        egui::ComboBox::from_id_salt("operation face")
            .selected_text(text)
            .width(130.0)
            .show_ui(ui, |ui| {
                for i in 0..faces.min(500) {
                    let kind = document
                        .and_then(|d| d.part.faces.get(i))
                        .map_or("", |f| f.kind.as_str());
                    if ui
                        .selectable_label(*face == i, format!("Face {} {kind}", i + 1))
                        .clicked()
                    {
                        *face = i;
                        commit = true;
                    }
                }
            });
        if let Some(Selection::Face(sel)) = document.map(|d| d.selection)
            && sel != *face
            && ui
                .small_button("use selected")
                .on_hover_text(format!("Face {}", sel + 1))
                .clicked()
        {
            *face = sel;
            commit = true;
        }
    });
    ui.end_row();
    commit
}

fn strategy_rows(ui: &mut egui::Ui, strategy: &mut Strategy) -> bool {
    let mut commit = false;
    match strategy {
        Strategy::IsoParametric { pattern } => {
            label(ui, "Pattern", "How the passes are ordered");
            let before = *pattern;
            ui.horizontal(|ui| {
                ui.selectable_value(pattern, Pattern::Zigzag, "zig-zag");
                ui.selectable_value(pattern, Pattern::Oneway, "one way");
                ui.selectable_value(pattern, Pattern::Spiral, "spiral");
            });
            ui.end_row();
            commit |= before != *pattern;
        }
        Strategy::IsoPlanar { angle } => {
            let l = label(
                ui,
                "Plane angle",
                "Angle of the cutting planes' normal from +X",
            );
            commit |= number(ui, l, angle, 1f64.to_degrees(), -180.0..=180.0, 2, "°");
            ui.end_row();
        }
        Strategy::IsoScallop => {}
    }
    commit
}

fn axis_rows(ui: &mut egui::Ui, axis: &mut AxisMode) -> bool {
    let mut commit = false;
    label(
        ui,
        "Tool axis",
        "Surface normal with lead and tilt (5-axis) or fixed +Z (3-axis)",
    );
    let normal = matches!(axis, AxisMode::Normal { .. });
    let mut choice = normal;
    ui.horizontal(|ui| {
        ui.selectable_value(&mut choice, true, "normal + lead/tilt");
        ui.selectable_value(&mut choice, false, "fixed +Z");
    });
    ui.end_row();
    if choice != normal {
        *axis = if choice {
            AxisMode::default()
        } else {
            AxisMode::Fixed(DVec3::Z)
        };
        commit = true;
    }
    if let AxisMode::Normal { lead, tilt } = axis {
        let l = label(
            ui,
            "Lead",
            "Tilt of the axis toward the feed (raised when needed against gouging)",
        );
        commit |= number(ui, l, lead, 1f64.to_degrees(), -60.0..=60.0, 2, "°");
        ui.end_row();
        let l = label(ui, "Tilt", "Sideways tilt of the axis");
        commit |= number(ui, l, tilt, 1f64.to_degrees(), -60.0..=60.0, 2, "°");
        ui.end_row();
    }
    commit
}

fn summary_ui(ui: &mut egui::Ui, result: &ComputedOp, fresh: bool) {
    ui.label(egui::RichText::new("Tool path").strong());
    if !fresh {
        ui.colored_label(
            theme::WARNING,
            "Stale: the operation, its tool or the part changed since. Calculate again.",
        );
    }
    let tp = result.toolpath();
    let s = &tp.summary;
    let mut rows: Vec<(&str, String)> = vec![
        ("Poses", grouped(s.pose_count)),
        ("Passes", grouped(result.computed.passes)),
        ("Cut length", format!("{:.1} mm", s.cut_length_mm)),
        ("Other moves", format!("{:.1} mm", s.other_length_mm)),
        ("Time at feed", duration_text(s.estimated_time_s)),
    ];
    if let Some(h) = s.predicted_max_scallop_mm {
        rows.push(("Max predicted scallop", format!("{:.2} µm", h * 1000.0)));
    }
    if let Some(lead) = result.computed.lead_rad {
        rows.push(("Lead used", format!("{:.2}°", lead.to_degrees())));
    }
    let exact = matches!(
        result.operation,
        Operation::Finish { options, .. } if options.exact_check
    );
    if let Some(g) = s.gouge.as_ref().filter(|_| !exact) {
        rows.push((
            "Gouge check",
            if g.local_gouge {
                "local gouging (see below); exact check off".to_string()
            } else {
                "curvature only (exact check off)".to_string()
            },
        ));
    }
    if let Some(g) = s.gouge.as_ref().filter(|_| exact) {
        rows.push((
            "Gouge check",
            if g.gouging_poses == 0 && !g.local_gouge {
                format!("clean ({} poses)", grouped(g.checked_poses))
            } else {
                format!(
                    "{} gouging poses, deepest {:.1} µm",
                    grouped(g.gouging_poses),
                    g.max_depth_mm * 1000.0
                )
            },
        ));
        if let Some(at) = g.worst_at {
            rows.push(("Deepest gouge at", mm3(at)));
        }
    }
    rows.push(("Computed in", format!("{:.2} s", result.elapsed_s)));
    grid(ui, "operation summary", &rows);
    for d in &result.computed.diagnostics {
        let colour = match d.severity {
            Severity::Error => theme::ERROR,
            Severity::Warning => theme::WARNING,
            Severity::Info => ui.visuals().weak_text_color(),
        };
        ui.colored_label(colour, d.to_string());
    }
}

fn pose_ui(ui: &mut egui::Ui, result: &ComputedOp, index: usize, picked: bool) {
    let Some(p) = result.toolpath().poses.get(index) else {
        return;
    };
    ui.label(
        egui::RichText::new(if picked {
            "Picked pose"
        } else {
            "Playback pose"
        })
        .strong(),
    );
    let kind = match p.kind {
        MoveKind::Cut => "cut",
        MoveKind::Link => "link",
        MoveKind::Rapid => "rapid",
        MoveKind::Plunge => "plunge",
    };
    let tilt = p.axis.angle_between(DVec3::Z).to_degrees();
    let mut rows = vec![
        (
            "Pose",
            format!(
                "{} of {}",
                grouped(index + 1),
                grouped(result.toolpath().poses.len())
            ),
        ),
        ("Move", kind.to_string()),
        ("Tool tip", mm3(p.tip)),
        (
            "Tool axis",
            format!(
                "{:.4}, {:.4}, {:.4} ({tilt:.2}° from +Z)",
                p.axis.x, p.axis.y, p.axis.z
            ),
        ),
        ("Feed", format!("{:.0} mm/min", p.feed_mm_per_min)),
    ];
    if let Some(t) = result.clock_s.get(index) {
        rows.push(("Time at feed", duration_text(*t)));
    }
    if let Some(cc) = p.cc {
        rows.push(("Contact point", mm3(cc)));
    }
    if let Some(c) = p.contact {
        rows.push(("Contact", format!("{c:?}").to_lowercase()));
    }
    if let Some(h) = p.scallop_mm {
        rows.push(("Predicted scallop", format!("{:.2} µm", h * 1000.0)));
    }
    grid(ui, "pose", &rows);
}

/// The "add operation" buttons of the project tree: one per kind (finishing kinds need a B-rep
/// part); the new operation takes the selected tool and the selected face.
pub fn add_operation_ui(ui: &mut egui::Ui, has_faces: bool, commands: &mut Vec<Command>) {
    ui.menu_button("+ Operation", |ui| {
        for kind in OperationKind::ALL {
            let enabled = has_faces || !kind.needs_face();
            let r = ui.add_enabled(enabled, egui::Button::new(kind.label()));
            let r = if enabled {
                r
            } else {
                r.on_disabled_hover_text("Needs a STEP part with exact faces")
            };
            if r.clicked() {
                commands.push(Command::AddOperation(kind));
                ui.close();
            }
        }
    });
}

#[cfg(test)]
mod tests {
    #[test]
    fn durations_read_naturally() {
        assert_eq!(super::duration_text(12.34), "12.3 s");
        assert_eq!(super::duration_text(185.0), "3 min 05 s");
        assert_eq!(super::duration_text(3725.0), "1 h 02 min");
        assert_eq!(super::duration_text(f64::NAN), "—");
    }
}
