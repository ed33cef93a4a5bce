//! `.bpt` reading and writing: the teapot's orientation, round trips, and
//! every refusal with its file and line. (The declared point count is checked
//! by a unit test in `src/scene/bpt.rs`.)
//!
//! The teapot is read from its copy in `scenes/models/`.

mod common;

use std::path::{Path, PathBuf};

use bezier_subdiv::input::limits::MAX_COORD;
use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::scene::bpt::{parse, read, write};
use bezier_subdiv::scene::SceneError;
use glam::{DVec3, Vec3};
fn teapot_path() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("scenes/models");
    let path = dir.join("teapot.bpt");
    assert!(path.exists(), "{} not found ", path.display());
    path
}

fn teapot() -> Vec<BezierPatch> {
    read(&teapot_path()).expect("teapot.bpt loads")
}

fn d(v: Vec3) -> DVec3 {
    DVec3::new(v.x as f64, v.y as f64, v.z as f64)
}

/// A scratch file under the system temp directory, removed on drop.
struct TempFile(PathBuf);

impl TempFile {
    fn new(tag: &str, contents: &str) -> Self {
        let path = std::env::temp_dir().join(format!(
            "bezier-subdiv-bpt-{}-{tag}.bpt",
            std::process::id()
        ));
        std::fs::write(&path, contents).unwrap();
        TempFile(path)
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// One patch on a 4×4 grid of points: valid input to break in one place.
fn one_patch_lines() -> Vec<String> {
    let mut lines = vec!["1".to_string()];
    lines.push(
        (1..=16)
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(","),
    );
    lines.push("16".to_string());
    for j in 0..4 {
        for i in 0..4 {
            lines.push(format!("{i},{j},{}", (i * j) as f32 * 0.25));
        }
    }
    lines
}

/// Reads `text` from a temp file and expects a parse error at `line`
/// whose message contains `needle`; the displayed error names the file.
fn expect_error(tag: &str, text: &str, line: usize, needle: &str) {
    let f = TempFile::new(tag, text);
    let err = read(&f.0).expect_err(tag);
    let shown = err.to_string();
    assert!(
        shown.starts_with(&format!("{}:{line}: ", f.0.display())),
        "{tag}: wanted line {line}, got {shown}"
    );
    assert!(
        shown.contains(needle),
        "{tag}: wanted {needle:?} in {shown}"
    );
    match err {
        SceneError::Parse { path, line: l, .. } => {
            assert_eq!((path, l), (f.0.clone(), line), "{tag}")
        }
        other => panic!("{tag}: expected a parse error, got {other:?}"),
    }
}

fn with_line(index: usize, replacement: &str) -> String {
    let mut lines = one_patch_lines();
    lines[index] = replacement.to_string();
    lines.join("\n") + "\n"
}

/// The body (patches 4–11 of Newell's set: rows of constant v are
/// horizontal arcs around the z axis) has its normals pointing away from
/// the axis under our reading, and towards it under the transposed one.
#[test]
fn teapot_body_normals_point_away_from_axis() {
    let patches = teapot();
    for (k, s) in patches.iter().enumerate().take(12).skip(4) {
        for &(u, v) in &[
            (0.25f32, 0.25f32),
            (0.5, 0.5),
            (0.75, 0.75),
            (0.2, 0.8),
            (0.8, 0.2),
        ] {
            let n = d(s.normal(u, v)).normalize();
            let p = d(s.eval(u, v));
            let radial = DVec3::new(p.x, p.y, 0.0).normalize();
            assert!(
                n.dot(radial) > 0.5,
                "patch {k} at ({u}, {v}): n·r = {}",
                n.dot(radial)
            );
        }
    }
}

/// Signed solid angle of triangle (a, b, c) seen from `p` (Van Oosterom &
/// Strackee); positive when the triangle's normal (b−a)×(c−a) points
/// away from `p`.
fn solid_angle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * num.atan2(den)
}

fn tessellate(patches: &[BezierPatch], n: usize) -> Vec<[DVec3; 3]> {
    let mut tris = Vec::new();
    for s in patches {
        let g = |i: usize, j: usize| d(s.eval(i as f32 / n as f32, j as f32 / n as f32));
        for j in 0..n {
            for i in 0..n {
                // Counter-clockwise in (u, v): triangle normals agree with ∂u × ∂v.
                tris.push([g(i, j), g(i + 1, j), g(i + 1, j + 1)]);
                tris.push([g(i, j), g(i + 1, j + 1), g(i, j + 1)]);
            }
        }
    }
    tris
}

fn winding(tris: &[[DVec3; 3]], p: DVec3) -> f64 {
    let total: f64 = tris.iter().map(|t| solid_angle(p, t[0], t[1], t[2])).sum();
    total / (4.0 * std::f64::consts::PI)
}

/// Every patch, not only the surfaces of revolution: the generalised
/// winding number of the whole (open, self-intersecting) teapot, averaged
/// over two points just either side of the surface along the normal, is
/// about +1/2 when normals point out (inside ≈ 1, outside ≈ 0; where the
/// handle and spout dip into the body, 2 and 1) and −1/2 when they all
/// point in. The jump across the surface alone would not tell the two
/// apart; the mean does. Samples where the normal vanishes are skipped.
#[test]
fn teapot_normals_point_outward() {
    let patches = teapot();
    let tris = tessellate(&patches, 24);
    let delta = 0.02; // the teapot is about 6 units wide
    let mut checked = 0;
    for (k, s) in patches.iter().enumerate() {
        for &u in &[0.25f32, 0.5, 0.75] {
            for &v in &[0.25f32, 0.5, 0.75] {
                let (su, sv) = s.partials(u, v);
                let n = d(su.cross(sv));
                if n.length() <= 1e-6 * d(su).length() * d(sv).length() {
                    continue;
                }
                let n = n.normalize();
                let p = d(s.eval(u, v));
                let mean = 0.5 * (winding(&tris, p - delta * n) + winding(&tris, p + delta * n));
                assert!(
                    mean > 0.3,
                    "patch {k} at ({u}, {v}): mean winding {mean:.3}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(
        checked,
        32 * 9,
        "no sample should be degenerate in the interior"
    );
}

#[test]
fn write_then_read_is_bit_exact_and_keeps_points_shared() {
    let patches = teapot();
    let f = TempFile::new("roundtrip", "");
    write(&f.0, &patches).unwrap();
    let back = read(&f.0).unwrap();
    assert_eq!(back.len(), patches.len());
    for (a, b) in patches.iter().zip(&back) {
        for (p, q) in a.pts.iter().zip(&b.pts) {
            assert_eq!(
                p.to_array().map(f32::to_bits),
                q.to_array().map(f32::to_bits)
            );
        }
    }
    // Shared control points are written once: the file holds exactly the
    // distinct control points (by bits) of the patches.
    let text = std::fs::read_to_string(&f.0).unwrap();
    let written: usize = text
        .lines()
        .nth(1 + patches.len())
        .unwrap()
        .parse()
        .unwrap();
    let mut bits: Vec<[u32; 3]> = patches
        .iter()
        .flat_map(|p| p.pts.iter().map(|q| q.to_array().map(f32::to_bits)))
        .collect();
    bits.sort_unstable();
    bits.dedup();
    assert_eq!(written, bits.len());
    assert!(written < 306);
    // No temporary file is left beside it.
    let dir = f.0.parent().unwrap();
    let stem = format!(".{}.tmp-", f.0.file_name().unwrap().to_string_lossy());
    let leftovers = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().starts_with(&stem))
        .count();
    assert_eq!(leftovers, 0);
}

#[test]
fn write_round_trips_awkward_floats() {
    let mut pts = [Vec3::ZERO; 16];
    let awkward = [
        1.0e-38f32,
        f32::MIN_POSITIVE / 3.0, // subnormal
        // The largest magnitudes a scene accepts (and the f32 just below).
        f32::from_bits(MAX_COORD.to_bits() - 1),
        -MAX_COORD,
        0.1,
        1.0 / 3.0,
        999_999.06, // not exact in f32
        -2.5e-7,
    ];
    for (k, p) in pts.iter_mut().enumerate() {
        *p = Vec3::new(awkward[k % 8], awkward[(k + 3) % 8], k as f32 * 0.1);
    }
    let patch = BezierPatch { pts };
    let f = TempFile::new("awkward", "");
    write(&f.0, &[patch, patch]).unwrap();
    let back = read(&f.0).unwrap();
    assert_eq!(back.len(), 2);
    for b in &back {
        for (p, q) in patch.pts.iter().zip(&b.pts) {
            assert_eq!(
                p.to_array().map(f32::to_bits),
                q.to_array().map(f32::to_bits)
            );
        }
    }
}

#[test]
fn write_refuses_bad_input_and_leaves_nothing() {
    let f = TempFile::new("refused", "");
    let _ = std::fs::remove_file(&f.0);
    assert!(matches!(write(&f.0, &[]), Err(SceneError::Invalid { .. })));
    let mut bad = one_patch();
    bad.pts[5].y = f32::NAN;
    assert!(matches!(
        write(&f.0, &[bad]),
        Err(SceneError::Invalid { .. })
    ));
    let mut far = one_patch();
    far.pts[5].y = 2.0 * MAX_COORD;
    assert!(matches!(
        write(&f.0, &[far]),
        Err(SceneError::Invalid { .. })
    ));
    assert!(!f.0.exists());
    // A directory that does not exist: an I/O error naming the path.
    let missing = std::env::temp_dir().join("bezier-subdiv-no-such-dir/x.bpt");
    match write(&missing, &[one_patch()]) {
        Err(SceneError::Io { path, .. }) => assert_eq!(path, missing),
        other => panic!("expected an I/O error, got {other:?}"),
    }
}

fn one_patch() -> BezierPatch {
    parse(Path::new("inline"), &(one_patch_lines().join("\n") + "\n")).unwrap()[0]
}

#[test]
fn tolerates_whitespace_crlf_and_trailing_blank_lines() {
    let spaced: Vec<String> = one_patch_lines()
        .iter()
        .map(|l| format!("  {}\t", l.replace(',', " , ")))
        .collect();
    let text = spaced.join("\r\n") + "\r\n\r\n  \n\n";
    let a = parse(Path::new("spaced"), &text).unwrap();
    assert_eq!(a, vec![one_patch()]);
    // No final newline at all is fine too.
    let b = parse(Path::new("bare"), &one_patch_lines().join("\n")).unwrap();
    assert_eq!(b, vec![one_patch()]);
}

#[test]
fn negative_zero_is_canonicalised() {
    let text = with_line(3, "-0.0,-0,0");
    let p = parse(Path::new("zeros"), &text).unwrap()[0];
    assert_eq!(p.pts[0].to_array().map(f32::to_bits), [0, 0, 0]);
}

#[test]
fn errors_name_the_file_and_line() {
    let good = one_patch_lines();
    let n = good.len(); // 19 lines
    expect_error("empty", "", 1, "empty file");
    expect_error("blank", " \n\n", 1, "empty file");
    expect_error("count", &with_line(0, "1x"), 1, "patch count");
    expect_error("zero-patches", "0\n", 1, "no patches");
    expect_error("few-indices", &with_line(1, "1,2,3"), 2, "16");
    expect_error(
        "many-indices",
        &with_line(
            1,
            &(1..=17)
                .map(|i| i.to_string())
                .collect::<Vec<_>>()
                .join(","),
        ),
        2,
        "16",
    );
    // A bad index on the index line (line 2).
    for (tag, indices, needle) in [
        (
            "garbled-index",
            "1,2,3,4,5,x,7,8,9,10,11,12,13,14,15,16",
            "\"x\"",
        ),
        (
            "index-zero",
            "0,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16",
            "out of range",
        ),
        (
            "index-high",
            "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,17",
            "out of range",
        ),
        (
            "negative-index",
            "-1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16",
            "\"-1\"",
        ),
    ] {
        expect_error(tag, &with_line(1, indices), 2, needle);
    }
    expect_error("point-count", &with_line(2, "sixteen"), 3, "point count");
    expect_error(
        "garbled-coord",
        &with_line(7, "1.0,abc,2"),
        8,
        "not a number",
    );
    expect_error("two-coords", &with_line(7, "1.0,2.0"), 8, "x,y,z");
    expect_error("nan", &with_line(7, "1.0,NaN,2"), 8, "not finite");
    expect_error("inf", &with_line(9, "inf,0,2"), 10, "not finite");
    expect_error("overflow", &with_line(9, "1e39,0,2"), 10, "not finite");
    expect_error(
        "beyond-scene-limit",
        &with_line(9, "1e30,0,2"),
        10,
        "beyond ±1e6",
    );
    expect_error(
        "just-beyond",
        &with_line(9, "0,-1000000.1,2"),
        10,
        "coordinate y",
    );
    expect_error(
        "trailing",
        &(good.join("\n") + "\n\nhello\n"),
        n + 2,
        "after the last point",
    );
    expect_error("blank-inside", &with_line(1, ""), 2, "16");
    // Truncated: the first missing line is blamed.
    expect_error(
        "no-patch-line",
        "2\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n",
        3,
        "patch line 2 of 2",
    );
    expect_error(
        "no-point-count",
        &(good[..2].join("\n") + "\n\n"),
        3,
        "point count",
    );
    expect_error(
        "few-points",
        &(good[..n - 1].join("\n") + "\n"),
        n,
        "point 16 of 16",
    );
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let path = std::env::temp_dir().join("bezier-subdiv-definitely-missing.bpt");
    let err = read(&path).unwrap_err();
    assert!(matches!(&err, SceneError::Io { path: p, .. } if *p == path));
    assert!(err
        .to_string()
        .contains("bezier-subdiv-definitely-missing.bpt"));
}

/// Garbage in, an error out: no input panics the parser.
#[test]
fn never_panics_on_mangled_input() {
    use rand::{rngs::SmallRng, SeedableRng};
    let base = one_patch_lines().join("\n");
    let alphabet = b"0123456789,.-+eE \n\rNaNinf";
    let mut rng = SmallRng::seed_from_u64(7);
    for _ in 0..5000 {
        let text = common::fuzz::mangle(&mut rng, &base, alphabet);
        if let Ok(p) = parse(Path::new("fuzz"), &text) {
            assert!(p.iter().all(|p| p.is_finite()));
        }
    }
    // A huge promised count does not allocate up front.
    assert!(parse(Path::new("huge"), "18446744073709551615\n").is_err());
}
