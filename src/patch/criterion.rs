//! The subdivision criterion of paper §3.2, in the GPU's operation order.
//!
//! A sample point `s` is compared against its linear stand-in: the line
//! through the end points `a`, `b` (edge tier, and the diagonal points of the
//! inner tier) or the plane of a triangle (the off-diagonal inner points). Two
//! distances are blended by λ: the orthogonal distance δ⊥ (controls the
//! geometric error, enough for silhouettes) and the parametric distance δp to
//! the stand-in's point at the same parameter (controls the parameterisation,
//! i.e. shading and texturing). To keep every decision free of division and
//! square roots (which GPUs do not round like the CPU), the blend is taken on
//! squares and multiplied through by the stand-in's squared size:
//!
//! ```text
//!   (1-λ)·δ⊥² + λ·δp² ≤ t²      with δ⊥² = |(s-a)×(b-a)|² / |b-a|²
//!   ⇔ (1-λ)·|(s-a)×(b-a)|² + (λ·δp²)·|b-a|² ≤ t²·|b-a|²
//! ```
//!
//! Blending squares gives exactly the paper's metrics at λ = 0 and λ = 1 and,
//! in between, a power mean that is never below the linear blend, so it is
//! never laxer. `t = ε_k · max(depth, near)` is ε pixels projected to world
//! space at the edge midpoint (edge tier) or the patch centre (inner tier).
//! A zero-length chord (a collapsed edge, like the teapot's poles) uses the
//! distance to the point instead, so degenerate input cannot produce NaN.
//!
//! Edge decisions must be identical for the two patches sharing the edge, so
//! an edge is always tested by [`edge_flat`] from its four control points and
//! the view alone, sampling the curve at 1/3 *and* the reversed curve at 1/3
//! (the whole sample — point, line point, chord, distance — on the reversed
//! control points): the pair of samples is then the same set from both sides,
//! bit for bit, whatever the edge's direction in each patch.

use glam::Vec3;

use super::bezier::{curve, BezierPatch};
use super::ops::{affine_row, cross3, dot3, maxf, THIRD, TWO_THIRDS};
use super::view::ViewParams;

/// `t²` for a tolerance measured at world point `p`.
#[inline]
pub fn tolerance2(p: Vec3, vp: &ViewParams) -> f32 {
    let z = maxf(affine_row(vp.depth_row, p), vp.near);
    let t = vp.eps_k * z;
    t * t
}

/// The two sides of the line test for sample `s` against the line `a → b`,
/// whose point at `s`'s parameter `t` is `a·(1-t) + b·t`: the sample is flat
/// when `lhs <= rhs`. Returned (rather than only the verdict) so tests can
/// check that both patches sharing an edge compute the same bits.
#[inline]
pub fn line_sample_terms(
    s: Vec3,
    a: Vec3,
    b: Vec3,
    t: f32,
    t2: f32,
    vp: &ViewParams,
) -> (f32, f32) {
    let chord = b - a;
    let d = s - a;
    let on_line = a * (1.0 - t) + b * t;
    let par = s - on_line;
    let chord2 = dot3(chord, chord);
    if chord2 == 0.0 {
        return (dot3(d, d), t2);
    }
    let x = cross3(d, chord);
    let lhs = vp.w_orth * dot3(x, x) + (vp.w_par * dot3(par, par)) * chord2;
    (lhs, t2 * chord2)
}

/// Is `s` within tolerance of the line `a → b` (see [`line_sample_terms`])?
#[inline]
pub fn line_sample_flat(s: Vec3, a: Vec3, b: Vec3, t: f32, t2: f32, vp: &ViewParams) -> bool {
    let (lhs, rhs) = line_sample_terms(s, a, b, t, t2, vp);
    lhs <= rhs
}

/// Is `s` within tolerance of the plane of triangle `(a, b, c)`, whose point
/// at `s`'s parameter is the centroid (true for both inner off-diagonal
/// samples, see [`inner_flat`])?
#[inline]
pub fn plane_sample_flat(s: Vec3, a: Vec3, b: Vec3, c: Vec3, t2: f32, vp: &ViewParams) -> bool {
    let centroid = (a * THIRD + b * THIRD) + c * THIRD;
    let par = s - centroid;
    let par2 = dot3(par, par);
    let n = cross3(b - a, c - a);
    let n2 = dot3(n, n);
    if n2 == 0.0 {
        // A degenerate triangle has no plane: fall back to the point distance.
        return par2 <= t2;
    }
    let h = dot3(n, s - a);
    let lhs = vp.w_orth * (h * h) + (vp.w_par * par2) * n2;
    lhs <= t2 * n2
}

