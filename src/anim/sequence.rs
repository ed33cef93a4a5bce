//! OBJ sequences: `file = "anim/walk_####.obj"`, the usual export of
//! animation tools, one file per frame with the same faces. The first frame
//! is the model (converted, its stencils built); every other frame only
//! gives the cage's vertices, and is refused, with its file and line, where
//! its faces differ from the first frame's.

use std::path::Path;

use glam::Vec3;

use crate::cage::stencil::CageModel;
use crate::scene::SceneError;

/// The cage vertices of one more frame of the sequence whose first frame is
/// `cage`: its `v` statements in cage order. Refused where its faces (`f`
/// statements, by vertex) differ from the first frame's.
pub fn read_frame(path: &Path, cage: &CageModel) -> Result<Vec<Vec3>, SceneError> {
    let text = crate::input::text::read_text(path)?;
    let mut positions: Vec<Vec3> = Vec::with_capacity(cage.file_vertices);
    let mut face = 0usize;
    let mut last_line = 0;
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        last_line = line_no;
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let xyz: Vec<f32> = words.take(3).filter_map(|w| w.parse().ok()).collect();
                match xyz[..] {
                    [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => {
                        positions.push(Vec3::new(x, y, z) + Vec3::ZERO)
                    }
                    _ => {
                        return Err(SceneError::at(
                            path,
                            line_no,
                            "a vertex needs three finite numbers",
                        ))
                    }
                }
            }
            Some("f") => {
                let refs: Option<Vec<usize>> = words
                    .map(|w| {
                        let v: i64 = w.split('/').next()?.parse().ok()?;
                        match v {
                            v if v > 0 => Some(v as usize - 1),
                            v if v < 0 => positions.len().checked_sub(v.unsigned_abs() as usize),
                            _ => None,
                        }
                    })
                    .collect();
                let want = cage.file_faces.get(face);
                if refs.as_ref() != want {
                    let msg = match want {
                        Some(w) => format!(
                            "face {} differs from the first frame's ({}): a sequence keeps one topology",
                            face + 1,
                            w.iter().map(|v| (v + 1).to_string()).collect::<Vec<_>>().join(" ")
                        ),
                        None => format!(
                            "face {} is more than the first frame's {}: a sequence keeps one topology",
                            face + 1,
                            cage.file_faces.len()
                        ),
                    };
                    return Err(SceneError::at(path, line_no, msg));
                }
                face += 1;
            }
            _ => {}
        }
    }
    if face != cage.file_faces.len() {
        return Err(SceneError::at(
            path,
            last_line,
            format!(
                "{face} faces where the first frame has {}: a sequence keeps one topology",
                cage.file_faces.len()
            ),
        ));
    }
    if positions.len() != cage.file_vertices {
        return Err(SceneError::at(
            path,
            last_line,
            format!(
                "{} vertices where the first frame has {}: a sequence keeps one topology",
                positions.len(),
                cage.file_vertices
            ),
        ));
    }
    Ok(cage.file_vertex.iter().map(|&i| positions[i]).collect())
}
