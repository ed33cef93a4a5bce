//! `stats`: the CPU oracle's subdivision statistics for one view of a scene.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{anyhow, Context as _};
use serde::Serialize;

use super::{keyframe, ViewRequest};
use crate::constants::PATCH_MODEL_SHIFT;
use crate::figures::thousands;
use crate::patch::oracle::{
    explain, explain_displaced, process_any, process_displaced, subdivide_displaced,
    subdivide_parallel_weighted, triangle_counts, triangulate_surfaces, Outcome, SplitCause,
    WeightedPatches,
};
use crate::patch::quadnode::QuadNode;
use crate::patch::view::{ViewParams, FLAGS_DEFAULT, FLAG_WEDGES};
use crate::scene::desc::Scene;
use crate::scene::displaced::Displaced;
use crate::scene::geometry::SceneGeometry;
use crate::validate::raster::{PreviewShade, Raster};

/// Background of preview images.
const PREVIEW_BACKGROUND: [u8; 4] = [38, 42, 50, 255];
/// Ready nodes triangulated per batch while drawing a preview (bounds memory).
const PREVIEW_BATCH: usize = 1 << 16;

/// What `stats` is asked for.
#[derive(Clone, Debug)]
pub struct StatsArgs {
    /// Scene file.
    pub scene: PathBuf,
    /// Keyframe (0 = the scene camera).
    pub frame: usize,
    /// ε override.
    pub eps: Option<f64>,
    /// λ override.
    pub lambda: Option<f64>,
    /// Viewport.
    pub size: (u32, u32),
    /// `FLAG_*` bits for the view.
    pub flags: u32,
    /// How nodes split (`None`: the scene's `[view] split`); its flag is
    /// added to `flags`.
    pub split: Option<crate::patch::view::Split>,
    /// Write a CPU-rasterised preview of the ready nodes here (PNG).
    pub preview: Option<PathBuf>,
    /// What the preview's colours show.
    pub preview_shade: PreviewShade,
    /// Also break the figures down per model, with why nodes split.
    pub by_model: bool,
}

impl StatsArgs {
    /// Defaults for a scene: frame 0, the scene's ε and λ, 1920×1080.
    pub fn new(scene: PathBuf) -> Self {
        StatsArgs {
            scene,
            frame: 0,
            eps: None,
            lambda: None,
            size: (1920, 1080),
            flags: FLAGS_DEFAULT,
            split: None,
            preview: None,
            preview_shade: PreviewShade::Normal,
            by_model: false,
        }
    }
}

/// The oracle's figures for one view.
#[derive(Clone, Debug, Serialize)]
pub struct StatsReport {
    /// Scene file.
    pub scene: String,
    /// Scene name.
    pub name: String,
    /// Keyframe.
    pub frame: usize,
    /// Viewport width.
    pub width: u32,
    /// Viewport height.
    pub height: u32,
    /// Pixel tolerance.
    pub eps: f64,
    /// Distance blend.
    pub lambda: f64,
    /// How nodes split: `iso` or `aniso`.
    pub split: &'static str,
    /// Depth limit.
    pub l_max: u32,
    /// Base patches.
    pub patches: u64,
    /// Nodes (any depth) dropped by the frustum test.
    pub culled_patches: u64,
    /// Ready nodes dropped as back-facing.
    pub backface_culled: u64,
    /// Ready quads drawn.
    pub ready_quads: u64,
    /// Triangles drawn (2 per quad + wedges).
    pub triangles: u64,
    /// Wedge triangles among them.
    pub wedge_triangles: u64,
    /// Deepest ready node.
    pub max_depth: u32,
    /// Ready nodes at the depth limit.
    pub nodes_at_lmax: u64,
    /// Work items processed.
    pub nodes_processed: u64,
    /// Wall time of the oracle run (CPU), seconds.
    pub oracle_seconds: f64,
    /// The preview image written, if one was asked for.
    pub preview: Option<String>,
    /// Per model (with `by_model`), in scene order.
    pub models: Option<Vec<ModelStats>>,
}

