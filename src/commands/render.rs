//! `render`: one offscreen frame of a method to a PNG, with a JSON stats
//! file beside it.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context as _};
use serde_json::{json, Map, Value};

use super::{eps_lambda, keyframe, thousands, GpuRequest};
use crate::constants::{SHADE_DEPTH, SHADE_NORMAL, SHADE_WEDGES};
use crate::files::{check_writable, commit, stage, temp_sibling};
use crate::frame::View;
use crate::gpu::write_png;
use crate::renderer::{FrameReport, Renderer};
use crate::scene::file::Scene;

/// The background of rendered images.
pub const BACKGROUND: [f32; 4] = [0.09, 0.10, 0.12, 1.0];

/// Shading of the rendered image.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Shade {
    /// Lit surface, normals from the base patches' own derivatives.
    Normal,
    /// Heat map of the QuadNode depth.
    Depth,
    /// The depth map with crack-closing wedges highlighted.
    Wedges,
}

impl Shade {
    /// The shader's `SHADE_*` value.
    pub fn code(self) -> u32 {
        match self {
            Shade::Normal => SHADE_NORMAL,
            Shade::Depth => SHADE_DEPTH,
            Shade::Wedges => SHADE_WEDGES,
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            Shade::Normal => "normal",
            Shade::Depth => "depth",
            Shade::Wedges => "wedges",
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
}

/// The JSON stats path for an image path: same name, `.json`.
pub fn stats_path(png: &Path) -> PathBuf {
    png.with_extension("json")
}

/// The commit this binary was built from (short hash, `-dirty` when the
/// tracked files differed from it; see `build.rs`).
pub fn commit_id() -> &'static str {
    env!("BEZIER_SUBDIV_COMMIT")
}

/// Renders and writes the PNG and its JSON; returns a short summary.
pub fn run(args: &RenderArgs) -> anyhow::Result<String> {
    let method = args.gpu.method_info()?;
    let scene = Scene::load(&args.gpu.scene)?;
    let camera = keyframe(&scene, &args.gpu.scene, args.frame)?;
    let (eps, lambda) = eps_lambda(&scene, args.gpu.eps, args.gpu.lambda)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(format!("{}.png", scene.name)));
    check_writable(&out, args.out.is_none()).map_err(|e| anyhow!(e))?;
    let json_path = stats_path(&out);
    let geo = scene
        .geometry()
        .with_context(|| format!("loading the models of {}", args.gpu.scene.display()))?;

    let ctx = args.gpu.context()?;
    let mut renderer = args.gpu.renderer(&ctx, &geo)?;
    let view = View::new(&camera, args.gpu.size, eps, lambda, args.shade.code());
    let report = renderer.render(&view)?;
    let rgba = renderer.read_image()?;
    if args.gpu.validation {
        ctx.check_validation()?;
    }

    let stats = stats_json(args, &scene, eps, lambda, &renderer, &report);
    let (w, h) = args.gpu.size;
    write_outputs(&out, &json_path, (w, h), &rgba, &stats)?;
    let info = ctx.info();
    let s = &report.stats;
    let wedges = s.get_u64("wedge_triangles");
    Ok(format!(
        "{} ({}) on {}{}, {} path: {} triangles{}, {:.2} ms GPU\nwrote {} and {}\n",
        args.gpu.scene.display(),
        method.name,
        info.name,
        if info.is_cpu { " (CPU device)" } else { "" },
        report.draw_path,
        thousands(s.triangles),
        wedges.map_or(String::new(), |w| format!(
            " ({:.1} % wedges)",
            100.0 * w as f64 / s.triangles.max(1) as f64
        )),
        report.ms("frame").unwrap_or(0.0),
        out.display(),
        json_path.display()
    ))
}

/// Writes the image and its stats as one set: both appear or neither.
fn write_outputs(
    png: &Path,
    json_path: &Path,
    (w, h): (u32, u32),
    rgba: &[u8],
    stats: &Value,
) -> anyhow::Result<()> {
    let tmp_png = temp_sibling(png);
    write_png(&tmp_png, w, h, rgba)?;
    let json = serde_json::to_string_pretty(stats)? + "\n";
    let tmp_json = match stage(json_path, json.as_bytes()) {
        Ok(t) => t,
        Err(e) => {
            let _ = std::fs::remove_file(&tmp_png);
            return Err(e).with_context(|| format!("writing {}", json_path.display()));
        }
    };
    commit(&[
        (tmp_png, png.to_path_buf()),
        (tmp_json, json_path.to_path_buf()),
    ])
    .map_err(|(file, e)| anyhow::Error::new(e).context(format!("writing {}", file.display())))
}

/// The stats file: the run's setup, the common keys, GPU time per pass,
/// memory per purpose, and the method's own figures under `method_stats`.
fn stats_json(
    args: &RenderArgs,
    scene: &Scene,
    eps: f64,
    lambda: f64,
    renderer: &Renderer,
    report: &FrameReport,
) -> Value {
    let info = renderer.context().info();
    let gpu_ms: Map<String, Value> = report
        .gpu_ms
        .iter()
        .map(|(name, ms)| (name.clone(), json!(ms)))
        .collect();
    let memory: Map<String, Value> = renderer
        .memory()
        .into_iter()
        .map(|(name, bytes)| (name.to_string(), json!(bytes)))
        .collect();
    let own: Map<String, Value> = report
        .stats
        .own
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
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
        "eps": eps,
        "lambda": lambda,
        "l_max": crate::constants::L_MAX,
        "commit": commit_id(),
        "patches": renderer.scene().count,
        "triangles": report.stats.triangles,
        "culled_patches": report.stats.culled_patches,
        "frames_redone": report.redone,
        "gpu_ms": gpu_ms,
        "memory_bytes": memory,
        "method_stats": own,
    })
}
