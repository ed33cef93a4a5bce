//! Finds every method's constants module (`src/methods/<method>/constants.rs`)
//! and every other module folder's (`src/<folder>/constants.rs`, such as the
//! levels of detail's) and writes `method_constants.rs`, which compiles each
//! into the tool by path, so that new constants reach their shaders without
//! an edit here.

use std::path::{Path, PathBuf};

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let src = manifest.join("../../src");
    let mut found = Vec::new();
    for (folder, prefix) in [("methods", "src/methods"), ("", "src")] {
        let dir = src.join(folder);
        // A folder or a constants file added or removed changes these folders.
        println!("cargo:rerun-if-changed={}", dir.display());
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let sub = entry.path();
            if !sub.is_dir() {
                continue;
            }
            println!("cargo:rerun-if-changed={}", sub.display());
            let file = sub.join("constants.rs");
            if let (true, Some(name)) = (file.is_file(), entry.file_name().to_str()) {
                found.push((
                    name.to_owned(),
                    format!("{prefix}/{name}/constants.rs"),
                    file,
                ));
            }
        }
    }
    found.sort();
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    std::fs::write(out.join("method_constants.rs"), table(&found))
        .expect("write method_constants.rs");
}

/// The modules, one per folder, and `METHODS`: (folder name, the constants
/// file as the workspace names it, its table).
fn table(found: &[(String, String, PathBuf)]) -> String {
    let mut text = String::new();
    for (name, _, file) in found {
        text += &format!("#[path = {:?}]\npub mod {name};\n", path_text(file));
    }
    text += "/// Every folder's constants: (its name, its file, its table).\n";
    text += "pub const METHODS: &[(&str, &str, &[crate::constants::SharedConst])] = &[\n";
    for (name, source, _) in found {
        text += &format!("    ({name:?}, {source:?}, {name}::ALL),\n");
    }
    text + "];\n"
}

fn path_text(file: &Path) -> String {
    let file = file.canonicalize().unwrap_or_else(|_| file.to_path_buf());
    file.display().to_string()
}
