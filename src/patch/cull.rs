//! Culling: the view frustum against a (sub-)patch's control-point box, and
//! a conservative back-face test for ready sub-patches.
//!
//! Both are pure functions of the sub-patch and the view, in a fixed
//! operation order, so the GPU takes the same decisions. Neither needs to
//! agree across a shared edge: a patch culled by the frustum lies wholly
//! outside the view (the convex-hull property), so any crack beside it is
//! off-screen too.

use glam::Vec3;

use super::bezier::BezierPatch;
use super::ops::{affine_row, cross3, dot3, max3, min3};
use super::quadnode::QuadNode;
use super::view::ViewParams;
use super::wedge::node_mesh;

/// True when the box [lo, hi] lies entirely on the outer side of one of the
/// frustum planes (tested at the box corner farthest along the plane normal).
pub fn outside_frustum(lo: Vec3, hi: Vec3, vp: &ViewParams) -> bool {
    let mut outside = false;
    for p in &vp.planes {
        let corner = Vec3::new(
            if p.x >= 0.0 { hi.x } else { lo.x },
            if p.y >= 0.0 { hi.y } else { lo.y },
            if p.z >= 0.0 { hi.z } else { lo.z },
        );
        outside |= affine_row(*p, corner) < 0.0;
    }
    outside
}

/// An interval [lo, hi].
#[derive(Clone, Copy, Debug)]
struct Iv(f32, f32);

#[inline]
fn fmin(a: f32, b: f32) -> f32 {
    if b < a {
        b
    } else {
        a
    }
}

#[inline]
fn fmax(a: f32, b: f32) -> f32 {
    if b > a {
        b
    } else {
        a
    }
}

#[inline]
fn imul(a: Iv, b: Iv) -> Iv {
    let p0 = a.0 * b.0;
    let p1 = a.0 * b.1;
    let p2 = a.1 * b.0;
    let p3 = a.1 * b.1;
    Iv(
        fmin(fmin(p0, p1), fmin(p2, p3)),
        fmax(fmax(p0, p1), fmax(p2, p3)),
    )
}

#[inline]
fn isub(a: Iv, b: Iv) -> Iv {
    Iv(a.0 - b.1, a.1 - b.0)
}

/// Conservative back-face test. Every tangent ∂S/∂u of a Bézier patch is 3×
/// a convex combination of the 12 differences `p[i+1][j] - p[i][j]`, so it
/// lies in 3× their bounding box U; likewise ∂S/∂v in 3× V. The normal
/// ∂S/∂u × ∂S/∂v therefore lies in 9× the interval cross product U ⊗ V, and
/// every surface point in the control-point box B. If the interval bound of
/// `(U ⊗ V) · (B - eye)` is strictly positive, every normal points away from
/// the eye at every surface point: the patch has no front-facing part and is
/// culled. (Up to f32 rounding in the bound itself.)
pub fn back_facing(s: &BezierPatch, lo: Vec3, hi: Vec3, eye: Vec3) -> bool {
    let mut ulo = s.at(1, 0) - s.at(0, 0);
    let mut uhi = ulo;
    let mut vlo = s.at(0, 1) - s.at(0, 0);
    let mut vhi = vlo;
    for j in 0..4 {
        for i in 0..3 {
            let du = s.at(i + 1, j) - s.at(i, j);
            ulo = min3(ulo, du);
            uhi = max3(uhi, du);
            let dv = s.at(j, i + 1) - s.at(j, i);
            vlo = min3(vlo, dv);
            vhi = max3(vhi, dv);
        }
    }
    let (ux, uy, uz) = (Iv(ulo.x, uhi.x), Iv(ulo.y, uhi.y), Iv(ulo.z, uhi.z));
    let (vx, vy, vz) = (Iv(vlo.x, vhi.x), Iv(vlo.y, vhi.y), Iv(vlo.z, vhi.z));
    let nx = isub(imul(uy, vz), imul(uz, vy));
    let ny = isub(imul(uz, vx), imul(ux, vz));
    let nz = isub(imul(ux, vy), imul(uy, vx));
    let wlo = lo - eye;
    let whi = hi - eye;
    let dx = imul(nx, Iv(wlo.x, whi.x));
    let dy = imul(ny, Iv(wlo.y, whi.y));
    let dz = imul(nz, Iv(wlo.z, whi.z));
    (dx.0 + dy.0) + dz.0 > 0.0
}

