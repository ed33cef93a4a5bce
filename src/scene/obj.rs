//! Catmull–Clark control cages (Wavefront OBJ) → bicubic Bézier patches.
//!
//! # Reading
//!
//! The file is parsed by `tobj` (faces kept as polygons, one index per
//! attribute). Before that, a small scan of our own walks the text to give
//! errors a line number, which `tobj`'s errors lack, and to refuse what
//! `tobj` accepts but a cage cannot use:
//!
//! - a `v` line without three numbers, or with a NaN or infinite coordinate
//!   (after an optional `w`, which must not be 0);
//! - an `f` line with fewer than three vertices, an index that is not a
//!   number, is 0, or points past the vertices (negative indices count back
//!   from the last vertex read, as OBJ says); `l` (polyline) lines;
//! - `vt`/`vn` lines without numbers and texture/normal indices out of range
//!   (`tobj` would refuse them; the cage does not use them).
//!
//! Unknown statements are skipped; OpenSubdiv's `t` tags (crease and corner
//! sharpness) are counted and reported in one warning: creases are not
//! modelled, every interior edge is smooth.
//!
//! When `o`/`g`/`usemtl` lines split the file into several `tobj` models,
//! they are joined into one cage: vertices with bit-identical positions
//! (after -0.0 → +0.0) become one vertex. Within a single model the file's
//! vertex indices are kept as they are, so coincident but distinct vertices
//! stay distinct there.
//!
//! The cage must be an oriented 2-manifold, possibly with boundary (see
//! `cage.rs`): no edge in more than two faces or twice in the same direction,
//! no face with a repeated vertex, one fan of faces around every vertex.
//!
//! # Conversion (the project's rules)
//!
//! Valence n of a vertex: its number of incident edges. An edge with one face
//! is a boundary edge; a vertex on one is a boundary vertex, otherwise it is
//! interior.
//!
//! Parameterisation: quad face (v0, v1, v2, v3) in file order has its
//! parameter origin at v0, u running towards v1 and v towards v3 — vertex k
//! at (0,0), (1,0), (1,1), (0,1), OpenSubdiv's quad convention. Faces listed
//! counter-clockwise seen from outside then give an outward ∂S/∂u × ∂S/∂v.
//!
//! One bicubic patch per quad, by approximate Catmull–Clark surfaces (Loop &
//! Schaefer 2008). All arithmetic is f64 from the file's f32 positions; each
//! control point is rounded to f32 once.
//!
//! - Interior point of face F near its corner v, with e_a, e_b the two
//!   neighbours of v in F and f the opposite vertex:
//!   (n·v + 2·e_a + 2·e_b + f)/(n + 5). At a regular vertex (n = 4) this is
//!   the B-spline → Bézier rule. At a boundary vertex n = 4 is used whatever
//!   the valence.
//! - Edge point of an interior edge (v, w) near v: the average of the two
//!   interior points near v of the two faces sharing the edge.
//! - Corner point of an interior vertex: its Catmull–Clark limit position
//!   (n²·v + 4·Σ edge neighbours + Σ diagonal vertices)/(n(n + 5)), which is
//!   also the average of the interior points around v.
//! - Boundaries are sharp creases: the boundary curve is the uniform cubic
//!   B-spline of the boundary vertices, as OpenSubdiv's default edge-only
//!   boundary interpolation gives along the boundary. Edge point of a boundary
//!   edge (v, w) near v: (2v + w)/3. Corner point of a boundary vertex with
//!   two or more faces: (v_prev + 4v + v_next)/6 from its two boundary
//!   neighbours; of a vertex with one face (a cage corner): v itself.
//!   Inside the patches next to a boundary this only approximates
//!   OpenSubdiv's limit surface.
//!
//! The surface is C0 everywhere (tangent-continuous only where the regular
//! B-spline rules apply). It is watertight bit for bit (DESIGN invariant 4):
//! every corner point and every edge point (per edge and end) is computed
//! once and copied into each patch that uses it, never recomputed per face.
//!
//! Non-quad faces: if any face is not a quad, one global Catmull–Clark step
//! (`cage::refine`: standard rules, boundary edges creased, cage corners with
//! one face fixed) first turns the whole cage into quads; sub-quad k of face
//! F is (v_k, edge point of (v_k, v_k+1), face point, edge point of
//! (v_k−1, v_k)), and the patches follow face order, then k. A warning says
//! so.
//!
//! Origins: `PatchOrigin::face` is the index of the original cage face (the
//! n-th `f` line, 0-based). `corners_uv` are the face-parameter coordinates of
//! the patch's parameter corners (0,0), (1,0), (1,1), (0,1): the unit square
//! for an unrefined quad; for sub-quad k of a refined quad the corner k of
//! the square, the midpoint of edge (k, k+1), the centre and the midpoint of
//! edge (k−1, k) (sub-quad 0: `[[0,0],[0.5,0],[0.5,0.5],[0,0.5]]`); `None` for
//! patches of non-quad faces.

