//! Catmull–Clark control cages (Wavefront OBJ) → bicubic Bézier patches.
//!
//! # Reading
//!
//! The file is parsed by `tobj` (faces kept as polygons, one index per
//! attribute). Before that, a small scan of our own walks the text to give
//! errors a line number, which `tobj`'s errors lack, to read OpenSubdiv's
//! `t` tags (`tags.rs`), and to refuse what `tobj` accepts but a cage cannot
//! use:
//!
//! - a `v` line without three numbers, or with a NaN or infinite coordinate
//!   (after an optional `w`, which must not be 0);
//! - an `f` line with fewer than three vertices, an index that is not a
//!   number, is 0, or points past the vertices (negative indices count back
//!   from the last vertex read, as OBJ says); `l` (polyline) lines;
//! - `vt`/`vn` lines without numbers and texture/normal indices out of range
//!   (`tobj` would refuse them; the cage does not use them);
//! - tags that cannot be meant (see `tags.rs`).
//!
//! Unknown statements are skipped. When `o`/`g`/`usemtl` lines split the
//! file into several `tobj` models, they are joined into one cage: vertices
//! with bit-identical positions (after -0.0 → +0.0) become one vertex.
//! Within a single model the file's vertex indices are kept as they are, so
//! coincident but distinct vertices stay distinct there. Tags name file
//! vertices; they are carried to the cage through the faces that use them.
//!
//! The cage may be non-manifold (`mesh.rs`): an edge with three or more
//! faces is a boundary of each, a vertex may join several fans of faces.
//! Refused: faces with a repeated vertex, and an edge two faces run in the
//! same direction (a flipped face).
//!
//! # Features: creases, corners, boundaries (`sharpness.rs`)
//!
//! Sharpness comes from `t crease` and `t corner`; the boundary rule from
//! `t interpolateboundary`, else from the scene's `boundary` key or
//! `import --boundary`, else `edge-and-corner`. The rule and the
//! non-manifold rules are turned into explicit sharpness first (boundary
//! and non-manifold edges infinitely sharp; cage corners too under
//! `edge-and-corner`; faces at the boundary holes under `none`). Each vertex
//! then gets its Catmull–Clark rule from its sharp edges: smooth, dart,
//! crease (two) or corner (three or more, or a sharp vertex).
//!
//! # Conversion (the project's rules)
//!
//! Valence n of a vertex: its number of incident edges.
//!
//! Parameterisation: quad face (v0, v1, v2, v3) in file order has its
//! parameter origin at v0, u running towards v1 and v towards v3 — vertex k
//! at (0,0), (1,0), (1,1), (0,1), OpenSubdiv's quad convention. Faces listed
//! counter-clockwise seen from outside then give an outward ∂S/∂u × ∂S/∂v.
//!
//! One bicubic patch per quad that is not a hole, by approximate
//! Catmull–Clark surfaces (Loop & Schaefer 2008) extended to sharp features
//! in the way boundaries always were. All arithmetic is f64 from the file's
//! f32 positions; each control point is rounded to f32 once.
//!
//! - Interior point of face F near its corner v, with e_a, e_b the two
//!   neighbours of v in F and f the opposite vertex:
//!   (n·v + 2·e_a + 2·e_b + f)/(n + 5). At a regular vertex (n = 4) this is
//!   the B-spline → Bézier rule. At a crease or corner vertex n = 4 is used
//!   whatever the valence.
//! - Edge point of edge (v, w) near v: (2v + w)/3 when the edge is sharp and
//!   v is a crease or corner (so sharp edges are boundary-like curves shared
//!   by every face on them); otherwise the average of the two interior
//!   points near v of the two faces sharing the edge.
//! - Corner point: a smooth or dart vertex's Catmull–Clark limit position
//!   (n²·v + 4·Σ edge neighbours + Σ diagonal vertices)/(n(n + 5)), which is
//!   also the average of the interior points around v; a crease vertex's
//!   (a + 4v + b)/6 from the far ends a, b of its two sharp edges (the crease
//!   curve is the uniform cubic B-spline of the crease vertices); a corner
//!   vertex stays where it is.
//! - Semi-sharp features (0 < s < 10) are approximated: sharpness 1 and more
//!   is converted as infinitely sharp; below 1 every point near the vertex
//!   is the smooth rules' moved by s towards the sharp rules' (s averaged
//!   over the vertex's features below 1), OpenSubdiv's own blend for a
//!   feature that runs out within one step. OpenSubdiv rounds a crease of
//!   sharpness s off within about 2^−s of a face from it; the patches keep
//!   it sharp there (measured in tests/osd_reference.rs).
//!
//! These patches equal OpenSubdiv's limit surface (to f32 rounding) where
//! every corner is regular: a smooth vertex of valence 4, a crease with two
//! faces on the patch's side, or a corner with the face alone between its
//! sharp edges — `PatchRule::exact`; elsewhere they approximate it. The
//! surface is watertight bit for bit (DESIGN invariant 4): every corner
//! point and every edge point (per edge and end) is computed once and copied
//! into each patch that uses it, never recomputed per face.
//!
//! Non-quad faces: if any face is not a quad, one global Catmull–Clark step
//! (`refine.rs`, with OpenSubdiv's crease rules; semi-sharp sharpness goes
//! down by one) first turns the whole cage into quads; sub-quad k of face F
//! is (v_k, edge point of (v_k, v_k+1), face point, edge point of
//! (v_k−1, v_k)), OpenSubdiv's sub-face k, and the patches follow face
//! order, then k. A warning says so.
//!
//! Shading: each patch also gets tangent patches (`tangent.rs`) whose
//! normals are continuous across every edge that is not a feature.
//!
//! Origins: `PatchOrigin::face` is the index of the original cage face (the
//! n-th `f` line, 0-based), `sub` its sub-quad for a refined cage.
//! `corners_uv` are the face-parameter coordinates of the patch's parameter
//! corners (0,0), (1,0), (1,1), (0,1): the unit square for an unrefined
//! quad; for sub-quad k of a refined quad the corner k of the square, the
//! midpoint of edge (k, k+1), the centre and the midpoint of edge (k−1, k)
//! (sub-quad 0: `[[0,0],[0.5,0],[0.5,0.5],[0,0.5]]`); `None` for patches of
//! non-quad faces. `rule` is how the patch was made.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::mesh::{Cage, Scheme, Topology};
use super::model::{CageInfo, ImportedModel, RuleSource};
use super::scan::{scan, Scan};
use super::sharpness::{self, BoundaryRule, INFINITE};
use super::uv::{self, FaceUvs, FvarRule};
use super::{isolate, orient};
use crate::input::SceneError;