/// True when every wedge triangle of a ready node faces away from the eye
/// (or there are none). A back-facing node may only be dropped together
/// with its wedges when they face away too: a wedge reaches from the node's
/// edge to a pivot on a coarser edge, possibly where the surface already
/// faces the eye, and on a closed, consistently wound, watertight mesh only
/// triangles that face away can be removed without uncovering anything.
/// Positions are the drawn ones ([`BezierPatch::eval`]).
pub fn wedges_face_away(base: &BezierPatch, node: QuadNode, eye: Vec3, with_wedges: bool) -> bool {
    wedges_face_away_with(|u, v| base.eval(u, v), node, eye, with_wedges)
}

/// [`wedges_face_away`] with the drawn positions given by `eval` (a
/// rational patch's evaluation).
pub fn wedges_face_away_with(
    eval: impl Fn(f32, f32) -> Vec3,
    node: QuadNode,
    eye: Vec3,
    with_wedges: bool,
) -> bool {
    let mesh = node_mesh(node, with_wedges);
    let mut away = true;
    for t in &mesh.tris[2..mesh.tri_count] {
        let [a, b, c] = t.map(|k| {
            let (u, v) = mesh.uv[k as usize];
            eval(u, v)
        });
        let n = cross3(b - a, c - a);
        away &= dot3(n, a - eye) > 0.0;
    }
    away
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::blossom::reconstruct;
    use crate::patch::ops::dot3;
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    /// A patch on the sphere of radius 1 around the origin, near direction +z,
    /// parameterised so that ∂u × ∂v points outward.
    fn cap(size: f32) -> BezierPatch {
        let mut pts = [Vec3::ZERO; 16];
        for j in 0..4 {
            for i in 0..4 {
                let x = (i as f32 / 3.0 - 0.5) * size;
                let y = (j as f32 / 3.0 - 0.5) * size;
                pts[4 * j + i] = Vec3::new(x, y, 1.0 - 0.5 * (x * x + y * y));
            }
        }
        BezierPatch { pts }
    }

    #[test]
    fn cap_seen_from_outside_and_inside() {
        let s = cap(0.3);
        let (lo, hi) = s.bbox();
        assert!(!back_facing(&s, lo, hi, Vec3::new(0.0, 0.0, 5.0)));
        assert!(back_facing(&s, lo, hi, Vec3::new(0.0, 0.0, -5.0)));
        // Grazing view: neither culled nor wrongly kept as a whole.
        assert!(!back_facing(&s, lo, hi, Vec3::new(5.0, 0.0, 1.0)));
    }

    /// Never culls a patch that has a front-facing point (random patches and
    /// random eyes, checked on a dense sample grid).
    #[test]
    fn never_culls_a_visible_part() {
        let mut rng = SmallRng::seed_from_u64(3);
        let mut culled = 0;
        for _ in 0..3000 {
            let base = cap(rng.random_range(0.1..1.5));
            let a = rng.random_range(0.0..0.5f32);
            let c = rng.random_range(0.0..0.5f32);
            let s = reconstruct(&base, a, a + 0.5, c, c + 0.5);
            let eye = Vec3::new(
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
                rng.random_range(-3.0..3.0),
            );
            let (lo, hi) = s.bbox();
            if !back_facing(&s, lo, hi, eye) {
                continue;
            }
            culled += 1;
            for k in 0..=16 {
                for l in 0..=16 {
                    let (u, v) = (k as f32 / 16.0, l as f32 / 16.0);
                    let p = s.eval(u, v);
                    let n = s.normal(u, v);
                    assert!(dot3(n, p - eye) > 0.0, "front-facing point culled");
                }
            }
        }
        assert!(culled > 100, "the test must exercise culling ({culled})");
    }
}
