//! The suite must run from a read-only checkout: no test writes into the
//! source tree. Tests write under `CARGO_TARGET_TMPDIR` (or the system's
//! temporary directory); this test reads every test source and refuses the
//! ways a test has written into the tree before: a path into the checkout's
//! own `target/` (`CARGO_MANIFEST_DIR/target/test-output/...`, which is not
//! even the target directory when `CARGO_TARGET_DIR` points elsewhere).

use std::path::{Path, PathBuf};

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            if path.file_name().is_some_and(|n| n != "data") {
                sources(&path, out);
            }
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Code lines (comments dropped) of every Rust file under `tests/` and
/// `src/` that mention a path into the checkout's `target/`.
fn writes_into_the_tree() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    sources(&root.join("tests"), &mut files);
    sources(&root.join("src"), &mut files);
    let me = Path::new(file!()).file_name().unwrap();
    let mut found = Vec::new();
    for file in files.iter().filter(|f| f.file_name() != Some(me)) {
        let text = std::fs::read_to_string(file).unwrap();
        for (i, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            if code.contains("\"target/") || code.contains("test-output") {
                found.push(format!("{}:{}: {}", file.display(), i + 1, line.trim()));
            }
        }
    }
    found
}

#[test]
fn no_test_writes_into_the_source_tree() {
    let found = writes_into_the_tree();
    assert!(
        found.is_empty(),
        "write test output under CARGO_TARGET_TMPDIR (tests/common::output_dir), \
         not into the checkout:\n{}",
        found.join("\n")
    );
}
