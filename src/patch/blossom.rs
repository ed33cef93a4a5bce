//! Sub-patch reconstruction by tensor-product blossoms (paper §3.3.2).
//!
//! The 16 Bézier points of the sub-patch over [a,b]×[c,d] are the blossom
//! values `s(a^(3-i), b^(i) | c^(3-j), d^(j))`, computed from the base patch by
//! three rounds of bilinear interpolation. Round one and two insert the same
//! parameter pair (the "doubled" parameter), round three the single one. With
//! the pairwise parentheses of [`bilerp`], every permutation of the domain
//! (flipping u, flipping v, swapping them) performs the same multiplications
//! and the same additions up to commutation, so neighbouring sub-patches, and
//! neighbouring base patches that share a boundary curve, get identical bits
//! on their common edge. The paper's listing prints the final output index as
//! `P[2+l+k][2+j+i]`; from the blossom the v index is `2l+k` and the u index
//! `2j+i`, with arrays indexed `[v][u]`.
//!
//! Rational patches are rebuilt the same way on their homogeneous control
//! points (w·p, w) ([`reconstruct_points`] on `Vec4`): every operation is
//! component by component, so each of the four components goes through
//! exactly the operation sequence a polynomial coordinate does, and the
//! §4.4 argument carries over unchanged. For weights 1 the w components
//! stay exactly 1 (node domains are dyadic with at most `L_MAX` fraction
//! bits, so every product and sum of the round is exact) and the xyz
//! components are the polynomial bits.

use std::ops::{Add, Mul};

use glam::Vec3;

use super::bezier::BezierPatch;

/// A control point the blossom rounds can interpolate: `Vec3` (Cartesian)
/// or `Vec4` (homogeneous), with component-wise IEEE operations.
pub trait BlossomPoint: Copy + Mul<f32, Output = Self> + Add<Output = Self> {
    /// The zero point.
    const ZERO: Self;
}

impl BlossomPoint for Vec3 {
    const ZERO: Self = Vec3::ZERO;
}

impl BlossomPoint for glam::Vec4 {
    const ZERO: Self = glam::Vec4::ZERO;
}

/// Bilinear interpolation with the paper's parenthesisation:
/// `(P00 + P11) + (P10 + P01)`, weights `u1*v1`, `u0*v1`, `u1*v0`, `u0*v0`.
/// `p10` is the neighbour along u, `p01` along v.
#[inline]
pub fn bilerp(u0: f32, v0: f32, p00: Vec3, p10: Vec3, p01: Vec3, p11: Vec3) -> Vec3 {
    bilerp_points(u0, v0, p00, p10, p01, p11)
}

/// [`bilerp`] for any [`BlossomPoint`].
#[inline]
pub fn bilerp_points<T: BlossomPoint>(u0: f32, v0: f32, p00: T, p10: T, p01: T, p11: T) -> T {
    let u1 = 1.0 - u0;
    let v1 = 1.0 - v0;
    let w00 = p00 * (u1 * v1);
    let w10 = p10 * (u0 * v1);
    let w01 = p01 * (u1 * v0);
    let w11 = p11 * (u0 * v0);
    (w00 + w11) + (w10 + w01)
}

/// The sub-patch of `base` over [a,b]×[c,d].
pub fn reconstruct(base: &BezierPatch, a: f32, b: f32, c: f32, d: f32) -> BezierPatch {
    BezierPatch {
        pts: reconstruct_points(&base.pts, a, b, c, d),
    }
}

/// The 16 control points over [a,b]×[c,d] of the patch with control points
/// `p` (Cartesian or homogeneous), in the order of [`reconstruct`].
pub fn reconstruct_points<T: BlossomPoint>(p: &[T; 16], a: f32, b: f32, c: f32, d: f32) -> [T; 16] {
    let us = [a, b];
    let vs = [c, d];

    // First round: bi-quadratic nets s(U[k], · · | V[l], · ·), 3×3 each.
    let mut d_net = [[[T::ZERO; 9]; 2]; 2];
    for l in 0..2 {
        for k in 0..2 {
            d_net[l][k] = blossom_round(p, 4, us[k], vs[l]);
        }
    }

    // Second round: bilinear nets s(U[k], U[k], · | V[l], V[l], ·), 2×2 each.
    let mut e_net = [[[T::ZERO; 4]; 2]; 2];
    for l in 0..2 {
        for k in 0..2 {
            e_net[l][k] = blossom_round(&d_net[l][k], 3, us[k], vs[l]);
        }
    }

    // Third round: s(U[j], U[j], U[i] | V[l], V[l], V[k]) is the point with
    // u index 2j+i and v index 2l+k.
    let mut out = [T::ZERO; 16];
    for l in 0..2 {
        for k in 0..2 {
            for j in 0..2 {
                for i in 0..2 {
                    let e = &e_net[l][j];
                    out[4 * (2 * l + k) + (2 * j + i)] =
                        bilerp_points(us[i], vs[k], e[0], e[1], e[2], e[3]);
                }
            }
        }
    }
    out
}

/// One of the first two rounds: the (n−1)×(n−1) net (`M` = (n−1)² points)
/// that inserts (u, v) into every 2×2 cell of the n×n net `net` (rows of n
/// points along u, indexed `[v][u]` like the patch).
fn blossom_round<T: BlossomPoint, const M: usize>(net: &[T], n: usize, u: f32, v: f32) -> [T; M] {
    debug_assert_eq!((net.len(), M), (n * n, (n - 1) * (n - 1)));
    let mut out = [T::ZERO; M];
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            out[(n - 1) * j + i] = bilerp_points(
                u,
                v,
                net[n * j + i],
                net[n * j + i + 1],
                net[n * (j + 1) + i],
                net[n * (j + 1) + i + 1],
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::bezier::curve;
    use crate::patch::fixtures::grid;

    fn wavy() -> BezierPatch {
        grid(|x, y| Vec3::new(x + 0.3 * y, y - 0.2 * x * x, (x * 1.7 + y * 0.9).sin()))
    }

    #[test]
    fn full_domain_is_identity() {
        let s = wavy();
        assert_eq!(reconstruct(&s, 0.0, 1.0, 0.0, 1.0), s);
    }

    #[test]
    fn corners_and_boundary_match_the_surface() {
        let s = wavy();
        let r = reconstruct(&s, 0.25, 0.5, 0.125, 0.375);
        for &(i, j, u, v) in &[
            (0, 0, 0.25, 0.125),
            (3, 0, 0.5, 0.125),
            (3, 3, 0.5, 0.375),
            (0, 3, 0.25, 0.375),
        ] {
            assert!((r.at(i, j) - s.eval(u, v)).length() < 1e-5);
        }
        // A boundary curve of the sub-patch traces the base surface.
        let bottom = r.row(0);
        for k in 0..=8 {
            let t = k as f32 / 8.0;
            let want = s.eval(0.25 + 0.25 * t, 0.125);
            assert!((curve(t, &bottom) - want).length() < 1e-5);
        }
    }
}
