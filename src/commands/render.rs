//! `render`: one offscreen frame of a method to a PNG, with a JSON stats
//! file beside it.

use std::path::{Path, PathBuf};

use anyhow::{anyhow, Context as _};
use serde_json::{json, Map, Value};

use super::{eps_lambda, keyframe, GpuRequest};
use crate::constants::{SHADE_DEPTH, SHADE_NORMAL, SHADE_WEDGES};
use crate::draw::write_png;
use crate::files::{check_writable, temp_sibling, write_atomic};
use crate::methods::Method;
use crate::renderer::{FrameReport, Renderer, View};
use crate::scene::file::Scene;
use crate::vk::Context;

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

/// The current commit (short hash, `-dirty` with local changes), or
/// "unknown" outside a git checkout.
pub fn commit_id() -> String {
    let dir = env!("CARGO_MANIFEST_DIR");
    let run = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(dir)
            .args(args)
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
    };
    match run(&["rev-parse", "--short=12", "HEAD"]) {
        Some(hash) if !hash.is_empty() => {
            let dirty = run(&["status", "--porcelain", "--untracked-files=no"])
                .is_some_and(|s| !s.is_empty());
            if dirty {
                format!("{hash}-dirty")
            } else {
                hash
            }
        }
        _ => "unknown".into(),
    }
}

/// Renders and writes the PNG and its JSON; returns a short summary.
pub fn run(args: &RenderArgs) -> anyhow::Result<String> {
    let method = Method::parse(&args.gpu.method).map_err(|e| anyhow!(e))?;
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
    let path = renderer.path();
    let (w, h) = args.gpu.size;
    let view = View::new(&camera, args.gpu.size, eps, lambda, args.shade.code());
    let report = renderer.render(&view, false)?;
    let rgba = renderer.target().read_rgba(&ctx)?;
    if args.gpu.validation {
        ctx.check_validation()?;
    }

    let info = ctx.info();
    let stats = stats_json(args, &scene, method, eps, lambda, &renderer, &report, &ctx);
    // Both files under temporary names first, so a failure leaves neither.
    let tmp_png = temp_sibling(&out);
    write_png(&tmp_png, w, h, &rgba)?;
    let json = serde_json::to_string_pretty(&stats)? + "\n";
    if let Err(e) = write_atomic(&json_path, json.as_bytes()) {
        let _ = std::fs::remove_file(&tmp_png);
        return Err(e).with_context(|| format!("writing {}", json_path.display()));
    }
    std::fs::rename(&tmp_png, &out).with_context(|| format!("writing {}", out.display()))?;
    let s = &report.stats;
    Ok(format!(
        "{} ({}) on {}{}, {} path: {} ready quads, {} triangles ({:.1} % wedges), max depth {}, {:.2} ms GPU\nwrote {} and {}\n",
        args.gpu.scene.display(),
        method.name(),
        info.name,
        if info.is_cpu { " (CPU device)" } else { "" },
        path.name(),
        s.ready_quads,
        s.triangles,
        100.0 * s.wedge_triangles as f64 / (s.triangles.max(1)) as f64,
        s.max_depth,
        report
            .gpu_ms
            .iter()
            .find(|(n, _)| n == "frame")
            .map_or(0.0, |(_, ms)| *ms),
        out.display(),
        json_path.display()
    ))
}

#[allow(clippy::too_many_arguments)]
fn stats_json(
    args: &RenderArgs,
    scene: &Scene,
    method: Method,
    eps: f64,
    lambda: f64,
    renderer: &Renderer<'_>,
    report: &FrameReport,
    ctx: &Context,
) -> Value {
    let info = ctx.info();
    let s = &report.stats;
    let frame = renderer.frame();
    let mut gpu_ms = Map::new();
    for (name, ms) in &report.gpu_ms {
        gpu_ms.insert(name.clone(), json!(ms));
    }
    let mut memory = Map::new();
    memory.insert(
        "base_patches".into(),
        json!(renderer.scene().patches.size() + renderer.scene().flags.size()),
    );
    for (name, bytes) in frame.memory_bytes() {
        memory.insert(name.into(), json!(bytes));
    }
    json!({
        "scene": args.gpu.scene.display().to_string(),
        "frame": args.frame,
        "width": args.gpu.size.0,
        "height": args.gpu.size.1,
        "device": info.name,
        "device_is_cpu": info.is_cpu,
        "driver": format!("{} {}", info.driver_name, info.driver_info),
        "draw_path": renderer.path().name(),
        "method": method.name(),
        "shade": args.shade.name(),
        "eps": eps,
        "lambda": lambda,
        "l_max": crate::constants::L_MAX,
        "commit": commit_id(),
        "patches": scene_patch_count(renderer),
        "ready_quads": s.ready_quads,
        "triangles": s.triangles,
        "wedge_triangles": s.wedge_triangles,
        "culled_patches": s.culled_patches,
        "backface_culled": s.backface_culled,
        "max_depth": s.max_depth,
        "nodes_at_lmax": s.nodes_at_lmax,
        "nodes_processed": s.nodes_processed,
        "queue_capacity_items": frame.caps.queue,
        "queue_peak_items": s.queue_peak_items,
        "queue_spills": s.queue_spills,
        "queue_pushed": s.queue_pushed,
        "ready_capacity_items": frame.caps.ready,
        "ready_list_regrown": report.regrown,
        "gpu_ms": gpu_ms,
        "memory_bytes": memory,
        "scene_name": scene.name,
    })
}

fn scene_patch_count(renderer: &Renderer<'_>) -> u32 {
    renderer.scene().count
}
