//! `render`: one offscreen frame of a method to a PNG, with a JSON stats
//! file beside it.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context as _};
use serde_json::{json, Map, Value};

use super::{keyframe, GpuRequest, ViewRequest};
use crate::constants::{
    SHADE_DEPTH, SHADE_DISPLACEMENT, SHADE_NORMAL, SHADE_NORMALS, SHADE_TEXTURE, SHADE_UV,
    SHADE_WEDGES, SHADE_WIREFRAME,
};
use crate::eval::flip::{flip, FlipResult};
use crate::eval::ground_truth_image;
use crate::figures::{thousands, Timing};
use crate::files::{check_writable, commit, stage, temp_sibling};
use crate::frame::View;
use crate::gpu::write_png;
use crate::input::limits::GEOMETRY_BYTES_PER_PATCH;
use crate::patch::shading::SHADING_BYTES_PER_PATCH;
use crate::renderer::{FrameReport, Renderer};
use crate::scene::desc::Scene;

/// The background of rendered images.
pub const BACKGROUND: [f32; 4] = [0.09, 0.10, 0.12, 1.0];

/// Shading of the rendered image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Shade {
    /// Lit surface, with the shading normals (the scene's tangent patches,
    /// smooth across extraordinary vertices).
    Normal,
    /// Heat map of the QuadNode depth.
    Depth,
    /// The depth map with crack-closing wedges highlighted.
    Wedges,
    /// Lit surface with the outline of every drawn cell (QuadNodes, grid
    /// cells).
    Wireframe,
    /// The shading normal as colour.
    Normals,
    /// The texture coordinates (s, t) as red and green, with a checker of
    /// eighths in blue: a cage's UVs through the conversion, else each
    /// patch's own (u, v).
    Uv,
    /// The albedo unlit: each model's map where it has one (MTL `map_Kd` or
    /// the scene's `texture`), else its tint.
    Texture,
    /// The height of each displaced model's map at the surface, dark blue
    /// (0) to yellow (1), unlit: where the surface is moved by bias +
    /// scale·height; grey where a model is not displaced.
    Displacement,
}

impl Shade {
    /// The shader's `SHADE_*` value.
    pub fn code(self) -> u32 {
        match self {
            Shade::Normal => SHADE_NORMAL,
            Shade::Depth => SHADE_DEPTH,
            Shade::Wedges => SHADE_WEDGES,
            Shade::Wireframe => SHADE_WIREFRAME,
            Shade::Normals => SHADE_NORMALS,
            Shade::Uv => SHADE_UV,
            Shade::Texture => SHADE_TEXTURE,
            Shade::Displacement => SHADE_DISPLACEMENT,
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Shade::Normal => "normal",
            Shade::Depth => "depth",
            Shade::Wedges => "wedges",
            Shade::Wireframe => "wireframe",
            Shade::Normals => "normals",
            Shade::Uv => "uv",
            Shade::Texture => "texture",
            Shade::Displacement => "displacement",
        }
    }
}

/// What `render` is asked for.
#[derive(Clone, Debug)]
pub struct RenderArgs {
    /// Scene, method, tolerance, image, device.
    pub gpu: GpuRequest,
    /// Keyframe (0 = the scene camera).
    pub frame: usize,
    /// Shading.
    pub shade: Shade,
    /// Output PNG (`None`: `out/<scene name>.png`).
    pub out: Option<PathBuf>,
    /// Untimed frames drawn first (the shader caches' and the driver's
    /// first-use costs go there); 0 times the first, cold frame; `None`:
    /// [`default_warmup`].
    pub warmup: Option<u32>,
    /// Timed frames whose medians are reported (0: the one frame).
    pub repeat: u32,
    /// Also compare with `ground-truth` of the same view: the mean FLIP
    /// goes into the stats, the heat map beside the image.
    pub flip: bool,
}

/// The JSON stats path for an image path: same name, `.json`.
pub fn stats_path(png: &Path) -> PathBuf {
    png.with_extension("json")
}

/// The FLIP heat map path for an image path: `NAME.flip.png`.
pub fn flip_path(png: &Path) -> PathBuf {
    png.with_extension("flip.png")
}

/// The mean FLIP of an image against its ground truth, and its heat map.
pub(crate) struct FlipOutput {
    result: FlipResult,
    /// Grid cells per patch side of the reference.
    grid: u32,
    /// The geometric error against the same reference (distance images).
    geometry: crate::eval::geometry::Breakdown,
}

