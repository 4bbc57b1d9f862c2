//! The tilted work plane of a 3+2 setup in each dialect's own words: its rotation as the
//! control's angles, the blocks that set it and turn the tool onto it, and the block that
//! cancels it. `gcode::workplane` reads them back with the same conventions:
//!
//! - Fanuc `G68.2 X0 Y0 Z0 I J K` (Euler Z-X-Z, `R = Rz(I)·Rx(J)·Rz(K)`; Fanuc 30i/31i-B
//!   operator's manual, "tilted working plane indexing", Eulerian angle method), `G53.1` (tool
//!   axis direction control), `G69`;
//! - Sinumerik `CYCLE800(0, "TABLE", 0, 27, 0, 0, 0, A, B, C, 0, 0, 0, DIR, 100, 1)`
//!   (`_FR` 0: no retract, the post has retracted; `_ST` 0: a new plane; `_MODE` 27: axis by
//!   axis X, Y, Z, `R = Rx(A)·Ry(B)·Rz(C)` about the turned axes; `_DIR` ±1 the sign of the
//!   tilt axis the control turns to; SINUMERIK 840D sl cycles programming manual, CYCLE800
//!   "swivel plane"), `CYCLE800()`;
//! - Heidenhain `PLANE SPATIAL SPA SPB SPC TURN MB0 FMAX SEQ±` (about the fixed X, Y, Z in that
//!   order, `R = Rz(SPC)·Ry(SPB)·Rx(SPA)`; TNC 640 ISO programming manual, "PLANE function"),
//!   `PLANE RESET STAY`.
//!
//! The angles are rounded as the dialect writes them and the plane coordinates are computed
//! for the rotation those rounded angles give, so the control's plane is the one written.

use glam::{DMat3, DVec3};

use super::Dialect;

/// How a dialect writes a tilted work plane.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WorkPlaneStyle {
    /// Explicit rotary words and rotated machine coordinates (LinuxCNC; any control).
    #[default]
    Explicit,
    /// Fanuc `G68.2` / `G53.1` / `G69`.
    G68_2,
    /// Sinumerik `CYCLE800` / `CYCLE800()`.
    Cycle800,
    /// Heidenhain `PLANE SPATIAL … TURN` / `PLANE RESET`.
    PlaneSpatial,
}

fn at(r: &DMat3, row: usize, col: usize) -> f64 {
    r.col(col).to_array().get(row).copied().unwrap_or(0.0)
}

/// `(I, J, K)` in degrees with `R = Rz(I)·Rx(J)·Rz(K)`.
#[must_use]
pub fn euler_zxz(r: &DMat3) -> [f64; 3] {
    let beta = at(r, 2, 2).clamp(-1.0, 1.0).acos();
    let (alpha, gamma) = if beta.sin().abs() > 1e-12 {
        (
            at(r, 0, 2).atan2(-at(r, 1, 2)),
            at(r, 2, 0).atan2(at(r, 2, 1)),
        )
    } else {
        (at(r, 1, 0).atan2(at(r, 0, 0)), 0.0)
    };
    [alpha.to_degrees(), beta.to_degrees(), gamma.to_degrees()]
}

