//! Shared machinery of tests/draw.rs: scenes and views with the oracle's
//! ready list, uploading it with the indirect arguments the subdivision pass
//! would write, drawing with both paths, and the bit-for-bit checks of the
//! drawn positions against the oracle.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use ash::vk;
use glam::{DVec3, Vec3};

use bezier_subdiv::constants::*;
use bezier_subdiv::draw::{DrawPath, ReadyCaps, ReadyStage};
use bezier_subdiv::frame::{headlight, FrameRec, Retired, View};
use bezier_subdiv::gpu::{write_png, DrawTarget, SceneGpu, SceneLayout, Shaders};
use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::patch::oracle::{node_positions, subdivide, triangulate};
use bezier_subdiv::patch::quadnode::QuadNode;
use bezier_subdiv::patch::shading::ShadingPatch;
use bezier_subdiv::patch::view::ViewParams;
use bezier_subdiv::patch::wedge::{node_mesh, wedge_code, wedge_pivots};
use bezier_subdiv::scene::camera::Camera;
use bezier_subdiv::scene::desc::Scene;
use bezier_subdiv::scene::geometry::load_model;
use bezier_subdiv::vk::{Buffer, Context, GpuTimer, MemoryLocation};

use super::common;

pub const W: u32 = 320;
pub const H: u32 = 240;
/// A background no shading mode produces, so it can be counted.
pub const BG: [f32; 4] = [0.2, 0.0, 0.4, 1.0];
pub const BG_RGBA: [u8; 4] = [51, 0, 102, 255];
pub const WHITE: [u8; 4] = [255, 255, 255, 255];
pub const GREEN: [u8; 4] = [0, 255, 0, 255];
/// Marks capture and vertex words nobody wrote.
pub const SENTINEL: u32 = u32::MAX;
pub const PATHS: [DrawPath; 2] = [DrawPath::Mesh, DrawPath::Fallback];

pub fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Where failures' images go: Cargo's scratch directory for integration
/// tests, never the source tree (the suite runs from a read-only checkout).
pub fn out_dir() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("draw");
    std::fs::create_dir_all(&dir).expect("create the test output directory");
    dir
}

/// One scene and view, with the oracle's ready list for it.
#[derive(Clone)]
pub struct Case {
    pub name: String,
    pub patches: Vec<BezierPatch>,
    pub flags: Vec<u32>,
    pub camera: Camera,
    pub vp: ViewParams,
    pub ready: Vec<QuadNode>,
}

impl Case {
    /// ε = 1, λ = 0.5 (the teapot scene's), view flags `off` cleared.
    pub fn new(
        name: &str,
        patches: Vec<BezierPatch>,
        flags: Vec<u32>,
        camera: Camera,
        off: u32,
    ) -> Self {
        let mut vp = camera.view_params(W, H, 1.0, 0.5);
        vp.flags &= !off;
        let ready = subdivide(&patches, &flags, &vp).ready;
        assert!(!ready.is_empty(), "{name}: nothing to draw");
        let name = name.into();
        Case {
            name,
            patches,
            flags,
            camera,
            vp,
            ready,
        }
    }

    /// The same view subdivided with 1:2 splits (`--split aniso`): the
    /// oracle's ready list again, under FLAG_ANISO.
    pub fn aniso(&self, name: &str) -> Self {
        let mut vp = self.vp;
        vp.flags |= FLAG_ANISO;
        let ready = subdivide(&self.patches, &self.flags, &vp).ready;
        Case {
            name: name.into(),
            vp,
            ready,
            ..self.clone()
        }
    }

    /// The same ready list seen with other view flags.
    pub fn with_flags(&self, name: &str, flags: u32) -> Self {
        let mut c = Case {
            name: name.into(),
            ..self.clone()
        };
        c.vp.flags = flags;
        c
    }

    pub fn wedges(&self) -> bool {
        self.vp.flags & FLAG_WEDGES != 0
    }
}