/// One model's share of a view (`stats --by-model`).
#[derive(Clone, Debug, Default, Serialize)]
pub struct ModelStats {
    /// Model name.
    pub name: String,
    /// Its base patches (all instances).
    pub patches: u64,
    /// Base patches with at least one ready node drawn.
    pub drawn_patches: u64,
    /// Ready quads drawn.
    pub ready_quads: u64,
    /// Triangles drawn, wedges included.
    pub triangles: u64,
    /// Wedge triangles among them.
    pub wedge_triangles: u64,
    /// Nodes split because edges along both directions were not flat.
    pub splits_both_directions: u64,
    /// Nodes split because edges along one direction only were not flat.
    pub splits_one_direction: u64,
    /// Nodes split by the inner tier alone (every edge flat).
    pub splits_inner_only: u64,
}

impl StatsReport {
    /// Wedge triangles as a percentage of all triangles.
    pub fn wedge_share(&self) -> f64 {
        if self.triangles == 0 {
            0.0
        } else {
            100.0 * self.wedge_triangles as f64 / self.triangles as f64
        }
    }

    /// The human-readable table.
    pub fn to_text(&self) -> String {
        let t = |n: u64| thousands(n);
        format!(
            "scene           {} ({}), frame {}, {}x{}, eps {} px, lambda {}, split {}, l_max {}\n\
             patches         {}\n\
             culled          {} nodes outside the frustum\n\
             back-facing     {} ready nodes\n\
             ready quads     {}\n\
             triangles       {} ({} wedges, {:.1} %)\n\
             max depth       {}\n\
             nodes at l_max  {}\n\
             nodes processed {}\n\
             oracle time     {:.2} s (CPU reference)\n",
            self.scene,
            self.name,
            self.frame,
            self.width,
            self.height,
            self.eps,
            self.lambda,
            self.split,
            self.l_max,
            t(self.patches),
            t(self.culled_patches),
            t(self.backface_culled),
            t(self.ready_quads),
            t(self.triangles),
            t(self.wedge_triangles),
            self.wedge_share(),
            self.max_depth,
            t(self.nodes_at_lmax),
            t(self.nodes_processed),
            self.oracle_seconds,
        ) + &self.models_text()
    }

    fn models_text(&self) -> String {
        let Some(models) = &self.models else {
            return String::new();
        };
        let t = |n: u64| thousands(n);
        let mut out = format!(
            "\n{:<14} {:>8} {:>8} {:>9} {:>10} {:>7} {:>8} {:>8} {:>8}\n",
            "model",
            "patches",
            "drawn",
            "quads",
            "triangles",
            "wedges",
            "split uv",
            "split 1d",
            "inner"
        );
        for m in models {
            let share = if m.triangles == 0 {
                0.0
            } else {
                100.0 * m.wedge_triangles as f64 / m.triangles as f64
            };
            out += &format!(
                "{:<14} {:>8} {:>8} {:>9} {:>10} {:>6.1}% {:>8} {:>8} {:>8}\n",
                m.name,
                t(m.patches),
                t(m.drawn_patches),
                t(m.ready_quads),
                t(m.triangles),
                share,
                t(m.splits_both_directions),
                t(m.splits_one_direction),
                t(m.splits_inner_only),
            );
        }
        out + "(split uv: edges along u and v not flat; 1d: along one direction only; inner: every edge flat, the inner tier not)\n"
    }
}