/// Choices for cages that the file itself does not make.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct CageOptions {
    /// Boundary rule for a cage without a `t interpolateboundary` tag
    /// (`None`: [`sharpness::DEFAULT_BOUNDARY`]).
    pub boundary: Option<BoundaryRule>,
    /// Catmull–Clark steps before conversion where the conversion is not
    /// exact (`isolate.rs`); 0 converts the cage as it is.
    pub isolate: u32,
    /// How the cage's texture coordinates, if it has any, are
    /// interpolated (`uv.rs`).
    pub fvar: FvarRule,
}

/// Reads an OBJ control cage and converts it to Bézier patches.
pub fn read(path: &Path) -> Result<ImportedModel, SceneError> {
    read_with(path, &CageOptions::default())
}

/// [`read`] with options.
pub fn read_with(path: &Path, options: &CageOptions) -> Result<ImportedModel, SceneError> {
    let text = crate::input::text::read_text(path)?;
    parse_with(path, &text, options)
}

/// Parses OBJ text; `path_for_errors` only names the source in errors.
pub fn parse(path_for_errors: &Path, text: &str) -> Result<ImportedModel, SceneError> {
    parse_with(path_for_errors, text, &CageOptions::default())
}

/// [`parse`] with options.
pub fn parse_with(
    path_for_errors: &Path,
    text: &str,
    options: &CageOptions,
) -> Result<ImportedModel, SceneError> {
    let path = path_for_errors;
    let scan = scan(path, text)?;
    let models = load_models(path, text, &scan)?;

    let mut warnings = Vec::new();
    warnings.extend(scan.tags.ignored_warning());
    let (mut cage, joined) = cage_from_models(path, &models, &scan.face_lines)?;
    let uvs = FaceUvs::from_scan(path, &scan, &cage, &mut warnings)?;
    if joined > 1 {
        warnings.push(format!(
            "{joined} objects/groups joined into one cage by merging vertices with bit-identical positions"
        ));
    }
    let topo = Topology::build(&cage, path)?;
    let tagged = apply_tags(path, &mut cage, &topo, &scan)?;
    let tagged_holes = apply_holes(path, &mut cage, &scan)?;
    cage.scheme = Scheme {
        chaikin: scan.tags.chaikin.is_some_and(|(_, c)| c),
        smooth_triangles: scan.tags.smooth_triangles.is_some_and(|(_, s)| s),
    };

    let (boundary, boundary_from) = match (scan.tags.boundary, options.boundary) {
        (Some((line, rule)), _) => (rule, RuleSource::Tag(line)),
        (None, Some(rule)) => (rule, RuleSource::Option),
        (None, None) => (sharpness::DEFAULT_BOUNDARY, RuleSource::Default),
    };
    let resolved = sharpness::resolve(&mut cage, &topo, boundary);
    let non_manifold_vertices = (0..cage.positions.len())
        .filter(|&v| topo.is_non_manifold_vertex(v))
        .count();
    warnings.extend(non_manifold_warning(&topo, non_manifold_vertices));
    check_holes(path, &cage, &resolved, tagged_holes, &mut warnings)?;
    let orientation = orient::inside_out(&cage, &topo);
    if orientation.inside_out > 0 {
        warnings.push(format!(
            "{} of {} closed parts wound inside out (clockwise seen from outside): their patches are turned (u and v swapped) so the outside faces out",
            orientation.inside_out, orientation.closed
        ));
    }

    let uv_inexact = match (&uvs, options.isolate) {
        (Some(u), 1..) => uv::inexact_faces(u, &cage, options.fvar, boundary),
        _ => Vec::new(),
    };
    let conv = convert_oriented(
        path,
        &cage,
        &topo,
        options,
        &uv_inexact,
        &orientation,
        &mut warnings,
    )?;
    let info = CageInfo {
        boundary,
        boundary_from,
        boundary_edges: topo.boundary_edges,
        sharp_edges: tagged.sharp_edges,
        semi_sharp_edges: tagged.semi_sharp_edges,
        corners: tagged.corners,
        non_manifold_edges: topo.non_manifold_edges,
        non_manifold_vertices,
        holes: resolved.holes,
        tagged_holes,
        degenerate_edges: topo.degenerate_edges,
        misoriented_edges: topo.misoriented_edges,
        inside_out: orientation.inside_out,
        closed_parts: orientation.closed,
        scheme: cage.scheme,
        isolate: options.isolate,
        levels: conv.levels.clone(),
        isolation: (options.isolate > 0).then(|| isolate_note(&conv, options.isolate)),
        uv: uvs.as_ref().map(|u| u.info(&cage)),
    };
    let uv_patches = uvs.as_ref().map(|u| {
        let converted = uv::Converted {
            cage: &cage,
            origins: &conv.origins,
            stencils: &conv.stencils,
            boundary,
            isolate: options.isolate,
        };
        uv::uv_patches(u, &converted, options.fvar)
    });
    let albedo = super::mtl::albedo_map(path, &scan.materials, &mut warnings)?;
    let mut model = imported_model(&cage, &scan, conv, info, warnings);
    model.albedo = albedo;
    model.uvs = uvs.map(std::sync::Arc::new);
    model.uv_patches = uv_patches;
    Ok(model)
}

