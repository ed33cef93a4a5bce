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
//! whole edge: the two normals agree in direction and length, whatever α
//! is. Where a vertex's tangents could not be fitted (fewer than three
//! edges around a smooth vertex, degenerate geometry) the geometry's own
//! are used and the normal may still jump near that vertex.
//!
//! Linear in the control points, for animation. What depends on positions
//! is decided once ([`decide`], from the cage as loaded) and kept for every
//! pose: each sector's fit (cyclic, crease, open with its angle Φ, or the
//! geometry's own tangents) and each shared edge end's α, which is
//! cos θ where the sector is fitted (the identity above makes the
//! projection (t_A + t_B)·T / 2|T|² exactly that) and that projection where
//! it is not. With those fixed the construction is a linear map of the
//! patches' control points; it is written once over [`Vector`], so the
//! same code gives the tangents of a pose ([`tangent_patches`]) and the
//! combinations of control points they are ([`recipe`], `stencil.rs`).

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::acc::{is_feature_edge, Conversion};
use super::linear::{Comb, Vector};
use super::mesh::{Cage, Topology};
use super::sharpness;
use crate::patch::shading::ShadingPatch;

/// How one sector's corner tangents are made: the construction's only
/// choices that depend on positions, made once from the cage as loaded
/// ([`decide`]) and kept for every pose of an animation.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fit {
    /// The first Fourier harmonic around a closed fan.
    Cyclic,
    /// An open sector at a crease vertex: its two feature edges opposite.
    Crease,
    /// An open sector spanning the angle `phi`, its feature edges kept.
    Open { phi: f64 },
    /// Not fitted: the geometry's own edge tangents.
    Own,
}

impl Fit {
    /// The angle between neighbouring tangents of a fitted sector of
    /// `edges` edges.
    fn theta(self, edges: usize, cyclic: bool) -> Option<f64> {
        let n = edges as f64;
        match self {
            Fit::Cyclic if cyclic => Some(2.0 * PI / n),
            Fit::Crease => Some(PI / (n - 1.0)),
            Fit::Open { phi } => Some(phi / (n - 1.0)),
            _ => None,
        }
    }
}

/// The position-dependent choices of the construction for one converted
/// cage: per vertex and sector (in `sharpness::sectors` order) its fit;
/// per shared smooth edge and end the blend α of the along-edge tangent
/// (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct Decisions {
    fits: Vec<Vec<Fit>>,
    /// (edge, end 0 or 1) → α.
    alpha: HashMap<(usize, usize), f64>,
}

/// Along-edge (3) and inward (4) tangents of one patch edge.
#[derive(Clone)]
struct EdgeTangents<V> {
    along: [V; 3],
    inward: [V; 4],
}

/// The points of a conversion the construction reads, as values or names.
struct Points<'a, V> {
    corner: &'a dyn Fn(usize) -> V,
    edge: &'a dyn Fn(usize, usize) -> V,
    /// Control point `slot` of patch `p`.
    slot: &'a dyn Fn(usize, usize) -> V,
}

/// The patch's control-point slot at (i along edge k, j inward from it).
fn rotated_slot(k: usize, i: usize, j: usize) -> usize {
    let (u, v) = match k {
        0 => (i, j),
        1 => (3 - j, i),
        2 => (3 - i, 3 - j),
        _ => (j, 3 - i),
    };
    4 * v + u
}

fn feature<'a>(cage: &'a Cage, topo: &'a Topology) -> impl Fn(usize) -> bool + 'a {
    move |e: usize| {
        let (a, b) = topo.edges[e].ends;
        is_feature_edge(cage, topo, a, b)
    }
}

/// Whether `v` is a crease vertex: two feature edges, not a corner. Its
/// crease curve is smooth through it, whatever the two edge tangents'
/// angle says (the exact limit corner of a semi-sharp crease, `limit.rs`,
/// sits a little off the chord of the sharp rules' edge points).
fn is_crease(cage: &Cage, topo: &Topology, v: usize) -> bool {
    let features = topo.vertex_edges[v]
        .iter()
        .filter(|&&e| feature(cage, topo)(e))
        .count();
    features == 2 && cage.vertex_sharpness(v) < 1.0
}

