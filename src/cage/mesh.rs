//! Polygonal control cages and their adjacency, read as OpenSubdiv reads
//! them (`Vtr::Level`'s rules), so that every cage OpenSubdiv draws is
//! accepted and has the same edges, fans and non-manifold features:
//!
//! - an edge is a pair of vertices, shared by every face that runs between
//!   them; an edge with one face is a boundary edge;
//! - a *non-manifold* edge is one with three or more faces, one whose two
//!   faces run it in the same direction (inconsistent orientation, often a
//!   flipped face), a degenerate edge (a face repeats a vertex, e.g. the
//!   quad `4 3 5 5`: each such edge is its own), or an edge a face uses
//!   twice (then each use is its own edge). Every face on a non-manifold
//!   edge treats it as its own boundary, so each fan of faces is a separate
//!   sheet that meets the others along the edge's curve (`sharpness.rs`
//!   makes such edges infinitely sharp, as OpenSubdiv does);
//! - the faces around a vertex form one or more fans, each a run of faces
//!   joined through manifold edges; a vertex with more than one fan, or on
//!   a non-manifold edge, is a non-manifold vertex.
//!
//! Refused, naming the source line of a face involved where the cage came
//! from a file: a face with fewer than three corners, a vertex index out of
//! range, a NaN or infinite position.
//!
//! A refined cage (`refine.rs`) names its edges explicitly
//! ([`Cage::face_edges`]): the two halves of a degenerate edge join the same
//! two vertices and are still two edges, as in OpenSubdiv.

use super::hash::IndexMap;
use std::path::Path;

use glam::DVec3;

use crate::input::SceneError;

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
    /// infinitely sharp. (Edges joining the same two vertices share it; all
    /// such edges are non-manifold, hence infinitely sharp.)
    pub edge_sharpness: IndexMap<(usize, usize), f64>,
    /// Corner sharpness of vertices; a vertex not listed has 0.
    pub vertex_sharpness: IndexMap<usize, f64>,
    /// Faces that give no patch (`t hole`, the `none` boundary rule's
    /// boundary faces); empty when there are none.
    pub holes: Vec<bool>,
    /// Explicit edges of a refined cage: per face, the edge of each corner k
    /// (from corner k to k + 1), indices into [`Cage::edge_list`]. Empty:
    /// edges follow from the vertex pairs ([`Topology::build`]).
    pub face_edges: Vec<Vec<usize>>,
    /// With [`Cage::face_edges`]: each edge's ends and whether it descends
    /// from a non-manifold edge (it stays one, as in OpenSubdiv).
    pub edge_list: Vec<CageEdge>,
    /// How the cage refines: creasing method, triangle rule.
    pub scheme: Scheme,
}

/// OpenSubdiv's scheme options that change how a cage refines (its
/// `Sdc::Options` beyond the boundary rule).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Scheme {
    /// `t creasemethod 0/0/1 chaikin`: Chaikin's rule for the sharpness of
    /// semi-sharp crease halves (default uniform: one less).
    pub chaikin: bool,
    /// `t smoothtriangles 0/0/1 smooth`: OpenSubdiv's smoother edge weights
    /// next to triangles (default: Catmull–Clark's).
    pub smooth_triangles: bool,
}

/// An explicit edge of a refined cage.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CageEdge {
    /// Its two vertices.
    pub ends: (usize, usize),
    /// Inherited from a non-manifold parent edge.
    pub non_manifold: bool,
}

