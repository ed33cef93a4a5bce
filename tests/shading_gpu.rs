//! Shading normals on the GPU (lavapipe, validation on): every draw path
//! lights with the scene's tangent patches (`glsl/common/shading.glsl`),
//! so the normal image is the CPU's `ShadingPatch::normal` at each pixel's
//! patch parameters, and it no longer jumps across patch edges next to
//! extraordinary vertices.
//!
//! The checks look at images of the OpenSubdiv cages (`scenes/cages.toml`:
//! the xord sheets close up, the valence-64 pole from above) at 320×180:
//! `SHADE_NORMALS`, and the test modes that say what each pixel shows
//! (`SHADE_PATCH_ID`, `SHADE_PARAMS`, `SHADE_DISTANCE`).
//! `cargo test --release --test shading_gpu -- --nocapture` prints the
//! figures.

mod common;

use bezier_subdiv::constants::{SHADE_DISTANCE, SHADE_NORMALS, SHADE_PARAMS, SHADE_PATCH_ID};
use bezier_subdiv::draw::DrawPath;
use bezier_subdiv::frame::View;
use bezier_subdiv::methods::MethodOptions;
use bezier_subdiv::patch::shading::SHADING_BYTES_PER_PATCH;
use bezier_subdiv::renderer::Renderer;
use bezier_subdiv::scene::camera::Camera;
use bezier_subdiv::scene::geometry::SceneShading;
use glam::{DVec3, DVec4};

const SIZE: (u32, u32) = (320, 180);

/// The largest colour difference (per channel, 0..1) allowed between the
/// GPU's normal image and the CPU's shading normal at the pixel's own
/// patch and parameters (rounded to 1/4095): rounding to 8 bits is half a
/// step. Measured on lavapipe: 0.5/255 on every path; 48/255 with the
/// patches' own derivatives.
const MATCH: f32 = 3.0 / 255.0;

/// The largest colour step allowed across a patch border beyond the steps
/// beside it (`largest_jump`). Measured on lavapipe at 320×180: at most
/// 10/255 with the tangent patches, 81/255 with the patches' own
/// derivatives.
const JUMP: f32 = 30.0 / 255.0;

/// What the images say about each pixel.
struct Shot {
    /// n·½ + ½ (the shading normal turned towards the eye).
    color: Vec<[f32; 3]>,
    /// The base patch shown.
    patch: Vec<u32>,
    /// Its parameters there.
    uv: Vec<(f32, f32)>,
    /// The distance from the eye; infinite on the background.
    distance: Vec<f32>,
}

