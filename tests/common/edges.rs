//! Boundary curves that two base patches share, and the nodes along them.

use std::collections::{HashMap, HashSet};
use std::hash::Hash;

use bezier_subdiv::patch::criterion::{line_sample_terms, EdgeSample};
use bezier_subdiv::patch::ops::THIRD;
use bezier_subdiv::patch::oracle::Triangle;
use bezier_subdiv::patch::quadnode::{QuadNode, EDGE_PENDING};
use bezier_subdiv::patch::view::ViewParams;
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::Rng;

/// The node along edge `e` (counter-clockwise order) of a base patch
/// covering segment `k` of `2^l`, counted in that direction.
pub fn edge_node(patch: u32, e: usize, l: u32, k: u32) -> QuadNode {
    let last = (1u32 << l) - 1;
    let (m, n) = match e {
        0 => (k, 0),
        1 => (last, k),
        2 => (last - k, last),
        _ => (0, last - k),
    };
    QuadNode::new(patch, (l, m), (l, n), [EDGE_PENDING; 4])
}

/// A boundary curve shared by two base patches.
pub struct SharedEdge {
    pub a: (u32, usize),
    pub b: (u32, usize),
    pub reversed: bool,
}

/// Every pair of (patch, edge) uses of one boundary curve among `patches`
/// base patches. `curve(k, e)` gives the bits of edge `e` of patch `k`
/// forwards and backwards, or `None` for a collapsed edge (a pole, not an
/// edge between two patches).
pub fn shared_edges<K: Ord + Hash>(
    patches: usize,
    curve: impl Fn(usize, usize) -> Option<(K, K)>,
) -> Vec<SharedEdge> {
    // Curve bits (in the canonical direction) → (patch, edge, flipped).
    type Uses = Vec<(u32, usize, bool)>;
    let mut by_key: HashMap<K, Uses> = HashMap::new();
    for k in 0..patches {
        for e in 0..4 {
            let Some((fwd, rev)) = curve(k, e) else {
                continue;
            };
            // Key on the lexicographically smaller direction.
            let (key, flipped) = if fwd <= rev {
                (fwd, false)
            } else {
                (rev, true)
            };
            by_key.entry(key).or_default().push((k as u32, e, flipped));
        }
    }
    let mut out = Vec::new();
    for list in by_key.values() {
        for i in 0..list.len() {
            for j in i + 1..list.len() {
                let (pa, ea, fa) = list[i];
                let (pb, eb, fb) = list[j];
                out.push(SharedEdge {
                    a: (pa, ea),
                    b: (pb, eb),
                    reversed: fa != fb,
                });
            }
        }
    }
    out
}

/// The segments of depth `l` along an edge to check: all of them where
/// `all`, else `random` of them drawn from `rng`.
pub fn segments(l: u32, all: bool, random: usize, rng: &mut SmallRng) -> Vec<u32> {
    let segs = 1u32 << l;
    if all {
        (0..segs).collect()
    } else {
        (0..random).map(|_| rng.random_range(0..segs)).collect()
    }
}

/// The nodes of depth `l` on both sides of `se` covering segment `k`
/// (counted along side a) and their curves along the edge, `curve(node,
/// e)` rebuilding edge `e` of the node's sub-patch: `(na, nb, ca, cb,
/// cb_aligned)`, the last side b's curve turned to run the way side a's
/// does.
#[allow(clippy::type_complexity)]
pub fn sides<T: Copy>(
    se: &SharedEdge,
    l: u32,
    k: u32,
    curve: impl Fn(QuadNode, usize) -> [T; 4],
) -> (QuadNode, QuadNode, [T; 4], [T; 4], [T; 4]) {
    let segs = 1u32 << l;
    let kb = if se.reversed { segs - 1 - k } else { k };
    let na = edge_node(se.a.0, se.a.1, l, k);
    let nb = edge_node(se.b.0, se.b.1, l, kb);
    let ca = curve(na, se.a.1);
    let cb = curve(nb, se.b.1);
    let cb_aligned = if se.reversed {
        [cb[3], cb[2], cb[1], cb[0]]
    } else {
        cb
    };
    (na, nb, ca, cb, cb_aligned)
}