impl Cage {
    /// The faces `faces` of this cage as a cage of their own, vertices renumbered
    /// in order of use; also the new index of each old vertex used.
    pub(crate) fn extract(&self, faces: &[usize]) -> (Cage, Vec<Option<usize>>) {
        let mut map: Vec<Option<usize>> = vec![None; self.positions.len()];
        let mut out = Cage {
            scheme: self.scheme,
            ..Cage::default()
        };
        for &f in faces {
            let face = self.faces[f]
                .iter()
                .map(|&v| {
                    *map[v].get_or_insert_with(|| {
                        out.positions.push(self.positions[v]);
                        out.positions.len() - 1
                    })
                })
                .collect();
            out.faces.push(face);
            out.face_lines.push(self.line_of(f));
            out.holes.push(self.is_hole(f));
        }
        for (&(a, b), &s) in &self.edge_sharpness {
            if let (Some(a), Some(b)) = (map[a], map[b]) {
                out.edge_sharpness.insert((a.min(b), a.max(b)), s);
            }
        }
        for (&v, &s) in &self.vertex_sharpness {
            if let Some(v) = map[v] {
                out.vertex_sharpness.insert(v, s);
            }
        }
        if !out.holes.iter().any(|&h| h) {
            out.holes.clear();
        }
        (out, map)
    }

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

/// One edge of a cage.
#[derive(Clone, Debug)]
pub struct Edge {
    /// Its ends, in the direction of the first face that uses it.
    pub ends: (usize, usize),
    /// Every (face, corner) whose outgoing edge this is, in face order.
    pub uses: Vec<(usize, usize)>,
    /// Non-manifold (see the module doc); an edge with one face is a
    /// boundary edge, and also non-manifold when degenerate.
    pub non_manifold: bool,
}

impl Edge {
    /// A manifold edge: two faces running it in opposite directions.
    pub fn is_manifold(&self) -> bool {
        !self.non_manifold && self.uses.len() == 2
    }

    /// The end that is not `v` (`v` itself for a degenerate edge).
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
    /// Edges in order of first use.
    pub edges: Vec<Edge>,
    /// Per face, the edge of each corner k (from corner k to k + 1).
    pub face_edges: Vec<Vec<usize>>,
    /// (smaller, larger) vertex → the first edge between them.
    edge_index: IndexMap<(usize, usize), usize>,
    /// Directed manifold edge (a, b) → (face, corner of a in that face).
    half_edges: IndexMap<(usize, usize), (usize, usize)>,
    /// The fans of each vertex (none for vertices no face uses).
    pub fans: Vec<Vec<Fan>>,
    /// The edges at each vertex, in order of first use; a degenerate edge
    /// is listed twice (both its ends are the vertex), as in OpenSubdiv.
    pub vertex_edges: Vec<Vec<usize>>,
    /// Whether each vertex is non-manifold: on a non-manifold edge, or
    /// with more than one fan.
    pub non_manifold_vertex: Vec<bool>,
    /// Number of edges with a single face.
    pub boundary_edges: usize,
    /// Number of non-manifold edges, for whatever reason.
    pub non_manifold_edges: usize,
    /// Of those: degenerate edges (a face repeats a vertex).
    pub degenerate_edges: usize,
    /// Of those: edges whose two faces run them in the same direction.
    pub misoriented_edges: usize,
}

impl Topology {
    /// The (face, corner) whose outgoing edge runs from `a` to `b`, for a
    /// manifold edge.
    pub fn half_edge(&self, a: usize, b: usize) -> Option<(usize, usize)> {
        self.half_edges.get(&(a, b)).copied()
    }

    /// Index of the (first) edge between `a` and `b`.
    pub fn edge_id(&self, a: usize, b: usize) -> Option<usize> {
        self.edge_index.get(&(a.min(b), a.max(b))).copied()
    }

    /// The (first) edge between `a` and `b`. Panics if there is none:
    /// callers only ask about edges of the cage's own faces.
    pub fn edge(&self, a: usize, b: usize) -> &Edge {
        &self.edges[self.edge_id(a, b).expect("an edge of the cage")]
    }

    /// Number of edges at `v` (a degenerate edge counts twice).
    pub fn valence(&self, v: usize) -> usize {
        self.vertex_edges[v].len()
    }

    /// Number of face corners at `v` (a face that repeats `v` counts twice).
    pub fn face_count(&self, v: usize) -> usize {
        self.fans[v].iter().map(|f| f.corners.len()).sum()
    }

    /// `v` is non-manifold: on a non-manifold edge, or more than one fan of
    /// faces meets there.
    pub fn is_non_manifold_vertex(&self, v: usize) -> bool {
        self.non_manifold_vertex[v]
    }

