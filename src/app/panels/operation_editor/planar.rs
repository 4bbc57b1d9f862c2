//! The rows of the 2.5D and hole operations (facing, pocket, contour, holes): the strategy's
//! own numbers, then the record they share ([`crate::project::op_common::Common`]: feeds,
//! spindle, coolant, heights with what each is measured from, stock to leave). Every number
//! carries its unit and the range the engine's `validate` accepts.

use super::{label, number};
use crate::features::regions::RegionKind;
use crate::project::Operation;
use crate::project::op_common::{Common, Height, HeightFrom};
use crate::project::op_contour::ContourOp;
use crate::project::op_holes::{HoleSelection, HolesOp};
use crate::project::op_regions::RegionTarget;

/// The rows of a 2.5D or hole operation; true when a value was committed.
pub(super) fn planar_rows(ui: &mut egui::Ui, draft: &mut Operation) -> bool {
    let target = match &*draft {
        Operation::Face(o) => region_text(&o.target),
        Operation::Pocket(o) => region_text(&o.target),
        Operation::Contour(o) => region_text(&o.target),
        Operation::Holes(o) => format!("{} · {}", o.cycle.name(), holes_text(&o.holes)),
        _ => return false,
    };
    label(
        ui,
        "Machines",
        "The regions or holes (set in the project file)",
    );
    ui.label(target);
    ui.end_row();
    let mut commit = false;
    let deg = 1f64.to_degrees();
    match draft {
        Operation::Face(o) => {
            let l = label(
                ui,
                "Stock above the part",
                "Material facing removes over the part's top",
            );
            commit |= number(ui, l, &mut o.stock_above_mm, 1.0, 0.0..=100.0, 3, "mm");
            ui.end_row();
            commit |= step_rows(ui, &mut o.step_down_mm, &mut o.step_over_fraction);
            let l = label(
                ui,
                "Overrun",
                "How far the passes run beyond the stock's edge",
            );
            commit |= number(ui, l, &mut o.overrun_mm, 1.0, 0.0..=100.0, 2, "mm");
            ui.end_row();
            label(
                ui,
                "Pattern",
                "Zig-zag, or every pass in the same direction",
            );
            ui.horizontal(|ui| {
                commit |= ui
                    .selectable_value(&mut o.zigzag, true, "zig-zag")
                    .changed();
                commit |= ui
                    .selectable_value(&mut o.zigzag, false, "one way")
                    .changed();
            });
            ui.end_row();
            commit |= common_rows(ui, &mut o.common);
        }
        Operation::Pocket(o) => {
            commit |= step_rows(ui, &mut o.step_down_mm, &mut o.step_over_fraction);
            let l = label(
                ui,
                "Ramp angle",
                "Entry ramp's slope (a helix where it fits)",
            );
            commit |= number(ui, l, &mut o.ramp_angle_rad, deg, 0.5..=90.0, 1, "°");
            ui.end_row();
            commit |= tolerance_row(ui, &mut o.tolerance_mm);
            commit |= common_rows(ui, &mut o.common);
        }
        Operation::Contour(o) => commit |= contour_rows(ui, o),
        Operation::Holes(o) => commit |= holes_rows(ui, o),
        _ => {}
    }
    commit
}

fn contour_rows(ui: &mut egui::Ui, o: &mut ContourOp) -> bool {
    let mut commit = false;
    let deg = 1f64.to_degrees();
    label(ui, "Side", "Cut outside or inside the region's boundary");
    ui.horizontal(|ui| {
        commit |= ui
            .selectable_value(&mut o.outside, true, "outside")
            .changed();
        commit |= ui
            .selectable_value(&mut o.outside, false, "inside")
            .changed();
    });
    ui.end_row();
    label(ui, "Direction", "Climb or conventional milling");
    ui.horizontal(|ui| {
        commit |= ui.selectable_value(&mut o.climb, true, "climb").changed();
        commit |= ui
            .selectable_value(&mut o.climb, false, "conventional")
            .changed();
    });
    ui.end_row();
    let l = label(ui, "Step-down", "Depth of each contour pass");
    commit |= number(ui, l, &mut o.step_down_mm, 1.0, 0.01..=100.0, 3, "mm");
    ui.end_row();
    let l = label(ui, "Lead radius", "Arc lead in and out (0: none)");
    commit |= number(ui, l, &mut o.lead_radius_mm, 1.0, 0.0..=100.0, 2, "mm");
    ui.end_row();
    let l = label(ui, "Tabs", "Bridges left to hold the part (0: none)");
    #[allow(clippy::cast_precision_loss)]
    let mut tabs = o.tabs as f64;
    if number(ui, l, &mut tabs, 1.0, 0.0..=64.0, 0, "") {
        #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
        {
            o.tabs = tabs.round().clamp(0.0, 64.0) as usize;
        }
        commit = true;
    }
    ui.end_row();
    if o.tabs > 0 {
        let l = label(ui, "Tab width", "Length of each tab along the boundary");
        commit |= number(ui, l, &mut o.tab_width_mm, 1.0, 0.1..=100.0, 2, "mm");
        ui.end_row();
        let l = label(ui, "Tab height", "Height of each tab above the floor");
        commit |= number(ui, l, &mut o.tab_height_mm, 1.0, 0.1..=100.0, 2, "mm");
        ui.end_row();
    }
    let l = label(ui, "Ramp angle", "Slope of the ramp down between depths");
    commit |= number(ui, l, &mut o.ramp_angle_rad, deg, 0.5..=90.0, 1, "°");
    ui.end_row();
    commit |= tolerance_row(ui, &mut o.tolerance_mm);
    commit |= common_rows(ui, &mut o.common);
    commit
}

