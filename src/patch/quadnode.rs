//! The 8-byte quad-tree node of paper §3.1 and §3.4, generalised to a depth
//! per direction so that a node can be halved in u or in v alone (1:2) as
//! well as 1:4 (`--split aniso`; `--split iso` only ever splits 1:4 and then
//! the two depths are equal).
//!
//! Layout (two 32-bit words, the GPU's `uvec2`):
//!
//! ```text
//!   word 0: patch id (24 bits) | bottom edge (4) | top edge (4)
//!   word 1: u code (11) | v code (11) | left edge (4) | right edge (4) | 0 (2)
//! ```
//!
//! The u code is `(1 << du) | m` (a leading one above the `du`-bit index, so
//! depth and index share 11 bits for `du` ≤ 10), likewise the v code. The
//! node covers [m, m+1]·2^-du × [n, n+1]·2^-dv of its base patch. Each edge
//! carries its state (see [`super::wedge`]): the depth, in the edge's own
//! direction, at which the edge was found flat, or [`EDGE_PENDING`] while it
//! still has to be tested. The paper's node needs two such states (its
//! children always have two brand-new inner edges); after a 1:2 split a child
//! inherits three edges from its parent, and further splits can leave all
//! four inherited at different depths, hence four. Patch ids fit 24 bits:
//! scenes hold at most `MAX_BASE_PATCHES` (the kernel's in-flight count).

use bytemuck::{Pod, Zeroable};

use super::bezier::{EDGE_BOTTOM, EDGE_RIGHT, EDGE_TOP};
use super::ops::pow2_neg;

/// Deepest subdivision level per direction the 11-bit codes allow.
pub use crate::constants::L_MAX;
/// The state of an edge that has not been tested at the node's depth.
pub use crate::constants::NODE_EDGE_PENDING as EDGE_PENDING;
use crate::constants::{
    NODE_BOTTOM_SHIFT, NODE_LEFT_SHIFT, NODE_PATCH_MASK, NODE_RIGHT_SHIFT, NODE_TOP_SHIFT,
    NODE_U_SHIFT, NODE_V_SHIFT,
};
const MASK4: u32 = 0xf;
const MASK11: u32 = 0x7ff;

/// Where edge `e`'s state lives: (word, shift).
const fn edge_slot(e: usize) -> (usize, u32) {
    match e {
        EDGE_BOTTOM => (0, NODE_BOTTOM_SHIFT),
        EDGE_RIGHT => (1, NODE_RIGHT_SHIFT),
        EDGE_TOP => (0, NODE_TOP_SHIFT),
        _ => (1, NODE_LEFT_SHIFT),
    }
}

/// Whether edge `e` runs along u (bottom, top) rather than v (left, right).
pub const fn along_u(e: usize) -> bool {
    e == EDGE_BOTTOM || e == EDGE_TOP
}

/// A sub-patch: base patch id, quad-tree coordinates per direction and the
/// state of each edge. Ordering is by the two words (patch first), used to
/// compare ready sets as sorted lists.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Pod, Zeroable)]
pub struct QuadNode {
    /// Patch id and the states of the edges along u.
    pub w0: u32,
    /// The u and v codes and the states of the edges along v.
    pub w1: u32,
}

impl QuadNode {
    /// Packs a node. `du`, `dv` ≤ [`L_MAX`], `m` < 2^du, `n` < 2^dv, each
    /// edge state ≤ the node's depth in its direction or [`EDGE_PENDING`],
    /// `patch` < 2^24.
    pub fn new(patch: u32, (du, m): (u32, u32), (dv, n): (u32, u32), edges: [u32; 4]) -> Self {
        debug_assert!(patch <= NODE_PATCH_MASK);
        debug_assert!(du <= L_MAX && dv <= L_MAX && m < (1 << du) && n < (1 << dv));
        let mut w = [
            patch,
            ((1 << du) | m) << NODE_U_SHIFT | ((1 << dv) | n) << NODE_V_SHIFT,
        ];
        for (e, &s) in edges.iter().enumerate() {
            debug_assert!(
                s == EDGE_PENDING || s <= if along_u(e) { du } else { dv },
                "edge {e} state {s} at depths ({du}, {dv})"
            );
            let (k, shift) = edge_slot(e);
            w[k] |= s << shift;
        }
        QuadNode { w0: w[0], w1: w[1] }
    }

    /// The whole base patch: depth 0 both ways, every edge pending.
    pub fn root(patch: u32) -> Self {
        QuadNode::new(patch, (0, 0), (0, 0), [EDGE_PENDING; 4])
    }

    /// Base patch index.
    pub fn patch(self) -> u32 {
        self.w0 & NODE_PATCH_MASK
    }

    /// The same node of another base patch (chunked runs renumber).
    pub fn with_patch(self, patch: u32) -> Self {
        debug_assert!(patch <= NODE_PATCH_MASK);
        QuadNode {
            w0: (self.w0 & !NODE_PATCH_MASK) | patch,
            w1: self.w1,
        }
    }

    fn u_code(self) -> u32 {
        (self.w1 >> NODE_U_SHIFT) & MASK11
    }

    fn v_code(self) -> u32 {
        (self.w1 >> NODE_V_SHIFT) & MASK11
    }

    /// Depth along u.
    pub fn du(self) -> u32 {
        31 - self.u_code().leading_zeros()
    }

    /// Depth along v.
    pub fn dv(self) -> u32 {
        31 - self.v_code().leading_zeros()
    }

    /// The deeper of the two depths (the node's depth under `iso`, where
    /// they are equal); what statistics and the depth heat map show.
    pub fn depth(self) -> u32 {
        self.du().max(self.dv())
    }