/// The teapot scene's keyframe `frame` (its ε and λ are the defaults 1, 0.5).
pub fn teapot(frame: usize, name: &str) -> Case {
    let scene = Scene::load(&root().join("scenes/teapot.toml")).expect("teapot scene");
    assert_eq!((scene.view.eps, scene.view.lambda), (1.0, 0.5));
    let geo = scene.geometry().expect("teapot geometry");
    let camera = scene.frame_camera(frame).expect("teapot frame");
    Case::new(name, geo.patches, geo.flags, camera, 0)
}

pub fn model(file: &str, model_index: u32) -> (Vec<BezierPatch>, Vec<u32>) {
    let patches = load_model(&root().join("scenes/models").join(file))
        .unwrap_or_else(|e| panic!("{e}"))
        .patches;
    let flags = vec![model_index << PATCH_MODEL_SHIFT; patches.len()];
    (patches, flags)
}

pub fn bounds(patches: &[BezierPatch]) -> (DVec3, f64) {
    let (lo, hi) = BezierPatch::bounds(patches).unwrap();
    (((lo + hi) * 0.5).as_dvec3(), (hi - lo).length() as f64)
}

/// Looking at the model from `dir` (in units of its bounding-box diagonal).
pub fn outside_camera(patches: &[BezierPatch], dir: DVec3) -> Camera {
    let (c, r) = bounds(patches);
    Camera {
        position: (c + dir * r).to_array(),
        target: c.to_array(),
        up: [0.0, 0.0, 1.0],
        fov_y_deg: 45.0,
        near: 0.01 * r,
        far: 100.0 * r,
    }
}

/// The converted torus and cube from an oblique view.
pub fn converted(file: &str, model_index: u32) -> Case {
    let (patches, flags) = model(file, model_index);
    let camera = outside_camera(&patches, DVec3::new(0.9, -1.2, 0.8));
    Case::new(file.trim_end_matches(".obj"), patches, flags, camera, 0)
}

/// Everything a test needs on the GPU, made once per test: a ready stage
/// per draw path (with a capture buffer), the target, and the pieces of a
/// frame recording.
pub struct Rig {
    pub ctx: Arc<Context>,
    pub scene_layout: SceneLayout,
    pub stages: Vec<ReadyStage>,
    pub target: DrawTarget,
    pub timer: GpuTimer,
    copy_out: Buffer,
}

impl Rig {
    pub fn new(gpu: &common::Gpu) -> Self {
        let ctx = gpu.arc();
        let scene_layout = SceneLayout::new(&ctx).expect("scene layout");
        let mut shaders = Shaders::default();
        let caps = ReadyCaps {
            ready: 1,
            vertices: true,
            capture: true,
            sort: false,
        };
        let stages = PATHS
            .iter()
            .map(|&p| {
                ReadyStage::new(&ctx, &mut shaders, &scene_layout, p, caps).expect("ready stage")
            })
            .collect();
        let target = DrawTarget::new(&ctx, W, H, BG).expect("draw target");
        let timer = GpuTimer::new(&ctx, 8).expect("timer");
        let copy_out = Buffer::new(
            &ctx,
            "rig copy-out",
            4096,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )
        .expect("copy-out");
        Rig {
            ctx,
            scene_layout,
            stages,
            target,
            timer,
            copy_out,
        }
    }

    pub fn stage(&mut self, path: DrawPath) -> &mut ReadyStage {
        self.stages.iter_mut().find(|s| s.path() == path).unwrap()
    }

    /// Uploads the case's patches (one frame slot, with its view).
    pub fn scene(&self, case: &Case) -> SceneGpu {
        let shading: Vec<ShadingPatch> = case
            .patches
            .iter()
            .map(ShadingPatch::from_geometry)
            .collect();
        let mut scene = SceneGpu::new(
            &self.ctx,
            &self.scene_layout,
            &case.patches,
            &case.flags,
            &shading,
            1,
        )
        .expect("upload scene");
        scene.set_view(&self.ctx, 0, &case.vp).expect("view");
        scene
    }

