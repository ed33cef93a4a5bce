//! Polygonal control cages and their adjacency.
//!
//! A cage is accepted when every face has at least three distinct vertices
//! and every edge used by exactly two faces is traversed by them in opposite
//! directions (two faces running an edge the same way almost always means a
//! flipped face, so that is refused with the line of the second face).
//! Everything else a polygon soup can do is accepted and described:
//!
//! - an edge with one face is a boundary edge;
//! - an edge with three or more faces (in any directions) is a non-manifold
//!   edge: every face on it treats it as its own boundary, so each fan of
//!   faces is a separate sheet that meets the others along the edge's curve
//!   (the curve is shared, see `sharpness.rs` for the rules that make it so);
//! - the faces around a vertex form one or more fans, each a run of faces
//!   joined through manifold edges; a vertex with more than one fan is a
//!   non-manifold vertex.
//!
//! Refusals name the source line of a face involved, where the cage came
//! from a file.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::SceneError;

/// A polygonal control cage with its OpenSubdiv-style sharpness. Positions
/// are f64 so that a refined cage is not rounded before the patches are
/// computed from it.
#[derive(Clone, Debug, Default)]
pub struct Cage {
    /// Vertex positions.
    pub positions: Vec<DVec3>,
    /// Faces as vertex indices, in order (counter-clockwise seen from outside).
    pub faces: Vec<Vec<usize>>,
    /// Source line (1-based) of each face, for error messages; `None` when
    /// the face has no line of its own.
    pub face_lines: Vec<Option<usize>>,
    /// Crease sharpness of edges keyed by (smaller, larger) vertex index;
    /// an edge not listed is smooth (0). `sharpness::INFINITE` and above is
    /// infinitely sharp.
    pub edge_sharpness: HashMap<(usize, usize), f64>,
    /// Corner sharpness of vertices; a vertex not listed has 0.
    pub vertex_sharpness: HashMap<usize, f64>,
    /// Faces that give no patch (the `none` boundary rule's boundary faces);
    /// empty when there are none.
    pub holes: Vec<bool>,
}

impl Cage {
    /// Sharpness of the edge between `a` and `b` (0 when untagged).
    pub fn edge_sharpness(&self, a: usize, b: usize) -> f64 {
        self.edge_sharpness
            .get(&(a.min(b), a.max(b)))
            .copied()
            .unwrap_or(0.0)
    }

    /// Corner sharpness of vertex `v` (0 when untagged).
    pub fn vertex_sharpness(&self, v: usize) -> f64 {
        self.vertex_sharpness.get(&v).copied().unwrap_or(0.0)
    }

    /// Whether face `f` is a hole.
    pub fn is_hole(&self, f: usize) -> bool {
        self.holes.get(f).copied().unwrap_or(false)
    }

    /// The source line of face `f`, if it has one.
    pub fn line_of(&self, f: usize) -> Option<usize> {
        self.face_lines.get(f).copied().flatten()
    }
}

/// One undirected edge of a cage.
#[derive(Clone, Debug)]
pub struct Edge {
    /// Its ends, in the direction of the first face that uses it.
    pub ends: (usize, usize),
    /// Every (face, corner) whose outgoing edge this is, in face order.
    pub uses: Vec<(usize, usize)>,
}

impl Edge {
    /// Exactly two faces, running the edge in opposite directions.
    pub fn is_manifold(&self) -> bool {
        self.uses.len() == 2
    }

    /// The end that is not `v`.
    pub fn other(&self, v: usize) -> usize {
        if self.ends.0 == v {
            self.ends.1
        } else {
            self.ends.0
        }
    }
}

/// A run of faces around a vertex joined through manifold edges.
#[derive(Clone, Debug, Default)]
pub struct Fan {
    /// (face, corner) pairs in rotation order: each next face lies across
    /// the outgoing edge `corner → corner + 1` of the one before. An open fan
    /// starts at the corner whose incoming edge is not manifold and ends at
    /// the one whose outgoing edge is not.
    pub corners: Vec<(usize, usize)>,
    /// The last corner's outgoing edge is the first one's incoming edge.
    pub closed: bool,
}

/// Adjacency of a validated cage.
#[derive(Clone, Debug)]
pub struct Topology {
    /// Undirected edges in order of first use.
    pub edges: Vec<Edge>,
    /// (smaller, larger) vertex → index into `edges`.
    edge_index: HashMap<(usize, usize), usize>,
    /// Directed manifold edge (a, b) → (face, corner of a in that face).
    half_edges: HashMap<(usize, usize), (usize, usize)>,
    /// The fans of each vertex (none for vertices no face uses).
    pub fans: Vec<Vec<Fan>>,
    /// The edges at each vertex, in order of first use.
    pub vertex_edges: Vec<Vec<usize>>,
    /// Number of edges with a single face.
    pub boundary_edges: usize,
    /// Number of edges with three or more faces.
    pub non_manifold_edges: usize,
}

