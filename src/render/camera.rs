//! The viewport camera: orbits a target point in a Z-up world, pans, zooms toward the cursor,
//! fits a bounding box, snaps to standard views, and switches between perspective and
//! orthographic projection while keeping the apparent size of the target plane.

use glam::camera::rh::proj::directx::{orthographic, perspective};
use glam::camera::rh::view::look_to_mat4;
use glam::{Mat3, Mat4, Vec2, Vec3};

/// Perspective or orthographic projection.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Projection {
    /// Perspective with the camera's vertical field of view.
    Perspective,
    /// Orthographic; the visible height at the target equals the perspective one.
    Orthographic,
}

/// The standard views of a Z-up CAM world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StandardView {
    /// Looking down −Z, X to the right, Y up.
    Top,
    /// Looking along +Y (from the front), X to the right, Z up.
    Front,
    /// Looking along −X (from the right), Y to the right, Z up.
    Right,
    /// Looking along −Y (from the back), X to the left, Z up.
    Back,
    /// Looking along +X (from the left), Y to the left, Z up.
    Left,
    /// Looking up +Z (from below), X to the right, Y down.
    Bottom,
    /// Isometric, from +X −Y +Z.
    Iso,
    /// Isometric from the octant of the eye: the signs of its X, Y and Z (true: positive).
    /// `IsoFrom([true, false, true])` is [`StandardView::Iso`].
    IsoFrom([bool; 3]),
}

impl StandardView {
    /// Every named standard view, in menu order (the other isometric octants are reached from
    /// the view cube's corners).
    pub const ALL: [Self; 7] = [
        Self::Top,
        Self::Front,
        Self::Right,
        Self::Back,
        Self::Left,
        Self::Bottom,
        Self::Iso,
    ];

    /// A short name for menus.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Top => "Top",
            Self::Front => "Front",
            Self::Right => "Right",
            Self::Back => "Back",
            Self::Left => "Left",
            Self::Bottom => "Bottom",
            Self::Iso | Self::IsoFrom([true, false, true]) => "Isometric",
            Self::IsoFrom(signs) => OCTANT_NAMES[octant_index(signs)],
        }
    }

    /// The view from the octant of the eye with these signs; [`StandardView::Iso`] for its own
    /// octant.
    #[must_use]
    pub fn iso_from(signs: [bool; 3]) -> Self {
        if signs == [true, false, true] {
            Self::Iso
        } else {
            Self::IsoFrom(signs)
        }
    }

    /// (yaw, pitch) in rad of the direction from the target to the eye.
    fn angles_rad(self) -> (f32, f32) {
        use std::f32::consts::{FRAC_PI_2, PI};
        // atan(1/sqrt(2)) = 35.264°: the eye on a cube diagonal.
        let iso_pitch = (1.0_f32 / 2.0_f32.sqrt()).atan();
        let sign = |positive: bool| if positive { 1.0_f32 } else { -1.0 };
        match self {
            Self::Top => (-FRAC_PI_2, FRAC_PI_2),
            Self::Front => (-FRAC_PI_2, 0.0),
            Self::Right => (0.0, 0.0),
            Self::Back => (FRAC_PI_2, 0.0),
            Self::Left => (PI, 0.0),
            Self::Bottom => (-FRAC_PI_2, -FRAC_PI_2),
            Self::Iso => Self::IsoFrom([true, false, true]).angles_rad(),
            Self::IsoFrom([x, y, z]) => (sign(y).atan2(sign(x)), sign(z) * iso_pitch),
        }
    }
}

/// Menu names of the isometric views by octant (index: x + 2y + 4z, 1 for positive).
const OCTANT_NAMES: [&str; 8] = [
    "Isometric (−X −Y −Z)",
    "Isometric (+X −Y −Z)",
    "Isometric (−X +Y −Z)",
    "Isometric (+X +Y −Z)",
    "Isometric (−X −Y +Z)",
    "Isometric (+X −Y +Z)",
    "Isometric (−X +Y +Z)",
    "Isometric (+X +Y +Z)",
];

fn octant_index([x, y, z]: [bool; 3]) -> usize {
    usize::from(x) + 2 * usize::from(y) + 4 * usize::from(z)
}

