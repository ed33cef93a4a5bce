//! One global Catmull–Clark step with OpenSubdiv's rules (`Sdc` with the
//! cage's creasing method and triangle rule): used to make every face of a
//! cage a quad, and repeated for isolation (`isolate.rs`).
//!
//! - Face point: the face's centroid (a repeated vertex counts twice).
//! - Edge point: the midpoint for a sharp edge (sharpness ≥ 1, boundary or
//!   non-manifold, all infinitely sharp by then); for a smooth manifold edge
//!   the mean of its ends and the two face points, or, under `t
//!   smoothtriangles 0/0/1 smooth`, next to a triangle OpenSubdiv's weights
//!   (each triangle's face point 0.47 instead of 0.25, averaged over the two
//!   faces, the rest on the two ends); a sharpness s below 1 blends the two,
//!   s of the way to the midpoint.
//! - Vertex point by the vertex rule (`sharpness.rs`): smooth and dart
//!   (Q + 2R + (n−3)v)/n with Q the mean of the face points and R the mean
//!   of the edge midpoints around v; crease (a + 6v + b)/8 from the two sharp
//!   edges' far ends; corner v. When the rule of the refined vertex is
//!   smoother than this one (a semi-sharp feature runs out), the two are
//!   blended with OpenSubdiv's transition weight: the mean sharpness of the
//!   features that run out (vertex and edges whose children are smooth), at
//!   most 1.
//! - Sharpness of a vertex's child: s − 1 (0 below 1), infinite stays
//!   infinite. Of each half of an edge: the same under uniform creasing;
//!   under Chaikin's (`t creasemethod 0/0/1 chaikin`) the half at vertex v
//!   gets ¾ s + ¼ (the mean of the other semi-sharp edges at v) − 1 where v
//!   has two or more semi-sharp edges (OpenSubdiv's
//!   `Crease::SubdivideEdgeSharpnessAtVertex`, in f32 as there). Edges inside
//!   a face are smooth.
//! - The sub-quads of a hole are holes.
//!
//! Sub-quad k of face F is (v_k', e(v_k, v_k+1), f_F, e(v_k−1, v_k)), so
//! orientation is kept. New vertices: vertex points, then edge points (in
//! edge order), then face points. The refined cage names its edges
//! ([`Cage::face_edges`]): each edge's two halves (non-manifold if it was),
//! then one edge per face corner from its edge point to the face point.

use std::path::Path;
use std::sync::OnceLock;

use glam::DVec3;

use super::mesh::{Cage, CageEdge, Topology};
use super::sharpness::{Config, VertexRule, INFINITE};
use crate::input::SceneError;

/// Face-parameter coordinates of a quad's corners 0..4.
pub const QUAD_UV: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

/// `corners_uv` of sub-quad `k` of a quad face, in the face's parameters.
pub fn sub_quad_uv(k: usize) -> [[f32; 2]; 4] {
    let c = |i: usize| QUAD_UV[i % 4];
    let mid = |a: [f32; 2], b: [f32; 2]| [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5];
    [c(k), mid(c(k), c(k + 1)), [0.5, 0.5], mid(c(k + 3), c(k))]
}

/// Where each face of a refined cage came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubFace {
    /// The face of the coarse cage.
    pub face: usize,
    /// Which corner of it the sub-quad sits at.
    pub corner: usize,
}

/// The sharpness of a child feature under uniform creasing: one step
/// less, infinite kept.
fn child_sharpness(s: f64) -> f64 {
    if s >= INFINITE {
        INFINITE
    } else if s <= 1.0 {
        0.0
    } else {
        s - 1.0
    }
}

