//! Stencil tables: a converted cage as a fixed linear map of its vertices.
//!
//! For a fixed topology and tag set, the conversion of a cage to Bézier
//! patches (`refine.rs`, `acc.rs`, `limit.rs`, `fit.rs`) is linear in the
//! cage's vertex positions: every rule is a weighted sum whose weights
//! follow from valences, sharpness and sample parameters, never from where
//! the vertices are. So each control point is a fixed combination of cage
//! vertices, and an animated cage (a deformer, an OBJ sequence) can be
//! converted every frame by evaluating those combinations, on the GPU
//! (`glsl/anim_*.comp`) and on the CPU (this module) in the same f32
//! operations.
//!
//! # How the combinations are found
//!
//! By *probing* the conversion, not by writing its rules a second time: the
//! conversion is run on cages whose vertices are unit vectors in one
//! coordinate or zero, and each output then reads off the weight of the
//! vertex that lit it. Vertices far enough apart to share no output are lit
//! in the same run (a greedy colouring of the cage, three colours per run,
//! one per coordinate), so a cage takes a few tens of runs, not one per
//! vertex. This follows whatever the conversion computes, now and after it
//! changes, and needs nothing of it but linearity, which is checked: an
//! output lit where no vertex of that colour may reach it, or a table that
//! does not reproduce the conversion of the cage as loaded (within f32
//! rounding), widens the assumed reach and probes again, and fails the
//! import with a sentence past that. Anything that depends on positions is
//! decided once, from the cage as loaded: which closed parts are inside out
//! (`orient.rs`) and the shading construction's fits (`tangent.rs`).
//! Making the conversion generic over its point type would have found the
//! same weights in one run, at the price of rewriting every rule's code
//! around a second number type.
//!
//! # The tables
//!
//! - **Point rows**: one per distinct control point. A point that lies on a
//!   patch boundary is computed once by the conversion and copied into
//!   every patch on it (DESIGN invariant 4), so its probed combination is
//!   one and the same, and it gets one row, evaluated once per frame and
//!   read by every patch that uses it: neighbours get the same bits in
//!   every frame by construction. Rows are kept in the *reference form*
//!   x_r + Σₖ wₖ·(xₖ − x_r), x_r the vertex of the largest weight (the
//!   weights sum to 1): a point that is a vertex copies it exactly, and the
//!   rounding follows the size of the neighbourhood, not the distance from
//!   the origin.
//! - **Shading rows**: the 24 tangent vectors of each patch as combinations
//!   of point rows (`tangent::recipe`), Σₖ cₖ·(xₖ − x_r) (the coefficients
//!   sum to 0).
//!
//! Evaluation order, the contract with `glsl/common/anim.glsl`: per row,
//! an accumulator starts at +0 and adds wₖ·(xₖ − x_r) term by term in
//! stored order, per coordinate (one subtraction, one multiplication, one
//! addition, no fused multiply-add); a point row then adds x_r. Weights are
//! f32.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec3, Vec3};

use super::acc::Conversion;
use super::linear::Comb;
use super::mesh::{Cage, Topology};
use super::tangent;
use crate::input::SceneError;
use crate::patch::bezier::BezierPatch;
use crate::patch::shading::ShadingPatch;

/// Rows of combinations in the reference form, compressed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Table {
    /// Per row, its first term; one more entry for the end.
    pub starts: Vec<u32>,
    /// Per row, the input it is relative to.
    pub refs: Vec<u32>,
    /// Per term, its input.
    pub index: Vec<u32>,
    /// Per term, its weight.
    pub weight: Vec<f32>,
}

/// Bytes of one term (input, weight) and of one row (start, reference) on
/// the GPU.
pub const TERM_BYTES: usize = 8;
/// See [`TERM_BYTES`].
pub const ROW_BYTES: usize = 8;

impl Table {
    /// Rows.
    pub fn rows(&self) -> usize {
        self.refs.len()
    }

    /// Terms of all rows.
    pub fn terms(&self) -> usize {
        self.index.len()
    }

    /// Bytes on the GPU.
    pub fn bytes(&self) -> usize {
        self.rows() * ROW_BYTES + self.terms() * TERM_BYTES
    }

