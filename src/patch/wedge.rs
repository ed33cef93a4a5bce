//! Edge flatness depths, their inheritance, and wedge triangles (paper §3.4).
//!
//! Every edge of a node carries the depth at which it was found flat. A node
//! at depth `l` knows its two *outer* edges' depths from its parent (`l0` for
//! the edge along u, `l1` for the edge along v); its two inner edges were
//! created by the split that made it, so they are at depth `l`. An edge depth
//! below `l` means "this edge lies on an edge found flat at that coarser
//! depth"; equal to `l` means "not yet known flat: test it now".
//!
//! Project decisions:
//! - An edge found flat is **not tested again** at finer depths. Both sides of
//!   a shared edge inherit the same result from the same test (at the depth
//!   where both had it as a whole edge), so skipping is consistent, and it
//!   saves work. The node's decision then rests on its still-pending edges and
//!   the inner tier.
//! - A ready node with an outer edge flat at depth `le < l` closes the crack
//!   to its coarser neighbour with a wedge: the triangle from its own edge to
//!   the pivot, the node's coordinate along the edge rounded **down** to depth
//!   `le`, i.e. the start of the coarse edge in this patch's parameterisation.
//!   All fine nodes along one coarse edge thus fan from the same coarse
//!   vertex, and the fan exactly spans the polygon between the fine polyline
//!   and the coarse chord. (Rounding some nodes up and others down would leave
//!   a triangle of that polygon uncovered.) A node that starts at the coarse
//!   vertex has a degenerate wedge, which is omitted.
//! - Wedges are wound opposite to the quad's traversal of the shared edge, so
//!   the triangulation stays consistently oriented (front faces stay front).

use super::bezier::{EDGE_BOTTOM, EDGE_LEFT, EDGE_RIGHT, EDGE_TOP};
use super::ops::pow2_neg;
use super::quadnode::QuadNode;

/// Flat depths of the node's edges, indexed by `EDGE_*`.
pub fn edge_depths(node: QuadNode) -> [u32; 4] {
    let l = node.depth();
    let mut d = [l; 4];
    if node.n() & 1 == 0 {
        d[EDGE_BOTTOM] = node.l0();
    } else {
        d[EDGE_TOP] = node.l0();
    }
    if node.m() & 1 == 0 {
        d[EDGE_LEFT] = node.l1();
    } else {
        d[EDGE_RIGHT] = node.l1();
    }
    d
}

/// The edge depths a node passes down after testing its pending edges:
/// unchanged where inherited flat, `l` where found flat now, `l + 1` (pending
/// in the child) where not flat.
pub fn resolve_depths(node: QuadNode, depths: [u32; 4], flat_now: [bool; 4]) -> [u32; 4] {
    let l = node.depth();
    let mut r = depths;
    for e in 0..4 {
        if depths[e] >= l {
            r[e] = if flat_now[e] { l } else { l + 1 };
        }
    }
    r
}

/// The four children, in the order (0,0), (1,0), (0,1), (1,1), each
/// inheriting the resolved depths of the parent edges it lies on.
pub fn children(node: QuadNode, resolved: [u32; 4]) -> [QuadNode; 4] {
    let mk = |x: u32, y: u32| {
        let l0 = resolved[if y == 0 { EDGE_BOTTOM } else { EDGE_TOP }];
        let l1 = resolved[if x == 0 { EDGE_LEFT } else { EDGE_RIGHT }];
        node.child(x, y, l0, l1)
    };
    [mk(0, 0), mk(1, 0), mk(0, 1), mk(1, 1)]
}

/// Vertices of a ready node in parameter space, as exact (u, v) pairs:
/// 0..4 are the corners (a,c), (b,c), (b,d), (a,d); then up to two pivots.
/// `tris` lists the triangles as vertex indices, the two quad triangles
/// first, then the wedges; `wedges` of them are wedges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NodeMesh {
    /// Parameter-space vertices; only the first `vertex_count` are used.
    pub uv: [(f32, f32); 6],
    /// Number of vertices used.
    pub vertex_count: usize,
    /// Triangles as vertex indices; only the first `tri_count` are used.
    pub tris: [[u8; 3]; 4],
    /// Number of triangles (2 + wedges).
    pub tri_count: usize,
}

impl NodeMesh {
    /// Number of wedge triangles.
    pub fn wedges(&self) -> usize {
        self.tri_count - 2
    }
}

