//! The recursive driver: the CPU reference every GPU path is checked against.
//!
//! [`process`] is one work item exactly as the GPU kernel treats it: rebuild
//! the sub-patch, frustum-cull it, test it, and either split it into four
//! children or declare it ready (then back-face cull it). [`subdivide`] runs
//! it depth-first over every base patch; [`triangulate`] turns ready nodes
//! into world-space triangles with the one shared evaluation function.

use glam::Vec3;

use super::bezier::BezierPatch;
use super::blossom::reconstruct;
use super::criterion::{edge_flat, inner_flat};
use super::cull::{back_facing, outside_frustum, wedges_face_away};
use super::ops::{max3, min3};
use super::quadnode::QuadNode;
use super::view::{ViewParams, FLAG_BACKFACE_CULL, FLAG_FRUSTUM_CULL, FLAG_WEDGES};
use super::wedge::{children, edge_depths, node_mesh, resolve_depths, wedge_pivots, NodeMesh};

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
    /// Needs subdivision: these four children follow.
    Split([QuadNode; 4]),
}

/// Processes one node of `base` (whose per-patch flags are `flags`).
pub fn process(base: &BezierPatch, flags: u32, node: QuadNode, vp: &ViewParams) -> Outcome {
    let (a, b, c, d) = node.domain();
    let sub = reconstruct(base, a, b, c, d);
    let (lo, hi) = sub.bbox();
    let pivots = wedge_pivots(node);
    if vp.has(FLAG_FRUSTUM_CULL) {
        // The node's wedges, and those of every descendant along its outer
        // edges, reach from its own edge to a pivot that may lie outside its
        // control points' box: the box must hold the pivots too, or a wedge
        // reaching into the view would be culled with the node.
        let (mut clo, mut chi) = (lo, hi);
        for (u, v) in pivots.into_iter().flatten() {
            let p = base.eval(u, v);
            clo = min3(clo, p);
            chi = max3(chi, p);
        }
        if outside_frustum(clo, chi, vp) {
            return Outcome::Culled;
        }
    }
    let l = node.depth();
    if l < vp.l_max {
        let depths = edge_depths(node);
        let mut flat = [true; 4];
        let mut edges_flat = true;
        // Every pending edge is tested, with no early exit: the children
        // inherit the results.
        for (e, f) in flat.iter_mut().enumerate() {
            if depths[e] >= l {
                *f = edge_flat(&sub.edge(e), vp);
                edges_flat &= *f;
            }
        }
        if !edges_flat || !inner_flat(&sub, vp) {
            return Outcome::Split(children(node, resolve_depths(node, depths, flat)));
        }
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
    assert_eq!(patches.len(), flags.len());
    let mut out = SubdivResult::default();
    out.stats.patches = patches.len() as u64;
    let mut stack = Vec::with_capacity(64);
    for (id, base) in patches.iter().enumerate() {
        stack.push(QuadNode::root(id as u32));
        while let Some(node) = stack.pop() {
            out.stats.nodes_processed += 1;
            match process(base, flags[id], node, vp) {
                Outcome::Culled => out.stats.culled_patches += 1,
                Outcome::BackFacing => out.stats.backface_culled += 1,
                Outcome::Ready => {
                    let l = node.depth();
                    out.stats.ready_quads += 1;
                    out.stats.max_depth = out.stats.max_depth.max(l);
                    out.stats.nodes_at_lmax += (l >= vp.l_max) as u64;
                    out.ready.push(node);
                }
                // Reversed so the children pop in order 0..3.
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
    let threads = threads.clamp(1, 64);
    if threads == 1 || patches.len() < 64 {
        return subdivide(patches, flags, vp);
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
                let mut r = subdivide(&patches[range.clone()], &flags[range], vp);
                for q in &mut r.ready {
                    q.patch += (k * chunk) as u32;
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
pub fn node_positions(base: &BezierPatch, mesh: &NodeMesh) -> [Vec3; 6] {
    let mut p = [Vec3::ZERO; 6];
    for (i, &(u, v)) in mesh.uv.iter().enumerate().take(mesh.vertex_count) {
        p[i] = base.eval(u, v);
    }
    p
}

/// The triangles of `ready` nodes (two per quad plus wedges, if enabled).
pub fn triangulate(
    patches: &[BezierPatch],
    ready: &[QuadNode],
    with_wedges: bool,
) -> Vec<Triangle> {
    let mut tris = Vec::with_capacity(ready.len() * 2 + ready.len() / 2);
    for &node in ready {
        let base = &patches[node.patch as usize];
        let mesh = node_mesh(node, with_wedges);
        let pos = node_positions(base, &mesh);
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