/// `(A, B, C)` in degrees with `R = Rz(C)·Ry(B)·Rx(A)` (turns about the fixed X, Y, Z).
#[must_use]
pub fn fixed_xyz(r: &DMat3) -> [f64; 3] {
    let b = (-at(r, 2, 0)).clamp(-1.0, 1.0).asin();
    let (a, c) = if b.cos().abs() > 1e-12 {
        (
            at(r, 2, 1).atan2(at(r, 2, 2)),
            at(r, 1, 0).atan2(at(r, 0, 0)),
        )
    } else {
        (0.0, (-at(r, 0, 1)).atan2(at(r, 1, 1)))
    };
    [a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

/// `(A, B, C)` in degrees with `R = Rx(A)·Ry(B)·Rz(C)` (turns about the turned X, Y, Z).
#[must_use]
pub fn turned_xyz(r: &DMat3) -> [f64; 3] {
    let b = at(r, 0, 2).clamp(-1.0, 1.0).asin();
    let (a, c) = if b.cos().abs() > 1e-12 {
        (
            (-at(r, 1, 2)).atan2(at(r, 2, 2)),
            (-at(r, 0, 1)).atan2(at(r, 0, 0)),
        )
    } else {
        (at(r, 2, 1).atan2(at(r, 1, 1)), 0.0)
    };
    [a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

fn rad(v: f64) -> f64 {
    v.to_radians()
}

/// The blocks that set plane `w` (columns: its axes in program coordinates) and turn the tool
/// onto it, the blocks that cancel it, and the rotation the written (rounded) angles give.
/// `tilt_rad` is the tilt axis the post turns to (its sign picks the control's solution).
/// `None` for [`WorkPlaneStyle::Explicit`].
#[must_use]
pub(super) fn blocks(
    d: &Dialect,
    style: WorkPlaneStyle,
    w: &DMat3,
    tilt_rad: f64,
) -> Option<(Vec<String>, Vec<String>, DMat3)> {
    let da = d.decimals_angle;
    let round = |v: f64| Dialect::rounded(v, da);
    let num = |v: f64| d.number(round(v), da);
    let signed = |v: f64| {
        let s = num(v);
        if s.starts_with('-') {
            s
        } else {
            format!("+{s}")
        }
    };
    let zero = d.number(0.0, d.decimals_linear);
    match style {
        WorkPlaneStyle::Explicit => None,
        WorkPlaneStyle::G68_2 => {
            let [i, j, k] = euler_zxz(w).map(round);
            let r = DMat3::from_rotation_z(rad(i))
                * DMat3::from_rotation_x(rad(j))
                * DMat3::from_rotation_z(rad(k));
            Some((
                vec![
                    format!(
                        "G68.2 X{zero} Y{zero} Z{zero} I{} J{} K{}",
                        num(i),
                        num(j),
                        num(k)
                    ),
                    "G53.1".into(),
                ],
                vec!["G69".into()],
                r,
            ))
        }
        WorkPlaneStyle::Cycle800 => {
            let [a, b, c] = turned_xyz(w).map(round);
            let r = DMat3::from_rotation_x(rad(a))
                * DMat3::from_rotation_y(rad(b))
                * DMat3::from_rotation_z(rad(c));
            let dir = if tilt_rad < 0.0 { -1 } else { 1 };
            Some((
                vec![format!(
                    "CYCLE800(0, \"TABLE\", 0, 27, 0, 0, 0, {}, {}, {}, 0, 0, 0, {dir}, 100, 1)",
                    num(a),
                    num(b),
                    num(c)
                )],
                vec!["CYCLE800()".into()],
                r,
            ))
        }
        WorkPlaneStyle::PlaneSpatial => {
            let [a, b, c] = fixed_xyz(w).map(round);
            let r = DMat3::from_rotation_z(rad(c))
                * DMat3::from_rotation_y(rad(b))
                * DMat3::from_rotation_x(rad(a));
            let seq = if tilt_rad < 0.0 { '-' } else { '+' };
            Some((
                vec![format!(
                    "PLANE SPATIAL SPA{} SPB{} SPC{} TURN MB0 FMAX SEQ{seq}",
                    signed(a),
                    signed(b),
                    signed(c)
                )],
                vec!["PLANE RESET STAY".into()],
                r,
            ))
        }
    }
}

/// The plane's tool axis (its +Z) in program coordinates.
#[must_use]
pub(super) fn tool_axis(w: &DMat3) -> DVec3 {
    *w * DVec3::Z
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Matrices and angles computed independently with numpy (rotation matrices written out
    /// element by element, not with glam):
    /// `python3 -c 'import numpy as n; …'` as in the comments of each case.
    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9)
    }

    fn m(rows: [[f64; 3]; 3]) -> DMat3 {
        DMat3::from_cols_array_2d(&rows).transpose()
    }

    #[test]
    fn a_90_degree_tilt_about_x() {
        // Rx(90°): rows [1,0,0], [0,0,-1], [0,1,0].
        let r = m([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]]);
        assert!(close(euler_zxz(&r), [0.0, 90.0, 0.0]));
        assert!(close(fixed_xyz(&r), [90.0, 0.0, 0.0]));
        assert!(close(turned_xyz(&r), [90.0, 0.0, 0.0]));
    }

    #[test]
    fn a_compound_tilt() {
        // numpy: Rz(30)·Ry(-20)·Rx(40) with
        // Rx(t)=[[1,0,0],[0,c,-s],[0,s,c]], Ry(t)=[[c,0,s],[0,1,0],[-s,0,c]],
        // Rz(t)=[[c,-s,0],[s,c,0],[0,0,1]]:
        let r = m([
            [
                0.813_797_681_349_373_8,
                -0.573_414_711_288_066_1,
                0.094_492_871_206_281_48,
            ],
            [
                0.469_846_310_392_954_16,
                0.553_490_792_972_461_3,
                -0.687_671_714_341_111_9,
            ],
            [
                0.342_020_143_325_668_7,
                0.604_022_773_555_053_6,
                0.719_846_310_392_954_2,
            ],
        ]);
        assert!(
            close(fixed_xyz(&r), [40.0, -20.0, 30.0]),
            "{:?}",
            fixed_xyz(&r)
        );
        // numpy, Z-X-Z of the same matrix: beta = acos(R33), alpha = atan2(R13, -R23),
        // gamma = atan2(R31, R32) (and Rz·Rx·Rz of them equals R, np.allclose):
        assert!(
            close(
                euler_zxz(&r),
                [
                    7.824_007_411_096_643,
                    43.958_207_002_617_77,
                    29.520_151_634_854_987
                ]
            ),
            "{:?}",
            euler_zxz(&r)
        );
        // numpy: Rx(a)·Ry(b)·Rz(c) angles of the same matrix: b = asin(R13),
        // a = atan2(-R23, R33), c = atan2(-R12, R11) (np.allclose back to R):
        assert!(
            close(
                turned_xyz(&r),
                [
                    43.690_498_071_688_04,
                    5.422_132_170_125_193,
                    35.169_129_767_203_245
                ]
            ),
            "{:?}",
            turned_xyz(&r)
        );
    }
}
