//! Build script: embeds the compiled SPIR-V and records the source commit.
//!
//! - Every `spirv/*.spv` and `spirv/<method>/*.spv` is embedded with
//!   `include_bytes!`, so a copied or installed binary runs without its
//!   source tree (`src/vk/shader.rs`; `BEZIER_SUBDIV_SPIRV_DIR` still loads
//!   files from disk for shader work).
//! - `BEZIER_SUBDIV_COMMIT`: the commit the binary was built from (short
//!   hash, `-dirty` when tracked files differed from it), or the value of
//!   that variable in the build environment (for packagers), or `unknown`
//!   outside a git checkout. The stats files report it.

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    embed_spirv(&root);
    record_commit(&root);
}

fn embed_spirv(root: &Path) {
    let dir = root.join("spirv");
    println!("cargo:rerun-if-changed={}", dir.display());
    let mut names = spv_names(&dir, "");
    // A method's shaders sit in a folder of their own (`spirv/cudatess/`).
    for folder in subfolders(&dir) {
        println!("cargo:rerun-if-changed={}", dir.join(&folder).display());
        names.extend(spv_names(&dir.join(&folder), &format!("{folder}/")));
    }
    names.sort();
    let mut table = String::from(
        "/// Every compiled shader: (GLSL path below `glsl/`, SPIR-V bytes).\n\
         pub static EMBEDDED: &[(&str, &[u8])] = &[\n",
    );
    for n in &names {
        let path = dir.join(n);
        table += &format!(
            "    ({:?}, include_bytes!({:?})),\n",
            n.trim_end_matches(".spv"),
            path.display().to_string()
        );
    }
    table += "];\n";
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    std::fs::write(out.join("spirv_table.rs"), table).expect("write the SPIR-V table");
}

/// The names of the entries of `dir`, each for which `keep` holds.
fn names_in(dir: &Path, keep: impl Fn(&std::fs::DirEntry) -> bool) -> Vec<String> {
    std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(Result::ok)
                .filter(|e| keep(e))
                .filter_map(|e| e.file_name().into_string().ok())
                .collect()
        })
        .unwrap_or_default()
}

/// The `.spv` files directly in `dir`, each as `prefix` + its name.
fn spv_names(dir: &Path, prefix: &str) -> Vec<String> {
    names_in(dir, |e| e.path().is_file())
        .into_iter()
        .filter(|n| n.ends_with(".spv"))
        .map(|n| format!("{prefix}{n}"))
        .collect()
}

fn subfolders(dir: &Path) -> Vec<String> {
    names_in(dir, |e| e.path().is_dir())
}

fn git(root: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(root)
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn record_commit(root: &Path) {
    println!("cargo:rerun-if-env-changed=BEZIER_SUBDIV_COMMIT");
    // Whatever the binary is built from: a change there may make it dirty.
    for p in ["src", "glsl", "spirv", "Cargo.toml", "build.rs"] {
        println!("cargo:rerun-if-changed={}", root.join(p).display());
    }
    if let Some(git_dir) = git(root, &["rev-parse", "--absolute-git-dir"]) {
        // HEAD moves on checkout, the index on commit and add.
        for f in ["HEAD", "index"] {
            println!(
                "cargo:rerun-if-changed={}",
                Path::new(&git_dir).join(f).display()
            );
        }
    }
    let commit = std::env::var("BEZIER_SUBDIV_COMMIT")
        .ok()
        .filter(|c| !c.is_empty())
        .or_else(|| {
            let hash = git(root, &["rev-parse", "--short=12", "HEAD"]).filter(|h| !h.is_empty())?;
            let dirty = git(root, &["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            Some(if dirty { format!("{hash}-dirty") } else { hash })
        })
        .unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=BEZIER_SUBDIV_COMMIT={commit}");
}