/// The commit this binary was built from (short hash, `-dirty` when the
/// tracked files differed from it; see `build.rs`).
pub fn commit_id() -> &'static str {
    env!("BEZIER_SUBDIV_COMMIT")
}

/// Renders and writes the PNG and its JSON; returns a short summary. A
/// failure leaves nothing behind: not even the default `out/` directory
/// where this run made it.
pub fn run(args: &RenderArgs) -> anyhow::Result<String> {
    let method = args.gpu.method_info()?;
    let scene = Scene::load(&args.gpu.scene)?;
    let camera = keyframe(&scene, &args.gpu.scene, args.frame)?;
    let ViewRequest { eps, lambda, split } = args.gpu.view_request(&scene)?;
    let made = args.out.is_none() && !Path::new(super::DEFAULT_OUT_DIR).exists();
    let paths = output_paths(args, &scene)?;
    let done = render_to(args, method, &scene, &camera, (eps, lambda, split), paths);
    if done.is_err() && made {
        // Only if still empty.
        let _ = std::fs::remove_dir(super::DEFAULT_OUT_DIR);
    }
    done
}

/// [`run`] once the request is checked and the output paths are known.
fn render_to(
    args: &RenderArgs,
    method: &crate::methods::MethodInfo,
    scene: &Scene,
    camera: &crate::scene::camera::Camera,
    (eps, lambda, split): (f64, f64, crate::patch::view::Split),
    (out, json_path, heat_path): (PathBuf, PathBuf, Option<PathBuf>),
) -> anyhow::Result<String> {
    let loaded = scene
        .load_animated()
        .with_context(|| format!("loading the models of {}", args.gpu.scene.display()))?;
    args.gpu.seconds(loaded.animation.as_ref())?;
    super::note_undisplaced(&loaded.geometry, std::slice::from_ref(&args.gpu.method));

    let ctx = args.gpu.context()?;
    let mut renderer = args.gpu.renderer(&ctx, &loaded.geometry, &loaded.shading)?;
    args.gpu.animate(&mut renderer, loaded.animation.as_ref())?;
    renderer.set_progress(super::progress::parts_bar());
    let mut view = View::new(camera, args.gpu.size, eps, lambda, args.shade.code());
    view.params.flags |= split.flag();
    let warmup = args.warmup.unwrap_or_else(|| default_warmup(method.name));
    let frames = timed_frames(&mut renderer, &view, warmup, args.repeat)?;
    let report = &frames.report;
    let timing = frames.timing.as_ref();
    let rgba = renderer.read_image()?;
    let (w, h) = args.gpu.size;
    let flipped = if args.flip {
        Some(compare_with_ground_truth(
            &mut renderer,
            &view,
            camera,
            (w, h),
            &rgba,
        )?)
    } else {
        None
    };
    if args.gpu.validation {
        ctx.check_validation()?;
    }

    let mut stats = stats_json(args, scene, eps, lambda, &renderer, report);
    add_frames(&mut stats, &frames, warmup);
    if let Some(f) = &flipped {
        add_flip(&mut stats, f, eps);
    }
    let heat = flipped.as_ref().zip(heat_path.as_deref());
    write_outputs(&out, &json_path, (w, h), &rgba, &stats, heat)?;
    let info = ctx.info();
    let s = &report.stats;
    let wedges = s.get_u64("wedge_triangles");
    let flip_line = match (&flipped, &heat_path) {
        (Some(f), Some(p)) => flip_summary(f, p, eps),
        _ => String::new(),
    };
    let frame_ms = timing
        .and_then(|t| t.scopes.iter().find(|s| s.0 == "frame").map(|s| s.1))
        .or_else(|| report.ms("frame"))
        .unwrap_or(0.0);
    let occlusion = occlusion_summary(report);
    let lod = if report.lod.bytes > 0 {
        format!(
            ", levels of detail on ({} instances, {} triangles of them, {} hidden)",
            thousands(report.lod.instances),
            thousands(report.lod.triangles),
            thousands(report.lod.occluded)
        )
    } else {
        String::new()
    };
    Ok(format!(
        "{} ({}) on {}{}, {} path{occlusion}{lod}: {} triangles{}, {:.3} ms GPU{}{}\n{flip_line}wrote {} and {}\n",
        args.gpu.scene.display(),
        method.name,
        info.name,
        if info.is_cpu { " (CPU device)" } else { "" },
        report.draw_path,
        thousands(report.triangles()),
        wedges.map_or(String::new(), |w| format!(
            " ({:.1} % wedges)",
            100.0 * w as f64 / s.triangles.max(1) as f64
        )),
        frame_ms,
        if args.repeat > 0 {
            format!(" (median of {})", args.repeat)
        } else {
            String::new()
        },
        warmth(warmup, frames.cold.as_ref().map(|(ms, _)| &ms[..])),
        out.display(),
        json_path.display()
    ))
}

