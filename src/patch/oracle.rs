//! The recursive driver: the CPU reference every GPU path is checked against.
//!
//! [`process`] is one work item exactly as the GPU kernel treats it: rebuild
//! the sub-patch, frustum-cull it, test it, and either split it into four
//! children or declare it ready (then back-face cull it). [`subdivide`] runs
//! it depth-first over every base patch; [`triangulate`] turns ready nodes
//! into world-space triangles with the one shared evaluation function.
//!
//! Rational patches (flag `PATCH_RATIONAL`, with their weights) take
//! [`process_rational`]: the same steps on the homogeneous sub-patch of
//! [`super::homogeneous`]; the `*_weighted`
//! entry points dispatch per patch, and with no weights (or no patch
//! flagged) they are the polynomial functions exactly.

use glam::Vec3;

use super::bezier::{BezierPatch, EDGE_BOTTOM, EDGE_LEFT, EDGE_RIGHT, EDGE_TOP};
use super::blossom::reconstruct;
use super::criterion::{edge_flat, edge_flat_within, inner_flat, inner_flat_within};
use super::cull::{back_facing, outside_frustum, wedges_face_away, wedges_face_away_with};
use super::displace::{Displacer, ModelDisplacement};
use super::homogeneous::{self, HomPatch};
use super::ops::{max3, min3};
use super::quadnode::QuadNode;
use super::rational::{RationalPatch, Weights};
use super::view::{ViewParams, FLAG_ANISO, FLAG_BACKFACE_CULL, FLAG_FRUSTUM_CULL, FLAG_WEDGES};
use super::wedge::{children, node_mesh, pending, resolve, wedge_pivots, NodeMesh, Split};

/// Per-patch flag: the patch has weights; see [`process_rational`].
pub use crate::constants::PATCH_RATIONAL;
/// Per-patch flag: the model is open or thin; never back-face cull it.
pub use crate::constants::PATCH_TWO_SIDED;

/// What happened to one work item.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// The control-point box is outside the view frustum.
    Culled,
    /// Ready, but back-facing everywhere; not drawn.
    BackFacing,
    /// Ready to draw.
    Ready,
    /// Needs subdivision: these children follow (four for 1:4, two for 1:2).
    Split(Children),
}

/// The children of a split, in the order (0,0), (1,0), (0,1), (1,1) of
/// those the split makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Children {
    nodes: [QuadNode; 4],
    count: usize,
}

impl std::ops::Deref for Children {
    type Target = [QuadNode];
    fn deref(&self) -> &[QuadNode] {
        &self.nodes[..self.count]
    }
}

impl IntoIterator for Children {
    type Item = QuadNode;
    type IntoIter = std::iter::Take<std::array::IntoIter<QuadNode, 4>>;
    fn into_iter(self) -> Self::IntoIter {
        self.nodes.into_iter().take(self.count)
    }
}

/// Processes one node of `base` (whose per-patch flags are `flags`).
pub fn process(base: &BezierPatch, flags: u32, node: QuadNode, vp: &ViewParams) -> Outcome {
    let (a, b, c, d) = node.domain();
    let sub = reconstruct(base, a, b, c, d);
    let (lo, hi) = sub.bbox();
    if vp.has(FLAG_FRUSTUM_CULL) && frustum_culled(lo, hi, node, |u, v| base.eval(u, v), vp) {
        return Outcome::Culled;
    }
    if let Some(kids) = split(
        node,
        vp,
        |e| edge_flat(&sub.edge(e), vp),
        || inner_flat(&sub, vp),
    ) {
        return Outcome::Split(kids);
    }
    // A back-facing node goes only if its wedges face away too (see
    // `wedges_face_away`): they may reach where the surface faces the eye.
    let one_sided = flags & PATCH_TWO_SIDED == 0;
    let eye = vp.eye.truncate();
    if vp.has(FLAG_BACKFACE_CULL)
        && one_sided
        && back_facing(&sub, lo, hi, eye)
        && wedges_face_away(base, node, eye, vp.has(FLAG_WEDGES))
    {
        return Outcome::BackFacing;
    }
    Outcome::Ready
}

