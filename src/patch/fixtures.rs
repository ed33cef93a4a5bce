//! Patches the unit tests share (here and in the modules that use
//! `patch`): built from a formula per control point, so a test says what
//! surface it needs in one line.

use glam::Vec3;

use super::bezier::BezierPatch;

/// The patch whose control point (i, j) (u index i, v index j) is
/// `f(i, j)`.
pub fn grid(f: impl Fn(f32, f32) -> Vec3) -> BezierPatch {
    BezierPatch {
        pts: std::array::from_fn(|k| f((k % 4) as f32, (k / 4) as f32)),
    }
}

/// A wavy patch over the unit square, not symmetric in u and v (the base
/// patch of the rational tests).
pub fn wavy() -> BezierPatch {
    grid(|i, j| {
        let (x, y) = (i / 3.0, j / 3.0);
        Vec3::new(x, y, (x * 2.7).sin() * (y * 1.9).cos() * 0.6)
    })
}

/// A gently curved patch over [offset, offset + 3] × [0, 3]: `ramp(0.0)`
/// ends where `ramp(3.0)` starts, up to the curvature of that shared side.
pub fn ramp(offset: f32) -> BezierPatch {
    grid(|i, j| Vec3::new(i + offset, j, i * j * 0.1))
}
