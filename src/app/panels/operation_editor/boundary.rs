//! The boundary rows of a 3-axis finishing operation: the region (the whole part, the part's
//! silhouette, a polygon typed as `X,Y; X,Y; …` in mm, or face numbers) and the rule (the tool
//! centre or the contact point must lie inside). A typed region is applied when the typing is
//! confirmed and parses; otherwise the reason is shown and the operation keeps its region.

use super::label;
use crate::app::document::Document;
use crate::app::theme;
use crate::project::Operation;
use crate::strategies::boundary::{Boundary, BoundaryRule, Region};

/// Which kind of region the combo box shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Whole,
    Silhouette,
    Polygon,
    Faces,
}

impl Kind {
    const ALL: [Self; 4] = [Self::Whole, Self::Silhouette, Self::Polygon, Self::Faces];

    fn of(b: Option<&Boundary>) -> Self {
        match b.map(|b| &b.region) {
            None => Self::Whole,
            Some(Region::Silhouette) => Self::Silhouette,
            Some(Region::Polygon(_)) => Self::Polygon,
            Some(Region::Faces(_)) => Self::Faces,
        }
    }

    fn label(self) -> &'static str {
        match self {
            Self::Whole => "whole part",
            Self::Silhouette => "part silhouette",
            Self::Polygon => "drawn polygon",
            Self::Faces => "selected faces",
        }
    }
}

/// The region as the text field shows it (polygon vertices or face numbers).
fn region_text(region: &Region) -> String {
    match region {
        Region::Polygon(p) => p
            .iter()
            .map(|v| format!("{},{}", v[0], v[1]))
            .collect::<Vec<_>>()
            .join("; "),
        Region::Faces(f) => faces_text(f),
        Region::Silhouette => String::new(),
    }
}

/// Face indices as the project tree numbers them (from 1).
fn faces_text(faces: &[usize]) -> String {
    faces
        .iter()
        .map(|f| (f + 1).to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Face numbers typed as the project tree shows them (from 1), as the engine's indices
/// (from 0); the reason when one is not a face number.
fn parse_faces(text: &str) -> Result<Vec<usize>, String> {
    text.split(',')
        .map(|v| match v.trim().parse::<usize>() {
            Ok(0) => Err("face numbers start at 1, as in the project tree".to_string()),
            Ok(n) => Ok(n - 1),
            Err(_) => Err(format!("boundary face '{}' is not a face number", v.trim())),
        })
        .collect()
}

/// A starting region of `kind`: the part's box outline for a polygon, the first face (Face 1)
/// for faces.
fn start_region(kind: Kind, document: Option<&Document>) -> Option<Region> {
    match kind {
        Kind::Whole => None,
        Kind::Silhouette => Some(Region::Silhouette),
        Kind::Polygon => {
            let (lo, hi) = document.map_or(([0.0, 0.0], [10.0, 10.0]), |d| {
                (
                    [d.bounds.min.x, d.bounds.min.y],
                    [d.bounds.max.x, d.bounds.max.y],
                )
            });
            Some(Region::Polygon(vec![
                lo,
                [hi[0], lo[1]],
                hi,
                [lo[0], hi[1]],
            ]))
        }
        Kind::Faces => Some(Region::Faces(vec![0])),
    }
}

/// The boundary rows; true when the operation changed (apply it now: one undo step).
pub(super) fn boundary_rows(
    ui: &mut egui::Ui,
    document: Option<&Document>,
    draft: &mut Operation,
) -> bool {
    let Some(slot) = draft.boundary_mut() else {
        return false;
    };
    label(
        ui,
        "Boundary",
        "Limit the path to a region: the part's outline from above, a polygon or faces",
    );
    let old = Kind::of(slot.as_ref());
    let mut kind = old;
    egui::ComboBox::from_id_salt("operation boundary")
        .selected_text(kind.label())
        .width(190.0)
        .show_ui(ui, |ui| {
            for k in Kind::ALL {
                ui.selectable_value(&mut kind, k, k.label());
            }
        });
    ui.end_row();
    let mut commit = false;
    if kind != old {
        let rule = slot.as_ref().map_or(BoundaryRule::ToolCentre, |b| b.rule);
        *slot = start_region(kind, document).map(|region| Boundary { region, rule });
        commit = true;
    }
    let Some(boundary) = slot.as_mut() else {
        return commit;
    };
    if matches!(kind, Kind::Polygon | Kind::Faces) {
        commit |= region_row(ui, kind, boundary);
    }
    label(
        ui,
        "Boundary rule",
        "Which point must lie inside: the tool's centre (its tip in plan view) or where it \
         touches the part",
    );
    ui.horizontal(|ui| {
        commit |= ui
            .radio_value(&mut boundary.rule, BoundaryRule::ToolCentre, "tool centre")
            .changed();
        commit |= ui
            .radio_value(&mut boundary.rule, BoundaryRule::Contact, "contact point")
            .changed();
    });
    ui.end_row();
    commit
}

/// The typed vertices or face numbers, kept in the UI's memory while typed; applied when the
/// typing is confirmed and the text parses.
fn region_row(ui: &mut egui::Ui, kind: Kind, boundary: &mut Boundary) -> bool {
    let (title, hint) = if kind == Kind::Polygon {
        (
            "Polygon",
            "Vertices X,Y in mm, separated by ';' (at least three)",
        )
    } else {
        (
            "Faces",
            "Face numbers as in the project tree (from 1), separated by ','",
        )
    };
    let l = label(ui, title, hint);
    let id = l.with("boundary text");
    let shown = region_text(&boundary.region);
    let mut text: String = ui.data(|d| d.get_temp(id)).unwrap_or_else(|| shown.clone());
    let mut commit = false;
    ui.vertical(|ui| {
        let r = ui
            .add(egui::TextEdit::singleline(&mut text).desired_width(190.0))
            .labelled_by(l);
        let confirmed = r.lost_focus();
        let parsed = if kind == Kind::Polygon {
            Boundary::parse(&text, boundary.rule)
        } else {
            parse_faces(&text).and_then(|f| {
                let list: Vec<String> = f.iter().map(ToString::to_string).collect();
                Boundary::parse(&format!("faces:{}", list.join(",")), boundary.rule)
            })
        };
        match &parsed {
            Ok(b) if confirmed => {
                if b.region != boundary.region {
                    boundary.region = b.region.clone();
                    commit = true;
                }
                ui.data_mut(|d| d.remove::<String>(id));
            }
            _ if text != shown => {
                if let Err(e) = &parsed {
                    ui.colored_label(theme::ERROR, e);
                }
                ui.data_mut(|d| d.insert_temp(id, text.clone()));
            }
            _ => ui.data_mut(|d| d.remove::<String>(id)),
        }
    });
    ui.end_row();
    commit
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The field numbers faces as the tree does: "Face 3" in the tree is `3` in the field and
    /// index 2 in the engine; 0 is refused.
    #[test]
    fn face_numbers_in_the_field_are_the_trees() {
        assert_eq!(faces_text(&[0, 2, 291]), "1, 3, 292");
        assert_eq!(parse_faces(" 1, 3,292 "), Ok(vec![0, 2, 291]));
        assert_eq!(parse_faces(&faces_text(&[4, 7])), Ok(vec![4, 7]));
        assert!(parse_faces("0").unwrap_err().contains("start at 1"));
        assert!(parse_faces("2, x").unwrap_err().contains("'x'"));
    }
}
