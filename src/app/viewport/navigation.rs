//! Mouse and trackpad navigation: left drag orbits, right or middle drag (or Shift + left) pans,
//! the wheel zooms toward the cursor.

use glam::Vec2;

use crate::render::Camera;

/// Radians of orbit per point dragged.
const ORBIT_RAD_PER_POINT: f32 = 0.008;
/// Zoom factor per point of wheel scroll.
const ZOOM_PER_POINT: f32 = 0.998;

/// Apply this frame's pointer input over the viewport `response` to `camera`. Returns true when
/// the camera moved.
pub fn navigate(ui: &egui::Ui, response: &egui::Response, camera: &mut Camera) -> bool {
    let rect = response.rect;
    let before = *camera;
    let (shift, delta) = ui.input(|i| (i.modifiers.shift, i.pointer.delta()));
    let pan = response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
        || (shift && response.dragged_by(egui::PointerButton::Primary));
    if pan {
        let ppp = ui.ctx().pixels_per_point();
        camera.pan(Vec2::new(delta.x, delta.y) * ppp, rect.height() * ppp);
    } else if response.dragged_by(egui::PointerButton::Primary) {
        camera.orbit(delta.x * ORBIT_RAD_PER_POINT, delta.y * ORBIT_RAD_PER_POINT);
    }
    if let Some(pos) = response.hover_pos() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        let pinch = ui.input(|i| i.zoom_delta());
        let factor = ZOOM_PER_POINT.powf(scroll) / pinch;
        if (factor - 1.0).abs() > 1e-6 {
            camera.zoom_toward(factor, ndc(rect, pos), rect.aspect_ratio());
        }
    }
    *camera != before
}

/// Normalised device coordinates (−1..1, y up) of `pos` in `rect`.
#[must_use]
pub fn ndc(rect: egui::Rect, pos: egui::Pos2) -> Vec2 {
    let x = (pos.x - rect.left()) / rect.width().max(1.0) * 2.0 - 1.0;
    let y = 1.0 - (pos.y - rect.top()) / rect.height().max(1.0) * 2.0;
    Vec2::new(x, y)
}