/// Reads the text with `tobj` (faces as polygons), after refusing a file
/// the scan found no faces in.
fn load_models(path: &Path, text: &str, scan: &Scan) -> Result<Vec<tobj::Model>, SceneError> {
    if scan.face_lines.is_empty() {
        let msg = if text.trim().is_empty() {
            "empty file"
        } else {
            "no faces (`f` lines): nothing to convert"
        };
        return Err(SceneError::invalid(path, msg));
    }

    // The struct gains fields with tobj's optional features (merging,
    // reordering); the update keeps this compiling if one gets enabled.
    #[allow(clippy::needless_update)]
    let load = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: false,
        ignore_lines: false,
        ..Default::default()
    };
    let mut reader = text.as_bytes();
    let (models, _materials) =
        tobj::load_obj_buf(&mut reader, &load, |_| Err(tobj::LoadError::GenericFailure))
            .map_err(|e| SceneError::invalid(path, format!("OBJ reader: {e}")))?;
    Ok(models)
}

/// Refuses a cage whose every face is a hole, and warns of faces tagged
/// `t hole` (the surface is open there).
fn check_holes(
    path: &Path,
    cage: &Cage,
    resolved: &sharpness::Resolved,
    tagged_holes: usize,
    warnings: &mut Vec<String>,
) -> Result<(), SceneError> {
    let holes = (0..cage.faces.len()).filter(|&f| cage.is_hole(f)).count();
    if holes == cage.faces.len() {
        let why = if resolved.holes == holes {
            "the boundary rule `none` leaves no face: every face touches the boundary"
        } else {
            "every face is a hole (`t hole`, or the boundary rule `none`)"
        };
        return Err(SceneError::invalid(path, why));
    }
    if tagged_holes > 0 {
        // Only wholly back-facing nodes are culled and the rasterizer culls
        // nothing, so a one-sided model seen through a hole shows part of
        // its inside, lit as outside, in blocks.
        warnings.push(format!(
            "{tagged_holes} faces tagged `t hole`: the surface is open there; draw it with \
             `two_sided = true`, else its inside shows through the hole in patches"
        ));
    }
    Ok(())
}