    fn push(&mut self, reference: u32, terms: &[(u32, f32)]) -> u32 {
        if self.starts.is_empty() {
            self.starts.push(0);
        }
        self.refs.push(reference);
        for &(i, w) in terms {
            self.index.push(i);
            self.weight.push(w);
        }
        self.starts.push(self.index.len() as u32);
        self.refs.len() as u32 - 1
    }

    /// Row `r`: its reference and terms.
    pub fn row(&self, r: usize) -> (u32, impl Iterator<Item = (u32, f32)> + '_) {
        let (a, b) = (self.starts[r] as usize, self.starts[r + 1] as usize);
        (
            self.refs[r],
            self.index[a..b]
                .iter()
                .copied()
                .zip(self.weight[a..b].iter().copied()),
        )
    }

    /// Σ wₖ·(xₖ − x_r) of row `r`, in the GPU's order.
    fn sum(&self, r: usize, x: &[Vec3]) -> (Vec3, Vec3) {
        let (reference, terms) = self.row(r);
        let base = x[reference as usize];
        let (mut ax, mut ay, mut az) = (0.0f32, 0.0f32, 0.0f32);
        for (i, w) in terms {
            let p = x[i as usize];
            ax += (p.x - base.x) * w;
            ay += (p.y - base.y) * w;
            az += (p.z - base.z) * w;
        }
        (base, Vec3::new(ax, ay, az))
    }

    /// Every row as a point: x_r + Σ wₖ·(xₖ − x_r).
    pub fn points(&self, x: &[Vec3]) -> Vec<Vec3> {
        (0..self.rows())
            .map(|r| {
                let (b, a) = self.sum(r, x);
                Vec3::new(b.x + a.x, b.y + a.y, b.z + a.z)
            })
            .collect()
    }

    /// Every row as a vector: Σ cₖ·(xₖ − x_r).
    pub fn vectors(&self, x: &[Vec3]) -> Vec<Vec3> {
        (0..self.rows()).map(|r| self.sum(r, x).1).collect()
    }

    /// Appends `other`, its inputs renamed by `input`.
    fn append(&mut self, other: &Table, input: &dyn Fn(u32) -> u32) {
        for r in 0..other.rows() {
            let (reference, terms) = other.row(r);
            let terms: Vec<(u32, f32)> = terms.map(|(i, w)| (input(i), w)).collect();
            self.push(input(reference), &terms);
        }
    }
}

/// The stencils of one converted cage: its patches and shading patches as
/// functions of its vertices.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CageStencils {
    /// Cage vertices (the inputs), in the cage's order.
    pub vertices: usize,
    /// Point rows over cage vertices.
    pub points: Table,
    /// Per patch, the point row of each control point.
    pub patch_rows: Vec<[u32; 16]>,
    /// 24 rows per patch, in patch order (`ShadingPatch`'s ∂u then ∂v),
    /// over point rows.
    pub shading: Table,
}

impl CageStencils {
    /// Patches.
    pub fn patches(&self) -> usize {
        self.patch_rows.len()
    }

    /// Bytes on the GPU: both tables and the patches' row indices.
    pub fn bytes(&self) -> usize {
        self.points.bytes() + self.shading.bytes() + self.patch_rows.len() * 16 * 4
    }

    /// The patches and shading patches of the cage posed at `cage`.
    pub fn evaluate(&self, cage: &[Vec3]) -> (Vec<BezierPatch>, Vec<ShadingPatch>) {
        let points = self.points.points(cage);
        let vectors = self.shading.vectors(&points);
        let patches = self
            .patch_rows
            .iter()
            .map(|rows| BezierPatch {
                pts: rows.map(|r| points[r as usize]),
            })
            .collect();
        let shading = vectors
            .chunks_exact(24)
            .map(|v| ShadingPatch {
                du: std::array::from_fn(|n| v[n]),
                dv: std::array::from_fn(|n| v[12 + n]),
            })
            .collect();
        (patches, shading)
    }

