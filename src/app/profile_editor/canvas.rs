//! The 2D canvas of the profile editor: a view in mm (centre and scale, y up) with a grid on the
//! 1-2-5 series and snapping to it; the profile, its points, the exact electrode-centre path,
//! the electrode drawn along it, the per-point path and its gouges in colour.
//!
//! Mouse: a click adds a point (on a segment: inserted there; elsewhere: appended), dragging a
//! point moves it, a right click deletes it, dragging elsewhere (or with the right or middle
//! button) pans, the wheel zooms about the pointer.

use egui::{Color32, Pos2, Rect, Sense, Shape, Stroke, Vec2};
use glam::DVec2;

use crate::app::number_field::format_number;
use crate::profile::{Element, FlagKind, ProfileResult};

/// Colour of the profile.
pub const PROFILE: Color32 = Color32::from_rgb(225, 228, 235);
/// Colour of the exact centre path.
pub const PATH: Color32 = Color32::from_rgb(40, 190, 255);
/// Colour of the electrode outlines.
pub const ELECTRODE: Color32 = Color32::from_rgba_premultiplied(45, 90, 120, 70);
/// Colour of the per-point path.
pub const NAIVE: Color32 = Color32::from_rgb(130, 134, 145);
/// Colour of a plunge.
pub const PLUNGE: Color32 = Color32::from_rgb(255, 150, 30);
/// Colour of a side collision.
pub const COLLISION: Color32 = Color32::from_rgb(240, 60, 150);

/// Pixels within which the pointer is on a point or a segment.
const PICK_PX: f32 = 8.0;

/// The colour of a flag kind.
#[must_use]
pub fn flag_colour(kind: FlagKind) -> Color32 {
    match kind {
        FlagKind::Plunge => PLUNGE,
        FlagKind::Collision => COLLISION,
    }
}

/// What the canvas shows: centre (mm) and scale (pixels per mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// The world point at the canvas centre, mm.
    pub centre: DVec2,
    /// Pixels per mm.
    pub px_per_mm: f64,
    /// Fit the profile at the next frame.
    pub fit: bool,
}

impl Default for View {
    fn default() -> Self {
        Self {
            centre: DVec2::ZERO,
            px_per_mm: 20.0,
            fit: true,
        }
    }
}

impl View {
    /// Screen position of world point `p` in `rect`.
    #[must_use]
    pub fn to_screen(&self, rect: Rect, p: DVec2) -> Pos2 {
        let c = rect.center();
        let d = (p - self.centre) * self.px_per_mm;
        #[allow(clippy::cast_possible_truncation)]
        Pos2::new(c.x + d.x as f32, c.y - d.y as f32)
    }

    /// World point under screen position `s` in `rect`.
    #[must_use]
    pub fn to_world(&self, rect: Rect, s: Pos2) -> DVec2 {
        let c = rect.center();
        self.centre + DVec2::new(f64::from(s.x - c.x), f64::from(c.y - s.y)) / self.px_per_mm
    }

    /// The minor grid step, mm: 1, 2 or 5 × 10ⁿ, at least 16 pixels.
    #[must_use]
    pub fn grid_step_mm(&self) -> f64 {
        let min_mm = 16.0 / self.px_per_mm;
        let decade = 10f64.powf(min_mm.log10().floor());
        [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .map(|m| m * decade)
            .find(|s| *s >= min_mm)
            .unwrap_or(10.0 * decade)
    }

    /// `p` rounded to the grid.
    #[must_use]
    pub fn snap(&self, p: DVec2) -> DVec2 {
        let s = self.grid_step_mm();
        (p / s).round() * s
    }

    /// Fit the box `lo`..`hi` (mm) into `rect` with a margin.
    pub fn fit_box(&mut self, rect: Rect, lo: DVec2, hi: DVec2) {
        let size = (hi - lo).max(DVec2::splat(1e-6));
        let sx = f64::from(rect.width()) * 0.85 / size.x;
        let sy = f64::from(rect.height()) * 0.85 / size.y;
        self.centre = (lo + hi) / 2.0;
        self.px_per_mm = sx.min(sy).clamp(1e-4, 1e7);
        self.fit = false;
    }

    /// Zoom by `factor` keeping the world point under `at` in place.
    pub fn zoom_at(&mut self, rect: Rect, at: Pos2, factor: f64) {
        let before = self.to_world(rect, at);
        self.px_per_mm = (self.px_per_mm * factor).clamp(1e-4, 1e7);
        let after = self.to_world(rect, at);
        self.centre += before - after;
    }
}

/// What the user did on the canvas this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CanvasAction {
    /// Add a point at the end.
    Append(DVec2),
    /// Insert a point before row `usize`.
    Insert(usize, DVec2),
    /// Move the point of a row.
    Move(usize, DVec2),
    /// Delete the point of a row.
    Delete(usize),
    /// Select the point of a row.
    Select(usize),
}