impl Topology {
    /// The (face, corner) whose outgoing edge runs from `a` to `b`, for a
    /// manifold edge.
    pub fn half_edge(&self, a: usize, b: usize) -> Option<(usize, usize)> {
        self.half_edges.get(&(a, b)).copied()
    }

    /// Index of the edge between `a` and `b`.
    pub fn edge_id(&self, a: usize, b: usize) -> Option<usize> {
        self.edge_index.get(&(a.min(b), a.max(b))).copied()
    }

    /// The edge between `a` and `b`. Panics if there is none: callers only
    /// ask about edges of the cage's own faces.
    pub fn edge(&self, a: usize, b: usize) -> &Edge {
        &self.edges[self.edge_id(a, b).expect("an edge of the cage")]
    }

    /// Number of edges at `v`.
    pub fn valence(&self, v: usize) -> usize {
        self.vertex_edges[v].len()
    }

    /// Number of faces at `v`.
    pub fn face_count(&self, v: usize) -> usize {
        self.fans[v].iter().map(|f| f.corners.len()).sum()
    }

    /// More than one fan of faces meets at `v`.
    pub fn is_non_manifold_vertex(&self, v: usize) -> bool {
        self.fans[v].len() > 1
    }

    /// Validates `cage` and builds its adjacency. `path` only names the
    /// source in errors.
    pub fn build(cage: &Cage, path: &Path) -> Result<Topology, SceneError> {
        let fail = |face: usize, msg: String| match cage.line_of(face) {
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

        let mut edges: Vec<Edge> = Vec::new();
        let mut edge_index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut vertex_edges: Vec<Vec<usize>> = vec![Vec::new(); nv];
        for (f, face) in cage.faces.iter().enumerate() {
            for (k, (a, b)) in face_edges(face).enumerate() {
                let id = *edge_index.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    edges.push(Edge {
                        ends: (a, b),
                        uses: Vec::new(),
                    });
                    vertex_edges[a].push(edges.len() - 1);
                    vertex_edges[b].push(edges.len() - 1);
                    edges.len() - 1
                });
                edges[id].uses.push((f, k));
            }
        }

        // In face order, so a flipped face is reported at the first face
        // that runs a two-face edge the way an earlier one did.
        let mut half_edges = HashMap::with_capacity(edges.len() * 2);
        for (f, face) in cage.faces.iter().enumerate() {
            for (k, (a, b)) in face_edges(face).enumerate() {
                if edges[edge_index[&(a.min(b), a.max(b))]].uses.len() != 2 {
                    continue;
                }
                if half_edges.insert((a, b), (f, k)).is_some() {
                    return Err(fail(
                        f,
                        format!(
                            "two faces run along the edge from {} to {} in the same direction: \
                             the faces are not consistently oriented (a flipped face?)",
                            show(cage.positions[a]),
                            show(cage.positions[b])
                        ),
                    ));
                }
            }
        }
        let boundary_edges = edges.iter().filter(|e| e.uses.len() == 1).count();
        let non_manifold_edges = edges.iter().filter(|e| e.uses.len() > 2).count();

