//! The subdivision criterion of paper §3.2, in the GPU's operation order.
//!
//! A sample point `s` is compared against its linear stand-in: the chord
//! through the curve's end points (edge tier) or the quad's two drawn
//! triangles (inner tier, against the closest of them). Two distances are
//! blended by λ: the orthogonal distance δ⊥ (controls the geometric error,
//! enough for silhouettes) and the parametric distance δp to the stand-in's
//! point at the same parameter (controls the parameterisation, i.e. shading
//! and texturing). To keep every decision free of division and square roots
//! (which GPUs do not round like the CPU), the blend is taken on squares and
//! multiplied through by the stand-in's squared size:
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

/// `t²` for a tolerance measured at world point `p` and reduced by `reach`
/// (world units the drawn surface may move beyond what the control points
/// say: a displaced node's height range), or -1 where nothing is left of it
/// (no sample can then pass). With `reach` 0 it is [`tolerance2`] bit for
/// bit.
#[inline]
pub fn tolerance2_within(p: Vec3, vp: &ViewParams, reach: f32) -> f32 {
    let z = maxf(affine_row(vp.depth_row, p), vp.near);
    let t = vp.eps_k * z - reach;
    if t > 0.0 {
        t * t
    } else {
        -1.0
    }
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

/// One candidate of the inner tier's orthogonal distance: `s` against the
/// plane of triangle `(a, b, c)`, usable only when the foot of `s` on that
/// plane lies inside the triangle (then the plane distance *is* the distance
/// to a point of the drawn surface). The test is the line test's blend with
/// the triangle's normal `n = (b-a)×(c-a)` in place of the chord:
/// `(1-λ)·(n·(s-a))² + (λ·δp²)·|n|² ≤ t²·|n|²`. The inside test uses the
/// signs of `((e_k)×(s-v_k))·n`, the projected foot's barycentric
/// coordinates times `|n|²`, so it needs no division either. A degenerate
/// triangle (n = 0) offers no candidate.
#[inline]
pub fn triangle_candidate_flat(
    s: Vec3,
    [a, b, c]: [Vec3; 3],
    w_par2: f32,
    t2: f32,
    vp: &ViewParams,
) -> bool {
    let n = cross3(b - a, c - a);
    let n2 = dot3(n, n);
    let sa = s - a;
    let inside_ab = dot3(cross3(b - a, sa), n) >= 0.0;
    let inside_bc = dot3(cross3(c - b, s - b), n) >= 0.0;
    let inside_ca = dot3(cross3(a - c, s - c), n) >= 0.0;
    let h = dot3(n, sa);
    let lhs = vp.w_orth * (h * h) + w_par2 * n2;
    let fits = lhs <= t2 * n2;
    ((n2 > 0.0) & fits) & ((inside_ab & inside_bc) & inside_ca)
}

/// The other candidate: `s` against the quad's diagonal `a → b` (shared by
/// both triangles), usable when the foot of `s` on that line lies within
/// the segment (`0 ≤ (s-a)·(b-a) ≤ |b-a|²`).
#[inline]
pub fn diagonal_candidate_flat(
    s: Vec3,
    a: Vec3,
    b: Vec3,
    w_par2: f32,
    t2: f32,
    vp: &ViewParams,
) -> bool {
    let chord = b - a;
    let chord2 = dot3(chord, chord);
    let d = s - a;
    let along = dot3(d, chord);
    let x = cross3(d, chord);
    let lhs = vp.w_orth * dot3(x, x) + w_par2 * chord2;
    let fits = lhs <= t2 * chord2;
    ((chord2 > 0.0) & fits) & ((along >= 0.0) & (along <= chord2))
}

/// One inner-tier sample `s` whose drawn point (the two-triangle
/// approximation at the same (u, v)) is `p`: within tolerance when
/// `(1-λ)·δ⊥² + λ·δp² ≤ t²`, δp = |s - p| and δ⊥ the distance from `s` to
/// the *closest* of the two drawn triangles (paper §3.2). δ⊥ is the least
/// of the candidates that are distances to actual points of the drawn
/// surface: the foot on either triangle's plane when it falls inside that
/// triangle, the foot on the diagonal when it falls within it, and `p`
/// itself. So δ⊥ is never below the true distance (an upper bound of the
/// error at the sample), and equals it unless the nearest drawn point lies
/// on the quad's outer boundary. The blend with the least candidate holds
/// iff it holds for some candidate, so the test is an OR of candidate tests,
/// each free of division and square roots.
pub fn inner_sample_flat(s: Vec3, p: Vec3, q: &[Vec3; 4], t2: f32, vp: &ViewParams) -> bool {
    let [q00, q10, q11, q01] = *q;
    let par = s - p;
    let par2 = dot3(par, par);
    let w_par2 = vp.w_par * par2;
    let at_p = par2 <= t2;
    let diagonal = diagonal_candidate_flat(s, q00, q11, w_par2, t2, vp);
    let first = triangle_candidate_flat(s, [q00, q10, q11], w_par2, t2, vp);
    let second = triangle_candidate_flat(s, [q00, q11, q01], w_par2, t2, vp);
    (at_p | diagonal) | (first | second)
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
    edge_samples_flat(edge_samples(p), t2, vp)
}

/// [`edge_flat`] with the tolerance reduced by `reach` (a displaced edge's
/// height range; see [`tolerance2_within`]).
pub fn edge_flat_within(p: &[Vec3; 4], vp: &ViewParams, reach: f32) -> bool {
    let t2 = tolerance2_within((p[0] + p[3]) * 0.5, vp, reach);
    edge_samples_flat(edge_samples(p), t2, vp)
}

/// The edge tier's verdict on its two samples (polynomial or projected
/// rational ones) at tolerance `t2`: both are evaluated, no short circuit,
/// as on the GPU.
pub fn edge_samples_flat([f, b]: [EdgeSample; 2], t2: f32, vp: &ViewParams) -> bool {
    let fwd = line_sample_flat(f.point, f.from, f.to, THIRD, t2, vp);
    let bwd = line_sample_flat(b.point, b.from, b.to, THIRD, t2, vp);
    fwd & bwd
}

/// Inner tier. The quad is drawn as the triangles (00, 10, 11) and
/// (00, 11, 01), i.e. split along the diagonal from (0,0) to (1,1). The
/// samples (1/3,1/3) and (2/3,2/3) lie on that diagonal (drawn point: the
/// diagonal's point at the same parameter), (2/3,1/3) in the first triangle
/// and (1/3,2/3) in the second (drawn point: the triangle's centroid). Each
/// is measured against the closest drawn triangle ([`inner_sample_flat`]).
/// All four are evaluated.
pub fn inner_flat(s: &BezierPatch, vp: &ViewParams) -> bool {
    let corners = [s.at(0, 0), s.at(3, 0), s.at(3, 3), s.at(0, 3)];
    inner_flat_of(corners, |u, v| s.eval(u, v), vp)
}

/// [`inner_flat`] on the corners q00, q10, q11, q01 and the surface `eval`
/// (also the rational patches' inner tier, `patch::homogeneous`).
pub fn inner_flat_of(q: [Vec3; 4], eval: impl Fn(f32, f32) -> Vec3, vp: &ViewParams) -> bool {
    let [q00, q10, q11, q01] = q;
    let t2 = tolerance2(((q00 + q11) + (q10 + q01)) * 0.25, vp);
    inner_flat_at(q, eval, t2, vp)
}

/// [`inner_flat`] with the tolerance reduced by `reach` (a displaced
/// node's height range; see [`tolerance2_within`]).
pub fn inner_flat_within(s: &BezierPatch, vp: &ViewParams, reach: f32) -> bool {
    let q = [s.at(0, 0), s.at(3, 0), s.at(3, 3), s.at(0, 3)];
    let [q00, q10, q11, q01] = q;
    let t2 = tolerance2_within(((q00 + q11) + (q10 + q01)) * 0.25, vp, reach);
    inner_flat_at(q, |u, v| s.eval(u, v), t2, vp)
}

/// The inner tier's four samples at tolerance `t2`.
fn inner_flat_at(q: [Vec3; 4], eval: impl Fn(f32, f32) -> Vec3, t2: f32, vp: &ViewParams) -> bool {
    let [q00, q10, q11, q01] = q;
    let on_diagonal = |t: f32| q00 * (1.0 - t) + q11 * t;
    let centroid = |a: Vec3, b: Vec3, c: Vec3| (a * THIRD + b * THIRD) + c * THIRD;
    let d1 = inner_sample_flat(eval(THIRD, THIRD), on_diagonal(THIRD), &q, t2, vp);
    let d2 = inner_sample_flat(
        eval(TWO_THIRDS, TWO_THIRDS),
        on_diagonal(TWO_THIRDS),
        &q,
        t2,
        vp,
    );
    let t0 = inner_sample_flat(eval(TWO_THIRDS, THIRD), centroid(q00, q10, q11), &q, t2, vp);
    let t1 = inner_sample_flat(eval(THIRD, TWO_THIRDS), centroid(q00, q11, q01), &q, t2, vp);
    (d1 & d2) & (t0 & t1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::view::FLAGS_DEFAULT;
    use glam::{DVec3, Vec4};

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
            width: 0,
            height: 0,
            clip: [Vec4::ZERO; 4],
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

    /// The distance from `p` to triangle (a, b, c), in f64.
    fn point_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
        let n = (b - a).cross(c - a);
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|&(x, y)| (y - x).cross(p - x).dot(n) >= 0.0);
        if inside && n.length_squared() > 0.0 {
            return ((p - a).dot(n) / n.length()).abs();
        }
        let seg = |x: DVec3, y: DVec3| {
            let d = y - x;
            let t = if d.length_squared() > 0.0 {
                ((p - x).dot(d) / d.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (p - (x + d * t)).length()
        };
        seg(a, b).min(seg(b, c)).min(seg(c, a))
    }

    /// The inner tier's orthogonal measure is an upper bound of the error
    /// at its samples: whenever a patch passes at λ = 0, each of the four
    /// samples lies within the tolerance of the drawn two-triangle surface
    /// (distances in f64, a little slack for the f32 arithmetic). And it is
    /// the distance to the closest triangle, not to the diagonal line: on
    /// random patches it passes patches the line test refused.
    #[test]
    fn inner_tier_bounds_the_distance_to_the_drawn_triangles() {
        use rand::{rngs::SmallRng, Rng, SeedableRng};
        let mut rng = SmallRng::seed_from_u64(16);
        let vp = params(2e-3, 0.0);
        let (mut passed, mut line_would_split) = (0, 0);
        for _ in 0..20_000 {
            let amp = rng.random_range(0.0..0.05f32);
            let mut pts = [Vec3::ZERO; 16];
            for j in 0..4 {
                for i in 0..4 {
                    let jitter = Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    );
                    pts[4 * j + i] = Vec3::new(i as f32, j as f32, -5.0) + jitter * amp;
                }
            }
            let patch = BezierPatch { pts };
            if !inner_flat(&patch, &vp) {
                continue;
            }
            passed += 1;
            let q = [
                patch.at(0, 0),
                patch.at(3, 0),
                patch.at(3, 3),
                patch.at(0, 3),
            ]
            .map(|p| p.as_dvec3());
            let t = f64::from(tolerance2(
                ((q[0] + q[2]) + (q[1] + q[3])).as_vec3() * 0.25,
                &vp,
            ))
            .sqrt();
            for (u, v) in [
                (THIRD, THIRD),
                (TWO_THIRDS, TWO_THIRDS),
                (TWO_THIRDS, THIRD),
                (THIRD, TWO_THIRDS),
            ] {
                let s = patch.eval(u, v).as_dvec3();
                let d =
                    point_triangle(s, q[0], q[1], q[2]).min(point_triangle(s, q[0], q[2], q[3]));
                assert!(
                    d <= t * 1.001,
                    "sample ({u}, {v}) is {d} from the drawn quad, tolerance {t}"
                );
            }
            let on_line = |t: f32| {
                line_sample_flat(
                    patch.eval(t, t),
                    patch.at(0, 0),
                    patch.at(3, 3),
                    t,
                    tolerance2(patch.eval(0.5, 0.5), &vp),
                    &vp,
                )
            };
            line_would_split += (!on_line(THIRD) || !on_line(TWO_THIRDS)) as u32;
        }
        assert!(passed > 1_000, "both outcomes exercised ({passed} passed)");
        assert!(
            line_would_split > 0,
            "the diagonal line refuses some patch the triangles accept"
        );
    }

    /// Paper Fig. 3a: a perfectly flat patch whose control points are
    /// unevenly spaced in its plane is one quad at λ = 0 (δ⊥ = 0), and is
    /// split once λ weighs the parameterisation.
    #[test]
    fn a_flat_patch_with_uneven_parameters_is_one_quad_at_lambda_zero() {
        let xs = [0.0, 0.2, 0.4, 3.0];
        let mut pts = [Vec3::ZERO; 16];
        for j in 0..4 {
            for i in 0..4 {
                pts[4 * j + i] = Vec3::new(xs[i], j as f32, -5.0);
            }
        }
        let flat = BezierPatch { pts };
        assert!(inner_flat(&flat, &params(1e-3, 0.0)));
        assert!(!inner_flat(&flat, &params(1e-3, 0.5)));
        // The diagonal line alone would have split it at λ = 0.
        let t2 = tolerance2(flat.eval(0.5, 0.5), &params(1e-3, 0.0));
        assert!(!line_sample_flat(
            flat.eval(THIRD, THIRD),
            flat.at(0, 0),
            flat.at(3, 3),
            THIRD,
            t2,
            &params(1e-3, 0.0)
        ));
    }

    /// A quad folded convexly along its diagonal (a ridge) with a sample
    /// above the ridge, on the convex side: its feet on both triangles'
    /// planes fall outside the triangles, so the planes (0.0816 away) are
    /// not the distance to the drawn surface; the ridge (0.1 away) is. A
    /// tolerance between the two must split.
    #[test]
    fn on_the_convex_side_of_a_fold_the_diagonal_decides() {
        let q = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, -0.5),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, -0.5),
        ];
        let s = Vec3::new(0.5, 0.5, 0.1);
        let p = q[0] * 0.5 + q[2] * 0.5;
        let vp = params(1.0, 0.0);
        let t2 = 0.09f32 * 0.09;
        let plane = |a: Vec3, b: Vec3, c: Vec3| {
            let n = cross3(b - a, c - a);
            let h = dot3(n, s - a);
            h * h <= t2 * dot3(n, n)
        };
        assert!(plane(q[0], q[1], q[2]) && plane(q[0], q[2], q[3]));
        assert!(!triangle_candidate_flat(
            s,
            [q[0], q[1], q[2]],
            0.0,
            t2,
            &vp
        ));
        assert!(!triangle_candidate_flat(
            s,
            [q[0], q[2], q[3]],
            0.0,
            t2,
            &vp
        ));
        assert!(!inner_sample_flat(s, p, &q, t2, &vp));
        // On the concave side the nearer plane is the distance: it passes.
        let below = Vec3::new(0.6, 0.4, -0.12);
        assert!(inner_sample_flat(
            below,
            q[0] * 0.5 + q[2] * 0.5,
            &q,
            0.06 * 0.06,
            &vp
        ));
        assert!(!diagonal_candidate_flat(
            below,
            q[0],
            q[2],
            0.0,
            0.06 * 0.06,
            &vp
        ));
    }
}
