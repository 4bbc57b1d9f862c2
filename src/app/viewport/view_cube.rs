//! The view cube: a small cube in the viewport's upper-right corner, turned with the camera and
//! drawn with the egui painter. Clicking a face snaps to that standard view, clicking near a
//! corner to the isometric view from that corner's octant.
//!
//! The geometry is pure: the cube [-1, 1]³ is projected orthographically with the camera's
//! right and up vectors to "cube coordinates" (x right, y down, in units of the cube's half
//! size, origin at the cube's centre); the widget scales them into its rectangle.

use glam::{Vec2, Vec3};

use crate::render::{Camera, StandardView};

/// Side of the widget's square, points.
const WIDGET_SIZE: f32 = 96.0;
/// Gap between the widget and the viewport's corner, points.
const MARGIN: f32 = 8.0;
/// A point inside a face is a corner pick where both face coordinates are beyond this (of 1).
const CORNER_ZONE: f32 = 0.6;
/// Faces seen more obliquely than this (cosine of the angle to the view) are not drawn.
const MIN_FACING: f32 = 1e-3;

/// One face of the cube.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubeFace {
    /// Its label.
    pub label: &'static str,
    /// The view that looks at it.
    pub view: StandardView,
    /// Outward normal (world).
    pub normal: Vec3,
    /// First in-face axis (world).
    pub u: Vec3,
    /// Second in-face axis (world), `normal × u`.
    pub v: Vec3,
}

const fn face(label: &'static str, view: StandardView, normal: Vec3, u: Vec3, v: Vec3) -> CubeFace {
    CubeFace {
        label,
        view,
        normal,
        u,
        v,
    }
}

/// The six faces.
pub const FACES: [CubeFace; 6] = [
    face("TOP", StandardView::Top, Vec3::Z, Vec3::X, Vec3::Y),
    face(
        "BOTTOM",
        StandardView::Bottom,
        Vec3::NEG_Z,
        Vec3::X,
        Vec3::NEG_Y,
    ),
    face("FRONT", StandardView::Front, Vec3::NEG_Y, Vec3::X, Vec3::Z),
    face("BACK", StandardView::Back, Vec3::Y, Vec3::NEG_X, Vec3::Z),
    face("RIGHT", StandardView::Right, Vec3::X, Vec3::Y, Vec3::Z),
    face(
        "LEFT",
        StandardView::Left,
        Vec3::NEG_X,
        Vec3::NEG_Y,
        Vec3::Z,
    ),
];

/// A face as seen by the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectedFace {
    /// Index into [`FACES`].
    pub face: usize,
    /// Corners in cube coordinates (x right, y down), in order around the face.
    pub corners: [Vec2; 4],
    /// Cosine of the angle between the face's normal and the direction to the eye (> 0).
    pub facing: f32,
}

/// Cube coordinates (x right, y down) of the vector `w` of the camera's frame (the cube's axes
/// are the frame's: a setup's, when the view follows the setup).
fn project(camera: &Camera, w: Vec3) -> Vec2 {
    Vec2::new(w.dot(camera.local_right()), -w.dot(camera.local_up()))
}

/// The faces turned toward the eye, from back to front (the order to paint them in).
#[must_use]
pub fn projected_faces(camera: &Camera) -> Vec<ProjectedFace> {
    let back = camera.local_backward();
    let mut faces: Vec<ProjectedFace> = FACES
        .iter()
        .enumerate()
        .filter_map(|(i, f)| {
            let facing = f.normal.dot(back);
            (facing > MIN_FACING).then(|| ProjectedFace {
                face: i,
                corners: [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(a, b)| project(camera, f.normal + f.u * a + f.v * b)),
                facing,
            })
        })
        .collect();
    // A visible face's centre is nearer the eye the more it faces it.
    faces.sort_by(|a, b| a.facing.total_cmp(&b.facing));
    faces
}

/// What lies under a point of the cube.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubePick {
    /// Index into [`FACES`] of the face under the point.
    pub face: usize,
    /// The face coordinates (u, v) of the point, each in [−1, 1].
    pub at: Vec2,
    /// The cube corner (signs of x, y, z; true: positive) when the point is near one.
    pub corner: Option<[bool; 3]>,
}

