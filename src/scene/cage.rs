//! Polygonal control cages: validation into a half-edge adjacency, and one
//! global Catmull–Clark refinement step (used to make every face a quad).
//!
//! A cage is accepted when it is an oriented 2-manifold, possibly with
//! boundary: every face has at least three distinct vertices, every edge
//! belongs to one or two faces, two faces sharing an edge traverse it in
//! opposite directions, and the faces around every vertex form a single fan
//! (a disc, or a half-disc at the boundary). Everything else is refused with
//! the source line of a face involved, where the cage came from a file.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::SceneError;

/// A polygonal control cage. Positions are f64 so that a refined cage is not
/// rounded before the patches are computed from it.
#[derive(Clone, Debug, Default)]
pub struct Cage {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Faces as vertex indices, in order (counter-clockwise seen from outside).
    pub faces: Vec<Vec<usize>>,
    /// Source line (1-based) of each face, for error messages; `None` when
    /// the face has no line of its own.
    pub face_lines: Vec<Option<usize>>,
}

/// The faces around one vertex.
#[derive(Clone, Debug, Default)]
pub struct Fan {
    /// Incident (face, corner) pairs in rotation order: each next face lies
    /// across the outgoing edge `corner → corner + 1` of the one before. At a
    /// boundary vertex the first has the boundary as its incoming edge and the
    /// last as its outgoing edge.
    pub corners: Vec<(usize, usize)>,
    /// Number of incident edges.
    pub valence: usize,
    /// For a boundary vertex, its two neighbours along the boundary:
    /// (start of the incoming boundary edge, end of the outgoing one).
    pub boundary: Option<(usize, usize)>,
}

/// Half-edge adjacency of a validated cage.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Directed edge (a, b) → (face, corner of a in that face).
    half_edges: HashMap<(usize, usize), (usize, usize)>,
    /// One fan per vertex (empty for vertices no face uses).
    pub fans: Vec<Fan>,
    /// Number of edges with a single face.
    pub boundary_edges: usize,
}

impl Topology {
    /// The (face, corner) whose outgoing edge runs from `a` to `b`, if any.
    pub fn half_edge(&self, a: usize, b: usize) -> Option<(usize, usize)> {
        self.half_edges.get(&(a, b)).copied()
    }

    /// Validates `cage` and builds its adjacency. `path` only names the
    /// source in errors.
    pub fn build(cage: &Cage, path: &Path) -> Result<Topology, SceneError> {
        let fail = |face: usize, msg: String| match cage.face_lines.get(face).copied().flatten() {
            Some(line) => SceneError::at(path, line, msg),
            None => SceneError::invalid(path, format!("face {}: {msg}", face + 1)),
        };
        let nv = cage.positions.len();
        if cage.faces.is_empty() {
            return Err(SceneError::invalid(path, "the cage has no faces"));
        }
        if let Some(i) = cage.positions.iter().position(|p| !p.is_finite()) {
            return Err(SceneError::invalid(
                path,
                format!("vertex {} has a NaN or infinite coordinate", i + 1),
            ));
        }

        for (f, face) in cage.faces.iter().enumerate() {
            if face.len() < 3 {
                return Err(fail(
                    f,
                    format!(
                        "a face needs at least 3 vertices, this one has {}",
                        face.len()
                    ),
                ));
            }
            if let Some(&v) = face.iter().find(|&&v| v >= nv) {
                return Err(fail(f, format!("vertex index {} out of range", v + 1)));
            }
            for (k, &v) in face.iter().enumerate() {
                if face[k + 1..].contains(&v) {
                    return Err(fail(
                        f,
                        format!(
                            "degenerate face: vertex at {} appears twice",
                            show(cage.positions[v])
                        ),
                    ));
                }
            }
        }

        // Undirected use counts first, so that an edge shared by three faces
        // is named as such rather than as an orientation problem.
        let mut uses: HashMap<(usize, usize), usize> = HashMap::new();
        for (f, face) in cage.faces.iter().enumerate() {
            for (a, b) in face_edges(face) {
                let n = uses.entry((a.min(b), a.max(b))).or_insert(0);
                *n += 1;
                if *n > 2 {
                    return Err(fail(
                        f,
                        format!(
                            "non-manifold edge: the edge from {} to {} belongs to more than two faces",
                            show(cage.positions[a]),
                            show(cage.positions[b])
                        ),
                    ));
                }
            }
        }
        let boundary_edges = uses.values().filter(|&&n| n == 1).count();

        let mut half_edges = HashMap::with_capacity(uses.len() * 2);
        for (f, face) in cage.faces.iter().enumerate() {
            for (k, (a, b)) in face_edges(face).enumerate() {
                if half_edges.insert((a, b), (f, k)).is_some() {
                    return Err(fail(
                        f,
                        format!(
                            "two faces run along the edge from {} to {} in the same direction: \
                             the faces are not consistently oriented",
                            show(cage.positions[a]),
                            show(cage.positions[b])
                        ),
                    ));
                }
            }
        }

        let mut incident: Vec<Vec<(usize, usize)>> = vec![Vec::new(); nv];
        for (f, face) in cage.faces.iter().enumerate() {
            for (k, &v) in face.iter().enumerate() {
                incident[v].push((f, k));
            }
        }

        let mut topo = Topology {
            half_edges,
            fans: Vec::with_capacity(nv),
            boundary_edges,
        };
        for (v, inc) in incident.iter().enumerate() {
            let fan = topo.walk_fan(cage, v, inc).ok_or_else(|| {
                fail(
                    inc[0].0,
                    format!(
                        "non-manifold vertex at {}: its faces do not form a single fan",
                        show(cage.positions[v])
                    ),
                )
            })?;
            topo.fans.push(fan);
        }
        Ok(topo)
    }

