//! The command line as a user meets it: `import` with its sidecar, refusals
//! that name the file and exit non-zero, and `render`'s checks that run
//! before any GPU work.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::cli::bin;

/// `import` of `file`, ready for more arguments.
fn import(file: &Path) -> Command {
    let mut cmd = bin();
    cmd.arg("import").arg(file);
    cmd
}

/// A test's scratch folder, removed when the test passes (each run left
/// about 100 MB in the system's temp folder before) and kept, with its
/// path printed, when it fails.
struct TempDir(PathBuf);

impl std::ops::Deref for TempDir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl AsRef<Path> for TempDir {
    fn as_ref(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        if std::thread::panicking() {
            eprintln!("kept for a look: {}", self.0.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

fn temp_dir(tag: &str) -> TempDir {
    let d = std::env::temp_dir().join(format!("bezier-subdiv-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    TempDir(d)
}

fn model(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/models")
        .join(name)
}

#[test]
fn import_writes_patches_and_sidecar() {
    let dir = temp_dir("import");
    let out = dir.join("pawn.bpt");
    let run = import(&model("catmark_pawn.obj"))
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&run.stdout);
    common::cli::assert_success(&run, &text);
    assert!(text.contains("patches         588"), "{text}");
    assert!(
        text.contains("creases         0 infinitely sharp edges, 120 semi-sharp"),
        "the crease tags are read: {text}"
    );
    assert!(
        text.contains("boundary rule   edge-and-corner (default"),
        "{text}"
    );
    // The written patches read back as the same model.
    let again = import(&out).output().unwrap();
    assert!(again.status.success());
    assert!(String::from_utf8_lossy(&again.stdout).contains("patches         588"));
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("pawn.bpt.json")).unwrap()).unwrap();
    let entries = side["patches"].as_array().unwrap();
    assert_eq!(entries.len(), 588);
    assert_eq!(entries[0]["face"], 0);
    assert_eq!(
        entries[0]["corners_uv"],
        serde_json::json!([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    );
    assert_eq!(entries[587]["face"], 587);
    // Which rule each patch used, and the boundary rule of the whole cage.
    assert_eq!(side["boundary"]["rule"], "edge-and-corner");
    assert_eq!(side["boundary"]["from"], "default");
    for e in entries {
        let rule = e["rule"].as_str().unwrap();
        assert!(
            [
                "regular",
                "crease",
                "corner",
                "extraordinary",
                "irregular-sharp",
                "semi-sharp"
            ]
            .contains(&rule),
            "{rule}"
        );
        assert_eq!(
            e["exact"],
            rule == "regular" || rule == "crease" || rule == "corner"
        );
        assert_eq!(e["corners"].as_array().unwrap().len(), 4);
    }
    let semi = entries.iter().filter(|e| e["rule"] == "semi-sharp").count();
    assert!(semi > 0);
    // Nothing else left behind (no temporary files).
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn refused_files_name_themselves_and_fail() {
    let dir = temp_dir("refuse");
    let bad = dir.join("broken.bpt");
    std::fs::write(&bad, "2\n1,2,3\n").unwrap();
    for file in [bad.clone(), dir.join("missing.obj"), dir.join("model.stl")] {
        let run = import(&file).output().unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success());
        assert!(err.contains(&*file.to_string_lossy()), "{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let run = import(&bad).output().unwrap();
    assert!(
        String::from_utf8_lossy(&run.stderr).contains("broken.bpt:2"),
        "the line is named"
    );
    // Coordinates a scene would refuse are refused here, with the line; the
    // limit itself is accepted.
    let patch = (1..=16)
        .map(|i| i.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let points = |far: &str| {
        let mut p: Vec<String> = (0..16).map(|i| format!("{},{},0", i % 4, i / 4)).collect();
        p[5] = far.into();
        format!("1\n{patch}\n16\n{}\n", p.join("\n"))
    };
    let far = dir.join("far.bpt");
    std::fs::write(&far, points("1e30,0,0")).unwrap();
    let run = import(&far).output().unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(err.contains("far.bpt:9: coordinate x"), "{err}");
    assert!(err.contains("beyond ±1e6"), "{err}");
    std::fs::write(&far, points("1000000,0,-1000000")).unwrap();
    common::cli::run_ok(&mut import(&far));
    // The same coordinate in a cage: refused at its line too, and with
    // --out nothing is written, not even a temporary file (it was accepted,
    // and the writer then failed naming its temporary file).
    let cage = dir.join("far.obj");
    std::fs::write(&cage, "v 0 0 0\nv 1 0 0\nv 1e30 1 0\nv 0 1 0\nf 1 2 3 4\n").unwrap();
    let out = dir.join("far-out.bpt");
    let run = import(&cage).arg("--out").arg(&out).output().unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(
        err.contains("far.obj:3: ") && err.contains("beyond ±1e6"),
        "{err}"
    );
    assert!(!err.contains(".tmp-"), "{err}");
    let left: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.contains("far-out"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

#[test]
fn render_refuses_bad_requests_before_gpu_work() {
    let dir = temp_dir("render");
    let cases: [(&[&str], &str); 6] = [
        (&["--eps", "0"], "--eps must be a positive number"),
        // A negative number reaches the same check (clap took "-1" for a
        // flag: "unexpected argument '-1' found").
        (&["--eps", "-1"], "--eps must be a positive number"),
        // A sample count the device does not offer is not a missing
        // requirement: say what it offers.
        (
            &["--msaa", "8", "--size", "64x64"],
            "does not offer 8 samples per pixel",
        ),
        (&["--method", "magic"], "unknown method"),
        (&["--out", "/nonexistent-dir/x.png"], "does not exist"),
        (&["--frame", "99"], "frame 99 does not exist"),
    ];
    for (args, want) in cases {
        let run = bin()
            .arg("render")
            .arg("--scene")
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml"))
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{args:?}");
        assert!(err.contains(want), "{args:?}: {err}");
    }
    let scene = dir.join("bad.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [1.0, 2.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov = 3\n",
    )
    .unwrap();
    let run = bin()
        .arg("render")
        .arg("--scene")
        .arg(&scene)
        .current_dir(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(err.contains("bad.toml:4"), "{err}");
    assert!(!dir.join("out").exists(), "nothing written on failure");
}

/// `bench --occlusion on|off` and `--lod on|off` are values, not switches:
/// clap took a `bool` field for a switch and then refused its own `true`
/// ("invalid value 'true' for '--occlusion'") until the flags said
/// `ArgAction::Set`. Each reaches the run's own checks (here: the frame
/// count), whatever its value.
#[test]
fn on_off_flags_take_their_values() {
    let dir = temp_dir("on-off");
    for flag in ["--occlusion", "--lod"] {
        for value in ["on", "off"] {
            let run = bin()
                .args(["bench", "--scene"])
                .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml"))
                .args([flag, value, "--frames", "0", "--out"])
                .arg(dir.join("out"))
                .current_dir(&dir)
                .output()
                .unwrap();
            let err = String::from_utf8_lossy(&run.stderr);
            assert!(!run.status.success(), "{flag} {value}");
            assert!(
                err.contains("--frames must be at least 1"),
                "{flag} {value}: {err}"
            );
        }
    }
}

/// The levels' shading bound is an angle: refused outside (0, 180] with
/// the reason, taken inside (the run then stops at `--frames 0`).
#[test]
fn lod_shading_takes_an_angle() {
    let dir = temp_dir("lod-shading");
    for (value, says) in [
        ("0", "above 0 and at most 180"),
        ("200", "above 0 and at most 180"),
        ("wide", "an angle in degrees"),
        ("12.5", "--frames must be at least 1"),
    ] {
        let run = bin()
            .args(["bench", "--scene"])
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml"))
            .args([
                "--lod",
                "on",
                "--lod-shading",
                value,
                "--frames",
                "0",
                "--out",
            ])
            .arg(dir.join("out"))
            .current_dir(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(!run.status.success(), "{value}");
        assert!(err.contains(says), "{value}: {err}");
    }
}

/// Levels are made once and read back after: a second `render --lod on`
/// of the same scene reads every model's levels from the cache
/// (`BEZIER_SUBDIV_CACHE`) and draws the same image.
#[test]
fn levels_are_read_back_from_the_cache() {
    let dir = temp_dir("lod-cache");
    let render = |out: &str| {
        let run = bin()
            .args(["render", "--scene"])
            .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml"))
            .args(["--size", "128x96", "--lod", "on", "--out", out])
            .env("BEZIER_SUBDIV_CACHE", dir.join("cache"))
            .current_dir(&dir)
            .output()
            .unwrap();
        common::cli::assert_success(&run, "render --lod on: ");
        String::from_utf8_lossy(&run.stderr).into_owned()
    };
    let first = render("a.png");
    assert!(
        first.contains("0 models' levels read, 1 made and stored"),
        "{first}"
    );
    let second = render("b.png");
    assert!(
        second.contains("1 models' levels read, 0 made and stored"),
        "{second}"
    );
    assert_eq!(
        std::fs::read(dir.join("a.png")).unwrap(),
        std::fs::read(dir.join("b.png")).unwrap()
    );
}

/// Runs `cmd`, again while the executable is "busy": a freshly copied
/// binary can be, for as long as a process forked meanwhile by another
/// test thread still holds the copy's write handle (until it execs).
fn output_when_free(cmd: &mut Command) -> std::process::Output {
    for _ in 0..100 {
        match cmd.output() {
            Err(e) if e.kind() == std::io::ErrorKind::ExecutableFileBusy => {
                std::thread::sleep(std::time::Duration::from_millis(20));
            }
            other => return other.unwrap(),
        }
    }
    panic!("the copied binary stayed busy")
}

/// A copy of the binary, run from an unrelated directory without the SPIR-V
/// override, renders with both kinds of method and records the commit it
/// was built from.
#[test]
fn copied_binary_renders_anywhere() {
    let dir = temp_dir("copied");
    let copy = dir.join("bezier-subdiv");
    std::fs::copy(env!("CARGO_BIN_EXE_bezier-subdiv"), &copy).unwrap();
    let elsewhere = dir.join("cwd");
    std::fs::create_dir_all(&elsewhere).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml");
    for method in ["subdiv", "ground-truth"] {
        let out = dir.join(format!("{method}.png"));
        let run = output_when_free(
            Command::new(&copy)
                .args([
                    "render", "--size", "96x64", "--grid", "8", "--method", method,
                ])
                .arg("--scene")
                .arg(&scene)
                .arg("--out")
                .arg(&out)
                .env_remove("BEZIER_SUBDIV_SPIRV_DIR")
                .current_dir(&elsewhere),
        );
        let err = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{method}: {err}");
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.with_extension("json")).unwrap()).unwrap();
        assert_eq!(stats["method"], method);
        assert!(stats["triangles"].as_u64().unwrap() > 0, "{stats}");
        // The scene's memory: control points and flags, shading patches.
        let patches = stats["patches"].as_u64().unwrap();
        assert_eq!(patches, 32);
        for (key, per_patch) in [("base_patches", 196), ("shading_patches", 288)] {
            assert_eq!(stats["memory_per_patch_bytes"][key], per_patch, "{key}");
            assert_eq!(stats["memory_bytes"][key], patches * per_patch, "{key}");
        }
        let commit = stats["commit"].as_str().unwrap();
        let head = Command::new("git")
            .args(["rev-parse", "--short=12", "HEAD"])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string());
        if let Some(head) = head {
            assert!(
                commit.starts_with(&head),
                "built from {commit}, HEAD is {head}"
            );
        }
    }
    assert!(
        !elsewhere.join("out").exists(),
        "nothing written beside the cwd"
    );
}

/// `render --flip` writes the mean FLIP against the ground truth of the
/// same view into the stats and the heat map beside the image; the ground
/// truth against itself scores 0; with the heat map's place blocked nothing
/// at all is written.
#[test]
fn render_flip_writes_mean_and_heat_map() {
    let dir = temp_dir("flip");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml");
    let render = |method: &str, out: &Path| {
        bin()
            .args([
                "render", "--size", "128x96", "--grid", "16", "--flip", "--method", method,
            ])
            .arg("--scene")
            .arg(&scene)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap()
    };
    for (method, zero) in [("tess", false), ("ground-truth", true)] {
        let out = dir.join(format!("{method}.png"));
        let run = render(method, &out);
        let text = String::from_utf8_lossy(&run.stdout);
        common::cli::assert_success(&run, &format!("{method}: "));
        assert!(text.contains("FLIP mean"), "{text}");
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.with_extension("json")).unwrap()).unwrap();
        let mean = stats["flip_mean"].as_f64().unwrap();
        assert_eq!(stats["flip_reference"]["grid"], 16);
        assert_eq!(mean == 0.0, zero, "{method}: FLIP {mean}");
        assert!((0.0..0.2).contains(&mean), "{method}: FLIP {mean}");
        // The geometric error beside it: zero for the reference itself,
        // within a pixel (ε = 1) for tess, measured on real pixels.
        let g = &stats["geometric_error"];
        let p99 = g["p99_px"].as_f64().unwrap();
        assert!(g["pixels"].as_u64().unwrap() > 500, "{method}: {g}");
        assert_eq!(p99 == 0.0, zero, "{method}: {g}");
        assert!(p99 <= 1.0, "{method}: geometric error beyond ε: {g}");
        assert!(text.contains("geometric error"), "{text}");
        let heat = image::open(dir.join(format!("{method}.flip.png"))).unwrap();
        assert_eq!((heat.width(), heat.height()), (128, 96));
    }
    // A directory where the heat map goes: refused before any GPU work.
    let out = dir.join("blocked.png");
    std::fs::create_dir_all(dir.join("blocked.flip.png")).unwrap();
    let run = render("tess", &out);
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("blocked.flip.png"));
    assert!(!out.exists() && !out.with_extension("json").exists());
}

#[test]
fn ground_truth_grid_must_be_a_power_of_two() {
    let run = bin()
        .args(["render", "--method", "ground-truth", "--grid", "48"])
        .arg("--scene")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert!(
        err.contains("--grid") && err.contains("power of two"),
        "{err}"
    );
}

/// Many workgroups on many worker threads, so lanes of different
/// workgroups really interleave (lavapipe runs a workgroup per thread):
/// both subdivision methods still equal the oracle; the persistent level
/// kernel keeps only the workgroups that run at once and issues far fewer
/// than one global atomic per node; the queue kernel's figures stay honest
/// (a peak within the capacity, no spills from a queue that was never full).
#[test]
fn interleaved_workgroups_equal_the_oracle() {
    let dir = temp_dir("interleave");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/kitchen.toml");
    for method in ["subdiv", "subdiv-indirect"] {
        let run = bin()
            .args([
                "validate",
                "--size",
                "320x180",
                "--groups",
                "16",
                "--no-holes",
            ])
            .args(["--frame", "0", "--method", method])
            .arg("--scene")
            .arg(&scene)
            .env("LP_NUM_THREADS", "8")
            .output()
            .unwrap();
        let out = String::from_utf8_lossy(&run.stdout);
        common::cli::assert_success(&run, &format!("{method}: {out}"));
        // Ready set, positions, reordering, occlusion culling.
        assert!(out.contains("all 4 checks passed"), "{out}");
    }
    let render = |kernel: &str| {
        let out = dir.join(format!("k-{kernel}.png"));
        common::cli::run_ok(
            bin()
                .args([
                    "render", "--size", "320x180", "--groups", "32", "--repeat", "2", "--kernel",
                    kernel,
                ])
                .arg("--scene")
                .arg(&scene)
                .arg("--out")
                .arg(&out)
                .env("LP_NUM_THREADS", "8"),
        );
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.with_extension("json")).unwrap()).unwrap();
        assert_eq!(stats["repeat"], 2);
        stats["method_stats"].clone()
    };
    let m = render("levels");
    println!("{m}");
    assert_eq!(m["kernel"], "levels");
    assert_eq!(m["workgroups"], 32);
    let joined = m["workgroups_joined"].as_u64().unwrap();
    assert!((1..=8).contains(&joined), "{m}");
    // The schedule's atomics (arrivals, releases) per node; occlusion
    // culling's visibility bits take about one per cluster it draws.
    let nodes = m["nodes_processed"].as_f64().unwrap();
    let visibility = m["visibility_atomics"].as_f64().unwrap();
    let schedule = m["global_atomics"].as_f64().unwrap() - visibility;
    assert!(schedule / nodes <= 0.01, "{m}");
    let clusters = m["clusters_early"].as_f64().unwrap() + m["clusters_late"].as_f64().unwrap();
    assert!(visibility <= 2.0 * clusters, "{m}");
    let m = render("queue");
    println!("{m}");
    let (peak, cap) = (
        m["queue_peak_items"].as_u64().unwrap(),
        m["queue_capacity_items"].as_u64().unwrap(),
    );
    assert!(peak <= cap, "peak {peak} of a {cap}-entry queue");
    assert_eq!(m["queue_spills"], 0, "{m}");
    assert_eq!(m["workgroups"], 32);
    assert!(
        m["global_atomics_per_node"].as_f64().unwrap() <= 0.25,
        "{m}"
    );
}

/// Each cause is printed once: a binary file, a missing file, a broken model
/// of a scene (whose path the message names once).
#[test]
fn errors_say_each_thing_once() {
    let dir = temp_dir("once");
    let binary = dir.join("patches.bpt");
    std::fs::write(&binary, [0x32u8, 0x0a, 0xff, 0xfe, 0x00, 0x31]).unwrap();
    let run = import(&binary).output().unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert_eq!(err.matches("not a text file").count(), 1, "{err}");
    assert!(
        err.contains("patches.bpt:2: "),
        "the line of the first bad byte: {err}"
    );
    assert!(!err.contains("stream did not contain valid UTF-8"), "{err}");

    let run = import(&dir.join("gone.obj")).output().unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(err.matches("No such file or directory").count(), 1, "{err}");

    let scene = dir.join("broken.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [5.0, -5.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\n[[model]]\nname = \"bad\"\nfile = \"bad.obj\"\n",
    )
    .unwrap();
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 9\n").unwrap();
    let run = bin()
        .arg("stats")
        .arg("--scene")
        .arg(&scene)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!run.status.success());
    assert_eq!(err.matches("broken.toml").count(), 1, "{err}");
    assert!(err.contains("model 'bad': "), "{err}");
    assert!(err.contains("bad.obj:3: "), "{err}");
    assert!(err.contains("the file has 2 vertices"), "{err}");
}

/// `import --boundary` applies to cages without their own tag.
#[test]
fn import_takes_a_boundary_rule() {
    let dir = temp_dir("boundary");
    let sheet = dir.join("sheet.obj");
    std::fs::write(
        &sheet,
        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nv 1 1 0\nv 2 1 0\nf 1 2 5 4\nf 2 3 6 5\n",
    )
    .unwrap();
    let out = dir.join("sheet.bpt");
    let run = common::cli::run_ok(
        import(&sheet)
            .args(["--boundary", "edge-only", "--out"])
            .arg(&out),
    );
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("boundary rule   edge-only (option)"),
        "{text}"
    );
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("sheet.bpt.json")).unwrap())
            .unwrap();
    assert_eq!(side["boundary"]["rule"], "edge-only");
    assert_eq!(side["boundary"]["from"], "option");
    // Smoothed cage corners (crease rule, one face): no patch is exact.
    let patches = side["patches"].as_array().unwrap();
    for (p, k) in [(0, 0), (0, 3), (1, 1), (1, 2)] {
        assert_eq!(patches[p]["corners"][k]["rule"], "crease");
        assert_eq!(patches[p]["corners"][k]["sector"], 1);
    }
    assert!(patches.iter().all(|e| e["exact"] == false));
    let run = import(&sheet)
        .args(["--boundary", "sharp"])
        .output()
        .unwrap();
    assert!(!run.status.success());
    assert!(String::from_utf8_lossy(&run.stderr).contains("none, edge-only, edge-and-corner"));
}

