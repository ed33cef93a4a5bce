//! Creases, corners and boundary rules: which edges and vertices of a cage
//! are sharp, and which Catmull–Clark vertex rule follows, as OpenSubdiv
//! decides them (Sdc with uniform creasing).
//!
//! - Sharpness 0 is smooth; [`INFINITE`] (10) and above is infinitely sharp;
//!   anything between is semi-sharp: sharp for that many subdivision steps,
//!   then smooth (a fraction blends the last step).
//! - The boundary rule (`t interpolateboundary`, or the model's option) is
//!   turned into explicit sharpness before anything else ([`resolve`]):
//!   boundary edges and non-manifold edges become infinitely sharp;
//!   `edge-and-corner` also makes every vertex with one face and two edges an
//!   infinitely sharp corner; `none` turns every face at a boundary vertex
//!   into a hole (no patch) unless all of that vertex's boundary edges are
//!   tagged infinitely sharp. A non-manifold vertex becomes an infinitely
//!   sharp corner, except along a non-manifold crease (exactly two
//!   non-manifold edges, no boundary edge, more faces than edges), where the
//!   sheets share a crease curve.
//! - The vertex rule counts the sharp edges at a vertex: corner when the
//!   vertex itself is sharp or three or more edges are, crease for two, dart
//!   for one, smooth for none.

use std::fmt;

use super::mesh::{Cage, Topology};

/// Infinitely sharp, as OpenSubdiv's `Sdc::Crease::SHARPNESS_INFINITE`.
pub const INFINITE: f64 = 10.0;

/// How boundary edges and corners are interpolated (OpenSubdiv's
/// `VtxBoundaryInterpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BoundaryRule {
    /// Faces at the boundary are not part of the surface.
    None,
    /// Boundary edges are sharp creases; cage corners are smoothed.
    EdgeOnly,
    /// Boundary edges are sharp creases; cage corners are kept.
    EdgeAndCorner,
}

/// The rule for cages that neither tag one nor get one from the scene or the
/// command line: boundary curves through the boundary vertices' B-spline,
/// cage corners kept where they are (Blender's "keep corners", Maya's "sharp
/// edges and corners", and what this project always did).
pub const DEFAULT_BOUNDARY: BoundaryRule = BoundaryRule::EdgeAndCorner;

impl BoundaryRule {
    /// The names users write: `none`, `edge-only`, `edge-and-corner`.
    pub const NAMES: [&'static str; 3] = ["none", "edge-only", "edge-and-corner"];

    /// The name users write.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryRule::None => Self::NAMES[0],
            BoundaryRule::EdgeOnly => Self::NAMES[1],
            BoundaryRule::EdgeAndCorner => Self::NAMES[2],
        }
    }

    /// From OpenSubdiv's integer in `t interpolateboundary 1/0/0 N`.
    pub fn from_tag(n: i64) -> Option<Self> {
        match n {
            0 => Some(BoundaryRule::None),
            1 => Some(BoundaryRule::EdgeAndCorner),
            2 => Some(BoundaryRule::EdgeOnly),
            _ => None,
        }
    }
}

impl fmt::Display for BoundaryRule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for BoundaryRule {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(BoundaryRule::None),
            "edge-only" => Ok(BoundaryRule::EdgeOnly),
            "edge-and-corner" => Ok(BoundaryRule::EdgeAndCorner),
            _ => Err(format!(
                "unknown boundary rule {s:?}: expected one of {}",
                Self::NAMES.join(", ")
            )),
        }
    }
}

impl<'de> serde::Deserialize<'de> for BoundaryRule {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let s = String::deserialize(d)?;
        s.parse().map_err(serde::de::Error::custom)
    }
}

/// What [`resolve`] did, for the import summary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Resolved {
    /// Faces made holes by the `none` rule.
    pub holes: usize,
    /// Cage corners (one face, two edges) made sharp by `edge-and-corner`.
    pub sharpened_corners: usize,
    /// Non-manifold vertices made sharp corners.
    pub non_manifold_corners: usize,
}

