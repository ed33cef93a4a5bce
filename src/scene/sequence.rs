//! OBJ sequences in a scene file: `file = "anim/walk_####.obj"`, one file
//! per frame. Here, which files a pattern names; `anim::sequence` reads
//! their vertices.

use std::path::{Path, PathBuf};

use super::SceneError;

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