/// Processes one node of the rational patch `base` (per-patch flags
/// `flags`): [`process`] on the homogeneous sub-patch (see
/// [`super::homogeneous`]), the box of its Cartesian control points for the
/// frustum, and the rational back-face bound.
pub fn process_rational(
    base: &RationalPatch,
    flags: u32,
    node: QuadNode,
    vp: &ViewParams,
) -> Outcome {
    let (a, b, c, d) = node.domain();
    let h = HomPatch::of(base);
    let sub = h.sub(a, b, c, d);
    if vp.has(FLAG_FRUSTUM_CULL) {
        let (lo, hi) = sub.bbox();
        if frustum_culled(lo, hi, node, |u, v| h.eval(u, v), vp) {
            return Outcome::Culled;
        }
    }
    let edge = |e| homogeneous::edge_flat(&sub.edge(e), vp);
    if let Some(kids) = split(node, vp, edge, || homogeneous::inner_flat(&sub, vp)) {
        return Outcome::Split(kids);
    }
    let one_sided = flags & PATCH_TWO_SIDED == 0;
    let eye = vp.eye.truncate();
    if vp.has(FLAG_BACKFACE_CULL)
        && one_sided
        && homogeneous::back_facing(&sub, eye)
        && wedges_face_away_with(|u, v| h.eval(u, v), node, eye, vp.has(FLAG_WEDGES))
    {
        return Outcome::BackFacing;
    }
    Outcome::Ready
}

/// Processes one node of base patch `base` with weights `w` (None: all 1),
/// rational when `flags` say so.
pub fn process_any(
    base: &BezierPatch,
    w: Option<&Weights>,
    flags: u32,
    node: QuadNode,
    vp: &ViewParams,
) -> Outcome {
    match w {
        Some(w) if flags & PATCH_RATIONAL != 0 => {
            process_rational(&RationalPatch::new(*base, *w), flags, node, vp)
        }
        _ => process(base, flags, node, vp),
    }
}

/// Processes one node of base patch `g` of a displaced model (settings
/// `m`): [`process`] with the criterion's tolerance reduced by the node's
/// height range (its edges' from the edge owners, see
/// `scene::displacement`), its box grown by the largest displacement, and
/// no back-face test (a displaced surface can face the eye where its base
/// patch does not).
pub fn process_displaced(
    dc: &dyn Displacer,
    g: usize,
    m: &ModelDisplacement,
    node: QuadNode,
    vp: &ViewParams,
) -> Outcome {
    let base = &dc.patches().0[g];
    let (a, b, c, d) = node.domain();
    let sub = reconstruct(base, a, b, c, d);
    if vp.has(FLAG_FRUSTUM_CULL) {
        let (lo, hi) = displaced_box(&sub, node, base, m);
        if outside_frustum(lo, hi, vp) {
            return Outcome::Culled;
        }
    }
    let edge = |e| edge_flat_within(&sub.edge(e), vp, dc.edge_reach(g, m, node, e));
    let inner = || inner_flat_within(&sub, vp, dc.inner_reach(g, m, node));
    match split(node, vp, edge, inner) {
        Some(kids) => Outcome::Split(kids),
        None => Outcome::Ready,
    }
}

/// The box of everything a displaced node and its descendants draw: its
/// control points and wedge pivots, grown by the model's largest
/// displacement (twin of the displaced branch of process_points).
pub fn displaced_box(
    sub: &BezierPatch,
    node: QuadNode,
    base: &BezierPatch,
    m: &ModelDisplacement,
) -> (Vec3, Vec3) {
    let (mut lo, mut hi) = sub.bbox();
    for (u, v) in wedge_pivots(node).into_iter().flatten() {
        let p = base.eval(u, v);
        lo = min3(lo, p);
        hi = max3(hi, p);
    }
    let grow = Vec3::splat(m.margin());
    (lo - grow, hi + grow)
}

/// The frustum test of a node whose control-point box is [lo, hi]. The
/// node's wedges, and those of every descendant along its outer edges,
/// reach from its own edge to a pivot that may lie outside that box: the
/// box must hold the pivots too (evaluated by `eval`, the drawn
/// positions), or a wedge reaching into the view would be culled with the
/// node.
fn frustum_culled(
    lo: Vec3,
    hi: Vec3,
    node: QuadNode,
    eval: impl Fn(f32, f32) -> Vec3,
    vp: &ViewParams,
) -> bool {
    let (mut clo, mut chi) = (lo, hi);
    for (u, v) in wedge_pivots(node).into_iter().flatten() {
        let p = eval(u, v);
        clo = min3(clo, p);
        chi = max3(chi, p);
    }
    outside_frustum(clo, chi, vp)
}

