//! `.bpt` Bézier patch files (the Utah teapot's format).
//!
//! ```text
//! 32                                  patch count
//! 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16   16 one-based point indices per patch
//! ...
//! 306                                 point count
//! 1.4,0.0,2.4                         x,y,z per point
//! ```
//!
//! Index order: the 16 indices of a patch line are a 4×4 array written row by
//! row, and each written row is a curve of constant **v** with u running along
//! it: line position `4 * j + i` is (u index `i`, v index `j`), which is
//! exactly our storage order `pts[4 * j + i]`. With this reading every teapot
//! patch has ∂S/∂u × ∂S/∂v pointing out of the pot; the transposed reading
//! turns all 32 inwards. The tests `teapot_body_normals_point_away_from_axis`
//! and `teapot_normals_point_outward` pin this.
//!
//! What is accepted: whitespace around numbers, CRLF line ends, blank lines at
//! the end of the file. What is refused, each with file and 1-based line: an
//! empty file, a file that ends before the counts promise, garbled numbers, a
//! patch line without exactly 16 indices, an index that is 0 or past the
//! point count, a coordinate that is NaN, infinite or beyond ±1e6 (the
//! largest a scene accepts, [`MAX_COORD`]), a point line without
//! exactly three coordinates, anything after the last point, and a patch
//! count of 0. -0.0 is read as +0.0 (see `BezierPatch::canonical_zeros`).
//!
//! # `.rbpt`: rational patches
//!
//! The same layout with a weight column: every point line is `x,y,z,w`,
//! the Cartesian point p and its weight w (not the homogeneous w·p), so a
//! file with every w = 1 describes exactly the patches of the `.bpt` file
//! without the column. A patch's weights are those of its 16 points, in the
//! patch line's order (`w[4 * j + i]` with `pts[4 * j + i]`); two patches
//! that share a boundary must share its points *and* weights to meet. Refused
//! besides the `.bpt` cases, with file and line: a point line without exactly
//! four fields, and a weight that is not a number in
//! [`MIN_WEIGHT`]..=[`MAX_WEIGHT`] (zero and negative weights included).
//!
//! ```text
//! 1
//! 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16
//! 16
//! 1,0,0,1                             x,y,z,w per point
//! 1,0.4142135,0,0.8047379
//! ...
//! ```

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use glam::Vec3;

use crate::input::limits::MAX_COORD;
use crate::input::SceneError;
use crate::patch::bezier::BezierPatch;
use crate::patch::rational::{weight_ok, Weights, MAX_WEIGHT, MIN_WEIGHT};

/// Storage slot (`pts` index) of the value at position `k` (0..16) of a
/// patch line. The file order is our storage order (see the module doc); the
/// function names the decision in the one place a change would go.
#[inline]
fn slot_of_line_position(k: usize) -> usize {
    k
}

/// Reads a `.bpt` file.
pub fn read(path: &Path) -> Result<Vec<BezierPatch>, SceneError> {
    let text = crate::input::text::read_text(path)?;
    parse(path, &text)
}

/// Parses `.bpt` text; `path_for_errors` only names the source in errors.
pub fn parse(path_for_errors: &Path, text: &str) -> Result<Vec<BezierPatch>, SceneError> {
    parse_with_points(path_for_errors, text).map(|(patches, _)| patches)
}

/// Reads a `.rbpt` file: the patches and their weights.
pub fn read_rational(path: &Path) -> Result<(Vec<BezierPatch>, Vec<Weights>), SceneError> {
    let text = crate::input::text::read_text(path)?;
    parse_rational(path, &text)
}

/// Parses `.rbpt` text; `path_for_errors` only names the source in errors.
pub fn parse_rational(
    path_for_errors: &Path,
    text: &str,
) -> Result<(Vec<BezierPatch>, Vec<Weights>), SceneError> {
    parse_any(path_for_errors, text, true).map(|(patches, weights, _)| (patches, weights))
}

/// [`parse`], also returning the file's point list (for tests and tools that
/// want the declared points, duplicates included).
fn parse_with_points(
    path_for_errors: &Path,
    text: &str,
) -> Result<(Vec<BezierPatch>, Vec<Vec3>), SceneError> {
    parse_any(path_for_errors, text, false).map(|(patches, _, points)| (patches, points))
}