/// The pivots (u, v) of the node's wedges, along u (on the bottom or top
/// outer edge) and along v (left or right): the node's coordinate along an
/// outer edge flat at a coarser depth, rounded down to that depth; `None`
/// where the edge is not flat at a coarser depth or the pivot is the node's
/// own corner. Every descendant along that edge has the same pivot, which is
/// why frustum culling must keep a node whose pivots are in view.
pub fn wedge_pivots(node: QuadNode) -> [Option<(f32, f32)>; 2] {
    let l = node.depth();
    let s = pow2_neg(l);
    let (m, n) = (node.m(), node.n());
    let u = |k: u32| k as f32 * s;
    let mut out = [None, None];
    let le = node.l0();
    if le < l {
        let mp = (m >> (l - le)) << (l - le);
        if mp != m {
            let v_edge = if n & 1 == 0 { u(n) } else { u(n + 1) };
            out[0] = Some((u(mp), v_edge));
        }
    }
    let le = node.l1();
    if le < l {
        let np = (n >> (l - le)) << (l - le);
        if np != n {
            let u_edge = if m & 1 == 0 { u(m) } else { u(m + 1) };
            out[1] = Some((u_edge, u(np)));
        }
    }
    out
}

/// Builds the triangles of a ready node: two triangles split along the
/// (0,0)–(1,1) diagonal, plus a wedge on each outer edge flat at a coarser
/// depth whose pivot differs from the edge's end points.
pub fn node_mesh(node: QuadNode, with_wedges: bool) -> NodeMesh {
    let l = node.depth();
    let s = pow2_neg(l);
    let (m, n) = (node.m(), node.n());
    let u = |k: u32| k as f32 * s;
    let (a, b, c, d) = (u(m), u(m + 1), u(n), u(n + 1));
    let mut mesh = NodeMesh {
        uv: [(a, c), (b, c), (b, d), (a, d), (0.0, 0.0), (0.0, 0.0)],
        vertex_count: 4,
        tris: [[0, 1, 2], [0, 2, 3], [0; 3], [0; 3]],
        tri_count: 2,
    };
    if !with_wedges {
        return mesh;
    }
    let [along_u, along_v] = wedge_pivots(node);
    if let Some(p) = along_u {
        let bottom = n & 1 == 0;
        push_wedge(&mut mesh, p, if bottom { [1, 0, 4] } else { [3, 2, 4] });
    }
    if let Some(p) = along_v {
        let left = m & 1 == 0;
        push_wedge(&mut mesh, p, if left { [0, 3, 5] } else { [2, 1, 5] });
    }
    mesh
}

fn push_wedge(mesh: &mut NodeMesh, pivot: (f32, f32), tri: [u8; 3]) {
    // Pivot slots are fixed (4: along u, 5: along v) so the GPU can write
    // them without compaction; the used count covers the highest slot.
    let slot = tri[2] as usize;
    mesh.uv[slot] = pivot;
    mesh.vertex_count = mesh.vertex_count.max(slot + 1);
    mesh.tris[mesh.tri_count] = tri;
    mesh.tri_count += 1;
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn root_has_all_edges_pending() {
        assert_eq!(edge_depths(QuadNode::root(0)), [0; 4]);
    }

    #[test]
    fn inheritance_follows_child_position() {
        let root = QuadNode::root(1);
        // Bottom flat at 0, right not flat, top flat, left not flat.
        let r = resolve_depths(root, edge_depths(root), [true, false, true, false]);
        assert_eq!(r, [0, 1, 0, 1]);
        let ch = children(root, r);
        // Lower-left: bottom (0) and left (1).
        assert_eq!(edge_depths(ch[0]), [0, 1, 1, 1]);
        // Lower-right: bottom (0) and right (1).
        assert_eq!(edge_depths(ch[1]), [0, 1, 1, 1]);
        // Upper-left: top (0) and left (1).
        assert_eq!(edge_depths(ch[2]), [1, 1, 0, 1]);
        assert_eq!(ch[3].l0(), 0);
        // Inherited-flat edges stay at their depth two levels down.
        let r1 = resolve_depths(ch[2], edge_depths(ch[2]), [false; 4]);
        assert_eq!(r1, [2, 2, 0, 2]);
        let g = children(ch[2], r1)[3];
        assert_eq!(edge_depths(g)[EDGE_TOP], 0);
    }

    #[test]
    fn wedges_pivot_at_the_coarse_edge_start() {
        // Depth 2, m = 3: the top-right grandchild along a bottom edge flat at 0.
        let node = QuadNode::new(0, 2, 3, 0, 0, 2);
        let mesh = node_mesh(node, true);
        assert_eq!(mesh.tri_count, 3);
        assert_eq!(mesh.uv[4], (0.0, 0.0));
        assert_eq!(mesh.tris[2], [1, 0, 4]);
        // m = 0 starts at the coarse vertex: degenerate, omitted.
        let first = QuadNode::new(0, 2, 0, 0, 0, 2);
        assert_eq!(node_mesh(first, true).tri_count, 2);
        // Right edge flat at depth 1, node at depth 3 with n = 5 (odd → top
        // child, m odd → right child): pivot rounds n to 4.
        let node = QuadNode::new(0, 3, 7, 5, 3, 1);
        let mesh = node_mesh(node, true);
        assert_eq!(mesh.tri_count, 3);
        assert_eq!(mesh.uv[5], (1.0, 0.5));
        assert_eq!(mesh.tris[2], [2, 1, 5]);
        assert_eq!(node_mesh(node, false).tri_count, 2);
    }
}
