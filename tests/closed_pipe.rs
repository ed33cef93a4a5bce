//! Every command that prints, with its stdout a pipe whose reader is gone
//! (`bezier-subdiv info | head -0`): no panic, the command's own exit
//! status, and its files written all the same.
//!
//! The read end is closed before the child starts, so the very first write
//! meets a closed pipe however little the command prints. (A reader that
//! closes after the child is done, or a `head -1` that races it, lets an
//! output smaller than the pipe's buffer through unnoticed: that is how an
//! earlier fix passed its test and still failed on the command line.)
//! One case also closes stderr, for an error that must still be reported
//! without a panic.

mod common;

use std::os::fd::{FromRawFd, OwnedFd};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn bin() -> &'static str {
    env!("CARGO_BIN_EXE_bezier-subdiv")
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("closed-pipe-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A pipe's write end whose read end is already closed.
fn closed_pipe() -> OwnedFd {
    let mut fds = [0; 2];
    // SAFETY: pipe() fills two new descriptors, owned from here on.
    assert_eq!(unsafe { libc::pipe(fds.as_mut_ptr()) }, 0, "pipe()");
    let (reader, writer) = unsafe { (OwnedFd::from_raw_fd(fds[0]), OwnedFd::from_raw_fd(fds[1])) };
    drop(reader);
    writer
}

/// Runs `cmd` with stdout (and with `close_stderr` also stderr) into a
/// closed pipe; returns the output (stderr captured unless closed).
fn run_closed(mut cmd: Command, close_stderr: bool) -> Output {
    cmd.stdin(Stdio::null()).stdout(closed_pipe());
    if close_stderr {
        cmd.stderr(closed_pipe());
    } else {
        cmd.stderr(Stdio::piped());
    }
    cmd.spawn().unwrap().wait_with_output().unwrap()
}

fn assert_quiet_success(what: &str, run: &Output) {
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(!err.contains("panicked"), "{what}: {err}");
    assert!(run.status.success(), "{what}: {:?}\n{err}", run.status);
}

fn on_path(tool: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(tool).is_file()))
}

fn command(args: &[&str]) -> Command {
    let mut c = Command::new(bin());
    c.args(args);
    c
}

/// The CPU-only commands and the ones that need only a Vulkan device.
#[test]
fn commands_survive_a_closed_stdout() {
    let dir = temp_dir("cpu");
    let teapot = root().join("scenes/teapot.toml");
    let teapot = teapot.to_str().unwrap();
    let car = root().join("scenes/models/catmark_car.obj");
    let bpt = dir.join("car.bpt");
    let png = dir.join("teapot.png");
    let cases: Vec<(&str, Command)> = vec![
        ("--help", command(&["--help"])),
        ("render --help", command(&["render", "--help"])),
        ("--version", command(&["--version"])),
        ("info", command(&["info"])),
        (
            "import OBJ",
            command(&[
                "import",
                car.to_str().unwrap(),
                "--out",
                bpt.to_str().unwrap(),
            ]),
        ),
        ("stats", command(&["stats", "--scene", teapot])),
        (
            "stats --json",
            command(&["stats", "--scene", teapot, "--json"]),
        ),
        (
            "render",
            command(&[
                "render",
                "--scene",
                teapot,
                "--size",
                "64x36",
                "--out",
                png.to_str().unwrap(),
            ]),
        ),
        (
            "validate",
            command(&[
                "validate",
                "--scene",
                teapot,
                "--frame",
                "0",
                "--size",
                "64x36",
                "--no-holes",
            ]),
        ),
    ];
    for (what, cmd) in cases {
        let run = run_closed(cmd, false);
        assert_quiet_success(what, &run);
    }
    // The work was done although nobody read about it.
    assert!(bpt.is_file() && png.is_file() && png.with_extension("json").is_file());
    // The .bpt written above is read back through the same closed pipe.
    let again = run_closed(command(&["import", bpt.to_str().unwrap()]), false);
    assert_quiet_success("import BPT", &again);
    let _ = std::fs::remove_dir_all(dir);
}

/// `bench` (a tiny run) prints its closing line into a closed pipe.
#[test]
fn bench_survives_a_closed_stdout() {
    let dir = temp_dir("bench");
    let out = dir.join("bench");
    let teapot = root().join("scenes/teapot.toml");
    let run = run_closed(
        command(
            &[
                &["bench", "--scene", teapot.to_str().unwrap()][..],
                &common::cli::BENCH_ONE_POINT,
                &[
                    "--frames",
                    "1",
                    "--warmup",
                    "0",
                    "--flip-frames",
                    "0",
                    "--size",
                    "64x36",
                    "--out",
                    out.to_str().unwrap(),
                ],
            ]
            .concat(),
        ),
        false,
    );
    assert_quiet_success("bench", &run);
    assert!(out.join("summary.json").is_file());
    let _ = std::fs::remove_dir_all(dir);
}

/// `view` (two frames on a virtual display) prints its summary into a
/// closed pipe.
#[test]
fn view_survives_a_closed_stdout() {
    let teapot = root().join("scenes/teapot.toml");
    let args = [
        "view",
        "--scene",
        teapot.to_str().unwrap(),
        "--size",
        "64x36",
        "--frames",
        "2",
    ];
    let cmd = if on_path("xvfb-run") {
        let mut c = Command::new("xvfb-run");
        c.args(["-a", "-s", "-screen 0 640x360x24", bin()])
            .args(args);
        c
    } else {
        assert!(
            std::env::var_os("DISPLAY").is_some(),
            "neither xvfb-run nor a DISPLAY: run tools/install-deps.sh"
        );
        command(&args)
    };
    let run = run_closed(cmd, false);
    assert_quiet_success("view", &run);
}

/// A failing command with both stdout and stderr closed exits with its
/// failure status (1), not a panic's (101).
#[test]
fn an_error_into_a_closed_stderr_is_no_panic() {
    let run = run_closed(
        command(&["render", "--scene", "/nonexistent/scene.toml"]),
        true,
    );
    assert_eq!(run.status.code(), Some(1), "{:?}", run.status);
}
