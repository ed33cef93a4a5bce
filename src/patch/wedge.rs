//! Edge states, their inheritance, splits and wedge triangles (paper §3.4).
//!
//! Every edge of a node carries a state: the depth, in the edge's own
//! direction (u for the bottom and top edges, v for left and right), at
//! which it was found flat, or [`EDGE_PENDING`] while it has not been tested
//! at the node's depth. A root has four pending edges. A split hands each
//! child the states of the parent's edges it lies on (a half of a parent
//! edge keeps the parent's state) and gives it a pending state for the new
//! edge the split created inside the parent.
//!
//! Which way a node splits: `iso` (the paper) always 1:4. `aniso` halves
//! only the direction whose edges asked for it: u when an edge along u is
//! not flat, v when an edge along v is not, both when edges of both kinds
//! are not or when every edge is flat and the inner tier is not (the inner
//! tier decides what it decides under `iso`). A direction at `l_max` is not
//! split any further; a node that can split in neither is drawn.
//!
//! Why neighbours agree without talking to each other: a pending edge is
//! tested from its own four control points, bit-identical on both sides, at
//! the depth (in its direction) both sides have it at. If it is not flat,
//! both halve that direction (a node with a non-flat edge along u always
//! splits in u), so both test the halves, at the same depth again; once it
//! is flat, both keep that depth for every piece of it, however finely
//! either side goes on to split for other reasons. Under `iso` this is the
//! paper's scheme exactly (the two states a child inherits are its `l0` and
//! `l1`); `aniso` needs the other two because a 1:2 split leaves a child
//! three edges of its parent, and more splits all four.
//!
//! Project decisions:
//! - An edge found flat is **not tested again** at finer depths. Both sides of
//!   a shared edge inherit the same result from the same test, so skipping is
//!   consistent, and it saves work.
//! - A ready node with an edge flat at depth `le` coarser than its own depth
//!   in that direction closes the crack to its coarser neighbour with a
//!   wedge: the triangle from its own edge to the pivot, the node's
//!   coordinate along the edge rounded **down** to depth `le`, i.e. the start
//!   of the coarse edge in this patch's parameterisation. All fine nodes
//!   along one coarse edge thus fan from the same coarse vertex, and the fan
//!   exactly spans the polygon between the fine polyline and the coarse
//!   chord. (Rounding some nodes up and others down would leave a triangle of
//!   that polygon uncovered.) A node that starts at the coarse vertex has a
//!   degenerate wedge, which is omitted. Under `iso` only the two edges a
//!   node shares with its parent's boundary can have wedges; under `aniso`
//!   all four can.
//! - Wedges are wound opposite to the quad's traversal of the shared edge, so
//!   the triangulation stays consistently oriented (front faces stay front).

use super::bezier::{EDGE_BOTTOM, EDGE_LEFT, EDGE_TOP};
use super::ops::{cross3, dot3, pow2_neg};
pub use super::quadnode::EDGE_PENDING;
use super::quadnode::{along_u, QuadNode};
use crate::constants::{WEDGE_LIT_BACK, WEDGE_LIT_FRONT};
use glam::Vec3;

/// Which edges are still to be test at the node's depth.
pub fn pending(node: QuadNode) -> [bool; 4] {
    node.edges().map(|s| s == EDGE_PENDING)
}

/// The states a node passes down after testing its pending edges
/// (`flat_now[e]`, read only where pending): flat now becomes the node's
/// depth in the edge's direction; not flat stays pending (the children
/// test the halves); inherited states are kept.
pub fn resolve(node: QuadNode, flat_now: [bool; 4]) -> [u32; 4] {
    std::array::from_fn(|e| match node.edge(e) {
        EDGE_PENDING if flat_now[e] => node.depth_along(e),
        s => s,
    })
}

/// Which way a node splits: (halve u, halve v).
pub type Split = (bool, bool);