/// Applies `rule` and the non-manifold rules to `cage` as explicit
/// sharpness and holes (see the module doc). Run once, on the cage as read:
/// a refined cage inherits the result.
pub fn resolve(cage: &mut Cage, topo: &Topology, rule: BoundaryRule) -> Resolved {
    let mut out = Resolved::default();
    let nv = cage.positions.len();
    if rule == BoundaryRule::None {
        let mut holes = vec![false; cage.faces.len()];
        for v in 0..nv {
            let open = topo.vertex_edges[v].iter().any(|&e| {
                let edge = &topo.edges[e];
                edge.uses.len() == 1 && cage.edge_sharpness(edge.ends.0, edge.ends.1) < INFINITE
            });
            if open {
                for fan in &topo.fans[v] {
                    for &(f, _) in &fan.corners {
                        holes[f] = true;
                    }
                }
            }
        }
        out.holes = holes.iter().filter(|&&h| h).count();
        if out.holes > 0 {
            // On top of the faces `t hole` left out.
            cage.holes.resize(holes.len(), false);
            for (h, new) in cage.holes.iter_mut().zip(holes) {
                *h |= new;
            }
        }
    }
    for e in &topo.edges {
        if !e.is_manifold() {
            let (a, b) = e.ends;
            cage.edge_sharpness.insert((a.min(b), a.max(b)), INFINITE);
        }
    }
    for v in 0..nv {
        let faces = topo.face_count(v);
        let edges = topo.valence(v);
        if faces == 1 && edges == 2 && rule == BoundaryRule::EdgeAndCorner {
            if cage.vertex_sharpness(v) < INFINITE {
                cage.vertex_sharpness.insert(v, INFINITE);
                out.sharpened_corners += 1;
            }
            continue;
        }
        if topo.is_non_manifold_vertex(v) {
            // OpenSubdiv's counts: a degenerate edge is listed twice and is
            // both a boundary (one face) and non-manifold.
            let count = |pred: &dyn Fn(&super::mesh::Edge) -> bool| {
                topo.vertex_edges[v]
                    .iter()
                    .filter(|&&e| pred(&topo.edges[e]))
                    .count()
            };
            let non_manifold = count(&|e| e.non_manifold);
            let boundary = count(&|e| e.uses.len() == 1);
            let crease = non_manifold == 2 && boundary == 0 && faces > edges;
            if !crease && cage.vertex_sharpness(v) < INFINITE {
                cage.vertex_sharpness.insert(v, INFINITE);
                out.non_manifold_corners += 1;
            }
        }
    }
    out
}

/// Catmull–Clark's vertex rules.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VertexRule {
    /// No sharp edge: the smooth rule.
    Smooth,
    /// One sharp edge: still the smooth rule.
    Dart,
    /// Two sharp edges: the vertex moves along the crease curve.
    Crease,
    /// A sharp vertex or three or more sharp edges: it stays where it is.
    Corner,
}

impl VertexRule {
    /// From the vertex's own sharpness and its number of sharp edges.
    pub fn of(vertex_sharp: bool, sharp_edges: usize) -> Self {
        match (vertex_sharp, sharp_edges) {
            (true, _) | (_, 3..) => VertexRule::Corner,
            (false, 2) => VertexRule::Crease,
            (false, 1) => VertexRule::Dart,
            (false, _) => VertexRule::Smooth,
        }
    }

    /// Whether the smooth rule applies (smooth or dart).
    pub fn is_smooth(self) -> bool {
        matches!(self, VertexRule::Smooth | VertexRule::Dart)
    }

    /// Lower-case name for the sidecar.
    pub fn name(self) -> &'static str {
        match self {
            VertexRule::Smooth => "smooth",
            VertexRule::Dart => "dart",
            VertexRule::Crease => "crease",
            VertexRule::Corner => "corner",
        }
    }
}

/// Which sharpness counts as sharp when the converter evaluates its rules.
/// A semi-sharp feature of sharpness s ≥ 1 is converted as sharp; one below
/// 1 is computed both ways and blended (see [`fractional_weight`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Config {
    /// Every feature with sharpness above 0 is sharp.
    Sharp,
    /// Only features of sharpness 1 or more are.
    Soft,
}

