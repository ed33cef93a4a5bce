//! `bench` on lavapipe: a short run writes every report with the expected
//! columns and medians that agree with its own rows; FLIP of the ground
//! truth against itself is 0; a run stopped part-way (the library's cancel
//! flag, and Ctrl-C on the binary) leaves whole CSV rows and reports of what
//! was measured; bad requests are refused before any GPU work.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};

use bezier_subdiv::commands::bench::{run_on, BenchArgs};
use bezier_subdiv::eval::{flip::flip, ground_truth_image};
use bezier_subdiv::frame::View;

fn scene_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes")
        .join(name)
}

fn out_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("bezier-subdiv-bench-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// 2 methods, one ε and λ, 3 frames, a small image and a coarse reference.
fn short(scene: PathBuf, out: PathBuf) -> BenchArgs {
    BenchArgs {
        methods: Some(vec!["subdiv".into(), "subdiv-indirect".into()]),
        eps: vec![1.0],
        lambda: vec![0.5],
        frames: Some(3),
        size: (128, 72),
        warmup: Some(1),
        flip_frames: Some(2),
        grid: 4,
        ..BenchArgs::new(scene, out)
    }
}

/// Rows of a CSV file (quoted cells with doubled quotes, as written).
fn csv(path: &Path) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(
        text.ends_with('\n'),
        "{}: the last row is whole",
        path.display()
    );
    text.lines()
        .map(|line| {
            let (mut cells, mut cell, mut quoted) = (Vec::new(), String::new(), false);
            let mut chars = line.chars().peekable();
            while let Some(c) = chars.next() {
                match (c, quoted) {
                    ('"', true) if chars.peek() == Some(&'"') => {
                        cell.push('"');
                        chars.next();
                    }
                    ('"', _) => quoted = !quoted,
                    (',', false) => cells.push(std::mem::take(&mut cell)),
                    _ => cell.push(c),
                }
            }
            cells.push(cell);
            cells
        })
        .collect()
}

fn column(rows: &[Vec<String>], name: &str) -> usize {
    rows[0]
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name} in {:?}", rows[0]))
}

