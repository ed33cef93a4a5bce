//! Which patch sides are the same boundary curve: the neighbourhood
//! `cudatess` makes its edge factors consistent over (Schwarz and
//! Stamminger: "neighborhood information provided by the application").
//!
//! Two sides are one edge when their four control points and weights are
//! bit-identical, read in the same or in opposite directions. That is
//! exactly the condition under which the two patches trace the same curve
//! and (with the reversal-symmetric evaluation) compute the same points on
//! it; the cage converter and the `.bpt` readers produce shared boundary
//! points bit for bit. A side nobody else has is a boundary edge, alone in
//! its group; a collapsed side (a pole) is shared by every patch that
//! collapses to the same point; a non-manifold edge by all its patches.

use std::collections::HashMap;

use crate::patch::bezier::BezierPatch;
use crate::patch::rational::{edge_indices, Weights, UNIT_WEIGHTS};

/// The edge of every patch side, numbered 0..count.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EdgeTable {
    /// Per patch, the edge ids of its sides 0: u = 0, 1: v = 0, 2: u = 1,
    /// 3: v = 1.
    pub ids: Vec<[u32; 4]>,
    /// Distinct edges.
    pub count: u32,
}

/// An edge by the bits of its points and weights, in the smaller direction.
type Key = [u32; 16];

fn side_key(p: &BezierPatch, w: &Weights, side: usize) -> Key {
    let idx = edge_indices(side);
    let bits = |order: [usize; 4]| -> Key {
        let mut k = [0u32; 16];
        for (n, &i) in order.iter().enumerate() {
            let q = p.pts[i];
            k[4 * n..4 * n + 4].copy_from_slice(&[
                q.x.to_bits(),
                q.y.to_bits(),
                q.z.to_bits(),
                w[i].to_bits(),
            ]);
        }
        k
    };
    let fwd = bits(idx);
    let rev = bits([idx[3], idx[2], idx[1], idx[0]]);
    fwd.min(rev)
}

/// The edge table of `patches` with `weights` (empty: all weights 1).
/// Ids are given in order of first appearance, so the table is a function
/// of the scene alone.
pub fn edge_table(patches: &[BezierPatch], weights: &[Weights]) -> EdgeTable {
    let mut index: HashMap<Key, u32> = HashMap::with_capacity(patches.len() * 2);
    let mut ids = Vec::with_capacity(patches.len());
    for (k, p) in patches.iter().enumerate() {
        let w = weights.get(k).unwrap_or(&UNIT_WEIGHTS);
        let mut sides = [0u32; 4];
        for (side, id) in sides.iter_mut().enumerate() {
            let next = index.len() as u32;
            *id = *index.entry(side_key(p, w, side)).or_insert(next);
        }
        ids.push(sides);
    }
    EdgeTable {
        ids,
        count: index.len() as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::fixtures::ramp;

    #[test]
    fn shared_sides_get_one_id_and_weights_count() {
        // Patch 1 starts where patch 0 ends: side 2 of 0 is side 0 of 1.
        let a = ramp(0.0);
        let mut b = ramp(3.0);
        for j in 0..4 {
            b.pts[4 * j] = a.pts[4 * j + 3];
        }
        let t = edge_table(&[a, b], &[]);
        assert_eq!(t.count, 7);
        assert_eq!(t.ids[0][2], t.ids[1][0]);
        // Reversed traversal is the same edge.
        let flipped = b.reoriented(false, false, true);
        let t = edge_table(&[a, flipped], &[]);
        assert_eq!(t.ids[0][2], t.ids[1][0]);
        // Different weights on the shared points: a different curve.
        let mut w = UNIT_WEIGHTS;
        w[4] = 2.0;
        let t = edge_table(&[a, b], &[UNIT_WEIGHTS, w]);
        assert_ne!(t.ids[0][2], t.ids[1][0]);
        assert_eq!(t.count, 8);
    }
}