/// Converts the cage to patches (with the warning on non-quads) and turns
/// the patches of inside-out parts so their outside faces out.
fn convert_oriented(
    path: &Path,
    cage: &Cage,
    topo: &Topology,
    options: &CageOptions,
    uv_inexact: &[bool],
    orientation: &orient::Orientation,
    warnings: &mut Vec<String>,
) -> Result<isolate::Converted, SceneError> {
    let mut conv = isolate::convert(cage, topo, options.isolate, uv_inexact, path)?;
    if options.isolate == 0 {
        let non_quads = cage.faces.iter().filter(|f| f.len() != 4).count();
        if non_quads > 0 {
            warnings.push(format!(
                "{non_quads} non-quad faces: one Catmull–Clark step applied to the whole cage, {} patches",
                conv.patches.len()
            ));
        }
    }
    for ((p, s), o) in conv
        .patches
        .iter_mut()
        .zip(&mut conv.shading)
        .zip(&mut conv.origins)
    {
        if orientation.flip[o.face] {
            *p = orient::flip_patch(p);
            *s = s.transposed();
            o.flip();
        }
    }
    let turned: Vec<bool> = conv
        .origins
        .iter()
        .map(|o| orientation.flip[o.face])
        .collect();
    conv.stencils.flip(&turned);
    Ok(conv)
}

/// The imported model: the converted patches, the cage's summary, and the
/// stencils that move the patches with the file's vertices (when every
/// cage vertex has one).
fn imported_model(
    cage: &Cage,
    scan: &Scan,
    conv: isolate::Converted,
    info: CageInfo,
    warnings: Vec<String>,
) -> ImportedModel {
    ImportedModel {
        patches: conv.patches,
        weights: Vec::new(),
        origins: conv.origins,
        shading: conv.shading,
        cage: Some(info),
        uvs: None,
        uv_patches: None,
        albedo: None,
        stencils: file_vertices(cage, scan).map(|file_vertex| {
            std::sync::Arc::new(super::stencil::CageModel {
                stencils: conv.stencils,
                rest: cage.positions.iter().map(|p| p.as_vec3()).collect(),
                file_vertex,
                file_faces: scan.faces.clone(),
                file_vertices: scan.vertices,
            })
        }),
        warnings,
    }
}

/// The file vertex (0-based `v` line) of each cage vertex, through the
/// faces that use it; `None` if the reader's faces do not match the file's
/// `f` lines.
fn file_vertices(cage: &Cage, scan: &Scan) -> Option<Vec<usize>> {
    if scan.faces.len() != cage.faces.len() {
        return None;
    }
    let mut out = vec![usize::MAX; cage.positions.len()];
    for (file_face, cage_face) in scan.faces.iter().zip(&cage.faces) {
        if file_face.len() != cage_face.len() {
            return None;
        }
        for (&i, &v) in file_face.iter().zip(cage_face) {
            if out[v] == usize::MAX {
                out[v] = i;
            }
        }
    }
    (!out.contains(&usize::MAX)).then_some(out)
}