use std::collections::HashMap;
use std::path::Path;

use glam::DVec3;

use super::cage::{refine, Cage, Topology};
use super::{acc, ImportedModel, PatchOrigin, SceneError};

/// Reads an OBJ control cage and converts it to Bézier patches.
pub fn read(path: &Path) -> Result<ImportedModel, SceneError> {
    let text = super::read_text(path)?;
    parse(path, &text)
}

/// Parses OBJ text; `path_for_errors` only names the source in errors.
pub fn parse(path_for_errors: &Path, text: &str) -> Result<ImportedModel, SceneError> {
    let path = path_for_errors;
    let scan = scan(path, text)?;
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
    let options = tobj::LoadOptions {
        single_index: false,
        triangulate: false,
        ignore_points: false,
        ignore_lines: false,
        ..Default::default()
    };
    let mut reader = text.as_bytes();
    let (models, _materials) = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::GenericFailure)
    })
    .map_err(|e| SceneError::invalid(path, format!("OBJ reader: {e}")))?;

    let mut warnings = Vec::new();
    if scan.t_lines > 0 {
        warnings.push(format!(
            "{} OpenSubdiv `t` tag lines (crease/corner sharpness) ignored: creases are not modelled",
            scan.t_lines
        ));
    }
    let (cage, joined) = cage_from_models(path, &models, &scan.face_lines)?;
    if joined > 1 {
        warnings.push(format!(
            "{joined} objects/groups joined into one cage by merging vertices with bit-identical positions"
        ));
    }
    let topo = Topology::build(&cage, path)?;
    if topo.boundary_edges > 0 {
        warnings.push(format!(
            "{} boundary edges: boundaries are creased (cubic B-spline of the boundary vertices); \
             next to them the surface approximates OpenSubdiv's",
            topo.boundary_edges
        ));
    }

    let non_quads = cage.faces.iter().filter(|f| f.len() != 4).count();
    let (patches, origins) = if non_quads == 0 {
        let patches = acc::convert(&cage, &topo, path)?;
        let origins = (0..patches.len())
            .map(|face| PatchOrigin {
                face,
                corners_uv: Some(QUAD_UV),
            })
            .collect();
        (patches, origins)
    } else {
        let (fine, subs) = refine(&cage, &topo);
        let fine_topo = Topology::build(&fine, path)?;
        let patches = acc::convert(&fine, &fine_topo, path)?;
        let origins = subs
            .iter()
            .map(|s| PatchOrigin {
                face: s.face,
                corners_uv: (cage.faces[s.face].len() == 4).then(|| sub_quad_uv(s.corner)),
            })
            .collect();
        warnings.push(format!(
            "{non_quads} non-quad faces: one Catmull–Clark step applied to the whole cage, {} patches",
            patches.len()
        ));
        (patches, origins)
    };

    Ok(ImportedModel {
        patches,
        origins,
        warnings,
    })
}

/// Face-parameter coordinates of a quad's corners 0..4.
const QUAD_UV: [[f32; 2]; 4] = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];