/// One edge-tier sample: the curve point at parameter 1/3 measured from
/// `from` towards `to`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeSample {
    /// The curve point.
    pub point: Vec3,
    /// The end point the parameter is measured from.
    pub from: Vec3,
    /// The other end point.
    pub to: Vec3,
}

/// The edge tier's two samples of boundary curve `p`: at 1/3 on `p`, and at
/// 1/3 on the reversed curve, each computed entirely in its own direction.
pub fn edge_samples(p: &[Vec3; 4]) -> [EdgeSample; 2] {
    let reversed = [p[3], p[2], p[1], p[0]];
    [
        EdgeSample {
            point: curve(THIRD, p),
            from: p[0],
            to: p[3],
        },
        EdgeSample {
            point: curve(THIRD, &reversed),
            from: p[3],
            to: p[0],
        },
    ]
}

/// `t²` of the edge tier: ε projected at the edge midpoint (symmetric in the
/// end points).
pub fn edge_tolerance2(p: &[Vec3; 4], vp: &ViewParams) -> f32 {
    tolerance2((p[0] + p[3]) * 0.5, vp)
}

/// Edge tier for one boundary curve `p` (either direction).
pub fn edge_flat(p: &[Vec3; 4], vp: &ViewParams) -> bool {
    let t2 = edge_tolerance2(p, vp);
    let [f, b] = edge_samples(p);
    let fwd = line_sample_flat(f.point, f.from, f.to, THIRD, t2, vp);
    let bwd = line_sample_flat(b.point, b.from, b.to, THIRD, t2, vp);
    fwd & bwd
}

/// Inner tier. The quad is drawn as the triangles (00, 10, 11) and
/// (00, 11, 01), i.e. split along the diagonal from (0,0) to (1,1). The
/// samples (1/3,1/3) and (2/3,2/3) lie on that diagonal and are compared with
/// the diagonal line; (2/3,1/3) lies in the first triangle, (1/3,2/3) in the
/// second, each compared with its triangle's plane (their parametric point is
/// the triangle's centroid). All four are evaluated.
pub fn inner_flat(s: &BezierPatch, vp: &ViewParams) -> bool {
    let corners = [s.at(0, 0), s.at(3, 0), s.at(3, 3), s.at(0, 3)];
    inner_flat_of(corners, |u, v| s.eval(u, v), vp)
}

