//! Face groups in the workstation: several faces selected at once (ctrl-click toggles a face,
//! shift-click in the tree adds the range from the last clicked face, a plain click starts over
//! with one face), the one-click "tangent-connected faces" selection, and a finishing operation
//! created over the group ([`crate::project::Operation::Finish`] with its `group`). The
//! multi-selection lives in the UI's memory beside the document's single selection, which stays
//! the last clicked face.

use super::command::Command;
use super::document::Document;
use crate::geometry::brep::tangent_connected;
use crate::project::{Edit, Operation, OperationKind, Project};

/// Largest angle between the faces' normals along a shared edge for "tangent-connected", rad.
const TANGENT_TOL_RAD: f64 = 1.0f64.to_radians();

/// The faces selected together, in the order they were picked.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FaceGroup {
    /// Face indices (0-based), no repeats.
    pub faces: Vec<usize>,
    /// The last face clicked (the start of a shift-click range).
    pub anchor: Option<usize>,
}

impl FaceGroup {
    /// A click on `face`: `toggle` (ctrl) adds or removes it, `range` (shift) adds every face
    /// from the anchor to it, neither starts over with it alone.
    pub fn click(&mut self, face: usize, toggle: bool, range: bool) {
        match (range, self.anchor) {
            (true, Some(a)) => {
                for f in a.min(face)..=a.max(face) {
                    if !self.faces.contains(&f) {
                        self.faces.push(f);
                    }
                }
            }
            _ if toggle => {
                if let Some(k) = self.faces.iter().position(|&f| f == face) {
                    self.faces.remove(k);
                } else {
                    self.faces.push(face);
                }
            }
            _ => self.faces = vec![face],
        }
        self.anchor = Some(face);
    }
}

fn memory_id() -> egui::Id {
    egui::Id::unique("talas.face_group")
}

/// The current face group.
#[must_use]
pub fn group(ctx: &egui::Context) -> FaceGroup {
    ctx.data(|d| d.get_temp::<FaceGroup>(memory_id()))
        .unwrap_or_default()
}

/// Replace the face group.
pub fn set_group(ctx: &egui::Context, group: FaceGroup) {
    ctx.data_mut(|d| d.insert_temp(memory_id(), group));
}

/// Record a click on `face` with the keyboard's modifiers (the tree and the viewport call this
/// beside selecting the face).
pub fn click(ctx: &egui::Context, face: usize) {
    // The modifiers held when the button went up (they may be released in the same frame).
    let m = ctx.input(|i| {
        i.events
            .iter()
            .rev()
            .find_map(|e| match e {
                egui::Event::PointerButton {
                    pressed: false,
                    modifiers,
                    ..
                } => Some(*modifiers),
                _ => None,
            })
            .unwrap_or(i.modifiers)
    });
    let mut g = group(ctx);
    g.click(face, m.command || m.ctrl, m.shift);
    set_group(ctx, g);
}

/// Is `face` in the group (with at least two faces)?
#[must_use]
pub fn in_group(ctx: &egui::Context, face: usize) -> bool {
    let g = group(ctx);
    g.faces.len() > 1 && g.faces.contains(&face)
}

/// The finishing operation of `kind` over `faces` (the first is the operation's face).
#[must_use]
pub fn group_operation(kind: OperationKind, tool: usize, faces: &[usize]) -> Option<Operation> {
    let (&first, rest) = faces.split_first()?;
    let mut op = Operation::new(kind, tool, first);
    if let Operation::Finish { group, name, .. } = &mut op {
        *group = rest.to_vec();
        *name = format!("{} ({} faces)", kind.label(), faces.len());
    }
    Some(op)
}

/// The face-group section under the selection's properties: the faces selected, the
/// "tangent-connected faces" button and one button per finishing kind creating the group
/// operation.
pub fn group_ui(
    ui: &mut egui::Ui,
    document: Option<&Document>,
    project: &Project,
    commands: &mut Vec<Command>,
) {
    let Some(doc) = document else { return };
    let Some(brep) = doc.part.workpiece.part.as_ref() else {
        return;
    };
    let ctx = ui.ctx().clone();
    let g = group(&ctx);
    ui.add_space(8.0);
    ui.label(egui::RichText::new("FACE GROUP").small().strong().weak());
    if g.faces.is_empty() {
        ui.weak("Ctrl-click faces (tree or viewport) to select several.");
    } else {
        let area: f64 = g
            .faces
            .iter()
            .filter_map(|&f| doc.face_area_mm2.get(f))
            .sum();
        let names: Vec<String> = g.faces.iter().map(|f| format!("{}", f + 1)).collect();
        ui.label(format!(
            "{} faces ({area:.1} mm²): Face {}",
            g.faces.len(),
            names.join(", ")
        ));
    }
    if let Some(seed) = g.anchor.or_else(|| g.faces.first().copied())
        && ui
            .button("Tangent-connected faces")
            .on_hover_text("Every face joined to the last clicked one across tangent edges")
            .clicked()
    {
        let faces = tangent_connected(brep, seed, TANGENT_TOL_RAD);
        set_group(
            &ctx,
            FaceGroup {
                faces,
                anchor: Some(seed),
            },
        );
    }
    let Some(tool) = project.selected_tool.or(if project.tools.is_empty() {
        None
    } else {
        Some(0)
    }) else {
        return;
    };
    if g.faces.len() < 2 {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        for kind in [
            OperationKind::IsoScallop,
            OperationKind::IsoPlanar,
            OperationKind::IsoParametric,
        ] {
            if ui
                .button(format!("{} on the group", kind.label()))
                .clicked()
                && let Some(operation) = group_operation(kind, tool, &g.faces)
            {
                let index = project.operations.len();
                commands.push(Command::Edit(Edit::AddOperation { index, operation }));
                commands.push(Command::Inspect(super::state::Focus::Operation(index)));
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clicks_toggle_extend_and_start_over() {
        let mut g = FaceGroup::default();
        g.click(3, false, false);
        g.click(7, true, false);
        assert_eq!(g.faces, vec![3, 7]);
        g.click(5, false, true);
        assert_eq!(g.faces, vec![3, 7, 5, 6]);
        g.click(7, true, false);
        assert_eq!(g.faces, vec![3, 5, 6]);
        g.click(9, false, false);
        assert_eq!(g.faces, vec![9]);
        let op = group_operation(OperationKind::IsoPlanar, 0, &[4, 2, 8]).expect("op");
        assert_eq!(op.faces(), vec![4, 2, 8]);
    }
}
