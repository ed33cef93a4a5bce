//! All-quad control cage → one bicubic Bézier patch per face, by Loop and
//! Schaefer's approximate Catmull–Clark surfaces ("ACC", 2008) with this
//! project's rules for boundaries, creases and corners. The rules are
//! listed in `obj.rs`'s module doc; this module is their implementation.
//!
//! Crack-freeness (DESIGN invariant 4) rests on one discipline: every point
//! that lies on a patch boundary — the corner points and the two edge points
//! near each end of every edge — is computed exactly once, rounded to f32
//! once, stored, and copied into every patch that uses it. Nothing on a
//! boundary is ever recomputed per face, so neighbours get the same bits,
//! whatever rule made the point.

use super::hash::IndexMap;
use std::path::Path;

use glam::{DVec3, Vec3};

use super::mesh::{Cage, Topology};
use super::sharpness::{self, Config, VertexRule};
use crate::input::SceneError;
use crate::patch::bezier::BezierPatch;

/// Rounds once to f32; +0.0 replaces -0.0.
fn round(p: DVec3) -> Vec3 {
    Vec3::new(p.x as f32, p.y as f32, p.z as f32) + Vec3::ZERO
}

/// The rule one corner of a patch was made with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CornerRule {
    /// The vertex rule with every feature of sharpness above 0 sharp.
    pub rule: VertexRule,
    /// Edges at the vertex.
    pub valence: u32,
    /// Faces in the patch's sector: between sharp edges, or all of them.
    pub sector: u32,
    /// A semi-sharp feature meets the vertex: the patch approximates.
    pub semi_sharp: bool,
}

impl CornerRule {
    /// The patch is exactly OpenSubdiv's limit surface near this corner
    /// when it is a regular smooth vertex, a crease with two faces on this
    /// side, or a corner with this face alone in its sector.
    pub fn is_regular(&self) -> bool {
        !self.semi_sharp
            && match self.rule {
                VertexRule::Smooth => self.valence == 4,
                VertexRule::Dart => false,
                VertexRule::Crease => self.sector == 2,
                VertexRule::Corner => self.sector == 1,
            }
    }
}

/// How one patch was made, for the sidecar and for tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchRule {
    /// At the patch's corners (0,0), (1,0), (1,1), (0,1).
    pub corners: [CornerRule; 4],
    /// Bit k: the edge from corner k to corner k + 1 is a feature edge
    /// (boundary, non-manifold, or a crease of sharpness ≥ 1): the surface
    /// may fold there and the shading normal may jump.
    pub feature_edges: u8,
}

impl PatchRule {
    /// The patch equals OpenSubdiv's limit surface (to f32 rounding).
    pub fn exact(&self) -> bool {
        self.corners.iter().all(CornerRule::is_regular)
    }

    /// The rule of the patch with u and v swapped: corners 1 and 3 trade
    /// places, and edge k (corner k to k + 1) becomes edge 3 − k reversed.
    pub fn flipped(&self) -> Self {
        let c = self.corners;
        let mut feature_edges = 0;
        for k in 0..4 {
            if self.feature_edges & (1 << (3 - k)) != 0 {
                feature_edges |= 1 << k;
            }
        }
        PatchRule {
            corners: [c[0], c[3], c[2], c[1]],
            feature_edges,
        }
    }

    /// One word for the sidecar and the deviation tables: `regular`,
    /// `crease` (boundaries included), `corner`, `extraordinary` (an
    /// irregular smooth vertex), `irregular-sharp` (dart, or a crease or
    /// corner with another number of faces), `semi-sharp`.
    pub fn class(&self) -> &'static str {
        let has = |r: VertexRule| self.corners.iter().any(|c| c.rule == r);
        if self.corners.iter().any(|c| c.semi_sharp) {
            "semi-sharp"
        } else if self.exact() {
            if has(VertexRule::Corner) {
                "corner"
            } else if has(VertexRule::Crease) {
                "crease"
            } else {
                "regular"
            }
        } else if self.corners.iter().all(|c| c.rule == VertexRule::Smooth) {
            "extraordinary"
        } else {
            "irregular-sharp"
        }
    }
}