        let mut incident: Vec<Vec<(usize, usize)>> = vec![Vec::new(); nv];
        for (f, face) in cage.faces.iter().enumerate() {
            for (k, &v) in face.iter().enumerate() {
                incident[v].push((f, k));
            }
        }
        let mut topo = Topology {
            edges,
            edge_index,
            half_edges,
            fans: Vec::with_capacity(nv),
            vertex_edges,
            boundary_edges,
            non_manifold_edges,
        };
        for (v, inc) in incident.iter().enumerate() {
            let fans = topo.walk_fans(cage, v, inc);
            topo.fans.push(fans);
        }
        Ok(topo)
    }

    /// Orders the faces around `v` into fans: open ones first (from each
    /// corner whose incoming edge is not manifold), then closed ones.
    fn walk_fans(&self, cage: &Cage, v: usize, incident: &[(usize, usize)]) -> Vec<Fan> {
        let prev_of = |(f, k): (usize, usize)| {
            let face = &cage.faces[f];
            face[(k + face.len() - 1) % face.len()]
        };
        let next_of = |(f, k): (usize, usize)| {
            let face = &cage.faces[f];
            face[(k + 1) % face.len()]
        };
        let step = |c: (usize, usize)| {
            self.half_edges
                .get(&(next_of(c), v))
                .map(|&(g, m)| (g, (m + 1) % cage.faces[g].len()))
        };
        let mut seen: Vec<(usize, usize)> = Vec::with_capacity(incident.len());
        let mut fans = Vec::new();
        let starts = incident
            .iter()
            .copied()
            .filter(|&c| !self.half_edges.contains_key(&(v, prev_of(c))));
        for start in starts {
            let mut corners = vec![start];
            let mut at = start;
            // Each corner has one successor and an open start none, so the
            // walk ends; the bound only guards against a broken invariant.
            while let Some(next) = step(at) {
                if corners.len() > incident.len() {
                    break;
                }
                corners.push(next);
                at = next;
            }
            seen.extend(&corners);
            fans.push(Fan {
                corners,
                closed: false,
            });
        }
        for &first in incident {
            if seen.contains(&first) {
                continue;
            }
            let mut corners = vec![first];
            let mut at = first;
            while let Some(next) = step(at) {
                if next == first || corners.len() > incident.len() {
                    break;
                }
                corners.push(next);
                at = next;
            }
            seen.extend(&corners);
            fans.push(Fan {
                corners,
                closed: true,
            });
        }
        fans
    }

    /// The edge entering corner `c` of its face (from the previous vertex).
    pub fn incoming(&self, cage: &Cage, (f, k): (usize, usize)) -> usize {
        let face = &cage.faces[f];
        let prev = face[(k + face.len() - 1) % face.len()];
        self.edge_id(prev, face[k]).expect("face edge")
    }

    /// The edge leaving corner `c` of its face (to the next vertex).
    pub fn outgoing(&self, cage: &Cage, (f, k): (usize, usize)) -> usize {
        let face = &cage.faces[f];
        self.edge_id(face[k], face[(k + 1) % face.len()])
            .expect("face edge")
    }
}

/// The directed edges (v_k, v_k+1) of a face, k = 0..len.
pub fn face_edges(face: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..face.len()).map(move |k| (face[k], face[(k + 1) % face.len()]))
}

/// A position as the user wrote it (f32), for messages.
pub fn show(p: DVec3) -> String {
    format!("({}, {}, {})", p.x as f32, p.y as f32, p.z as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn cube() -> Cage {
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
            ..Cage::default()
        }
    }

    #[test]
    fn cube_fans_are_closed_with_valence_three() {
        let topo = Topology::build(&cube(), Path::new("cube")).unwrap();
        assert_eq!((topo.boundary_edges, topo.non_manifold_edges), (0, 0));
        for v in 0..8 {
            let fans = &topo.fans[v];
            assert_eq!(fans.len(), 1);
            assert!(fans[0].closed);
            assert_eq!((topo.valence(v), fans[0].corners.len()), (3, 3));
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
            let fans = &topo.fans[v];
            assert_eq!(fans.len(), 1);
            assert!(!fans[0].closed);
            assert_eq!((topo.valence(v), fans[0].corners.len()), (3, 2));
            // The fan starts at a boundary edge and ends at one.
            let first = topo.incoming(&c, fans[0].corners[0]);
            let last = topo.outgoing(&c, *fans[0].corners.last().unwrap());
            assert_eq!(topo.edges[first].uses.len(), 1);
            assert_eq!(topo.edges[last].uses.len(), 1);
        }
    }

    #[test]
    fn three_faces_on_an_edge_make_three_sheets() {
        // Three quads hinged on the edge (0, 1), like the pages of a book.
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
            DVec3::new(-1.0, 0.0, 0.0),
            DVec3::new(-1.0, 1.0, 0.0),
        ];
        let c = Cage {
            positions,
            faces: vec![vec![0, 2, 3, 1], vec![1, 5, 4, 0], vec![0, 1, 7, 6]],
            face_lines: vec![Some(1), Some(2), Some(3)],
            ..Cage::default()
        };
        let topo = Topology::build(&c, Path::new("book")).unwrap();
        assert_eq!(topo.non_manifold_edges, 1);
        assert_eq!(topo.edge(0, 1).uses.len(), 3);
        assert!(topo.half_edge(0, 1).is_none());
        for v in [0, 1] {
            assert_eq!(topo.fans[v].len(), 3);
            assert!(topo.is_non_manifold_vertex(v));
        }
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
        // Two cubes touching at one vertex: accepted, with two closed fans there.
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
        let topo = Topology::build(&c, path).unwrap();
        assert_eq!(topo.fans[7].len(), 2);
        assert!(topo.fans[7].iter().all(|f| f.closed));
    }
}