    /// The patches `flip` marks with u and v swapped (`orient::flip_patch`,
    /// and their shading patches `ShadingPatch::transposed`): their rows
    /// are reordered as those reorder the points.
    pub fn flip(&mut self, flip: &[bool]) {
        if !flip.iter().any(|&f| f) {
            return;
        }
        let tag = |k: usize| Vec3::new(k as f32, 0.0, 0.0);
        let points = super::orient::flip_patch(&BezierPatch {
            pts: std::array::from_fn(tag),
        })
        .pts
        .map(|q| q.x as usize);
        let shading = ShadingPatch {
            du: std::array::from_fn(tag),
            dv: std::array::from_fn(|n| tag(12 + n)),
        }
        .transposed();
        let vectors: Vec<usize> = shading
            .du
            .iter()
            .chain(&shading.dv)
            .map(|q| q.x as usize)
            .collect();
        let mut table = Table::default();
        for (p, rows) in self.patch_rows.iter_mut().enumerate() {
            let turned = flip.get(p).copied().unwrap_or(false);
            if turned {
                let old = *rows;
                *rows = points.map(|k| old[k]);
            }
            for (k, &turn) in vectors.iter().enumerate() {
                let from = if turned { turn } else { k };
                let (reference, terms) = self.shading.row(24 * p + from);
                let terms: Vec<(u32, f32)> = terms.collect();
                table.push(reference, &terms);
            }
        }
        self.shading = table;
    }

    /// Joins the stencils of the parts of a cage: `parts` holds each
    /// part's stencils and the cage vertex of each of its vertices;
    /// `order` lists the patches of the result as (part, patch).
    pub fn join(
        vertices: usize,
        parts: &[(CageStencils, Vec<usize>)],
        order: &[(usize, usize)],
    ) -> CageStencils {
        let mut out = CageStencils {
            vertices,
            ..Default::default()
        };
        let mut row_base = Vec::new();
        for (s, map) in parts {
            row_base.push(out.points.rows() as u32);
            out.points.append(&s.points, &|i| map[i as usize] as u32);
        }
        for &(part, p) in order {
            let s = &parts[part].0;
            let base = row_base[part];
            out.patch_rows.push(s.patch_rows[p].map(|r| r + base));
            for k in 0..24 {
                let (reference, terms) = s.shading.row(24 * p + k);
                let terms: Vec<(u32, f32)> = terms.map(|(i, w)| (i + base, w)).collect();
                out.shading.push(reference + base, &terms);
            }
        }
        out
    }
}

/// A cage model as animation needs it: its stencils, its vertices as
/// loaded (the rest pose), and how they come from the file (another frame
/// of an OBJ sequence must have the same faces).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CageModel {
    /// The stencils of its patches.
    pub stencils: CageStencils,
    /// The cage's vertices as loaded.
    pub rest: Vec<Vec3>,
    /// The file vertex (0-based `v` statement) of each cage vertex.
    pub file_vertex: Vec<usize>,
    /// The file's faces: the 0-based `v` statement of each corner of each
    /// `f` statement.
    pub file_faces: Vec<Vec<usize>>,
    /// The file's `v` statements.
    pub file_vertices: usize,
}

impl CageModel {
    /// A patch file's patches as a "cage" of their distinct control points
    /// (shared boundary points, found by their bits, are one vertex): every
    /// point row one vertex, the shading rows the patches' own derivative
    /// nets (`ShadingPatch::from_geometry`, to the bit). So patch models
    /// animate by moving their control points.
    pub fn for_patches(patches: &[BezierPatch]) -> Self {
        let mut index: HashMap<[u32; 3], u32> = HashMap::new();
        let mut rest = Vec::new();
        let mut stencils = CageStencils::default();
        for p in patches {
            let rows = p.pts.map(|q| {
                *index
                    .entry(q.to_array().map(f32::to_bits))
                    .or_insert_with(|| {
                        rest.push(q);
                        stencils.points.push(rest.len() as u32 - 1, &[])
                    })
            });
            stencils.patch_rows.push(rows);
            let diff = |a: usize, b: usize| -> (u32, Vec<(u32, f32)>) {
                let (ra, rb) = (rows[a], rows[b]);
                if ra == rb {
                    return (ra, Vec::new());
                }
                // The reference form's reference is the lower input of two
                // equal weights: 3·(a − b) is −3·(b − a) to the bit.
                if ra < rb {
                    (ra, vec![(rb, -3.0)])
                } else {
                    (rb, vec![(ra, 3.0)])
                }
            };
            for n in 0..12 {
                let (i, j) = (n % 3, n / 3);
                let (r, t) = diff(4 * j + i + 1, 4 * j + i);
                stencils.shading.push(r, &t);
            }
            for n in 0..12 {
                let (i, j) = (n % 4, n / 4);
                let (r, t) = diff(4 * (j + 1) + i, 4 * j + i);
                stencils.shading.push(r, &t);
            }
        }
        stencils.vertices = rest.len();
        CageModel {
            stencils,
            file_vertex: (0..rest.len()).collect(),
            file_vertices: rest.len(),
            rest,
            file_faces: Vec::new(),
        }
    }
}