/// The image, stats and (with `--flip`) heat map paths, checked before
/// any GPU work.
fn output_paths(
    args: &RenderArgs,
    scene: &Scene,
) -> anyhow::Result<(PathBuf, PathBuf, Option<PathBuf>)> {
    let out = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(super::DEFAULT_OUT_DIR).join(format!("{}.png", scene.name))
    });
    check_writable(&out, args.out.is_none()).map_err(|e| anyhow!(e))?;
    let json_path = stats_path(&out);
    let heat_path = args.flip.then(|| flip_path(&out));
    if let Some(p) = &heat_path {
        check_writable(p, false).map_err(|e| anyhow!(e))?;
    }
    Ok((out, json_path, heat_path))
}

/// Compares the image `rgba` (`w` × `h`) of `view` with the ground truth's: the mean
/// FLIP and its heat map, and the geometric error.
fn compare_with_ground_truth(
    renderer: &mut Renderer,
    view: &View,
    camera: &crate::scene::camera::Camera,
    (w, h): (u32, u32),
    rgba: &[u8],
) -> anyhow::Result<FlipOutput> {
    let reference = ground_truth_image(renderer, view)?;
    let result = flip(&reference, rgba, w, h)
        .ok_or_else(|| anyhow!("FLIP: the reference and the image differ in size"))?;
    let geometry = crate::eval::geometric_error(renderer, view, camera, &result.errors)?;
    Ok(FlipOutput {
        result,
        grid: renderer.options().per_method.reference_grid(),
        geometry,
    })
}

/// Adds to the stats what the frames drawn say beyond the last one: the
/// medians of repeated frames, the warm-up and the cold frame's times.
fn add_frames(stats: &mut Value, frames: &Frames, warmup: u32) {
    if let Some(t) = &frames.timing {
        add_timing(stats, t);
    }
    stats["warmup_frames"] = json!(warmup);
    stats["timed_frame_compiled"] = json!(frames.timed_compiled);
    if let Some((cold, compiled)) = &frames.cold {
        stats["gpu_ms_cold"] = gpu_ms_json(cold);
        stats["cold_frame_compiled"] = json!(compiled);
    }
}

/// Adds the comparison with the ground truth to the stats.
fn add_flip(stats: &mut Value, f: &FlipOutput, eps: f64) {
    stats["flip_mean"] = json!(f.result.mean);
    stats["flip_reference"] = json!({ "method": crate::methods::reference().name, "grid": f.grid });
    let g = &f.geometry;
    stats["geometric_error"] = json!({
        "mean_px": g.geo_mean_px,
        "p99_px": g.geo_p99_px,
        "pixels": g.geo_pixels,
        "silhouette_diff_px": g.silhouette_diff_px,
        "flip_silhouette_share": g.flip_silhouette_share,
        "eps": eps,
    });
}

/// The summary's lines on the comparison with the ground truth (heat map
/// at `heat_path`).
fn flip_summary(f: &FlipOutput, heat_path: &Path, eps: f64) -> String {
    format!(
        "FLIP mean {:.4} against ground-truth (grid {}); heat map {}\n\
         geometric error {:.3} px mean, {:.3} px p99 off silhouettes (ε {eps}), \
         {} silhouette pixels differ\n",
        f.result.mean,
        f.grid,
        heat_path.display(),
        f.geometry.geo_mean_px,
        f.geometry.geo_p99_px,
        thousands(f.geometry.silhouette_diff_px),
    )
}

/// The summary's note on occlusion culling, when it was on.
fn occlusion_summary(report: &FrameReport) -> String {
    match report.stats.own.iter().find(|(k, _)| *k == "occlusion") {
        Some((_, v)) if v == &serde_json::Value::Bool(true) => format!(
            ", occlusion culling on ({} instances hidden)",
            report.stats.get_u64("instances_occluded").unwrap_or(0)
        ),
        _ => String::new(),
    }
}

