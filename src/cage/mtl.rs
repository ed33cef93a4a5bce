//! A cage's albedo map from its material library: the OBJ's `mtllib` and
//! `usemtl` statements, the library's `newmtl` and `map_Kd`. One map per
//! model (the renderer has one albedo per model): the first material the
//! faces use that has a `map_Kd`; other maps are named in a warning.
//!
//! What a user meets: a library that is not there is a warning and the
//! model is drawn untextured (OBJ files often travel without theirs); a
//! `map_Kd` naming a file that cannot be read is an error when the scene
//! loads the texture (`scene::texture`), naming the file.

use std::path::{Path, PathBuf};

use crate::input::text::statements;
use crate::input::SceneError;

/// The material statements of an OBJ file.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MaterialUse {
    /// `mtllib` files (relative to the OBJ), with their line.
    pub libs: Vec<(usize, String)>,
    /// `usemtl` names in order of first use, with their line.
    pub used: Vec<(usize, String)>,
}

impl MaterialUse {
    /// Records an `mtllib` or `usemtl` statement at `line`.
    pub fn record(&mut self, line: usize, keyword: &str, rest: &[&str]) {
        match keyword {
            "mtllib" => self
                .libs
                .extend(rest.iter().map(|name| (line, (*name).to_owned()))),
            "usemtl" => {
                let name = rest.join(" ");
                if !self.used.iter().any(|(_, n)| *n == name) {
                    self.used.push((line, name));
                }
            }
            _ => {}
        }
    }
}

/// An albedo map a material names.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AlbedoMap {
    /// The image file (relative paths resolved against the library's folder).
    pub path: PathBuf,
    /// Where it is named: `library.mtl:line`.
    pub from: String,
}

/// The albedo map of the OBJ at `obj` with material statements `uses`, if
/// any: see the module comment. Warnings go to `warnings`.
pub fn albedo_map(
    obj: &Path,
    uses: &MaterialUse,
    warnings: &mut Vec<String>,
) -> Result<Option<AlbedoMap>, SceneError> {
    if uses.used.is_empty() {
        return Ok(None);
    }
    let dir = obj.parent().unwrap_or(Path::new(""));
    let mut maps: Vec<(String, AlbedoMap)> = Vec::new();
    for (line, lib) in &uses.libs {
        let lib_path = dir.join(lib);
        let text = match std::fs::read_to_string(&lib_path) {
            Ok(text) => text,
            Err(e) => {
                warnings.push(format!(
                    "{}:{line}: material library {} not read ({e}): drawn without its texture",
                    obj.display(),
                    lib_path.display()
                ));
                continue;
            }
        };
        maps.extend(library_maps(&lib_path, &text)?);
    }
    let mut chosen: Option<AlbedoMap> = None;
    for (_, name) in &uses.used {
        let Some((_, map)) = maps.iter().find(|(n, _)| n == name) else {
            continue;
        };
        match &chosen {
            None => chosen = Some(map.clone()),
            Some(first) if first.path != map.path => warnings.push(format!(
                "material '{name}' has its own map_Kd ({}): one albedo map per model, {} is drawn",
                map.from, first.from
            )),
            Some(_) => {}
        }
    }
    Ok(chosen)
}

/// Each material of a library with a `map_Kd`: its name and map. A
/// `map_Kd` without a file name is an error at its line.
fn library_maps(lib: &Path, text: &str) -> Result<Vec<(String, AlbedoMap)>, SceneError> {
    let dir = lib.parent().unwrap_or(Path::new(""));
    let mut current: Option<String> = None;
    let mut out = Vec::new();
    for (line, keyword, rest) in statements(text) {
        match keyword {
            "newmtl" => current = Some(rest.join(" ")),
            "map_Kd" => {
                // Options (`-s 1 1 1`, `-bm 0.5`, …) come first; the file
                // name is the last word.
                let Some(file) = rest.last() else {
                    return Err(SceneError::at(lib, line, "`map_Kd` without a file name"));
                };
                let Some(name) = current.clone() else {
                    return Err(SceneError::at(lib, line, "`map_Kd` before any `newmtl`"));
                };
                out.push((
                    name,
                    AlbedoMap {
                        path: dir.join(file),
                        from: format!("{}:{line}", lib.display()),
                    },
                ));
            }
            _ => {}
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("bs-mtl-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn uses(text: &str) -> MaterialUse {
        let mut u = MaterialUse::default();
        for (line, keyword, rest) in statements(text) {
            u.record(line, keyword, &rest);
        }
        u
    }

    #[test]
    fn the_first_used_material_with_a_map_is_the_albedo() {
        let dir = scratch("first");
        std::fs::write(
            dir.join("m.mtl"),
            "newmtl plain\nKd 1 0 0\nnewmtl wood\nmap_Kd -s 2 2 1 tex/wood.png\nnewmtl stone\nmap_Kd stone.png\n",
        )
        .unwrap();
        let obj = dir.join("a.obj");
        let mut w = Vec::new();
        let u = uses("mtllib m.mtl\nusemtl plain\nf 1 2 3\nusemtl wood\nf 1 2 3\nusemtl stone\n");
        let map = albedo_map(&obj, &u, &mut w).unwrap().unwrap();
        assert_eq!(map.path, dir.join("tex/wood.png"));
        assert!(map.from.ends_with("m.mtl:4"), "{}", map.from);
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("stone") && w[0].contains("one albedo map"),
            "{w:?}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_missing_library_is_a_warning_and_a_bad_map_an_error_with_its_line() {
        let dir = scratch("bad");
        let obj = dir.join("a.obj");
        let mut w = Vec::new();
        let u = uses("mtllib gone.mtl\nusemtl x\n");
        assert_eq!(albedo_map(&obj, &u, &mut w).unwrap(), None);
        assert!(w[0].contains("gone.mtl") && w[0].contains(":1:"), "{w:?}");
        std::fs::write(dir.join("m.mtl"), "newmtl x\nmap_Kd\n").unwrap();
        let u = uses("mtllib m.mtl\nusemtl x\n");
        let e = albedo_map(&obj, &u, &mut Vec::new())
            .unwrap_err()
            .to_string();
        assert!(e.contains("m.mtl:2") && e.contains("map_Kd"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
