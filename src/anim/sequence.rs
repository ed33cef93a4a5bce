//! OBJ sequences: `file = "anim/walk_####.obj"`, the usual export of
//! animation tools, one file per frame with the same faces. The first frame
//! is the model (converted, its stencils built); every other frame only
//! gives the cage's vertices, and is refused, with its file and line, where
//! its faces differ from the first frame's.

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::scene::stencil::CageModel;
use crate::scene::SceneError;

/// The frame files of `pattern` (its run of `#` is the frame number,
/// zero-padded to that width), in order: every number from the lowest
/// found up, with no gap.
pub fn frames(pattern: &Path) -> Result<Vec<PathBuf>, SceneError> {
    let name = pattern
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| SceneError::invalid(pattern, "a sequence pattern needs a file name"))?;
    let start = name.find('#').ok_or_else(|| {
        SceneError::invalid(
            pattern,
            "a sequence pattern needs a run of `#` for the frame number",
        )
    })?;
    let width = name[start..].chars().take_while(|&c| c == '#').count();
    let (prefix, suffix) = (&name[..start], &name[start + width..]);
    if suffix.contains('#') {
        return Err(SceneError::invalid(
            pattern,
            "a sequence pattern has one run of `#` (the frame number)",
        ));
    }
    // A bare file name's parent is "", which read_dir refuses.
    let dir = match pattern.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let entries = std::fs::read_dir(dir).map_err(|e| SceneError::io(dir, e))?;
    let mut numbers: Vec<u64> = entries
        .filter_map(|e| e.ok())
        .filter_map(|e| e.file_name().to_str().map(str::to_owned))
        .filter_map(|n| {
            let digits = n.strip_prefix(prefix)?.strip_suffix(suffix)?;
            (digits.len() == width && digits.bytes().all(|b| b.is_ascii_digit()))
                .then(|| digits.parse().ok())
                .flatten()
        })
        .collect();
    numbers.sort_unstable();
    let Some(&first) = numbers.first() else {
        return Err(SceneError::invalid(
            pattern,
            format!(
                "no frame files match ({prefix}{}{suffix})",
                "0".repeat(width)
            ),
        ));
    };
    let path_of = |n: u64| dir.join(format!("{prefix}{n:0width$}{suffix}"));
    for (k, &n) in numbers.iter().enumerate() {
        if n != first + k as u64 {
            return Err(SceneError::invalid(
                &path_of(first + k as u64),
                format!(
                    "missing: the sequence has frames {first} to {} with a gap here",
                    numbers.last().copied().unwrap_or(first)
                ),
            ));
        }
    }
    Ok(numbers.into_iter().map(path_of).collect())
}

/// The cage vertices of one more frame of the sequence whose first frame is
/// `cage`: its `v` statements in cage order. Refused where its faces (`f`
/// statements, by vertex) differ from the first frame's.
pub fn read_frame(path: &Path, cage: &CageModel) -> Result<Vec<Vec3>, SceneError> {
    let text = crate::scene::text::read_text(path)?;
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
