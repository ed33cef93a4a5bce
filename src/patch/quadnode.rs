//! The 8-byte quad-tree node of paper §3.1 and §3.4.
//!
//! Word 0 is the base patch id. Word 1 packs, from the least significant bit:
//! depth `l` (4 bits), `m` (10), `n` (10), `l0` (4), `l1` (4). The node covers
//! [m, m+1]·2^-l × [n, n+1]·2^-l of its base patch. `l0` and `l1` are the
//! depths at which the node's two *outer* edges (the ones it shares with its
//! parent's boundary) were found flat; see [`super::wedge`] for their meaning.
//! The same layout is used on the GPU as a `uvec2`.

use bytemuck::{Pod, Zeroable};

use super::ops::pow2_neg;

/// Deepest subdivision level the 10-bit `m`, `n` fields allow.
pub use crate::constants::L_MAX;
use crate::constants::{
    NODE_DEPTH_SHIFT as DEPTH_SHIFT, NODE_L0_SHIFT as L0_SHIFT, NODE_L1_SHIFT as L1_SHIFT,
    NODE_M_SHIFT as M_SHIFT, NODE_N_SHIFT as N_SHIFT,
};
const MASK4: u32 = 0xf;
const MASK10: u32 = 0x3ff;

/// A sub-patch: base patch id plus quad-tree coordinates and inherited edge
/// flatness depths. Ordering is by (patch, packed bits), used to compare
/// ready sets as sorted lists.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Pod, Zeroable)]
pub struct QuadNode {
    /// Base patch index.
    pub patch: u32,
    /// Packed depth, m, n, l0, l1.
    pub bits: u32,
}

impl QuadNode {
    /// Packs a node. Fields must be in range (`depth`, `l0`, `l1` ≤ 15 and at
    /// most `depth`; `m`, `n` < 2^depth ≤ 1024).
    pub fn new(patch: u32, depth: u32, m: u32, n: u32, l0: u32, l1: u32) -> Self {
        debug_assert!(depth <= L_MAX && l0 <= depth && l1 <= depth);
        debug_assert!(m < (1 << depth) && n < (1 << depth));
        let bits = (depth << DEPTH_SHIFT)
            | (m << M_SHIFT)
            | (n << N_SHIFT)
            | (l0 << L0_SHIFT)
            | (l1 << L1_SHIFT);
        QuadNode { patch, bits }
    }

    /// The whole base patch, depth 0.
    pub fn root(patch: u32) -> Self {
        QuadNode { patch, bits: 0 }
    }

    /// Subdivision depth `l`.
    pub fn depth(self) -> u32 {
        (self.bits >> DEPTH_SHIFT) & MASK4
    }
    /// Node index along u.
    pub fn m(self) -> u32 {
        (self.bits >> M_SHIFT) & MASK10
    }
    /// Node index along v.
    pub fn n(self) -> u32 {
        (self.bits >> N_SHIFT) & MASK10
    }
    /// Flat depth of the outer edge running along u (bottom if `n` is even,
    /// top if odd).
    pub fn l0(self) -> u32 {
        (self.bits >> L0_SHIFT) & MASK4
    }
    /// Flat depth of the outer edge running along v (left if `m` is even,
    /// right if odd).
    pub fn l1(self) -> u32 {
        (self.bits >> L1_SHIFT) & MASK4
    }

    /// Parameter domain `(a, b, c, d)` = [a,b]×[c,d], exact in f32.
    pub fn domain(self) -> (f32, f32, f32, f32) {
        let s = pow2_neg(self.depth());
        let (m, n) = (self.m() as f32, self.n() as f32);
        (m * s, (m + 1.0) * s, n * s, (n + 1.0) * s)
    }

    /// Child `(x, y)` ∈ {0,1}², i.e. `(l+1, 2m+x, 2n+y)`, carrying the given
    /// inherited edge depths.
    pub fn child(self, x: u32, y: u32, l0: u32, l1: u32) -> Self {
        QuadNode::new(
            self.patch,
            self.depth() + 1,
            2 * self.m() + x,
            2 * self.n() + y,
            l0,
            l1,
        )
    }

    /// `(l-1, m/2, n/2)` of the parent, or `None` at the root.
    pub fn parent_coords(self) -> Option<(u32, u32, u32)> {
        let l = self.depth();
        (l > 0).then(|| (l - 1, self.m() >> 1, self.n() >> 1))
    }

    /// The 8 bytes as one little-endian u64 (patch in the low word).
    pub fn to_u64(self) -> u64 {
        (self.patch as u64) | ((self.bits as u64) << 32)
    }

    /// Inverse of [`QuadNode::to_u64`].
    pub fn from_u64(x: u64) -> Self {
        QuadNode {
            patch: x as u32,
            bits: (x >> 32) as u32,
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

    #[test]
    fn pack_unpack_round_trips() {
        let mut rng = SmallRng::seed_from_u64(7);
        for _ in 0..100_000 {
            let patch = rng.random::<u32>();
            let depth = rng.random_range(0..=L_MAX);
            let m = rng.random_range(0..1u32 << depth);
            let n = rng.random_range(0..1u32 << depth);
            let l0 = rng.random_range(0..=depth);
            let l1 = rng.random_range(0..=depth);
            let q = QuadNode::new(patch, depth, m, n, l0, l1);
            assert_eq!(
                (q.patch, q.depth(), q.m(), q.n(), q.l0(), q.l1()),
                (patch, depth, m, n, l0, l1)
            );
            assert_eq!(QuadNode::from_u64(q.to_u64()), q);
            assert_eq!(bytemuck::bytes_of(&q), &q.to_u64().to_le_bytes());
        }
    }

    #[test]
    fn children_tile_the_parent() {
        let mut rng = SmallRng::seed_from_u64(11);
        for _ in 0..10_000 {
            let depth = rng.random_range(0..L_MAX);
            let q = QuadNode::new(
                3,
                depth,
                rng.random_range(0..1u32 << depth),
                rng.random_range(0..1u32 << depth),
                0,
                0,
            );
            let (a, b, c, d) = q.domain();
            for y in 0..2 {
                for x in 0..2 {
                    let ch = q.child(x, y, depth, 0);
                    assert_eq!(ch.depth(), depth + 1);
                    assert_eq!(ch.parent_coords(), Some((depth, q.m(), q.n())));
                    assert_eq!((ch.m() & 1, ch.n() & 1), (x, y));
                    let (ca, cb, cc, cd) = ch.domain();
                    let (mu, mv) = ((a + b) * 0.5, (c + d) * 0.5);
                    assert_eq!((ca, cb), if x == 0 { (a, mu) } else { (mu, b) });
                    assert_eq!((cc, cd), if y == 0 { (c, mv) } else { (mv, d) });
                }
            }
        }
        assert_eq!(QuadNode::root(5).parent_coords(), None);
        assert_eq!(QuadNode::root(5).domain(), (0.0, 1.0, 0.0, 1.0));
    }
}