/// What [`parse_any`] reads: the patches, their weights and the points.
type Parsed = (Vec<BezierPatch>, Vec<Weights>, Vec<Vec3>);

/// Both formats: `weighted` reads `.rbpt` point lines (x,y,z,w). Returns
/// the patches, their weights (all 1 without the column) and the points.
fn parse_any(path_for_errors: &Path, text: &str, weighted: bool) -> Result<Parsed, SceneError> {
    let path = path_for_errors;
    let mut lines = Lines::new(text);

    let (line_no, first) = lines
        .next()
        .ok_or_else(|| SceneError::at(path, 1, "empty file (expected the patch count)"))?;
    let patch_count = parse_count(path, line_no, first, "patch count")?;
    if patch_count == 0 {
        return Err(SceneError::at(
            path,
            line_no,
            "patch count is 0: no patches",
        ));
    }

    // Indices are checked against the point count once that is known, so keep
    // each patch's line for the message.
    let mut index_lines: Vec<(usize, [usize; 16])> = Vec::new();
    for p in 0..patch_count {
        let (line_no, line) = lines.next().ok_or_else(|| {
            SceneError::at(
                path,
                lines.end_line(),
                format!(
                    "file ends early: expected patch line {} of {patch_count}",
                    p + 1
                ),
            )
        })?;
        index_lines.push((line_no, parse_indices(path, line_no, line)?));
    }

    let (line_no, line) = lines.next().ok_or_else(|| {
        SceneError::at(
            path,
            lines.end_line(),
            "file ends early: expected the point count",
        )
    })?;
    let point_count = parse_count(path, line_no, line, "point count")?;

    let mut points: Vec<Vec3> = Vec::new();
    let mut point_weights: Vec<f32> = Vec::new();
    for p in 0..point_count {
        let (line_no, line) = lines.next().ok_or_else(|| {
            SceneError::at(
                path,
                lines.end_line(),
                format!("file ends early: expected point {} of {point_count}", p + 1),
            )
        })?;
        let (point, w) = parse_point(path, line_no, line, weighted)?;
        points.push(point);
        point_weights.push(w);
    }

    while let Some((line_no, line)) = lines.next() {
        if line.trim().is_empty() {
            continue;
        }
        return Err(SceneError::at(
            path,
            line_no,
            format!("unexpected content after the last point: {:?}", clip(line)),
        ));
    }

    let mut patches = Vec::with_capacity(index_lines.len());
    let mut weights = Vec::with_capacity(index_lines.len());
    for (line_no, idx) in index_lines {
        let mut pts = [Vec3::ZERO; 16];
        let mut w = [1.0f32; 16];
        for (k, &i) in idx.iter().enumerate() {
            if i == 0 || i > point_count {
                return Err(SceneError::at(
                    path,
                    line_no,
                    format!("point index {i} out of range 1..={point_count}"),
                ));
            }
            pts[slot_of_line_position(k)] = points[i - 1];
            w[slot_of_line_position(k)] = point_weights[i - 1];
        }
        patches.push(BezierPatch { pts }.canonical_zeros());
        weights.push(w);
    }
    Ok((patches, weights, points))
}

/// Writes patches as a `.bpt` file. Control points are deduplicated by exact
/// bits, so points that patches share stay shared; coordinates use Rust's
/// shortest round-trip float format, so reading the file back gives the same
/// bits (for patches without -0.0, which reading canonicalises). The file is
/// written beside its destination and renamed into place, so a failure never
/// leaves a half-written file under `path`.
pub fn write(path: &Path, patches: &[BezierPatch]) -> Result<(), SceneError> {
    write_any(path, patches, None)
}

/// Writes patches and their weights as a `.rbpt` file, as [`write`] does
/// (points are shared by exact bits of the point *and* its weight).
pub fn write_rational(
    path: &Path,
    patches: &[BezierPatch],
    weights: &[Weights],
) -> Result<(), SceneError> {
    if weights.len() != patches.len() {
        return Err(SceneError::invalid(
            path,
            format!(
                "{} patches with {} weight sets",
                patches.len(),
                weights.len()
            ),
        ));
    }
    if let Some(i) = weights
        .iter()
        .position(|w| !w.iter().all(|&x| weight_ok(x)))
    {
        return Err(SceneError::invalid(
            path,
            format!("patch {i} has a weight outside {MIN_WEIGHT}..={MAX_WEIGHT}"),
        ));
    }
    write_any(path, patches, Some(weights))
}