/// One warning on what is non-manifold, if anything.
fn non_manifold_warning(topo: &Topology, vertices: usize) -> Option<String> {
    if topo.non_manifold_edges == 0 && vertices == 0 {
        return None;
    }
    let mut why = Vec::new();
    if topo.degenerate_edges > 0 {
        why.push(format!(
            "{} degenerate (a face repeats a vertex)",
            topo.degenerate_edges
        ));
    }
    if topo.misoriented_edges > 0 {
        why.push(format!(
            "{} whose two faces run them the same way (not consistently oriented)",
            topo.misoriented_edges
        ));
    }
    let why = if why.is_empty() {
        String::new()
    } else {
        format!(" ({})", why.join(", "))
    };
    Some(format!(
        "{} non-manifold edges{why} and {vertices} non-manifold vertices: \
         each fan of faces is its own sheet, sheets meet along shared crease curves (OpenSubdiv's rule)",
        topo.non_manifold_edges
    ))
}

/// The note on what `isolate` did: patches per level and what they hold
/// on the GPU (control points, flags and shading patches, per patch as
/// the scene buffers store them).
fn isolate_note(conv: &isolate::Converted, n: u32) -> String {
    use crate::figures::{bytes_text, thousands};
    let per_patch = crate::input::limits::GEOMETRY_BYTES_PER_PATCH
        + crate::patch::shading::SHADING_BYTES_PER_PATCH as u64;
    let per_level: Vec<String> = conv
        .levels
        .iter()
        .map(|l| {
            format!(
                "level {}: {} patches ({} exact), {}",
                l.level,
                thousands(l.patches as u64),
                thousands(l.exact as u64),
                bytes_text(l.patches as u64 * per_patch)
            )
        })
        .collect();
    let total: usize = conv.levels.iter().map(|l| l.patches).sum();
    format!(
        "isolate {n}: {} of {} connected parts refined {n} times; {}; {} in all",
        conv.isolated_parts,
        conv.parts,
        per_level.join(", "),
        bytes_text(total as u64 * per_patch)
    )
}

/// Marks the faces `t hole` names (0-based in `f` order) as holes; returns
/// how many.
fn apply_holes(path: &Path, cage: &mut Cage, scan: &Scan) -> Result<usize, SceneError> {
    if scan.tags.holes.is_empty() {
        return Ok(0);
    }
    if scan.faces.len() != cage.faces.len() {
        return Err(SceneError::invalid(
            path,
            "internal: the OBJ reader's faces do not match the file's `f` lines; cannot place the holes",
        ));
    }
    cage.holes.resize(cage.faces.len(), false);
    for &(line, f) in &scan.tags.holes {
        if f >= cage.faces.len() {
            return Err(SceneError::at(
                path,
                line,
                format!(
                    "`t hole`: face {f} out of range: faces count from 0 and the file has {}",
                    cage.faces.len()
                ),
            ));
        }
        cage.holes[f] = true;
    }
    Ok(cage.holes.iter().filter(|&&h| h).count())
}

/// What the tags put on the cage.
struct Tagged {
    sharp_edges: usize,
    semi_sharp_edges: usize,
    corners: usize,
}

/// Puts the file's crease and corner tags on `cage` (file vertex indices
/// mapped to the cage's through the faces that use them).
fn apply_tags(
    path: &Path,
    cage: &mut Cage,
    topo: &Topology,
    scan: &Scan,
) -> Result<Tagged, SceneError> {
    let tags = &scan.tags;
    if tags.creases.is_empty() && tags.corners.is_empty() {
        return Ok(Tagged {
            sharp_edges: 0,
            semi_sharp_edges: 0,
            corners: 0,
        });
    }
    if scan.faces.len() != cage.faces.len() {
        return Err(SceneError::invalid(
            path,
            "internal: the OBJ reader's faces do not match the file's `f` lines; cannot place the tags",
        ));
    }
    let mut to_cage: HashMap<usize, usize> = HashMap::new();
    for (file_face, cage_face) in scan.faces.iter().zip(&cage.faces) {
        for (&i, &v) in file_face.iter().zip(cage_face) {
            to_cage.insert(i, v);
        }
    }
    for &(line, a, b, s) in &tags.creases {
        let edge = match (to_cage.get(&a), to_cage.get(&b)) {
            (Some(&ca), Some(&cb)) => topo.edge_id(ca, cb).map(|_| (ca.min(cb), ca.max(cb))),
            _ => None,
        };
        let Some(key) = edge else {
            return Err(SceneError::at(
                path,
                line,
                format!(
                    "`t crease`: vertices {a} and {b} (counting from 0) are not the ends of an edge of any face"
                ),
            ));
        };
        if s > 0.0 {
            cage.edge_sharpness.insert(key, s.min(INFINITE));
        } else {
            cage.edge_sharpness.remove(&key);
        }
    }
    for &(_, v, s) in &tags.corners {
        // A corner on a vertex no face uses changes nothing.
        if let Some(&cv) = to_cage.get(&v) {
            if s > 0.0 {
                cage.vertex_sharpness.insert(cv, s.min(INFINITE));
            } else {
                cage.vertex_sharpness.remove(&cv);
            }
        }
    }
    let sharp_edges = cage
        .edge_sharpness
        .values()
        .filter(|&&s| s >= INFINITE)
        .count();
    Ok(Tagged {
        sharp_edges,
        semi_sharp_edges: cage.edge_sharpness.len() - sharp_edges,
        corners: cage.vertex_sharpness.len(),
    })
}