/// A converted cage.
#[derive(Clone, Debug, Default)]
pub struct Conversion {
    /// One patch per face that is not a hole, in face order.
    pub patches: Vec<BezierPatch>,
    /// The cage face of each patch.
    pub faces: Vec<usize>,
    /// How each patch was made.
    pub rules: Vec<PatchRule>,
    /// The corner point of each vertex, as stored in the patches.
    pub corner: Vec<Vec3>,
    /// The edge point of each edge end `(near, far)`, as stored.
    pub edge_point: IndexMap<(usize, usize), Vec3>,
}

impl Conversion {
    /// The patch of each cage face that has one (holes have none).
    pub fn patch_of_face(&self) -> IndexMap<usize, usize> {
        self.faces
            .iter()
            .enumerate()
            .map(|(p, &f)| (f, p))
            .collect()
    }
}

/// A vertex's rule in one configuration and the far ends of its sharp
/// edges, in fan order.
struct Local {
    rule: VertexRule,
    ends: Vec<usize>,
}

fn local(cage: &Cage, topo: &Topology, v: usize, cfg: Config) -> Local {
    let mut ids: Vec<usize> = Vec::new();
    for fan in &topo.fans[v] {
        let mut consider = |e: usize| {
            if !ids.contains(&e) {
                ids.push(e);
            }
        };
        for &c in &fan.corners {
            consider(topo.incoming(c));
        }
        if let (false, Some(&last)) = (fan.closed, fan.corners.last()) {
            consider(topo.outgoing(last));
        }
    }
    let ends: Vec<usize> = ids
        .into_iter()
        .map(|e| &topo.edges[e])
        .filter(|e| cfg.sharp(cage.edge_sharpness(e.ends.0, e.ends.1)))
        .map(|e| e.other(v))
        .collect();
    let corner = cfg.sharp(cage.vertex_sharpness(v));
    Local {
        rule: VertexRule::of(corner, ends.len()),
        ends,
    }
}

/// Every control point of one configuration, in f64.
struct Points {
    inner: Vec<[DVec3; 4]>,
    corner: Vec<DVec3>,
    edge: IndexMap<(usize, usize), DVec3>,
}

fn points(
    cage: &Cage,
    topo: &Topology,
    cfg: Config,
    exact: &[Option<DVec3>],
) -> (Points, Vec<Local>) {
    let p = &cage.positions;
    let locals: Vec<Local> = (0..p.len()).map(|v| local(cage, topo, v, cfg)).collect();

    // Interior point of each face near each corner k (kept in f64: they are
    // private to the face, and edge points are averaged from them).
    let inner: Vec<[DVec3; 4]> = cage
        .faces
        .iter()
        .map(|face| {
            std::array::from_fn(|k| {
                let v = face[k];
                let (ea, eb, opp) = (face[(k + 3) % 4], face[(k + 1) % 4], face[(k + 2) % 4]);
                let n = if locals[v].rule.is_smooth() {
                    topo.valence(v) as f64
                } else {
                    4.0
                };
                (p[v] * n + p[ea] * 2.0 + p[eb] * 2.0 + p[opp]) / (n + 5.0)
            })
        })
        .collect();

    let corner: Vec<DVec3> = (0..p.len())
        .map(|v| match locals[v].rule {
            _ if exact[v].is_some() => exact[v].unwrap_or(p[v]),
            VertexRule::Corner => p[v],
            VertexRule::Crease => {
                let [a, b] = [locals[v].ends[0], locals[v].ends[1]];
                (p[a] + p[v] * 4.0 + p[b]) / 6.0
            }
            VertexRule::Smooth | VertexRule::Dart => match &topo.fans[v][..] {
                [fan] if fan.closed => {
                    let n = topo.valence(v) as f64;
                    let (mut edge_sum, mut diag_sum) = (DVec3::ZERO, DVec3::ZERO);
                    for &(f, k) in &fan.corners {
                        let face = &cage.faces[f];
                        edge_sum += p[face[(k + 1) % 4]];
                        diag_sum += p[face[(k + 2) % 4]];
                    }
                    (p[v] * (n * n) + edge_sum * 4.0 + diag_sum) / (n * (n + 5.0))
                }
                // Unreachable after `sharpness::resolve` (open and multiple
                // fans are bounded by sharp edges); kept total.
                _ => p[v],
            },
        })
        .collect();

    let mut edge = IndexMap::with_capacity_and_hasher(topo.edges.len() * 2, Default::default());
    for e in &topo.edges {
        let (a, b) = e.ends;
        let sharp = cfg.sharp(cage.edge_sharpness(a, b));
        for (near, far) in [(a, b), (b, a)] {
            let value = match (topo.half_edge(near, far), topo.half_edge(far, near)) {
                (Some((f, k)), Some((g, m))) if !sharp || locals[near].rule.is_smooth() => {
                    // `near` is corner k of f and corner m+1 of g.
                    (inner[f][k] + inner[g][(m + 1) % 4]) * 0.5
                }
                _ => (p[near] * 2.0 + p[far]) / 3.0,
            };
            edge.insert((near, far), value);
        }
    }
    (
        Points {
            inner,
            corner,
            edge,
        },
        locals,
    )
}