/// Where `acc.rs` puts a face's corner and edge points in its patch, face
/// (v0, v1, v2, v3): (slot, the corner's vertex k) and (slot, the edge
/// point's (near, far) corners). Only used to find most of the points the
/// shading construction reads among the patches' own (checked bit for bit
/// against the conversion; any other is probed as an output of its own).
const CORNER_SLOTS: [(usize, usize); 4] = [(0, 0), (3, 1), (15, 2), (12, 3)];
/// See [`CORNER_SLOTS`].
const EDGE_SLOTS: [(usize, (usize, usize)); 8] = [
    (1, (0, 1)),
    (2, (1, 0)),
    (4, (0, 3)),
    (7, (1, 2)),
    (8, (3, 0)),
    (11, (2, 1)),
    (13, (3, 2)),
    (14, (2, 3)),
];

/// Names of the conversion's outputs: every control point of every patch,
/// then the corner and edge points the shading construction reads that no
/// patch holds (next to holes).
struct Outputs {
    patches: usize,
    /// Corners and edge points of their own, after the patches' points.
    extra: Vec<Key>,
    corner_id: HashMap<usize, u32>,
    edge_id: HashMap<(usize, usize), u32>,
}

#[derive(Clone, Copy)]
enum Key {
    Corner(usize),
    Edge(usize, usize),
}

impl Outputs {
    fn new(cage: &Cage, fine: &Topology, conv: &Conversion) -> Self {
        let patches = conv.patches.len();
        let mut corner_id: HashMap<usize, u32> = HashMap::new();
        let mut edge_id: HashMap<(usize, usize), u32> = HashMap::new();
        for (p, &f) in conv.faces.iter().enumerate() {
            let face = &cage.faces[f];
            let pts = &conv.patches[p].pts;
            for (slot, k) in CORNER_SLOTS {
                let v = face[k];
                if pts[slot].to_array().map(f32::to_bits)
                    == conv.corner[v].to_array().map(f32::to_bits)
                {
                    corner_id.entry(v).or_insert((16 * p + slot) as u32);
                }
            }
            for (slot, (a, b)) in EDGE_SLOTS {
                let e = (face[a], face[b]);
                let same = conv.edge_point.get(&e).is_some_and(|q| {
                    q.to_array().map(f32::to_bits) == pts[slot].to_array().map(f32::to_bits)
                });
                if same {
                    edge_id.entry(e).or_insert((16 * p + slot) as u32);
                }
            }
        }
        let mut extra = Vec::new();
        for v in 0..conv.corner.len() {
            if !fine.fans[v].is_empty() && !corner_id.contains_key(&v) {
                corner_id.insert(v, (16 * patches + extra.len()) as u32);
                extra.push(Key::Corner(v));
            }
        }
        let mut edges: Vec<(usize, usize)> = conv.edge_point.keys().copied().collect();
        edges.sort_unstable();
        for e in edges {
            if let std::collections::hash_map::Entry::Vacant(slot) = edge_id.entry(e) {
                slot.insert((16 * patches + extra.len()) as u32);
                extra.push(Key::Edge(e.0, e.1));
            }
        }
        Outputs {
            patches,
            extra,
            corner_id,
            edge_id,
        }
    }

    fn len(&self) -> usize {
        16 * self.patches + self.extra.len()
    }

