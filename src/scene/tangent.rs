//! Tangent patches for converted cages: a continuous shading-normal field
//! across every edge that is not a feature (crease, boundary, non-manifold).
//!
//! After Loop and Schaefer's ACC tangent patches (2008), in this project's
//! own construction. Per patch, ∂u is a 3×4 and ∂v a 4×3 control net
//! (`shading.rs`). Their boundary rows are, per patch edge k (running from
//! corner k to k + 1, "inward" pointing into the patch):
//!
//! - the along-edge tangent T_k, quadratic: its ends are the corner
//!   tangents along the edge, its middle the geometry's own
//!   3·(E_far − E_near) — the same on both sides of the edge;
//! - the inward tangent X_k, cubic: its ends are the corner tangents along
//!   the neighbouring edges; its two middle vectors the geometry's own,
//!   except on a shared smooth edge (below).
//!
//! Corner tangents. Around each vertex the edges of a sector (faces between
//! feature edges, or the whole closed fan) get tangents of the form
//! `t_k = A·cos kθ + B·sin kθ`: for a closed fan of n edges θ = 2π/n and A,
//! B are the first Fourier harmonic of the geometry's edge tangents
//! g_k = 3·(E_k − C) (exactly g_k at a regular vertex); for an open sector
//! of m faces the two feature edges keep their own g (crease curves are
//! C¹ through a crease vertex, so there A = (g_0 − g_m)/2, θ = π/m and B
//! fits the inner tangents), with θ = Φ/m where Φ is the sector's angle
//! otherwise. All tangents of a sector then lie in one plane (the vertex's
//! shading tangent plane), and every inner edge's two neighbours satisfy
//! t_{k−1} + t_{k+1} = 2 cos θ · t_k.
//!
//! Shared smooth edge, faces A and B, parameter s along A's direction, T(s)
//! the common along-edge tangent: the inward tangents are
//! X_A = X̄ + α·T and X_B = −X̄ + α·T with X̄ the mean of A's and minus B's
//! geometric inward tangents (middle vectors; the ends are the corner
//! tangents) and α linear, α(0)·T(0) = (t_A + t_B)/2 at each end (the
//! identity above makes that exact). Then T × X_A = −(T × X_B) along the
//! whole edge: the two normals agree in direction and length. Where a
//! vertex's tangents could not be fitted (fewer than three edges around a
//! smooth vertex, degenerate geometry) the geometry's own are used and the
//! normal may still jump near that vertex.

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::acc::{is_feature_edge, Conversion};
use super::cage::{Cage, Topology};
use super::shading::ShadingPatch;
use super::sharpness;

/// Along-edge (3) and inward (4) tangents of one patch edge, f64.
#[derive(Clone, Copy, Default)]
struct EdgeTangents {
    along: [DVec3; 3],
    inward: [DVec3; 4],
}

/// The patch's control point at (i along edge k, j inward from it).
fn rotated(p: &[DVec3; 16], k: usize, i: usize, j: usize) -> DVec3 {
    let (u, v) = match k {
        0 => (i, j),
        1 => (3 - j, i),
        2 => (3 - i, 3 - j),
        _ => (j, 3 - i),
    };
    p[4 * v + u]
}

/// Corner tangents of each sector of `v`, by (face, corner): (along the
/// incoming edge, along the outgoing edge), both pointing away from `v`.
fn corner_tangents(
    cage: &Cage,
    topo: &Topology,
    conv: &Conversion,
    v: usize,
    out: &mut HashMap<(usize, usize), (DVec3, DVec3)>,
) {
    let c = conv.corner[v].as_dvec3();
    let g = |e: usize| (conv.edge_point[&(v, topo.edges[e].other(v))].as_dvec3() - c) * 3.0;
    let feature = |e: usize| {
        let (a, b) = topo.edges[e].ends;
        is_feature_edge(cage, topo, a, b)
    };
    // A crease vertex (two feature edges, not a corner): its crease curve
    // is smooth through it, whatever the two edge tangents' angle says (the
    // exact limit corner of a semi-sharp crease, `limit.rs`, sits a little
    // off the chord of the sharp rules' edge points).
    let features = topo.vertex_edges[v].iter().filter(|&&e| feature(e)).count();
    let crease = features == 2 && cage.vertex_sharpness(v) < 1.0;
    for sector in sharpness::sectors(topo, v, &feature) {
        let geo: Vec<DVec3> = sector.edges.iter().map(|&e| g(e)).collect();
        let t = if sector.cyclic {
            fit_cyclic(&geo)
        } else {
            fit_open(&geo, crease)
        }
        .unwrap_or_else(|| geo.clone());
        let n = sector.corners.len();
        for (i, &corner) in sector.corners.iter().enumerate() {
            let next = if sector.cyclic { (i + 1) % n } else { i + 1 };
            out.insert(corner, (t[i], t[next]));
        }
    }
}

