//! Subdivision of rational patches: the sub-patch in homogeneous
//! coordinates and the criterion on its projected points. The GPU twin is
//! `glsl/common/rational_subdiv.glsl`, operation for operation.
//!
//! A rational sub-patch is the blossom of the homogeneous control points
//! (w·p, w) ([`reconstruct_points`] on `Vec4`), so the edge a sub-patch
//! shares with its neighbour (in the same base patch or across a base-patch
//! edge with the same control points and weights) has the same homogeneous
//! bits on both sides, exactly as in the polynomial case (§4.4). Everything
//! the criterion measures is then a function of those bits alone:
//!
//! - edge tier: the end points are the projected end control points, the
//!   samples are the projected homogeneous curve at 1/3 from either end
//!   ([`curve4`], reversal-symmetric); the line test is the polynomial one
//!   ([`criterion::line_sample_flat`]) on those Cartesian points;
//! - inner tier: the corners and the four samples of the polynomial inner
//!   tier, each a projected homogeneous point;
//! - frustum culling: the box of the projected (Cartesian) control points.
//!   With positive weights every surface point is a convex combination of
//!   them (the Bernstein-times-weight coefficients over their sum are
//!   non-negative and sum to 1), so the box holds the sub-patch.
//!
//! Back-face culling reduces to the polynomial bound. With B(u, v) the
//! homogeneous surface, w = B.w > 0 and p = B.xyz / w, the 4×4 determinant
//! det[B, B_u, B_v, (eye, 1)] equals w³ (p − eye) · (p_u × p_v), so it has
//! the sign of the facing test. Subtracting multiples of the last column
//! turns it into det[Q, Q_u, Q_v] = Q · (Q_u × Q_v) for the *polynomial*
//! patch Q with control points w_i (p_i − eye) (the homogeneous points with
//! the eye moved to the origin). [`back_facing`] is therefore
//! [`cull::back_facing`] on Q with the eye at the origin: its interval
//! bound is exactly as sound for Q as for any polynomial patch.

use glam::{Vec3, Vec4};

use super::bezier::BezierPatch;
use super::bezier::{EDGE_BOTTOM, EDGE_LEFT, EDGE_RIGHT, EDGE_TOP};
use super::blossom::reconstruct_points;
use super::criterion::{self, tolerance2, EdgeSample};
use super::cull;
use super::ops::{max3, min3, THIRD};
use super::rational::{curve4, homogeneous, project, RationalPatch};
use super::view::ViewParams;

/// A (sub-)patch as 16 homogeneous control points, `pts[4 * v + u]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HomPatch {
    /// (w·p, w) per control point.
    pub pts: [Vec4; 16],
}

impl HomPatch {
    /// The homogeneous control points of `base`.
    pub fn of(base: &RationalPatch) -> Self {
        Self {
            pts: std::array::from_fn(|k| homogeneous(base.patch.pts[k], base.w[k])),
        }
    }

    /// The sub-patch over [a,b]×[c,d], by blossoms.
    pub fn sub(&self, a: f32, b: f32, c: f32, d: f32) -> Self {
        Self {
            pts: reconstruct_points(&self.pts, a, b, c, d),
        }
    }

    /// Homogeneous control point (u index `i`, v index `j`).
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> Vec4 {
        self.pts[4 * j + i]
    }

    /// The Cartesian control point (u index `i`, v index `j`).
    #[inline]
    pub fn point(&self, i: usize, j: usize) -> Vec3 {
        project(self.at(i, j))
    }

    /// The surface point at (u, v): rows at u, then the column at v, then
    /// divided (the order of [`RationalPatch::eval`]).
    pub fn eval(&self, u: f32, v: f32) -> Vec3 {
        let row = |j: usize| [0, 1, 2, 3].map(|i| self.at(i, j));
        let c = [0, 1, 2, 3].map(|j| curve4(u, &row(j)));
        project(curve4(v, &c))
    }

    /// Boundary curve `e` (see `EDGE_*` in [`super::bezier`]), homogeneous,
    /// counter-clockwise around the domain like [`BezierPatch::edge`](super::bezier::BezierPatch::edge).
    pub fn edge(&self, e: usize) -> [Vec4; 4] {
        let k: [usize; 4] = match e {
            EDGE_BOTTOM => [0, 1, 2, 3],
            EDGE_RIGHT => [3, 7, 11, 15],
            EDGE_TOP => [15, 14, 13, 12],
            EDGE_LEFT => [12, 8, 4, 0],
            _ => panic!("edge index {e} out of range"),
        };
        k.map(|i| self.pts[i])
    }

    /// The box of the Cartesian control points (holds the surface for
    /// positive weights).
    pub fn bbox(&self) -> (Vec3, Vec3) {
        let first = project(self.pts[0]);
        let (mut lo, mut hi) = (first, first);
        for h in &self.pts[1..] {
            let p = project(*h);
            lo = min3(lo, p);
            hi = max3(hi, p);
        }
        (lo, hi)
    }
}

/// The edge tier's two samples of homogeneous boundary curve `h`: the
/// projected curve at 1/3 from either end, each computed in its own
/// direction, with the projected end points.
pub fn edge_samples(h: &[Vec4; 4]) -> [EdgeSample; 2] {
    let reversed = [h[3], h[2], h[1], h[0]];
    let (a, b) = (project(h[0]), project(h[3]));
    [
        EdgeSample {
            point: project(curve4(THIRD, h)),
            from: a,
            to: b,
        },
        EdgeSample {
            point: project(curve4(THIRD, &reversed)),
            from: b,
            to: a,
        },
    ]
}