    fn values(&self, conv: &Conversion) -> Vec<Vec3> {
        let mut out: Vec<Vec3> = conv.patches.iter().flat_map(|p| p.pts).collect();
        out.extend(self.extra.iter().map(|&k| match k {
            Key::Corner(v) => conv.corner[v],
            Key::Edge(a, b) => conv.edge_point[&(a, b)],
        }));
        out
    }

    /// The fine faces output `id` belongs to.
    fn faces(&self, id: usize, fine: &Topology, conv: &Conversion) -> Vec<usize> {
        if id < 16 * self.patches {
            return vec![conv.faces[id / 16]];
        }
        let fan_faces = |v: usize| -> Vec<usize> {
            fine.fans[v]
                .iter()
                .flat_map(|f| f.corners.iter().map(|c| c.0))
                .collect()
        };
        match self.extra[id - 16 * self.patches] {
            Key::Corner(v) => fan_faces(v),
            Key::Edge(a, b) => match fine.edge_id(a, b) {
                Some(e) => fine.edges[e].uses.iter().map(|u| u.0).collect(),
                None => fan_faces(a),
            },
        }
    }
}

/// The cage vertices within `rings` face rings of each face of `cage`
/// (faces sharing a vertex are one ring apart), sorted.
fn reach(cage: &Cage, topo: &Topology, rings: u32) -> Vec<Vec<u32>> {
    let faces_of = |v: usize| -> Vec<usize> {
        topo.fans[v]
            .iter()
            .flat_map(|f| f.corners.iter().map(|c| c.0))
            .collect()
    };
    let mut vertex_faces: Vec<Vec<usize>> = (0..cage.positions.len()).map(faces_of).collect();
    for (f, face) in cage.faces.iter().enumerate() {
        for &v in face {
            if !vertex_faces[v].contains(&f) {
                vertex_faces[v].push(f);
            }
        }
    }
    (0..cage.faces.len())
        .map(|f| {
            let mut faces = vec![f];
            let mut seen = std::collections::HashSet::from([f]);
            let mut frontier = vec![f];
            for _ in 0..rings {
                let mut next = Vec::new();
                for &g in &frontier {
                    for &v in &cage.faces[g] {
                        for &h in &vertex_faces[v] {
                            if seen.insert(h) {
                                next.push(h);
                                faces.push(h);
                            }
                        }
                    }
                }
                frontier = next;
            }
            let mut vs: Vec<u32> = faces
                .iter()
                .flat_map(|&g| cage.faces[g].iter().map(|&v| v as u32))
                .collect();
            vs.sort_unstable();
            vs.dedup();
            vs
        })
        .collect()
}

/// A colouring of the vertices such that no two vertices of one candidate
/// set share a colour (DSATUR: the next vertex is the one with the most
/// distinct colours among its neighbours); returns the colours and their
/// number.
fn colour(vertices: usize, sets: &[Vec<u32>]) -> (Vec<u32>, u32) {
    let mut member: Vec<Vec<u32>> = vec![Vec::new(); vertices];
    for (s, set) in sets.iter().enumerate() {
        for &v in set {
            member[v as usize].push(s as u32);
        }
    }
    // Neighbours: the vertices sharing a set.
    let neighbours: Vec<Vec<u32>> = (0..vertices)
        .map(|v| {
            let mut n: Vec<u32> = member[v]
                .iter()
                .flat_map(|&s| sets[s as usize].iter().copied())
                .filter(|&u| u as usize != v)
                .collect();
            n.sort_unstable();
            n.dedup();
            n
        })
        .collect();
    let mut colour = vec![u32::MAX; vertices];
    // Per vertex, the colours its coloured neighbours have (sorted).
    let mut seen: Vec<Vec<u32>> = vec![Vec::new(); vertices];
    let mut heap: std::collections::BinaryHeap<(usize, usize, std::cmp::Reverse<usize>)> = (0
        ..vertices)
        .filter(|&v| !member[v].is_empty())
        .map(|v| (0, neighbours[v].len(), std::cmp::Reverse(v)))
        .collect();
    let mut count = 0;
    while let Some((sat, _, std::cmp::Reverse(v))) = heap.pop() {
        if colour[v] != u32::MAX || sat != seen[v].len() {
            continue;
        }
        let c = (0u32..)
            .find(|c| seen[v].binary_search(c).is_err())
            .unwrap_or(0);
        colour[v] = c;
        count = count.max(c + 1);
        for &u in &neighbours[v] {
            let u = u as usize;
            if colour[u] == u32::MAX {
                if let Err(at) = seen[u].binary_search(&c) {
                    seen[u].insert(at, c);
                    heap.push((seen[u].len(), neighbours[u].len(), std::cmp::Reverse(u)));
                }
            }
        }
    }
    (colour, count)
}