/// The points and the elements between them as the canvas draws them.
pub struct Drawn<'a> {
    /// (row, point, bulge) of every usable row.
    pub points: &'a [(usize, DVec2, f64)],
    /// The last point joins the first.
    pub closed: bool,
    /// The computed result for these points (may be one edit old while a new one runs).
    pub result: Option<&'a ProfileResult>,
    /// Draw the electrode along the exact path.
    pub electrodes: bool,
    /// Draw the per-point path.
    pub naive: bool,
    /// The selected row.
    pub selected_row: Option<usize>,
    /// The flag picked in the list.
    pub selected_flag: Option<usize>,
}

impl Drawn<'_> {
    fn elements(&self) -> Vec<(usize, Element)> {
        let n = self.points.len();
        let m = if self.closed && n > 2 {
            n
        } else {
            n.saturating_sub(1)
        };
        (0..m)
            .filter_map(|k| {
                let &(row, a, bulge) = self.points.get(k)?;
                let &(_, b, _) = self.points.get((k + 1) % n)?;
                Some((row, Element::from_bulge(a, b, bulge)))
            })
            .collect()
    }
}

/// Screen points along an element (arcs sampled every 3° at most).
fn element_points(view: &View, rect: Rect, e: &Element) -> Vec<Pos2> {
    let n = match *e {
        Element::Line { .. } => 1,
        Element::Arc { sweep_rad, .. } => {
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let k = (sweep_rad.abs().to_degrees() / 3.0).ceil() as usize;
            k.clamp(2, 240)
        }
    };
    #[allow(clippy::cast_precision_loss)]
    (0..=n)
        .map(|i| view.to_screen(rect, e.point_at(i as f64 / n as f64)))
        .collect()
}

/// The canvas: draws, handles the mouse, returns what the user asked for.
pub fn canvas_ui(
    ui: &mut egui::Ui,
    view: &mut View,
    snap: bool,
    drawn: &Drawn<'_>,
    dragging: &mut Option<usize>,
) -> Option<CanvasAction> {
    let size = ui.available_size().max(Vec2::new(200.0, 200.0));
    let (response, painter) = ui.allocate_painter(size, Sense::click_and_drag());
    let response = response.accessible_name("Profile canvas");
    let rect = response.rect;
    if view.fit {
        fit(view, rect, drawn);
    }
    painter.rect_filled(rect, 0.0, Color32::from_rgb(22, 24, 28));
    grid(&painter, rect, view);
    draw_result(&painter, rect, view, drawn);
    draw_profile(&painter, rect, view, drawn);
    let action = interact(ui, &response, rect, view, snap, drawn, dragging);
    legend(&painter, rect, drawn);
    if let Some(p) = response.hover_pos() {
        let w = if snap {
            view.snap(view.to_world(rect, p))
        } else {
            view.to_world(rect, p)
        };
        let text = format!(
            "x {} mm  y {} mm  ·  grid {} mm{}",
            format_number(w.x, 4),
            format_number(w.y, 4),
            format_number(view.grid_step_mm(), 6),
            if snap { " (snap)" } else { "" }
        );
        painter.text(
            rect.left_bottom() + Vec2::new(8.0, -8.0),
            egui::Align2::LEFT_BOTTOM,
            text,
            egui::FontId::monospace(12.0),
            Color32::from_gray(200),
        );
    }
    action
}

