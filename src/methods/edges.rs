//! Shared patch edges under tessellation: both patches along an edge must
//! give it the same outer level and put the same vertices on it, bit for
//! bit, or the surface cracks. The tessellation methods capture every
//! patch's levels and every edge vertex (`methods::tess`); these checks
//! hold the captures against the scene's edges, on whatever device ran
//! them (the tessellator's coordinates are the device's own).

use std::collections::HashMap;

use glam::Vec3;

use crate::figures::thousands;
use crate::patch::bezier::BezierPatch;

/// One patch's levels as the control stage wrote them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchLevels {
    /// Outer levels of the edges u = 0, v = 0, u = 1, v = 1.
    pub outer: [f32; 4],
    /// The metric's inner levels along u and v.
    pub inner: [f32; 2],
    /// The inner levels the tessellator got: the metric's, raised in a
    /// direction whose border strips were narrowed (tess/tess.glsl).
    pub drawn_inner: [f32; 2],
    /// The bound on the mixed derivative.
    pub mixed: f32,
    /// Frustum- or back-face-culled (all levels 0).
    pub culled: bool,
}

/// A vertex the evaluation stage placed strictly inside a patch edge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeVertex {
    /// Base patch.
    pub patch: u32,
    /// Edge: 0 u = 0, 1 v = 0, 2 u = 1, 3 v = 1.
    pub edge: u32,
    /// The tessellator's coordinate along the edge (v on edges 0 and 2,
    /// u on 1 and 3).
    pub t: f32,
    /// The position drawn.
    pub position: [f32; 3],
}

/// The control points of outer edge `k` as the tessellation stages number
/// and orient it (0: u = 0, 1: v = 0, 2: u = 1, 3: v = 1; points in the
/// direction of the edge's parameter).
pub fn tess_edge(p: &BezierPatch, k: usize) -> [Vec3; 4] {
    let at = |i: usize, j: usize| p.pts[4 * j + i];
    match k {
        0 => [at(0, 0), at(0, 1), at(0, 2), at(0, 3)],
        1 => [at(0, 0), at(1, 0), at(2, 0), at(3, 0)],
        2 => [at(3, 0), at(3, 1), at(3, 2), at(3, 3)],
        _ => [at(0, 3), at(1, 3), at(2, 3), at(3, 3)],
    }
}

/// An edge by the bits of its control points, in the smaller of its two
/// directions.
pub type EdgeKey = [u32; 12];

/// One patch's side of an edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EdgeSide {
    /// Base patch.
    pub patch: usize,
    /// Its outer edge (numbered as in [`tess_edge`]).
    pub edge: usize,
    /// The key runs against the edge's parameter.
    pub reversed: bool,
}

/// The key of edge `e` and whether it is `e` reversed.
pub fn edge_key(e: &[Vec3; 4]) -> (EdgeKey, bool) {
    let bits = |pts: [Vec3; 4]| -> EdgeKey {
        let mut k = [0u32; 12];
        for (i, p) in pts.iter().enumerate() {
            k[3 * i..3 * i + 3].copy_from_slice(&p.to_array().map(f32::to_bits));
        }
        k
    };
    let fwd = bits(*e);
    let rev = bits([e[3], e[2], e[1], e[0]]);
    if rev < fwd {
        (rev, true)
    } else {
        (fwd, false)
    }
}

/// Every edge that more than one patch side holds (a collapsed edge, like
/// the teapot's poles, may be held by many).
pub fn shared_edges(patches: &[BezierPatch]) -> HashMap<EdgeKey, Vec<EdgeSide>> {
    let mut map: HashMap<EdgeKey, Vec<EdgeSide>> = HashMap::new();
    for (patch, p) in patches.iter().enumerate() {
        for edge in 0..4 {
            let (key, reversed) = edge_key(&tess_edge(p, edge));
            map.entry(key).or_default().push(EdgeSide {
                patch,
                edge,
                reversed,
            });
        }
    }
    map.retain(|_, sides| sides.len() > 1);
    map
}

/// What a check of shared edges found.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct EdgeCheck {
    /// Shared edges (or edge vertices) compared.
    pub checked: u64,
    /// Of those, how many differ between the sides.
    pub bad: u64,
    /// The first difference, in words.
    pub first: Option<String>,
}

impl EdgeCheck {
    /// Counts a failure, keeping the first one's words.
    pub fn fail(&mut self, what: impl FnOnce() -> String) {
        self.bad += 1;
        if self.first.is_none() {
            self.first = Some(what());
        }
    }

    /// `": "` and the first failure, or nothing where none failed: the end
    /// of every report line of an edge check.
    pub fn first_suffix(&self) -> String {
        self.first
            .as_ref()
            .map_or(String::new(), |f| format!(": {f}"))
    }

    /// The detail of a check that the sides of shared edges agree on a
    /// value: `N <edges>, M with different <what> on their sides`.
    pub fn sides_detail(&self, edges: &str, what: &str) -> String {
        format!(
            "{} {edges}, {} with different {what} on their sides{}",
            thousands(self.checked),
            self.bad,
            self.first_suffix()
        )
    }

    /// The detail of [`check_edge_vertices`], which the tessellation
    /// methods and cudatess report in the same words.
    pub fn vertices_detail(&self) -> String {
        format!(
            "{} shared edge vertices, {} differing or missing on a side{}",
            thousands(self.checked),
            self.bad,
            self.first_suffix()
        )
    }
}

/// Sides of culled patches drop out: a culled patch draws nothing, and its
/// neighbour draws the edge alone.
fn drawn<'a>(sides: &'a [EdgeSide], levels: &'a [PatchLevels]) -> Vec<&'a EdgeSide> {
    sides
        .iter()
        .filter(|s| levels.get(s.patch).is_some_and(|l| !l.culled))
        .collect()
}