/// `import --isolate N` reports the refinement (parts refined, patches and
/// memory per level) as a line of the summary, not as a warning: it is
/// what was asked for (it was printed as `warning: isolate 2: ...`).
#[test]
fn import_reports_isolation_as_a_summary_line() {
    let cage = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/osd-shapes/catmark_chaikin0.obj");
    let run = common::cli::run_ok(import(&cage).args(["--isolate", "2"]));
    let text = String::from_utf8_lossy(&run.stdout);
    assert!(
        text.contains("  isolation       isolate 2: 1 of 1 connected parts refined 2 times; level 2: 352 patches"),
        "{text}"
    );
    assert!(!text.contains("warning: isolate"), "{text}");
    let plain = import(&cage).output().unwrap();
    assert!(!String::from_utf8_lossy(&plain.stdout).contains("isolation"));
}

/// A wait that runs out says what was running, how long it had run and
/// what to try (a longer --timeout or its environment variable, a smaller
/// --size, a coarser --grid), exits 1 and writes nothing; the flag and the
/// environment variable both set it, and a bad value of either is refused
/// before any GPU work.
#[test]
fn a_timeout_says_what_ran_and_what_to_try() {
    let dir = temp_dir("timeout");
    let out = dir.join("gt.png");
    let render = |flag: Option<&str>, env: Option<&str>| {
        let mut cmd = bin();
        cmd.args([
            "render",
            "--method",
            "ground-truth",
            "--grid",
            "16",
            "--scene",
        ])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/kitchen.toml"))
        // A warm-up frame first: the first frame's shader compile is
        // allowed beyond the timeout, the timed frame is held to it.
        .args(["--size", "320x180", "--warmup", "1", "--out"])
        .arg(&out)
        .env_remove("BEZIER_SUBDIV_TIMEOUT");
        if let Some(t) = flag {
            cmd.args(["--timeout", t]);
        }
        if let Some(t) = env {
            cmd.env("BEZIER_SUBDIV_TIMEOUT", t);
        }
        cmd.output().unwrap()
    };
    // 1 ms: far less than anything here takes, the first wait runs out.
    for (flag, env) in [
        (Some("0.001"), None),
        (None, Some("0.001")),
        (Some("0.001"), Some("600")),
    ] {
        let run = render(flag, env);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{flag:?} {env:?}: {err}");
        for want in [
            "1 ms fence timeout (",
            "since it was submitted",
            "--timeout SECONDS",
            "BEZIER_SUBDIV_TIMEOUT=SECONDS",
            "--size",
            "--grid",
        ] {
            assert!(
                err.contains(want),
                "{flag:?} {env:?}: wanted {want:?} in {err}"
            );
        }
        assert!(!err.contains("panicked"), "{err}");
        assert!(!out.exists() && !out.with_extension("json").exists());
    }
    let run = render(None, Some("soon"));
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(1), "{err}");
    assert!(
        err.contains("BEZIER_SUBDIV_TIMEOUT: `soon` is not a number of seconds"),
        "{err}"
    );
    let run = render(Some("0"), None);
    let err = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "clap refuses it: {err}");
    assert!(err.contains("positive number of seconds"), "{err}");
}