/// Whether [`write`] would write `patches` to `path` (errors name `path`):
/// one patch at least, every control point finite and within ±MAX_COORD,
/// as [`read`] demands. A writer that goes through a temporary file checks
/// first, so that an error names the file asked for.
pub fn check(path: &Path, patches: &[BezierPatch]) -> Result<(), SceneError> {
    if patches.is_empty() {
        return Err(SceneError::invalid(
            path,
            "refusing to write a .bpt file with no patches",
        ));
    }
    if let Some(i) = patches.iter().position(|p| !p.is_finite()) {
        return Err(SceneError::invalid(
            path,
            format!("patch {i} has a NaN or infinite control point"),
        ));
    }
    // What `read` would refuse is not written either.
    if let Some(i) = patches
        .iter()
        .position(|p| p.pts.iter().any(|q| q.abs().max_element() > MAX_COORD))
    {
        return Err(SceneError::invalid(
            path,
            format!("patch {i} has a control point beyond ±{MAX_COORD:e}"),
        ));
    }
    Ok(())
}

fn write_any(
    path: &Path,
    patches: &[BezierPatch],
    weights: Option<&[Weights]>,
) -> Result<(), SceneError> {
    check(path, patches)?;
    let mut index_of: HashMap<[u32; 4], usize> = HashMap::new();
    let mut points: Vec<(Vec3, f32)> = Vec::new();
    let mut text = String::new();
    let _ = writeln!(text, "{}", patches.len());
    for (n, patch) in patches.iter().enumerate() {
        for k in 0..16 {
            let slot = slot_of_line_position(k);
            let p = patch.pts[slot];
            let w = weights.map_or(1.0, |w| w[n][slot]);
            let key = [p.x.to_bits(), p.y.to_bits(), p.z.to_bits(), w.to_bits()];
            let index = *index_of.entry(key).or_insert_with(|| {
                points.push((p, w));
                points.len()
            });
            let sep = if k == 15 { "\n" } else { "," };
            let _ = write!(text, "{index}{sep}");
        }
    }
    let _ = writeln!(text, "{}", points.len());
    for (p, w) in &points {
        if weights.is_some() {
            let _ = writeln!(text, "{},{},{},{w}", p.x, p.y, p.z);
        } else {
            let _ = writeln!(text, "{},{},{}", p.x, p.y, p.z);
        }
    }

    write_atomically(path, text.as_bytes())
}

/// Writes `bytes` through a temporary file and a rename (see `files`).
fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), SceneError> {
    if path.file_name().is_none() {
        return Err(SceneError::invalid(path, "not a file path"));
    }
    crate::files::write_atomic(path, bytes).map_err(|e| SceneError::io(path, e))
}

/// Non-empty lines with their 1-based numbers. Blank lines are only allowed
/// at the end: one in the middle is reported where it is.
struct Lines<'a> {
    inner: std::iter::Enumerate<std::str::Lines<'a>>,
    last: usize,
}

impl<'a> Lines<'a> {
    fn new(text: &'a str) -> Self {
        Lines {
            inner: text.lines().enumerate(),
            last: 0,
        }
    }

    /// The next line, or `None` at the end of the file or when only blank
    /// lines remain. A blank line followed by content is returned as is (and
    /// then fails to parse where it stands).
    fn next(&mut self) -> Option<(usize, &'a str)> {
        let (i, line) = self.inner.next()?;
        if line.trim().is_empty() && self.inner.clone().all(|(_, l)| l.trim().is_empty()) {
            return None;
        }
        self.last = i + 1;
        Some((i + 1, line))
    }

    /// The line number to blame when the file ends too early.
    fn end_line(&self) -> usize {
        self.last + 1
    }
}