/// What the criterion found for a node that can still split.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// The node's edge states before this test.
    pub states: [u32; 4],
    /// Per edge: tested now (pending) or inherited flat.
    pub tested: [bool; 4],
    /// Per edge: flat (inherited, or found flat now).
    pub flat: [bool; 4],
    /// The inner tier's answer; `None` when an edge already asked to split
    /// (the inner tier is not evaluated then).
    pub inner_flat: Option<bool>,
    /// Which directions may still be halved (below `l_max`).
    pub can_split: Split,
    /// `aniso` splits (else 1:4 always).
    pub aniso: bool,
}

impl Verdict {
    /// Which way the node splits, if it does (see [`super::wedge`]).
    pub fn split(&self) -> Option<Split> {
        let along_u = !self.flat[EDGE_BOTTOM] || !self.flat[EDGE_TOP];
        let along_v = !self.flat[EDGE_LEFT] || !self.flat[EDGE_RIGHT];
        let inner = self.inner_flat == Some(false);
        let want = if self.aniso {
            (along_u || inner, along_v || inner)
        } else {
            let any = along_u || along_v || inner;
            (any, any)
        };
        let s = (want.0 && self.can_split.0, want.1 && self.can_split.1);
        (s.0 || s.1).then_some(s)
    }

    /// Does the node split?
    pub fn splits(&self) -> bool {
        self.split().is_some()
    }

    /// Why it splits, for statistics: which directions' edges asked for it.
    pub fn cause(&self) -> Option<SplitCause> {
        self.split()?;
        let along_u = !self.flat[EDGE_BOTTOM] || !self.flat[EDGE_TOP];
        let along_v = !self.flat[EDGE_LEFT] || !self.flat[EDGE_RIGHT];
        match (along_u, along_v) {
            (true, true) => Some(SplitCause::BothDirections),
            (true, false) | (false, true) => Some(SplitCause::OneDirection),
            (false, false) => Some(SplitCause::InnerOnly),
        }
    }
}

/// Why a node split (see [`Verdict::cause`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SplitCause {
    /// Edges along u and along v were not flat.
    BothDirections,
    /// Only the edges along one direction were not flat: a 1:4 split
    /// refines the other direction for nothing (`aniso` halves that one).
    OneDirection,
    /// Every edge flat, the inner tier not.
    InnerOnly,
}

/// The criterion of a node: `None` when it cannot split any more (`iso`:
/// at `l_max`; `aniso`: both directions at `l_max`), else what the edge
/// tests (`edge_flat(e)`, pending edges only, no early exit: the children
/// inherit the results) and the inner tier found.
fn verdict(
    node: QuadNode,
    vp: &ViewParams,
    edge_flat: impl Fn(usize) -> bool,
    inner_flat: impl FnOnce() -> bool,
) -> Option<Verdict> {
    let aniso = vp.has(FLAG_ANISO);
    let can_split = if aniso {
        (node.du() < vp.l_max, node.dv() < vp.l_max)
    } else {
        let can = node.depth() < vp.l_max;
        (can, can)
    };
    if !can_split.0 && !can_split.1 {
        return None;
    }
    let states = node.edges();
    let tested = pending(node);
    let mut flat = [true; 4];
    for e in 0..4 {
        if tested[e] {
            flat[e] = edge_flat(e);
        }
    }
    let inner_flat = (!flat.contains(&false)).then(inner_flat);
    Some(Verdict {
        states,
        tested,
        flat,
        inner_flat,
        can_split,
        aniso,
    })
}

/// The criterion of a node: its children when an edge (`edge_flat(e)`) or
/// the inner tier (`inner_flat`) says split.
fn split(
    node: QuadNode,
    vp: &ViewParams,
    edge_flat: impl Fn(usize) -> bool,
    inner_flat: impl FnOnce() -> bool,
) -> Option<Children> {
    let v = verdict(node, vp, edge_flat, inner_flat)?;
    let (nodes, count) = children(node, v.split()?, resolve(node, v.flat));
    Some(Children { nodes, count })
}