/// The sharpness of the half of edge `e` at its vertex `v`.
fn child_edge_sharpness(cage: &Cage, topo: &Topology, e: usize, v: usize) -> f64 {
    let (a, b) = topo.edges[e].ends;
    let s = cage.edge_sharpness(a, b);
    let around = &topo.vertex_edges[v];
    if !cage.scheme.chaikin || around.len() < 2 || s <= 0.0 || s >= INFINITE {
        return child_sharpness(s);
    }
    // OpenSubdiv computes this in f32; so does this, to take the same
    // branch where a half runs out exactly.
    let semi: Vec<f32> = around
        .iter()
        .map(|&i| {
            let (p, q) = topo.edges[i].ends;
            cage.edge_sharpness(p, q) as f32
        })
        .filter(|&x| x > 0.0 && x < INFINITE as f32)
        .collect();
    let s = s as f32;
    let mut t = s;
    if semi.len() > 1 {
        let sum: f32 = semi.iter().sum();
        let others = (sum - s) / (semi.len() - 1) as f32;
        t = 0.75 * s + 0.25 * others;
    }
    let t = t - 1.0;
    if t > 0.0 {
        f64::from(t)
    } else {
        0.0
    }
}

/// The vertex rule of `v` and the far ends of its sharp edges (in edge
/// order), with every feature of sharpness above 0 counted as sharp, edge
/// sharpness given per edge id by `edge_sharp` and the vertex's own by
/// `vertex_sharp`.
fn rule_at(
    topo: &Topology,
    v: usize,
    edge_sharp: &dyn Fn(usize) -> f64,
    vertex_sharp: f64,
) -> (VertexRule, Vec<usize>) {
    let ends: Vec<usize> = topo.vertex_edges[v]
        .iter()
        .filter(|&&e| Config::Sharp.sharp(edge_sharp(e)))
        .map(|&e| topo.edges[e].other(v))
        .collect();
    let corner = Config::Sharp.sharp(vertex_sharp);
    (VertexRule::of(corner, ends.len()), ends)
}

/// One global Catmull–Clark step (see the module doc).
pub fn refine(cage: &Cage, topo: &Topology) -> (Cage, Vec<SubFace>) {
    let nv = cage.positions.len();
    let ne = topo.edges.len();
    let face_points: Vec<DVec3> = cage
        .faces
        .iter()
        .map(|face| {
            face.iter().fold(DVec3::ZERO, |s, &v| s + cage.positions[v]) / face.len() as f64
        })
        .collect();
    let edge_points: Vec<DVec3> = (0..ne)
        .map(|e| edge_point(cage, topo, e, &face_points))
        .collect();
    let vertex_points: Vec<DVec3> = (0..nv)
        .map(|v| vertex_point(cage, topo, v, &face_points))
        .collect();

    let face_base = nv + ne;
    let mut out = Cage {
        positions: vertex_points,
        scheme: cage.scheme,
        ..Cage::default()
    };
    out.positions.extend(edge_points);
    out.positions.extend(face_points);
    // The two halves of every edge: half j joins end j to the edge point.
    for (e, edge) in topo.edges.iter().enumerate() {
        let ends = [edge.ends.0, edge.ends.1];
        for end in ends {
            out.edge_list.push(CageEdge {
                ends: (end, nv + e),
                non_manifold: edge.non_manifold,
            });
            let child = child_edge_sharpness(cage, topo, e, end);
            if child > 0.0 {
                let key = (end.min(nv + e), end.max(nv + e));
                out.edge_sharpness.insert(key, child);
            }
        }
    }
    for (&v, &s) in &cage.vertex_sharpness {
        let child = child_sharpness(s);
        if child > 0.0 {
            out.vertex_sharpness.insert(v, child);
        }
    }
    let mut origin = Vec::new();
    for (f, face) in cage.faces.iter().enumerate() {
        let m = face.len();
        // One edge per corner k, from the edge point of edge k inwards.
        let inner = out.edge_list.len();
        for &e in &topo.face_edges[f] {
            out.edge_list.push(CageEdge {
                ends: (nv + e, face_base + f),
                non_manifold: false,
            });
        }
        for (k, &v) in face.iter().enumerate() {
            let prev = (k + m - 1) % m;
            let (e_k, e_prev) = (topo.face_edges[f][k], topo.face_edges[f][prev]);
            let start = topo.start_end(cage, (f, k));
            let end_prev = 1 - topo.start_end(cage, (f, prev));
            out.faces
                .push(vec![v, nv + e_k, face_base + f, nv + e_prev]);
            out.face_edges.push(vec![
                2 * e_k + start,
                inner + k,
                inner + prev,
                2 * e_prev + end_prev,
            ]);
            out.face_lines.push(cage.line_of(f));
            origin.push(SubFace { face: f, corner: k });
        }
    }
    if cage.holes.iter().any(|&h| h) {
        out.holes = origin.iter().map(|s| cage.is_hole(s.face)).collect();
    }
    (out, origin)
}

