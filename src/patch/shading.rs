//! Shading normals: a pair of tangent patches per base patch, whose cross
//! product is the normal a renderer shades with. Positions never come from
//! here (crack-freeness and the oracle comparison rest on the geometry
//! patches alone).
//!
//! A geometry patch's own derivatives give normals that jump across patch
//! edges next to extraordinary vertices (ACC patches meet there with C0
//! only). The tangent patches are built (`tangent.rs`, after Loop and
//! Schaefer 2008) so that the normal field is continuous across every edge
//! that is not a crease; elsewhere they are the geometry's own derivatives.
//!
//! Layout (the GPU contract): per base patch 24 control vectors, 72 f32:
//!
//! - `du[3 * j + i]`, i = 0..3 along u, j = 0..4 along v: ∂S/∂u as a
//!   patch of degree 2 in u and 3 in v;
//! - `dv[4 * j + i]`, i = 0..4 along u, j = 0..3 along v: ∂S/∂v, degree 3
//!   in u and 2 in v;
//!
//! and the normal at (u, v) is `Du(u, v) × Dv(u, v)` with
//! `Du = Σ_j B3_j(v) Σ_i B2_i(u) du[3j + i]`,
//! `Dv = Σ_j B2_j(v) Σ_i B3_i(u) dv[4j + i]` (Bernstein polynomials
//! B2 = ((1−t)², 2t(1−t), t²), B3 = ((1−t)³, 3t(1−t)², 3t²(1−t), t³)),
//! normalised by the renderer. Where it vanishes (a collapsed patch edge, or
//! a smoothed cage corner) it is taken a little way into the domain, as
//! `BezierPatch::normal` does.

use std::collections::HashMap;

use glam::{DMat4, DVec3, Vec3};

use crate::constants::SHADING_FLOATS;
use crate::patch::bezier::BezierPatch;

/// The tangent patches of one base patch (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadingPatch {
    /// ∂S/∂u control vectors, `du[3 * j + i]`.
    pub du: [Vec3; 12],
    /// ∂S/∂v control vectors, `dv[4 * j + i]`.
    pub dv: [Vec3; 12],
}

/// Bytes per base patch of tightly packed tangent patches.
pub const SHADING_BYTES_PER_PATCH: usize = SHADING_FLOATS as usize * 4;

fn bern2(t: f32) -> [f32; 3] {
    let s = 1.0 - t;
    [s * s, 2.0 * t * s, t * t]
}

fn bern3(t: f32) -> [f32; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t]
}

impl ShadingPatch {
    /// The geometry patch's own derivative nets: shading with these is
    /// shading with `BezierPatch::partials`.
    pub fn from_geometry(p: &BezierPatch) -> Self {
        let du = std::array::from_fn(|n| {
            let (i, j) = (n % 3, n / 3);
            (p.at(i + 1, j) - p.at(i, j)) * 3.0
        });
        let dv = std::array::from_fn(|n| {
            let (i, j) = (n % 4, n / 4);
            (p.at(i, j + 1) - p.at(i, j)) * 3.0
        });
        ShadingPatch { du, dv }
    }

    /// The two tangent fields at (u, v).
    pub fn tangents(&self, u: f32, v: f32) -> (Vec3, Vec3) {
        let (a2, b3) = (bern2(u), bern3(v));
        let mut tu = Vec3::ZERO;
        for (j, bj) in b3.iter().enumerate() {
            let row =
                self.du[3 * j] * a2[0] + self.du[3 * j + 1] * a2[1] + self.du[3 * j + 2] * a2[2];
            tu += row * *bj;
        }
        let (a3, b2) = (bern3(u), bern2(v));
        let mut tv = Vec3::ZERO;
        for (j, bj) in b2.iter().enumerate() {
            let row = (self.dv[4 * j] * a3[0] + self.dv[4 * j + 1] * a3[1])
                + (self.dv[4 * j + 2] * a3[2] + self.dv[4 * j + 3] * a3[3]);
            tv += row * *bj;
        }
        (tu, tv)
    }

    /// Unnormalised shading normal `Du × Dv` at (u, v); where it vanishes,
    /// the normal a little way towards the middle of the domain.
    pub fn normal(&self, u: f32, v: f32) -> Vec3 {
        let (tu, tv) = self.tangents(u, v);
        let n = tu.cross(tv);
        let scale = tu.length_squared() * tv.length_squared();
        if n.length_squared() > 1e-12 * scale && scale > 0.0 {
            return n;
        }
        let nudge = |t: f32| t + (0.5 - t) * 1e-3;
        let (tu, tv) = self.tangents(nudge(u), nudge(v));
        tu.cross(tv)
    }

    /// The tangent patches of `transform_patch(p, m)` (scene instancing):
    /// vectors take the linear part of `m` (f64, rounded once); a mirroring
    /// transform swaps u and v as the geometry does, which turns the ∂u net
    /// into the transposed ∂v net and the other way round.
    pub fn transformed(&self, m: &DMat4) -> Self {
        let t = |d: Vec3| m.transform_vector3(d.as_dvec3()).as_vec3() + Vec3::ZERO;
        let du = self.du.map(t);
        let dv = self.dv.map(t);
        let out = ShadingPatch { du, dv };
        if m.determinant() >= 0.0 {
            out
        } else {
            out.transposed()
        }
    }