    /// Orders the faces around `v`; `None` when they do not form one fan.
    fn walk_fan(&self, cage: &Cage, v: usize, incident: &[(usize, usize)]) -> Option<Fan> {
        if incident.is_empty() {
            return Some(Fan::default());
        }
        let prev_of = |(f, k): (usize, usize)| {
            let face = &cage.faces[f];
            face[(k + face.len() - 1) % face.len()]
        };
        let next_of = |(f, k): (usize, usize)| {
            let face = &cage.faces[f];
            face[(k + 1) % face.len()]
        };
        // A corner whose incoming edge has no twin starts a boundary fan.
        let mut starts = incident
            .iter()
            .copied()
            .filter(|&c| !self.half_edges.contains_key(&(v, prev_of(c))));
        let start = starts.next();
        if starts.next().is_some() {
            return None;
        }
        let first = start.unwrap_or(incident[0]);

        let mut corners = vec![first];
        let mut at = first;
        loop {
            let w = next_of(at);
            match self.half_edges.get(&(w, v)) {
                None => break, // reached the boundary: only valid for a boundary fan
                Some(&(g, m)) => {
                    let next = (g, (m + 1) % cage.faces[g].len());
                    if next == first {
                        break;
                    }
                    if corners.len() >= incident.len() {
                        return None;
                    }
                    corners.push(next);
                    at = next;
                }
            }
        }
        if corners.len() != incident.len() {
            return None;
        }
        let last = *corners.last()?;
        let boundary = start.map(|s| (prev_of(s), next_of(last)));
        let valence = corners.len() + usize::from(boundary.is_some());
        Some(Fan {
            corners,
            valence,
            boundary,
        })
    }
}

/// The directed edges (v_k, v_k+1) of a face, k = 0..len.
pub fn face_edges(face: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..face.len()).map(move |k| (face[k], face[(k + 1) % face.len()]))
}

fn show(p: DVec3) -> String {
    format!("({}, {}, {})", p.x as f32, p.y as f32, p.z as f32)
}

/// Where each face of a refined cage came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SubFace {
    /// The face of the coarse cage.
    pub face: usize,
    /// Which corner of it the sub-quad sits at.
    pub corner: usize,
}

