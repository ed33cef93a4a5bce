//! Rational bicubic Bézier patches (Schwarz and Stamminger 2009, §3):
//! 16 control points p_ij with weights w_ij, i.e. homogeneous points
//! b_ij = (w_ij p_ij, w_ij). The surface is the tensor-product Bézier patch
//! of the b_ij projected back, p(u, v) = b(u, v).xyz / b(u, v).w; a patch
//! whose weights are all 1 is the ordinary polynomial patch.
//!
//! The evaluation functions here are the CPU twins of
//! `glsl/common/rational.glsl`, in the same operation order: homogeneous
//! points are formed as `p * w` component by component, curves are the
//! reversal-symmetric [`curve`](super::bezier::curve) order in four
//! dimensions, surfaces are rows at u then the column at v, and the point is
//! the homogeneous result divided by its w. The normal is the paper's: with
//! the 4D derivatives b_u and b_v, the tangents are
//! t_u = (b_u.xyz − b_u.w · p) / b.w (and t_v alike) and n = t_u × t_v.
//!
//! The tessellation bound is Zheng and Sederberg's for rational surfaces as
//! the paper states it (see [`zs_bounds`]).

use glam::{Vec3, Vec4};

use super::bezier::BezierPatch;

/// The 16 weights of a patch, stored like its control points
/// (`w[4 * j + i]` belongs to `pts[4 * j + i]`).
pub type Weights = [f32; 16];

/// The weights of a polynomial patch.
pub const UNIT_WEIGHTS: Weights = [1.0; 16];

/// Smallest and largest weight a model file may give (positive, and far
/// enough from 0 and from overflow that w·p and sums of them stay finite for
/// coordinates up to the scene's limit).
pub const MIN_WEIGHT: f32 = 1.0e-4;
/// See [`MIN_WEIGHT`].
pub const MAX_WEIGHT: f32 = 1.0e4;

/// Whether `w` is a weight a model may have.
pub fn weight_ok(w: f32) -> bool {
    w.is_finite() && (MIN_WEIGHT..=MAX_WEIGHT).contains(&w)
}

/// Whether every weight is exactly 1.
pub fn is_polynomial(w: &Weights) -> bool {
    w.iter().all(|&x| x == 1.0)
}

/// Weights of a patch whose parameter domain is reordered exactly as
/// [`BezierPatch::reoriented`] reorders its points.
pub fn reoriented_weights(w: &Weights, swap: bool, flip_u: bool, flip_v: bool) -> Weights {
    let mut out = *w;
    for j in 0..4 {
        for i in 0..4 {
            let ni = if flip_u { 3 - i } else { i };
            let nj = if flip_v { 3 - j } else { j };
            let (oi, oj) = if swap { (nj, ni) } else { (ni, nj) };
            out[4 * j + i] = w[4 * oj + oi];
        }
    }
    out
}

/// The homogeneous point (w p, w), component by component.
#[inline]
pub fn homogeneous(p: Vec3, w: f32) -> Vec4 {
    Vec4::new(p.x * w, p.y * w, p.z * w, w)
}

/// A cubic Bézier curve of homogeneous points at `u0`, in the operation
/// order of [`curve`](super::bezier::curve): reversal-symmetric for exact
/// complements `u0` and `1 − u0`.
#[inline]
pub fn curve4(u0: f32, p: &[Vec4; 4]) -> Vec4 {
    super::bezier::curve(u0, p)
}

/// Derivative of a homogeneous cubic at `u0` (shading and tests only).
#[inline]
pub fn curve4_derivative(u0: f32, p: &[Vec4; 4]) -> Vec4 {
    super::bezier::curve_derivative(u0, p)
}

/// The Cartesian point of a homogeneous one: xyz / w.
#[inline]
pub fn project(h: Vec4) -> Vec3 {
    Vec3::new(h.x / h.w, h.y / h.w, h.z / h.w)
}

/// A point of the rational cubic with control points `p` and weights `w`
/// at `t`: the homogeneous curve, divided. Reversal-symmetric like
/// [`curve4`], so two patches sharing the curve get the same bits.
pub fn rational_curve(t: f32, p: &[Vec3; 4], w: &[f32; 4]) -> Vec3 {
    let h = [0, 1, 2, 3].map(|k| homogeneous(p[k], w[k]));
    project(curve4(t, &h))
}