    /// The tangent patches of the patch with u and v swapped
    /// (`BezierPatch::reoriented(true, …)`).
    pub fn transposed(&self) -> Self {
        let (du, dv) = (self.du, self.dv);
        // New ∂u (degree 2 in the new u = old v) is the old ∂v net transposed.
        ShadingPatch {
            du: std::array::from_fn(|n| {
                let (i, j) = (n % 3, n / 3);
                dv[4 * i + j]
            }),
            dv: std::array::from_fn(|n| {
                let (i, j) = (n % 4, n / 4);
                du[3 * i + j]
            }),
        }
    }

    /// The 72 floats of the GPU layout: `du` then `dv`, x, y, z each.
    pub fn to_floats(&self) -> [f32; SHADING_FLOATS as usize] {
        let mut out = [0.0; SHADING_FLOATS as usize];
        for (k, v) in self.du.iter().chain(&self.dv).enumerate() {
            out[3 * k..3 * k + 3].copy_from_slice(&v.to_array());
        }
        out
    }
}

/// Parameters of the point at `t` along edge `k` of a patch, running from
/// corner k to corner k + 1 (corners (0,0), (1,0), (1,1), (0,1)).
pub fn edge_uv(k: usize, t: f32) -> (f32, f32) {
    match k {
        0 => (t, 0.0),
        1 => (1.0, t),
        2 => (1.0 - t, 1.0),
        _ => (0.0, 1.0 - t),
    }
}

/// Two patches meeting along an edge: (patch, edge) on each side; the
/// second runs the edge the other way.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgePair {
    /// First side.
    pub a: (usize, usize),
    /// Second side.
    pub b: (usize, usize),
}

/// Every edge two patches share bit for bit (the same four control points,
/// reversed) and only two, leaving out those `feature(patch, edge)` marks
/// as creases or boundaries.
pub fn shared_edges(
    patches: &[BezierPatch],
    feature: &dyn Fn(usize, usize) -> bool,
) -> Vec<EdgePair> {
    let bits = |c: [Vec3; 4]| c.map(|p| p.to_array().map(f32::to_bits));
    let mut by_curve: HashMap<[[u32; 3]; 4], Vec<(usize, usize)>> = HashMap::new();
    for (p, patch) in patches.iter().enumerate() {
        for k in 0..4 {
            by_curve
                .entry(bits(patch.edge(k)))
                .or_default()
                .push((p, k));
        }
    }
    let mut out = Vec::new();
    for (curve, sides) in &by_curve {
        let [a] = sides[..] else { continue };
        let mut rev = *curve;
        rev.reverse();
        let Some(other) = by_curve.get(&rev) else {
            continue;
        };
        let [b] = other[..] else { continue };
        if a < b && a.0 != b.0 && !feature(a.0, a.1) && !feature(b.0, b.1) {
            out.push(EdgePair { a, b });
        }
    }
    out.sort_unstable_by_key(|e| (e.a, e.b));
    out
}

/// The largest angle between the normals on the two sides of an edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jump {
    /// The angle in degrees.
    pub degrees: f64,
    /// Where: patch and edge of the first side, and the parameter along it.
    pub patch: usize,
    /// Edge of `patch`.
    pub edge: usize,
    /// Parameter along the edge.
    pub t: f32,
}

/// Samples every pair at `samples + 1` evenly spaced points (ends included)
/// and returns the largest angle between `normal(patch, u, v)` on the two
/// sides; `None` when there is no pair. Zero normals are skipped.
pub fn largest_jump(
    pairs: &[EdgePair],
    samples: u32,
    normal: &dyn Fn(usize, f32, f32) -> Vec3,
) -> Option<Jump> {
    let mut worst: Option<Jump> = None;
    for pair in pairs {
        for s in 0..=samples {
            let t = s as f32 / samples as f32;
            let (ua, va) = edge_uv(pair.a.1, t);
            let (ub, vb) = edge_uv(pair.b.1, 1.0 - t);
            let na = normal(pair.a.0, ua, va).as_dvec3();
            let nb = normal(pair.b.0, ub, vb).as_dvec3();
            if na == DVec3::ZERO || nb == DVec3::ZERO {
                continue;
            }
            let degrees = na.cross(nb).length().atan2(na.dot(nb)).to_degrees();
            if worst.is_none_or(|w| degrees > w.degrees) {
                worst = Some(Jump {
                    degrees,
                    patch: pair.a.0,
                    edge: pair.a.1,
                    t,
                });
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy() -> BezierPatch {
        let pts = std::array::from_fn(|n| {
            let (i, j) = ((n % 4) as f32, (n / 4) as f32);
            Vec3::new(i, j, (i * 1.3).sin() * (j * 0.7).cos())
        });
        BezierPatch { pts }
    }

    #[test]
    fn geometry_nets_reproduce_the_partials() {
        let p = wavy();
        let s = ShadingPatch::from_geometry(&p);
        for (u, v) in [(0.0, 0.0), (0.3, 0.8), (1.0, 0.5), (0.7, 1.0)] {
            let (a, b) = p.partials(u, v);
            let (c, d) = s.tangents(u, v);
            assert!((a - c).length() < 1e-5 && (b - d).length() < 1e-5);
        }
    }
}