/// Tangents around a closed fan: the first Fourier harmonic of `g`.
fn fit_cyclic(g: &[DVec3]) -> Option<Vec<DVec3>> {
    let n = g.len();
    if n < 3 {
        return None;
    }
    let theta = 2.0 * PI / n as f64;
    let (mut a, mut b) = (DVec3::ZERO, DVec3::ZERO);
    for (k, gk) in g.iter().enumerate() {
        a += *gk * (k as f64 * theta).cos();
        b += *gk * (k as f64 * theta).sin();
    }
    let (a, b) = (a * (2.0 / n as f64), b * (2.0 / n as f64));
    if a.cross(b).length() <= 1e-9 * a.length() * b.length() || a == DVec3::ZERO {
        return None;
    }
    Some(
        (0..n)
            .map(|k| a * (k as f64 * theta).cos() + b * (k as f64 * theta).sin())
            .collect(),
    )
}

/// Tangents across an open sector of `g.len() − 1` faces, keeping the two
/// feature edges' own tangents (see the module doc); at a `crease` vertex
/// the two are made opposite.
fn fit_open(g: &[DVec3], crease: bool) -> Option<Vec<DVec3>> {
    let m = g.len() - 1;
    if m < 2 {
        return None;
    }
    let axis: DVec3 = g.windows(2).map(|w| w[0].cross(w[1])).sum();
    let (g0, gm) = (g[0], g[m]);
    if axis.length() == 0.0 || g0.length() == 0.0 || gm.length() == 0.0 {
        return None;
    }
    let axis = axis.normalize();
    let mut phi = (g0.cross(gm).dot(axis)).atan2(g0.dot(gm));
    if phi <= 0.0 {
        phi += 2.0 * PI;
    }
    let mut t = vec![DVec3::ZERO; m + 1];
    if (phi - PI).abs() < 0.02 || (crease && (phi - PI).abs() < 0.5) {
        // A crease through the vertex: g_m = −g_0 up to rounding.
        let theta = PI / m as f64;
        let a = (g0 - gm) * 0.5;
        let (mut num, mut den) = (DVec3::ZERO, 0.0);
        for (k, gk) in g.iter().enumerate().take(m).skip(1) {
            let (c, s) = ((k as f64 * theta).cos(), (k as f64 * theta).sin());
            num += (*gk - a * c) * s;
            den += s * s;
        }
        let b = num / den;
        if a.cross(b).length() <= 1e-9 * a.length() * b.length() {
            return None;
        }
        for (k, tk) in t.iter_mut().enumerate() {
            *tk = a * (k as f64 * theta).cos() + b * (k as f64 * theta).sin();
        }
        t[0] = a;
        t[m] = -a;
    } else if phi.sin().abs() >= 0.02 {
        let theta = phi / m as f64;
        let b = (gm - g0 * phi.cos()) / phi.sin();
        for (k, tk) in t.iter_mut().enumerate() {
            *tk = g0 * (k as f64 * theta).cos() + b * (k as f64 * theta).sin();
        }
        t[0] = g0;
        t[m] = gm;
    } else {
        return None;
    }
    Some(t)
}

