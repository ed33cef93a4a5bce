//! The checks of `cudatess` on what a frame left in its buffers
//! ([`CudaTess::read_frame`]), which `validate` runs on every keyframe
//! ([`run`], declared by the registry entry): the edge factors are the
//! largest any drawn patch on the edge asked for (so equal from both
//! sides), the vertices along shared edges are bit identical from every
//! side (through the generic shared-edge checks of
//! [`crate::methods::edges`]), and every patch's indices are its pattern's
//! ([`Pattern::triangles`]) inside its own slot of the vertex buffer.
//! PN triangles (the records after the patches'): both triangles of every
//! shared edge read the same factor and write the same vertex bits along
//! it, and every triangle's indices stay inside its own slot and use all
//! of it.

use std::collections::HashMap;

use super::pattern::Pattern;
use super::{CudaTess, FrameData, PatchRecord};
use crate::figures::thousands;
use crate::methods::checks::{Check, CheckFrame, CheckResult};
use crate::methods::edges::{
    check_edge_vertices, check_levels, shared_edges, EdgeCheck, EdgeKey, EdgeSide,
};
use crate::methods::edges::{EdgeVertex, PatchLevels};
use crate::methods::RenderError;
use crate::scene::geometry::SceneGeometry;
use crate::scene::pn::PnScene;

/// The checks for a scene's geometry (`MethodInfo::checks`).
pub fn make(geo: &SceneGeometry) -> Box<dyn Check + '_> {
    Box::new(FrameChecks {
        geo,
        shared: shared_edges(&geo.patches),
    })
}

/// The scene, and its shared edges found once for every keyframe.
struct FrameChecks<'a> {
    geo: &'a SceneGeometry,
    shared: HashMap<EdgeKey, Vec<EdgeSide>>,
}

impl Check for FrameChecks<'_> {
    fn keyframe(&self, frame: &dyn CheckFrame, k: usize) -> Result<Vec<CheckResult>, RenderError> {
        let frame = frame
            .method()
            .downcast::<CudaTess>()
            .ok_or_else(|| RenderError::Request("not cudatess".into()))?
            .read_frame(frame.context())?;
        Ok(keyframe(self.geo, &self.shared, &frame, k))
    }
}

/// The checks of one keyframe's frame.
fn keyframe(
    geo: &SceneGeometry,
    shared: &HashMap<EdgeKey, Vec<EdgeSide>>,
    frame: &FrameData,
    k: usize,
) -> Vec<CheckResult> {
    let levels = levels(frame);
    let equal = check_levels(shared, &levels);
    let largest = check_max_factors(shared, frame);
    let vx = check_edge_vertices(shared, &levels, &edge_vertices(frame));
    let ix = check_indices(frame);
    let mut out = vec![
        CheckResult::new(
            "edge factors",
            Some(k),
            equal.bad == 0,
            equal.sides_detail("shared edges", "factors"),
        ),
        CheckResult::new(
            "largest factor",
            Some(k),
            largest.bad == 0,
            format!(
                "{} patch edges and every shared edge: {} not the largest asked for{}",
                thousands(largest.checked),
                largest.bad,
                largest.first_suffix()
            ),
        ),
        CheckResult::new("edge vertices", Some(k), vx.bad == 0, vx.vertices_detail()),
        CheckResult::new(
            "indices",
            Some(k),
            ix.bad == 0 && ix.checked > 0,
            format!(
                "{} drawn patches' index slots against their patterns, {} wrong{}",
                thousands(ix.checked),
                ix.bad,
                ix.first_suffix()
            ),
        ),
    ];
    if !geo.pn.triangles.is_empty() {
        let (factors, vertices) = check_pn_edges(&geo.pn, frame);
        out.push(CheckResult::new(
            "PN edge factors",
            Some(k),
            factors.bad == 0 && factors.checked > 0,
            factors.sides_detail("shared PN edges", "factors"),
        ));
        out.push(CheckResult::new(
            "PN edge vertices",
            Some(k),
            vertices.bad == 0,
            vertices.sides_detail("shared PN edges", "vertex bits"),
        ));
    }
    out
}

/// The records as the tessellation methods' levels: edge factors as outer
/// levels, the patch's own factors as inner ones, culled patches marked.
pub fn levels(frame: &FrameData) -> Vec<PatchLevels> {
    frame.records[..frame.patches]
        .iter()
        .map(|r| PatchLevels {
            outer: r.edges.map(|e| e as f32),
            inner: r.own.map(|f| f as f32),
            drawn_inner: r.own.map(|f| f as f32),
            mixed: 0.0,
            culled: r.culled(),
        })
        .collect()
}