/// The geometry's edge tangents g = 3·(E − C) of a sector's edges at `v`.
fn edge_tangents<V: Vector>(topo: &Topology, pts: &Points<V>, v: usize, edges: &[usize]) -> Vec<V> {
    let c = (pts.corner)(v);
    edges
        .iter()
        .map(|&e| ((pts.edge)(v, topo.edges[e].other(v)) - c.clone()) * 3.0)
        .collect()
}

/// The fit of a closed fan's tangents `g`.
fn decide_cyclic(g: &[DVec3]) -> Fit {
    let n = g.len();
    if n < 3 {
        return Fit::Own;
    }
    let [a, b] = harmonic(g, 2.0 * PI / n as f64);
    if a.cross(b).length() <= 1e-9 * a.length() * b.length() || a == DVec3::ZERO {
        Fit::Own
    } else {
        Fit::Cyclic
    }
}

/// The first Fourier harmonic (A, B) of `g` at angle step `theta`.
fn harmonic<V: Vector>(g: &[V], theta: f64) -> [V; 2] {
    let n = g.len() as f64;
    let (mut a, mut b) = (V::zero(), V::zero());
    for (k, gk) in g.iter().enumerate() {
        a = a + gk.clone() * (k as f64 * theta).cos();
        b = b + gk.clone() * (k as f64 * theta).sin();
    }
    [a * (2.0 / n), b * (2.0 / n)]
}

/// The fit of an open sector's tangents `g` (`g.len() − 1` faces); at a
/// `crease` vertex the two feature edges are made opposite, whatever their
/// angle: the crease curve is C¹ there. The angle says nothing at a crease
/// whose sharpness has not run out (a refined cage's crease of sharpness
/// s ≥ 1): its corner is the exact limit, sunk below the sharp rules' edge
/// points by a share of the edge that grows with each refinement step, so
/// both feature tangents lean outwards (219° apart on OpenSubdiv's
/// `catmark_chaikin0` at `isolate = 4`). Fitted by that angle, the sector's
/// plane held the crease and its outward diagonal, and the shading normal
/// stood at right angles to the surface's along the whole crease.
fn decide_open(g: &[DVec3], crease: bool) -> Fit {
    let m = g.len() - 1;
    if m < 2 {
        return Fit::Own;
    }
    let axis: DVec3 = g.windows(2).map(|w| w[0].cross(w[1])).sum();
    let (g0, gm) = (g[0], g[m]);
    if axis.length() == 0.0 || g0.length() == 0.0 || gm.length() == 0.0 {
        return Fit::Own;
    }
    let axis = axis.normalize();
    let mut phi = (g0.cross(gm).dot(axis)).atan2(g0.dot(gm));
    if phi <= 0.0 {
        phi += 2.0 * PI;
    }
    if crease || (phi - PI).abs() < 0.02 {
        let [a, b] = open_crease(g);
        if a.cross(b).length() <= 1e-9 * a.length() * b.length() {
            Fit::Own
        } else {
            Fit::Crease
        }
    } else if phi.sin().abs() >= 0.02 {
        Fit::Open { phi }
    } else {
        Fit::Own
    }
}

/// A crease sector's (A, B): A half the difference of the feature edges'
/// tangents, B the least-squares fit of the inner ones.
fn open_crease<V: Vector>(g: &[V]) -> [V; 2] {
    let m = g.len() - 1;
    let theta = PI / m as f64;
    let a = (g[0].clone() - g[m].clone()) * 0.5;
    let (mut num, mut den) = (V::zero(), 0.0);
    for (k, gk) in g.iter().enumerate().take(m).skip(1) {
        let (c, s) = ((k as f64 * theta).cos(), (k as f64 * theta).sin());
        num = num + (gk.clone() - a.clone() * c) * s;
        den += s * s;
    }
    [a, num * (1.0 / den)]
}