/// The criterion's verdict on `node` of `base` (rational when `flags` and
/// `w` say so), as [`process_any`] would reach it: for statistics and tests.
pub fn explain(
    base: &BezierPatch,
    w: Option<&Weights>,
    flags: u32,
    node: QuadNode,
    vp: &ViewParams,
) -> Option<Verdict> {
    let (a, b, c, d) = node.domain();
    match w {
        Some(w) if flags & PATCH_RATIONAL != 0 => {
            let sub = HomPatch::of(&RationalPatch::new(*base, *w)).sub(a, b, c, d);
            let edge = |e| homogeneous::edge_flat(&sub.edge(e), vp);
            verdict(node, vp, edge, || homogeneous::inner_flat(&sub, vp))
        }
        _ => {
            let sub = reconstruct(base, a, b, c, d);
            verdict(
                node,
                vp,
                |e| edge_flat(&sub.edge(e), vp),
                || inner_flat(&sub, vp),
            )
        }
    }
}

/// [`explain`] for base patch `g` of a displaced model (settings `m`), as
/// [`process_displaced`] reaches it.
pub fn explain_displaced(
    dc: &dyn Displacer,
    g: usize,
    m: &ModelDisplacement,
    node: QuadNode,
    vp: &ViewParams,
) -> Option<Verdict> {
    let (a, b, c, d) = node.domain();
    let sub = reconstruct(&dc.patches().0[g], a, b, c, d);
    let edge = |e| edge_flat_within(&sub.edge(e), vp, dc.edge_reach(g, m, node, e));
    verdict(node, vp, edge, || {
        inner_flat_within(&sub, vp, dc.inner_reach(g, m, node))
    })
}

/// Counts gathered by one subdivision run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SubdivStats {
    /// Base patches in the input.
    pub patches: u64,
    /// Work items processed (every node visited, base patches included).
    pub nodes_processed: u64,
    /// Nodes (at any depth) dropped by the frustum test.
    pub culled_patches: u64,
    /// Ready nodes dropped as back-facing.
    pub backface_culled: u64,
    /// Ready nodes drawn.
    pub ready_quads: u64,
    /// Deepest ready node.
    pub max_depth: u32,
    /// Ready nodes at the depth limit (drawn whatever the criterion said).
    pub nodes_at_lmax: u64,
}

/// The oracle's result for one view.
#[derive(Clone, Debug, Default)]
pub struct SubdivResult {
    /// Ready nodes, in depth-first order per base patch.
    pub ready: Vec<QuadNode>,
    /// Counts.
    pub stats: SubdivStats,
}

/// Subdivides every base patch depth-first down to `vp.l_max`.
pub fn subdivide(patches: &[BezierPatch], flags: &[u32], vp: &ViewParams) -> SubdivResult {
    subdivide_weighted(patches, &[], flags, vp)
}

/// [`subdivide`] with the patches' weights (`weights` parallel to
/// `patches`, or empty for none): patches flagged `PATCH_RATIONAL` take
/// [`process_rational`].
pub fn subdivide_weighted(
    patches: &[BezierPatch],
    weights: &[Weights],
    flags: &[u32],
    vp: &ViewParams,
) -> SubdivResult {
    subdivide_range(patches, weights, flags, vp, 0, None)
}

/// [`subdivide_weighted`] on patches that are base patches `first..` of
/// the displaced geometry `dc` (those of displaced models take
/// [`process_displaced`]).
fn subdivide_range(
    patches: &[BezierPatch],
    weights: &[Weights],
    flags: &[u32],
    vp: &ViewParams,
    first: usize,
    dc: Option<&dyn Displacer>,
) -> SubdivResult {
    assert_eq!(patches.len(), flags.len());
    assert!(weights.is_empty() || weights.len() == patches.len());
    let mut out = SubdivResult::default();
    out.stats.patches = patches.len() as u64;
    let mut stack = Vec::with_capacity(64);
    for (id, base) in patches.iter().enumerate() {
        stack.push(QuadNode::root(id as u32));
        while let Some(node) = stack.pop() {
            out.stats.nodes_processed += 1;
            let g = first + id;
            let outcome = match dc.and_then(|dc| Some((dc, dc.model_of(g)?))) {
                Some((dc, m)) => process_displaced(dc, g, m, node, vp),
                None => process_any(base, weights.get(id), flags[id], node, vp),
            };
            match outcome {
                Outcome::Culled => out.stats.culled_patches += 1,
                Outcome::BackFacing => out.stats.backface_culled += 1,
                Outcome::Ready => {
                    let l = node.depth();
                    out.stats.ready_quads += 1;
                    out.stats.max_depth = out.stats.max_depth.max(l);
                    out.stats.nodes_at_lmax += (l >= vp.l_max) as u64;
                    out.ready.push(node);
                }
                // Reversed so the children pop in order.
                Outcome::Split(ch) => stack.extend(ch.iter().rev()),
            }
        }
    }
    out
}

