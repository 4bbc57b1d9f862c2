//! Differential geometry of a surface at a point: unit normal, first and second fundamental
//! forms, principal curvatures and directions, normal curvature in a tangent direction.
//!
//! Sign convention (as Open CASCADE's `GeomLProp_SLProps`): the normal is `S_u × S_v` normalised
//! and curvatures are signed with respect to it (k_min ≤ k_max, 1/mm).

use super::DVec3;

/// Point and partial derivatives up to second order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    /// S(u, v), mm.
    pub p: DVec3,
    /// ∂S/∂u.
    pub su: DVec3,
    /// ∂S/∂v.
    pub sv: DVec3,
    /// ∂²S/∂u².
    pub suu: DVec3,
    /// ∂²S/∂u∂v.
    pub suv: DVec3,
    /// ∂²S/∂v².
    pub svv: DVec3,
}

/// Principal curvatures and directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principal {
    /// Smaller principal curvature, 1/mm.
    pub k_min: f64,
    /// Larger principal curvature, 1/mm.
    pub k_max: f64,
    /// Unit 3D tangent direction of k_min.
    pub dir_min: DVec3,
    /// Unit 3D tangent direction of k_max.
    pub dir_max: DVec3,
}