/// The tangents of a sector with edge tangents `g` by its `fit`
/// (linear in `g`).
fn fitted<V: Vector>(g: &[V], fit: Fit, cyclic: bool) -> Vec<V> {
    let n = g.len();
    let along = |a: &V, b: &V, theta: f64, k: usize| {
        a.clone() * (k as f64 * theta).cos() + b.clone() * (k as f64 * theta).sin()
    };
    match fit {
        Fit::Cyclic if cyclic => {
            let theta = 2.0 * PI / n as f64;
            let [a, b] = harmonic(g, theta);
            (0..n).map(|k| along(&a, &b, theta, k)).collect()
        }
        Fit::Crease => {
            let m = n - 1;
            let theta = PI / m as f64;
            let [a, b] = open_crease(g);
            let mut t: Vec<V> = (0..=m).map(|k| along(&a, &b, theta, k)).collect();
            t[0] = a.clone();
            t[m] = -a;
            t
        }
        Fit::Open { phi } => {
            let m = n - 1;
            let theta = phi / m as f64;
            let b = (g[m].clone() - g[0].clone() * phi.cos()) * (1.0 / phi.sin());
            let mut t: Vec<V> = (0..=m).map(|k| along(&g[0], &b, theta, k)).collect();
            t[0] = g[0].clone();
            t[m] = g[m].clone();
            t
        }
        _ => g.to_vec(),
    }
}

/// Corner tangents of every sector of every vertex, by (face, corner):
/// (along the incoming edge, along the outgoing edge), both pointing away
/// from the vertex.
fn corner_tangents<V: Vector>(
    cage: &Cage,
    topo: &Topology,
    pts: &Points<V>,
    decisions: &Decisions,
) -> HashMap<(usize, usize), (V, V)> {
    let mut out = HashMap::new();
    for v in 0..cage.positions.len() {
        let sectors = sharpness::sectors(topo, v, &feature(cage, topo));
        for (sector, &fit) in sectors.iter().zip(&decisions.fits[v]) {
            let g = edge_tangents(topo, pts, v, &sector.edges);
            let t = fitted(&g, fit, sector.cyclic);
            let n = sector.corners.len();
            for (i, &corner) in sector.corners.iter().enumerate() {
                let next = if sector.cyclic { (i + 1) % n } else { i + 1 };
                out.insert(corner, (t[i].clone(), t[next].clone()));
            }
        }
    }
    out
}

/// Decides every sector's fit and every shared smooth edge end's α from
/// the conversion `conv` of `cage` (see the module doc).
pub fn decide(cage: &Cage, topo: &Topology, conv: &Conversion) -> Decisions {
    in_f64(conv, |pts| decide_over(cage, topo, conv, pts))
}