#[test]
fn a_short_bench_writes_every_report() {
    let gpu = common::gpu();
    let out = out_dir("short");
    let args = short(scene_file("teapot.toml"), out.clone());
    let cancel = AtomicBool::new(false);
    let (mut last, mut total) = (0, 0);
    let done = run_on(&gpu.arc(), &args, &cancel, &mut |s| {
        (last, total) = (s.done, s.total);
    })
    .unwrap();
    assert_eq!(done.stopped, None);
    assert_eq!((done.rows, done.flips), (6, 4));
    assert_eq!(last, total, "the progress reaches its end");

    let rows = csv(&out.join("frames.csv"));
    assert_eq!(rows.len(), 1 + 6);
    for name in [
        "method",
        "draw_path",
        "eps",
        "lambda",
        "frame",
        "t",
        "triangles",
        "culled_patches",
        "wedge_share",
        "gpu_ms.frame",
        "gpu_ms.subdivide",
        "gpu_ms.draw",
        "memory_bytes.node_memory",
        "method_stats.ready_quads",
        "method_stats.max_depth",
        "method_stats.rounds",
        "method_stats.chunk_nodes",
    ] {
        column(&rows, name);
    }
    assert!(rows.iter().all(|r| r.len() == rows[0].len()));
    let (m, tri, ms) = (
        column(&rows, "method"),
        column(&rows, "triangles"),
        column(&rows, "gpu_ms.frame"),
    );
    // Frame by frame, every configuration in turn.
    let methods: Vec<&str> = rows[1..].iter().map(|r| r[m].as_str()).collect();
    assert_eq!(methods, ["subdiv", "subdiv-indirect"].repeat(3));
    let frame = column(&rows, "frame");
    let frames: Vec<&str> = rows[1..].iter().map(|r| r[frame].as_str()).collect();
    assert_eq!(frames, ["0", "0", "1", "1", "2", "2"]);

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["complete"], true);
    assert_eq!(summary["patches"], 32);
    let configs = summary["configs"].as_array().unwrap();
    assert_eq!(configs.len(), 2);
    for c in configs {
        // The medians are those of the rows in frames.csv.
        let mine: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[m] == c["method"]).collect();
        let mut t: Vec<f64> = mine.iter().map(|r| r[tri].parse().unwrap()).collect();
        let mut f: Vec<f64> = mine.iter().map(|r| r[ms].parse().unwrap()).collect();
        t.sort_by(f64::total_cmp);
        f.sort_by(f64::total_cmp);
        assert_eq!(c["triangles"].as_f64(), Some(t[1]));
        assert_eq!(c["gpu_ms"]["frame"].as_f64(), Some(f[1]));
        assert_eq!(c["min"]["gpu_ms"]["frame"].as_f64(), Some(f[0]));
        assert_eq!(c["max"]["gpu_ms"]["frame"].as_f64(), Some(f[2]));
        assert_eq!(c["frames"], 3);
        assert!(c["memory_bytes"]["base_patches"].as_f64().unwrap() > 0.0);
        assert!(c["method_stats"]["ready_quads"].as_f64().unwrap() > 0.0);
        assert_eq!(c["flip"]["perspectives"].as_array().unwrap().len(), 2);
        let flip = c["flip"]["median"].as_f64().unwrap();
        assert!(flip > 0.0 && flip < 0.5, "{flip}");
    }

    let flips = csv(&out.join("flip.csv"));
    assert_eq!(flips.len(), 1 + 4);
    let (img, heat) = (column(&flips, "image"), column(&flips, "heat_map"));
    column(&flips, "flip_mean");
    for r in &flips[1..] {
        for f in [&r[img], &r[heat]] {
            let png = image::open(out.join(f)).unwrap();
            assert_eq!((png.width(), png.height()), (128, 72), "{f}");
        }
    }
    for f in ["flip/ground-truth-p1.png", "flip/ground-truth-p2.png"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    for f in ["frame_time.png", "triangles.png", "flip_vs_triangles.png"] {
        let png = image::open(out.join(f)).unwrap();
        assert!(png.width() >= 800, "{f}");
    }

    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    for want in [
        "## Table 1",
        "## Table 2",
        "## GPU time per pass",
        "## Memory by purpose",
        "## Targets",
        "| run | complete |",
        "128×72",
        "32 base patches",
        "frame_time.png",
        bezier_subdiv::commands::render::commit_id(),
        &gpu.info().name,
    ] {
        assert!(md.contains(want), "report.md lacks {want:?}:\n{md}");
    }
    // Table 2's cells are the summary's medians.
    let t0 = configs[0]["triangles"].as_f64().unwrap() as u64;
    assert!(md.contains(&bezier_subdiv::figures::thousands(t0)), "{md}");
    let _ = std::fs::remove_dir_all(&out);
    gpu.finish();
}

#[test]
fn the_ground_truth_against_itself_is_zero() {
    let gpu = common::gpu();
    let (scene, geo) = common::scene("teapot.toml");
    let size = (160, 90);
    let mut options =
        bezier_subdiv::methods::MethodOptions::new(bezier_subdiv::draw::DrawPath::Fallback);
    options.per_method.ground_truth.grid = 8;
    let mut r = common::renderer(&gpu, &geo, "subdiv", size, options);
    let view = View::new(
        &scene.camera,
        size,
        2.0,
        0.0,
        bezier_subdiv::constants::SHADE_NORMAL,
    );
    let a = ground_truth_image(&mut r, &view).unwrap();
    let b = ground_truth_image(&mut r, &view).unwrap();
    assert_eq!(flip(&a, &b, size.0, size.1).unwrap().mean, 0.0);
    // Not zero for everything: a coarse subdivision differs from it.
    r.render(&view).unwrap();
    let coarse = r.read_image().unwrap();
    assert!(flip(&a, &coarse, size.0, size.1).unwrap().mean > 0.0);
    gpu.finish();
}