/// The edge point of edge `e` (see the module doc).
fn edge_point(cage: &Cage, topo: &Topology, e: usize, face_points: &[DVec3]) -> DVec3 {
    let p = &cage.positions;
    let edge = &topo.edges[e];
    let (a, b) = edge.ends;
    let mid = (p[a] + p[b]) * 0.5;
    let s = cage.edge_sharpness(a, b);
    if s >= 1.0 || !edge.is_manifold() {
        return mid;
    }
    let (f, g) = (edge.uses[0].0, edge.uses[1].0);
    let tri = |f: usize| cage.faces[f].len() == 3;
    let smooth = if cage.scheme.smooth_triangles && (tri(f) || tri(g)) {
        // OpenSubdiv's `assignSmoothMaskForEdge` with TRI_SUB_SMOOTH.
        let weight = |f: usize| if tri(f) { 0.470 } else { 0.25 };
        let fw = 0.5 * (weight(f) + weight(g));
        let vw = 0.5 * (1.0 - 2.0 * fw);
        (p[a] + p[b]) * vw + (face_points[f] + face_points[g]) * fw
    } else {
        (p[a] + p[b] + face_points[f] + face_points[g]) * 0.25
    };
    if s > 0.0 {
        smooth + (mid - smooth) * s
    } else {
        smooth
    }
}

/// The vertex point of `v` (see the module doc).
fn vertex_point(cage: &Cage, topo: &Topology, v: usize, face_points: &[DVec3]) -> DVec3 {
    let p = &cage.positions;
    let parent_sharp = |e: usize| {
        let (a, b) = topo.edges[e].ends;
        cage.edge_sharpness(a, b)
    };
    let (rule, ends) = rule_at(topo, v, &parent_sharp, cage.vertex_sharpness(v));
    let point = |rule: VertexRule, ends: &[usize]| match rule {
        VertexRule::Corner => p[v],
        VertexRule::Crease => (p[ends[0]] + p[v] * 6.0 + p[ends[1]]) * 0.125,
        VertexRule::Smooth | VertexRule::Dart => smooth_vertex(cage, topo, v, face_points),
    };
    let parent = point(rule, &ends);
    let child_sharp = |e: usize| child_edge_sharpness(cage, topo, e, v);
    let child_vertex = child_sharpness(cage.vertex_sharpness(v));
    let (child_rule, child_ends) = rule_at(topo, v, &child_sharp, child_vertex);
    if child_rule == rule || topo.fans[v].is_empty() {
        return parent;
    }
    let w = transition_weight(cage, topo, v, &child_sharp);
    let child = point(child_rule, &child_ends);
    child + (parent - child) * w
}