/// A bicubic patch with weights.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RationalPatch {
    /// The Cartesian control points.
    pub patch: BezierPatch,
    /// Their weights.
    pub w: Weights,
}

impl RationalPatch {
    /// A patch with weights `w`.
    pub fn new(patch: BezierPatch, w: Weights) -> Self {
        Self { patch, w }
    }

    /// The polynomial patch `patch` (all weights 1).
    pub fn polynomial(patch: BezierPatch) -> Self {
        Self::new(patch, UNIT_WEIGHTS)
    }

    /// Whether every weight is 1.
    pub fn is_polynomial(&self) -> bool {
        is_polynomial(&self.w)
    }

    /// Homogeneous control point `k` (storage index).
    #[inline]
    pub fn hom(&self, k: usize) -> Vec4 {
        homogeneous(self.patch.pts[k], self.w[k])
    }

    /// Homogeneous control row `j` (u ascending).
    pub fn hom_row(&self, j: usize) -> [Vec4; 4] {
        [0, 1, 2, 3].map(|i| self.hom(4 * j + i))
    }

    /// The homogeneous surface point b(u, v): rows at u, then the column
    /// at v (the order of `eval_patch`).
    pub fn eval_homogeneous(&self, u: f32, v: f32) -> Vec4 {
        let c = [0, 1, 2, 3].map(|j| curve4(u, &self.hom_row(j)));
        curve4(v, &c)
    }

    /// The surface point: b(u, v) divided by its weight.
    pub fn eval(&self, u: f32, v: f32) -> Vec3 {
        project(self.eval_homogeneous(u, v))
    }

    /// b, ∂b/∂u and ∂b/∂v at (u, v), all homogeneous.
    pub fn homogeneous_partials(&self, u: f32, v: f32) -> (Vec4, Vec4, Vec4) {
        let rows = [0, 1, 2, 3].map(|j| self.hom_row(j));
        let pu = rows.map(|r| curve4(u, &r));
        let du = rows.map(|r| curve4_derivative(u, &r));
        (curve4(v, &pu), curve4(v, &du), curve4_derivative(v, &pu))
    }

    /// The tangents t_u and t_v of the paper: (b_u.xyz − b_u.w p) / b.w.
    pub fn partials(&self, u: f32, v: f32) -> (Vec3, Vec3) {
        let (b, bu, bv) = self.homogeneous_partials(u, v);
        let p = project(b);
        let t = |d: Vec4| (d.truncate() - p * d.w) / b.w;
        (t(bu), t(bv))
    }

    /// Unnormalised normal t_u × t_v; where a boundary collapses to a point
    /// (a sphere's poles) it is taken a little way into the domain, as
    /// [`BezierPatch::normal`] does.
    pub fn normal(&self, u: f32, v: f32) -> Vec3 {
        super::bezier::normal_from_partials(|u, v| self.partials(u, v), u, v)
    }

    /// Edge curve `k` numbered as the tessellation methods number them
    /// (0: u = 0, 1: v = 0, 2: u = 1, 3: v = 1), points and weights in the
    /// direction of the edge's parameter.
    pub fn edge(&self, k: usize) -> ([Vec3; 4], [f32; 4]) {
        let idx = edge_indices(k);
        (idx.map(|i| self.patch.pts[i]), idx.map(|i| self.w[i]))
    }
}

/// Storage indices of edge `k`'s control points (0: u = 0, 1: v = 0,
/// 2: u = 1, 3: v = 1), in the direction of the edge's parameter.
pub fn edge_indices(k: usize) -> [usize; 4] {
    match k {
        0 => [0, 4, 8, 12],
        1 => [0, 1, 2, 3],
        2 => [3, 7, 11, 15],
        _ => [12, 13, 14, 15],
    }
}

