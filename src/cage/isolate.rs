//! From a resolved cage to patches, with or without isolation.
//!
//! Without isolation (`isolate = 0`, the default) the cage is converted as
//! it is, or, if any face is not a quad, after one Catmull–Clark step of the
//! whole cage (`refine.rs`).
//!
//! With `isolate = N` every connected part of the cage (faces joined
//! through shared vertices) whose conversion is not exact everywhere —
//! an extraordinary vertex, a dart, a semi-sharp crease or corner, an
//! irregular crease or corner, a face that is not a quad — is refined N
//! times by OpenSubdiv's rules before it is converted. Each step quarters
//! the faces; the patches that touch an irregular vertex (the irregular
//! ring, a quarter as wide per step) keep approximating the limit surface,
//! every other patch is exactly OpenSubdiv's bicubic B-spline patch, and a
//! semi-sharp feature of sharpness s has run out after ⌈s⌉ steps. Parts
//! that are exact already stay as they are.
//!
//! Why every face of such a part, not only those near its features (as
//! OpenSubdiv's feature-adaptive refinement does): a patch drawn by this
//! renderer meets its neighbours along whole edges with the same four
//! control points, which is what keeps it crack-free. Next to a refined face
//! a coarse one would meet two half edges with one curve (a T-junction),
//! which no per-edge decision can draw without a crack; making the coarse
//! face's neighbours conform spreads to every face of the part. Drawing
//! T-junctions crack-free needs the subdivision kernel to take a coarse
//! edge's halves from its finer neighbours, which it does not (see
//! docs/GUIDE.md, "Isolation").
//!
//! Crack-freeness is the converter's as always: the refined cage is
//! converted by `acc.rs`, which computes every boundary point once.

use std::path::Path;

use super::acc::{self, Conversion};
use super::mesh::{Cage, Topology};
use super::origin::PatchOrigin;
use super::probe;
use super::refine::{sub_quad_uv, StepTopologies, SubFace, QUAD_UV};
use super::stencil::CageStencils;
use super::{fit, tangent};
use crate::input::SceneError;
use crate::patch::bezier::BezierPatch;
use crate::patch::shading::ShadingPatch;

/// The most refinement steps `isolate` may ask for: each step quarters
/// every face, so 6 is already 4,096 patches per cage face.
pub const MAX_ISOLATE: u32 = 6;

/// The patches of a cage and where each came from.
#[derive(Clone, Debug, Default)]
pub struct Converted {
    /// Patches, following the cage's face order.
    pub patches: Vec<crate::patch::bezier::BezierPatch>,
    /// Their shading patches.
    pub shading: Vec<ShadingPatch>,
    /// Their origins.
    pub origins: Vec<PatchOrigin>,
    /// Patches per level, lowest first.
    pub levels: Vec<LevelCount>,
    /// Connected parts refined by isolation.
    pub isolated_parts: usize,
    /// Connected parts in all.
    pub parts: usize,
    /// The patches and shading patches as functions of the cage's
    /// vertices (`stencil.rs`).
    pub stencils: CageStencils,
}

/// Converts `cage` (sharpness resolved, `topo` its adjacency) with `isolate`
/// refinement steps where they help (see the module doc), and in every
/// part holding a face `uv_inexact` marks (its texture coordinates would
/// be approximated unrefined: OpenSubdiv's adaptive refinement considers
/// the face-varying channel too; empty: none).
pub fn convert(
    cage: &Cage,
    topo: &Topology,
    isolate: u32,
    uv_inexact: &[bool],
    path: &Path,
) -> Result<Converted, SceneError> {
    if isolate == 0 {
        let levels = u32::from(cage.faces.iter().any(|f| f.len() != 4));
        let mut out = convert_refined(cage, topo, levels, path)?;
        out.parts = 1;
        return Ok(out);
    }
    let parts = parts(cage);
    let mut pieces: Vec<(Vec<usize>, Vec<usize>, Converted)> = Vec::with_capacity(parts.len());
    let mut isolated = 0;
    for faces in parts.iter() {
        let (sub, map) = cage.extract(faces);
        // The cage vertex of each vertex of the part.
        let mut vertex = vec![0; sub.positions.len()];
        for (old, new) in map.iter().enumerate() {
            if let Some(n) = new {
                vertex[*n] = old;
            }
        }
        let sub_topo = Topology::build(&sub, path)?;
        let base = u32::from(sub.faces.iter().any(|f| f.len() != 4));
        // Whether a part of quads converts exactly is known from its
        // rules alone (the fits change no rule), before any stencil is
        // probed.
        let for_uvs = faces.iter().any(|&f| uv_inexact.get(f) == Some(&true));
        let refined = base > 0 || for_uvs || {
            let rules = acc::convert(&sub, &sub_topo, path)?.rules;
            rules.iter().any(|r| !r.exact())
        };
        let levels = if refined { isolate.max(base) } else { base };
        isolated += usize::from(refined);
        let piece = convert_refined(&sub, &sub_topo, levels, path)?;
        pieces.push((faces.clone(), vertex, piece));
    }
    let mut out = merge(cage.positions.len(), pieces);
    out.parts = parts.len();
    out.isolated_parts = isolated;
    Ok(out)
}