/// Converts an all-quad cage (validated into `topo`, sharpness resolved) to
/// one patch per face that is not a hole, in face order. Face (v0, v1, v2,
/// v3) gets its parameter origin at v0, u towards v1, v towards v3.
pub fn convert(cage: &Cage, topo: &Topology, path: &Path) -> Result<Conversion, SceneError> {
    convert_with(cage, topo, path, true)
}

/// [`convert`]; `exact_corners` false keeps OpenSubdiv's closed-form masks
/// at semi-sharp vertices, darts and valence 2 instead of refining their
/// rings to the limit (for a surface only sampled in between, `fit.rs`).
pub fn convert_with(
    cage: &Cage,
    topo: &Topology,
    path: &Path,
    exact_corners: bool,
) -> Result<Conversion, SceneError> {
    if let Some(f) = cage.faces.iter().position(|face| face.len() != 4) {
        return Err(SceneError::invalid(
            path,
            format!("internal: face {} is not a quad after refinement", f + 1),
        ));
    }
    let nv = cage.positions.len();
    let exact = exact_limits(cage, topo, exact_corners);
    let (blend, locals) = Blend::new(cage, topo, &exact);

    let corner: Vec<Vec3> = (0..nv)
        .map(|v| round(blend.point(v, &|pts| pts.corner[v])))
        .collect();
    let edge_point: IndexMap<(usize, usize), Vec3> = blend
        .sharp
        .edge
        .keys()
        .map(|&(near, far)| {
            (
                (near, far),
                round(blend.point(near, &|pts| pts.edge[&(near, far)])),
            )
        })
        .collect();
    let sector_of = sector_sizes(cage, topo);

    let mut out = Conversion {
        corner,
        edge_point,
        ..Conversion::default()
    };
    for (f, face) in cage.faces.iter().enumerate() {
        if cage.is_hole(f) {
            continue;
        }
        let patch = face_patch(&out, &blend, face, f);
        if !patch.is_finite() {
            let msg = "the patch of this face has a non-finite control point (coordinates too large for f32?)";
            return Err(match cage.line_of(f) {
                Some(line) => SceneError::at(path, line, msg),
                None => SceneError::invalid(path, format!("face {}: {msg}", f + 1)),
            });
        }
        let rule = patch_rule(cage, topo, &locals, &sector_of, face, f);
        out.patches.push(patch);
        out.faces.push(f);
        out.rules.push(rule);
    }
    Ok(out)
}

/// Each vertex's limit position where no closed-form mask gives it
/// (semi-sharp features, darts, valence 2): its one-ring refined to the
/// limit (`limit.rs`); `None` elsewhere, or everywhere without
/// `exact_corners`.
fn exact_limits(cage: &Cage, topo: &Topology, exact_corners: bool) -> Vec<Option<DVec3>> {
    (0..cage.positions.len())
        .map(|v| {
            (exact_corners && super::limit::needs_iteration(cage, topo, v))
                .then(|| super::limit::limit_position(cage, topo, v))
                .flatten()
        })
        .collect()
}

/// The control points of the sharp configuration and, where some feature
/// has sharpness below 1, of the soft one, with each vertex's weight
/// between them.
struct Blend {
    /// Every point with features of sharpness below 1 taken as sharp.
    sharp: Points,
    /// Every point with them taken as smooth, when there are any.
    smooth: Option<Points>,
    /// Per vertex: the weight of the sharp configuration, for a vertex with
    /// features of sharpness below 1.
    weight: Vec<Option<f64>>,
}