/// Warm-up frames `render` draws unless told: 1, so the figures are not the
/// shader compiler's; none for the ground truth, whose image is what it is
/// for (its frames are the longest).
pub fn default_warmup(method: &str) -> u32 {
    u32::from(method != crate::methods::reference().name)
}

/// The frames `render` draws: `warmup` untimed ones (the first of them
/// kept as the cold figure), then the timed one, or `repeat` timed ones
/// summarised by their medians.
struct Frames {
    /// The last timed frame.
    report: FrameReport,
    /// Medians over `repeat` timed frames.
    timing: Option<Timing>,
    /// GPU time per scope of the first frame, when it was not the one
    /// timed, and whether it ran a pipeline for the first time.
    cold: Option<(Vec<(String, f64)>, bool)>,
    /// Whether a timed frame ran a pipeline for the first time (on a device
    /// that compiles at first use, its time includes the compile).
    timed_compiled: bool,
}

fn timed_frames(
    renderer: &mut Renderer,
    view: &View,
    warmup: u32,
    repeat: u32,
) -> anyhow::Result<Frames> {
    let mut cold = None;
    for k in 0..warmup {
        let first = renderer.render(view)?;
        if k == 0 {
            cold = Some((first.gpu_ms, first.compiled));
        }
    }
    let mut report = renderer.render(view)?;
    let mut times = vec![report.gpu_ms.clone()];
    let mut timed_compiled = report.compiled;
    for _ in 1..repeat {
        report = renderer.render(view)?;
        times.push(report.gpu_ms.clone());
        timed_compiled |= report.compiled;
    }
    Ok(Frames {
        report,
        timing: (repeat > 0).then(|| Timing::of(&times)),
        cold,
        timed_compiled,
    })
}

/// How the summary says which frame was timed.
fn warmth(warmup: u32, cold: Option<&[(String, f64)]>) -> String {
    let first = cold.and_then(|c| c.iter().find(|(n, _)| n == "frame").map(|(_, ms)| *ms));
    match first {
        Some(ms) => format!(
            ", after {warmup} warm-up frame{} (the first took {ms:.3} ms)",
            if warmup == 1 { "" } else { "s" }
        ),
        None => " (the first frame: cold)".into(),
    }
}

/// GPU milliseconds per scope as a JSON object.
fn gpu_ms_json(ms: &[(String, f64)]) -> Value {
    Value::Object(ms.iter().map(|(n, v)| (n.clone(), json!(v))).collect())
}

/// Replaces `gpu_ms` with the medians of repeated frames and adds their
/// minima and maxima.
fn add_timing(stats: &mut Value, t: &Timing) {
    let pick = |k: usize| -> Map<String, Value> {
        t.scopes
            .iter()
            .map(|s| {
                let v = [s.1, s.2, s.3][k];
                (s.0.clone(), json!(v))
            })
            .collect()
    };
    stats["gpu_ms"] = Value::Object(pick(0));
    stats["gpu_ms_min"] = Value::Object(pick(1));
    stats["gpu_ms_max"] = Value::Object(pick(2));
    stats["repeat"] = json!(t.frames);
}

/// Writes the image, its stats and (with `--flip`) the FLIP heat map as
/// one set: all appear or none.
pub(crate) fn write_outputs(
    png: &Path,
    json_path: &Path,
    (w, h): (u32, u32),
    rgba: &[u8],
    stats: &Value,
    heat: Option<(&FlipOutput, &Path)>,
) -> anyhow::Result<()> {
    let mut staged: Vec<(PathBuf, PathBuf)> = Vec::new();
    let result = (|| -> anyhow::Result<()> {
        let tmp_png = temp_sibling(png);
        staged.push((tmp_png.clone(), png.to_path_buf()));
        write_png(&tmp_png, w, h, rgba)?;
        if let Some((f, path)) = heat {
            let tmp = temp_sibling(path);
            staged.push((tmp.clone(), path.to_path_buf()));
            f.result.save_heat_map(&tmp)?;
        }
        let json = serde_json::to_string_pretty(stats)? + "\n";
        let tmp_json = stage(json_path, json.as_bytes())
            .with_context(|| format!("writing {}", json_path.display()))?;
        staged.push((tmp_json, json_path.to_path_buf()));
        Ok(())
    })();
    if let Err(e) = result {
        for (tmp, _) in &staged {
            let _ = std::fs::remove_file(tmp);
        }
        return Err(e);
    }
    commit(&staged)
        .map_err(|(file, e)| anyhow::Error::new(e).context(format!("writing {}", file.display())))
}