/// The children of a split, each carrying the resolved states of the
/// parent edges it lies on and a pending state for the new ones; in the
/// order (0,0), (1,0), (0,1), (1,1) of those that exist (two for a 1:2
/// split, four for 1:4).
pub fn children(node: QuadNode, split: Split, resolved: [u32; 4]) -> ([QuadNode; 4], usize) {
    let (in_u, in_v) = split;
    let mut out = [node; 4];
    let mut k = 0;
    for y in 0..=in_v as u32 {
        for x in 0..=in_u as u32 {
            // A child lies on the parent's edge e unless the split cut
            // across it: then that side of the child is the new edge.
            let keep = |e: usize| match e {
                EDGE_BOTTOM => y == 0,
                EDGE_TOP => y == 1 || !in_v,
                EDGE_LEFT => x == 0,
                _ => x == 1 || !in_u,
            };
            let edges = std::array::from_fn(|e| if keep(e) { resolved[e] } else { EDGE_PENDING });
            out[k] = node.child(split, (x, y), edges);
            k += 1;
        }
    }
    (out, k)
}

/// Vertices of a ready node in parameter space, as exact (u, v) pairs:
/// 0..4 are the corners (a,c), (b,c), (b,d), (a,d); 4 + e the pivot of the
/// wedge on edge e. `tris` lists the triangles as vertex indices, the two
/// quad triangles first, then the wedges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeMesh {
    /// Parameter-space vertices; only the first `vertex_count` are used.
    pub uv: [(f32, f32); 8],
    /// Number of vertices used.
    pub vertex_count: usize,
    /// Triangles as vertex indices; only the first `tri_count` are used.
    pub tris: [[u8; 3]; 6],
    /// Number of triangles (2 + wedges).
    pub tri_count: usize,
}

impl NodeMesh {
    /// Number of wedge triangles.
    pub fn wedges(&self) -> usize {
        self.tri_count - 2
    }
}

/// The pivot (u, v) of the wedge on each edge (`EDGE_*`): the node's
/// coordinate along an edge flat at a coarser depth than the node's in that
/// direction, rounded down to that depth; `None` where the edge is not flat
/// at a coarser depth or the pivot is the node's own corner. Every
/// descendant along that edge has the same pivot, which is why frustum
/// culling must keep a node whose pivots are in view.
pub fn wedge_pivots(node: QuadNode) -> [Option<(f32, f32)>; 4] {
    let (du, dv) = (node.du(), node.dv());
    let (m, n) = (node.m(), node.n());
    let (su, sv) = (pow2_neg(du), pow2_neg(dv));
    let rounded = |k: u32, d: u32, le: u32| (k >> (d - le)) << (d - le);
    std::array::from_fn(|e| {
        let le = node.edge(e);
        let d = node.depth_along(e);
        if le == EDGE_PENDING || le >= d {
            return None;
        }
        if along_u(e) {
            let mp = rounded(m, d, le);
            let v = if e == EDGE_BOTTOM { n } else { n + 1 };
            (mp != m).then_some((mp as f32 * su, v as f32 * sv))
        } else {
            let np = rounded(n, d, le);
            let u = if e == EDGE_LEFT { m } else { m + 1 };
            (np != n).then_some((u as f32 * su, np as f32 * sv))
        }
    })
}

/// The wedge on edge `e`: the edge as the quad does not traverse it (the
/// quad runs 0 → 1 → 2 → 3), then the pivot in slot 4 + e.
const WEDGE_TRIS: [[u8; 3]; 4] = [[1, 0, 4], [2, 1, 5], [3, 2, 6], [0, 3, 7]];

/// Builds the triangles of a ready node: two triangles split along the
/// (0,0)–(1,1) diagonal, plus a wedge on each edge flat at a coarser depth
/// whose pivot differs from the edge's end points.
pub fn node_mesh(node: QuadNode, with_wedges: bool) -> NodeMesh {
    let (a, b, c, d) = node.domain();
    let mut mesh = NodeMesh {
        uv: [
            (a, c),
            (b, c),
            (b, d),
            (a, d),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
            (0.0, 0.0),
        ],
        vertex_count: 4,
        tris: [[0, 1, 2], [0, 2, 3], [0; 3], [0; 3], [0; 3], [0; 3]],
        tri_count: 2,
    };
    if !with_wedges {
        return mesh;
    }
    for (e, pivot) in wedge_pivots(node).into_iter().enumerate() {
        if let Some(p) = pivot {
            // Pivot slots are fixed (4 + edge) so the GPU can write them
            // without compaction; the used count covers the highest slot.
            let slot = 4 + e;
            mesh.uv[slot] = p;
            mesh.vertex_count = mesh.vertex_count.max(slot + 1);
            mesh.tris[mesh.tri_count] = WEDGE_TRIS[e];
            mesh.tri_count += 1;
        }
    }
    mesh
}

