//! Exact limit positions of cage vertices whose neighbourhood no closed-form
//! mask covers: semi-sharp vertices and creases (sharp for some steps,
//! then smooth), darts (a crease ending at the vertex) and smooth vertices
//! of valence 2.
//!
//! Catmull–Clark maps a vertex's one-ring (the faces around it) to the next
//! level's one-ring (the sub-faces at the vertex) by its rules alone, so
//! refining the ring again and again (`refine.rs`, with the cage's own
//! creasing and its semi-sharp decrements and transitions) shrinks it onto
//! the limit point. OpenSubdiv's limit masks are exact only where every
//! feature at the vertex is infinitely sharp or absent and a smooth vertex
//! has valence 3 or more; elsewhere (its smooth mask applied at a dart) they
//! miss by the refinement's remainder: 8.6e-4 of the model at level 2 on
//! `catmark_inf_crease0`.

use std::path::Path;

use glam::DVec3;

use super::mesh::{Cage, Topology};
use super::refine::refine;
use super::sharpness;

/// Refinement steps of the ring: it shrinks by the subdominant eigenvalue
/// per step (at most about 0.7 for the valences met, 0.5 or less once a
/// semi-sharp feature has run out), so 50 steps leave less than 1e-7 of the
/// ring's size, below f32 rounding of any model.
const STEPS: usize = 50;

/// Whether `v`'s limit needs [`limit_position`]: a semi-sharp feature at
/// `v`, a dart, or a smooth vertex of valence 2 (one closed fan of two).
pub fn needs_iteration(cage: &Cage, topo: &Topology, v: usize) -> bool {
    if topo.is_non_manifold_vertex(v) || topo.fans[v].is_empty() {
        return false;
    }
    if sharpness::has_semi_sharp(cage, topo, v) {
        return true;
    }
    let sharp = topo.vertex_edges[v]
        .iter()
        .filter(|&&e| {
            let (a, b) = topo.edges[e].ends;
            cage.edge_sharpness(a, b) > 0.0
        })
        .count();
    let smooth = cage.vertex_sharpness(v) <= 0.0;
    smooth && (sharp == 1 || (sharp == 0 && topo.face_count(v) == 2))
}

/// The limit position of manifold vertex `v` by refining its one-ring (see
/// the module doc); `None` for a non-manifold vertex.
pub fn limit_position(cage: &Cage, topo: &Topology, v: usize) -> Option<DVec3> {
    if topo.is_non_manifold_vertex(v) {
        return None;
    }
    let path = Path::new("one-ring");
    let faces: Vec<usize> = ring_faces(cage, v);
    let (mut ring, map) = cage.extract(&faces);
    let mut at = map[v]?;
    for _ in 0..STEPS {
        let ring_topo = Topology::build(&ring, path).ok()?;
        // Once the semi-sharp features have run out, a closed form is exact.
        if !needs_iteration(&ring, &ring_topo, at) {
            return closed_form(&ring, &ring_topo, at);
        }
        let (fine, _) = refine(&ring, &ring_topo);
        // The vertex point keeps the vertex's index.
        let next = ring_faces(&fine, at);
        let (sub, map) = fine.extract(&next);
        at = map[at]?;
        ring = sub;
    }
    Some(ring.positions[at])
}

/// OpenSubdiv's limit masks where they are exact: a corner stays, an
/// (infinitely sharp) crease vertex is (a + 4v + b)/6, a smooth vertex of
/// valence n ≥ 3 is (n²·v + 4·Σ e + Σ d)/(n(n + 5)) over its quads.
fn closed_form(cage: &Cage, topo: &Topology, v: usize) -> Option<DVec3> {
    let p = &cage.positions;
    let sharp: Vec<usize> = topo.vertex_edges[v]
        .iter()
        .filter(|&&e| {
            let (a, b) = topo.edges[e].ends;
            cage.edge_sharpness(a, b) > 0.0
        })
        .map(|&e| topo.edges[e].other(v))
        .collect();
    if cage.vertex_sharpness(v) > 0.0 || sharp.len() > 2 {
        return Some(p[v]);
    }
    if let [a, b] = sharp[..] {
        return Some((p[a] + p[v] * 4.0 + p[b]) / 6.0);
    }
    let [fan] = &topo.fans[v][..] else {
        return None;
    };
    let n = fan.corners.len() as f64;
    let (mut e, mut d) = (DVec3::ZERO, DVec3::ZERO);
    for &(f, k) in &fan.corners {
        let face = &cage.faces[f];
        if face.len() != 4 {
            return None;
        }
        e += p[face[(k + 1) % 4]];
        d += p[face[(k + 2) % 4]];
    }
    Some((p[v] * (n * n) + e * 4.0 + d) / (n * (n + 5.0)))
}

/// The faces that use `v`, in order.
fn ring_faces(cage: &Cage, v: usize) -> Vec<usize> {
    (0..cage.faces.len())
        .filter(|&f| cage.faces[f].contains(&v))
        .collect()
}
