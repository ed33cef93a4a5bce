//! The binary as a child process.

use std::process::{Command, Output};

/// `bench`'s smallest sweep: one method at one (eps, lambda) point, for the
/// tests that need a bench run but not a measurement.
pub const BENCH_ONE_POINT: [&str; 6] = ["--methods", "subdiv", "--eps", "1", "--lambda", "0.5"];

/// The crate's binary, ready for arguments.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_bezier-subdiv"))
}

/// Fails the test unless `run` exited successfully; the message is
/// `context` followed by the child's stderr.
pub fn assert_success(run: &Output, context: &str) {
    assert!(
        run.status.success(),
        "{context}{}",
        String::from_utf8_lossy(&run.stderr)
    );
}

/// Runs `cmd` to its end and fails the test unless it succeeded (the
/// message is its stderr); returns what it wrote.
pub fn run_ok(cmd: &mut Command) -> Output {
    let run = cmd
        .output()
        .unwrap_or_else(|e| panic!("cannot run {cmd:?}: {e}"));
    assert_success(&run, "");
    run
}