/// The Zheng–Sederberg bounds of a rational patch for tolerance `eps`, as
/// the paper's §3 states them: with r the largest distance of a control
/// point from the origin (here the centre of the control points' box: the
/// error does not depend on the origin, and a near one keeps r small),
///
/// - D_uu = 6 max over i ∈ {0, 1}, j of ‖Δ²_u (w p)_ij‖ + (r − ε) |Δ²_u w_ij|,
/// - D_uv = 9 max over i, j ∈ {0, 1, 2} of the same with the mixed
///   difference Δ_u Δ_v,
/// - D_vv = 6 max over i, j ∈ {0, 1} of the same with Δ²_v,
///
/// and the steps must satisfy D_uu δ_u² + 2 D_uv δ_u δ_v + D_vv δ_v² ≤
/// 8 ε min w. (r − ε) is taken as 0 when negative. Returns
/// (D_uu, D_uv, D_vv, min w). For weights 1 the w terms vanish and these
/// are the polynomial bounds (those `tess` uses). f64: the reference for
/// the GPU's f32 in `glsl/common/cudatess.glsl`.
pub fn zs_bounds(p: &RationalPatch, eps: f64) -> (f64, f64, f64, f64) {
    let (lo, hi) = p.patch.bbox();
    let c = ((lo + hi) * 0.5).as_dvec3();
    let pts: Vec<glam::DVec3> = p.patch.pts.iter().map(|q| q.as_dvec3() - c).collect();
    let w: Vec<f64> = p.w.iter().map(|&x| f64::from(x)).collect();
    let r = pts.iter().map(|q| q.length()).fold(0.0, f64::max);
    let slack = (r - eps).max(0.0);
    let h = |k: usize| (pts[k] * w[k], w[k]);
    let term = |(a, wa): (glam::DVec3, f64)| a.length() + slack * wa.abs();
    let second = |k0: usize, k1: usize, k2: usize| {
        let (a, b, cc) = (h(k0), h(k1), h(k2));
        term((a.0 - b.0 * 2.0 + cc.0, a.1 - 2.0 * b.1 + cc.1))
    };
    let mut duu: f64 = 0.0;
    let mut dvv: f64 = 0.0;
    let mut duv: f64 = 0.0;
    for j in 0..4 {
        for i in 0..2 {
            duu = duu.max(second(4 * j + i, 4 * j + i + 1, 4 * j + i + 2));
            dvv = dvv.max(second(4 * i + j, 4 * (i + 1) + j, 4 * (i + 2) + j));
        }
    }
    for j in 0..3 {
        for i in 0..3 {
            let (a, b, cc, d) = (
                h(4 * j + i),
                h(4 * j + i + 1),
                h(4 * (j + 1) + i),
                h(4 * (j + 1) + i + 1),
            );
            duv = duv.max(term((a.0 - b.0 - cc.0 + d.0, a.1 - b.1 - cc.1 + d.1)));
        }
    }
    let w_min = w.iter().copied().fold(f64::INFINITY, f64::min);
    (6.0 * duu, 9.0 * duv, 6.0 * dvv, w_min)
}

/// Factors (m along u, n along v) that satisfy the bound of [`zs_bounds`]:
/// 2 D_uv δ_u δ_v ≤ D_uv (δ_u² + δ_v²), so it suffices that
/// (D_uu + D_uv) δ_u² + (D_vv + D_uv) δ_v² ≤ 8 ε min w, and giving each
/// term half: m = ⌈√((D_uu + D_uv) / (4 ε min w))⌉, n alike, clamped to
/// [1, `max`]. For weights 1 this is exactly the inner level of the `tess`
/// baseline, rounded up.
pub fn zs_factors(bounds: (f64, f64, f64, f64), eps: f64, max: u32) -> (u32, u32) {
    let (duu, duv, dvv, w_min) = bounds;
    let f = |d: f64| {
        let x = (d / (4.0 * eps * w_min)).sqrt().ceil();
        if x.is_nan() || x < 1.0 {
            1
        } else {
            (x.min(f64::from(max))) as u32
        }
    };
    (f(duu + duv), f(dvv + duv))
}

