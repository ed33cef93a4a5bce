//! The user's documentation stays complete and short where it must: every
//! key the scene parser reads is in docs/GUIDE.md, the README links the
//! guide and keeps its command table to short rows, and pointers that went
//! stale once do not come back.

use std::path::Path;

fn read(rel: &str) -> String {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)).unwrap()
}

/// The field names of `struct NAME { .. }` in `source` (serde's keys: the
/// structs deny unknown fields and rename none).
fn fields(source: &str, name: &str) -> Vec<String> {
    let start = source
        .find(&format!("struct {name} {{"))
        .unwrap_or_else(|| panic!("no struct {name}"));
    let body = &source[start..];
    let body = &body[body.find('{').unwrap() + 1..body.find("\n}").unwrap()];
    // A `#[serde(rename = "x")]` names the next field's key.
    let mut renamed: Option<String> = None;
    let mut out = Vec::new();
    for l in body.lines().map(str::trim) {
        if let Some(r) = l.strip_prefix("#[serde(rename = \"") {
            renamed = r.split('"').next().map(str::to_string);
            continue;
        }
        if l.starts_with("//") || l.starts_with('#') {
            continue;
        }
        let l = l.strip_prefix("pub ").unwrap_or(l);
        let Some((n, _)) = l.split_once(':') else {
            continue;
        };
        let n = n.trim();
        if !n.is_empty() && n.chars().all(|c| c.is_ascii_lowercase() || c == '_') {
            out.push(renamed.take().unwrap_or_else(|| n.to_string()));
        }
    }
    out
}

#[test]
fn the_guide_documents_every_scene_key() {
    let guide = read("docs/GUIDE.md");
    let structs = [
        ("src/scene/file.rs", "SceneToml"),
        ("src/scene/desc.rs", "ViewDefaults"),
        ("src/scene/file.rs", "PathToml"),
        ("src/scene/file.rs", "ModelToml"),
        ("src/scene/file.rs", "InstanceToml"),
        ("src/scene/file.rs", "GridToml"),
        ("src/scene/camera.rs", "Camera"),
        ("src/scene/orbit.rs", "Orbit"),
        ("src/scene/keys.rs", "DeformToml"),
        ("src/scene/keys.rs", "KeyToml"),
        ("src/scene/keys.rs", "AnimationToml"),
    ];
    let mut missing = Vec::new();
    for (file, name) in structs {
        let keys = fields(&read(file), name);
        assert!(keys.len() >= 2, "{name}: read no fields ({keys:?})");
        for k in keys {
            let shown = [
                format!("`{k}`"),
                format!("[{k}]"),
                format!(".{k}]"),
                format!("{k} ="),
            ];
            if !shown.iter().any(|s| guide.contains(s.as_str())) {
                missing.push(format!("{name}.{k}"));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "docs/GUIDE.md does not document {missing:?}"
    );
    for value in [
        "edge-and-corner",
        "edge-only",
        "pn-triangles",
        ".rbpt",
        "t crease",
        "t corner",
    ] {
        assert!(
            guide.contains(value),
            "docs/GUIDE.md does not mention {value}"
        );
    }
}

#[test]
fn the_readme_links_the_guide_and_keeps_its_table_short() {
    let readme = read("README.md");
    assert!(
        readme.contains("(docs/GUIDE.md)"),
        "README does not link docs/GUIDE.md"
    );
    for row in readme.lines().filter(|l| l.starts_with("| `")) {
        let words = row.split_whitespace().count();
        assert!(words <= 45, "a README table row of {words} words: {row}");
    }
}

#[test]
fn stale_pointers_stay_gone() {
    for (file, stale) in [
        ("src/methods/mod.rs", "later `subdiv-indirect`"),
        ("src/draw/mod.rs", "later\n//! `subdiv-indirect`"),
        (
            "src/methods/subdiv/push.rs",
            "`SubdivPush` in\n/// `glsl/levels/persistent.comp`",
        ),
        ("docs/BENCHMARKS.md", "DESIGN.md"),
        ("README.md", "described at the top of `src/scene/file.rs`"),
    ] {
        assert!(!read(file).contains(stale), "{file} still says {stale:?}");
    }
    let arch = read("docs/ARCHITECTURE.md");
    let eval_rows = arch
        .lines()
        .filter(|l| l.starts_with("| `src/eval/`"))
        .count();
    assert_eq!(
        eval_rows, 1,
        "ARCHITECTURE.md lists src/eval/ {eval_rows} times"
    );
    for block in [
        "DrawPush",
        "SubdivPush",
        "LevelPush",
        "ListPush",
        "GridPush",
        "CtPush",
    ] {
        assert!(
            arch.contains(&format!("`{block}`")),
            "ARCHITECTURE.md misses {block}"
        );
    }
}