/// The topologies of [`linear_part`]'s refinements, built by the
/// conversion at rest and read by the stencil probes (same faces, other
/// positions).
#[derive(Default)]
struct Topologies {
    levels: StepTopologies,
    fit: fit::FitTopologies,
}

/// A refined cage, its topology, where each of its faces came from, and its
/// conversion.
type Linear<'a> = (Cage, &'a Topology, Vec<Vec<SubFace>>, Conversion);

/// The part of the conversion that is linear in the cage's vertices:
/// `levels` refinement steps, the ACC conversion and the fits. Returns the
/// refined cage, its topology, where each of its faces came from, and its
/// conversion. `topos` keeps the refinements' topologies for the next call
/// on the same faces.
fn linear_part<'a>(
    cage: &Cage,
    topo: &'a Topology,
    levels: u32,
    topos: &'a Topologies,
    path: &Path,
) -> Result<Linear<'a>, SceneError> {
    // The step every non-quad cage takes anyway.
    let base = u32::from(cage.faces.iter().any(|f| f.len() != 4));
    let mut chain: Vec<Vec<SubFace>> = Vec::new();
    let (fine, fine_topo) = topos
        .levels
        .refine(cage.clone(), topo, levels, path, |subs| chain.push(subs))?;
    let mut conv: Conversion = acc::convert(&fine, fine_topo, path)?;
    // Next to semi-sharp features and the ends of sharper creases, fit the
    // patches to a finer surface (`fit.rs`). Isolation does not shorten the
    // fit: a crease sharper than `levels` is still semi-sharp at the last
    // level, and left to the sharp rules it would be drawn as a crease with
    // a dart where it runs out. With isolation, the patches that still
    // approximate (the irregular ring) are fitted too: Loop and Schaefer's
    // patch follows the limit surface's shape there far better than its
    // parameters.
    let (want, steps) = fit::plan(&fine, fine_topo, &conv, levels > base);
    if steps > 0 {
        fit::apply(&fine, fine_topo, &mut conv, &want, steps, &topos.fit, path)?;
    }
    Ok((fine, fine_topo, chain, conv))
}

/// Converts `cage` after `levels` global refinement steps; origins name
/// the faces of `cage`. The patches and shading patches are the stencils
/// (`stencil.rs`) evaluated at the cage's vertices, so that any other pose
/// of the cage converts in the same operations.
fn convert_refined(
    cage: &Cage,
    topo: &Topology,
    levels: u32,
    path: &Path,
) -> Result<Converted, SceneError> {
    let topos = Topologies::default();
    let (fine, fine_topo, chain, conv) = linear_part(cage, topo, levels, &topos, path)?;
    let decisions = tangent::decide(&fine, fine_topo, &conv);
    // The coarse face of each fine face.
    let mut coarse_face: Vec<usize> = (0..fine.faces.len()).collect();
    for subs in chain.iter().rev() {
        for f in coarse_face.iter_mut() {
            *f = subs[*f].face;
        }
    }
    let linear = |probe: &Cage| linear_part(probe, topo, levels, &topos, path).map(|r| r.3);
    let stencils = probe::probe(
        cage,
        topo,
        &fine,
        fine_topo,
        &coarse_face,
        &conv,
        &decisions,
        &linear,
        path,
    )?;
    let rest: Vec<glam::Vec3> = cage.positions.iter().map(|p| p.as_vec3()).collect();
    let (patches, shading) = stencils.evaluate(&rest);
    if let Some(p) = patches.iter().position(|p| !p.is_finite()) {
        let msg = "the patch of this face has a non-finite control point (coordinates too large for f32?)";
        let f = coarse_face[conv.faces[p]];
        return Err(match cage.line_of(f) {
            Some(line) => SceneError::at(path, line, msg),
            None => SceneError::invalid(path, format!("face {}: {msg}", f + 1)),
        });
    }
    let patches: Vec<BezierPatch> = patches.into_iter().map(|p| p.canonical_zeros()).collect();
    let origins: Vec<PatchOrigin> = conv
        .faces
        .iter()
        .zip(&conv.rules)
        .map(|(&f, &rule)| origin(cage, &chain, f, rule, levels))
        .collect();
    let exact = origins.iter().filter(|o| o.rule.exact()).count();
    Ok(Converted {
        levels: vec![LevelCount {
            level: levels,
            patches: conv.patches.len(),
            exact,
        }],
        patches,
        shading,
        origins,
        stencils,
        isolated_parts: 0,
        parts: 1,
    })
}

