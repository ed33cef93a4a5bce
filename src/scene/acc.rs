//! All-quad control cage → one bicubic Bézier patch per face, by Loop and
//! Schaefer's approximate Catmull–Clark surfaces ("ACC", 2008) with this
//! project's boundary rules. The rules are listed in `obj.rs`'s module doc;
//! this module is their implementation.
//!
//! Crack-freeness (DESIGN invariant 4) rests on one discipline: every point
//! that lies on a patch boundary — the corner points and the two edge points
//! near each end of every edge — is computed exactly once, rounded to f32
//! once, stored, and copied into every patch that uses it. Nothing on a
//! boundary is ever recomputed per face, so neighbours get the same bits.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec3, Vec3};

use super::cage::{face_edges, Cage, Topology};
use super::SceneError;
use crate::patch::bezier::BezierPatch;

/// Rounds once to f32; +0.0 replaces -0.0.
fn round(p: DVec3) -> Vec3 {
    Vec3::new(p.x as f32, p.y as f32, p.z as f32) + Vec3::ZERO
}

/// Converts an all-quad cage (validated into `topo`) to one patch per face,
/// in face order. Face (v0, v1, v2, v3) gets its parameter origin at v0,
/// u towards v1, v towards v3.
pub fn convert(cage: &Cage, topo: &Topology, path: &Path) -> Result<Vec<BezierPatch>, SceneError> {
    let p = &cage.positions;
    if let Some(f) = cage.faces.iter().position(|face| face.len() != 4) {
        return Err(SceneError::invalid(
            path,
            format!("internal: face {} is not a quad after refinement", f + 1),
        ));
    }

    // Interior point of each face near each corner k (kept in f64: they are
    // private to the face, and edge points are averaged from them).
    let inner: Vec<[DVec3; 4]> = cage
        .faces
        .iter()
        .map(|face| {
            std::array::from_fn(|k| {
                let v = face[k];
                let (ea, eb, opp) = (face[(k + 3) % 4], face[(k + 1) % 4], face[(k + 2) % 4]);
                let fan = &topo.fans[v];
                let n = if fan.boundary.is_some() {
                    4.0
                } else {
                    fan.valence as f64
                };
                (p[v] * n + p[ea] * 2.0 + p[eb] * 2.0 + p[opp]) / (n + 5.0)
            })
        })
        .collect();

    // Corner points, one per vertex.
    let corner: Vec<Vec3> = (0..p.len())
        .map(|v| {
            let fan = &topo.fans[v];
            match fan.boundary {
                _ if fan.corners.is_empty() => round(p[v]),
                Some(_) if fan.corners.len() == 1 => round(p[v]),
                Some((a, b)) => round((p[a] + p[v] * 4.0 + p[b]) / 6.0),
                None => {
                    let n = fan.valence as f64;
                    let (mut edge_sum, mut diag_sum) = (DVec3::ZERO, DVec3::ZERO);
                    for &(f, k) in &fan.corners {
                        let face = &cage.faces[f];
                        edge_sum += p[face[(k + 1) % 4]];
                        diag_sum += p[face[(k + 2) % 4]];
                    }
                    round((p[v] * (n * n) + edge_sum * 4.0 + diag_sum) / (n * (n + 5.0)))
                }
            }
        })
        .collect();

    // Edge points, keyed (near end, far end), one per edge end.
    let mut edge_point: HashMap<(usize, usize), Vec3> = HashMap::new();
    for face in &cage.faces {
        for (a, b) in face_edges(face) {
            if edge_point.contains_key(&(a, b)) {
                continue;
            }
            for (near, far) in [(a, b), (b, a)] {
                let value = match (topo.half_edge(near, far), topo.half_edge(far, near)) {
                    (Some((f, k)), Some((g, m))) => {
                        // `near` is corner k of f and corner m+1 of g.
                        (inner[f][k] + inner[g][(m + 1) % 4]) * 0.5
                    }
                    _ => (p[near] * 2.0 + p[far]) / 3.0,
                };
                edge_point.insert((near, far), round(value));
            }
        }
    }

    let mut patches = Vec::with_capacity(cage.faces.len());
    for (f, face) in cage.faces.iter().enumerate() {
        let [v0, v1, v2, v3] = [face[0], face[1], face[2], face[3]];
        let e = |a: usize, b: usize| edge_point[&(a, b)];
        let i = |k: usize| round(inner[f][k]);
        #[rustfmt::skip]
        let pts = [
            corner[v0], e(v0, v1), e(v1, v0), corner[v1],
            e(v0, v3),  i(0),      i(1),      e(v1, v2),
            e(v3, v0),  i(3),      i(2),      e(v2, v1),
            corner[v3], e(v3, v2), e(v2, v3), corner[v2],
        ];
        let patch = BezierPatch { pts }.canonical_zeros();
        if !patch.is_finite() {
            let msg = "the patch of this face has a non-finite control point (coordinates too large for f32?)";
            return Err(match cage.face_lines.get(f).copied().flatten() {
                Some(line) => SceneError::at(path, line, msg),
                None => SceneError::invalid(path, format!("face {}: {msg}", f + 1)),
            });
        }
        patches.push(patch);
    }
    Ok(patches)
}