/// The points of `conv` in f64, as the construction reads them, handed to
/// `f` (the f32 points widen exactly, so deciding and constructing over
/// them see the same values).
fn in_f64<R>(conv: &Conversion, f: impl FnOnce(&Points<'_, DVec3>) -> R) -> R {
    let corner = |v: usize| conv.corner[v].as_dvec3();
    let edge = |a: usize, b: usize| conv.edge_point[&(a, b)].as_dvec3();
    let slot = |p: usize, s: usize| conv.patches[p].pts[s].as_dvec3();
    let pts = Points {
        corner: &corner,
        edge: &edge,
        slot: &slot,
    };
    f(&pts)
}

/// [`decide`] over the points `pts` of `conv`.
fn decide_over(
    cage: &Cage,
    topo: &Topology,
    conv: &Conversion,
    pts: &Points<'_, DVec3>,
) -> Decisions {
    let mut decisions = Decisions::default();
    // (vertex, edge) → (fit, edges, cyclic) of the sector holding the edge.
    let mut sector_of: HashMap<(usize, usize), (Fit, usize, bool)> = HashMap::new();
    for v in 0..cage.positions.len() {
        let crease = is_crease(cage, topo, v);
        let mut fits = Vec::new();
        for sector in sharpness::sectors(topo, v, &feature(cage, topo)) {
            let g = edge_tangents(topo, pts, v, &sector.edges);
            let fit = if sector.cyclic {
                decide_cyclic(&g)
            } else {
                decide_open(&g, crease)
            };
            for &e in &sector.edges {
                sector_of.insert((v, e), (fit, sector.edges.len(), sector.cyclic));
            }
            fits.push(fit);
        }
        decisions.fits.push(fits);
    }
    // α: ± the cosine of the sector's angle step where it was fitted (what
    // the projection below gives there, exactly); the projection of the
    // geometry's own tangents where it was not.
    let corner_t = corner_tangents(cage, topo, pts, &decisions);
    for e in 0..topo.edges.len() {
        let Some(sides) = shared_smooth(cage, topo, conv, e) else {
            continue;
        };
        let [(f, k), (g, m)] = sides;
        for end in 0..2 {
            // End 0 is corner k of f (and corner m + 1 of g).
            let v = cage.faces[f][(k + end) % 4];
            let fitted = sector_of
                .get(&(v, e))
                .and_then(|&(fit, n, cyclic)| fit.theta(n, cyclic));
            let alpha = match fitted {
                // The along-edge tangent points away from end 0 and
                // towards end 1.
                Some(theta) if end == 0 => theta.cos(),
                Some(theta) => -theta.cos(),
                None => {
                    let (ta, t) = if end == 0 {
                        (corner_t[&(f, k)].0, corner_t[&(f, k)].1)
                    } else {
                        let c = corner_t[&(f, (k + 1) % 4)];
                        (c.1, -c.0)
                    };
                    let tb = if end == 0 {
                        corner_t[&(g, (m + 1) % 4)].1
                    } else {
                        corner_t[&(g, m)].0
                    };
                    let l = t.length_squared();
                    if l > 0.0 {
                        (ta + tb).dot(t) / (2.0 * l)
                    } else {
                        0.0
                    }
                }
            };
            decisions.alpha.insert((e, end), alpha);
        }
    }
    decisions
}

/// The two patch sides of edge `e` when it is a smooth edge between two
/// patches: ((face, corner), (face, corner)) as the edge's uses list them.
fn shared_smooth(
    cage: &Cage,
    topo: &Topology,
    conv: &Conversion,
    e: usize,
) -> Option<[(usize, usize); 2]> {
    let edge = &topo.edges[e];
    let [a, b] = edge.uses[..] else {
        return None;
    };
    let has_patch = |f: usize| conv.faces.binary_search(&f).is_ok();
    if !has_patch(a.0) || !has_patch(b.0) || is_feature_edge(cage, topo, edge.ends.0, edge.ends.1) {
        return None;
    }
    Some([a, b])
}

/// The tangent patches of every patch of `conv` (see the module doc), by
/// `decisions` ([`decide`]), over points of type `V`: 24 vectors per
/// patch, ∂u's 12 then ∂v's 12 in `ShadingPatch` order.
fn construct<V: Vector>(
    cage: &Cage,
    topo: &Topology,
    conv: &Conversion,
    pts: &Points<V>,
    decisions: &Decisions,
) -> Vec<[V; 24]> {
    let corner_t = corner_tangents(cage, topo, pts, decisions);
    let patch_of = conv.patch_of_face();

    let mut edges: Vec<Vec<EdgeTangents<V>>> = Vec::with_capacity(conv.patches.len());
    for (p, &f) in conv.faces.iter().enumerate() {
        let face = &cage.faces[f];
        let t = |k: usize| corner_t[&(f, k % 4)].clone();
        edges.push(
            (0..4)
                .map(|k| {
                    let (v0, v1) = (face[k], face[(k + 1) % 4]);
                    let mid = ((pts.edge)(v1, v0) - (pts.edge)(v0, v1)) * 3.0;
                    let geo = |i: usize| {
                        ((pts.slot)(p, rotated_slot(k, i, 1))
                            - (pts.slot)(p, rotated_slot(k, i, 0)))
                            * 3.0
                    };
                    EdgeTangents {
                        along: [t(k).1, mid, -t(k + 1).0],
                        inward: [t(k).0, geo(1), geo(2), t(k + 1).1],
                    }
                })
                .collect(),
        );
    }

    for e in 0..topo.edges.len() {
        let Some([(f, k), (g, m)]) = shared_smooth(cage, topo, conv, e) else {
            continue;
        };
        let (pa, pb) = (patch_of[&f], patch_of[&g]);
        let along = edges[pa][k].along.clone();
        let xa = edges[pa][k].inward.clone();
        let mut xb = edges[pb][m].inward.clone();
        xb.reverse();
        let (a0, a1) = (decisions.alpha[&(e, 0)], decisions.alpha[&(e, 1)]);
        let at1 = (along[0].clone() * a1 + along[1].clone() * (2.0 * a0)) * (1.0 / 3.0);
        let at2 = (along[1].clone() * (2.0 * a1) + along[2].clone() * a0) * (1.0 / 3.0);
        let mean1 = (xa[1].clone() - xb[1].clone()) * 0.5;
        let mean2 = (xa[2].clone() - xb[2].clone()) * 0.5;
        edges[pa][k].inward[1] = mean1.clone() + at1.clone();
        edges[pa][k].inward[2] = mean2.clone() + at2.clone();
        edges[pb][m].inward[2] = -mean1 + at1;
        edges[pb][m].inward[1] = -mean2 + at2;
    }

    edges
        .into_iter()
        .enumerate()
        .map(|(p, e)| assemble(p, pts, &e))
        .collect()
}

/// Writes the four edges' tangents over the geometry's own derivative
/// nets: `du[3j + i]` (i < 3 along u, j < 4 along v) then `dv[4j + i]`
/// (i < 4, j < 3), 24 vectors.
fn assemble<V: Vector>(p: usize, pts: &Points<V>, e: &[EdgeTangents<V>]) -> [V; 24] {
    let at = |i: usize, j: usize| (pts.slot)(p, 4 * j + i);
    let mut du: Vec<V> = (0..12)
        .map(|n| {
            let (i, j) = (n % 3, n / 3);
            (at(i + 1, j) - at(i, j)) * 3.0
        })
        .collect();
    let mut dv: Vec<V> = (0..12)
        .map(|n| {
            let (i, j) = (n % 4, n / 4);
            (at(i, j + 1) - at(i, j)) * 3.0
        })
        .collect();
    for i in 0..3 {
        du[i] = e[0].along[i].clone();
        dv[4 * i + 3] = e[1].along[i].clone();
        du[9 + (2 - i)] = -e[2].along[i].clone();
        dv[4 * (2 - i)] = -e[3].along[i].clone();
    }
    for i in 0..4 {
        dv[i] = e[0].inward[i].clone();
        du[3 * i + 2] = -e[1].inward[i].clone();
        dv[8 + (3 - i)] = -e[2].inward[i].clone();
        du[3 * (3 - i)] = e[3].inward[i].clone();
    }
    du.extend(dv);
    let mut it = du.into_iter();
    std::array::from_fn(|_| it.next().expect("24 vectors"))
}

/// The tangent patches of every patch of `conv` (see the module doc),
/// computed in f64 from its points and rounded once.
pub fn tangent_patches(cage: &Cage, topo: &Topology, conv: &Conversion) -> Vec<ShadingPatch> {
    let decisions = decide(cage, topo, conv);
    in_f64(conv, |pts| construct(cage, topo, conv, pts, &decisions))
        .iter()
        .map(|v| {
            let round = |d: DVec3| d.as_vec3() + Vec3::ZERO;
            ShadingPatch {
                du: std::array::from_fn(|n| round(v[n])),
                dv: std::array::from_fn(|n| round(v[12 + n])),
            }
        })
        .collect()
}

/// The tangent patches of every patch of `conv` as combinations of named
/// points (`corner(v)`, `edge(near, far)`, `slot(patch, slot)` name them),
/// by `decisions`: what [`tangent_patches`] computes, as a recipe that
/// holds for every pose of the cage.
pub fn recipe(
    cage: &Cage,
    topo: &Topology,
    conv: &Conversion,
    decisions: &Decisions,
    corner: &dyn Fn(usize) -> u32,
    edge: &dyn Fn(usize, usize) -> u32,
    slot: &dyn Fn(usize, usize) -> u32,
) -> Vec<[Comb; 24]> {
    let c = |v: usize| Comb::of(corner(v));
    let e = |a: usize, b: usize| Comb::of(edge(a, b));
    let s = |p: usize, k: usize| Comb::of(slot(p, k));
    let pts = Points {
        corner: &c,
        edge: &e,
        slot: &s,
    };
    construct(cage, topo, conv, &pts, decisions)
}