fn fit(view: &mut View, rect: Rect, drawn: &Drawn<'_>) {
    let mut lo = DVec2::splat(f64::INFINITY);
    let mut hi = DVec2::splat(f64::NEG_INFINITY);
    for (_, e) in drawn.elements() {
        let (a, b) = e.bounds();
        lo = lo.min(a);
        hi = hi.max(b);
    }
    for &(_, p, _) in drawn.points {
        lo = lo.min(p);
        hi = hi.max(p);
    }
    if let Some(r) = drawn.result {
        for v in r.paths.iter().flat_map(|p| &p.vertices) {
            lo = lo.min(v.centre - r.radius_mm);
            hi = hi.max(v.centre + r.radius_mm);
        }
    }
    if lo.x.is_finite() && hi.x.is_finite() {
        let pad = ((hi - lo).max_element() * 0.05).max(1.0);
        view.fit_box(rect, lo - pad, hi + pad);
    } else {
        view.fit_box(rect, DVec2::splat(-10.0), DVec2::splat(10.0));
    }
}

fn grid(painter: &egui::Painter, rect: Rect, view: &View) {
    let step = view.grid_step_mm();
    let lo = view.to_world(rect, rect.left_bottom());
    let hi = view.to_world(rect, rect.right_top());
    let minor = Stroke::new(1.0, Color32::from_rgb(34, 37, 43));
    let major = Stroke::new(1.0, Color32::from_rgb(50, 54, 62));
    let axis = Stroke::new(1.0, Color32::from_rgb(85, 90, 102));
    #[allow(clippy::cast_possible_truncation)]
    let lines = |a: f64, b: f64| {
        let first = (a / step).floor() as i64;
        let last = (b / step).ceil() as i64;
        (first..=last).take(400)
    };
    for k in lines(lo.x, hi.x) {
        #[allow(clippy::cast_precision_loss)]
        let x = view.to_screen(rect, DVec2::new(k as f64 * step, 0.0)).x;
        let s = match (k == 0, k % 5 == 0) {
            (true, _) => axis,
            (false, true) => major,
            _ => minor,
        };
        painter.line_segment([Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())], s);
    }
    for k in lines(lo.y, hi.y) {
        #[allow(clippy::cast_precision_loss)]
        let y = view.to_screen(rect, DVec2::new(0.0, k as f64 * step)).y;
        let s = match (k == 0, k % 5 == 0) {
            (true, _) => axis,
            (false, true) => major,
            _ => minor,
        };
        painter.line_segment([Pos2::new(rect.left(), y), Pos2::new(rect.right(), y)], s);
    }
}

fn px(view: &View, mm: f64) -> f32 {
    #[allow(clippy::cast_possible_truncation)]
    let r = (mm * view.px_per_mm) as f32;
    r
}

fn draw_profile(painter: &egui::Painter, rect: Rect, view: &View, drawn: &Drawn<'_>) {
    for (_, e) in drawn.elements() {
        painter.add(Shape::line(
            element_points(view, rect, &e),
            Stroke::new(2.0, PROFILE),
        ));
    }
    let flagged = |row: usize| {
        drawn.result.and_then(|r| {
            r.flags
                .iter()
                .find(|f| f.point_index == row)
                .map(|f| flag_colour(f.kind))
        })
    };
    for &(row, p, _) in drawn.points {
        let s = view.to_screen(rect, p);
        let fill = flagged(row).unwrap_or(PROFILE);
        let selected = drawn.selected_row == Some(row);
        painter.circle(
            s,
            if selected { 5.5 } else { 4.0 },
            fill,
            Stroke::new(
                if selected { 2.0 } else { 1.0 },
                if selected {
                    Color32::YELLOW
                } else {
                    Color32::BLACK
                },
            ),
        );
    }
}