fn holes_rows(ui: &mut egui::Ui, o: &mut HolesOp) -> bool {
    let mut commit = false;
    let l = label(
        ui,
        "Peck depth",
        "Depth of each peck (peck and chip-break cycles)",
    );
    commit |= number(ui, l, &mut o.peck_mm, 1.0, 0.01..=100.0, 3, "mm");
    ui.end_row();
    let l = label(ui, "Dwell", "Pause at the bottom of each hole");
    commit |= number(ui, l, &mut o.dwell_s, 1.0, 0.0..=60.0, 2, "s");
    ui.end_row();
    commit |= optional_row(
        ui,
        ("Pitch", "Thread pitch, or the helix's descent per turn"),
        &mut o.pitch_mm,
        (0.05..=20.0, 3, "mm"),
        1.0,
    );
    commit |= optional_row(
        ui,
        (
            "Depth",
            "Depth below each hole's top instead of the recognised one",
        ),
        &mut o.depth_mm,
        (0.01..=1000.0, 3, "mm"),
        10.0,
    );
    let l = label(
        ui,
        "Finish allowance",
        "Radial stock the helical roughing leaves",
    );
    commit |= number(ui, l, &mut o.finish_mm, 1.0, 0.0..=10.0, 3, "mm");
    ui.end_row();
    commit |= common_rows(ui, &mut o.common);
    commit
}

/// What a 2.5D operation machines, in words (face numbers from 1, as the tree shows them).
fn region_text(t: &RegionTarget) -> String {
    match t {
        RegionTarget::Auto { kinds } if kinds.is_empty() => {
            "the regions found from +Z (the strategy's kinds)".into()
        }
        RegionTarget::Auto { kinds } => {
            let names: Vec<String> = kinds
                .iter()
                .map(|k| {
                    match k {
                        RegionKind::Top => "top face",
                        RegionKind::ClosedPocket => "closed pocket",
                        RegionKind::OpenPocket => "open pocket",
                        RegionKind::Step => "step",
                        RegionKind::Slot => "slot",
                        RegionKind::OuterProfile => "outer profile",
                    }
                    .to_string()
                })
                .collect();
            format!("every {} found from +Z", names.join(", "))
        }
        RegionTarget::Faces { faces } => format!("the floors on faces {}", numbers(faces)),
        RegionTarget::Drawn {
            file,
            top_mm,
            depth_mm,
        } => format!(
            "the boundary in {} from {top_mm:.2} mm down {depth_mm:.2} mm",
            file.display()
        ),
    }
}

fn holes_text(h: &HoleSelection) -> String {
    match h {
        HoleSelection::Auto {
            min_diameter_mm,
            max_diameter_mm,
        } => match (min_diameter_mm, max_diameter_mm) {
            (None, None) => "the holes the tool fits".into(),
            (lo, hi) => format!(
                "the holes the tool fits, Ø {} to {} mm",
                lo.map_or_else(|| "0".to_string(), |v| format!("{v:.2}")),
                hi.map_or_else(|| "any".to_string(), |v| format!("{v:.2}"))
            ),
        },
        HoleSelection::Faces { faces } => format!("the holes on faces {}", numbers(faces)),
        HoleSelection::Points { points } => format!("{} holes at given points", points.len()),
    }
}

