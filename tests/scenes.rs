//! Every shipped scene file: it loads, has the patch count it documents, every
//! keyframe sees something, and the oracle draws every model from frame 0.
//! Also the `stats --preview` path end to end.

mod common;

use std::path::{Path, PathBuf};

use bezier_subdiv::commands::stats::{self, StatsArgs};
use bezier_subdiv::constants::PATCH_MODEL_SHIFT;
use bezier_subdiv::patch::oracle::subdivide_parallel_weighted;
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::scene::geometry::SceneGeometry;
use bezier_subdiv::validate::raster::PreviewShade;

/// The shipped scenes: file, base patches, keyframes (camera + path keys).
/// The paper's kitchen has 35,940 base patches; ours is built to match.
const SCENES: &[(&str, usize, usize)] = &[
    ("teapot.toml", 32, 4),
    ("kitchen.toml", 35_940, 8),
    ("blobs.toml", 35_940, 7),
    ("cages.toml", 577, 4),
    ("rational.toml", 56, 3),
    ("cylinder.toml", 4, 3),
    ("pillow.toml", 4, 3),
    ("herd.toml", 1_008_406, 6),
    ("anim.toml", 2_608, 1),
    ("kitchen-anim.toml", 35_940, 8),
    ("textured.toml", 199, 3),
    ("displaced.toml", 506, 2),
    ("kitchen-displaced.toml", 35_940, 9),
    ("panels.toml", 470, 2),
    ("parking.toml", 19_300, 2),
];

/// Scenes of PN triangles alone (no patches: only cudatess draws them),
/// tested by their own files (tests/pn.rs) instead of the loops here.
const PN_SCENES: &[&str] = &["pn.toml"];

/// Small viewport: enough for the culling and criterion to act, fast.
const SIZE: (u32, u32) = (320, 180);

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn load(name: &str) -> (Scene, SceneGeometry) {
    let path = scenes_dir().join(name);
    let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let geo = scene.geometry().unwrap_or_else(|e| panic!("{e}"));
    (scene, geo)
}

#[test]
fn every_scene_file_is_listed_here() {
    let mut found: Vec<String> = std::fs::read_dir(scenes_dir())
        .unwrap()
        .filter_map(|e| {
            let name = e.unwrap().file_name().to_string_lossy().into_owned();
            name.ends_with(".toml").then_some(name)
        })
        .collect();
    found.sort();
    let mut listed: Vec<String> = SCENES.iter().map(|s| s.0.to_string()).collect();
    listed.extend(PN_SCENES.iter().map(|s| s.to_string()));
    listed.sort();
    assert_eq!(
        found, listed,
        "add new scenes to SCENES with their patch count"
    );
}

#[test]
fn scenes_have_their_documented_patch_counts() {
    for &(name, patches, frames) in SCENES {
        let (scene, geo) = load(name);
        assert_eq!(scene.frame_count(), frames, "{name}: keyframes");
        assert_eq!(geo.patches.len(), patches, "{name}");
        assert_eq!(geo.flags.len(), patches, "{name}");
        let sum: usize = geo
            .models
            .iter()
            .map(|m| m.patches_per_instance * m.instances)
            .sum();
        assert_eq!(sum, patches, "{name}");
    }
}

/// One row of a scene file's header table:
/// `#   name   file   instances × patches = total`.
struct TableRow {
    name: String,
    instances: usize,
    per_instance: usize,
    total: usize,
}

fn header_table(text: &str) -> Vec<TableRow> {
    let num = |s: &str| s.replace(',', "").parse::<usize>().ok();
    let mut rows = Vec::new();
    for line in text.lines().take_while(|l| l.starts_with('#')) {
        let t: Vec<&str> = line.trim_start_matches('#').split_whitespace().collect();
        let Some(file) = t
            .iter()
            .position(|w| w.ends_with(".obj") || w.ends_with(".bpt"))
        else {
            continue;
        };
        if t.len() != file + 6 || t[file + 2] != "×" || t[file + 4] != "=" {
            continue;
        }
        if let (Some(instances), Some(per_instance), Some(total)) =
            (num(t[file + 1]), num(t[file + 3]), num(t[file + 5]))
        {
            rows.push(TableRow {
                name: t[..file].join(" "),
                instances,
                per_instance,
                total,
            });
        }
    }
    rows
}

#[test]
fn the_kitchen_header_tables_match_the_geometry() {
    for name in ["kitchen.toml", "kitchen-displaced.toml", "blobs.toml"] {
        header_table_matches(name, "35,940");
    }
    header_table_matches("herd.toml", "1,008,406");
}

fn header_table_matches(name: &str, total: &str) {
    let text = std::fs::read_to_string(scenes_dir().join(name)).unwrap();
    let rows = header_table(&text);
    let (_, geo) = load(name);
    assert_eq!(rows.len(), geo.models.len(), "one table row per model");
    for (row, m) in rows.iter().zip(&geo.models) {
        assert_eq!(row.name, m.name);
        assert_eq!(
            (row.instances, row.per_instance, row.total),
            (
                m.instances,
                m.patches_per_instance,
                m.instances * m.patches_per_instance
            ),
            "{}",
            m.name
        );
    }
    assert!(
        text.contains(&format!("{total}\n")),
        "{name}: the table's total line is stale"
    );
}