/// `t²` of the edge tier: ε projected at the midpoint of the projected end
/// points (symmetric in them).
pub fn edge_tolerance2(h: &[Vec4; 4], vp: &ViewParams) -> f32 {
    tolerance2((project(h[0]) + project(h[3])) * 0.5, vp)
}

/// Edge tier for one homogeneous boundary curve (either direction).
pub fn edge_flat(h: &[Vec4; 4], vp: &ViewParams) -> bool {
    let t2 = edge_tolerance2(h, vp);
    criterion::edge_samples_flat(edge_samples(h), t2, vp)
}

/// Inner tier, as [`super::criterion::inner_flat`] on the projected
/// corners and samples.
pub fn inner_flat(s: &HomPatch, vp: &ViewParams) -> bool {
    let corners = [s.point(0, 0), s.point(3, 0), s.point(3, 3), s.point(0, 3)];
    criterion::inner_flat_of(corners, |u, v| s.eval(u, v), vp)
}

/// The polynomial patch Q of weighted control points relative to the eye,
/// w_i (p_i − eye) = h_i.xyz − h_i.w · eye (see the module docs).
pub fn eye_patch(s: &HomPatch, eye: Vec3) -> BezierPatch {
    BezierPatch {
        pts: std::array::from_fn(|k| s.pts[k].truncate() - eye * s.pts[k].w),
    }
}

/// Conservative back-face test of a rational (sub-)patch: true only if
/// every normal faces away from `eye` at every point (up to f32 rounding in
/// the bound, as for polynomial patches).
pub fn back_facing(s: &HomPatch, eye: Vec3) -> bool {
    let q = eye_patch(s, eye);
    let (lo, hi) = q.bbox();
    cull::back_facing(&q, lo, hi, Vec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::blossom::reconstruct;
    use crate::patch::fixtures::wavy;

    fn weights() -> [f32; 16] {
        std::array::from_fn(|k| 0.4 + (k as f32 * 0.61).sin().abs() * 1.7)
    }

    /// The sub-patch's control points, with their weights, describe the
    /// base surface over the node's domain.
    #[test]
    fn sub_patch_evaluates_to_the_base_surface() {
        let base = RationalPatch::new(wavy(), weights());
        let h = HomPatch::of(&base);
        for (a, b, c, d) in [
            (0.0, 1.0, 0.0, 1.0),
            (0.25, 0.5, 0.125, 0.375),
            (0.5, 1.0, 0.0, 0.5),
            (0.6875, 0.75, 0.875, 0.9375),
        ] {
            let s = h.sub(a, b, c, d);
            // As a rational patch: Cartesian points and weights.
            let pts = std::array::from_fn(|k| project(s.pts[k]));
            let w = std::array::from_fn(|k| s.pts[k].w);
            let r = RationalPatch::new(BezierPatch { pts }, w);
            for k in 0..=8 {
                for l in 0..=8 {
                    let (u, v) = (k as f32 / 8.0, l as f32 / 8.0);
                    let want = base.eval(a + (b - a) * u, c + (d - c) * v);
                    let got = r.eval(u, v);
                    assert!((got - want).length() < 2e-6, "{got} {want}");
                    assert!((s.eval(u, v) - want).length() < 2e-6);
                }
            }
        }
    }

    /// Weights 1: the homogeneous blossom is the polynomial one bit for
    /// bit, with w exactly 1, and the Cartesian control points are the
    /// polynomial sub-patch's.
    #[test]
    fn unit_weights_rebuild_the_polynomial_sub_patch_bitwise() {
        let p = wavy();
        let h = HomPatch::of(&RationalPatch::polynomial(p));
        for l in 0..=10u32 {
            let s = 1.0 / (1u32 << l) as f32;
            for m in [0u32, (1 << l) / 3, (1 << l) - 1] {
                let n = (m * 7 + 1) % (1 << l);
                let (a, b, c, d) = (
                    m as f32 * s,
                    (m + 1) as f32 * s,
                    n as f32 * s,
                    (n + 1) as f32 * s,
                );
                let hs = h.sub(a, b, c, d);
                let ps = reconstruct(&p, a, b, c, d);
                for k in 0..16 {
                    assert_eq!(hs.pts[k].w, 1.0, "depth {l}");
                    assert_eq!(hs.pts[k].truncate().to_array(), ps.pts[k].to_array());
                    assert_eq!(project(hs.pts[k]).to_array(), ps.pts[k].to_array());
                }
                assert_eq!(hs.bbox(), ps.bbox());
            }
        }
    }

    #[test]
    fn edge_decision_is_direction_free() {
        use crate::patch::view::FLAGS_DEFAULT;
        let base = RationalPatch::new(wavy(), weights());
        let h = HomPatch::of(&base);
        let mut outcomes = [0u32; 2];
        for k in 1..200 {
            let eps_k = k as f32 * 1e-3;
            let vp = ViewParams {
                depth_row: Vec4::new(0.0, 0.0, -1.0, 5.0),
                planes: [Vec4::ZERO; 6],
                eye: Vec4::W,
                eps_k,
                near: 0.1,
                w_orth: 0.5,
                w_par: 0.5,
                l_max: 10,
                flags: FLAGS_DEFAULT,
                width: 0,
                height: 0,
                clip: [Vec4::ZERO; 4],
            };
            for e in 0..4 {
                let c = h.edge(e);
                let r = [c[3], c[2], c[1], c[0]];
                let f = edge_flat(&c, &vp);
                assert_eq!(f, edge_flat(&r, &vp));
                outcomes[f as usize] += 1;
            }
        }
        assert!(outcomes[0] > 0 && outcomes[1] > 0, "{outcomes:?}");
    }
}
