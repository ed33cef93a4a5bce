//! OBJ text checked line by line before `tobj` reads it, so that every
//! refusal names its line: vertices, faces and their references, tags
//! (`tags`), materials (`mtl`).

use std::path::Path;

use super::mtl::MaterialUse;
use super::tags::Tags;
use crate::input::limits::MAX_COORD;
use crate::input::text::statements;
use crate::input::SceneError;

/// What the line scan found.
pub(super) struct Scan {
    /// `v` statements.
    pub(super) vertices: usize,
    /// Line number of each `f` statement, in order.
    pub(super) face_lines: Vec<usize>,
    /// The 0-based file vertex index of each corner of each `f` statement.
    pub(super) faces: Vec<Vec<usize>>,
    /// The `vt` statements' (u, v), in order.
    pub(super) uvs: Vec<[f32; 2]>,
    /// The 0-based `vt` index of each corner of each `f` statement, `None`
    /// for a face without texture coordinates.
    pub(super) uv_faces: Vec<Option<Vec<usize>>>,
    /// Why the texture coordinates cannot be used, and the line that
    /// shows it: a face with them on some corners only, or a face without
    /// them where others have them.
    pub(super) uv_problem: Option<(usize, String)>,
    /// The OpenSubdiv tags.
    pub(super) tags: Tags,
    /// The `mtllib` and `usemtl` statements (`mtl.rs`).
    pub(super) materials: MaterialUse,
}

/// Checks the text line by line for what we refuse, with line numbers.
pub(super) fn scan(path: &Path, text: &str) -> Result<Scan, SceneError> {
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
        vertices: total[0],
        face_lines: Vec::new(),
        faces: Vec::new(),
        uvs: Vec::new(),
        uv_faces: Vec::new(),
        uv_problem: None,
        tags: Tags::default(),
        materials: MaterialUse::default(),
    };
    for (line_no, keyword, rest) in statements(text) {
        let err = |msg: String| SceneError::at(path, line_no, msg);
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
                if keyword == "vt" {
                    let uv = [rest[0], rest[1]].map(|w| w.parse::<f32>().unwrap_or(f32::NAN));
                    if uv.iter().any(|c| !c.is_finite()) {
                        return Err(err("`vt` coordinate is NaN or infinite".into()));
                    }
                    out.uvs.push(uv);
                }
                seen[if keyword == "vt" { 1 } else { 2 }] += 1;
            }
            "f" => {
                let corners =
                    face_corners(&rest, |r| check_face_ref(r, &seen, &total)).map_err(err)?;
                let uvs = face_uvs(&corners).unwrap_or_else(|why| {
                    out.uv_problem.get_or_insert((line_no, why));
                    None
                });
                out.uv_faces.push(uvs);
                out.faces.push(corners.iter().map(|c| c.vertex).collect());
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
            "usemtl" | "mtllib" => out.materials.record(line_no, keyword, &rest),
            "t" => out.tags.read(line_no, &rest, total[0]).map_err(err)?,
            _ => {}
        }
    }
    if out.uv_problem.is_none() {
        out.uv_problem = faces_without_uvs(&out);
    }
    Ok(out)
}

/// A face's texture indices: every corner's, or `None` where no corner
/// has one; a face with some corners only is a problem (OpenSubdiv's
/// face-varying data gives every corner of a face a value).
fn face_uvs(corners: &[Corner]) -> Result<Option<Vec<usize>>, String> {
    let with = corners.iter().filter(|c| c.uv.is_some()).count();
    match with {
        0 => Ok(None),
        n if n == corners.len() => Ok(Some(corners.iter().filter_map(|c| c.uv).collect())),
        n => Err(format!(
            "the face has texture coordinates on {n} of its {} corners",
            corners.len()
        )),
    }
}

/// A file where some faces have texture coordinates and others none: the
/// first face without, and why that is a problem (the surface's UVs would
/// stop there, and a texture could not be mapped across it).
fn faces_without_uvs(scan: &Scan) -> Option<(usize, String)> {
    let with = scan.uv_faces.iter().filter(|f| f.is_some()).count();
    if with == 0 || with == scan.uv_faces.len() {
        return None;
    }
    let first = scan.uv_faces.iter().position(Option::is_none)?;
    Some((
        scan.face_lines[first],
        format!(
            "this face has no texture coordinates, but {with} of the {} faces do",
            scan.uv_faces.len()
        ),
    ))
}

/// The corners of an `f` statement's words `refs`, each read by `corner`;
/// a face needs at least 3.
pub(crate) fn face_corners<T>(
    refs: &[&str],
    corner: impl Fn(&str) -> Result<T, String>,
) -> Result<Vec<T>, String> {
    if refs.len() < 3 {
        return Err(format!(
            "a face needs at least 3 vertices, this one has {}",
            refs.len()
        ));
    }
    refs.iter().map(|r| corner(r)).collect()
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
    // A scene refuses a control point past ±MAX_COORD (as a .bpt does);
    // the cage's limit surface lies within its vertices' hull, so saying so
    // here names the line, where the converted patches could not.
    if let Some(c) = xyz.iter().find(|c| c.abs() > MAX_COORD) {
        return Err(format!(
            "vertex coordinate {c:e} is beyond ±{MAX_COORD:e}, the largest a scene accepts \
             (scale the model down)"
        ));
    }
    Ok(())
}

/// One corner of a face: its file vertex and `vt` (0-based).
#[derive(Clone, Copy)]
struct Corner {
    vertex: usize,
    uv: Option<usize>,
}

/// One `v`, `v/vt`, `v//vn` or `v/vt/vn` reference of a face; returns
/// the 0-based indices of its vertex and texture coordinate in the file.
fn check_face_ref(r: &str, seen: &[usize; 3], total: &[usize; 3]) -> Result<Corner, String> {
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 {
        return Err(format!("face vertex {r:?} has more than three parts"));
    }
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const WHATS: [&str; 3] = ["vertices", "texture coordinates", "normals"];
    let mut corner = Corner {
        vertex: 0,
        uv: None,
    };
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
        let index = if x > 0 {
            x as usize - 1
        } else {
            (seen[slot] as i64 + x) as usize
        };
        match slot {
            0 => corner.vertex = index,
            1 => corner.uv = Some(index),
            _ => {}
        }
    }
    Ok(corner)
}