/// Runs `tools/<tool>/make.py` into a fresh scratch folder, which it returns.
fn run_make(tool: &str) -> PathBuf {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("bezier-subdiv-{tool}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let run = std::process::Command::new("python3")
        .arg(root.join(format!("tools/{tool}/make.py")))
        .arg(&out)
        .output()
        .unwrap_or_else(|e| panic!("python3 runs tools/{tool}/make.py: {e}"));
    common::cli::assert_success(&run, "");
    out
}

/// The herd is what `tools/herd/make.py` writes.
#[test]
fn the_herd_is_what_its_script_writes() {
    let out = run_make("herd");
    assert!(
        std::fs::read(out.join("herd.toml")).unwrap()
            == std::fs::read(scenes_dir().join("herd.toml")).unwrap(),
        "scenes/herd.toml is not what tools/herd/make.py writes: run it"
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The kitchen and its furniture cages are what `tools/kitchen/make.py`
/// writes: the script, not the files, is what gets edited.
#[test]
fn the_kitchen_is_what_its_script_writes() {
    let out = run_make("kitchen");
    let mut written = vec![out.join("kitchen.toml"), out.join("kitchen-displaced.toml")];
    for e in std::fs::read_dir(out.join("models")).unwrap() {
        written.push(e.unwrap().path());
    }
    assert!(
        written.len() > 5,
        "the script writes the scene and its cages"
    );
    for w in &written {
        let rel = w.strip_prefix(&out).unwrap();
        let shipped = std::fs::read(scenes_dir().join(rel))
            .unwrap_or_else(|e| panic!("scenes/{}: {e}", rel.display()));
        assert!(
            shipped == std::fs::read(w).unwrap(),
            "scenes/{} is not what tools/kitchen/make.py writes: run it",
            rel.display()
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn every_keyframe_sees_something() {
    for &(name, ..) in SCENES {
        let (scene, geo) = load(name);
        assert!(scene.frame_count() >= 1);
        for k in 0..scene.frame_count() {
            let cam = scene.frame_camera(k).unwrap();
            cam.check()
                .unwrap_or_else(|e| panic!("{name} frame {k}: {e}"));
            let vp = cam.view_params(SIZE.0, SIZE.1, scene.view.eps, scene.view.lambda);
            let res = subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, &vp, 2);
            assert!(res.stats.ready_quads > 0, "{name} frame {k} draws nothing");
        }
    }
}

#[test]
fn frame_zero_draws_every_model() {
    for &(name, ..) in SCENES {
        let (scene, geo) = load(name);
        let cam = scene.frame_camera(0).unwrap();
        let vp = cam.view_params(SIZE.0, SIZE.1, scene.view.eps, scene.view.lambda);
        let res = subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, &vp, 2);
        let mut per_model = vec![0u64; geo.models.len()];
        for q in &res.ready {
            per_model[(geo.flags[q.patch() as usize] >> PATCH_MODEL_SHIFT) as usize] += 1;
        }
        for (m, n) in geo.models.iter().zip(&per_model) {
            assert!(
                *n > 0,
                "{name}: model '{}' is entirely culled in frame 0",
                m.name
            );
        }
    }
}

#[test]
fn stats_writes_a_preview_and_refuses_a_bad_path_first() {
    let dir = std::env::temp_dir().join(format!("scenes-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("teapot.png");
    let mut args = StatsArgs::new(scenes_dir().join("teapot.toml"));
    args.size = (160, 90);
    args.preview = Some(png.clone());
    args.preview_shade = PreviewShade::Depth;
    let report = stats::run(&args).unwrap();
    assert_eq!(report.preview.as_deref(), Some(png.to_str().unwrap()));
    let img = image::open(&png).unwrap().to_rgba8();
    assert_eq!(img.dimensions(), (160, 90));
    let background = *img.get_pixel(0, 0);
    let drawn = img.pixels().filter(|p| **p != background).count();
    assert!(drawn > 500, "only {drawn} pixels drawn");

    // A missing directory is refused, by name, before any work is done.
    args.preview = Some(dir.join("no/such/dir/x.png"));
    args.scene = dir.join("no-such-scene.toml");
    let e = format!("{:#}", stats::run(&args).unwrap_err());
    assert!(
        e.contains("no/such/dir") && e.contains("does not exist"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The maps under scenes/textures/ are what `tools/textures/make.py`
/// writes, texel for texel (compared decoded: zlib's bytes may differ
/// between versions, the pixels may not).
#[test]
fn the_textures_are_what_their_script_writes() {
    let out = run_make("textures");
    let mut shipped: Vec<_> = std::fs::read_dir(scenes_dir().join("textures"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    shipped.sort();
    assert!(shipped.len() >= 2, "{shipped:?}");
    for name in &shipped {
        let written = out.join(name);
        let a = image::open(scenes_dir().join("textures").join(name)).unwrap();
        let b = image::open(&written)
            .unwrap_or_else(|e| panic!("the script does not write {name:?}: {e}"));
        assert!(
            a.to_rgba8() == b.to_rgba8(),
            "scenes/textures/{name:?} is not what tools/textures/make.py writes: run it"
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}
