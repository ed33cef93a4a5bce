//! Shading under MSAA: the fragment stage must light each pixel at a point
//! inside the triangle it shades.
//!
//! With multisampling a fragment covering only some of a pixel's samples is
//! still shaded once, at the pixel centre unless the inputs are
//! `centroid`: the centre may lie outside the triangle, and the
//! interpolated base-patch (u, v) is then extrapolated, possibly outside the
//! patch domain, where the shading patches give a wild normal. Around the
//! valence-64 pole of `scenes/cages.toml` the triangles are a pixel or less
//! wide, so such pixels are everywhere: dark and off-hue speckles at
//! `--msaa 4` that `--msaa 1` does not show (issue 17, defect 4), in
//! `subdiv` and `ground-truth` alike; at silhouettes, single bright pixels
//! on wedges (issue 21, item 5).
//!
//! The test runs the very command of the report, `render --scene
//! scenes/cages.toml --frame 2 --msaa 4` at its default size, and compares
//! it with the same frame at `--msaa 1`: away from edges in the image
//! (where MSAA legitimately blends) the two must agree within a few levels.
//! Measured on lavapipe at 1920×1080: before the fix 2 pixels of subdiv's
//! image differ by more than 16/255 (44 at most) and 6 of ground-truth's
//! (89 at most), after it none (8 at most).

use std::path::{Path, PathBuf};
use std::process::Command;

/// A pixel of the MSAA image further than this (per channel, 0..255) from
/// the single-sample image, where the latter is flat, is a speckle.
const SPECKLE: i32 = 16;

/// Pixels whose 5×5 neighbourhood in the single-sample image spans more
/// than this are edges (silhouettes, occlusions, the sector ripple's
/// steps): MSAA blends there by design.
const EDGE: i32 = 40;

/// One directory per method: the two tests run at once in one process, and
/// a shared one was emptied by the other test mid-render.
fn temp_dir(method: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "bezier-subdiv-msaa-{method}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// `render --scene scenes/cages.toml --frame 2 --msaa N --method M`.
fn render(dir: &Path, method: &str, msaa: u32, extra: &[&str]) -> image::RgbImage {
    let out = dir.join(format!("{method}-msaa{msaa}.png"));
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cages.toml");
    let run = Command::new(env!("CARGO_BIN_EXE_bezier-subdiv"))
        .arg("render")
        .arg("--scene")
        .arg(scene)
        .args(["--frame", "2", "--method", method])
        .args(["--msaa", &msaa.to_string()])
        .args(extra)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}{}",
        String::from_utf8_lossy(&run.stdout),
        String::from_utf8_lossy(&run.stderr)
    );
    image::open(&out).unwrap().to_rgb8()
}

/// (pixels compared, speckles, largest difference there, first speckle).
fn speckles(
    msaa: &image::RgbImage,
    single: &image::RgbImage,
) -> (usize, usize, i32, Option<(u32, u32)>) {
    let (w, h) = single.dimensions();
    let px = |img: &image::RgbImage, x: i64, y: i64| {
        let (x, y) = (x.clamp(0, w as i64 - 1), y.clamp(0, h as i64 - 1));
        img.get_pixel(x as u32, y as u32).0.map(i32::from)
    };
    let (mut compared, mut bad, mut worst, mut first) = (0, 0, 0, None);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let (mut lo, mut hi) = ([255; 3], [0; 3]);
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let p = px(single, x + dx, y + dy);
                    for c in 0..3 {
                        lo[c] = lo[c].min(p[c]);
                        hi[c] = hi[c].max(p[c]);
                    }
                }
            }
            if (0..3).any(|c| hi[c] - lo[c] > EDGE) {
                continue;
            }
            compared += 1;
            let (a, b) = (px(msaa, x, y), px(single, x, y));
            let d = (0..3).map(|c| (a[c] - b[c]).abs()).max().unwrap();
            worst = worst.max(d);
            if d > SPECKLE {
                bad += 1;
                first.get_or_insert((x as u32, y as u32));
            }
        }
    }
    (compared, bad, worst, first)
}

fn check(method: &str, extra: &[&str]) {
    let dir = temp_dir(method);
    let msaa = render(&dir, method, 4, extra);
    let single = render(&dir, method, 1, extra);
    let (compared, bad, worst, first) = speckles(&msaa, &single);
    println!("{method}: {compared} flat pixels, {bad} speckles, largest difference {worst}/255");
    assert!(compared > 1_000_000, "{method}: the test must see the pole");
    assert_eq!(
        bad,
        0,
        "{method}: {bad} pixels at --msaa 4 differ by more than {SPECKLE}/255 from --msaa 1 \
         (largest {worst}, first at {first:?}; images in {})",
        dir.display()
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn msaa_shades_inside_the_triangle_subdiv() {
    check("subdiv", &[]);
}

#[test]
fn msaa_shades_inside_the_triangle_ground_truth() {
    // At the default grid (64), as reported: 6 speckles before the fix
    // (89/255 at most, one a lit pixel on the helmet's dark silhouette),
    // none after. (At --grid 16 there were none even before.)
    check("ground-truth", &[]);
}
