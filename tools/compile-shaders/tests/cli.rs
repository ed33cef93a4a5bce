//! The tool as CI and developers run it: exit statuses and what it prints.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

#[path = "../src/temp_dir.rs"]
mod temp_dir;
use temp_dir::TempDir;

/// A tool checkout in a temp dir: glsl/common made, and the tool run on it.
trait Checkout {
    fn checkout(tag: &str) -> Self;
    fn run(&self, extra: &[&str]) -> Output;
    fn spv(&self, name: &str) -> PathBuf;
    fn header(&self) -> PathBuf;
}

impl Checkout for TempDir {
    fn checkout(tag: &str) -> Self {
        let dir = TempDir::new(&format!("cli-{tag}"));
        fs::create_dir_all(dir.0.join("glsl/common")).unwrap();
        dir
    }

    /// Runs the tool on this directory's glsl/ and spirv/, from inside it.
    fn run(&self, extra: &[&str]) -> Output {
        Command::new(env!("CARGO_BIN_EXE_compile-shaders"))
            .args(["--glsl", "glsl", "--spirv", "spirv"])
            .args(extra)
            .current_dir(&self.0)
            .output()
            .unwrap()
    }

    fn spv(&self, name: &str) -> PathBuf {
        self.0.join("spirv").join(name)
    }

    /// The generated constants header.
    fn header(&self) -> PathBuf {
        self.0.join("glsl/common/constants.glsl")
    }
}

fn text(out: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

const COMP: &str = "#version 460\n#include \"common/k.glsl\"\n\
    layout(local_size_x = 1) in;\nvoid main() {}\n";

fn is_spirv(path: &Path) -> bool {
    let bytes = fs::read(path).unwrap();
    bytes.len() >= 20 && bytes[..4] == 0x0723_0203u32.to_le_bytes()
}

#[test]
fn check_reports_stale_missing_and_orphaned_then_passes_after_compiling() {
    let dir = TempDir::checkout("check");
    dir.put("glsl/common/k.glsl", "const uint K = 3u;\n");
    dir.put("glsl/a.comp", COMP);
    dir.put("glsl/b.comp", COMP);
    dir.put("spirv/a.comp.spv", "stale bytes");
    dir.put("spirv/old.comp.spv", "no source any more");

    let out = dir.run(&["--check"]);
    let log = text(&out);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains("stale:") && log.contains("a.comp.spv"),
        "{log}"
    );
    assert!(
        log.contains("missing:") && log.contains("b.comp.spv"),
        "{log}"
    );
    assert!(
        log.contains("orphaned:") && log.contains("old.comp.spv"),
        "{log}"
    );
    // --check never writes.
    assert_eq!(fs::read(dir.spv("a.comp.spv")).unwrap(), b"stale bytes");
    assert!(!dir.spv("b.comp.spv").exists());

    let out = dir.run(&[]);
    let log = text(&out);
    assert!(out.status.success(), "{log}");
    assert!(
        log.contains("removed:") && log.contains("old.comp.spv"),
        "{log}"
    );
    assert!(is_spirv(&dir.spv("a.comp.spv")) && is_spirv(&dir.spv("b.comp.spv")));
    assert!(!dir.spv("old.comp.spv").exists());

    let out = dir.run(&["--check"]);
    let log = text(&out);
    assert!(out.status.success(), "{log}");
    assert!(log.contains("all 2 SPIR-V modules"), "{log}");

    // Editing an include makes the modules that use it stale.
    dir.put(
        "glsl/common/k.glsl",
        "const uint K = 4u;\nconst uint L = K;\n",
    );
    let out = dir.run(&["--check"]);
    assert_eq!(out.status.code(), Some(1), "{}", text(&out));
}