/// Whether the triangle `a b c`, as wound, faces the eye at `eye` (the
/// negation of [`super::cull::wedges_face_away`]'s test).
fn faces_eye(a: Vec3, b: Vec3, c: Vec3, eye: Vec3) -> bool {
    let n = cross3(b - a, c - a);
    // As the GPU's !(side > 0): a degenerate (NaN) triangle counts as facing.
    let side = dot3(n, a - eye);
    side <= 0.0 || side.is_nan()
}

/// The point across edge `e` of a node with domain (a, b, c, d), as far
/// from the edge as the node is wide (the quad triangle's third corner
/// mirrored in the edge). Exact: the parameters are dyadic.
fn across_edge((a, b, c, d): (f32, f32, f32, f32), e: usize) -> (f32, f32) {
    match e {
        0 => (b, c + (c - d)),
        1 => (b + (b - a), c),
        2 => (a, d + (d - c)),
        _ => (a + (a - b), d),
    }
}

/// The coarse neighbour across edge `e` of `node`, whose crack the wedge
/// on that edge closes, as a square node of the edge's flat depth with a
/// corner at the wedge's `pivot`: its quad triangle along the edge, in the
/// parameters of the node's base patch (beyond its domain at a patch
/// border).
fn neighbour_triangle(node: QuadNode, e: usize, pivot: (f32, f32)) -> [(f32, f32); 3] {
    let s = pow2_neg(node.edge(e));
    let (a, b, c, d) = node.domain();
    let (pu, pv) = pivot;
    match e {
        0 => [(pu, c - s), (pu + s, c), (pu, c)],
        1 => [(b, pv), (b + s, pv + s), (b, pv + s)],
        2 => [(pu, d), (pu + s, d), (pu + s, d + s)],
        _ => [(a - s, pv), (a, pv), (a, pv + s)],
    }
}