/// The conversion's part that is linear in the cage: given a cage with the
/// topology and tags of the one converted, its conversion.
pub type Linear<'a> = dyn Fn(&Cage) -> Result<Conversion, SceneError> + Sync + 'a;

/// Face rings the probing assumes an output may reach at first; each
/// failed check adds one, up to [`MAX_RINGS`].
const FIRST_RINGS: u32 = 1;
/// See [`FIRST_RINGS`].
const MAX_RINGS: u32 = 4;

/// The stencils of the conversion `conv` of the cage `coarse` (refined into
/// `fine`, its faces coming from the coarse faces `coarse_face`), found by
/// probing `linear` (see the module doc), with the shading construction's
/// `decisions`.
#[allow(clippy::too_many_arguments)]
pub fn probe(
    coarse: &Cage,
    coarse_topo: &Topology,
    fine: &Cage,
    fine_topo: &Topology,
    coarse_face: &[usize],
    conv: &Conversion,
    decisions: &tangent::Decisions,
    linear: &Linear,
    path: &Path,
) -> Result<CageStencils, SceneError> {
    let outputs = Outputs::new(fine, fine_topo, conv);
    let rest = outputs.values(conv);
    let mut rings = FIRST_RINGS;
    let combos = loop {
        match probe_with(
            coarse,
            coarse_topo,
            fine_topo,
            coarse_face,
            conv,
            &outputs,
            &rest,
            rings,
            linear,
            path,
        )? {
            Some(c) => break c,
            None if rings < MAX_RINGS => rings += 1,
            None => {
                return Err(SceneError::invalid(
                    path,
                    format!(
                        "internal: the conversion of this cage is not linear in its vertices \
                         (checked up to {MAX_RINGS} face rings): it cannot be animated by stencils"
                    ),
                ))
            }
        }
    };
    // One row per distinct combination: a point the conversion computed
    // once and copied is one row.
    let mut stencils = CageStencils {
        vertices: coarse.positions.len(),
        ..Default::default()
    };
    let mut row_of: HashMap<Vec<(u32, u32)>, u32> = HashMap::new();
    let mut rows = Vec::with_capacity(combos.len());
    for (id, terms) in combos.iter().enumerate() {
        let key: Vec<(u32, u32)> = terms.iter().map(|&(i, w)| (i, w.to_bits())).collect();
        let row = match row_of.get(&key) {
            Some(&r) => r,
            None => {
                let (reference, rest) = reference_form(terms, 1.0).ok_or_else(|| {
                    SceneError::invalid(
                        path,
                        format!("internal: control point {id} of the conversion is not an affine combination of cage vertices"),
                    )
                })?;
                let r = stencils.points.push(reference, &rest);
                row_of.insert(key, r);
                r
            }
        };
        rows.push(row);
    }
    stencils.patch_rows = (0..conv.patches.len())
        .map(|p| std::array::from_fn(|s| rows[16 * p + s]))
        .collect();
    let recipe = tangent::recipe(
        fine,
        fine_topo,
        conv,
        decisions,
        &|v| rows[outputs.corner_id[&v] as usize],
        &|a, b| rows[outputs.edge_id[&(a, b)] as usize],
        &|p, s| rows[16 * p + s],
    );
    for (p, vectors) in recipe.iter().enumerate() {
        for (k, c) in vectors.iter().enumerate() {
            let terms: Vec<(u32, f32)> = c.0.iter().map(|&(i, w)| (i, w as f32)).collect();
            let (reference, rest) = reference_form(&terms, 0.0)
                .or_else(|| zero_vector(c))
                .ok_or_else(|| {
                    SceneError::invalid(
                        path,
                        format!("internal: shading vector {k} of patch {p} is not a difference of control points"),
                    )
                })?;
            stencils.shading.push(reference, &rest);
        }
    }
    Ok(stencils)
}