impl Config {
    /// Whether sharpness `s` counts as sharp in this configuration.
    pub fn sharp(self, s: f64) -> bool {
        match self {
            Config::Sharp => s > 0.0,
            Config::Soft => s >= 1.0,
        }
    }
}

/// Whether `s` is semi-sharp (strictly between smooth and infinite).
pub fn is_semi_sharp(s: f64) -> bool {
    s > 0.0 && s < INFINITE
}

/// Whether anything at `v` (the vertex or an edge) is semi-sharp: there the
/// patches approximate OpenSubdiv's surface (see `obj.rs`).
pub fn has_semi_sharp(cage: &Cage, topo: &Topology, v: usize) -> bool {
    is_semi_sharp(cage.vertex_sharpness(v))
        || topo.vertex_edges[v].iter().any(|&e| {
            let (a, b) = topo.edges[e].ends;
            is_semi_sharp(cage.edge_sharpness(a, b))
        })
}

/// How much of the sharp rule the points near `v` get where features of
/// sharpness below 1 meet it: the mean of those sharpness values (vertex
/// and edges), as OpenSubdiv weighs a rule that runs out within one step.
/// `None` when there is no such feature at `v`.
pub fn fractional_weight(cage: &Cage, topo: &Topology, v: usize) -> Option<f64> {
    let fractional = |s: f64| s > 0.0 && s < 1.0;
    let mut sum = 0.0;
    let mut n = 0usize;
    let own = cage.vertex_sharpness(v);
    if fractional(own) {
        sum += own;
        n += 1;
    }
    for &e in &topo.vertex_edges[v] {
        let (a, b) = topo.edges[e].ends;
        let s = cage.edge_sharpness(a, b);
        if fractional(s) {
            sum += s;
            n += 1;
        }
    }
    (n > 0).then(|| sum / n as f64)
}

/// A run of faces around a vertex between sharp edges, or a whole closed
/// fan without them.
#[derive(Clone, Debug)]
pub struct Sector {
    /// (face, corner) pairs in fan order.
    pub corners: Vec<(usize, usize)>,
    /// Edge ids: for an open sector the `corners.len() + 1` edges from the
    /// first corner's incoming edge to the last one's outgoing edge; for a
    /// cyclic one the incoming edge of each corner.
    pub edges: Vec<usize>,
    /// A closed fan with fewer than two sharp edges (smooth or dart vertex).
    pub cyclic: bool,
}

/// The sectors of `v`, cutting its fans at edges for which `sharp` holds.
/// A closed fan with fewer than two such edges stays one cyclic sector: a
/// dart's crease ends at the vertex, which is smooth.
pub fn sectors(topo: &Topology, v: usize, sharp: &dyn Fn(usize) -> bool) -> Vec<Sector> {
    let mut out = Vec::new();
    for fan in &topo.fans[v] {
        let incoming: Vec<usize> = fan.corners.iter().map(|&c| topo.incoming(c)).collect();
        let cuts = incoming.iter().filter(|&&e| sharp(e)).count();
        if fan.closed && cuts < 2 {
            out.push(Sector {
                corners: fan.corners.clone(),
                edges: incoming,
                cyclic: true,
            });
            continue;
        }
        // Start where a sector starts: the fan's own start when open,
        // otherwise the first corner behind a sharp edge.
        let n = fan.corners.len();
        let start = if fan.closed {
            (0..n).find(|&i| sharp(incoming[i])).unwrap_or(0)
        } else {
            0
        };
        let mut current: Option<Sector> = None;
        for step in 0..n {
            let i = (start + step) % n;
            let c = fan.corners[i];
            if step == 0 || sharp(incoming[i]) {
                if let Some(s) = current.take() {
                    out.push(s);
                }
                current = Some(Sector {
                    corners: Vec::new(),
                    edges: vec![incoming[i]],
                    cyclic: false,
                });
            }
            let s = current.as_mut().expect("a sector is open");
            s.corners.push(c);
            s.edges.push(topo.outgoing(c));
        }
        out.extend(current);
    }
    out
}