/// `render` times a frame after a warm-up frame and says so, in its line
/// and its stats file, where the cold first frame's figures stay
/// (`gpu_ms_cold`); `--warmup 0` times the cold frame. The README's own
/// command (the kitchen at 1080p). On a CPU device, which compiles at
/// first use, the first frame is the one that compiled and the timed one
/// did not (the stats say so: a fact of the frames, not a comparison of
/// times, so a busy machine cannot fail it).
#[test]
fn render_times_a_warm_frame_and_keeps_the_cold_one() {
    let dir = temp_dir("warm");
    let render = |out: &Path, extra: &[&str]| {
        let run = common::cli::run_ok(bin().arg("render").args(extra).arg("--out").arg(out));
        let text = String::from_utf8_lossy(&run.stdout).to_string();
        let stats: serde_json::Value =
            serde_json::from_slice(&std::fs::read(out.with_extension("json")).unwrap()).unwrap();
        (text, stats)
    };
    let (text, stats) = render(&dir.join("kitchen.png"), &[]);
    assert_eq!(stats["warmup_frames"], 1, "{stats}");
    assert!(
        text.contains("after 1 warm-up frame (the first took"),
        "{text}"
    );
    assert!(stats["gpu_ms_cold"]["frame"].is_number(), "{stats}");
    assert_eq!(stats["timed_frame_compiled"], false, "{stats}");
    let cpu = stats["device_is_cpu"] == true;
    if cpu {
        assert_eq!(stats["cold_frame_compiled"], true, "{stats}");
    }
    let (text, stats) = render(
        &dir.join("cold.png"),
        &["--warmup", "0", "--size", "320x180"],
    );
    assert_eq!(stats["warmup_frames"], 0);
    assert!(stats.get("gpu_ms_cold").is_none(), "{stats}");
    assert!(text.contains("(the first frame: cold)"), "{text}");
    if cpu {
        assert_eq!(stats["timed_frame_compiled"], true, "{stats}");
    }
    // The ground truth is drawn for its image: no warm-up unless asked.
    let gt = [
        "--method",
        "ground-truth",
        "--grid",
        "4",
        "--size",
        "320x180",
    ];
    let (_, stats) = render(&dir.join("gt.png"), &gt);
    assert_eq!(stats["warmup_frames"], 0, "{stats}");
    let warm = [&gt[..], &["--warmup", "1"]].concat();
    let (_, stats) = render(&dir.join("gt-warm.png"), &warm);
    assert_eq!(stats["warmup_frames"], 1, "{stats}");
    assert!(stats["gpu_ms_cold"]["frame"].is_number(), "{stats}");
}