/// Where face `f` of the last level of `chain` lies in `cage`.
fn origin(
    cage: &Cage,
    chain: &[Vec<SubFace>],
    f: usize,
    rule: acc::PatchRule,
    level: u32,
) -> PatchOrigin {
    // Corners from the top: [k1, k2, …], k1 the sub-quad of the cage face.
    let mut corners = Vec::with_capacity(chain.len());
    let mut at = f;
    for subs in chain.iter().rev() {
        corners.push(subs[at].corner);
        at = subs[at].face;
    }
    corners.reverse();
    let quad = cage.faces[at].len() == 4;
    // An n-gon's sub-face k1 is its own (ptex) parameter square.
    let inner = if quad {
        &corners[..]
    } else {
        &corners[1.min(corners.len())..]
    };
    let corners_uv = (quad || !inner.is_empty()).then(|| {
        inner
            .iter()
            .fold(QUAD_UV, |c, &k| map_square(c, sub_quad_uv(k)))
    });
    PatchOrigin {
        face: at,
        sub: corners.first().copied().unwrap_or(0),
        corners_uv,
        rule,
        level,
        turned: false,
    }
}

/// The points `inner` (in the unit square) mapped into the square whose
/// corners (0,0), (1,0), (1,1), (0,1) lie at `outer`. Dyadic values stay
/// exact.
fn map_square(outer: [[f32; 2]; 4], inner: [[f32; 2]; 4]) -> [[f32; 2]; 4] {
    let [o, a, _, b] = outer;
    inner.map(|[s, t]| {
        [
            o[0] + s * (a[0] - o[0]) + t * (b[0] - o[0]),
            o[1] + s * (a[1] - o[1]) + t * (b[1] - o[1]),
        ]
    })
}

/// The faces of each connected part of `cage` (joined through shared
/// vertices), in face order.
fn parts(cage: &Cage) -> Vec<Vec<usize>> {
    let nv = cage.positions.len();
    let mut root: Vec<usize> = (0..nv).collect();
    fn find(root: &mut [usize], mut v: usize) -> usize {
        while root[v] != v {
            root[v] = root[root[v]];
            v = root[v];
        }
        v
    }
    for face in &cage.faces {
        let a = find(&mut root, face[0]);
        for &v in &face[1..] {
            let b = find(&mut root, v);
            root[b] = a;
        }
    }
    let mut by_root: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    let mut order: Vec<usize> = Vec::new();
    for (f, face) in cage.faces.iter().enumerate() {
        let r = find(&mut root, face[0]);
        let list = by_root.entry(r).or_default();
        if list.is_empty() {
            order.push(r);
        }
        list.push(f);
    }
    order
        .into_iter()
        .map(|r| by_root.remove(&r).unwrap_or_default())
        .collect()
}

/// Joins the parts' patches in the cage's face order (each part's own
/// patches follow its faces, then the refinement's corners).
fn merge(vertices: usize, pieces: Vec<(Vec<usize>, Vec<usize>, Converted)>) -> Converted {
    let mut all: Vec<(usize, usize, BezierPatch, ShadingPatch, PatchOrigin, usize)> = Vec::new();
    let mut levels: Vec<LevelCount> = Vec::new();
    let mut parts: Vec<(CageStencils, Vec<usize>)> = Vec::new();
    for (part, (faces, vertex, piece)) in pieces.into_iter().enumerate() {
        for l in &piece.levels {
            match levels.iter_mut().find(|m| m.level == l.level) {
                Some(m) => {
                    m.patches += l.patches;
                    m.exact += l.exact;
                }
                None => levels.push(*l),
            }
        }
        for (n, ((p, s), mut o)) in piece
            .patches
            .into_iter()
            .zip(piece.shading)
            .zip(piece.origins)
            .enumerate()
        {
            o.face = faces[o.face];
            all.push((o.face, n, p, s, o, part));
        }
        parts.push((piece.stencils, vertex));
    }
    all.sort_by_key(|e| (e.0, e.1));
    levels.sort_by_key(|l| l.level);
    let mut out = Converted {
        levels,
        ..Converted::default()
    };
    let order: Vec<(usize, usize)> = all.iter().map(|e| (e.5, e.1)).collect();
    for (_, _, p, s, o, _) in all {
        out.patches.push(p);
        out.shading.push(s);
        out.origins.push(o);
    }
    out.stencils = CageStencils::join(vertices, &parts, &order);
    out
}

/// Patches by the refinement level they were made at.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelCount {
    /// Refinement steps before conversion.
    pub level: u32,
    /// Patches made at that level.
    pub patches: usize,
    /// Of those, exactly OpenSubdiv's limit surface.
    pub exact: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_squares_compose() {
        // Sub-quad 2 of sub-quad 1: in the quadrant at corner (1, 0), the
        // quarter at that quadrant's corner 2, the face's centre.
        let c = map_square(sub_quad_uv(1), sub_quad_uv(2));
        assert_eq!(c, [[0.5, 0.5], [0.5, 0.25], [0.75, 0.25], [0.75, 0.5]]);
        assert_eq!(map_square(QUAD_UV, sub_quad_uv(3)), sub_quad_uv(3));
    }
}