fn numbers(faces: &[usize]) -> String {
    faces
        .iter()
        .map(|f| (f + 1).to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

fn step_rows(ui: &mut egui::Ui, step_down: &mut f64, step_over: &mut f64) -> bool {
    let l = label(ui, "Step-down", "Depth of each level");
    let mut commit = number(ui, l, step_down, 1.0, 0.01..=100.0, 3, "mm");
    ui.end_row();
    let l = label(
        ui,
        "Step-over",
        "Distance between passes, as a share of the tool's diameter",
    );
    commit |= number(ui, l, step_over, 100.0, 1.0..=100.0, 1, "% of Ø");
    ui.end_row();
    commit
}

fn tolerance_row(ui: &mut egui::Ui, tolerance: &mut f64) -> bool {
    let l = label(
        ui,
        "Tolerance",
        "Largest deviation of the path from the exact offsets",
    );
    let commit = number(ui, l, tolerance, 1.0, 1e-4..=1.0, 4, "mm");
    ui.end_row();
    commit
}

/// A value with a default: a tick box "own" and, when ticked, the number (`start` when first
/// ticked).
fn optional_row(
    ui: &mut egui::Ui,
    (text, hint): (&str, &str),
    value: &mut Option<f64>,
    (range, decimals, unit): (std::ops::RangeInclusive<f64>, usize, &str),
    start: f64,
) -> bool {
    let l = label(ui, text, hint);
    let mut commit = false;
    ui.horizontal(|ui| {
        let mut own = value.is_some();
        if ui.checkbox(&mut own, "own").changed() {
            *value = own.then_some(start);
            commit = true;
        }
        if let Some(v) = value {
            commit |= number(ui, l, v, 1.0, range, decimals, unit);
        } else {
            ui.weak("default");
        }
    });
    ui.end_row();
    commit
}

/// A feed or speed with a default shown (`None`: the default, which a typed value replaces).
fn defaulted_row(
    ui: &mut egui::Ui,
    (text, hint): (&str, &str),
    value: &mut Option<f64>,
    default: f64,
    (range, unit): (std::ops::RangeInclusive<f64>, &str),
) -> bool {
    let l = label(ui, text, hint);
    let mut commit = false;
    ui.horizontal(|ui| {
        let mut v = value.unwrap_or(default);
        if number(ui, l, &mut v, 1.0, range, 0, unit) {
            *value = Some(v);
            commit = true;
        }
        if value.is_some() {
            if ui
                .small_button("default")
                .on_hover_text(format!("Back to the default ({default:.0} {unit})"))
                .clicked()
            {
                *value = None;
                commit = true;
            }
        } else {
            ui.weak("(default)");
        }
    });
    ui.end_row();
    commit
}

fn height_row(ui: &mut egui::Ui, (text, hint): (&str, &str), h: &mut Height) -> bool {
    let l = label(ui, text, hint);
    let mut commit = false;
    ui.horizontal(|ui| {
        commit |= number(ui, l, &mut h.mm, 1.0, -1000.0..=1000.0, 2, "mm");
        ui.label("above");
        egui::ComboBox::from_id_salt((text, "from"))
            .selected_text(from_text(h.from))
            .show_ui(ui, |ui| {
                for f in [
                    HeightFrom::StockTop,
                    HeightFrom::PartTop,
                    HeightFrom::Origin,
                ] {
                    commit |= ui.selectable_value(&mut h.from, f, from_text(f)).changed();
                }
            });
    });
    ui.end_row();
    commit
}

fn from_text(f: HeightFrom) -> &'static str {
    match f {
        HeightFrom::StockTop => "the stock's top",
        HeightFrom::PartTop => "the part's top",
        HeightFrom::Origin => "the setup origin",
    }
}

/// The shared record's rows.
fn common_rows(ui: &mut egui::Ui, c: &mut Common) -> bool {
    let mut commit = false;
    let l = label(ui, "Feed", "Cutting feed");
    commit |= number(
        ui,
        l,
        &mut c.feed_mm_per_min,
        1.0,
        1.0..=100_000.0,
        0,
        "mm/min",
    );
    ui.end_row();
    let (plunge, ramp) = (c.feed_mm_per_min / 3.0, c.feed_mm_per_min / 2.0);
    commit |= defaulted_row(
        ui,
        (
            "Plunge feed",
            "Feed along the tool axis (default a third of the feed)",
        ),
        &mut c.plunge_feed_mm_per_min,
        plunge,
        (1.0..=100_000.0, "mm/min"),
    );
    commit |= defaulted_row(
        ui,
        (
            "Ramp feed",
            "Feed of cuts going down (default half the feed)",
        ),
        &mut c.ramp_feed_mm_per_min,
        ramp,
        (1.0..=100_000.0, "mm/min"),
    );
    commit |= optional_row(
        ui,
        (
            "Spindle speed",
            "This operation's own speed (default: the post's)",
        ),
        &mut c.spindle_rpm,
        (1.0..=100_000.0, 0, "rpm"),
        8000.0,
    );
    label(ui, "Coolant", "Flood coolant (M8) while cutting");
    commit |= ui.checkbox(&mut c.coolant, "flood").changed();
    ui.end_row();
    commit |= height_row(
        ui,
        ("Clearance", "Rapids between regions and holes run here"),
        &mut c.clearance,
    );
    commit |= height_row(
        ui,
        (
            "Retract",
            "The R plane of the hole cycles and short retracts",
        ),
        &mut c.retract,
    );
    commit |= height_row(
        ui,
        (
            "Feed from",
            "Rapids down stop here; the tool feeds on at the plunge feed",
        ),
        &mut c.feed_from,
    );
    let l = label(ui, "Stock to leave, walls", "Material left on the walls");
    commit |= number(
        ui,
        l,
        &mut c.stock_to_leave_walls_mm,
        1.0,
        0.0..=50.0,
        3,
        "mm",
    );
    ui.end_row();
    let l = label(ui, "Stock to leave, floors", "Material left on the floors");
    commit |= number(
        ui,
        l,
        &mut c.stock_to_leave_floors_mm,
        1.0,
        0.0..=50.0,
        3,
        "mm",
    );
    ui.end_row();
    commit
}