fn clip(s: &str) -> String {
    let s = s.trim();
    if s.chars().count() > 40 {
        format!("{}…", s.chars().take(40).collect::<String>())
    } else {
        s.to_string()
    }
}

fn parse_count(path: &Path, line_no: usize, line: &str, what: &str) -> Result<usize, SceneError> {
    line.trim().parse::<usize>().map_err(|_| {
        SceneError::at(
            path,
            line_no,
            format!(
                "expected the {what} (a non-negative integer), found {:?}",
                clip(line)
            ),
        )
    })
}

fn parse_indices(path: &Path, line_no: usize, line: &str) -> Result<[usize; 16], SceneError> {
    let fields: Vec<&str> = line.split(',').collect();
    if fields.len() != 16 {
        return Err(SceneError::at(
            path,
            line_no,
            format!(
                "expected 16 comma-separated point indices, found {}",
                fields.len()
            ),
        ));
    }
    let mut out = [0usize; 16];
    for (k, f) in fields.iter().enumerate() {
        out[k] = f.trim().parse::<usize>().map_err(|_| {
            SceneError::at(
                path,
                line_no,
                format!("index {} is not a point index: {:?}", k + 1, clip(f)),
            )
        })?;
    }
    Ok(out)
}

fn parse_point(
    path: &Path,
    line_no: usize,
    line: &str,
    weighted: bool,
) -> Result<(Vec3, f32), SceneError> {
    let fields: Vec<&str> = line.split(',').collect();
    let want = if weighted { 4 } else { 3 };
    if fields.len() != want {
        return Err(SceneError::at(
            path,
            line_no,
            format!(
                "expected {}, found {} comma-separated fields",
                if weighted { "x,y,z,w" } else { "x,y,z" },
                fields.len()
            ),
        ));
    }
    let mut c = [0f32; 3];
    for (k, f) in fields.iter().take(3).enumerate() {
        let x = f
            .trim()
            .parse::<f32>()
            .map_err(|_| SceneError::at(path, line_no, format!("not a number: {:?}", clip(f))))?;
        if !x.is_finite() {
            return Err(SceneError::at(
                path,
                line_no,
                format!(
                    "coordinate {} is not finite: {:?}",
                    "xyz".as_bytes()[k] as char,
                    clip(f)
                ),
            ));
        }
        // A scene refuses a world coordinate past ±MAX_COORD; saying so
        // here names the line, where the scene could only name the model.
        if x.abs() > MAX_COORD {
            return Err(SceneError::at(
                path,
                line_no,
                format!(
                    "coordinate {} = {:?} is beyond ±{MAX_COORD:e}, the largest a scene accepts \
                     (scale the model down)",
                    "xyz".as_bytes()[k] as char,
                    clip(f)
                ),
            ));
        }
        c[k] = x;
    }
    let mut w = 1.0;
    if weighted {
        let f = fields[3];
        w = f.trim().parse::<f32>().map_err(|_| {
            SceneError::at(
                path,
                line_no,
                format!("weight is not a number: {:?}", clip(f)),
            )
        })?;
        if !weight_ok(w) {
            return Err(SceneError::at(
                path,
                line_no,
                format!(
                    "weight {:?} is outside {MIN_WEIGHT}..={MAX_WEIGHT}",
                    clip(f)
                ),
            ));
        }
    }
    Ok((Vec3::from_array(c), w))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rest of the `.bpt` tests are in `tests/bpt.rs`; this one needs the
    /// declared point list, which the public API does not return.
    #[test]
    fn teapot_loads_with_its_counts() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/models/teapot.bpt");
        let text = std::fs::read_to_string(&path).unwrap();
        let (patches, points) = parse_with_points(&path, &text).unwrap();
        assert_eq!(patches.len(), 32);
        assert_eq!(points.len(), 306);
        assert!(patches.iter().all(|p| p.is_finite()));
        // Spot check: patch 1's first row is indices 1..4, u running along it.
        assert_eq!(patches[0].at(0, 0), Vec3::new(1.4, 0.0, 2.4));
        assert_eq!(patches[0].at(1, 0), Vec3::new(1.4, -0.784, 2.4));
        assert_eq!(patches[0].at(0, 1), Vec3::new(1.3375, 0.0, 2.53125));
    }
}