/// One global Catmull–Clark step. Face points are face centroids; an
/// interior edge's point is the average of its two ends and the two adjacent
/// face points; an interior vertex of valence n moves to (Q + 2R + (n−3)v)/n
/// (Q: average of the adjacent face points, R: average of the incident edge
/// midpoints). Boundary edges are creases: their point is the midpoint, a
/// boundary vertex moves to (v_prev + 6v + v_next)/8, and a vertex with a
/// single face (a cage corner) stays put. Sub-quad k of face F is
/// (v_k', e(v_k, v_k+1), f_F, e(v_k−1, v_k)), so orientation is kept.
/// New vertices: vertex points, then edge points (first-use order), then
/// face points.
pub fn refine(cage: &Cage, topo: &Topology) -> (Cage, Vec<SubFace>) {
    let nv = cage.positions.len();
    let p = &cage.positions;

    let face_points: Vec<DVec3> = cage
        .faces
        .iter()
        .map(|face| face.iter().fold(DVec3::ZERO, |s, &v| s + p[v]) / face.len() as f64)
        .collect();

    // Undirected edges in order of first use.
    let mut edge_id: HashMap<(usize, usize), usize> = HashMap::new();
    let mut edge_points: Vec<DVec3> = Vec::new();
    for face in &cage.faces {
        for (a, b) in face_edges(face) {
            let key = (a.min(b), a.max(b));
            if edge_id.contains_key(&key) {
                continue;
            }
            let point = match (topo.half_edge(a, b), topo.half_edge(b, a)) {
                (Some((f, _)), Some((g, _))) => {
                    (p[a] + p[b] + face_points[f] + face_points[g]) * 0.25
                }
                _ => (p[a] + p[b]) * 0.5,
            };
            edge_id.insert(key, nv + edge_points.len());
            edge_points.push(point);
        }
    }

    let vertex_points: Vec<DVec3> = (0..nv)
        .map(|v| {
            let fan = &topo.fans[v];
            match fan.boundary {
                _ if fan.corners.is_empty() => p[v],
                Some(_) if fan.corners.len() == 1 => p[v],
                Some((a, b)) => (p[a] + p[v] * 6.0 + p[b]) * 0.125,
                None => {
                    let n = fan.valence as f64;
                    let mut q = DVec3::ZERO;
                    let mut r = DVec3::ZERO;
                    for &(f, k) in &fan.corners {
                        let face = &cage.faces[f];
                        q += face_points[f];
                        r += (p[v] + p[face[(k + 1) % face.len()]]) * 0.5;
                    }
                    (q / n + r / n * 2.0 + p[v] * (n - 3.0)) / n
                }
            }
        })
        .collect();

    let face_base = nv + edge_points.len();
    let mut out = Cage {
        positions: vertex_points,
        faces: Vec::new(),
        face_lines: Vec::new(),
    };
    out.positions.extend(edge_points);
    out.positions.extend(face_points);
    let mut origin = Vec::new();
    let edge = |a: usize, b: usize| edge_id[&(a.min(b), a.max(b))];
    for (f, face) in cage.faces.iter().enumerate() {
        let m = face.len();
        for k in 0..m {
            let (prev, v, next) = (face[(k + m - 1) % m], face[k], face[(k + 1) % m]);
            out.faces
                .push(vec![v, edge(v, next), face_base + f, edge(prev, v)]);
            out.face_lines
                .push(cage.face_lines.get(f).copied().flatten());
            origin.push(SubFace { face: f, corner: k });
        }
    }
    (out, origin)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube() -> Cage {
        let positions = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
            .collect();
        // Counter-clockwise seen from outside.
        let faces = vec![
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
        ];
        Cage {
            positions,
            face_lines: (0..faces.len()).map(|f| Some(f + 10)).collect(),
            faces,
        }
    }

    #[test]
    fn cube_fans_are_closed_with_valence_three() {
        let topo = Topology::build(&cube(), Path::new("cube")).unwrap();
        assert_eq!(topo.boundary_edges, 0);
        for fan in &topo.fans {
            assert_eq!((fan.valence, fan.corners.len(), fan.boundary), (3, 3, None));
        }
    }

    #[test]
    fn open_cube_has_a_boundary_loop() {
        let mut c = cube();
        c.faces.remove(1);
        c.face_lines.remove(1);
        let topo = Topology::build(&c, Path::new("box")).unwrap();
        assert_eq!(topo.boundary_edges, 4);
        for v in [4, 5, 6, 7] {
            let fan = &topo.fans[v];
            assert_eq!((fan.valence, fan.corners.len()), (3, 2));
            let (a, b) = fan.boundary.unwrap();
            // Boundary neighbours are the two other top vertices next to v.
            assert!(a >= 4 && b >= 4 && a != b && a != v && b != v);
        }
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
        // (Q + 2R + 0·v)/3 with Q the mean of three face centres and R the
        // mean of three edge midpoints.
        let v0 = r.positions[0];
        let q = (DVec3::new(0.5, 0.5, 0.0) + DVec3::new(0.5, 0.0, 0.5) + DVec3::new(0.0, 0.5, 0.5))
            / 3.0;
        let rr =
            (DVec3::new(0.5, 0.0, 0.0) + DVec3::new(0.0, 0.5, 0.0) + DVec3::new(0.0, 0.0, 0.5))
                / 3.0;
        assert!((v0 - (q + rr * 2.0) / 3.0).length() < 1e-15);

        // Again, where the old face centres are valence-4 vertices, so the
        // (n − 3)·v term counts: (Q + 2R + v)/4.
        let (r2, _) = refine(&r, &rt);
        let v = 8 + 12; // face point of face 0
        let ring: Vec<&Vec<usize>> = r.faces.iter().filter(|f| f.contains(&v)).collect();
        assert_eq!(ring.len(), 4);
        let p = &r.positions;
        let q = ring
            .iter()
            .map(|f| f.iter().map(|&i| p[i]).sum::<DVec3>() / 4.0)
            .sum::<DVec3>()
            / 4.0;
        let mut nbrs: Vec<usize> = ring
            .iter()
            .flat_map(|f| {
                let k = f.iter().position(|&i| i == v).unwrap();
                [f[(k + 1) % 4], f[(k + 3) % 4]]
            })
            .collect();
        nbrs.sort_unstable();
        nbrs.dedup();
        assert_eq!(nbrs.len(), 4);
        let rr = nbrs.iter().map(|&w| (p[v] + p[w]) / 2.0).sum::<DVec3>() / 4.0;
        assert!((r2.positions[v] - (q + rr * 2.0 + p[v]) / 4.0).length() < 1e-15);
    }

    #[test]
    fn refine_creases_the_boundary() {
        // Two quads side by side, bent along their shared edge (1, 4).
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.5),
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 1.0, 0.5),
            DVec3::new(2.0, 1.0, 0.25),
        ];
        let c = Cage {
            positions: positions.clone(),
            faces: vec![vec![0, 1, 4, 3], vec![1, 2, 5, 4]],
            face_lines: vec![None, None],
        };
        let topo = Topology::build(&c, Path::new("strip")).unwrap();
        assert_eq!(topo.boundary_edges, 6);
        assert_eq!(topo.fans[1].boundary, Some((0, 2)));
        assert_eq!(topo.fans[4].boundary, Some((5, 3)));
        let (r, _) = refine(&c, &topo);
        let p = &positions;
        let f0 = (p[0] + p[1] + p[4] + p[3]) / 4.0;
        let f1 = (p[1] + p[2] + p[5] + p[4]) / 4.0;
        // Cage corners stay, boundary vertices with two faces get 1-6-1.
        assert_eq!(r.positions[0], p[0]);
        assert_eq!(r.positions[5], p[5]);
        assert!((r.positions[1] - (p[0] + p[1] * 6.0 + p[2]) / 8.0).length() < 1e-15);
        // Sub-quad 1 of face 0 starts at vertex 1: (v1', e(1,4), f0, e(0,1)).
        let sub = &r.faces[1];
        assert_eq!(sub[0], 1);
        assert!((r.positions[sub[1]] - (p[1] + p[4] + f0 + f1) / 4.0).length() < 1e-15);
        assert!((r.positions[sub[2]] - f0).length() < 1e-15);
        assert!((r.positions[sub[3]] - (p[0] + p[1]) / 2.0).length() < 1e-15);
        assert_eq!(r.faces.len(), 8);
        assert_eq!(r.positions.len(), 6 + 7 + 2);
    }

    #[test]
    fn refuses_bad_cages_naming_the_line() {
        let path = Path::new("bad.obj");
        let check = |c: &Cage, line: usize, needle: &str| {
            let e = Topology::build(c, path).unwrap_err().to_string();
            assert!(e.starts_with(&format!("bad.obj:{line}: ")), "{e}");
            assert!(e.contains(needle), "{e}");
        };
        let mut c = cube();
        c.faces[2] = vec![0, 1, 5, 1];
        check(&c, 12, "degenerate");
        let mut c = cube();
        c.faces[3] = vec![2, 6];
        check(&c, 13, "at least 3");
        let mut c = cube();
        c.faces[0].reverse();
        check(&c, 12, "same direction");
        let mut c = cube();
        c.faces.push(vec![0, 2, 3, 1]);
        c.face_lines.push(Some(99));
        check(&c, 99, "more than two faces");
        // Two cubes touching at one vertex: every edge is fine, the vertex is not.
        let mut c = cube();
        let shift = DVec3::splat(1.0);
        let extra: Vec<DVec3> = c.positions.iter().skip(1).map(|p| *p + shift).collect();
        let map = |v: usize| if v == 0 { 7 } else { 7 + v };
        c.positions.extend(extra);
        for f in 0..6 {
            let face: Vec<usize> = c.faces[f].iter().map(|&v| map(v)).collect();
            c.faces.push(face);
            c.face_lines.push(Some(50 + f));
        }
        let e = Topology::build(&c, path).unwrap_err().to_string();
        assert!(e.contains("non-manifold vertex"), "{e}");
    }
}