/// [`inner_flat`] on the corners q00, q10, q11, q01 and the surface `eval`
/// (also the rational patches' inner tier, `patch::homogeneous`).
pub fn inner_flat_of(
    [q00, q10, q11, q01]: [Vec3; 4],
    eval: impl Fn(f32, f32) -> Vec3,
    vp: &ViewParams,
) -> bool {
    let t2 = tolerance2(((q00 + q11) + (q10 + q01)) * 0.25, vp);
    let d1 = line_sample_flat(eval(THIRD, THIRD), q00, q11, THIRD, t2, vp);
    let d2 = line_sample_flat(eval(TWO_THIRDS, TWO_THIRDS), q00, q11, TWO_THIRDS, t2, vp);
    let t0 = plane_sample_flat(eval(TWO_THIRDS, THIRD), q00, q10, q11, t2, vp);
    let t1 = plane_sample_flat(eval(THIRD, TWO_THIRDS), q00, q11, q01, t2, vp);
    (d1 & d2) & (t0 & t1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::view::FLAGS_DEFAULT;
    use glam::Vec4;

    fn params(eps_k: f32, lambda: f32) -> ViewParams {
        ViewParams {
            depth_row: Vec4::new(0.0, 0.0, -1.0, 0.0),
            planes: [Vec4::ZERO; 6],
            eye: Vec4::W,
            eps_k,
            near: 0.1,
            w_orth: 1.0 - lambda,
            w_par: lambda,
            l_max: 10,
            flags: FLAGS_DEFAULT,
            pad: [0; 2],
        }
    }

    fn line(z: f32, bulge: f32) -> [Vec3; 4] {
        [
            Vec3::new(0.0, 0.0, z),
            Vec3::new(1.0, bulge, z),
            Vec3::new(2.0, bulge, z),
            Vec3::new(3.0, 0.0, z),
        ]
    }

    #[test]
    fn straight_edges_are_flat_curved_ones_are_not() {
        let vp = params(1e-3, 0.0);
        assert!(edge_flat(&line(-5.0, 0.0), &vp));
        // C(1/3) is 0.667 * bulge off the chord; tolerance at depth 5 is 5e-3.
        assert!(edge_flat(&line(-5.0, 0.007), &vp));
        assert!(!edge_flat(&line(-5.0, 0.008), &vp));
        // Farther away the same bulge passes.
        assert!(edge_flat(&line(-50.0, 0.05), &vp));
    }

    #[test]
    fn parametric_distance_catches_uneven_spacing() {
        // A straight but unevenly parameterised edge: δ⊥ = 0, δp > 0.
        let p = [
            Vec3::new(0.0, 0.0, -5.0),
            Vec3::new(2.5, 0.0, -5.0),
            Vec3::new(2.9, 0.0, -5.0),
            Vec3::new(3.0, 0.0, -5.0),
        ];
        assert!(edge_flat(&p, &params(1e-3, 0.0)));
        assert!(!edge_flat(&p, &params(1e-3, 1.0)));
        assert!(!edge_flat(&p, &params(1e-3, 0.5)));
    }

    #[test]
    fn edge_decision_is_direction_free() {
        let mut k = 0u32;
        let mut total = 0u32;
        for lambda in [0.0, 0.5, 1.0] {
            let vp = params(2e-3, lambda);
            for i in 0..200 {
                let f = i as f32 * 0.013;
                let b = 0.01 * f;
                let p = [
                    Vec3::new(0.1, 0.3, -3.0 - 0.011 * f),
                    Vec3::new(1.1, 0.3 + b, -3.0),
                    Vec3::new(2.1, 0.3 - 0.5 * b, -3.0 + 0.007 * f),
                    Vec3::new(3.1, 0.3 + 0.01 * f, -3.0),
                ];
                let r = [p[3], p[2], p[1], p[0]];
                assert_eq!(edge_flat(&p, &vp), edge_flat(&r, &vp));
                k += edge_flat(&p, &vp) as u32;
                total += 1;
            }
        }
        assert!(k > 0 && k < total, "both outcomes exercised ({k}/{total})");
    }

    #[test]
    fn collapsed_edges_are_handled_without_nan() {
        let vp = params(1e-3, 0.5);
        let p = [Vec3::new(1.0, 2.0, -3.0); 4];
        assert!(edge_flat(&p, &vp));
        let mut q = p;
        q[1].x += 1.0;
        assert!(!edge_flat(&q, &vp), "a loop from a point is not flat");
        // Behind the camera: depth clamps to `near`, so a tiny tolerance.
        assert!(edge_flat(&line(-5.0, 1e-3), &params(1e-3, 0.0)));
        assert!(!edge_flat(&line(5.0, 1e-3), &params(1e-3, 0.0)));
    }

    #[test]
    fn flat_patch_passes_inner_tier_and_bump_fails() {
        let vp = params(1e-3, 0.0);
        let mut pts = [Vec3::ZERO; 16];
        for j in 0..4 {
            for i in 0..4 {
                pts[4 * j + i] = Vec3::new(i as f32, j as f32, -5.0);
            }
        }
        let flat = BezierPatch { pts };
        assert!(inner_flat(&flat, &vp));
        let mut bump = flat;
        bump.pts[5].z += 0.1;
        bump.pts[6].z += 0.1;
        bump.pts[9].z += 0.1;
        bump.pts[10].z += 0.1;
        assert!(!inner_flat(&bump, &vp));
        // Degenerate triangle (collapsed bottom edge) stays NaN-free.
        let mut pole = flat;
        for i in 0..4 {
            pole.pts[i] = Vec3::new(1.5, 0.0, -5.0);
        }
        let _ = inner_flat(&pole, &vp);
    }
}