#[test]
fn a_cancelled_run_leaves_whole_rows_and_reports() {
    let gpu = common::gpu();
    let out = out_dir("cancel");
    std::fs::create_dir_all(&out).unwrap();
    // No camera path or orbit: the bench orbits the bounding box.
    let scene = out.join("bare.toml");
    std::fs::write(
        &scene,
        format!(
            "[camera]\nposition = [6.0, -7.0, 5.0]\ntarget = [0.0, 0.0, 1.0]\n[[model]]\nfile = \"{}\"\ntwo_sided = true\n",
            scene_file("models/teapot.bpt").display()
        ),
    )
    .unwrap();
    let mut args = short(scene, out.clone());
    args.frames = Some(10);
    let cancel = AtomicBool::new(false);
    let done = run_on(&gpu.arc(), &args, &cancel, &mut |s| {
        if s.rows >= 4 {
            cancel.store(true, Ordering::Relaxed);
        }
    })
    .unwrap();
    assert_eq!(done.stopped.as_deref(), Some("interrupted"));
    assert_eq!(done.rows, 4);
    let rows = csv(&out.join("frames.csv"));
    assert_eq!(rows.len(), 1 + 4);
    assert!(rows.iter().all(|r| r.len() == rows[0].len()));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["complete"], false);
    assert!(summary["path"].as_str().unwrap().contains("bounding box"));
    // Both configurations, with the two frames each had.
    let configs = summary["configs"].as_array().unwrap();
    assert_eq!(configs.len(), 2);
    assert!(configs.iter().all(|c| c["frames"] == 2));
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("stopped early"), "{md}");
    for f in [
        "flip.csv",
        "frame_time.png",
        "triangles.png",
        "flip_vs_triangles.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let _ = std::fs::remove_dir_all(&out);
    gpu.finish();
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bezier-subdiv"))
}

