//! The window, for real: `view` under Xvfb (lavapipe, validation layer on)
//! opens a window, presents frames, is resized once, saves a screenshot
//! and exits cleanly; the screenshot matches `render` of the same camera.
//!
//! Needs `xvfb-run` (installed by tools/install-deps.sh) unless a display
//! is already there.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use bezier_subdiv::eval::flip::flip;

/// Largest mean FLIP between the window's screenshot and `render` of the
/// same view. Both draw the same sorted ready list through the same
/// pipelines, so they should agree to the pixel; the margin allows a
/// driver's different multisample resolve between a first and a later
/// frame.
const SAME_VIEW_FLIP: f64 = 0.01;

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_bezier-subdiv")
}

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml")
}

fn temp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bezier-view-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn on_path(tool: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(tool).is_file()))
}

/// Runs `view` with `args` on a virtual display (or the one there is).
fn view(args: &[&str]) -> Output {
    let mut cmd = if on_path("xvfb-run") {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 1280x720x24", bin()]);
        c
    } else {
        assert!(
            std::env::var_os("DISPLAY").is_some(),
            "neither xvfb-run nor a DISPLAY: run tools/install-deps.sh"
        );
        Command::new(bin())
    };
    cmd.arg("view").args(args).output().unwrap()
}

fn read_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let img = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    (img.width(), img.height(), img.into_raw())
}

fn render(out: &Path, size: (u32, u32), frame: u32) {
    common::cli::run_ok(
        Command::new(bin())
            .args(["render", "--vk-validation", "--msaa", "4", "--size"])
            .arg(format!("{}x{}", size.0, size.1))
            .args(["--frame", &frame.to_string(), "--scene"])
            .arg(scene())
            .arg("--out")
            .arg(out),
    );
}

/// Frames presented, a resize halfway, a screenshot of the new size that
/// is not blank, equals `render` of the scene camera within
/// [`SAME_VIEW_FLIP`] and differs from another keyframe by far more, and
/// no validation error (the run fails on any).
#[test]
fn the_window_shows_what_render_draws() {
    let dir = temp_dir("shot");
    let shot = dir.join("view.png");
    let run = view(&[
        "--scene",
        scene().to_str().unwrap(),
        "--size",
        "320x200",
        "--frames",
        "6",
        "--resize",
        "288x176",
        "--screenshot",
        shot.to_str().unwrap(),
        "--vk-validation",
    ]);
    let out = String::from_utf8_lossy(&run.stdout);
    common::cli::assert_success(&run, &out);
    assert!(out.contains("view: 6 frames"), "{out}");
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(shot.with_extension("json")).unwrap()).unwrap();
    assert_eq!(stats["source"], "view");
    assert_eq!(
        (stats["width"].as_u64(), stats["height"].as_u64()),
        (Some(288), Some(176))
    );
    assert_eq!(stats["msaa"], 4, "view multisamples by default");
    assert!(stats["triangles"].as_u64().unwrap() > 0, "{stats}");

    let (w, h, pixels) = read_png(&shot);
    assert_eq!((w, h), (288, 176), "the screenshot is at the new size");
    let background = &pixels[..4];
    let drawn = pixels.chunks_exact(4).filter(|p| *p != background).count();
    assert!(
        drawn > (w * h / 20) as usize,
        "the screenshot is blank ({drawn} pixels drawn)"
    );

    let same = dir.join("render.png");
    render(&same, (w, h), 0);
    let (_, _, reference) = read_png(&same);
    let mean = flip(&reference, &pixels, w, h).unwrap().mean;
    println!("FLIP view vs render: {mean:.5}");
    assert!(mean <= SAME_VIEW_FLIP, "FLIP {mean} against render");

    let other = dir.join("other.png");
    render(&other, (w, h), 1);
    let (_, _, moved) = read_png(&other);
    let apart = flip(&moved, &pixels, w, h).unwrap().mean;
    assert!(
        apart > 5.0 * SAME_VIEW_FLIP,
        "another camera scores only {apart}: the threshold proves nothing"
    );
}

/// The other draw path, the other kinds of method (multisampled too), the
/// heat-map views, presenting without vsync and levels of detail start
/// and run clean too.
#[test]
fn other_methods_and_views_run_in_the_window() {
    let dir = temp_dir("methods");
    for (method, draw, shade, vsync, msaa, lod) in [
        ("subdiv-indirect", "fallback", "wedges", "off", "1", "on"),
        ("ground-truth", "auto", "wireframe", "on", "1", "off"),
        ("tess", "auto", "depth", "on", "4", "off"),
    ] {
        let shot = dir.join(format!("{method}.png"));
        let run = view(&[
            "--scene",
            scene().to_str().unwrap(),
            "--size",
            "256x160",
            "--frames",
            "3",
            "--method",
            method,
            "--draw",
            draw,
            "--shade",
            shade,
            "--grid",
            "8",
            "--msaa",
            msaa,
            "--vsync",
            vsync,
            "--lod",
            lod,
            "--screenshot",
            shot.to_str().unwrap(),
            "--vk-validation",
        ]);
        common::cli::assert_success(&run, &format!("{method}: "));
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(shot.with_extension("json")).unwrap()).unwrap();
        assert_eq!(stats["method"], method);
        assert_eq!(stats["shade"], shade);
        // Started with levels, the window's switch for them is there, on.
        let switch = (lod == "on").then_some(true);
        assert_eq!(stats["levels_of_detail_on"], serde_json::json!(switch));
        // FIFO is always there; without vsync anything the display offers.
        if vsync == "on" {
            assert_eq!(stats["present_mode"], "fifo");
        }
    }
}

/// Without a display the command says so, and what to do.
#[test]
fn no_display_is_a_clear_error() {
    let run = Command::new(bin())
        .args(["view", "--scene"])
        .arg(scene())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(
        err.contains("cannot open a window") && err.contains("xvfb-run"),
        "{err}"
    );
}