/// A sphere bounding what the camera should see (for clip planes and fitting).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundingSphere {
    /// Centre, world units (mm).
    pub centre: Vec3,
    /// Radius, world units (mm); at least a small positive value.
    pub radius: f32,
}

impl BoundingSphere {
    /// The sphere around an axis-aligned box (`min`, `max`).
    #[must_use]
    pub fn from_box(min: Vec3, max: Vec3) -> Self {
        let centre = (min + max) * 0.5;
        let radius = ((max - min).length() * 0.5).max(1e-3);
        Self { centre, radius }
    }
}

/// An orbit camera in a Z-up world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The point the camera orbits and looks at.
    pub target: Vec3,
    /// Distance from the target to the eye.
    pub distance: f32,
    /// Azimuth of the eye about +Z, rad (0: eye on +X).
    pub yaw_rad: f32,
    /// Elevation of the eye above the XY plane, rad, in [−π/2, π/2].
    pub pitch_rad: f32,
    /// Vertical field of view for perspective, rad.
    pub fov_y_rad: f32,
    /// Projection kind.
    pub projection: Projection,
    /// What the scene occupies, for the near and far planes.
    pub scene: BoundingSphere,
    /// The frame the camera orbits in (world from frame, a rotation): yaw turns about its Z,
    /// and the standard views look along its axes. The identity orbits the world's Z; a setup's
    /// rotation shows the part as it lies on that setup's table, "Top" looking down its spindle.
    pub frame: Mat3,
}

impl Default for Camera {
    fn default() -> Self {
        let mut camera = Self {
            target: Vec3::ZERO,
            distance: 200.0,
            yaw_rad: 0.0,
            pitch_rad: 0.0,
            fov_y_rad: 30.0_f32.to_radians(),
            projection: Projection::Perspective,
            scene: BoundingSphere {
                centre: Vec3::ZERO,
                radius: 50.0,
            },
            frame: Mat3::IDENTITY,
        };
        camera.set_view(StandardView::Iso);
        camera
    }
}

impl Camera {
    /// Unit vector from the target toward the eye, in the camera's [`Camera::frame`].
    #[must_use]
    pub fn local_backward(&self) -> Vec3 {
        let (sy, cy) = self.yaw_rad.sin_cos();
        let (sp, cp) = self.pitch_rad.sin_cos();
        Vec3::new(cp * cy, cp * sy, sp)
    }

    /// Unit vector pointing right on screen, in the camera's [`Camera::frame`].
    #[must_use]
    pub fn local_right(&self) -> Vec3 {
        let (sy, cy) = self.yaw_rad.sin_cos();
        Vec3::new(-sy, cy, 0.0)
    }

    /// Unit vector pointing up on screen, in the camera's [`Camera::frame`].
    #[must_use]
    pub fn local_up(&self) -> Vec3 {
        self.local_backward().cross(self.local_right())
    }

    /// Unit vector from the target toward the eye (world).
    #[must_use]
    pub fn backward(&self) -> Vec3 {
        (self.frame * self.local_backward()).normalize_or(Vec3::Z)
    }

    /// Unit vector pointing right on screen (world).
    #[must_use]
    pub fn right(&self) -> Vec3 {
        (self.frame * self.local_right()).normalize_or(Vec3::X)
    }

    /// Unit vector pointing up on screen (world).
    #[must_use]
    pub fn up(&self) -> Vec3 {
        self.backward().cross(self.right())
    }

    /// The eye position.
    #[must_use]
    pub fn eye(&self) -> Vec3 {
        self.target + self.backward() * self.distance
    }

    /// Half the visible height at the target's depth (world units).
    #[must_use]
    pub fn half_height_at_target(&self) -> f32 {
        self.distance * (self.fov_y_rad * 0.5).tan()
    }

    /// World-from-view is the inverse of this: the view matrix (world → camera space).
    #[must_use]
    pub fn view_from_world(&self) -> Mat4 {
        look_to_mat4(self.eye(), -self.backward(), self.up())
    }