/// The zero vector as a row (a tangent that cancels, e.g. of a collapsed
/// edge): relative to input 0 with no terms.
fn zero_vector(c: &Comb) -> Option<(u32, Vec<(u32, f32)>)> {
    c.0.is_empty().then(|| (0, Vec::new()))
}

/// `terms` (sorted by input) as (reference, the other terms), the reference
/// the term of the largest weight, where the weights sum to `sum` (1 for a
/// point, 0 for a vector) within rounding.
fn reference_form(terms: &[(u32, f32)], sum: f64) -> Option<(u32, Vec<(u32, f32)>)> {
    let total: f64 = terms.iter().map(|t| f64::from(t.1)).sum();
    let size: f64 = terms.iter().map(|t| f64::from(t.1).abs()).sum();
    if terms.is_empty() || (total - sum).abs() > 1e-5 * size.max(1.0) {
        return None;
    }
    let mut best = 0;
    for (k, t) in terms.iter().enumerate() {
        if t.1.abs() > terms[best].1.abs() {
            best = k;
        }
    }
    let reference = terms[best].0;
    let rest = terms
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != best)
        .map(|(_, &t)| t)
        .collect();
    Some((reference, rest))
}

/// The terms (input, weight) of one combination, sorted by input.
type Terms = Vec<(u32, f32)>;

/// One probing pass assuming outputs reach `rings` face rings: the
/// combination of every output, or `None` where that was not enough.
#[allow(clippy::too_many_arguments)]
fn probe_with(
    coarse: &Cage,
    coarse_topo: &Topology,
    fine_topo: &Topology,
    coarse_face: &[usize],
    conv: &Conversion,
    outputs: &Outputs,
    rest: &[Vec3],
    rings: u32,
    linear: &Linear,
    path: &Path,
) -> Result<Option<Vec<Terms>>, SceneError> {
    let reach = reach(coarse, coarse_topo, rings);
    let (set_of, sets) = candidate_sets(&reach, fine_topo, coarse_face, conv, outputs);
    let (colours, count) = colour(coarse.positions.len(), &sets);
    log::debug!(
        "stencils: {} vertices, {} outputs, {} candidate sets, {rings} rings: {count} colours, {} runs",
        coarse.positions.len(),
        outputs.len(),
        sets.len(),
        count.div_ceil(3)
    );
    // Per set, its vertices by colour.
    let by_colour: Vec<Vec<(u32, u32)>> = sets
        .iter()
        .map(|s| {
            let mut v: Vec<(u32, u32)> = s.iter().map(|&v| (colours[v as usize], v)).collect();
            v.sort_unstable();
            v
        })
        .collect();
    let results = run_probes(coarse, &colours, count.div_ceil(3), linear);
    let mut combos: Vec<Vec<(u32, f32)>> = vec![Vec::new(); outputs.len()];
    for (run, out) in results.into_iter().enumerate() {
        let out = out?;
        if out.patches.len() != conv.patches.len() {
            return Err(SceneError::invalid(
                path,
                "internal: the conversion made a different number of patches for another pose",
            ));
        }
        let values = outputs.values(&out);
        for (id, value) in values.iter().enumerate() {
            for ch in 0..3 {
                let w = value[ch];
                if w == 0.0 {
                    continue;
                }
                let c = 3 * run as u32 + ch as u32;
                let set = &by_colour[set_of[id] as usize];
                let Ok(k) = set.binary_search_by_key(&c, |t| t.0) else {
                    return Ok(None);
                };
                combos[id].push((set[k].1, w));
            }
        }
    }
    for c in &mut combos {
        c.sort_unstable_by_key(|t| t.0);
    }
    Ok(gives_rest(coarse, &combos, rest).then_some(combos))
}