    /// Validates `cage` and builds its adjacency. `path` only names the
    /// source in errors.
    pub fn build(cage: &Cage, path: &Path) -> Result<Topology, SceneError> {
        check_faces(cage, path)?;
        let nv = cage.positions.len();
        let (edges, face_edges) = if cage.face_edges.is_empty() {
            edges_from_pairs(cage)
        } else {
            edges_given(cage, path)?
        };
        let mut vertex_edges: Vec<Vec<usize>> = vec![Vec::new(); nv];
        let mut edge_index: IndexMap<(usize, usize), usize> = IndexMap::default();
        for (id, e) in edges.iter().enumerate() {
            let (a, b) = e.ends;
            vertex_edges[a].push(id);
            vertex_edges[b].push(id);
            edge_index.entry((a.min(b), a.max(b))).or_insert(id);
        }
        let mut half_edges =
            IndexMap::with_capacity_and_hasher(edges.len() * 2, Default::default());
        for e in edges.iter().filter(|e| e.is_manifold()) {
            for &(f, k) in &e.uses {
                let face = &cage.faces[f];
                half_edges.insert((face[k], face[(k + 1) % face.len()]), (f, k));
            }
        }
        let count = |pred: &dyn Fn(&Edge) -> bool| edges.iter().filter(|e| pred(e)).count();
        let boundary_edges = count(&|e| e.uses.len() == 1 && !e.non_manifold);
        let non_manifold_edges = count(&|e| e.non_manifold);
        let degenerate_edges = count(&|e| e.ends.0 == e.ends.1);
        let misoriented_edges = count(&|e| misoriented(cage, e));

        let mut incident: Vec<Vec<(usize, usize)>> = vec![Vec::new(); nv];
        for (f, face) in cage.faces.iter().enumerate() {
            for (k, &v) in face.iter().enumerate() {
                incident[v].push((f, k));
            }
        }
        let mut topo = Topology {
            edges,
            face_edges,
            edge_index,
            half_edges,
            fans: Vec::with_capacity(nv),
            vertex_edges,
            non_manifold_vertex: Vec::new(),
            boundary_edges,
            non_manifold_edges,
            degenerate_edges,
            misoriented_edges,
        };
        for inc in &incident {
            let fans = topo.walk_fans(cage, inc);
            topo.fans.push(fans);
        }
        topo.non_manifold_vertex = (0..nv)
            .map(|v| {
                topo.fans[v].len() > 1
                    || topo.vertex_edges[v]
                        .iter()
                        .any(|&e| topo.edges[e].non_manifold)
            })
            .collect();
        Ok(topo)
    }

    /// Orders the faces around a vertex (its `incident` corners) into fans:
    /// open ones first (from each corner whose incoming edge is not
    /// manifold), then closed ones.
    fn walk_fans(&self, cage: &Cage, incident: &[(usize, usize)]) -> Vec<Fan> {
        // Across the outgoing (manifold) edge of corner c: the other face
        // runs it the other way, so its corner after the edge is at v.
        let step = |c: (usize, usize)| {
            let e = &self.edges[self.outgoing(c)];
            if !e.is_manifold() {
                return None;
            }
            let &(g, m) = e.uses.iter().find(|&&u| u != c)?;
            Some((g, (m + 1) % cage.faces[g].len()))
        };
        let mut seen: Vec<(usize, usize)> = Vec::with_capacity(incident.len());
        let mut fans = Vec::new();
        let starts = incident
            .iter()
            .copied()
            .filter(|&c| !self.edges[self.incoming(c)].is_manifold());
        // The fan from `first`: to its open end, or (closed) back round to
        // `first`. Each corner has one successor and an open start none, so
        // the walk ends; the bound only guards against a broken invariant.
        let walk = |first: (usize, usize), closed: bool| {
            let mut corners = vec![first];
            let mut at = first;
            while let Some(next) = step(at) {
                if (closed && next == first) || corners.len() > incident.len() {
                    break;
                }
                corners.push(next);
                at = next;
            }
            Fan { corners, closed }
        };
        for start in starts {
            let fan = walk(start, false);
            seen.extend(&fan.corners);
            fans.push(fan);
        }
        for &first in incident {
            if !seen.contains(&first) {
                let fan = walk(first, true);
                seen.extend(&fan.corners);
                fans.push(fan);
            }
        }
        fans
    }

    /// The edge entering corner `c` of its face (from the previous vertex).
    pub fn incoming(&self, (f, k): (usize, usize)) -> usize {
        let edges = &self.face_edges[f];
        edges[(k + edges.len() - 1) % edges.len()]
    }

    /// The edge leaving corner `c` of its face (to the next vertex).
    pub fn outgoing(&self, (f, k): (usize, usize)) -> usize {
        self.face_edges[f][k]
    }