/// A patch's `count` entries from `offset`, or `None` when its record
/// points outside what the frame wrote.
fn slot<T>(all: &[T], offset: u32, count: u32) -> Option<&[T]> {
    all.get(offset as usize..offset as usize + count as usize)
}

/// Every vertex strictly inside an edge of a drawn patch, with its
/// coordinate along the edge: `s / e` put on the 2^-24 grid the shared-edge
/// check compares on (exact in f32; the two sides' coordinates, `s / e` and
/// `1 - s / e`, then land on complementary slots for every `e` the factors
/// can take). Patches whose records point outside the buffers are left out
/// (the index check reports them).
pub fn edge_vertices(frame: &FrameData) -> Vec<EdgeVertex> {
    let mut out = Vec::new();
    for (id, r) in frame.records[..frame.patches].iter().enumerate() {
        if r.culled() {
            continue;
        }
        let p = Pattern::new(r.edges);
        let Some(vertices) = slot(&frame.vertices, r.offsets[0], p.vertices) else {
            continue;
        };
        for k in 0..4 {
            let e = p.e[k];
            for s in 1..e {
                let t = (f64::from(s) / f64::from(e) * f64::from(1u32 << 24)).round()
                    / f64::from(1u32 << 24);
                out.push(EdgeVertex {
                    patch: id as u32,
                    edge: k as u32,
                    t: t as f32,
                    position: vertices[p.edge_vertex(k, s) as usize].position,
                });
            }
        }
    }
    out
}

/// Factor of edge `k` a patch asks for itself: m along u (edges 1 and 3),
/// n along v (edges 0 and 2).
fn own_factor(r: &PatchRecord, k: usize) -> u32 {
    r.own[(k + 1) % 2]
}

/// Every drawn patch's edge factors are at least its own, and every shared
/// edge's factor is the largest its drawn sides asked for: the consistent
/// factors of Schwarz and Stamminger's stage 2.
pub fn check_max_factors(shared: &HashMap<EdgeKey, Vec<EdgeSide>>, frame: &FrameData) -> EdgeCheck {
    let mut out = EdgeCheck::default();
    let recs = &frame.records[..frame.patches];
    for (id, r) in recs.iter().enumerate() {
        if r.culled() {
            continue;
        }
        for k in 0..4 {
            out.checked += 1;
            if r.edges[k] < own_factor(r, k) || r.edges[k] == 0 {
                out.fail(|| {
                    format!(
                        "patch {id} edge {k}: factor {} below its own {}",
                        r.edges[k],
                        own_factor(r, k)
                    )
                });
            }
        }
    }
    for sides in shared.values() {
        let drawn: Vec<&EdgeSide> = sides
            .iter()
            .filter(|s| recs.get(s.patch).is_some_and(|r| !r.culled()))
            .collect();
        let Some(want) = drawn
            .iter()
            .map(|s| own_factor(&recs[s.patch], s.edge))
            .max()
        else {
            continue;
        };
        if let Some(s) = drawn.iter().find(|s| recs[s.patch].edges[s.edge] != want) {
            out.fail(|| {
                format!(
                    "edge {} of patch {} has factor {}, the largest its sides asked for is {want}",
                    s.edge, s.patch, recs[s.patch].edges[s.edge]
                )
            });
        }
    }
    out
}

/// Every drawn patch's slot of the index buffer holds its pattern's
/// triangles ([`Pattern::triangles`], the CPU twin of `cudatess/indices.comp`)
/// offset into its own vertices; every slot lies inside what the frame
/// wrote, and the slots tile the buffers (the scan's offsets).
pub fn check_indices(frame: &FrameData) -> EdgeCheck {
    let mut out = EdgeCheck::default();
    let (mut next_vertex, mut next_index) = (0u32, 0u32);
    for (id, r) in frame.records.iter().enumerate() {
        if r.offsets != [next_vertex, next_index] {
            out.fail(|| {
                format!(
                    "patch {id} starts at {:?}, the counts before it sum to {:?}",
                    r.offsets,
                    [next_vertex, next_index]
                )
            });
        }
        next_vertex = next_vertex.wrapping_add(r.counts[0]);
        next_index = next_index.wrapping_add(r.counts[1]);
        if r.culled() {
            if r.counts != [0, 0] {
                out.fail(|| format!("culled patch {id} counts {:?}", r.counts));
            }
            continue;
        }
        out.checked += 1;
        if id >= frame.patches {
            check_pn_slot(frame, id - frame.patches, r, &mut out);
            continue;
        }
        let p = Pattern::new(r.edges);
        if r.counts != [p.vertices, p.indices] {
            out.fail(|| {
                format!(
                    "patch {id} counts {:?}, its pattern {:?}",
                    r.counts,
                    [p.vertices, p.indices]
                )
            });
            continue;
        }
        let Some(got) = slot(&frame.indices, r.offsets[1], p.indices) else {
            out.fail(|| format!("patch {id}'s indices run past the index buffer"));
            continue;
        };
        let base = r.offsets[0];
        let want = p.triangles().into_iter().flatten().map(|k| base + k);
        if !got.iter().copied().eq(want) {
            out.fail(|| format!("patch {id}'s indices are not its pattern's {:?}", p.e));
        }
    }
    let totals = [frame.vertices.len() as u32, frame.indices.len() as u32];
    if [next_vertex, next_index] != totals {
        out.fail(|| {
            format!(
                "the counts sum to {:?}, the frame wrote {totals:?}",
                [next_vertex, next_index]
            )
        });
    }
    out
}