    /// The projection matrix (camera space → clip space, depth 0..1) for `aspect` = width / height.
    #[must_use]
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let to_centre = (self.scene.centre - self.eye()).dot(-self.backward());
        let reach = self.scene.radius * 1.05 + 1e-3;
        let far = (to_centre + reach).max(1e-2);
        match self.projection {
            Projection::Perspective => {
                let near = (to_centre - reach).max(far * 1e-4);
                perspective(self.fov_y_rad, aspect, near, far)
            }
            Projection::Orthographic => {
                let h = self.half_height_at_target();
                let w = h * aspect;
                let near = to_centre - reach;
                orthographic(-w, w, -h, h, near, far.max(near + 1e-2))
            }
        }
    }

    /// Clip-from-world for `aspect`.
    #[must_use]
    pub fn clip_from_world(&self, aspect: f32) -> Mat4 {
        self.clip_from_view(aspect) * self.view_from_world()
    }

    /// Orbit by a screen drag of (`dx`, `dy`) rad: yaw about the frame's Z, pitch clamped at the
    /// poles.
    pub fn orbit(&mut self, dx_rad: f32, dy_rad: f32) {
        use std::f32::consts::{FRAC_PI_2, TAU};
        self.yaw_rad = (self.yaw_rad - dx_rad).rem_euclid(TAU);
        self.pitch_rad = (self.pitch_rad + dy_rad).clamp(-FRAC_PI_2, FRAC_PI_2);
    }

    /// Pan by a drag of `delta_px` pixels in a viewport `viewport_height_px` pixels tall, so the
    /// point under the cursor at the target's depth follows the cursor.
    pub fn pan(&mut self, delta_px: Vec2, viewport_height_px: f32) {
        if viewport_height_px <= 0.0 {
            return;
        }
        let world_per_px = 2.0 * self.half_height_at_target() / viewport_height_px;
        self.target += (-self.right() * delta_px.x + self.up() * delta_px.y) * world_per_px;
    }

    /// Zoom by `factor` (< 1 moves closer) toward the point under the cursor at `ndc`
    /// (normalised device coordinates, −1..1, y up) on the target's plane.
    pub fn zoom_toward(&mut self, factor: f32, ndc: Vec2, aspect: f32) {
        if !(factor.is_finite() && factor > 0.0) {
            return;
        }
        let h = self.half_height_at_target();
        let under_cursor =
            self.target + self.right() * (ndc.x * h * aspect) + self.up() * (ndc.y * h);
        let new_distance = (self.distance * factor).clamp(1e-3, 1e7);
        let applied = new_distance / self.distance;
        self.target = under_cursor + (self.target - under_cursor) * applied;
        self.distance = new_distance;
    }

    /// Look at the whole of `sphere` from the current direction, filling the viewport.
    pub fn fit(&mut self, sphere: BoundingSphere, aspect: f32) {
        let aspect = if aspect.is_finite() && aspect > 0.0 {
            aspect
        } else {
            1.0
        };
        let half_y = self.fov_y_rad * 0.5;
        let half_x = (half_y.tan() * aspect).atan();
        let half = half_y.min(half_x);
        self.scene = sphere;
        self.target = sphere.centre;
        self.distance = sphere.radius / half.sin() * 1.08;
    }

    /// Turn to a standard view (keeps target and distance).
    pub fn set_view(&mut self, view: StandardView) {
        let (yaw, pitch) = view.angles_rad();
        self.yaw_rad = yaw;
        self.pitch_rad = pitch;
    }

    /// The view ray through `ndc` (−1..1, y up): origin on the near side and unit direction.
    #[must_use]
    pub fn ray(&self, ndc: Vec2, aspect: f32) -> (Vec3, Vec3) {
        let inv = self.clip_from_world(aspect).inverse();
        let near = inv.project_point3(Vec3::new(ndc.x, ndc.y, 0.0));
        let far = inv.project_point3(Vec3::new(ndc.x, ndc.y, 1.0));
        (near, (far - near).normalize_or(-self.backward()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn near(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn standard_views_have_the_textbook_axes() {
        let mut c = Camera::default();
        c.set_view(StandardView::Top);
        assert!(near(c.backward(), Vec3::Z) && near(c.right(), Vec3::X) && near(c.up(), Vec3::Y));
        c.set_view(StandardView::Front);
        assert!(near(c.backward(), -Vec3::Y) && near(c.right(), Vec3::X) && near(c.up(), Vec3::Z));
        c.set_view(StandardView::Right);
        assert!(near(c.backward(), Vec3::X) && near(c.right(), Vec3::Y) && near(c.up(), Vec3::Z));
        c.set_view(StandardView::Back);
        assert!(near(c.backward(), Vec3::Y) && near(c.right(), -Vec3::X) && near(c.up(), Vec3::Z));
        c.set_view(StandardView::Left);
        assert!(near(c.backward(), -Vec3::X) && near(c.right(), -Vec3::Y) && near(c.up(), Vec3::Z));
        c.set_view(StandardView::Bottom);
        assert!(near(c.backward(), -Vec3::Z) && near(c.right(), Vec3::X) && near(c.up(), -Vec3::Y));
        c.set_view(StandardView::Iso);
        assert!(near(c.backward(), Vec3::new(1.0, -1.0, 1.0).normalize()));
        // Every octant: the eye on that cube diagonal, Z never pointing down on screen.
        for i in 0..8_u8 {
            let signs = [i & 1 != 0, i & 2 != 0, i & 4 != 0];
            let diagonal = Vec3::from_array(signs.map(|s| if s { 1.0 } else { -1.0 }));
            c.set_view(StandardView::iso_from(signs));
            assert!(near(c.backward(), diagonal.normalize()), "{signs:?}");
            assert!(c.up().z > 0.0);
        }
        assert_eq!(
            StandardView::iso_from([true, false, true]),
            StandardView::Iso
        );
        assert_eq!(
            StandardView::IsoFrom([true, false, true]).name(),
            "Isometric"
        );
        assert_eq!(
            StandardView::IsoFrom([false; 3]).name(),
            "Isometric (−X −Y −Z)"
        );
    }

    #[test]
    fn a_frame_turns_the_standard_views_with_it() {
        // A setup lying on its front face: its Z is the part's −Y, its X the part's X.
        let frame = Mat3::from_cols(Vec3::X, Vec3::Z, -Vec3::Y);
        let mut c = Camera {
            frame,
            ..Camera::default()
        };
        c.set_view(StandardView::Top);
        assert!(near(c.backward(), -Vec3::Y), "{:?}", c.backward());
        assert!(
            near(c.right(), Vec3::X) && near(c.up(), Vec3::Z),
            "{:?}",
            c.up()
        );
        assert!(near(c.local_backward(), Vec3::Z));
        // The view matrix agrees: the target's frame-Z neighbour projects straight at the eye.
        let m = c.clip_from_world(1.0);
        let a = m.project_point3(c.target);
        let b = m.project_point3(c.target - Vec3::Y * 5.0);
        assert!((a.x - b.x).abs() < 1e-5 && (a.y - b.y).abs() < 1e-5);
    }

    #[test]
    fn target_projects_to_the_centre_and_right_to_plus_x() {
        let c = Camera::default();
        let m = c.clip_from_world(1.5);
        let p = m.project_point3(c.target);
        assert!(p.x.abs() < 1e-5 && p.y.abs() < 1e-5 && (0.0..1.0).contains(&p.z));
        let q = m.project_point3(c.target + c.right());
        assert!(q.x > 0.0 && q.y.abs() < 1e-4);
    }

    #[test]
    fn zoom_keeps_the_point_under_the_cursor() {
        for projection in [Projection::Perspective, Projection::Orthographic] {
            let mut c = Camera {
                projection,
                ..Camera::default()
            };
            let ndc = Vec2::new(0.4, -0.3);
            let aspect = 1.6;
            let h = c.half_height_at_target();
            let point = c.target + c.right() * (ndc.x * h * aspect) + c.up() * (ndc.y * h);
            c.zoom_toward(0.5, ndc, aspect);
            let p = c.clip_from_world(aspect).project_point3(point);
            assert!(
                (p.x - ndc.x).abs() < 1e-4 && (p.y - ndc.y).abs() < 1e-4,
                "{p:?}"
            );
        }
    }

    #[test]
    fn fit_puts_the_whole_sphere_in_view() {
        let mut c = Camera::default();
        let sphere = BoundingSphere {
            centre: Vec3::new(10.0, 20.0, 5.0),
            radius: 30.0,
        };
        let aspect = 0.5;
        c.fit(sphere, aspect);
        let m = c.clip_from_world(aspect);
        for dir in [Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z] {
            let p = m.project_point3(sphere.centre + dir * sphere.radius);
            assert!(
                p.x.abs() <= 1.0 && p.y.abs() <= 1.0 && (0.0..=1.0).contains(&p.z),
                "{p:?}"
            );
        }
    }
}
