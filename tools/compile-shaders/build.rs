//! Finds every method's constants module (`src/methods/<method>/constants.rs`)
//! and writes `method_constants.rs`, which compiles each into the tool by
//! path, so that a new method's constants reach its shaders without an edit
//! here.

use std::path::{Path, PathBuf};

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets it"));
    let methods = manifest.join("../../src/methods");
    // A folder or a constants file added or removed changes these folders.
    println!("cargo:rerun-if-changed={}", methods.display());
    let mut found = Vec::new();
    for entry in std::fs::read_dir(&methods).into_iter().flatten().flatten() {
        let dir = entry.path();
        if !dir.is_dir() {
            continue;
        }
        println!("cargo:rerun-if-changed={}", dir.display());
        let file = dir.join("constants.rs");
        if let (true, Some(name)) = (file.is_file(), entry.file_name().to_str()) {
            found.push((name.to_owned(), file));
        }
    }
    found.sort();
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets it"));
    std::fs::write(out.join("method_constants.rs"), table(&found))
        .expect("write method_constants.rs");
}

/// The modules, one per method, and `METHODS`: (folder name, its table).
fn table(found: &[(String, PathBuf)]) -> String {
    let mut text = String::new();
    for (name, file) in found {
        text += &format!("#[path = {:?}]\npub mod {name};\n", path_text(file));
    }
    text += "/// Every method's constants: (its folder's name, its table).\n";
    text += "pub const METHODS: &[(&str, &[crate::constants::SharedConst])] = &[\n";
    for (name, _) in found {
        text += &format!("    ({name:?}, {name}::ALL),\n");
    }
    text + "];\n"
}

fn path_text(file: &Path) -> String {
    let file = file.canonicalize().unwrap_or_else(|_| file.to_path_buf());
    file.display().to_string()
}