/// `corners_uv` of sub-quad `k` of a refined quad face.
fn sub_quad_uv(k: usize) -> [[f32; 2]; 4] {
    let c = |i: usize| QUAD_UV[i % 4];
    let mid = |a: [f32; 2], b: [f32; 2]| [(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5];
    [c(k), mid(c(k), c(k + 1)), [0.5, 0.5], mid(c(k + 3), c(k))]
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

/// What the line scan found.
struct Scan {
    /// Line number of each `f` statement, in order.
    face_lines: Vec<usize>,
    /// Number of `t` tag lines.
    t_lines: usize,
}

/// Checks the text line by line for what we refuse, with line numbers.
fn scan(path: &Path, text: &str) -> Result<Scan, SceneError> {
    // Totals first: forward references to later vertices are legal OBJ.
    let mut total = [0usize; 3]; // v, vt, vn
    for line in text.lines() {
        match line.split_whitespace().next() {
            Some("v") => total[0] += 1,
            Some("vt") => total[1] += 1,
            Some("vn") => total[2] += 1,
            _ => {}
        }
    }

    let mut seen = [0usize; 3];
    let mut out = Scan {
        face_lines: Vec::new(),
        t_lines: 0,
    };
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let err = |msg: String| SceneError::at(path, line_no, msg);
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let rest: Vec<&str> = words.collect();
        match keyword {
            "v" => {
                check_vertex(&rest).map_err(err)?;
                seen[0] += 1;
            }
            "vt" | "vn" => {
                let need = if keyword == "vt" { 2 } else { 3 };
                if rest.len() < need || rest[..need].iter().any(|w| w.parse::<f32>().is_err()) {
                    return Err(err(format!("`{keyword}` needs {need} numbers")));
                }
                seen[if keyword == "vt" { 1 } else { 2 }] += 1;
            }
            "f" => {
                if rest.len() < 3 {
                    return Err(err(format!(
                        "a face needs at least 3 vertices, this one has {}",
                        rest.len()
                    )));
                }
                for r in &rest {
                    check_face_ref(r, &seen, &total).map_err(err)?;
                }
                out.face_lines.push(line_no);
            }
            "l" => {
                return Err(err(
                    "`l` (polyline) statements are not supported: a control cage has only faces"
                        .into(),
                ))
            }
            "usemtl" if rest.is_empty() => {
                return Err(err("`usemtl` without a material name".into()))
            }
            "t" => out.t_lines += 1,
            _ => {}
        }
    }
    Ok(out)
}

/// `x y z`, `x y z w` (w ≠ 0) or `x y z r g b`, all coordinates finite.
fn check_vertex(words: &[&str]) -> Result<(), String> {
    if !matches!(words.len(), 3 | 4 | 6) {
        return Err(format!(
            "a vertex needs x y z (optionally w, or r g b), found {} values",
            words.len()
        ));
    }
    let mut xyz = [0f32; 3];
    for (k, w) in words[..3].iter().enumerate() {
        xyz[k] = w
            .parse()
            .map_err(|_| format!("vertex coordinate is not a number: {w:?}"))?;
    }
    if words.len() == 4 {
        let w: f32 = words[3]
            .parse()
            .map_err(|_| format!("vertex weight w is not a number: {:?}", words[3]))?;
        if w == 0.0 {
            return Err("vertex weight w is 0".into());
        }
        xyz = xyz.map(|c| c / w);
    }
    if xyz.iter().any(|c| !c.is_finite()) {
        return Err(format!(
            "vertex coordinate is NaN or infinite: {}",
            words.join(" ")
        ));
    }
    Ok(())
}

/// One `v`, `v/vt`, `v//vn` or `v/vt/vn` reference of a face.
fn check_face_ref(r: &str, seen: &[usize; 3], total: &[usize; 3]) -> Result<(), String> {
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 {
        return Err(format!("face vertex {r:?} has more than three parts"));
    }
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const WHATS: [&str; 3] = ["vertices", "texture coordinates", "normals"];
    for (slot, s) in parts.iter().enumerate() {
        if s.is_empty() {
            if slot == 0 {
                return Err(format!("face vertex {r:?} has no vertex index"));
            }
            continue;
        }
        let what = WHAT[slot];
        let x: i64 = s
            .parse()
            .map_err(|_| format!("face {what} index is not a number: {s:?}"))?;
        // tobj ignores texture and normal indices when there are none.
        if slot > 0 && total[slot] == 0 {
            continue;
        }
        let name = |n: usize| if n == 1 { WHAT[slot] } else { WHATS[slot] };
        match x {
            0 => return Err(format!("face {what} index 0: OBJ indices start at 1")),
            x if x > 0 && x as u64 > total[slot] as u64 => {
                return Err(format!(
                    "face {what} index {x} out of range: the file has {} {}",
                    total[slot],
                    name(total[slot])
                ))
            }
            x if x < 0 && x.unsigned_abs() > seen[slot] as u64 => {
                return Err(format!(
                    "relative face {what} index {x} out of range: {} {} read so far",
                    seen[slot],
                    name(seen[slot])
                ))
            }
            _ => {}
        }
    }
    Ok(())
}