/// The candidate set of each output (an index into the sets) and the
/// distinct sets: the vertices within the reach of the output's coarse
/// faces, sorted.
fn candidate_sets(
    reach: &[Vec<u32>],
    fine_topo: &Topology,
    coarse_face: &[usize],
    conv: &Conversion,
    outputs: &Outputs,
) -> (Vec<u32>, Vec<Vec<u32>>) {
    let mut set_of: Vec<u32> = Vec::with_capacity(outputs.len());
    let mut sets: Vec<Vec<u32>> = Vec::new();
    let mut set_id: HashMap<Vec<usize>, u32> = HashMap::new();
    for id in 0..outputs.len() {
        let mut faces: Vec<usize> = outputs
            .faces(id, fine_topo, conv)
            .into_iter()
            .map(|f| coarse_face[f])
            .collect();
        faces.sort_unstable();
        faces.dedup();
        let s = *set_id.entry(faces.clone()).or_insert_with(|| {
            let mut vs: Vec<u32> = faces
                .iter()
                .flat_map(|&f| reach[f].iter().copied())
                .collect();
            vs.sort_unstable();
            vs.dedup();
            sets.push(vs);
            sets.len() as u32 - 1
        });
        set_of.push(s);
    }
    (set_of, sets)
}

/// Converts one probe cage per run (run r: the vertices of colours 3r,
/// 3r + 1, 3r + 2 at the unit x, y, z, every other vertex at 0), the results
/// in run order.
fn run_probes(
    coarse: &Cage,
    colours: &[u32],
    runs: u32,
    linear: &Linear,
) -> Vec<Result<Conversion, SceneError>> {
    let probe_cage = |run: u32| {
        let mut cage = coarse.clone();
        for (v, p) in cage.positions.iter_mut().enumerate() {
            let c = colours[v];
            *p = DVec3::ZERO;
            if c != u32::MAX && c / 3 == run {
                p[(c % 3) as usize] = 1.0;
            }
        }
        cage
    };
    // The runs are independent: on as many threads as the machine has.
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(runs as usize)
        .max(1);
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                let probe_cage = &probe_cage;
                scope.spawn(move || {
                    (0..runs)
                        .filter(|r| *r as usize % threads == t)
                        .map(|r| (r, linear(&probe_cage(r))))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        let mut all: Vec<(u32, Result<Conversion, SceneError>)> = workers
            .into_iter()
            .flat_map(|w| w.join().expect("a probing thread panicked"))
            .collect();
        all.sort_by_key(|r| r.0);
        all.into_iter().map(|r| r.1).collect()
    })
}

/// Whether the combinations give the conversion of the cage as loaded
/// (`rest`), within rounding.
fn gives_rest(coarse: &Cage, combos: &[Terms], rest: &[Vec3]) -> bool {
    let x: Vec<DVec3> = coarse.positions.clone();
    let scale = x
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()))
        .max(f64::MIN_POSITIVE);
    for (id, terms) in combos.iter().enumerate() {
        let got: DVec3 = terms
            .iter()
            .fold(DVec3::ZERO, |s, &(i, w)| s + x[i as usize] * f64::from(w));
        if (got - rest[id].as_dvec3()).abs().max_element() > 1e-5 * scale {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_evaluate_in_the_reference_form() {
        let mut t = Table::default();
        t.push(1, &[(0, 0.25), (2, 0.25)]);
        t.push(2, &[]);
        let x = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(5.0, 2.0, 4.0),
        ];
        assert_eq!(t.points(&x), vec![Vec3::new(3.0, 1.0, 1.0), x[2]]);
        assert_eq!(t.vectors(&x)[0], Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(t.bytes(), 2 * ROW_BYTES + 2 * TERM_BYTES);
    }

    #[test]
    fn reference_is_the_largest_weight() {
        let (r, rest) = reference_form(&[(3, 0.25), (5, 0.5), (9, 0.25)], 1.0).unwrap();
        assert_eq!((r, rest), (5, vec![(3, 0.25), (9, 0.25)]));
        assert!(reference_form(&[(3, 0.5)], 1.0).is_none());
        assert!(reference_form(&[(3, 3.0), (4, -3.0)], 0.0).is_some());
    }
}