/// The `WEDGE_*` code a draw hands the fragment stage for the wedge on edge
/// `e` of `node` (present, its pivot at `pivot`), whose corners are drawn
/// at `corners` (slots 0..4) and whose base patch is drawn by `eval`. A
/// wedge's own winding says little (it folds over where the fine polyline
/// dips below the coarse chord), so it is lit from the front when the
/// surface on either side of its edge faces the eye: the node's quad
/// triangle along the edge (0 1 2 for the bottom and right edges, 0 2 3 for
/// the top and left), a triangle as large mirrored across the edge, or the
/// coarse neighbour's quad triangle ([`neighbour_triangle`]). At a
/// silhouette a node can lie wholly beyond it, facing away, while its
/// wedge shows in front of the neighbour's front surface. At a patch
/// border the last two lie on the patch's extension beyond its domain,
/// which stands in for the next patch only where both agree. The twin of
/// draw_rational.glsl's `wedge_code` (see there for what was measured).
pub fn wedge_code(
    node: QuadNode,
    corners: [Vec3; 4],
    e: usize,
    pivot: (f32, f32),
    eye: Vec3,
    eval: impl Fn(f32, f32) -> Vec3,
) -> u32 {
    let [a, b, c] = [[0, 1, 2], [0, 2, 3]][e >> 1].map(|k| corners[k]);
    if faces_eye(a, b, c, eye) {
        return WEDGE_LIT_FRONT;
    }
    // The wedge's own corners run the edge backwards: with the point across
    // the edge in the pivot's place they wind as the surface does.
    let [w0, w1] = [0, 1].map(|k| corners[WEDGE_TRIS[e][k] as usize]);
    let (u, v) = across_edge(node.domain(), e);
    let inside = (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v);
    let mirror = faces_eye(w0, w1, eval(u, v), eye);
    let [p, q, r] = neighbour_triangle(node, e, pivot).map(|(u, v)| eval(u, v));
    let coarse = faces_eye(p, q, r, eye);
    if (inside && (mirror || coarse)) || (mirror && coarse) {
        WEDGE_LIT_FRONT
    } else {
        WEDGE_LIT_BACK
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const P: u32 = EDGE_PENDING;

    #[test]
    fn root_has_all_edges_pending() {
        assert_eq!(pending(QuadNode::root(0)), [true; 4]);
    }

    #[test]
    fn inheritance_follows_child_position() {
        let root = QuadNode::root(1);
        // Bottom flat at 0, right not flat, top flat, left not flat.
        let r = resolve(root, [true, false, true, false]);
        assert_eq!(r, [0, P, 0, P]);
        let (ch, k) = children(root, (true, true), r);
        assert_eq!(k, 4);
        // Lower-left: bottom (0) and left (pending), new top and right.
        assert_eq!(ch[0].edges(), [0, P, P, P]);
        // Lower-right: bottom (0) and right.
        assert_eq!(ch[1].edges(), [0, P, P, P]);
        // Upper-left: top (0) and left.
        assert_eq!(ch[2].edges(), [P, P, 0, P]);
        // Inherited-flat edges stay at their depth two levels down.
        let r1 = resolve(ch[2], [false; 4]);
        assert_eq!(r1, [P, P, 0, P]);
        let g = children(ch[2], (true, true), r1).0[3];
        assert_eq!(g.edge(EDGE_TOP), 0);
    }

    /// A 1:2 split in u keeps both edges along u on both children (halves
    /// of the parent's) and one edge along v each; the new middle edge is
    /// pending. An edge along v found flat now keeps the node's v depth:
    /// the child, at the same v depth, neither re-tests nor wedges it.
    #[test]
    fn a_split_in_u_hands_down_three_edges() {
        let root = QuadNode::root(2);
        let r = resolve(root, [false, true, true, true]);
        assert_eq!(r, [P, 0, 0, 0]);
        let (ch, k) = children(root, (true, false), r);
        assert_eq!(k, 2);
        assert_eq!((ch[0].du(), ch[0].dv()), (1, 0));
        assert_eq!(ch[0].edges(), [P, P, 0, 0]);
        assert_eq!(ch[1].edges(), [P, 0, 0, P]);
        assert_eq!(wedge_pivots(ch[0])[EDGE_LEFT], None);
        // The top edge, flat at u depth 0, gets a wedge on the right child
        // (its pivot rounds m = 1 down to 0); the left child starts there.
        assert_eq!(wedge_pivots(ch[1])[EDGE_TOP], Some((0.0, 1.0)));
        assert_eq!(wedge_pivots(ch[0])[EDGE_TOP], None);
        let (ch, k) = children(
            root,
            (false, true),
            resolve(root, [true, true, true, false]),
        );
        assert_eq!(k, 2);
        assert_eq!((ch[1].du(), ch[1].dv()), (0, 1));
        assert_eq!(ch[0].edges(), [0, 0, P, P]);
        assert_eq!(ch[1].edges(), [P, 0, 0, P]);
    }

    #[test]
    fn wedges_pivot_at_the_coarse_edge_start() {
        // Depth 2, m = 3: a node along a bottom edge flat at 0.
        let node = QuadNode::new(0, (2, 3), (2, 0), [0, P, P, 2]);
        let mesh = node_mesh(node, true);
        assert_eq!(mesh.tri_count, 3);
        assert_eq!(mesh.uv[4], (0.0, 0.0));
        assert_eq!(mesh.tris[2], [1, 0, 4]);
        // m = 0 starts at the coarse vertex: degenerate, omitted.
        let first = QuadNode::new(0, (2, 0), (2, 0), [0, P, P, 2]);
        assert_eq!(node_mesh(first, true).tri_count, 2);
        // Right edge flat at depth 1, node at depth 3 with n = 5: the pivot
        // rounds n to 4.
        let node = QuadNode::new(0, (3, 7), (3, 5), [P, 1, 3, P]);
        let mesh = node_mesh(node, true);
        assert_eq!(mesh.tri_count, 3);
        assert_eq!(mesh.uv[5], (1.0, 0.5));
        assert_eq!(mesh.tris[2], [2, 1, 5]);
        assert_eq!(node_mesh(node, false).tri_count, 2);
        // All four edges flat coarser: four wedges.
        let node = QuadNode::new(0, (3, 3), (2, 1), [1, 0, 1, 0]);
        let mesh = node_mesh(node, true);
        assert_eq!(mesh.tri_count, 6);
        assert_eq!(mesh.vertex_count, 8);
        assert_eq!(mesh.uv[4], (0.0, 0.25));
        assert_eq!(mesh.uv[6], (0.0, 0.5));
        assert_eq!(mesh.uv[7], (0.375, 0.0));
        assert_eq!(mesh.uv[5], (0.5, 0.0));
    }
}