/// One cage from `tobj`'s models, and how many models had faces. Face
/// `g` (over all models, in order) is the `g`-th `f` line of the file.
fn cage_from_models(
    path: &Path,
    models: &[tobj::Model],
    face_lines: &[usize],
) -> Result<(Cage, usize), SceneError> {
    let with_faces = models.iter().filter(|m| !m.mesh.indices.is_empty()).count();
    let join = with_faces > 1;
    let total: usize = models.iter().map(|m| face_count(&m.mesh)).sum();
    let lines_match = total == face_lines.len();

    let mut cage = Cage::default();
    let mut by_bits: HashMap<[u32; 3], usize> = HashMap::new();
    for model in models {
        let mesh = &model.mesh;
        let mut local = Vec::with_capacity(mesh.positions.len() / 3);
        for xyz in mesh.positions.chunks_exact(3) {
            // Through f64 so this compiles whichever float type tobj uses.
            let p = [0, 1, 2].map(|i| f64::from(xyz[i]) as f32 + 0.0);
            if p.iter().any(|c| !c.is_finite()) {
                return Err(SceneError::invalid(
                    path,
                    "a vertex has a NaN or infinite coordinate",
                ));
            }
            let mut push = || {
                cage.positions.push(DVec3::from_array(p.map(f64::from)));
                cage.positions.len() - 1
            };
            local.push(if join {
                *by_bits.entry(p.map(f32::to_bits)).or_insert_with(push)
            } else {
                push()
            });
        }

        let arities: Vec<usize> = if mesh.face_arities.is_empty() {
            vec![3; mesh.indices.len() / 3]
        } else {
            mesh.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut at = 0;
        for arity in arities {
            let face: Option<Vec<usize>> = mesh
                .indices
                .get(at..at + arity)
                .and_then(|ix| ix.iter().map(|&i| local.get(i as usize).copied()).collect());
            let face = face.ok_or_else(|| {
                SceneError::invalid(path, "OBJ reader returned an inconsistent face list")
            })?;
            at += arity;
            let g = cage.faces.len();
            cage.faces.push(face);
            cage.face_lines.push(if lines_match {
                face_lines.get(g).copied()
            } else {
                None
            });
        }
    }
    Ok((cage, with_faces))
}

fn face_count(mesh: &tobj::Mesh) -> usize {
    if mesh.face_arities.is_empty() {
        mesh.indices.len() / 3
    } else {
        mesh.face_arities.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_isolate_note_gives_patches_and_memory_per_level() {
        let conv = isolate::Converted {
            levels: vec![
                crate::cage::isolate::LevelCount {
                    level: 0,
                    patches: 1000,
                    exact: 900,
                },
                crate::cage::isolate::LevelCount {
                    level: 2,
                    patches: 4096,
                    exact: 4000,
                },
            ],
            isolated_parts: 1,
            parts: 3,
            ..Default::default()
        };
        // 484 bytes a patch: 196 of control points and flags, 288 of
        // shading patch.
        assert_eq!(
            isolate_note(&conv, 2),
            "isolate 2: 1 of 3 connected parts refined 2 times; level 0: 1,000 patches \
             (900 exact), 472.7 KiB, level 2: 4,096 patches (4,000 exact), 1.9 MiB; \
             2.4 MiB in all"
        );
    }
}
