//! A side view of the machine drawn with the egui painter: base, trunnion pedestal with the
//! tilt axis seen end-on, the tilting table with its C axis, and the spindle above. For an A/C
//! machine the view looks along X (the A axis), for B/C along Y; a 3-axis mill shows a fixed
//! table. Sizes come from the machine's drawing geometry and pivot offsets, in mm.

use crate::machine::{KinematicsKind, Machine};
use egui::{Color32, Pos2, Rect, Shape, Stroke, pos2};
use glam::DVec2;

/// What the schematic shows besides the machine.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct SchematicView {
    /// Tilt axis angle drawn (degrees).
    pub tilt_deg: f64,
}

/// The side-view coordinates (across, up; mm) of a point turned by `angle_rad` about `pivot`.
#[must_use]
pub fn tilted(p: DVec2, pivot: DVec2, angle_rad: f64) -> DVec2 {
    pivot + DVec2::from_angle(angle_rad).rotate(p - pivot)
}

/// Draw the schematic of `machine` into `rect`.
pub fn draw_schematic(
    painter: &egui::Painter,
    rect: Rect,
    machine: &Machine,
    view: &SchematicView,
    visuals: &egui::Visuals,
) {
    let d = &machine.drawing;
    let radius = (d.table_diameter_mm / 2.0).max(1.0);
    let thick = d.table_thickness_mm.max(1.0);
    let (tilt_name, across) = match machine.kinematics {
        KinematicsKind::TableAc => (Some('A'), machine.tilt_offset_mm.y),
        KinematicsKind::TableBc => (Some('B'), machine.tilt_offset_mm.x),
        KinematicsKind::ThreeAxis => (None, 0.0),
    };
    // Table top at height 0 over the C centre; the pivot where the offsets put it.
    let pivot = DVec2::new(across, machine.tilt_offset_mm.z.min(-thick));
    let base_y = pivot.y - 1.2 * radius.max(-pivot.y);
    let spindle_y = 1.0 * radius;
    // Fit the scene (x in ±1.5 r, y from base to spindle top) into the rect.
    let (x0, x1) = (-1.6 * radius, 1.6 * radius);
    let (y0, y1) = (base_y, spindle_y + 0.6 * radius);
    let scale = (rect.width() as f64 / (x1 - x0)).min(rect.height() as f64 / (y1 - y0)) * 0.95;
    let centre = rect.center();
    let mid = DVec2::new((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let to_screen = |p: DVec2| -> Pos2 {
        let q = (p - mid) * scale;
        pos2(centre.x + q.x as f32, centre.y - q.y as f32)
    };
    let line = visuals.widgets.noninteractive.fg_stroke.color;
    let stroke = Stroke::new(1.5, line);
    let body = visuals.widgets.inactive.weak_bg_fill;
    let accent = super::super::super::theme::ACCENT;
    let poly = |pts: &[DVec2], fill: Color32| {
        painter.add(Shape::convex_polygon(
            pts.iter().map(|&p| to_screen(p)).collect(),
            fill,
            stroke,
        ));
    };
    let label = |p: DVec2, text: &str, colour: Color32| {
        painter.text(
            to_screen(p),
            egui::Align2::LEFT_CENTER,
            text,
            egui::FontId::proportional(13.0),
            colour,
        );
    };
    // Base.
    let bw = 1.5 * radius;
    poly(
        &[
            DVec2::new(-bw, base_y),
            DVec2::new(bw, base_y),
            DVec2::new(bw, base_y + 0.15 * radius),
            DVec2::new(-bw, base_y + 0.15 * radius),
        ],
        body,
    );
    // Counter-clockwise in the view for a positive turn, times the axis's direction.
    let angle = match tilt_name.and_then(|t| machine.axis(t)) {
        Some(axis) => view.tilt_deg.to_radians() * axis.direction,
        None => 0.0,
    };
    let turn = |p: DVec2| tilted(p, pivot, angle);
    if let Some(name) = tilt_name {
        // Pedestal from the base to the pivot, the cradle from the pivot to under the table.
        let w = 0.18 * radius;
        poly(
            &[
                DVec2::new(pivot.x - w, base_y + 0.15 * radius),
                DVec2::new(pivot.x + w, base_y + 0.15 * radius),
                DVec2::new(pivot.x + w, pivot.y),
                DVec2::new(pivot.x - w, pivot.y),
            ],
            body,
        );
        let cradle = [
            DVec2::new(pivot.x - w * 0.7, pivot.y),
            DVec2::new(pivot.x + w * 0.7, pivot.y),
            DVec2::new(pivot.x + w * 0.7, -thick),
            DVec2::new(pivot.x - w * 0.7, -thick),
        ];
        poly(&cradle.map(turn), body.gamma_multiply(1.3));
        // The tilt axis end-on.
        let r = (0.09 * radius * scale) as f32;
        painter.circle(to_screen(pivot), r, body, Stroke::new(2.0, accent));
        painter.circle_filled(to_screen(pivot), 2.5, accent);
        label(
            pivot + DVec2::new(0.2 * radius, -0.12 * radius),
            &format!("{name} {:+.0}°", view.tilt_deg),
            accent,
        );
    } else {
        let w = 0.5 * radius;
        poly(
            &[
                DVec2::new(-w, base_y + 0.15 * radius),
                DVec2::new(w, base_y + 0.15 * radius),
                DVec2::new(w, -thick),
                DVec2::new(-w, -thick),
            ],
            body,
        );
    }
    // The table (turned with the tilt), and the C axis through its centre.
    let table = [
        DVec2::new(-radius, -thick),
        DVec2::new(radius, -thick),
        DVec2::new(radius, 0.0),
        DVec2::new(-radius, 0.0),
    ];
    poly(&table.map(turn), body.gamma_multiply(1.6));
    if tilt_name.is_some() {
        let a = turn(DVec2::new(0.0, -thick - 0.2 * radius));
        let b = turn(DVec2::new(0.0, 0.55 * radius));
        painter.extend(Shape::dashed_line(
            &[to_screen(a), to_screen(b)],
            Stroke::new(1.5, accent),
            8.0,
            5.0,
        ));
        label(b + DVec2::new(0.05 * radius, 0.0), "C", accent);
    }
    // Spindle and tool above the table centre.
    let s = 0.16 * radius;
    poly(
        &[
            DVec2::new(-s, spindle_y),
            DVec2::new(s, spindle_y),
            DVec2::new(s, spindle_y + 0.5 * radius),
            DVec2::new(-s, spindle_y + 0.5 * radius),
        ],
        body,
    );
    painter.line_segment(
        [
            to_screen(DVec2::new(0.0, spindle_y)),
            to_screen(DVec2::new(0.0, 0.3 * radius)),
        ],
        Stroke::new(3.0, line),
    );
    label(DVec2::new(s * 1.4, spindle_y + 0.25 * radius), "Z", line);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilting_turns_about_the_pivot() {
        let pivot = DVec2::new(0.0, -150.0);
        let p = DVec2::new(250.0, 0.0);
        let q = tilted(p, pivot, std::f64::consts::FRAC_PI_2);
        assert!((q.distance(pivot) - p.distance(pivot)).abs() < 1e-9);
        // A quarter turn counter-clockwise: (250, 150) from the pivot becomes (−150, 250).
        assert!(q.distance(DVec2::new(-150.0, 100.0)) < 1e-9, "{q}");
    }
}