/// `info` lists the sample counts `--msaa` (and the window's MSAA choice)
/// can take on each device, and a count it does not list is refused with
/// the ones it does.
#[test]
fn info_lists_the_sample_counts_msaa_takes() {
    let run = common::cli::run_ok(bin().arg("info"));
    let text = String::from_utf8_lossy(&run.stdout);
    let line = text
        .lines()
        .find(|l| l.contains("MSAA (--msaa):"))
        .unwrap_or_else(|| panic!("no sample counts in info:\n{text}"));
    let listed = line
        .split(':')
        .nth(1)
        .unwrap()
        .trim()
        .trim_end_matches("samples per pixel")
        .trim()
        .to_string();
    let counts: Vec<u32> = listed.split(", ").map(|n| n.parse().unwrap()).collect();
    assert!(counts.contains(&1), "{line}");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/teapot.toml");
    let dir = temp_dir("msaa");
    for n in [2, 4, 8] {
        let run = bin()
            .args([
                "render",
                "--size",
                "64x36",
                "--msaa",
                &n.to_string(),
                "--scene",
            ])
            .arg(&scene)
            .arg("--out")
            .arg(dir.join(format!("{n}.png")))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&run.stderr);
        if counts.contains(&n) {
            assert!(run.status.success(), "{n}x is listed: {err}");
        } else {
            assert_eq!(run.status.code(), Some(1), "{n}x: {err}");
            assert!(
                err.contains(&format!("it renders with {listed}")),
                "{n}x: {err}"
            );
        }
    }
}
