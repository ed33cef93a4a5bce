//! Textured surfaces (issue 39) in every method: each samples the albedo
//! map at the texture coordinates the CPU twin gives, and texturing leaves
//! untextured models as they were.
//!
//! The sheet is tests/data/cages/grid_uv.obj (warped, seam-free UVs), once
//! as it is and once mirrored (a mirrored instance reads its model's UV
//! patch at (v, u)), under a map of 8 × 8 solid cells written here. Per
//! pixel, the patch (SHADE_PATCH_ID) and its (u, v) (SHADE_PARAMS) are read
//! back; `SceneGeometry::surface_uv` gives the texture coordinates, which
//! SHADE_UV must show (fract(s, t) as red and green), and SHADE_TEXTURE
//! must show the cell's colour wherever the coordinates lie well inside a
//! cell (filtering blends only near its borders; the sheet is seen at
//! about two texels per pixel, mip level 1 or 2, four or more texels from
//! any border).

mod common;

use bezier_subdiv::constants::{
    PATCH_MODEL_SHIFT, SHADE_NORMAL, SHADE_PARAMS, SHADE_PATCH_ID, SHADE_TEXTURE, SHADE_UV,
};
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::scene::geometry::SceneGeometry;
use bezier_subdiv::scene::material::SceneMaterials;

const SIZE: (u32, u32) = (320, 180);
const CELLS: u32 = 8;
const CELL_TEXELS: u32 = 32;

/// The colour of map cell (i, j), j counted from the bottom (t = 0).
fn cell_color(i: u32, j: u32) -> [u8; 3] {
    [
        (24 + 28 * i) as u8,
        (24 + 28 * j) as u8,
        if (i + j) % 2 == 0 { 200 } else { 60 },
    ]
}

/// The textured sheet scene, written to a scratch folder.
fn sheet_scene() -> (Scene, SceneGeometry) {
    sheet_scene_with("sheet.toml", "")
}