    /// Records `path`'s draw of what its stage holds into the target with a
    /// fresh frame recorder (slot 0, `capture` as given).
    pub fn draw(
        &mut self,
        scene: &SceneGpu,
        view: &View,
        path: DrawPath,
        capture: bool,
    ) -> Result<(), bezier_subdiv::methods::RenderError> {
        let ctx = Arc::clone(&self.ctx);
        let Rig {
            stages,
            target,
            timer,
            copy_out,
            ..
        } = self;
        let stage = stages.iter().find(|s| s.path() == path).unwrap();
        let mut retired = Retired::default();
        ctx.one_shot(|cmd| {
            timer.reset(cmd);
            let mut f = FrameRec::new(
                &ctx,
                cmd,
                0,
                scene,
                view,
                target,
                capture,
                &mut retired,
                timer,
                copy_out,
            );
            stage.record_draw(&mut f, false)
        })?;
        Ok(())
    }
}

/// The case's view in `shade`.
pub fn case_view(case: &Case, shade: u32) -> View {
    View {
        params: case.vp,
        view_proj: case.camera.view_proj(W, H),
        light_dir: headlight(&case.camera),
        shade,
        distance_scale: 0.0,
    }
}

/// What one draw produced.
pub struct Render {
    pub rgba: Vec<u8>,
    pub vertices: Vec<u32>,
    pub capture: Vec<u32>,
}

/// Uploads the case's ready list to `path`'s stage, clears its vertex and
/// capture buffers to the sentinel, draws, and reads everything back.
pub fn render(rig: &mut Rig, case: &Case, scene: &SceneGpu, path: DrawPath, shade: u32) -> Render {
    let ctx = Arc::clone(&rig.ctx);
    let mut retired = Retired::default();
    rig.stage(path)
        .upload(&ctx, &case.ready, &mut retired)
        .expect("upload ready list");
    {
        // Stale results of an earlier draw must not pass for this one's.
        let list = rig.stage(path).list();
        ctx.one_shot(|cmd| {
            for b in [&list.vertices, &list.capture] {
                unsafe {
                    ctx.device()
                        .cmd_fill_buffer(cmd, b.handle(), 0, vk::WHOLE_SIZE, SENTINEL)
                };
            }
            Ok(())
        })
        .expect("clear");
    }
    rig.draw(scene, &case_view(case, shade), path, true)
        .expect("draw");
    let rgba = rig.target.read_rgba(&ctx).expect("read image");
    let list = rig.stage(path).list();
    Render {
        rgba,
        vertices: list.vertices.read(&ctx).expect("read vertices"),
        capture: list.capture.read(&ctx).expect("read capture"),
    }
}

pub fn bits(v: Vec3) -> [u32; 3] {
    v.to_array().map(f32::to_bits)
}