/// The tangent patches of every patch of `conv` (see the module doc).
pub fn tangent_patches(cage: &Cage, topo: &Topology, conv: &Conversion) -> Vec<ShadingPatch> {
    let mut corner_t = HashMap::new();
    for v in 0..cage.positions.len() {
        corner_tangents(cage, topo, conv, v, &mut corner_t);
    }
    let patch_of: HashMap<usize, usize> = conv
        .faces
        .iter()
        .enumerate()
        .map(|(p, &f)| (f, p))
        .collect();

    let mut edges: Vec<[EdgeTangents; 4]> = Vec::with_capacity(conv.patches.len());
    for (p, &f) in conv.faces.iter().enumerate() {
        let face = &cage.faces[f];
        let pts = conv.patches[p].pts.map(|q| q.as_dvec3());
        let t = |k: usize| corner_t[&(f, k % 4)];
        edges.push(std::array::from_fn(|k| {
            let (v0, v1) = (face[k], face[(k + 1) % 4]);
            let mid = (conv.edge_point[&(v1, v0)].as_dvec3()
                - conv.edge_point[&(v0, v1)].as_dvec3())
                * 3.0;
            let geo = |i: usize| (rotated(&pts, k, i, 1) - rotated(&pts, k, i, 0)) * 3.0;
            EdgeTangents {
                along: [t(k).1, mid, -t(k + 1).0],
                inward: [t(k).0, geo(1), geo(2), t(k + 1).1],
            }
        }));
    }

    for e in &topo.edges {
        let [(f, k), (g, m)] = e.uses[..] else {
            continue;
        };
        let (Some(&pa), Some(&pb)) = (patch_of.get(&f), patch_of.get(&g)) else {
            continue;
        };
        if is_feature_edge(cage, topo, e.ends.0, e.ends.1) {
            continue;
        }
        let along = edges[pa][k].along;
        let xa = edges[pa][k].inward;
        let mut xb = edges[pb][m].inward;
        xb.reverse();
        let alpha = |ta: DVec3, tb: DVec3, t: DVec3| {
            let l = t.length_squared();
            if l > 0.0 {
                (ta + tb).dot(t) / (2.0 * l)
            } else {
                0.0
            }
        };
        let a0 = alpha(xa[0], xb[0], along[0]);
        let a1 = alpha(xa[3], xb[3], along[2]);
        let at1 = (along[0] * a1 + along[1] * (2.0 * a0)) / 3.0;
        let at2 = (along[1] * (2.0 * a1) + along[2] * a0) / 3.0;
        let mean1 = (xa[1] - xb[1]) * 0.5;
        let mean2 = (xa[2] - xb[2]) * 0.5;
        edges[pa][k].inward[1] = mean1 + at1;
        edges[pa][k].inward[2] = mean2 + at2;
        edges[pb][m].inward[2] = -mean1 + at1;
        edges[pb][m].inward[1] = -mean2 + at2;
    }

    conv.patches
        .iter()
        .zip(&edges)
        .map(|(patch, e)| assemble(patch, e))
        .collect()
}

/// Writes the four edges' tangents over the geometry's own derivative nets.
fn assemble(patch: &crate::patch::bezier::BezierPatch, e: &[EdgeTangents; 4]) -> ShadingPatch {
    let geo = ShadingPatch::from_geometry(patch);
    let mut du = geo.du.map(|q| q.as_dvec3());
    let mut dv = geo.dv.map(|q| q.as_dvec3());
    // du[3j + i] (i < 3 along u, j < 4 along v); dv[4j + i] (i < 4, j < 3).
    for i in 0..3 {
        du[i] = e[0].along[i];
        dv[4 * i + 3] = e[1].along[i];
        du[9 + (2 - i)] = -e[2].along[i];
        dv[4 * (2 - i)] = -e[3].along[i];
    }
    for i in 0..4 {
        dv[i] = e[0].inward[i];
        du[3 * i + 2] = -e[1].inward[i];
        dv[8 + (3 - i)] = -e[2].inward[i];
        du[3 * (3 - i)] = e[3].inward[i];
    }
    let round = |d: DVec3| d.as_vec3() + Vec3::ZERO;
    ShadingPatch {
        du: du.map(round),
        dv: dv.map(round),
    }
}