impl Blend {
    /// Both configurations' points of `cage` and the sharp configuration's
    /// vertex rules.
    fn new(cage: &Cage, topo: &Topology, exact: &[Option<DVec3>]) -> (Self, Vec<Local>) {
        let nv = cage.positions.len();
        let (sharp, locals) = points(cage, topo, Config::Sharp, exact);
        // Features of sharpness below 1: the points near such a vertex are the
        // soft configuration's moved towards the sharp one's by its weight.
        let weight: Vec<Option<f64>> = (0..nv)
            .map(|v| sharpness::fractional_weight(cage, topo, v))
            .collect();
        let smooth = weight
            .iter()
            .any(Option::is_some)
            .then(|| points(cage, topo, Config::Soft, exact).0);
        (
            Blend {
                sharp,
                smooth,
                weight,
            },
            locals,
        )
    }

    /// The point `pick` near vertex `v`: the sharp configuration's, or the
    /// soft one's moved towards it by `v`'s weight.
    fn point(&self, v: usize, pick: &dyn Fn(&Points) -> DVec3) -> DVec3 {
        let hard = pick(&self.sharp);
        match (self.weight[v], &self.smooth) {
            (Some(w), Some(soft)) => {
                let soft = pick(soft);
                soft + (hard - soft) * w
            }
            _ => hard,
        }
    }
}

/// Sector sizes for the rules report, cutting fans at every sharp edge: per
/// face corner (face, k), the faces in its sector.
fn sector_sizes(cage: &Cage, topo: &Topology) -> IndexMap<(usize, usize), u32> {
    let mut sector_of: IndexMap<(usize, usize), u32> = IndexMap::default();
    for v in 0..cage.positions.len() {
        let is_sharp = |e: usize| {
            let (a, b) = topo.edges[e].ends;
            cage.edge_sharpness(a, b) > 0.0
        };
        for s in sharpness::sectors(topo, v, &is_sharp) {
            for &c in &s.corners {
                sector_of.insert(c, s.corners.len() as u32);
            }
        }
    }
    sector_of
}

/// The patch of quad `f` (`face`): the shared corner and edge points of
/// `out`, its own interior points.
fn face_patch(out: &Conversion, blend: &Blend, face: &[usize], f: usize) -> BezierPatch {
    let [v0, v1, v2, v3] = [face[0], face[1], face[2], face[3]];
    let e = |a: usize, b: usize| out.edge_point[&(a, b)];
    let i = |k: usize| round(blend.point(face[k], &|pts| pts.inner[f][k]));
    let c = |v: usize| out.corner[v];
    #[rustfmt::skip]
    let pts = [
        c(v0),     e(v0, v1), e(v1, v0), c(v1),
        e(v0, v3), i(0),      i(1),      e(v1, v2),
        e(v3, v0), i(3),      i(2),      e(v2, v1),
        c(v3),     e(v3, v2), e(v2, v3), c(v2),
    ];
    BezierPatch { pts }.canonical_zeros()
}

/// How the patch of quad `f` (`face`) was made: its corners' rules and its
/// feature edges.
fn patch_rule(
    cage: &Cage,
    topo: &Topology,
    locals: &[Local],
    sector_of: &IndexMap<(usize, usize), u32>,
    face: &[usize],
    f: usize,
) -> PatchRule {
    let corners = std::array::from_fn(|k| CornerRule {
        rule: locals[face[k]].rule,
        valence: topo.valence(face[k]) as u32,
        sector: sector_of.get(&(f, k)).copied().unwrap_or(0),
        semi_sharp: sharpness::has_semi_sharp(cage, topo, face[k]),
    });
    let mut feature_edges = 0u8;
    for k in 0..4 {
        if is_feature_edge(cage, topo, face[k], face[(k + 1) % 4]) {
            feature_edges |= 1 << k;
        }
    }
    PatchRule {
        corners,
        feature_edges,
    }
}

/// Whether the edge `(a, b)` of `cage` is a feature edge (see
/// [`PatchRule::feature_edges`]).
pub fn is_feature_edge(cage: &Cage, topo: &Topology, a: usize, b: usize) -> bool {
    cage.edge_sharpness(a, b) >= 1.0 || !topo.edge(a, b).is_manifold()
}