/// [`subdivide`] split over `threads` worker threads by base-patch ranges;
/// the result is identical to the sequential one (same order, same counts).
pub fn subdivide_parallel(
    patches: &[BezierPatch],
    flags: &[u32],
    vp: &ViewParams,
    threads: usize,
) -> SubdivResult {
    subdivide_parallel_weighted(patches, &[], flags, vp, threads)
}

/// [`subdivide_parallel`] with the patches' weights (see
/// [`subdivide_weighted`]).
pub fn subdivide_parallel_weighted(
    patches: &[BezierPatch],
    weights: &[Weights],
    flags: &[u32],
    vp: &ViewParams,
    threads: usize,
) -> SubdivResult {
    subdivide_parallel_in(patches, weights, flags, vp, threads, None)
}

/// [`subdivide_parallel_weighted`] on the whole of a displaced geometry.
pub fn subdivide_displaced(dc: &dyn Displacer, vp: &ViewParams, threads: usize) -> SubdivResult {
    let (patches, weights, flags) = dc.patches();
    subdivide_parallel_in(patches, weights, flags, vp, threads, Some(dc))
}

fn subdivide_parallel_in(
    patches: &[BezierPatch],
    weights: &[Weights],
    flags: &[u32],
    vp: &ViewParams,
    threads: usize,
    dc: Option<&dyn Displacer>,
) -> SubdivResult {
    let threads = threads.clamp(1, 64);
    if threads == 1 || patches.len() < 64 {
        return subdivide_range(patches, weights, flags, vp, 0, dc);
    }
    // Small chunks handed out from a counter balance the uneven cost of
    // patches; results are stored by chunk index to keep the order.
    let chunk = patches.len().div_ceil(threads * 16);
    let chunks = patches.len().div_ceil(chunk);
    let next = std::sync::atomic::AtomicUsize::new(0);
    let slots: Vec<std::sync::Mutex<Option<SubdivResult>>> =
        (0..chunks).map(|_| std::sync::Mutex::new(None)).collect();
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                if k >= chunks {
                    break;
                }
                let range = k * chunk..((k + 1) * chunk).min(patches.len());
                let w = if weights.is_empty() {
                    &[][..]
                } else {
                    &weights[range.clone()]
                };
                let first = range.start;
                let mut r =
                    subdivide_range(&patches[range.clone()], w, &flags[range], vp, first, dc);
                for q in &mut r.ready {
                    *q = q.with_patch(q.patch() + (k * chunk) as u32);
                }
                *slots[k].lock().unwrap() = Some(r);
            });
        }
    });
    let parts = slots
        .into_iter()
        .map(|m| m.into_inner().unwrap().expect("chunk done"));
    let mut out = SubdivResult::default();
    for r in parts {
        let (a, b) = (&mut out.stats, r.stats);
        a.patches += b.patches;
        a.nodes_processed += b.nodes_processed;
        a.culled_patches += b.culled_patches;
        a.backface_culled += b.backface_culled;
        a.ready_quads += b.ready_quads;
        a.max_depth = a.max_depth.max(b.max_depth);
        a.nodes_at_lmax += b.nodes_at_lmax;
        out.ready.extend(r.ready);
    }
    out
}

/// One world-space triangle of the output.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// Positions, each from [`BezierPatch::eval`] of the base patch.
    pub v: [Vec3; 3],
    /// Parameter coordinates of the vertices.
    pub uv: [(f32, f32); 3],
    /// The node that emitted it.
    pub node: QuadNode,
    /// True for crack-closing wedges.
    pub wedge: bool,
}

/// Evaluates a ready node's mesh: every vertex, corner or pivot alike, is the
/// base patch evaluated at exact dyadic parameters by the one function
/// [`BezierPatch::eval`].
pub fn node_positions(base: &BezierPatch, mesh: &NodeMesh) -> [Vec3; 8] {
    let mut p = [Vec3::ZERO; 8];
    for (i, &(u, v)) in mesh.uv.iter().enumerate().take(mesh.vertex_count) {
        p[i] = base.eval(u, v);
    }
    p
}