impl CubePick {
    /// The view a click here asks for.
    #[must_use]
    pub fn view(&self) -> Option<StandardView> {
        match self.corner {
            Some(signs) => Some(StandardView::iso_from(signs)),
            None => FACES.get(self.face).map(|f| f.view),
        }
    }
}

/// The face (and corner) under `point` (cube coordinates), the frontmost one if several.
#[must_use]
pub fn pick(camera: &Camera, point: Vec2) -> Option<CubePick> {
    projected_faces(camera).iter().rev().find_map(|p| {
        let f = FACES.get(p.face)?;
        // point = P(n) + u P(u) + v P(v): solve the 2×2 system.
        let (c, eu, ev) = (
            project(camera, f.normal),
            project(camera, f.u),
            project(camera, f.v),
        );
        let det = eu.perp_dot(ev);
        if det.abs() < 1e-9 {
            return None;
        }
        let d = point - c;
        let at = Vec2::new(d.perp_dot(ev) / det, eu.perp_dot(d) / det);
        if at.abs().max_element() > 1.0 {
            return None;
        }
        let corner = (at.abs().min_element() > CORNER_ZONE).then(|| {
            let w = f.normal + f.u * at.x.signum() + f.v * at.y.signum();
            [w.x > 0.0, w.y > 0.0, w.z > 0.0]
        });
        Some(CubePick {
            face: p.face,
            at,
            corner,
        })
    })
}

/// Where the cube sits in `viewport`: its square (in the upper-right corner), and the map from
/// cube coordinates to screen points.
pub fn cube_layout(viewport: egui::Rect) -> (egui::Rect, impl Fn(Vec2) -> egui::Pos2) {
    let rect = egui::Rect::from_min_size(
        egui::pos2(
            viewport.right() - MARGIN - WIDGET_SIZE,
            viewport.top() + MARGIN,
        ),
        egui::vec2(WIDGET_SIZE, WIDGET_SIZE),
    );
    // The cube's silhouette reaches √3 half sizes from the centre.
    let scale = WIDGET_SIZE * 0.5 / 3.0_f32.sqrt() * 0.95;
    let centre = rect.center();
    (rect, move |p: Vec2| centre + egui::vec2(p.x, p.y) * scale)
}