#[test]
fn a_compile_error_names_the_file_and_writes_nothing() {
    let dir = TempDir::checkout("error");
    dir.put("glsl/common/k.glsl", "const uint K = 3u;\n");
    dir.put("glsl/good.comp", COMP);
    dir.put(
        "glsl/bad.frag",
        "#version 460\nvoid main() { undefined_thing(); }\n",
    );
    dir.put("spirv/orphan.comp.spv", "kept while the build is broken");

    for extra in [&[][..], &["--check"][..]] {
        let out = dir.run(extra);
        let log = text(&out);
        assert_eq!(out.status.code(), Some(2), "{log}");
        assert!(log.contains("glsl/bad.frag:2:"), "{log}");
        assert!(log.contains("undefined_thing"), "{log}");
        assert!(!log.contains("good.comp"), "{log}");
    }
    assert!(!dir.spv("good.comp.spv").exists());
    assert!(dir.spv("orphan.comp.spv").exists());
    // The constants header does not depend on the shaders: it is written.
    assert!(dir.header().exists());
}

#[test]
fn a_run_writes_the_constants_header_first_and_check_catches_a_hand_edit() {
    let dir = TempDir::checkout("header");
    // The shader needs the header, which does not exist yet: a run must
    // write it before compiling.
    dir.put(
        "glsl/uses.comp",
        "#version 460\n#include \"common/constants.glsl\"\n\
         layout(local_size_x = 1) in;\n\
         layout(std430, binding = 0) buffer B { uint v[]; };\n\
         void main() { v[0] = L_MAX; }\n",
    );

    // --check compiles with the generated header, so the shader compiles
    // although the file is missing.
    let out = dir.run(&["--check"]);
    let log = text(&out);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains("missing:  glsl/common/constants.glsl"),
        "{log}"
    );
    assert!(log.contains("missing:  spirv/uses.comp.spv"), "{log}");
    assert!(!dir.header().exists(), "--check never writes");

    let out = dir.run(&[]);
    let log = text(&out);
    assert!(out.status.success(), "{log}");
    assert!(
        log.contains("created:  glsl/common/constants.glsl"),
        "{log}"
    );
    let generated = fs::read_to_string(dir.header()).unwrap();
    assert!(generated.starts_with("// Generated from src/constants.rs"));
    // A method's header too, in its own folder.
    assert!(
        log.contains("created:  glsl/cudatess/constants.glsl (generated from src/methods/cudatess/constants.rs)"),
        "{log}"
    );
    let out = dir.run(&["--check"]);
    let log = text(&out);
    assert!(out.status.success(), "{log}");
    assert!(
        log.contains("constants headers and all 1 SPIR-V module in spirv are current"),
        "{log}"
    );

    // A hand edit: one wrong value. Only the header is stale: --check compiles
    // with the generated text, as a run would.
    let line = "const uint L_MAX = 10;\n";
    assert!(generated.contains(line), "{generated}");
    let edited = generated.replace(line, "const uint L_MAX = 9;\n");
    fs::write(dir.header(), &edited).unwrap();
    let out = dir.run(&["--check"]);
    let log = text(&out);
    assert_eq!(out.status.code(), Some(1), "{log}");
    assert!(
        log.contains("stale:    glsl/common/constants.glsl"),
        "{log}"
    );
    assert!(log.contains("1 generated file is out of date"), "{log}");
    assert_eq!(fs::read_to_string(dir.header()).unwrap(), edited);

    let out = dir.run(&[]);
    let log = text(&out);
    assert!(out.status.success(), "{log}");
    assert!(
        log.contains("updated:  glsl/common/constants.glsl"),
        "{log}"
    );
    assert_eq!(fs::read_to_string(dir.header()).unwrap(), generated);
    assert!(dir.run(&["--check"]).status.success());
}

#[test]
fn an_empty_glsl_directory_compiles_and_checks_clean() {
    let dir = TempDir::checkout("empty");
    let out = dir.run(&[]);
    assert!(out.status.success(), "{}", text(&out));
    assert!(text(&out).contains("no shaders"), "{}", text(&out));
    let out = dir.run(&["--check"]);
    assert!(out.status.success(), "{}", text(&out));
}

#[test]
fn help_and_bad_arguments() {
    let dir = TempDir::checkout("args");
    let out = dir.run(&["--help"]);
    assert!(out.status.success());
    assert!(text(&out).contains("--check"));
    let out = dir.run(&["--frobnicate"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out).contains("unknown argument `--frobnicate`"));
}

#[test]
fn a_missing_glsl_directory_is_an_error() {
    let dir = TempDir::checkout("noglsl");
    let out = dir.run(&["--glsl", "nowhere"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out).contains("nowhere"), "{}", text(&out));
}