fn draw_result(painter: &egui::Painter, rect: Rect, view: &View, drawn: &Drawn<'_>) {
    let Some(r) = drawn.result else { return };
    let radius = px(view, r.radius_mm);
    if drawn.electrodes {
        for c in electrode_positions(r, 240) {
            painter.circle_stroke(view.to_screen(rect, c), radius, Stroke::new(1.0, ELECTRODE));
        }
    }
    if drawn.naive {
        let pts: Vec<Pos2> = r
            .naive
            .iter()
            .map(|n| view.to_screen(rect, n.centre))
            .collect();
        for p in &pts {
            painter.circle_filled(*p, 2.0, NAIVE);
        }
        painter.add(Shape::dashed_line(&pts, Stroke::new(1.0, NAIVE), 5.0, 4.0));
    }
    for p in &r.paths {
        for e in p.elements() {
            painter.add(Shape::line(
                element_points(view, rect, &e),
                Stroke::new(2.0, PATH),
            ));
        }
        for v in &p.vertices {
            painter.circle_filled(view.to_screen(rect, v.centre), 2.5, PATH);
        }
    }
    for (k, f) in r.flags.iter().enumerate() {
        let colour = flag_colour(f.kind);
        let selected = drawn.selected_flag == Some(k);
        let c = view.to_screen(rect, f.centre);
        painter.circle(
            c,
            radius,
            colour.gamma_multiply(if selected { 0.25 } else { 0.1 }),
            Stroke::new(if selected { 2.5 } else { 1.2 }, colour),
        );
        let d = view.to_screen(rect, f.deepest);
        let arm = if selected { 7.0 } else { 5.0 };
        let stroke = Stroke::new(2.0, colour);
        painter.line_segment([d - Vec2::splat(arm), d + Vec2::splat(arm)], stroke);
        painter.line_segment([d + Vec2::new(-arm, arm), d + Vec2::new(arm, -arm)], stroke);
    }
}

/// Centres at which the electrode is drawn: every path vertex and points between them about
/// 1.25 R apart, about `max` in all.
fn electrode_positions(r: &ProfileResult, max: usize) -> Vec<DVec2> {
    let total: f64 = r.paths.iter().map(crate::profile::ClPath::length_mm).sum();
    #[allow(clippy::cast_precision_loss)]
    let spacing = (r.radius_mm * 1.25).max(total / max.max(1) as f64);
    let mut out = Vec::new();
    for p in &r.paths {
        for e in p.elements() {
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = ((e.length() / spacing).ceil() as usize).clamp(1, max);
            #[allow(clippy::cast_precision_loss)]
            out.extend((0..n).map(|i| e.point_at(i as f64 / n as f64)));
        }
        if let Some(v) = p.vertices.last() {
            out.push(v.centre);
        }
    }
    out.truncate(4 * max);
    out
}

fn legend(painter: &egui::Painter, rect: Rect, drawn: &Drawn<'_>) {
    let mut items: Vec<(Color32, String)> = vec![(PROFILE, "profile".into())];
    if let Some(r) = drawn.result {
        items.push((PATH, "electrode centre path (exact offset)".into()));
        if drawn.electrodes {
            items.push((
                Color32::from_rgb(90, 160, 205),
                format!("electrode, R {} mm", format_number(r.radius_mm, 4)),
            ));
        }
        if drawn.naive {
            items.push((NAIVE, "per-point path (point + R · normal)".into()));
        }
        items.push((PLUNGE, "plunge of the per-point path".into()));
        items.push((COLLISION, "side collision of the per-point path".into()));
    }
    let mut y = rect.top() + 10.0;
    for (colour, text) in items {
        let x = rect.left() + 10.0;
        painter.line_segment(
            [Pos2::new(x, y + 7.0), Pos2::new(x + 18.0, y + 7.0)],
            Stroke::new(3.0, colour),
        );
        painter.text(
            Pos2::new(x + 24.0, y),
            egui::Align2::LEFT_TOP,
            text,
            egui::FontId::proportional(12.5),
            Color32::from_gray(215),
        );
        y += 18.0;
    }
}

/// The row whose point lies within [`PICK_PX`] of screen position `s`.
fn point_near(view: &View, rect: Rect, drawn: &Drawn<'_>, s: Pos2) -> Option<usize> {
    drawn
        .points
        .iter()
        .map(|&(row, p, _)| (row, view.to_screen(rect, p).distance(s)))
        .filter(|(_, d)| *d <= PICK_PX)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(row, _)| row)
}