    /// Which end of its edge corner k of face f starts, 0 or 1: the face
    /// runs the edge from that end. (A degenerate edge is its face's own,
    /// run from end 0.)
    pub fn start_end(&self, cage: &Cage, (f, k): (usize, usize)) -> usize {
        let e = &self.edges[self.face_edges[f][k]];
        let face = &cage.faces[f];
        let run = (face[k], face[(k + 1) % face.len()]);
        usize::from(e.ends != run)
    }
}

/// Two faces run the edge in the same direction.
fn misoriented(cage: &Cage, e: &Edge) -> bool {
    let dir = |&(f, k): &(usize, usize)| {
        let face = &cage.faces[f];
        (face[k], face[(k + 1) % face.len()])
    };
    matches!(&e.uses[..], [a, b] if a.0 != b.0 && dir(a) == dir(b) && e.ends.0 != e.ends.1)
}

/// What no cage can be: faces of fewer than three corners, indices out of
/// range, non-finite positions.
fn check_faces(cage: &Cage, path: &Path) -> Result<(), SceneError> {
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
    }
    Ok(())
}

/// Edges from vertex pairs, in OpenSubdiv's way (`Vtr::Level::
/// completeTopologyFromFaceVertices`): faces in order, each corner's edge
/// the first one between its two vertices, except that a degenerate edge
/// is always new, and so is an edge the same face already uses; a third
/// face, or a second running the same way, makes it non-manifold.
fn edges_from_pairs(cage: &Cage) -> (Vec<Edge>, Vec<Vec<usize>>) {
    let mut edges: Vec<Edge> = Vec::new();
    let mut first: IndexMap<(usize, usize), usize> = IndexMap::default();
    let mut face_edges = Vec::with_capacity(cage.faces.len());
    for (f, face) in cage.faces.iter().enumerate() {
        let mut ids = Vec::with_capacity(face.len());
        for (k, (a, b)) in face_edges_of(face).enumerate() {
            let key = (a.min(b), a.max(b));
            let mut found = if a == b {
                None
            } else {
                first.get(&key).copied()
            };
            let mut twice = false;
            if let Some(id) = found {
                let e = &mut edges[id];
                // Faces come in order, so this face used the edge already
                // exactly when it is the last one on it.
                if e.uses.last().map(|u| u.0) == Some(f) {
                    e.non_manifold = true;
                    twice = true;
                    found = None;
                } else if e.uses.len() > 1 || e.ends.0 == a {
                    e.non_manifold = true;
                }
            }
            let id = found.unwrap_or_else(|| {
                edges.push(Edge {
                    ends: (a, b),
                    uses: Vec::new(),
                    non_manifold: a == b || twice,
                });
                first.entry(key).or_insert(edges.len() - 1);
                edges.len() - 1
            });
            edges[id].uses.push((f, k));
            ids.push(id);
        }
        face_edges.push(ids);
    }
    (edges, face_edges)
}

/// Edges as a refined cage names them, with the same non-manifold rules.
fn edges_given(cage: &Cage, path: &Path) -> Result<(Vec<Edge>, Vec<Vec<usize>>), SceneError> {
    let mut edges: Vec<Edge> = cage
        .edge_list
        .iter()
        .map(|e| Edge {
            ends: e.ends,
            uses: Vec::new(),
            non_manifold: e.non_manifold || e.ends.0 == e.ends.1,
        })
        .collect();
    if cage.face_edges.len() != cage.faces.len() {
        return Err(SceneError::invalid(
            path,
            "internal: a refined cage's edges do not match its faces",
        ));
    }
    for (f, (face, ids)) in cage.faces.iter().zip(&cage.face_edges).enumerate() {
        let wrong = || {
            SceneError::invalid(
                path,
                format!(
                    "internal: face {} of a refined cage names a wrong edge",
                    f + 1
                ),
            )
        };
        if ids.len() != face.len() {
            return Err(wrong());
        }
        for (k, (&id, (a, b))) in ids.iter().zip(face_edges_of(face)).enumerate() {
            let e = edges
                .get_mut(id)
                .filter(|e| e.ends == (a, b) || e.ends == (b, a));
            let Some(e) = e else {
                return Err(wrong());
            };
            if let Some(&(g, m)) = e.uses.first() {
                let other = &cage.faces[g];
                let same_way = other[m] == a && a != b;
                if e.uses.len() > 1 || g == f || same_way {
                    e.non_manifold = true;
                }
            }
            e.uses.push((f, k));
        }
    }
    Ok((edges, cage.face_edges.clone()))
}