    /// Node index along u.
    pub fn m(self) -> u32 {
        self.u_code() ^ (1 << self.du())
    }

    /// Node index along v.
    pub fn n(self) -> u32 {
        self.v_code() ^ (1 << self.dv())
    }

    /// The node's depth in the direction edge `e` runs.
    pub fn depth_along(self, e: usize) -> u32 {
        if along_u(e) {
            self.du()
        } else {
            self.dv()
        }
    }

    /// The state of edge `e` (`EDGE_*`): its flat depth or [`EDGE_PENDING`].
    pub fn edge(self, e: usize) -> u32 {
        let (k, shift) = edge_slot(e);
        ([self.w0, self.w1][k] >> shift) & MASK4
    }

    /// The states of the four edges, indexed by `EDGE_*`.
    pub fn edges(self) -> [u32; 4] {
        std::array::from_fn(|e| self.edge(e))
    }

    /// Parameter domain `(a, b, c, d)` = [a,b]×[c,d], exact in f32.
    pub fn domain(self) -> (f32, f32, f32, f32) {
        let (su, sv) = (pow2_neg(self.du()), pow2_neg(self.dv()));
        let (m, n) = (self.m() as f32, self.n() as f32);
        (m * su, (m + 1.0) * su, n * sv, (n + 1.0) * sv)
    }

    /// The child at `(x, y)` of a split that halves u when `in_u` (else
    /// keeps u, and `x` must be 0) and v when `in_v`, carrying `edges`.
    pub fn child(self, (in_u, in_v): (bool, bool), (x, y): (u32, u32), edges: [u32; 4]) -> Self {
        debug_assert!((in_u || x == 0) && (in_v || y == 0));
        let (du, dv) = (self.du(), self.dv());
        let u = if in_u {
            (du + 1, 2 * self.m() + x)
        } else {
            (du, self.m())
        };
        let v = if in_v {
            (dv + 1, 2 * self.n() + y)
        } else {
            (dv, self.n())
        };
        QuadNode::new(self.patch(), u, v, edges)
    }

    /// The 8 bytes as one little-endian u64 (word 0 low).
    pub fn to_u64(self) -> u64 {
        (self.w0 as u64) | ((self.w1 as u64) << 32)
    }

    /// Inverse of [`QuadNode::to_u64`].
    pub fn from_u64(x: u64) -> Self {
        QuadNode {
            w0: x as u32,
            w1: (x >> 32) as u32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    #[test]
    fn size_is_eight_bytes() {
        assert_eq!(std::mem::size_of::<QuadNode>(), 8);
    }

    fn random_state(rng: &mut SmallRng, depth: u32) -> u32 {
        if rng.random_bool(0.3) {
            EDGE_PENDING
        } else {
            rng.random_range(0..=depth)
        }
    }

    #[test]
    fn pack_unpack_round_trips() {
        let mut rng = SmallRng::seed_from_u64(7);
        for _ in 0..100_000 {
            let patch = rng.random_range(0..=NODE_PATCH_MASK);
            let du = rng.random_range(0..=L_MAX);
            let dv = rng.random_range(0..=L_MAX);
            let m = rng.random_range(0..1u32 << du);
            let n = rng.random_range(0..1u32 << dv);
            let edges = std::array::from_fn(|e| {
                let d = if along_u(e) { du } else { dv };
                random_state(&mut rng, d)
            });
            let q = QuadNode::new(patch, (du, m), (dv, n), edges);
            assert_eq!(
                (q.patch(), q.du(), q.m(), q.dv(), q.n(), q.edges()),
                (patch, du, m, dv, n, edges)
            );
            assert_eq!(q.depth(), du.max(dv));
            assert_eq!(QuadNode::from_u64(q.to_u64()), q);
            assert_eq!(bytemuck::bytes_of(&q), &q.to_u64().to_le_bytes());
            assert_eq!(q.with_patch(5).patch(), 5);
            assert_eq!(q.with_patch(5).edges(), edges);
        }
    }

    #[test]
    fn children_tile_the_parent() {
        let mut rng = SmallRng::seed_from_u64(11);
        for _ in 0..10_000 {
            let (du, dv) = (rng.random_range(0..L_MAX), rng.random_range(0..L_MAX));
            let q = QuadNode::new(
                3,
                (du, rng.random_range(0..1u32 << du)),
                (dv, rng.random_range(0..1u32 << dv)),
                [EDGE_PENDING; 4],
            );
            let (a, b, c, d) = q.domain();
            let (mu, mv) = ((a + b) * 0.5, (c + d) * 0.5);
            for (in_u, in_v) in [(true, true), (true, false), (false, true)] {
                for y in 0..=in_v as u32 {
                    for x in 0..=in_u as u32 {
                        let ch = q.child((in_u, in_v), (x, y), [EDGE_PENDING; 4]);
                        assert_eq!(ch.du(), du + in_u as u32);
                        assert_eq!(ch.dv(), dv + in_v as u32);
                        let (ca, cb, cc, cd) = ch.domain();
                        let want_u = match (in_u, x) {
                            (false, _) => (a, b),
                            (true, 0) => (a, mu),
                            _ => (mu, b),
                        };
                        let want_v = match (in_v, y) {
                            (false, _) => (c, d),
                            (true, 0) => (c, mv),
                            _ => (mv, d),
                        };
                        assert_eq!(((ca, cb), (cc, cd)), (want_u, want_v));
                    }
                }
            }
        }
        assert_eq!(QuadNode::root(5).domain(), (0.0, 1.0, 0.0, 1.0));
        assert_eq!(QuadNode::root(5).edges(), [EDGE_PENDING; 4]);
    }
}