/// Every shared edge drawn by more than one patch has the same outer
/// level bits on all its sides.
pub fn check_levels(shared: &HashMap<EdgeKey, Vec<EdgeSide>>, levels: &[PatchLevels]) -> EdgeCheck {
    let mut out = EdgeCheck::default();
    for sides in shared.values() {
        let sides = drawn(sides, levels);
        let [first, rest @ ..] = sides.as_slice() else {
            continue;
        };
        if rest.is_empty() {
            continue;
        }
        out.checked += 1;
        let want = levels[first.patch].outer[first.edge];
        if let Some(s) = rest
            .iter()
            .find(|s| levels[s.patch].outer[s.edge].to_bits() != want.to_bits())
        {
            out.fail(|| {
                format!(
                    "edge {} of patch {} has level {}, edge {} of patch {} has {}",
                    first.edge, first.patch, want, s.edge, s.patch, levels[s.patch].outer[s.edge]
                )
            });
        }
    }
    out
}

/// Every vertex strictly inside a shared edge drawn by more than one patch
/// is there on every side, at the same coordinate (measured in the key's
/// direction) and with the same position bits.
pub fn check_edge_vertices(
    shared: &HashMap<EdgeKey, Vec<EdgeSide>>,
    levels: &[PatchLevels],
    vertices: &[EdgeVertex],
) -> EdgeCheck {
    let mut side_of: HashMap<(usize, usize), (&EdgeKey, bool)> = HashMap::new();
    for (key, sides) in shared {
        for s in sides {
            side_of.insert((s.patch, s.edge), (key, s.reversed));
        }
    }
    // (edge, coordinate on a 2^-24 grid) → position bits by patch.
    let mut at: HashMap<(&EdgeKey, i64), HashMap<usize, [u32; 3]>> = HashMap::new();
    let mut out = EdgeCheck::default();
    for v in vertices {
        let Some(&(key, reversed)) = side_of.get(&(v.patch as usize, v.edge as usize)) else {
            continue;
        };
        let t = f64::from(v.t);
        let t = if reversed { 1.0 - t } else { t };
        let slot = (t * f64::from(1u32 << 24)).round() as i64;
        let bits = v.position.map(f32::to_bits);
        if let Some(old) = at
            .entry((key, slot))
            .or_default()
            .insert(v.patch as usize, bits)
        {
            if old != bits {
                out.fail(|| {
                    format!(
                        "patch {} evaluated one edge vertex twice differently",
                        v.patch
                    )
                });
            }
        }
    }
    for ((key, slot), seen) in &at {
        let sides = drawn(&shared[*key], levels);
        if sides.len() < 2 {
            continue;
        }
        out.checked += 1;
        let missing: Vec<usize> = sides
            .iter()
            .map(|s| s.patch)
            .filter(|p| !seen.contains_key(p))
            .collect();
        let first = seen.values().next().copied();
        if !missing.is_empty() {
            out.fail(|| {
                format!(
                    "edge coordinate {} only on patches {:?}, not on {missing:?}",
                    *slot as f64 / f64::from(1u32 << 24),
                    seen.keys().collect::<Vec<_>>()
                )
            });
        } else if seen.values().any(|b| Some(*b) != first) {
            out.fail(|| {
                format!(
                    "an edge vertex differs between patches {:?}",
                    seen.keys().collect::<Vec<_>>()
                )
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::fixtures::ramp;

    fn levels(outer: [f32; 4]) -> PatchLevels {
        PatchLevels {
            outer,
            inner: [1.0; 2],
            drawn_inner: [1.0; 2],
            mixed: 0.0,
            culled: false,
        }
    }

    #[test]
    fn finds_shared_edges_and_unequal_levels() {
        // Patch 1 starts where patch 0 ends: edge 2 of 0 is edge 0 of 1.
        let mut b = ramp(3.0);
        for j in 0..4 {
            b.pts[4 * j] = ramp(0.0).pts[4 * j + 3];
        }
        let shared = shared_edges(&[ramp(0.0), b]);
        assert_eq!(shared.len(), 1);
        let sides = shared.values().next().unwrap();
        assert_eq!((sides[0].patch, sides[0].edge), (0, 2));
        assert_eq!((sides[1].patch, sides[1].edge), (1, 0));
        assert_eq!(sides[0].reversed, sides[1].reversed);
        let good = [levels([1.0, 1.0, 3.0, 1.0]), levels([3.0, 1.0, 1.0, 1.0])];
        assert_eq!(check_levels(&shared, &good).bad, 0);
        let bad = [levels([1.0, 1.0, 3.0, 1.0]), levels([4.0, 1.0, 1.0, 1.0])];
        let c = check_levels(&shared, &bad);
        assert_eq!((c.checked, c.bad), (1, 1));
        // A culled side leaves nothing to compare.
        let mut culled = bad;
        culled[1].culled = true;
        assert_eq!(check_levels(&shared, &culled).checked, 0);
        // Edge vertices: both sides at 1/2, then one side off by a bit.
        let v = |patch, edge, x: f32| EdgeVertex {
            patch,
            edge,
            t: 0.5,
            position: [x, 0.5, 0.0],
        };
        let ok = check_edge_vertices(&shared, &good, &[v(0, 2, 3.0), v(1, 0, 3.0)]);
        assert_eq!((ok.checked, ok.bad), (1, 0));
        let off = check_edge_vertices(&shared, &good, &[v(0, 2, 3.0), v(1, 0, 3.0000002)]);
        assert_eq!(off.bad, 1);
        let lonely = check_edge_vertices(&shared, &good, &[v(0, 2, 3.0)]);
        assert_eq!(lonely.bad, 1, "a T-junction");
    }
}