#[test]
fn bad_requests_are_refused_before_gpu_work() {
    let out = out_dir("refuse");
    let cases: [(&[&str], &str); 10] = [
        (&["--eps", "1,-1"], "--eps: -1 is not a positive number"),
        (&["--eps", "1,1"], "--eps: 1 is given twice"),
        (&["--eps", "one"], "invalid value 'one'"),
        (&["--lambda", "0,2"], "--lambda: 2 is not in [0, 1]"),
        (&["--methods", "subdiv,magic"], "unknown method `magic`"),
        (&["--methods", "subdiv,subdiv"], "subdiv is given twice"),
        (&["--frames", "0"], "--frames must be at least 1"),
        (&["--grid", "3"], "--grid"),
        (&["--out", "/proc/bench"], "cannot write to /proc/bench"),
        (
            &["--scene", "/nonexistent/scene.toml"],
            "/nonexistent/scene.toml",
        ),
    ];
    for (args, want) in cases {
        let mut cmd = bin();
        cmd.arg("bench").args(args);
        if !args.contains(&"--scene") {
            cmd.arg("--scene").arg(scene_file("teapot.toml"));
        }
        if !args.contains(&"--out") {
            cmd.arg("--out").arg(&out);
        }
        let run = cmd
            // No Vulkan driver: a request that got as far as the GPU would
            // fail with another message.
            .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
            .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let run = bin()
        .args(["bench", "--out"])
        .arg(&out)
        .env("BEZIER_SUBDIV_FONT", "/nonexistent/font.ttf")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(
        !run.status.success() && err.contains("plots need a TrueType font"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn ctrl_c_stops_the_binary_with_its_reports_written() {
    let out = out_dir("ctrl-c");
    let child = bin()
        .arg("bench")
        .args(common::cli::BENCH_ONE_POINT)
        .args([
            "--frames",
            "100000",
            "--warmup",
            "0",
            "--flip-frames",
            "1",
            "--grid",
            "4",
            "--size",
            "64x36",
        ])
        .arg("--scene")
        .arg(scene_file("teapot.toml"))
        .arg("--out")
        .arg(&out)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let frames = out.join("frames.csv");
    let start = std::time::Instant::now();
    while std::fs::read_to_string(&frames).map_or(0, |t| t.lines().count()) < 4 {
        assert!(
            start.elapsed().as_secs() < 120,
            "no frames after two minutes"
        );
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let run = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(err.contains("stopped early (interrupted)"), "{err}");
    let rows = csv(&frames);
    assert!(rows.len() >= 4 && rows.iter().all(|r| r.len() == rows[0].len()));
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("stopped early"), "{md}");
    let _ = std::fs::remove_dir_all(&out);
}

/// Against `tess` over several ε and λ: a method that ignores λ runs once
/// per ε (its λ cell empty), perspectives count from 1 as the file names
/// do, the report compares at equal error, a λ sweep draws Fig. 6, and
/// two methods with identical curves both show in the plot.
#[test]
fn a_bench_against_tess_compares_at_equal_error() {
    let gpu = common::gpu();
    let out = out_dir("pareto");
    let args = BenchArgs {
        methods: Some(vec![
            "subdiv".into(),
            "subdiv-indirect".into(),
            "tess".into(),
        ]),
        eps: vec![0.5, 1.0, 2.0, 4.0],
        lambda: vec![0.0, 0.5, 1.0],
        frames: Some(1),
        size: (160, 90),
        warmup: Some(0),
        flip_frames: Some(1),
        grid: 8,
        ..BenchArgs::new(scene_file("teapot.toml"), out.clone())
    };
    let cancel = AtomicBool::new(false);
    let done = run_on(&gpu.arc(), &args, &cancel, &mut |_| {}).unwrap();
    assert_eq!(done.stopped, None);
    // 2 methods × 3 λ × 4 ε, and tess once per ε.
    assert_eq!(done.rows, 2 * 3 * 4 + 4);
    let rows = csv(&out.join("frames.csv"));
    let (m, l) = (column(&rows, "method"), column(&rows, "lambda"));
    let tess: Vec<&Vec<String>> = rows[1..].iter().filter(|r| r[m] == "tess").collect();
    assert_eq!(tess.len(), 4);
    assert!(tess.iter().all(|r| r[l].is_empty()), "tess ignores λ");
    let flips = csv(&out.join("flip.csv"));
    let (p, img) = (column(&flips, "perspective"), column(&flips, "image"));
    for r in &flips[1..] {
        assert_eq!(r[p], "1");
        assert!(r[img].ends_with("-p1.png"), "{}", r[img]);
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(
        md.contains("## At equal image error (against `tess`)"),
        "{md}"
    );
    assert!(md.contains("| subdiv λ=0.5 | 1 |"), "{md}");
    assert!(md.contains("- **subdiv λ=0.5**"), "{md}");
    assert!(
        md.contains("| ε | | tess | subdiv, λ = 1 | subdiv-indirect, λ = 1 | subdiv, λ = 0.5 |"),
        "tess has one column in Table 2:\n{md}"
    );
    for f in [
        "flip_vs_triangles.png",
        "flip_vs_time.png",
        "geometric_vs_triangles.png",
        "lambda.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    // Beside FLIP: the geometric error, each method's ε against it, and
    // where the image error lies (per model: the teapot alone here).
    for want in [
        "## At equal geometric error (against `tess`)",
        "## At equal geometric error, 99th percentile (against `tess`)",
        "## Geometric error and each method's ε",
        "## Where the image error lies (ε = 1)",
        "teapot 100 %",
    ] {
        assert!(md.contains(want), "report.md lacks {want:?}:\n{md}");
    }
    let (geo, sil) = (
        column(&flips, "geo_p99_px"),
        column(&flips, "silhouette_diff_px"),
    );
    for r in &flips[1..] {
        let p99: f64 = r[geo].parse().unwrap();
        assert!(p99 > 0.0 && p99 < 20.0, "{p99}");
        assert!(r[sil].parse::<u64>().is_ok());
    }
    let per_model = csv(&out.join("breakdown.csv"));
    assert_eq!(per_model.len(), flips.len(), "one model, one row per image");
    assert!(per_model[1..]
        .iter()
        .all(|r| r[column(&per_model, "model")] == "teapot"));
    // subdiv and subdiv-indirect draw the same triangles, so their curves
    // coincide; both colours must still show.
    let png = image::open(out.join("flip_vs_triangles.png"))
        .unwrap()
        .to_rgb8();
    // Inside the panel, not the legend column on the right.
    let panel_width = png.width() - 300;
    let count = |c: [u8; 3]| {
        png.enumerate_pixels()
            .filter(|(x, _, p)| *x < panel_width && p.0 == c)
            .count()
    };
    let (blue, red) = (count([31, 119, 180]), count([214, 39, 40]));
    assert!(
        blue > 500 && red > 500,
        "subdiv {blue} px, subdiv-indirect {red} px"
    );
    let _ = std::fs::remove_dir_all(&out);
    gpu.finish();
}

/// A method that cannot draw the scene refuses the run before anything is
/// written: no output directory, no empty `flip/`.
#[test]
fn a_refused_method_leaves_nothing_behind() {
    let gpu = common::gpu();
    let out = out_dir("refused");
    let mut args = short(scene_file("rational.toml"), out.clone());
    args.methods = Some(vec!["subdiv".into(), "tess".into()]);
    let cancel = AtomicBool::new(false);
    let e = run_on(&gpu.arc(), &args, &cancel, &mut |_| {}).unwrap_err();
    assert!(
        format!("{e:#}").contains("cannot draw rational patches"),
        "{e:#}"
    );
    assert!(!out.exists(), "{} was created", out.display());
    gpu.finish();
}