/// The stats file: the run's setup, the common keys, GPU time per pass,
/// memory per purpose (and the scene's per base patch), and the method's
/// own figures under `method_stats`.
pub(crate) fn stats_json(
    args: &RenderArgs,
    scene: &Scene,
    eps: f64,
    lambda: f64,
    renderer: &Renderer,
    report: &FrameReport,
) -> Value {
    let info = renderer.context().info();
    let memory: Map<String, Value> = renderer
        .memory()
        .into_iter()
        .map(|(name, bytes)| (name.to_string(), json!(bytes)))
        .collect();
    let mut own: Map<String, Value> = report
        .stats
        .own
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    // The method's own count beside the query's, where it keeps one, and
    // the query's own figure where the method drew placeholders (the
    // fallback path's degenerate wedge slots), which `triangles` leaves out.
    if let Some((_, primitives)) = report.primitives {
        if report.stats.triangles > 0 {
            own.insert("method_triangles".into(), json!(report.stats.triangles));
        }
        if report.stats.placeholder_triangles > 0 {
            own.insert("query_primitives".into(), json!(primitives));
        }
    }
    json!({
        "scene": args.gpu.scene.display().to_string(),
        "scene_name": scene.name,
        "frame": args.frame,
        "width": args.gpu.size.0,
        "height": args.gpu.size.1,
        "device": info.name,
        "device_is_cpu": info.is_cpu,
        "driver": format!("{} {}", info.driver_name, info.driver_info),
        "method": report.method,
        "draw_path": report.draw_path,
        "shade": args.shade.name(),
        "msaa": renderer.target().samples().as_raw(),
        "eps": eps,
        "lambda": lambda,
        "l_max": crate::constants::L_MAX,
        "commit": commit_id(),
        "patches": renderer.scene().count,
        "model_patches": renderer.scene().model_patches,
        "instances": renderer.scene().instance_count,
        "triangles": report.triangles(),
        "triangles_source": report.triangles_source(),
        "culled_patches": report.stats.culled_patches,
        "frames_redone": report.redone,
        "gpu_ms": gpu_ms_json(&report.gpu_ms),
        "memory_bytes": memory,
        "memory_per_patch_bytes": {
            "base_patches": GEOMETRY_BYTES_PER_PATCH,
            "shading_patches": SHADING_BYTES_PER_PATCH,
        },
        "memory_per_instance_bytes": crate::scene::instances::GPU_BYTES_PER_INSTANCE,
        "method_stats": own,
        "levels_of_detail": renderer.levels().map(|l| levels_json(l, &report.lod)),
        "animation": renderer.animation().map(|a| json!({
            "time": renderer.time(),
            "wrapped_time": a.wrap(renderer.time()),
            "duration": a.duration,
            "fps": a.fps,
            "models": a.models.len(),
            "keyed_instances": a.keyed.len(),
            "vertices": a.vertices(),
            "patches": a.patches(),
        })),
    })
}

/// The levels of detail made for the scene (per model: each level's
/// triangles, vertices, measured error and bytes) and what they drew in
/// the frame.
fn levels_json(levels: &crate::lod::SceneLevels, frame: &crate::lod::gpu::LodFrame) -> Value {
    let models: Vec<Value> = levels
        .models
        .iter()
        .map(|m| {
            let each: Vec<Value> = m
                .levels
                .iter()
                .map(|l| {
                    json!({
                        "triangles": l.mesh.triangles(),
                        "vertices": l.mesh.positions.len(),
                        "error": l.error,
                        "normal_error_deg": l.normal_error.to_degrees(),
                        "normal_error_deg_by_footprint": l
                            .shading
                            .iter()
                            .map(|&(side, e)| [side, e.to_degrees()])
                            .collect::<Vec<_>>(),
                        "target": l.target,
                        "simplifier_error": l.simplifier_error,
                        "bytes": l.bytes(),
                    })
                })
                .collect();
            json!({
                "first_model_patch": m.source,
                "patches": m.count,
                "patch_bytes": m.patch_bytes(),
                "levels": each,
                "none_because": m.none_because,
            })
        })
        .collect();
    json!({
        "instances": frame.instances,
        "triangles": frame.triangles,
        "occluded": frame.occluded,
        "by_level": frame.by_level,
        "bytes": frame.bytes,
        "models": models,
    })
}