/// The fallback's VERTICES_PER_NODE vertices per node equal the oracle's
/// `triangulate` output, slot for slot: quad, quad, then the wedge on each
/// edge (bottom, right, top, left), a missing wedge as three copies of
/// corner 0.
pub fn check_vertices(case: &Case, words: &[u32]) -> Result<(), String> {
    let tris = triangulate(&case.patches, &case.ready, case.wedges());
    let mut next = 0;
    for (i, &node) in case.ready.iter().enumerate() {
        let mesh = node_mesh(node, case.wedges());
        let own = &tris[next..next + mesh.tri_count];
        next += mesh.tri_count;
        let mut slots = [None; NODE_MESH_TRIS as usize];
        slots[0] = Some(own[0]);
        slots[1] = Some(own[1]);
        for (k, tri) in own.iter().enumerate().skip(2) {
            // A wedge's third vertex is its edge's pivot slot, 4 + edge.
            slots[2 + mesh.tris[k][2] as usize - 4] = Some(*tri);
        }
        // Corners 0, 1, 2 from the first quad triangle, 3 from the second.
        let corners = [own[0].v[0], own[0].v[1], own[0].v[2], own[1].v[2]];
        let eye = case.vp.eye.truncate();
        let pivots = wedge_pivots(node);
        let base = &case.patches[node.patch() as usize];
        for (t, slot) in slots.iter().enumerate() {
            let code = match (t, slot, pivots.get(t.wrapping_sub(2))) {
                (2.., Some(_), Some(&Some(pivot))) => {
                    wedge_code(node, corners, t - 2, pivot, eye, |u, v| base.eval(u, v))
                }
                _ => WEDGE_NONE,
            };
            for k in 0..3 {
                let (pos, uv) = match slot {
                    Some(tri) => (tri.v[k], tri.uv[k]),
                    None => (own[0].v[0], own[0].uv[0]),
                };
                let attrs = (uv.0 * 1024.0) as u32
                    | ((uv.1 * 1024.0) as u32) << PACK_V_SHIFT
                    | (node.du() | node.dv() << 4) << PACK_DEPTH_SHIFT
                    | code << PACK_WEDGE_SHIFT;
                let mut want = bits(pos).to_vec();
                want.extend([node.patch(), attrs]);
                let o = (i * VERTICES_PER_NODE as usize + 3 * t + k) * VERTEX_WORDS as usize;
                let got = &words[o..o + VERTEX_WORDS as usize];
                if got != want.as_slice() {
                    return Err(format!(
                        "{}: node {i} {node:?} slot {t} vertex {k}: GPU {got:x?}, oracle {want:x?}",
                        case.name
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The capture holds the oracle's positions for exactly the used vertex
/// slots (corners, plus the pivots of present wedges); other slots keep the
/// sentinel. Returns the number of wedge pivots seen.
pub fn check_capture(case: &Case, words: &[u32], path: DrawPath) -> Result<usize, String> {
    let mut pivots = 0;
    for (i, &node) in case.ready.iter().enumerate() {
        let mesh = node_mesh(node, case.wedges());
        let pos = node_positions(&case.patches[node.patch() as usize], &mesh);
        let used = |s: u8| s < 4 || mesh.tris[2..mesh.tri_count].iter().any(|t| t[2] == s);
        for s in 0..NODE_MESH_SLOTS as u8 {
            let o = (NODE_MESH_SLOTS as usize * i + s as usize) * 4;
            let got = &words[o..o + 4];
            let want: Vec<u32> = if used(s) {
                pivots += (s >= 4) as usize;
                let mut w = bits(pos[s as usize]).to_vec();
                w.push(1.0f32.to_bits());
                w
            } else {
                vec![SENTINEL; 4]
            };
            if got != want.as_slice() {
                return Err(format!(
                    "{} ({path}): node {i} {node:?} slot {s}: GPU {got:x?}, oracle {want:x?}",
                    case.name
                ));
            }
        }
    }
    Ok(pivots)
}

pub fn count_pixels(rgba: &[u8], colour: [u8; 4]) -> usize {
    rgba.chunks_exact(4).filter(|p| *p == colour).count()
}

/// Whether background touches pixel (x, y) (8-neighbourhood). Where front
/// and back faces meet edge-on at the outline, their interpolated depths are
/// nearly equal and rounding can let the back face win a pixel.
pub fn at_silhouette(rgba: &[u8], x: u32, y: u32) -> bool {
    let (x0, x1) = (x.saturating_sub(1), (x + 1).min(W - 1));
    let (y0, y1) = (y.saturating_sub(1), (y + 1).min(H - 1));
    (y0..=y1).any(|yy| (x0..=x1).any(|xx| rgba[4 * (yy * W + xx) as usize..][..4] == BG_RGBA))
}

/// SHADE_WEDGES paints wedges magenta (lit); nothing else there has g = 0
/// and r = b (the background is (51, 0, 102)).
pub fn is_wedge(p: &[u8]) -> bool {
    p[1] == 0 && p[0] == p[2] && p[0] > 0
}

/// Pixels that differ, and an image marking them (red on a dimmed copy of `a`).
pub fn diff(a: &[u8], b: &[u8]) -> (usize, Vec<u8>) {
    let mut n = 0;
    let mut img = Vec::with_capacity(a.len());
    for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        if pa == pb {
            img.extend([pa[0] / 3, pa[1] / 3, pa[2] / 3, 255]);
        } else {
            n += 1;
            img.extend([255, 0, 0, 255]);
        }
    }
    (n, img)
}

pub fn shade_name(shade: u32) -> &'static str {
    match shade {
        SHADE_NORMAL => "normal",
        SHADE_DEPTH => "depth",
        SHADE_WEDGES => "wedges",
        _ => "key",
    }
}

pub fn save(name: &str, rgba: &[u8]) {
    let path = out_dir().join(format!("{name}.png"));
    write_png(&path, W, H, rgba).unwrap_or_else(|e| panic!("{e}"));
}

/// Draws `case` with both paths in `shade`; checks positions against the
/// oracle and the two images against each other. Returns the two renders.
pub fn both_paths(rig: &mut Rig, case: &Case, shade: u32) -> [Render; 2] {
    let scene = rig.scene(case);
    let [mesh, fallback] = PATHS.map(|p| render(rig, case, &scene, p, shade));
    check_vertices(case, &fallback.vertices).unwrap_or_else(|e| panic!("{e}"));
    let pivots =
        check_capture(case, &mesh.capture, DrawPath::Mesh).unwrap_or_else(|e| panic!("{e}"));
    check_capture(case, &fallback.capture, DrawPath::Fallback).unwrap_or_else(|e| panic!("{e}"));
    let (differ, img) = diff(&mesh.rgba, &fallback.rgba);
    let label = format!("{}-{}", case.name, shade_name(shade));
    println!(
        "{label}: {} ready nodes, {} wedge pivots, positions equal the oracle bit for bit; \
         mesh vs fallback: {differ} of {} pixels differ",
        case.ready.len(),
        pivots,
        W * H
    );
    save(&format!("{label}-mesh"), &mesh.rgba);
    save(&format!("{label}-fallback"), &fallback.rgba);
    let diff_path = out_dir().join(format!("{label}-diff.png"));
    if differ > 0 {
        save(&format!("{label}-diff"), &img);
    } else {
        // A diff left over from an earlier run would mislead.
        let _ = std::fs::remove_file(diff_path);
    }
    assert!(
        differ * 1000 <= (W * H) as usize,
        "{label}: the paths differ in {differ} pixels (more than 0.1%)"
    );
    assert!(
        count_pixels(&mesh.rgba, BG_RGBA) < (W * H) as usize,
        "{label}: nothing was drawn"
    );
    [mesh, fallback]
}

/// Signed volume of a triangle soup: positive when the triangles wind
/// counter-clockwise about outward normals.
pub fn signed_volume(case: &Case) -> f64 {
    triangulate(&case.patches, &case.ready, true)
        .iter()
        .map(|t| {
            let [a, b, c] = t.v.map(|v| v.as_dvec3());
            a.dot(b.cross(c)) / 6.0
        })
        .sum()
}

/// Pixels of `colour` in a SHADE_FACING image `key` that neither lie on a
/// wedge (per the SHADE_WEDGES image `wedges` of the same view) nor touch the
/// background. A wedge's facing says nothing about the winding: where the
/// fine polyline dips below the coarse chord (saddles) the wedge folds over
/// and shows its other side.
pub fn unexplained(key: &[u8], wedges: &[u8], colour: [u8; 4]) -> Vec<(u32, u32)> {
    (0..W * H)
        .filter(|&i| key[4 * i as usize..][..4] == colour)
        .filter(|&i| !is_wedge(&wedges[4 * i as usize..][..4]))
        .map(|i| (i % W, i / W))
        .filter(|&(x, y)| !at_silhouette(key, x, y))
        .collect()
}