/// [`sheet_scene`] with `extra` model keys (a deformer), as `name`.
fn sheet_scene_with(name: &str, extra: &str) -> (Scene, SceneGeometry) {
    let dir = common::output_dir("textures");
    let side = CELLS * CELL_TEXELS;
    let map = image::RgbImage::from_fn(side, side, |x, y| {
        let (i, j) = (x / CELL_TEXELS, CELLS - 1 - y / CELL_TEXELS);
        image::Rgb(cell_color(i, j))
    });
    map.save(dir.join("cells.png")).unwrap();
    let model = common::repo_path("tests/data/cages/grid_uv.obj");
    let text = format!(
        r#"name = "textured sheet"
[camera]
position = [0.0, -0.35, 1.7]
target = [0.0, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 45.0
[[model]]
name = "sheet"
file = "{}"
texture = "cells.png"
two_sided = true
{extra}
[[model.instance]]
translate = [-1.05, 0.0, 0.0]
[[model.instance]]
scale = [-1.0, 1.0, 1.0]
translate = [1.05, 0.0, 0.0]
"#,
        model.display()
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path).unwrap();
    let geo = scene.geometry().unwrap();
    (scene, geo)
}

fn patch_of(px: &[u8]) -> usize {
    (px[0] as usize) << 16 | (px[1] as usize) << 8 | px[2] as usize
}

fn params_of(px: &[u8]) -> (f32, f32) {
    let code = (px[0] as u32) << 16 | (px[1] as u32) << 8 | px[2] as u32;
    ((code >> 12) as f32 / 4095.0, (code & 4095) as f32 / 4095.0)
}

/// Pixels a check looked at.
struct Seen {
    uv: usize,
    map: usize,
    mirrored: usize,
}

/// Draws `geo` with `method` and checks every pixel's texture coordinates
/// against the CPU twin and, with `cells` (the map of `cell_color`), its
/// albedo inside the cells; panics on a pixel off.
fn check_textured(
    gpu: &common::Gpu,
    camera: &bezier_subdiv::scene::camera::Camera,
    geo: &SceneGeometry,
    method: &str,
    draw: DrawPath,
    cells: bool,
) -> Seen {
    let mut r = common::renderer(gpu, geo, method, SIZE, MethodOptions::new(draw));
    check_drawn(&mut r, camera, geo, &format!("{method} ({draw:?})"), cells)
}

/// [`check_textured`] with a renderer made by the caller (`label` names it).
fn check_drawn(
    r: &mut bezier_subdiv::renderer::Renderer,
    camera: &bezier_subdiv::scene::camera::Camera,
    geo: &SceneGeometry,
    label: &str,
    cells: bool,
) -> Seen {
    r.set_background([1.0; 4]);
    let mut image = |shade: u32| {
        r.render(&View::new(camera, SIZE, 1.0, 0.5, shade)).unwrap();
        r.read_image().unwrap()
    };
    let ids = image(SHADE_PATCH_ID);
    let params = image(SHADE_PARAMS);
    let uvs = image(SHADE_UV);
    let albedo = image(SHADE_TEXTURE);
    let mut seen = Seen {
        uv: 0,
        map: 0,
        mirrored: 0,
    };
    let (mut uv_wrong, mut map_wrong) = (0, 0);
    // Each pixel's patch and texture coordinates (the CPU twin's).
    let at: Vec<Option<(usize, [f32; 2])>> = (0..ids.len() / 4)
        .map(|k| {
            let patch = patch_of(&ids[4 * k..]);
            (patch < geo.patches.len()).then(|| {
                let (u, v) = params_of(&params[4 * k..]);
                (patch, geo.surface_uv(patch, u, v))
            })
        })
        .collect();
    let width = SIZE.0 as usize;
    for k in 0..ids.len() / 4 {
        let px = |img: &[u8]| img[4 * k..4 * k + 3].to_vec();
        let Some((patch, st)) = at[k] else {
            continue; // the background
        };
        seen.mirrored += usize::from(geo.instances.locate(patch).0.mirrored());
        let f = st.map(|c| c - c.floor());
        if f.iter().all(|&c| c > 0.02 && c < 0.98) {
            seen.uv += 1;
            let got = px(&uvs);
            if (0..2).any(|c| (f32::from(got[c]) / 255.0 - f[c]).abs() > 3.0 / 255.0) {
                uv_wrong += 1;
            }
        }
        let cell = f.map(|c| c * CELLS as f32);
        let inside = cell.map(|c| c - c.floor());
        // Texels per pixel step, from the four neighbours, all on the same
        // patch (the quad the GPU differentiates over may reach past the
        // patch's edge): where a step spans more than 4 texels (level 2
        // and beyond, at a grazing angle or far away), a cell is too few
        // texels for its middle to keep its colour through filtering.
        let step = |n: Option<usize>| match n.and_then(|n| at.get(n)) {
            Some(Some((p, s))) if *p == patch => {
                Some((s[0] - st[0]).abs().max((s[1] - st[1]).abs()) * (CELLS * CELL_TEXELS) as f32)
            }
            _ => None,
        };
        let around = [
            k.checked_sub(1),
            Some(k + 1),
            k.checked_sub(width),
            Some(k + width),
        ];
        let fine = around
            .iter()
            .all(|&n| step(n).is_some_and(|texels| texels <= 4.0));
        if cells && fine && inside.iter().all(|&c| c > 0.25 && c < 0.75) {
            seen.map += 1;
            let want = cell_color(cell[0] as u32, cell[1] as u32);
            let got = px(&albedo);
            if (0..3).any(|c| (i32::from(got[c]) - i32::from(want[c])).abs() > 2) {
                map_wrong += 1;
            }
        }
    }
    println!(
        "{label}: UVs {uv_wrong} of {} pixels off, map {map_wrong} of {} off ({} pixels of a mirrored instance)",
        seen.uv, seen.map, seen.mirrored
    );
    assert_eq!(uv_wrong, 0, "{label}: texture coordinates");
    assert_eq!(map_wrong, 0, "{label}: albedo");
    seen
}

#[test]
fn every_method_samples_the_map_at_the_surfaces_uvs() {
    let gpu = common::gpu();
    let (scene, geo) = sheet_scene();
    assert_eq!(geo.materials.cage_uv_patches, 16);
    assert_eq!(geo.materials.textures.len(), 1);
    let camera = scene.frame_camera(0).unwrap();
    let cases = [
        ("subdiv", DrawPath::Mesh),
        ("subdiv", DrawPath::Fallback),
        ("subdiv-indirect", DrawPath::Mesh),
        ("tess", DrawPath::Mesh),
        ("tess-reparam", DrawPath::Mesh),
        ("cudatess", DrawPath::Mesh),
        ("ground-truth", DrawPath::Mesh),
        ("corners", DrawPath::Mesh),
    ];
    for (method, draw) in cases {
        let seen = check_textured(&gpu, &camera, &geo, method, draw, true);
        assert!(
            seen.uv > 5_000 && seen.map > 1_000,
            "{method}: too few pixels checked"
        );
        assert!(
            seen.mirrored > 2_000,
            "{method}: the mirrored instance must be in view"
        );
    }
    gpu.finish();
}

/// An animated cage keeps its texture coordinates: the sheet twisted by a
/// deformer (the GPU's update pass moves its patches) is still mapped by
/// its UV patches, pixel by pixel, and the frame did move.
#[test]
fn a_deformed_cage_keeps_its_uvs() {
    let gpu = common::gpu();
    let twist = "[[model.deform]]\nkind = \"twist\"\naxis = \"y\"\ncenter = [0.5, 0.5, 0.0]\nangle_deg = [[0.0, 0.0], [2.0, 80.0]]\nlength = 1.0";
    let (scene, _) = sheet_scene_with("twisted.toml", twist);
    let loaded = scene.load_animated().unwrap();
    assert!(loaded.animation.is_some(), "the sheet must move");
    let camera = scene.frame_camera(0).unwrap();
    let options = bezier_subdiv::renderer::RendererOptions {
        size: SIZE,
        background: [1.0; 4],
        frames_in_flight: 2,
        methods: MethodOptions::new(DrawPath::Mesh),
    };
    let mut r = bezier_subdiv::renderer::Renderer::new(
        gpu.arc(),
        &loaded.geometry,
        &loaded.shading,
        "subdiv",
        options,
    )
    .unwrap();
    r.set_animation(loaded.animation.clone()).unwrap();
    r.set_time(0.0);
    r.render(&View::new(&camera, SIZE, 1.0, 0.5, SHADE_PATCH_ID))
        .unwrap();
    let rest = r.read_image().unwrap();
    r.set_time(1.0);
    let seen = check_drawn(&mut r, &camera, &loaded.geometry, "twisted sheet", true);
    assert!(
        seen.uv > 5_000 && seen.map > 1_000,
        "too few pixels checked"
    );
    r.render(&View::new(&camera, SIZE, 1.0, 0.5, SHADE_PATCH_ID))
        .unwrap();
    assert!(
        r.read_image().unwrap() != rest,
        "the twist must move the sheet"
    );
    gpu.finish();
}

/// OpenSubdiv's face-varying shapes, whose UV layouts have seams (their
/// UV patches against OpenSubdiv's limit: tests/osd_reference.rs): the
/// GPU maps them by the same UV patches, seams included.
#[test]
fn cages_with_uv_seams_are_mapped_as_their_uv_patches_say() {
    let gpu = common::gpu();
    let (scene, geo) = fvar_scene();
    assert!(
        geo.materials.cage_uv_patches >= 60,
        "{}",
        geo.materials.cage_uv_patches
    );
    let camera = scene.frame_camera(0).unwrap();
    let seen = check_textured(&gpu, &camera, &geo, "subdiv", DrawPath::Mesh, true);
    assert!(seen.uv > 5_000 && seen.map > 500, "too few pixels checked");
    let mut models = std::collections::BTreeSet::new();
    gpu.finish();
    for m in &geo.models {
        models.insert(m.name.clone());
    }
    assert_eq!(models.len(), 5);
}

/// bound0..3 and project0 of OpenSubdiv's shapes under the cells map.
fn fvar_scene() -> (Scene, SceneGeometry) {
    sheet_scene(); // writes cells.png
    let dir = common::output_dir("textures");
    let shape = |n: &str| common::repo_path(&format!("tests/data/osd-fvar/catmark_fvar_{n}.obj"));
    let mut text = String::from(
        r#"name = "face-varying shapes"
[camera]
position = [0.0, -0.9, 3.3]
target = [0.0, 0.35, 0.0]
up = [0.0, 1.0, 0.0]
fov_y_deg = 45.0
"#,
    );
    let placed = [
        ("bound0", "translate = [-2.4, -0.6, 0.0]"),
        ("bound1", "translate = [-1.2, -0.6, 0.0]"),
        ("bound2", "translate = [0.0, -0.6, 0.0]"),
        ("bound3", "scale = 0.5\ntranslate = [1.7, -0.1, 0.0]"),
        ("project0", "scale = 0.16\ntranslate = [-0.2, 0.4, 0.0]"),
    ];
    for (name, place) in placed {
        text += &format!(
            "[[model]]\nname = \"{name}\"\nfile = \"{}\"\ntexture = \"cells.png\"\ntwo_sided = true\n[[model.instance]]\n{place}\n",
            shape(name).display()
        );
    }
    let path = dir.join("fvar.toml");
    std::fs::write(&path, text).unwrap();
    let scene = Scene::load(&path).unwrap();
    let geo = scene.geometry().unwrap();
    (scene, geo)
}

/// The kitchen's floor is textured (its material library names the map)
/// and nothing else in the kitchen changes: lit, every pixel of another
/// model is byte-identical to the same kitchen drawn without materials
/// (pipelines specialized not to read them), and most floor pixels differ.
#[test]
fn the_kitchen_floor_is_textured_and_nothing_else_changes() {
    let gpu = common::gpu();
    let (scene, geo) = common::scene("kitchen.toml");
    assert_eq!(geo.materials.model_texture[0], Some(0), "the floor's map");
    assert_eq!(geo.materials.model_texture.iter().flatten().count(), 1);
    let mut plain = geo.clone();
    plain.materials = SceneMaterials::default();
    let camera = scene.frame_camera(0).unwrap();
    let draw = |geo: &SceneGeometry, shade: u32| {
        let mut r = common::renderer(
            &gpu,
            geo,
            "subdiv",
            SIZE,
            MethodOptions::new(DrawPath::Mesh),
        );
        r.render(&View::new(&camera, SIZE, 1.0, 0.5, shade))
            .unwrap();
        r.read_image().unwrap()
    };
    let ids = draw(&geo, SHADE_PATCH_ID);
    let textured = draw(&geo, SHADE_NORMAL);
    let untextured = draw(&plain, SHADE_NORMAL);
    let (mut floor, mut floor_changed, mut other, mut other_changed) = (0, 0, 0, 0);
    for k in 0..ids.len() / 4 {
        let Some(flags) = geo.flags.get(patch_of(&ids[4 * k..])) else {
            continue;
        };
        let changed = textured[4 * k..4 * k + 4] != untextured[4 * k..4 * k + 4];
        if flags >> PATCH_MODEL_SHIFT == 0 {
            floor += 1;
            floor_changed += usize::from(changed);
        } else {
            other += 1;
            other_changed += usize::from(changed);
        }
    }
    println!("floor: {floor_changed} of {floor} pixels textured; others: {other_changed} of {other} changed");
    assert!(floor > 5_000 && other > 5_000);
    assert!(
        floor_changed * 10 > floor * 9,
        "the floor must show its map"
    );
    assert_eq!(other_changed, 0, "untextured models must not change");
    gpu.finish();
}

/// A map that cannot be read stops the scene with the model and the file
/// named: missing, not a PNG, or named by a material whose file is gone.
/// A material library that is not there is a warning, the model untextured.
#[test]
fn bad_maps_are_refused_with_the_model_and_the_file_named() {
    let dir = common::output_dir("textures-bad");
    let sheet = common::repo_path("tests/data/cages/grid_uv.obj");
    let scene_with = |model_file: &std::path::Path, texture: Option<&str>| {
        let texture = texture.map_or(String::new(), |t| format!("texture = \"{t}\"\n"));
        let text = format!(
            "[camera]\nposition = [0.0, -3.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\n[[model]]\nname = \"sheet\"\nfile = \"{}\"\n{texture}",
            model_file.display()
        );
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        Scene::load(&path).unwrap().geometry()
    };
    let e = scene_with(&sheet, Some("nope.png"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("'sheet'") && e.contains("nope.png"), "{e}");
    std::fs::write(dir.join("text.png"), "not an image").unwrap();
    let e = scene_with(&sheet, Some("text.png"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("text.png") && e.contains("PNG"), "{e}");

    let obj = std::fs::read_to_string(&sheet).unwrap();
    let with_material = format!("mtllib sheet.mtl\nusemtl painted\n{obj}");
    std::fs::write(dir.join("sheet.obj"), &with_material).unwrap();
    std::fs::write(dir.join("sheet.mtl"), "newmtl painted\nmap_Kd gone.png\n").unwrap();
    let e = scene_with(&dir.join("sheet.obj"), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("gone.png"), "{e}");

    std::fs::remove_file(dir.join("sheet.mtl")).unwrap();
    let geo = scene_with(&dir.join("sheet.obj"), None).unwrap();
    assert_eq!(geo.materials.model_texture, [None]);
    let warnings = &geo.models[0].warnings;
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("sheet.mtl") && w.contains("without its texture")),
        "{warnings:?}"
    );
}

/// scenes/textured.toml in every method: the albedo image (SHADE_TEXTURE)
/// of each is the ground truth's but for silhouettes and where the
/// surfaces differ within ε, and it shows the map (not the tint).
#[test]
fn every_method_draws_the_textured_scene_like_the_ground_truth() {
    let gpu = common::gpu();
    let (scene, geo) = common::scene("textured.toml");
    let camera = scene.frame_camera(0).unwrap();
    let draw = |method: &str| {
        let mut options = MethodOptions::new(DrawPath::Mesh);
        options.per_method.ground_truth.grid = 16;
        let mut r = common::renderer(&gpu, &geo, method, SIZE, options);
        r.render(&View::new(&camera, SIZE, 1.0, 0.5, SHADE_TEXTURE))
            .unwrap();
        r.read_image().unwrap()
    };
    let truth = draw("ground-truth");
    let pixels = truth.len() / 4;
    let background = truth[..4].to_vec();
    let covered = truth.chunks_exact(4).filter(|p| *p != background).count();
    let colours: std::collections::HashSet<&[u8]> = truth.chunks_exact(4).collect();
    println!(
        "ground truth: {covered} of {pixels} pixels covered, {} colours",
        colours.len()
    );
    assert!(
        covered > pixels / 10 && colours.len() > 500,
        "the map must show"
    );
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    // Away from silhouettes: the pixel and its eight neighbours covered in
    // both images (at a silhouette the surfaces may differ by ε).
    let inside = |img: &[u8], k: usize| {
        let (x, y) = (k % w, k / w);
        (x > 0 && y > 0 && x + 1 < w && y + 1 < h)
            && (0..9).all(|n| {
                let q = (y + n / 3 - 1) * w + (x + n % 3 - 1);
                img[4 * q..4 * q + 4] != background[..]
            })
    };
    for method in [
        "subdiv",
        "subdiv-indirect",
        "tess",
        "tess-reparam",
        "cudatess",
        "corners",
    ] {
        let image = draw(method);
        let (mut checked, mut off, mut sum) = (0, 0, 0u64);
        for k in 0..pixels {
            if !(inside(&truth, k) && inside(&image, k)) {
                continue;
            }
            checked += 1;
            let (a, b) = (&image[4 * k..4 * k + 3], &truth[4 * k..4 * k + 3]);
            let d = (0..3)
                .map(|c| (i32::from(a[c]) - i32::from(b[c])).unsigned_abs())
                .max()
                .unwrap();
            sum += u64::from(d);
            off += usize::from(d > 48);
        }
        let mean = sum as f64 / checked.max(1) as f64;
        println!(
            "{method}: {checked} pixels inside the silhouettes, mean difference {mean:.2}, {off} by more than 48"
        );
        // Inside the silhouettes the surfaces differ within ε, so the map
        // lands a little shifted (subdiv spends more of ε than tess: 6.9
        // against 3.4 here), plus occluding contours over other surfaces,
        // a pixel wide. corners draws chords, not within ε (36): it is
        // only held to drawing the map.
        assert!(checked > covered / 2, "{method}: {checked} pixels checked");
        if method != "corners" {
            assert!(mean <= 10.0, "{method}: mean difference {mean:.2}");
        }
    }
    gpu.finish();
}

/// Where two patches share an edge and their UVs agree along it, they
/// agree bit for bit (the UV patches' boundary control points are the
/// same floats on both sides): what a crack-free displacement across
/// patch edges will stand on (issue 40). Elsewhere the edge is a seam (of
/// the cage's layout, or between two patches' parametric mappings).
#[test]
fn uv_patches_share_their_bits_along_shared_edges() {
    use bezier_subdiv::scene::adjacency::edge_table;
    let side = |k: usize| match k {
        0 => [0, 4, 8, 12],
        1 => [0, 1, 2, 3],
        2 => [3, 7, 11, 15],
        _ => [12, 13, 14, 15],
    };
    for name in ["textured.toml", "kitchen.toml"] {
        let (_, geo) = common::scene(name);
        let table = edge_table(&geo.patches, &[]);
        let mut by_edge: std::collections::HashMap<u32, Vec<(usize, usize)>> = Default::default();
        for (p, ids) in table.ids.iter().enumerate() {
            for (k, id) in ids.iter().enumerate() {
                by_edge.entry(*id).or_default().push((p, k));
            }
        }
        // The UV control points along side k of base patch p, and its
        // first control point (to find which way the neighbour runs).
        let along = |(p, k): (usize, usize)| {
            let (instance, m) = geo.instances.locate(p);
            assert!(!instance.mirrored(), "{name}: no mirrored instance here");
            let uv: Vec<[f32; 2]> = side(k)
                .iter()
                .map(|&i| geo.materials.uv_patches[m][i])
                .collect();
            (uv, geo.patches[p].pts[side(k)[0]])
        };
        let (mut bitwise, mut close, mut seams) = (0, 0, 0);
        for sides in by_edge.values().filter(|s| s.len() == 2) {
            let ((a, start_a), (mut b, start_b)) = (along(sides[0]), along(sides[1]));
            if start_a != start_b {
                b.reverse();
            }
            let near = a
                .iter()
                .zip(&b)
                .all(|(x, y)| (x[0] - y[0]).abs() < 1e-5 && (x[1] - y[1]).abs() < 1e-5);
            match (a == b, near) {
                (true, _) => bitwise += 1,
                (false, true) => close += 1,
                (false, false) => seams += 1,
            }
        }
        println!("{name}: shared edges {bitwise} bitwise equal in UV, {close} close but not bitwise, {seams} seams");
        assert!(bitwise > 100, "{name}: {bitwise}");
        assert_eq!(close, 0, "{name}: UVs equal in value but not in bits");
    }
}