fn code(p: &[u8]) -> u32 {
    (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32
}

fn shoot(r: &mut Renderer, cam: &Camera) -> Shot {
    let scale = cam.far as f32;
    let view = View {
        distance_scale: scale,
        ..View::new(cam, SIZE, 1.0, 0.5, SHADE_NORMALS)
    };
    r.set_background([1.0; 4]);
    let mut image = |shade: u32| -> Vec<[u8; 4]> {
        r.render(&View { shade, ..view }).unwrap();
        let rgba = r.read_image().unwrap();
        rgba.chunks_exact(4)
            .map(|p| [p[0], p[1], p[2], p[3]])
            .collect()
    };
    let color = image(SHADE_NORMALS)
        .iter()
        .map(|p| [0, 1, 2].map(|k| p[k] as f32 / 255.0))
        .collect();
    let patch = image(SHADE_PATCH_ID).iter().map(|p| code(p)).collect();
    let uv = image(SHADE_PARAMS)
        .iter()
        .map(|p| {
            let c = code(p);
            ((c >> 12) as f32 / 4095.0, (c & 0xfff) as f32 / 4095.0)
        })
        .collect();
    let distance = image(SHADE_DISTANCE)
        .iter()
        .map(|p| {
            if p[..3] == [255, 255, 255] {
                f32::INFINITY
            } else {
                code(p) as f32 / 16_777_214.0 * scale
            }
        })
        .collect();
    Shot {
        color,
        patch,
        uv,
        distance,
    }
}

/// The unit vector from pixel `i`'s centre towards the eye.
fn to_eye(cam: &Camera, i: usize) -> DVec3 {
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let inv = cam.view_proj(SIZE.0, SIZE.1).inverse();
    let ndc = |k: usize, n: usize| (k as f64 + 0.5) / n as f64 * 2.0 - 1.0;
    let far = inv * DVec4::new(ndc(i % w, w), ndc(i / w, h), 1.0, 1.0);
    (cam.eye() - far.truncate() / far.w).normalize()
}

/// Pixels that show surface facing the eye (|n·v| ≥ 0.3 by the image's
/// own normal): silhouettes and folds, where the side a triangle shows and
/// the side its normal faces may differ, are left out.
fn facing(shot: &Shot, cam: &Camera) -> Vec<bool> {
    (0..shot.color.len())
        .map(|i| {
            let c = shot.color[i].map(|x| x as f64 * 2.0 - 1.0);
            let n = DVec3::from_array(c);
            shot.distance[i].is_finite() && n.dot(to_eye(cam, i)).abs() >= 0.3
        })
        .collect()
}

/// The largest difference between the normal image and the CPU's shading
/// normal at each facing pixel's patch and parameters, where it was
/// (pixel, patch, u, v), and how many pixels were compared.
fn largest_mismatch(
    shot: &Shot,
    cam: &Camera,
    shading: &SceneShading,
) -> (f32, (usize, u32, f32, f32), usize) {
    let ok = facing(shot, cam);
    let mut worst = (0.0f32, (0, 0, 0.0, 0.0));
    let mut compared = 0;
    for i in (0..ok.len()).filter(|&i| ok[i]) {
        let (p, (u, v)) = (shot.patch[i], shot.uv[i]);
        let mut n = shading
            .normal(p as usize, u, v)
            .as_dvec3()
            .normalize_or_zero();
        if n.dot(to_eye(cam, i)) < 0.0 {
            n = -n;
        }
        let want = (n * 0.5 + 0.5).as_vec3().to_array();
        compared += 1;
        for (got, want) in shot.color[i].iter().zip(want) {
            let diff = (got - want).abs();
            if diff > worst.0 {
                worst = (diff, (i, p, u, v));
            }
        }
    }
    (worst.0, worst.1, compared)
}

/// The largest colour step across a patch border on one stretch of
/// surface beyond the steps just before and after it: along rows and
/// columns, four facing pixels a, b | c, d with a and b on one patch, c and
/// d on another, both accepted by `on`, and no depth jump (1 %) between
/// them, give max(0, |c − b| − max(|b − a|, |d − c|)) (per channel, the
/// largest). A normal field that is continuous across the border steps
/// there about as much as beside it; one that jumps does not. Returns the
/// largest and the number of borders seen.
fn largest_jump(shot: &Shot, cam: &Camera, on: &dyn Fn(u32) -> bool) -> (f32, usize) {
    let (w, h) = (SIZE.0 as usize, SIZE.1 as usize);
    let ok = facing(shot, cam);
    let usable = |i: usize| ok[i] && on(shot.patch[i]);
    let step = |i: usize, j: usize| -> Option<f32> {
        let (a, b) = (shot.distance[i], shot.distance[j]);
        ((a - b).abs() <= 0.01 * a.min(b)).then(|| {
            (0..3)
                .map(|k| (shot.color[i][k] - shot.color[j][k]).abs())
                .fold(0.0, f32::max)
        })
    };
    let (mut worst, mut borders) = (0.0f32, 0);
    for y in 0..h {
        for x in 0..w {
            // Rows (stride 1) and columns (stride w) through pixel (x, y) = b.
            for (stride, room) in [(1, x >= 1 && x + 2 < w), (w, y >= 1 && y + 2 < h)] {
                if !room {
                    continue;
                }
                let b = y * w + x;
                let [a, c, d] = [b - stride, b + stride, b + 2 * stride];
                if ![a, b, c, d].into_iter().all(usable) {
                    continue;
                }
                let p = |i: usize| shot.patch[i];
                if p(a) != p(b) || p(c) != p(d) || p(b) == p(c) {
                    continue;
                }
                let (Some(ab), Some(bc), Some(cd)) = (step(a, b), step(b, c), step(c, d)) else {
                    continue;
                };
                borders += 1;
                worst = worst.max(bc - ab.max(cd));
            }
        }
    }
    (worst, borders)
}

/// On every draw path (mesh, fallback, the ground truth's grids) and both
/// views, the GPU's normal image is the CPU's shading normal at each
/// pixel's patch parameters, and across the xord sheets' patch borders
/// the colour steps no more than beside them (`JUMP`). The same renderers given
/// the patches' own derivatives as shading data (what the GPU lit with
/// before) fail both checks, so neither can pass by accident. The scene's
/// shading patches are counted in the renderer's memory.
#[test]
fn every_draw_path_shades_with_the_tangent_patches() {
    let gpu = common::gpu();
    let (scene, geo, shading) = common::scene_with_shading("cages.toml");
    let own = SceneShading::from_geometry(&geo.patches);
    // The xord sheets come first in the scene.
    let xord_patches = geo.models[0].patches_per_instance as u32;
    assert_eq!(geo.models[0].name, "xord_interior");
    let xord = |p: u32| p < xord_patches;
    // Key 1: the xord sheets close up; key 2: the valence-64 pole.
    let cams = [1, 2].map(|k| scene.frame_camera(k).unwrap());
    let runs: [(&str, DrawPath); 3] = [
        ("subdiv", DrawPath::Mesh),
        ("subdiv", DrawPath::Fallback),
        ("ground-truth", DrawPath::Mesh),
    ];
    for (method, path) in runs {
        let mut options = MethodOptions::new(path);
        options.per_method.ground_truth.grid = 16;
        let mut r = common::renderer(&gpu, &geo, method, SIZE, options);
        let what = format!("{method} ({path:?})");
        // The renderer starts with the own derivatives; the scene's
        // tangent patches replace them.
        r.set_geometry(&geo, &shading).unwrap();
        let memory = r.memory();
        let bytes = memory.iter().find(|(k, _)| *k == "shading_patches");
        assert_eq!(
            bytes.map(|b| b.1),
            Some((geo.patches.len() * SHADING_BYTES_PER_PATCH) as u64),
            "{what}: {memory:?}"
        );
        for (k, cam) in cams.iter().enumerate() {
            let key = k + 1;
            let shot = shoot(&mut r, cam);
            let (mismatch, at, compared) = largest_mismatch(&shot, cam, &shading);
            let (jump, borders) = largest_jump(&shot, cam, &xord);
            println!(
                "{what:<22} key {key} tangent patches: largest mismatch {:.1}/255 at {at:?} \
                 over {compared} pixels; largest excess step across xord patch borders \
                 {:.1}/255 over {borders} borders",
                mismatch * 255.0,
                jump * 255.0
            );
            assert!(compared > 5000, "{what} key {key}: {compared} pixels");
            assert!(mismatch <= MATCH, "{what} key {key}: {mismatch} at {at:?}");
            assert!(borders > 300, "{what} key {key}: {borders} borders");
            assert!(jump <= JUMP, "{what} key {key}: {jump}");
        }
        // The patches' own derivatives: what the image showed before.
        r.set_geometry(&geo, &own).unwrap();
        let shot = shoot(&mut r, &cams[0]);
        let (mismatch, _, _) = largest_mismatch(&shot, &cams[0], &shading);
        let (jump, _) = largest_jump(&shot, &cams[0], &xord);
        println!(
            "{what:<22} key 1 own derivatives: largest mismatch {:.1}/255, largest excess step {:.1}/255",
            mismatch * 255.0,
            jump * 255.0
        );
        assert!(mismatch > MATCH && jump > JUMP, "{what}: {mismatch} {jump}");
    }
    gpu.finish();
}