/// [`node_positions`] of a rational patch: every vertex is
/// [`RationalPatch::eval`] (the homogeneous surface point, divided) at the
/// same dyadic parameters; on a shared boundary it reduces to the boundary
/// curve's own homogeneous evaluation, so neighbours get the same bits.
pub fn node_positions_rational(base: &RationalPatch, mesh: &NodeMesh) -> [Vec3; 8] {
    let mut p = [Vec3::ZERO; 8];
    for (i, &(u, v)) in mesh.uv.iter().enumerate().take(mesh.vertex_count) {
        p[i] = base.eval(u, v);
    }
    p
}

/// Drawn positions of ready nodes, for any mix of patches: what the
/// comparisons against the GPU's captured vertices evaluate.
pub trait Surfaces {
    /// The positions of `node`'s mesh (slots as in [`node_positions`]).
    fn node_positions(&self, node: QuadNode, mesh: &NodeMesh) -> [Vec3; 8];
}

impl Surfaces for [BezierPatch] {
    fn node_positions(&self, node: QuadNode, mesh: &NodeMesh) -> [Vec3; 8] {
        node_positions(&self[node.patch() as usize], mesh)
    }
}

impl Surfaces for Vec<BezierPatch> {
    fn node_positions(&self, node: QuadNode, mesh: &NodeMesh) -> [Vec3; 8] {
        self[..].node_positions(node, mesh)
    }
}

/// Patches with weights and flags: rational where flagged `PATCH_RATIONAL`
/// and weights are given (`weights` empty: all polynomial).
#[derive(Clone, Copy, Debug)]
pub struct WeightedPatches<'a> {
    /// The Cartesian control points.
    pub patches: &'a [BezierPatch],
    /// Weights parallel to `patches`, or empty.
    pub weights: &'a [Weights],
    /// Per-patch flags.
    pub flags: &'a [u32],
}

impl WeightedPatches<'_> {
    /// Patch `k` as a rational patch, if it is one.
    pub fn rational(&self, k: usize) -> Option<RationalPatch> {
        let w = self.weights.get(k)?;
        (self.flags[k] & PATCH_RATIONAL != 0).then(|| RationalPatch::new(self.patches[k], *w))
    }
}

impl Surfaces for WeightedPatches<'_> {
    fn node_positions(&self, node: QuadNode, mesh: &NodeMesh) -> [Vec3; 8] {
        let k = node.patch() as usize;
        match self.rational(k) {
            Some(r) => node_positions_rational(&r, mesh),
            None => node_positions(&self.patches[k], mesh),
        }
    }
}

/// The triangles of `ready` nodes (two per quad plus wedges, if enabled).
pub fn triangulate(
    patches: &[BezierPatch],
    ready: &[QuadNode],
    with_wedges: bool,
) -> Vec<Triangle> {
    triangulate_surfaces(patches, ready, with_wedges)
}

/// [`triangulate`] for any [`Surfaces`] (rational patches included).
pub fn triangulate_surfaces<S: Surfaces + ?Sized>(
    patches: &S,
    ready: &[QuadNode],
    with_wedges: bool,
) -> Vec<Triangle> {
    let mut tris = Vec::with_capacity(ready.len() * 2 + ready.len() / 2);
    for &node in ready {
        let mesh = node_mesh(node, with_wedges);
        let pos = patches.node_positions(node, &mesh);
        for (t, idx) in mesh.tris[..mesh.tri_count].iter().enumerate() {
            let i = idx.map(|k| k as usize);
            tris.push(Triangle {
                v: i.map(|k| pos[k]),
                uv: i.map(|k| mesh.uv[k]),
                node,
                wedge: t >= 2,
            });
        }
    }
    tris
}

/// Triangle and wedge counts for `ready` without building the triangles.
pub fn triangle_counts(ready: &[QuadNode], with_wedges: bool) -> (u64, u64) {
    let mut tris = 0u64;
    let mut wedges = 0u64;
    for &node in ready {
        let mesh = node_mesh(node, with_wedges);
        tris += mesh.tri_count as u64;
        wedges += mesh.wedges() as u64;
    }
    (tris, wedges)
}