/// The directed edges (v_k, v_k+1) of a face, k = 0..len.
pub fn face_edges_of(face: &[usize]) -> impl Iterator<Item = (usize, usize)> + '_ {
    (0..face.len()).map(move |k| (face[k], face[(k + 1) % face.len()]))
}

/// A position as the user wrote it (f32), for messages.
pub fn show(p: DVec3) -> String {
    format!("({}, {}, {})", p.x as f32, p.y as f32, p.z as f32)
}

/// The unit cube as a cage, its faces counter-clockwise seen from outside
/// and without source lines: the fixture of the cage, orientation and
/// refinement tests.
#[cfg(test)]
pub(crate) fn unit_cube() -> Cage {
    let positions = (0..8)
        .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64))
        .collect();
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
        face_lines: vec![None; faces.len()],
        faces,
        ..Cage::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube with source lines 10.. (for the messages tests).
    pub(crate) fn cube() -> Cage {
        let mut c = unit_cube();
        c.face_lines = (0..c.faces.len()).map(|f| Some(f + 10)).collect();
        c
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
            let first = topo.incoming(fans[0].corners[0]);
            let last = topo.outgoing(*fans[0].corners.last().unwrap());
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
        c.faces[3] = vec![2, 6];
        check(&c, 13, "at least 3");
        let mut c = cube();
        c.faces[3] = vec![2, 6, 70];
        check(&c, 13, "out of range");
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
        assert!(topo.is_non_manifold_vertex(7) && !topo.is_non_manifold_vertex(6));
    }

    #[test]
    fn a_flipped_face_makes_non_manifold_edges() {
        // OpenSubdiv's rule: an edge whose two faces run it the same way is
        // non-manifold (each face its own sheet there), not an error.
        let mut c = cube();
        c.faces[0].reverse();
        let topo = Topology::build(&c, Path::new("flip")).unwrap();
        assert_eq!((topo.misoriented_edges, topo.non_manifold_edges), (4, 4));
        assert_eq!(topo.boundary_edges, 0);
        for (a, b) in [(0, 1), (1, 3), (3, 2), (2, 0)] {
            assert!(!topo.edge(a, b).is_manifold());
            assert!(topo.is_non_manifold_vertex(a));
        }
        assert!(topo.edge(4, 5).is_manifold());
    }

    #[test]
    fn a_repeated_vertex_makes_a_degenerate_edge_of_its_own() {
        // A fan of four quads collapsed at the pole 4, each `a b 4 4`
        // (catmark_nonman_quadpole's faces): four degenerate edges, the
        // radial edges manifold, the pole non-manifold with one fan per face
        // pair across each radial edge.
        let mut positions: Vec<DVec3> = (0..4)
            .map(|k| {
                let t = k as f64 * std::f64::consts::FRAC_PI_2;
                DVec3::new(t.cos(), t.sin(), 0.0)
            })
            .collect();
        positions.push(DVec3::ZERO);
        let faces: Vec<Vec<usize>> = (0..4).map(|k| vec![k, (k + 1) % 4, 4, 4]).collect();
        let c = Cage {
            positions,
            face_lines: vec![None; 4],
            faces,
            ..Cage::default()
        };
        let topo = Topology::build(&c, Path::new("pole")).unwrap();
        assert_eq!(topo.degenerate_edges, 4);
        assert_eq!(topo.edges.len(), 4 + 4 + 4);
        assert_eq!(topo.valence(4), 4 + 2 * 4);
        assert!(topo.is_non_manifold_vertex(4));
        assert_eq!(topo.fans[4].len(), 4);
        assert!(topo.fans[4]
            .iter()
            .all(|f| f.corners.len() == 2 && !f.closed));
        assert!(topo.edge(1, 4).is_manifold());
        // A face that runs the same pair twice gets two edges.
        let c = Cage {
            positions: vec![DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z],
            faces: vec![vec![0, 1, 0, 2]],
            face_lines: vec![None],
            ..Cage::default()
        };
        let topo = Topology::build(&c, Path::new("fold")).unwrap();
        assert_eq!(topo.edges.len(), 4);
        assert!(topo.edges.iter().all(|e| !e.is_manifold()));
    }
}