/// Runs the oracle for one view of a scene.
pub fn run(args: &StatsArgs) -> anyhow::Result<StatsReport> {
    if let Some(p) = &args.preview {
        crate::files::check_writable(p, false).map_err(|e| anyhow!(e))?;
    }
    let scene = Scene::load(&args.scene)?;
    let camera = keyframe(&scene, &args.scene, args.frame)?;
    let ViewRequest { eps, lambda, split } =
        ViewRequest::resolve(&scene, args.eps, args.lambda, args.split)?;
    // Shading normals only for the preview that shows them.
    let smooth = args.preview.is_some() && args.preview_shade == PreviewShade::Smooth;
    let (geo, shading) = if smooth {
        scene.geometry_and_shading().map(|(g, s)| (g, Some(s)))
    } else {
        scene.geometry().map(|g| (g, None))
    }
    .with_context(|| format!("loading the models of {}", args.scene.display()))?;
    let (w, h) = args.size;
    let mut vp = camera.view_params(w, h, eps, lambda);
    vp.flags = args.flags | split.flag();
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let start = Instant::now();
    let displaced = Displaced::of(&geo);
    let res = match &displaced {
        Some(dc) => subdivide_displaced(dc, &vp, threads),
        None => subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, &vp, threads),
    };
    let (triangles, wedge_triangles) = triangle_counts(&res.ready, vp.has(FLAG_WEDGES));
    let oracle_seconds = start.elapsed().as_secs_f64();
    if let Some(path) = &args.preview {
        let view_proj = camera.view_proj(w, h);
        let mut img = Raster::new(w, h, PREVIEW_BACKGROUND);
        for batch in res.ready.chunks(PREVIEW_BATCH) {
            let surfaces = WeightedPatches {
                patches: &geo.patches,
                weights: &geo.weights,
                flags: &geo.flags,
            };
            let tris = match &displaced {
                Some(dc) => triangulate_surfaces(dc, batch, vp.has(FLAG_WEDGES)),
                None => triangulate_surfaces(&surfaces, batch, vp.has(FLAG_WEDGES)),
            };
            img.draw_triangles(
                &tris,
                &geo.patches,
                &geo.flags,
                shading.as_ref().map(|s| &s.patches[..]),
                &view_proj,
                (vp.eye.truncate(), crate::frame::headlight(&camera)),
                args.preview_shade,
            );
        }
        img.save_png(path)
            .with_context(|| format!("saving the preview {}", path.display()))?;
    }
    let s = res.stats;
    Ok(StatsReport {
        scene: args.scene.display().to_string(),
        name: scene.name,
        frame: args.frame,
        width: w,
        height: h,
        eps,
        lambda,
        split: split.name(),
        l_max: vp.l_max,
        patches: s.patches,
        culled_patches: s.culled_patches,
        backface_culled: s.backface_culled,
        ready_quads: s.ready_quads,
        triangles,
        wedge_triangles,
        max_depth: s.max_depth,
        nodes_at_lmax: s.nodes_at_lmax,
        nodes_processed: s.nodes_processed,
        oracle_seconds,
        preview: args.preview.as_ref().map(|p| p.display().to_string()),
        models: args.by_model.then(|| model_stats(&geo, &res.ready, &vp)),
    })
}

/// The per-model breakdown: ready nodes and triangles from the oracle's
/// result, and why each split happened from a second walk of every tree
/// with [`explain`] at each split.
fn model_stats(geo: &SceneGeometry, ready: &[QuadNode], vp: &ViewParams) -> Vec<ModelStats> {
    let model_of = |patch: usize| (geo.flags[patch] >> PATCH_MODEL_SHIFT) as usize;
    let mut out: Vec<ModelStats> = geo
        .models
        .iter()
        .map(|m| ModelStats {
            name: m.name.clone(),
            patches: (m.patches_per_instance * m.instances) as u64,
            ..ModelStats::default()
        })
        .collect();
    let mut last_drawn = None;
    for &node in ready {
        let m = &mut out[model_of(node.patch() as usize)];
        let (tris, wedges) = triangle_counts(&[node], vp.has(FLAG_WEDGES));
        m.ready_quads += 1;
        m.triangles += tris;
        m.wedge_triangles += wedges;
        if last_drawn != Some(node.patch()) {
            m.drawn_patches += 1;
            last_drawn = Some(node.patch());
        }
    }
    let mut stack = Vec::new();
    let displaced = Displaced::of(geo);
    for (id, base) in geo.patches.iter().enumerate() {
        let (w, flags) = (geo.weights.get(id), geo.flags[id]);
        let disp = displaced
            .as_ref()
            .and_then(|dc| Some((dc, dc.model_of(id)?)));
        let m = &mut out[model_of(id)];
        stack.push(QuadNode::root(id as u32));
        while let Some(node) = stack.pop() {
            let (outcome, verdict) = match disp {
                Some((dc, d)) => (
                    process_displaced(dc, id, d, node, vp),
                    explain_displaced(dc, id, d, node, vp),
                ),
                None => (
                    process_any(base, w, flags, node, vp),
                    explain(base, w, flags, node, vp),
                ),
            };
            if let Outcome::Split(kids) = outcome {
                match verdict.and_then(|v| v.cause()) {
                    Some(SplitCause::BothDirections) => m.splits_both_directions += 1,
                    Some(SplitCause::OneDirection) => m.splits_one_direction += 1,
                    Some(SplitCause::InnerOnly) | None => m.splits_inner_only += 1,
                }
                stack.extend(kids);
            }
        }
    }
    out
}
