//! Bicubic Bézier patches: storage, curve and surface evaluation, partials.
//!
//! Control point `p[i][j]` of the paper (i along u, j along v) is stored at
//! `pts[4 * j + i]`: rows of constant v, u running fastest. The `.bpt` reader
//! and the cage converter both produce this order, and a test pins it with the
//! teapot's outward normals (∂S/∂u × ∂S/∂v points out of the model).

use std::ops::{Add, Mul, Sub};

use glam::Vec3;

use super::ops::{cross3, dot3};

/// One bicubic Bézier patch over [0,1]².
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BezierPatch {
    /// 16 control points, `pts[4 * v + u]`.
    pub pts: [Vec3; 16],
}

/// The four boundary curves, counter-clockwise in (u, v):
/// bottom (v = 0), right (u = 1), top (v = 1), left (u = 0).
pub const EDGE_BOTTOM: usize = 0;
/// Right boundary curve, u = 1.
pub const EDGE_RIGHT: usize = 1;
/// Top boundary curve, v = 1.
pub const EDGE_TOP: usize = 2;
/// Left boundary curve, u = 0.
pub const EDGE_LEFT: usize = 3;

/// What a control point of [`curve`] must offer: `Vec3` (Cartesian) and
/// `Vec4` (homogeneous, `patch::rational`).
pub trait Cubic: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f32, Output = Self> {}
impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f32, Output = T>> Cubic for T {}

/// Cubic Bézier curve at `u0`, in the paper's operation order (§3.4):
/// Bernstein weights as written there, then `((b0 p0 + b1 p1) + (b2 p2 + b3 p3))`.
/// The order makes the curve evaluated at `u` on `p` bitwise equal to the
/// reversed curve evaluated at `1 - u`, for any `u` where `1 - (1 - u) == u`.
/// Generic over the point type so that homogeneous (`Vec4`) curves of
/// rational patches take exactly the same operations.
#[inline]
pub fn curve<T: Cubic>(u0: f32, p: &[T; 4]) -> T {
    let u1 = 1.0 - u0;
    let b0 = u1 * u1 * u1;
    let b1 = 3.0 * u1 * u0 * u1;
    let b2 = 3.0 * u0 * u1 * u0;
    let b3 = u0 * u0 * u0;
    (p[0] * b0 + p[1] * b1) + (p[2] * b2 + p[3] * b3)
}

/// Derivative of a cubic Bézier curve at `u0` (for shading only; not part of
/// any watertightness argument).
#[inline]
pub fn curve_derivative<T: Cubic>(u0: f32, p: &[T; 4]) -> T {
    let u1 = 1.0 - u0;
    let d0 = p[1] - p[0];
    let d1 = p[2] - p[1];
    let d2 = p[3] - p[2];
    ((d0 * (u1 * u1) + d1 * (2.0 * u1 * u0)) + d2 * (u0 * u0)) * 3.0
}

impl BezierPatch {
    /// Control point at (u index `i`, v index `j`).
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> Vec3 {
        self.pts[4 * j + i]
    }

    /// The control row of constant v index `j`, u ascending.
    #[inline]
    pub fn row(&self, j: usize) -> [Vec3; 4] {
        [
            self.pts[4 * j],
            self.pts[4 * j + 1],
            self.pts[4 * j + 2],
            self.pts[4 * j + 3],
        ]
    }

    /// The control column of constant u index `i`, v ascending.
    #[inline]
    pub fn column(&self, i: usize) -> [Vec3; 4] {
        [
            self.pts[i],
            self.pts[4 + i],
            self.pts[8 + i],
            self.pts[12 + i],
        ]
    }

    /// Boundary curve `e` (see `EDGE_*`), in counter-clockwise order around
    /// the domain. The edge tier samples both directions, so the direction
    /// only matters for wedge winding, which is derived from the same order.
    pub fn edge(&self, e: usize) -> [Vec3; 4] {
        let rev = |c: [Vec3; 4]| [c[3], c[2], c[1], c[0]];
        match e {
            EDGE_BOTTOM => self.row(0),
            EDGE_RIGHT => self.column(3),
            EDGE_TOP => rev(self.row(3)),
            EDGE_LEFT => rev(self.column(0)),
            _ => panic!("edge index {e} out of range"),
        }
    }

    /// Surface point, curve of curves: the four rows are evaluated at `u`,
    /// then the resulting curve at `v`. On a boundary this reduces exactly to
    /// the boundary curve's own evaluation, which is what makes two patches
    /// sharing that curve produce the same bits there.
    pub fn eval(&self, u: f32, v: f32) -> Vec3 {
        let c = [
            curve(u, &self.row(0)),
            curve(u, &self.row(1)),
            curve(u, &self.row(2)),
            curve(u, &self.row(3)),
        ];
        curve(v, &c)
    }

    /// Partial derivatives (∂S/∂u, ∂S/∂v).
    pub fn partials(&self, u: f32, v: f32) -> (Vec3, Vec3) {
        let du = [
            curve_derivative(u, &self.row(0)),
            curve_derivative(u, &self.row(1)),
            curve_derivative(u, &self.row(2)),
            curve_derivative(u, &self.row(3)),
        ];
        let pu = [
            curve(u, &self.row(0)),
            curve(u, &self.row(1)),
            curve(u, &self.row(2)),
            curve(u, &self.row(3)),
        ];
        (curve(v, &du), curve_derivative(v, &pu))
    }

    /// Unnormalised surface normal ∂S/∂u × ∂S/∂v. Where a boundary curve
    /// collapses to a point (the teapot's lid and bottom) the cross product
    /// vanishes; the normal is then taken a little way into the domain.
    pub fn normal(&self, u: f32, v: f32) -> Vec3 {
        normal_from_partials(|u, v| self.partials(u, v), u, v)
    }