/// The parameter of vertex `k` of `e` along an edge, the same float from
/// both directions: at or past the middle it is k / e, before it
/// 1 − (e − k) / e, so the side that runs the edge the other way (and asks
/// for e − k) gets the exact complement, and `curve`/`curve4` give the same
/// point from both sides. The GPU computes the same division (whatever its
/// rounding, both sides use it); this twin is exact IEEE.
pub fn edge_param(k: u32, e: u32) -> f32 {
    if 2 * k >= e {
        k as f32 / e as f32
    } else {
        1.0 - (e - k) as f32 / e as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::fixtures::wavy;

    fn weights() -> Weights {
        std::array::from_fn(|k| 0.5 + (k as f32 * 0.37).sin().abs())
    }

    #[test]
    fn unit_weights_give_the_polynomial_patch() {
        let p = RationalPatch::polynomial(wavy());
        for (u, v) in [(0.0, 0.0), (0.3, 0.7), (1.0, 0.25), (0.5, 0.5)] {
            assert_eq!(p.eval(u, v), p.patch.eval(u, v), "({u}, {v})");
            let n = p.normal(u, v).normalize();
            let m = p.patch.normal(u, v).normalize();
            assert!(n.dot(m) > 0.999_999, "({u}, {v}): {n} {m}");
        }
    }

    #[test]
    fn rational_curves_are_reversal_symmetric() {
        let r = RationalPatch::new(wavy(), weights());
        for k in 0..4 {
            let (p, w) = r.edge(k);
            let (pr, wr) = ([p[3], p[2], p[1], p[0]], [w[3], w[2], w[1], w[0]]);
            for e in 1..=64u32 {
                for i in 0..=e {
                    let a = rational_curve(edge_param(i, e), &p, &w);
                    let b = rational_curve(edge_param(e - i, e), &pr, &wr);
                    assert_eq!(a.to_array(), b.to_array(), "edge {k}, {i}/{e}");
                }
            }
        }
    }

    #[test]
    fn edge_params_are_exact_complements() {
        for e in 1..=64u32 {
            for k in 0..=e {
                let (a, b) = (edge_param(k, e), edge_param(e - k, e));
                assert_eq!(1.0 - a, b, "{k}/{e}");
                assert_eq!(1.0 - b, a, "{k}/{e}");
                assert!((f64::from(a) - f64::from(k) / f64::from(e)).abs() < 1e-7);
            }
        }
    }

    #[test]
    fn normals_match_finite_differences() {
        let r = RationalPatch::new(wavy(), weights());
        let h = 1e-3;
        for (u, v) in [(0.2f32, 0.3f32), (0.6, 0.8), (0.5, 0.1)] {
            let (su, sv) = r.partials(u, v);
            let fu = (r.eval(u + h, v) - r.eval(u - h, v)) / (2.0 * h);
            let fv = (r.eval(u, v + h) - r.eval(u, v - h)) / (2.0 * h);
            assert!(
                (su - fu).length() < 1e-3 * su.length().max(1.0),
                "{su} {fu}"
            );
            assert!(
                (sv - fv).length() < 1e-3 * sv.length().max(1.0),
                "{sv} {fv}"
            );
        }
    }

    #[test]
    fn reorienting_weights_follows_the_points() {
        let r = RationalPatch::new(wavy(), weights());
        for (swap, fu, fv) in [
            (true, false, false),
            (false, true, false),
            (true, true, true),
        ] {
            let q = RationalPatch::new(
                r.patch.reoriented(swap, fu, fv),
                reoriented_weights(&r.w, swap, fu, fv),
            );
            let (a, b) = (0.3f32, 0.6f32);
            let (s, t) = (if fu { 1.0 - a } else { a }, if fv { 1.0 - b } else { b });
            let (s, t) = if swap { (t, s) } else { (s, t) };
            assert!((q.eval(a, b) - r.eval(s, t)).length() < 1e-6);
        }
    }

    #[test]
    fn unit_weight_bounds_are_the_polynomial_ones() {
        let p = RationalPatch::polynomial(wavy());
        let (duu, duv, dvv, w_min) = zs_bounds(&p, 0.01);
        assert_eq!(w_min, 1.0);
        // 6 |(p0 + p2) - 2 p1| of the rows, 9 |mixed| of the net.
        let mut want_uu: f64 = 0.0;
        for j in 0..4 {
            for i in 0..2 {
                let a = p.patch.at(i, j).as_dvec3();
                let b = p.patch.at(i + 1, j).as_dvec3();
                let c = p.patch.at(i + 2, j).as_dvec3();
                want_uu = want_uu.max(((a + c) - 2.0 * b).length() * 6.0);
            }
        }
        assert!((duu - want_uu).abs() < 1e-6 * want_uu, "{duu} {want_uu}");
        assert!(duv > 0.0 && dvv >= 0.0);
    }
}