/// The smooth vertex point (Q + 2R + (n−3)v)/n over the one closed fan a
/// smooth or dart vertex has after `sharpness::resolve`.
fn smooth_vertex(cage: &Cage, topo: &Topology, v: usize, face_points: &[DVec3]) -> DVec3 {
    let p = &cage.positions;
    let Some(fan) = topo.fans[v].first() else {
        return p[v];
    };
    let n = topo.valence(v) as f64;
    let mut q = DVec3::ZERO;
    let mut r = DVec3::ZERO;
    for &(f, k) in &fan.corners {
        let face = &cage.faces[f];
        q += face_points[f];
        r += (p[v] + p[face[(k + 1) % face.len()]]) * 0.5;
    }
    (q / n + r / n * 2.0 + p[v] * (n - 3.0)) / n
}

/// OpenSubdiv's weight of the sharper rule where a semi-sharp feature runs
/// out (`Crease::ComputeFractionalWeightAtVertex`): the mean of the
/// sharpness of the vertex (if it runs out) and of the incident edges whose
/// halves at `v` are smooth, at most 1.
fn transition_weight(
    cage: &Cage,
    topo: &Topology,
    v: usize,
    child_sharp: &dyn Fn(usize) -> f64,
) -> f64 {
    let mut sum = 0.0;
    let mut n = 0usize;
    let own = cage.vertex_sharpness(v);
    if own > 0.0 && child_sharpness(own) == 0.0 {
        sum += own;
        n += 1;
    }
    for &e in &topo.vertex_edges[v] {
        let (a, b) = topo.edges[e].ends;
        let s = cage.edge_sharpness(a, b);
        if s > 0.0 && child_sharp(e) <= 0.0 {
            sum += s;
            n += 1;
        }
    }
    if n == 0 {
        0.0
    } else {
        (sum / n as f64).min(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn cube() -> Cage {
        crate::cage::mesh::unit_cube()
    }

    /// The kept topologies give a moved cage the refinement it gets
    /// without them: the same faces and the same positions, bit for bit.
    #[test]
    fn kept_topologies_refine_a_moved_cage_as_from_scratch() {
        let path = Path::new("cube");
        let rest = cube();
        let topo = Topology::build(&rest, path).unwrap();
        let kept = StepTopologies::default();
        let mut steps = 0;
        kept.refine(rest.clone(), &topo, 2, path, |_| steps += 1)
            .unwrap();
        assert_eq!(steps, 2);
        let mut moved = rest;
        moved.positions[3] += DVec3::new(0.25, -0.5, 0.125);
        let (fine, fine_topo) = kept.refine(moved.clone(), &topo, 2, path, |_| {}).unwrap();
        let (once, _) = refine(&moved, &topo);
        let (twice, _) = refine(&once, &Topology::build(&once, path).unwrap());
        assert_eq!(fine.faces, twice.faces);
        assert_eq!(fine.positions, twice.positions);
        let ends = |t: &Topology| t.edges.iter().map(|e| e.ends).collect::<Vec<_>>();
        assert_eq!(
            ends(fine_topo),
            ends(&Topology::build(&twice, path).unwrap())
        );
    }

    #[test]
    fn refine_keeps_the_cube_closed_and_quad() {
        let c = cube();
        let topo = Topology::build(&c, Path::new("cube")).unwrap();
        let (r, origin) = refine(&c, &topo);
        assert_eq!(r.faces.len(), 24);
        assert_eq!(r.positions.len(), 8 + 12 + 6);
        assert_eq!(origin[5], SubFace { face: 1, corner: 1 });
        let rt = Topology::build(&r, Path::new("cube")).unwrap();
        assert_eq!(rt.boundary_edges, 0);
        // Known Catmull–Clark result for the unit cube: corners move to
        // (Q + 2R + 0·v)/3.
        let v0 = r.positions[0];
        let q = (DVec3::new(0.5, 0.5, 0.0) + DVec3::new(0.5, 0.0, 0.5) + DVec3::new(0.0, 0.5, 0.5))
            / 3.0;
        let rr =
            (DVec3::new(0.5, 0.0, 0.0) + DVec3::new(0.0, 0.5, 0.0) + DVec3::new(0.0, 0.0, 0.5))
                / 3.0;
        assert!((v0 - (q + rr * 2.0) / 3.0).length() < 1e-15);
    }

    #[test]
    fn sharp_and_semi_sharp_edges_follow_the_crease_rules() {
        let mut c = cube();
        // Edges (0,1), (1,3), (3,2), (2,0) of the bottom face infinitely
        // sharp: vertex 0 has two sharp edges (a crease), and the bottom
        // face's edge points are midpoints.
        for (a, b) in [(0, 1), (1, 3), (2, 3), (0, 2)] {
            c.edge_sharpness.insert((a, b), INFINITE);
        }
        c.edge_sharpness.insert((4, 5), 0.5);
        c.edge_sharpness.insert((6, 7), 3.0);
        let topo = Topology::build(&c, Path::new("cube")).unwrap();
        let (r, _) = refine(&c, &topo);
        let p = &c.positions;
        assert_eq!(r.positions[0], (p[1] + p[0] * 6.0 + p[2]) * 0.125);
        let e01 = 8 + topo.edge_id(0, 1).unwrap();
        assert_eq!(r.positions[e01], (p[0] + p[1]) * 0.5);
        // Children of the sharp edges stay sharp, the 3.0 crease drops to
        // 2.0 and the 0.5 one is gone.
        assert_eq!(r.edge_sharpness(0, e01), INFINITE);
        let e67 = 8 + topo.edge_id(6, 7).unwrap();
        assert_eq!(r.edge_sharpness(6, e67), 2.0);
        let e45 = 8 + topo.edge_id(4, 5).unwrap();
        assert_eq!(r.edge_sharpness(4, e45), 0.0);
        // The 0.5 edge point is half way between smooth and the midpoint.
        let f = |face: usize| c.faces[face].iter().map(|&v| p[v]).sum::<DVec3>() / 4.0;
        let (g, h) = (topo.edge(4, 5).uses[0].0, topo.edge(4, 5).uses[1].0);
        let smooth = (p[4] + p[5] + f(g) + f(h)) * 0.25;
        let mid = (p[4] + p[5]) * 0.5;
        assert!((r.positions[e45] - (smooth + mid) * 0.5).length() < 1e-15);
    }
}

/// The topologies of a run of refinement steps, kept from the first run
/// for the later ones on the same faces. A topology depends on the faces
/// alone, and the stencil probes (`stencil.rs`) convert the same cage
/// again and again with other positions: building the topology of every
/// step of every probe was a quarter of an isolated import's time. One
/// value serves one starting topology and one number of steps.
#[derive(Default)]
pub struct StepTopologies(OnceLock<Vec<Topology>>);

impl StepTopologies {
    /// Refines `cage` (adjacency `topo`) `steps` times, handing each step's
    /// sub-faces to `each`; returns the refined cage and its topology
    /// (`topo` itself after no step).
    pub fn refine<'a>(
        &'a self,
        cage: Cage,
        topo: &'a Topology,
        steps: u32,
        path: &Path,
        mut each: impl FnMut(Vec<SubFace>),
    ) -> Result<(Cage, &'a Topology), SceneError> {
        let steps = steps as usize;
        let known = self.0.get();
        assert!(
            known.is_none_or(|k| k.len() == steps),
            "StepTopologies reused for another number of steps"
        );
        let mut built = Vec::new();
        let mut fine = cage;
        for step in 0..steps {
            let current = match (step, known) {
                (0, _) => topo,
                (_, Some(k)) => &k[step - 1],
                (_, None) => &built[step - 1],
            };
            let (next, subs) = refine(&fine, current);
            if known.is_none() {
                built.push(Topology::build(&next, path)?);
            }
            each(subs);
            fine = next;
        }
        if steps == 0 {
            return Ok((fine, topo));
        }
        // Another run may have set the same topologies meanwhile.
        let all = self.0.get_or_init(|| built);
        Ok((fine, &all[steps - 1]))
    }
}