/// The row ending the segment within [`PICK_PX`] of `s` (a point clicked there is inserted
/// before that row).
fn segment_near(view: &View, rect: Rect, drawn: &Drawn<'_>, s: Pos2) -> Option<usize> {
    let w = view.to_world(rect, s);
    let n = drawn.points.len();
    let tol = f64::from(PICK_PX) / view.px_per_mm;
    drawn
        .elements()
        .iter()
        .enumerate()
        .filter(|(_, (_, e))| e.distance(w) <= tol)
        .min_by(|a, b| a.1.1.distance(w).total_cmp(&b.1.1.distance(w)))
        .and_then(|(k, _)| {
            if k + 1 < n {
                drawn.points.get(k + 1).map(|p| p.0)
            } else {
                // The closing element of a closed profile: after the last row.
                drawn.points.last().map(|p| p.0 + 1)
            }
        })
}

fn interact(
    ui: &egui::Ui,
    response: &egui::Response,
    rect: Rect,
    view: &mut View,
    snap: bool,
    drawn: &Drawn<'_>,
    dragging: &mut Option<usize>,
) -> Option<CanvasAction> {
    let place = |view: &View, s: Pos2| {
        let w = view.to_world(rect, s);
        if snap { view.snap(w) } else { w }
    };
    if response.hovered() {
        let (scroll, zoom, pos) = ui.input(|i| {
            (
                i.smooth_scroll_delta.y,
                i.zoom_delta(),
                i.pointer.hover_pos(),
            )
        });
        if let Some(at) = pos {
            let factor = f64::from(zoom) * (f64::from(scroll) * 0.002).exp();
            if (factor - 1.0).abs() > 1e-6 {
                view.zoom_at(rect, at, factor);
            }
        }
    }
    if response.drag_started_by(egui::PointerButton::Primary) {
        let origin = ui.input(|i| i.pointer.press_origin());
        *dragging = origin.and_then(|o| point_near(view, rect, drawn, o));
    }
    if response.dragged_by(egui::PointerButton::Primary) {
        if let (Some(row), Some(s)) = (*dragging, response.interact_pointer_pos()) {
            return Some(CanvasAction::Move(row, place(view, s)));
        }
        pan(view, response.drag_delta());
    }
    if response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
    {
        pan(view, response.drag_delta());
    }
    if response.drag_stopped() {
        *dragging = None;
    }
    if response.clicked_by(egui::PointerButton::Primary)
        && let Some(s) = response.interact_pointer_pos()
    {
        if let Some(row) = point_near(view, rect, drawn, s) {
            return Some(CanvasAction::Select(row));
        }
        if let Some(row) = segment_near(view, rect, drawn, s) {
            return Some(CanvasAction::Insert(row, place(view, s)));
        }
        return Some(CanvasAction::Append(place(view, s)));
    }
    if response.clicked_by(egui::PointerButton::Secondary)
        && let Some(s) = response.interact_pointer_pos()
        && let Some(row) = point_near(view, rect, drawn, s)
    {
        return Some(CanvasAction::Delete(row));
    }
    None
}

fn pan(view: &mut View, delta: Vec2) {
    view.centre -= DVec2::new(f64::from(delta.x), -f64::from(delta.y)) / view.px_per_mm;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screen_and_world_are_inverse_and_the_grid_follows_1_2_5() {
        let rect = Rect::from_min_size(Pos2::new(100.0, 50.0), Vec2::new(800.0, 600.0));
        let view = View {
            centre: DVec2::new(3.0, -2.0),
            px_per_mm: 40.0,
            fit: false,
        };
        let p = DVec2::new(4.5, 1.25);
        let back = view.to_world(rect, view.to_screen(rect, p));
        assert!((back - p).length() < 1e-5, "{back}");
        // y up: a larger y is higher on the screen.
        assert!(view.to_screen(rect, p).y < view.to_screen(rect, DVec2::new(4.5, 0.0)).y);
        assert!((view.grid_step_mm() - 0.5).abs() < 1e-12);
        let mut v = view;
        v.px_per_mm = 3.0;
        assert!((v.grid_step_mm() - 10.0).abs() < 1e-9);
        assert_eq!(view.snap(DVec2::new(1.26, -0.74)), DVec2::new(1.5, -0.5));
        let mut z = view;
        let at = Pos2::new(300.0, 200.0);
        let w = z.to_world(rect, at);
        z.zoom_at(rect, at, 2.0);
        assert!((z.to_world(rect, at) - w).length() < 1e-5);
    }
}