/// PN triangle `t` (record `r`): a whole number of triangles, every index
/// inside the triangle's own vertices, and every one of them used (there is
/// no CPU twin of the triangular pattern; its shape is tested in
/// `tests/pn.rs` through the shared edges and the hole test).
fn check_pn_slot(frame: &FrameData, t: usize, r: &PatchRecord, out: &mut EdgeCheck) {
    let Some(got) = slot(&frame.indices, r.offsets[1], r.counts[1]) else {
        out.fail(|| format!("PN triangle {t}'s indices run past the index buffer"));
        return;
    };
    let own = r.offsets[0]..r.offsets[0].saturating_add(r.counts[0]);
    let mut used = vec![false; r.counts[0] as usize];
    for &i in got {
        if own.contains(&i) {
            used[(i - own.start) as usize] = true;
        } else {
            out.fail(|| format!("PN triangle {t} indexes vertex {i}, outside its own {own:?}"));
            return;
        }
    }
    if got.len() % 3 != 0 || r.counts[0] < 3 || used.contains(&false) {
        out.fail(|| {
            format!(
                "PN triangle {t}: {} indices over {} vertices, {} of them unused",
                got.len(),
                r.counts[0],
                used.iter().filter(|u| !**u).count()
            )
        });
    }
}

/// What the drawn PN triangles wrote along each shared edge: per edge id,
/// each side's triangle, factor and the sorted bits of its vertices along
/// the edge (corners included). The pattern's vertices start with the
/// three corners, then each side's inner edge vertices in side order.
fn pn_edge_sides(pn: &PnScene, frame: &FrameData) -> HashMap<u32, Vec<PnSide>> {
    let mut sides: HashMap<u32, Vec<PnSide>> = HashMap::new();
    for (t, ids) in pn.edge_ids.iter().enumerate() {
        let Some(r) = frame.records.get(frame.patches + t) else {
            continue;
        };
        if r.culled() {
            continue;
        }
        let Some(vertices) = slot(&frame.vertices, r.offsets[0], r.counts[0]) else {
            continue;
        };
        let mut next = 3usize;
        for (k, &factor) in r.edges[..3].iter().enumerate() {
            let inner = factor.saturating_sub(1) as usize;
            let mut local = vec![k, (k + 1) % 3];
            local.extend(next..next + inner);
            next += inner;
            let mut bits: Vec<[u32; 3]> = local
                .iter()
                .filter_map(|&l| vertices.get(l))
                .map(|v| v.position.map(f32::to_bits))
                .collect();
            bits.sort_unstable();
            sides.entry(ids[k]).or_default().push(PnSide {
                triangle: t,
                factor,
                bits,
            });
        }
    }
    sides
}

/// One triangle's view of a PN edge.
struct PnSide {
    triangle: usize,
    factor: u32,
    bits: Vec<[u32; 3]>,
}

/// Every PN edge drawn by two triangles: the same factor (first result)
/// and the same vertex bits along it (second) from both.
pub fn check_pn_edges(pn: &PnScene, frame: &FrameData) -> (EdgeCheck, EdgeCheck) {
    let (mut factors, mut vertices) = (EdgeCheck::default(), EdgeCheck::default());
    for (edge, on) in pn_edge_sides(pn, frame) {
        let Some((first, rest)) = on.split_first() else {
            continue;
        };
        for side in rest {
            factors.checked += 1;
            vertices.checked += 1;
            if side.factor != first.factor {
                factors.fail(|| {
                    format!(
                        "PN edge {edge}: factor {} on triangle {}, {} on {}",
                        side.factor, side.triangle, first.factor, first.triangle
                    )
                });
            } else if side.bits != first.bits {
                vertices.fail(|| {
                    format!(
                        "PN edge {edge}: triangles {} and {} wrote different vertices",
                        first.triangle, side.triangle
                    )
                });
            }
        }
    }
    (factors, vertices)
}