/// Draw the cube in the upper-right corner of `viewport` and return the view a click on it asks
/// for.
pub fn view_cube_ui(ui: &egui::Ui, viewport: egui::Rect, camera: &Camera) -> Option<StandardView> {
    let (rect, to_screen) = cube_layout(viewport);
    if !viewport.contains_rect(rect) {
        return None;
    }
    let response = ui.interact(rect, ui.scope_id().with("view cube"), egui::Sense::click());
    let centre = to_screen(Vec2::ZERO);
    let scale = to_screen(Vec2::X).x - centre.x;
    let hovered = response.hover_pos().and_then(|pos| {
        pick(
            camera,
            Vec2::new(pos.x - centre.x, pos.y - centre.y) / scale,
        )
    });

    let painter = ui.painter_at(rect);
    let edge = egui::Stroke::new(1.0, egui::Color32::from_gray(40));
    for p in projected_faces(camera) {
        let Some(f) = FACES.get(p.face) else { continue };
        let shade = (90.0 + 110.0 * p.facing) as u8;
        let whole_face = hovered.is_some_and(|h| h.face == p.face && h.corner.is_none());
        let fill = if whole_face {
            egui::Color32::from_rgb(255, 160, 40)
        } else {
            egui::Color32::from_rgb(shade / 2 + 20, shade / 2 + 26, shade / 2 + 36)
        };
        let points: Vec<egui::Pos2> = p.corners.iter().map(|&c| to_screen(c)).collect();
        painter.add(egui::Shape::convex_polygon(points, fill, edge));
        if let Some(h) = hovered.filter(|h| h.face == p.face && h.corner.is_some()) {
            // The hovered corner's zone of this face.
            let (su, sv) = (h.at.x.signum(), h.at.y.signum());
            let zone = [
                (CORNER_ZONE, CORNER_ZONE),
                (1.0, CORNER_ZONE),
                (1.0, 1.0),
                (CORNER_ZONE, 1.0),
            ]
            .map(|(a, b)| to_screen(project(camera, f.normal + f.u * (a * su) + f.v * (b * sv))));
            painter.add(egui::Shape::convex_polygon(
                zone.to_vec(),
                egui::Color32::from_rgb(255, 160, 40),
                egui::Stroke::NONE,
            ));
        }
        if p.facing > 0.25 {
            let alpha = (255.0 * ((p.facing - 0.25) / 0.5).min(1.0)) as u8;
            painter.text(
                to_screen(project(camera, f.normal)),
                egui::Align2::CENTER_CENTER,
                f.label,
                egui::FontId::proportional(9.0 + 3.0 * p.facing),
                egui::Color32::from_rgba_unmultiplied(235, 238, 245, alpha),
            );
        }
    }
    if let Some(h) = hovered {
        response
            .clone()
            .on_hover_text(h.view().map_or("", StandardView::name));
    }
    if response.clicked() {
        hovered.and_then(|h| h.view())
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera(yaw_deg: f32, pitch_deg: f32) -> Camera {
        Camera {
            yaw_rad: yaw_deg.to_radians(),
            pitch_rad: pitch_deg.to_radians(),
            ..Camera::default()
        }
    }

    fn viewed(view: StandardView) -> Camera {
        let mut c = Camera::default();
        c.set_view(view);
        c
    }

    /// The reference: cast the orthographic view ray through `point` at the box [-1, 1]³ (slab
    /// method): the face it enters by and where.
    fn ray_face(c: &Camera, point: Vec2) -> Option<(usize, Vec3)> {
        let dir = -c.backward();
        let origin = c.right() * point.x - c.up() * point.y + c.backward() * 10.0;
        let (mut t_in, mut t_out, mut normal) = (f32::NEG_INFINITY, f32::INFINITY, Vec3::ZERO);
        for axis in 0..3 {
            let (o, d) = (origin[axis], dir[axis]);
            if d.abs() < 1e-9 {
                if o.abs() > 1.0 {
                    return None;
                }
                continue;
            }
            let (t0, t1) = ((-1.0 - o) / d, (1.0 - o) / d);
            let (near, far) = (t0.min(t1), t0.max(t1));
            if near > t_in {
                t_in = near;
                let mut n = Vec3::ZERO;
                n[axis] = -d.signum();
                normal = n;
            }
            t_out = t_out.min(far);
        }
        let face = FACES.iter().position(|f| f.normal == normal)?;
        (t_in <= t_out).then_some((face, origin + dir * t_in))
    }

    #[test]
    fn face_axes_are_right_handed_and_views_look_at_their_face() {
        for f in FACES {
            assert!((f.normal.cross(f.u) - f.v).length() < 1e-6, "{}", f.label);
            // The face's view puts its normal toward the eye.
            assert!(
                (viewed(f.view).backward() - f.normal).length() < 1e-5,
                "{}",
                f.label
            );
        }
    }

    #[test]
    fn faces_are_sorted_back_to_front() {
        // Mostly from the top, a little from the front and right.
        let c = camera(-60.0, 70.0);
        let faces = projected_faces(&c);
        let labels: Vec<&str> = faces.iter().map(|p| FACES[p.face].label).collect();
        // Eye direction (cos70 cos(-60), cos70 sin(-60), sin70) = (0.171, -0.296, 0.940).
        assert_eq!(labels, ["RIGHT", "FRONT", "TOP"]);
        // Painter's order: each face's centre is farther from the eye than the next one's.
        let eye = c.backward() * 10.0;
        for w in faces.windows(2) {
            let d = |p: &ProjectedFace| (FACES[p.face].normal - eye).length();
            assert!(d(&w[0]) > d(&w[1]));
        }
        // Looking straight at a face shows only that face.
        assert_eq!(projected_faces(&viewed(StandardView::Front)).len(), 1);
    }

    #[test]
    fn clicks_name_the_face_under_the_point_as_a_ray_does() {
        // Brute-force reference: a ray cast into the cube, over a grid of points and many views.
        let mut compared = 0;
        for yaw in (-180..180).step_by(25) {
            for pitch in (-85..=85).step_by(17) {
                let c = camera(yaw as f32, pitch as f32);
                for i in -9..=9 {
                    for j in -9..=9 {
                        let point = Vec2::new(i as f32, j as f32) * 0.19;
                        let hit = ray_face(&c, point);
                        let expected = hit.map(|(f, _)| f);
                        let got = pick(&c, point).map(|p| p.face);
                        // Points within a hair of an edge may fall either side.
                        let on_edge = pick(&c, point)
                            .is_some_and(|p| p.at.abs().max_element() > 0.995)
                            || hit.is_some_and(|(_, q)| {
                                let a = q.abs();
                                a.x + a.y + a.z - a.max_element() - a.min_element() > 0.995
                            });
                        if !on_edge {
                            assert_eq!(got, expected, "yaw {yaw} pitch {pitch} at {point}");
                            compared += 1;
                        }
                    }
                }
            }
        }
        assert!(compared > 10_000);
    }

    #[test]
    fn faces_and_corners_give_their_views() {
        let front = viewed(StandardView::Front);
        let at = |c: &Camera, x: f32, y: f32| pick(c, Vec2::new(x, y)).and_then(|p| p.view());
        assert_eq!(at(&front, 0.0, 0.0), Some(StandardView::Front));
        assert_eq!(at(&front, 0.3, -0.5), Some(StandardView::Front));
        assert_eq!(at(&front, 1.2, 0.0), None);
        // Upper right of the front face: the corner (+X, −Y, +Z), the usual isometric view.
        assert_eq!(at(&front, 0.9, -0.9), Some(StandardView::Iso));
        assert_eq!(
            at(&front, -0.9, 0.9),
            Some(StandardView::IsoFrom([false, false, false]))
        );
        // In an isometric view the corner toward the eye projects onto the centre.
        for i in 0..8_u8 {
            let signs = [i & 1 != 0, i & 2 != 0, i & 4 != 0];
            let c = viewed(StandardView::iso_from(signs));
            let p = pick(&c, Vec2::new(0.01, 0.02)).expect("the cube is there");
            assert_eq!(p.corner, Some(signs));
        }
        let top = viewed(StandardView::Top);
        assert_eq!(at(&top, 0.0, 0.0), Some(StandardView::Top));
        // Top view: X right, Y up, so the screen's lower left is the corner (−X, −Y, +Z).
        assert_eq!(
            at(&top, -0.8, 0.8),
            Some(StandardView::IsoFrom([false, false, true]))
        );
    }

    #[test]
    fn a_click_on_the_viewport_s_cube_asks_for_the_view_and_selects_nothing() {
        use crate::app::command::Command;
        use crate::app::viewport::{ViewportState, viewport_ui};
        type State = (ViewportState, Vec<Command>, egui::Rect);
        let mut h = egui_kittest::Harness::builder()
            .with_size(egui::vec2(640.0, 400.0))
            .build_ui_state(
                |ui, (state, commands, rect): &mut State| {
                    *rect = ui.available_rect_before_wrap();
                    viewport_ui(
                        ui,
                        state,
                        None,
                        crate::app::viewport::ViewportExtras::default(),
                        commands,
                    );
                },
                (ViewportState::default(), Vec::new(), egui::Rect::NOTHING),
            );
        h.run();
        let (viewport, camera) = (h.state().2, h.state().0.camera);
        let (_, to_screen) = cube_layout(viewport);
        // The default camera is isometric: the top face's centre is on the cube's upper half.
        let top = to_screen(project(&camera, Vec3::Z));
        h.hover_at(top);
        h.run();
        for pressed in [true, false] {
            h.event(egui::Event::PointerButton {
                pos: top,
                button: egui::PointerButton::Primary,
                pressed,
                modifiers: egui::Modifiers::NONE,
            });
            h.run();
        }
        let commands = &h.state().1;
        assert!(
            commands.contains(&Command::StandardView(StandardView::Top)),
            "{commands:?}"
        );
        assert!(
            !commands.iter().any(|c| matches!(c, Command::Select(_))),
            "the click went to the viewport too: {commands:?}"
        );
    }
}
