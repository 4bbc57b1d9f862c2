//! Tool-axis modes: the surface normal with lead and tilt (5-axis), a fixed axis (3-axis and
//! 3+2), or toward/away from a point or a line; plus the limit on the axis change between poses.

use glam::DVec3;

/// How the tool axis is chosen at a contact.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum AxisMode {
    /// `a = cos T (cos L n + sin L f) + sin T t`: lead L toward the feed f (the thesis's Sturz),
    /// tilt T sideways toward `t = n × f` (the literature's form, eq. 3.36, with α, β from L, T).
    Normal {
        /// Lead toward the feed, rad.
        lead: f64,
        /// Tilt sideways, rad.
        tilt: f64,
    },
    /// A fixed unit axis (3-axis: +z; 3+2: any).
    Fixed(DVec3),
    /// From the contact toward a point (the axis points at it).
    TowardPoint(DVec3),
    /// From a point toward the contact (the axis points away from it).
    AwayFromPoint(DVec3),
    /// Toward the nearest point of a line (point, unit direction).
    TowardLine(DVec3, DVec3),
    /// Away from the nearest point of a line (point, unit direction).
    AwayFromLine(DVec3, DVec3),
}

impl Default for AxisMode {
    fn default() -> Self {
        Self::Normal {
            lead: 0.0,
            tilt: 0.0,
        }
    }
}

impl AxisMode {
    /// The unit axis at contact `cc` with tool-side normal `n` and unit feed `f` (⟂ n). Falls
    /// back to `n` where the mode's direction is undefined (contact on the point or line).
    #[must_use]
    pub fn axis(&self, cc: DVec3, n: DVec3, f: DVec3) -> DVec3 {
        let t = n.cross(f);
        let a = match *self {
            Self::Normal { lead, tilt } => {
                (n * lead.cos() + f * lead.sin()) * tilt.cos() + t * tilt.sin()
            }
            Self::Fixed(a) => a,
            Self::TowardPoint(p) => p - cc,
            Self::AwayFromPoint(p) => cc - p,
            Self::TowardLine(p, d) => {
                let d = d.normalize_or_zero();
                let q = p + d * (cc - p).dot(d);
                q - cc
            }
            Self::AwayFromLine(p, d) => {
                let d = d.normalize_or_zero();
                let q = p + d * (cc - p).dot(d);
                cc - q
            }
        };
        a.try_normalize().unwrap_or(n)
    }

    /// Lead angle (rad) of the mode, 0 when it is not a normal-relative mode.
    #[must_use]
    pub fn lead(&self) -> f64 {
        match *self {
            Self::Normal { lead, .. } => lead,
            _ => 0.0,
        }
    }
}

/// Angle between two unit axes, rad.
#[must_use]
pub fn axis_angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// Smooth a sequence of axes in place with a three-point moving average repeated `passes`
/// times (ends kept), renormalising; used to damp the axis change between poses.
pub fn smooth_axes(axes: &mut [DVec3], passes: usize) {
    for _ in 0..passes {
        let copy: Vec<DVec3> = axes.to_vec();
        for (i, a) in axes.iter_mut().enumerate().skip(1) {
            if let (Some(p), Some(q)) = (copy.get(i - 1), copy.get(i + 1)) {
                *a = (*p + *a * 2.0 + *q).try_normalize().unwrap_or(*a);
            }
        }
    }
}
