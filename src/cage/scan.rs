//! OBJ text checked line by line before `tobj` reads it, so that every
//! refusal names its line: vertices, faces and their references, tags
//! (`tags`); and the statements as the readers of OBJ text walk them.

use std::path::Path;

use super::tags::Tags;
use crate::input::limits::MAX_COORD;
use crate::input::SceneError;

/// What the line scan found.
pub(super) struct Scan {
    /// `v` statements.
    pub(super) vertices: usize,
    /// Line number of each `f` statement, in order.
    pub(super) face_lines: Vec<usize>,
    /// The 0-based file vertex index of each corner of each `f` statement.
    pub(super) faces: Vec<Vec<usize>>,
    /// The OpenSubdiv tags.
    pub(super) tags: Tags,
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
        tags: Tags::default(),
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
                seen[if keyword == "vt" { 1 } else { 2 }] += 1;
            }
            "f" => {
                let face =
                    face_corners(&rest, |r| check_face_ref(r, &seen, &total)).map_err(err)?;
                out.faces.push(face);
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
            "t" => out.tags.read(line_no, &rest, total[0]).map_err(err)?,
            _ => {}
        }
    }
    Ok(out)
}

/// The statements of OBJ text: each line that is not blank as its number
/// (from 1, for errors), its keyword and the words after it.
pub(crate) fn statements(text: &str) -> impl Iterator<Item = (usize, &str, Vec<&str>)> {
    text.lines().enumerate().filter_map(|(i, line)| {
        let mut words = line.split_whitespace();
        let keyword = words.next()?;
        Some((i + 1, keyword, words.collect()))
    })
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

/// One `v`, `v/vt`, `v//vn` or `v/vt/vn` reference of a face; returns
/// the 0-based index of its vertex in the file.
fn check_face_ref(r: &str, seen: &[usize; 3], total: &[usize; 3]) -> Result<usize, String> {
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 {
        return Err(format!("face vertex {r:?} has more than three parts"));
    }
    const WHAT: [&str; 3] = ["vertex", "texture coordinate", "normal"];
    const WHATS: [&str; 3] = ["vertices", "texture coordinates", "normals"];
    let mut vertex = 0;
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
        if slot == 0 {
            vertex = if x > 0 {
                x as usize - 1
            } else {
                (seen[0] as i64 + x) as usize
            };
        }
    }
    Ok(vertex)
}