    /// Axis-aligned bounding box of the control points.
    pub fn bbox(&self) -> (Vec3, Vec3) {
        let mut lo = self.pts[0];
        let mut hi = self.pts[0];
        for p in &self.pts[1..] {
            lo = super::ops::min3(lo, *p);
            hi = super::ops::max3(hi, *p);
        }
        (lo, hi)
    }

    /// The box of the control points of all `patches` (which contains the
    /// surfaces), or `None` for none.
    pub fn bounds(patches: &[BezierPatch]) -> Option<(Vec3, Vec3)> {
        let (mut lo, mut hi) = patches.first()?.bbox();
        for p in patches {
            let (a, b) = p.bbox();
            lo = super::ops::min3(lo, a);
            hi = super::ops::max3(hi, b);
        }
        Some((lo, hi))
    }

    /// True when every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.pts.iter().all(|p| p.is_finite())
    }

    /// The same patch with -0.0 replaced by +0.0. Signed zeros are equal as
    /// numbers but not as bits, and adding a zero weight term can turn one into
    /// the other, so imports canonicalise once.
    pub fn canonical_zeros(mut self) -> Self {
        for p in &mut self.pts {
            *p += Vec3::ZERO;
        }
        self
    }

    /// The patch with its parameter domain reordered: `R(u, v) = S(u'', v'')`
    /// where `u' = 1 - u` if `flip_u` (else `u`), likewise `v'`, and
    /// `(u'', v'') = (v', u')` if `swap`. Used by the reordering-invariance
    /// test of §4.4.
    pub fn reoriented(&self, swap: bool, flip_u: bool, flip_v: bool) -> Self {
        let mut out = *self;
        for j in 0..4 {
            for i in 0..4 {
                let ni = if flip_u { 3 - i } else { i };
                let nj = if flip_v { 3 - j } else { j };
                let (oi, oj) = if swap { (nj, ni) } else { (ni, nj) };
                out.pts[4 * j + i] = self.at(oi, oj);
            }
        }
        out
    }
}

/// The unnormalised normal ∂S/∂u × ∂S/∂v at (u, v) of the surface whose
/// partial derivatives `partials` gives, taken a little way into the domain
/// where it vanishes ([`BezierPatch::normal`], `RationalPatch::normal`).
pub fn normal_from_partials(partials: impl Fn(f32, f32) -> (Vec3, Vec3), u: f32, v: f32) -> Vec3 {
    let (su, sv) = partials(u, v);
    let n = cross3(su, sv);
    let scale = dot3(su, su) * dot3(sv, sv);
    if dot3(n, n) > 1e-12 * scale && scale > 0.0 {
        return n;
    }
    let nudge = |t: f32| t + (0.5 - t) * 1e-3;
    let (su, sv) = partials(nudge(u), nudge(v));
    cross3(su, sv)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::fixtures::grid;

    fn sample_patch() -> BezierPatch {
        grid(|i, j| {
            let (x, y) = (i / 3.0, j / 3.0);
            Vec3::new(x, y, (x * 3.1).sin() * (y * 2.3).cos() * 0.7)
        })
    }

    #[test]
    fn curve_is_symmetric_under_reversal() {
        let p = sample_patch().row(1);
        let r = [p[3], p[2], p[1], p[0]];
        for k in 0..=1024u32 {
            let u = k as f32 / 1024.0;
            assert_eq!(curve(u, &p), curve(1.0 - u, &r), "u = {u}");
        }
    }

    #[test]
    fn eval_hits_corners_and_boundaries_exactly() {
        let s = sample_patch();
        assert_eq!(s.eval(0.0, 0.0), s.at(0, 0));
        assert_eq!(s.eval(1.0, 0.0), s.at(3, 0));
        assert_eq!(s.eval(1.0, 1.0), s.at(3, 3));
        assert_eq!(s.eval(0.0, 1.0), s.at(0, 3));
        for k in 0..=64 {
            let t = k as f32 / 64.0;
            assert_eq!(s.eval(t, 0.0), curve(t, &s.row(0)));
            assert_eq!(s.eval(0.0, t), curve(t, &s.column(0)));
            assert_eq!(s.eval(t, 1.0), curve(t, &s.row(3)));
            assert_eq!(s.eval(1.0, t), curve(t, &s.column(3)));
        }
    }

    #[test]
    fn partials_match_finite_differences() {
        let s = sample_patch();
        let h = 1e-3;
        for &(u, v) in &[(0.2f32, 0.3f32), (0.7, 0.9), (0.5, 0.5)] {
            let (su, sv) = s.partials(u, v);
            let fu = (s.eval(u + h, v) - s.eval(u - h, v)) / (2.0 * h);
            let fv = (s.eval(u, v + h) - s.eval(u, v - h)) / (2.0 * h);
            assert!((su - fu).length() < 1e-2, "{su} vs {fu}");
            assert!((sv - fv).length() < 1e-2, "{sv} vs {fv}");
        }
    }

    #[test]
    fn reorientation_maps_the_surface() {
        let s = sample_patch();
        for &(swap, fu, fv) in &[
            (false, true, false),
            (true, false, false),
            (true, true, true),
        ] {
            let r = s.reoriented(swap, fu, fv);
            for &(u, v) in &[(0.25f32, 0.75f32), (0.5, 0.125)] {
                let (nu, nv) = (if fu { 1.0 - u } else { u }, if fv { 1.0 - v } else { v });
                let (ou, ov) = if swap { (nv, nu) } else { (nu, nv) };
                assert!((r.eval(u, v) - s.eval(ou, ov)).length() < 1e-5);
            }
        }
    }
}