/// Checks that the two sides `ca`, `cb` of one shared-edge segment give
/// the edge tier the same samples and comparisons (`terms`, as bits) and
/// the same decision (`flat`) under every view: the property that keeps a
/// shared edge crack-free, for either kind of boundary curve (Cartesian or
/// homogeneous). `what` names the pair in failure messages (made only on
/// failure: this runs for every segment). Returns how
/// many of the decisions were flat.
pub fn assert_sides_agree<C, T: PartialEq + std::fmt::Debug>(
    ca: &C,
    cb: &C,
    views: &[ViewParams],
    terms: impl Fn(&C, &ViewParams) -> T,
    flat: impl Fn(&C, &ViewParams) -> bool,
    what: impl Fn() -> String,
) -> u64 {
    let mut flat_count = 0;
    for vp in views {
        assert_eq!(terms(ca, vp), terms(cb, vp), "{}: samples differ", what());
        let fa = flat(ca, vp);
        assert_eq!(fa, flat(cb, vp), "{}: decision differs", what());
        flat_count += fa as u64;
    }
    flat_count
}

/// The edge tier's `samples` and both sides of both comparisons at the
/// squared tolerance `t2`, as bits, sorted (the two sides of an edge run
/// the curve in opposite directions).
pub fn edge_terms(samples: &[EdgeSample], t2: f32, vp: &ViewParams) -> Vec<[u32; 11]> {
    let mut v: Vec<[u32; 11]> = samples
        .iter()
        .map(|s| {
            let (lhs, rhs) = line_sample_terms(s.point, s.from, s.to, THIRD, t2, vp);
            let f = [s.point, s.from, s.to].map(|p| p.to_array().map(f32::to_bits));
            let mut out = [0u32; 11];
            out[..9].copy_from_slice(f.as_flattened());
            out[9] = lhs.to_bits();
            out[10] = rhs.to_bits();
            out
        })
        .collect();
    v.sort();
    v
}

/// Welds the bitwise-identical positions of `tris` and returns the directed
/// edge uses not matched by an opposite use (a crack, or a model's own
/// boundary), as their welded end points. Degenerate triangles (at a pole)
/// are skipped, and so is each edge i -> j of a triangle t that
/// `skip(t, i, j)` says lies on a boundary no other patch shares.
pub fn unmatched_edges(
    tris: &[Triangle],
    skip: impl Fn(&Triangle, usize, usize) -> bool,
) -> Vec<(Vec3, Vec3)> {
    let mut ids: HashMap<[u32; 3], u32> = HashMap::new();
    let mut points: Vec<Vec3> = Vec::new();
    let mut id = |p: Vec3| {
        let n = ids.len() as u32;
        let k = *ids.entry(p.to_array().map(f32::to_bits)).or_insert(n);
        if k == n {
            points.push(p);
        }
        k
    };
    let mut balance: HashMap<(u32, u32), i64> = HashMap::new();
    for t in tris {
        let v = t.v.map(&mut id);
        if v[0] == v[1] || v[1] == v[2] || v[0] == v[2] {
            continue;
        }
        for i in 0..3 {
            let j = (i + 1) % 3;
            if skip(t, i, j) {
                continue;
            }
            let (a, b) = (v[i], v[j]);
            let (key, s) = if a < b { ((a, b), 1) } else { ((b, a), -1) };
            *balance.entry(key).or_default() += s;
        }
    }
    balance
        .iter()
        .filter(|(_, &b)| b != 0)
        .map(|(&(a, b), _)| (points[a as usize], points[b as usize]))
        .collect()
}

/// [`unmatched_edges`] of `tris` that are cracks: those not lying on a
/// base-patch side that no other patch shares (the model's own boundary);
/// `shared` holds the (patch, side) pairs that another side shares.
pub fn cracks(tris: &[Triangle], shared: &HashSet<(u32, usize)>) -> Vec<(Vec3, Vec3)> {
    let on_model_boundary = |t: &Triangle, i: usize, j: usize| {
        let (a, b) = (t.uv[i], t.uv[j]);
        let sides = [
            a.1 == 0.0 && b.1 == 0.0,
            a.0 == 1.0 && b.0 == 1.0,
            a.1 == 1.0 && b.1 == 1.0,
            a.0 == 0.0 && b.0 == 0.0,
        ];
        (0..4).any(|e| sides[e] && !shared.contains(&(t.node.patch(), e)))
    };
    unmatched_edges(tris, on_model_boundary)
}
