//! `validate`: the checks that apply to the method, on every keyframe of a
//! scene (or one). Methods with a ready list are held against the CPU
//! oracle (ready set, vertex positions bit for bit, the §4.4 reordering
//! test on the GPU); methods that cull by occlusion are checked to change
//! no pixel by it; a method's own checks (its registry entry's `checks`:
//! the tessellators' shared edges, for one) run next; every method gets the
//! hole test on every model. Nothing here names a method.
//! Prints a table; the binary exits non-zero when any check fails.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use anyhow::Context as _;

use super::{keyframe, GpuRequest, ViewRequest};
use crate::constants::{FALLBACK_CHUNK_NODES, NODE_MESH_SLOTS, SHADE_NORMAL};
use crate::draw::{DrawPath, ReadyList, ReadyStage};
use crate::figures::thousands;
use crate::frame::View;
use crate::patch::oracle::{
    subdivide_displaced, subdivide_parallel_weighted, Surfaces, WeightedPatches,
};
use crate::patch::view::{Split, FLAG_WEDGES};
use crate::renderer::Renderer;
use crate::scene::desc::Scene;
use crate::scene::displaced::Displaced;
use crate::scene::geometry::SceneGeometry;
use crate::validate::holes::{self, run_model, run_model_from};
use crate::validate::{
    compare_capture, compare_ready, compare_vertices, positions_source, CheckResult, ReorderCheck,
};

/// What `validate` is asked for.
#[derive(Clone, Debug)]
pub struct ValidateArgs {
    /// Scene, method, tolerance, image, device.
    pub gpu: GpuRequest,
    /// The keyframes to check, in this order (empty: every keyframe).
    pub frames: Vec<usize>,
    /// Skip the hole test (it renders every model from six cameras).
    pub skip_holes: bool,
    /// Where the hole test leaves the images of views that found holes.
    pub debug_dir: Option<PathBuf>,
}

/// The outcome: every line, and the printed table.
#[derive(Clone, Debug)]
pub struct ValidateReport {
    /// Every check.
    pub results: Vec<CheckResult>,
    /// The table as printed.
    pub table: String,
}

impl ValidateReport {
    /// True when every check passed.
    pub fn ok(&self) -> bool {
        self.results.iter().all(|r| r.ok)
    }
}

/// Runs every check that applies to the method.
pub fn run(args: &ValidateArgs) -> anyhow::Result<ValidateReport> {
    let info = args.gpu.method_info()?;
    let scene = Scene::load(&args.gpu.scene)?;
    let frames: Vec<usize> = if args.frames.is_empty() {
        (0..scene.frame_count()).collect()
    } else {
        for &k in &args.frames {
            keyframe(&scene, &args.gpu.scene, k)?;
        }
        args.frames.clone()
    };
    let ViewRequest { eps, lambda, split } = args.gpu.view_request(&scene)?;
    let loaded = scene
        .load_animated()
        .with_context(|| format!("loading the models of {}", args.gpu.scene.display()))?;
    // An animated scene is checked at one time: the GPU converts it in its
    // update pass, the oracle's scene is the CPU twin's at that time.
    let time = args.gpu.seconds(loaded.animation.as_ref())?;
    super::note_undisplaced(&loaded.geometry, std::slice::from_ref(&args.gpu.method));
    let (geo, _) = loaded.at(time);
    let ctx = args.gpu.context()?;
    // Single-sampled: the hole test counts exact key colours. Without
    // occlusion culling: the oracle has no depth buffer (the occlusion
    // check below holds the culled images against these).
    let request = GpuRequest {
        msaa: 1,
        occlusion: Some(false),
        // The oracle compares patches: levels of detail are checked on
        // their own below (the hole test of every level).
        lod: false,
        ..args.gpu.clone()
    };
    let mut renderer = request.renderer(&ctx, &loaded.geometry, &loaded.shading)?;
    request.animate(&mut renderer, loaded.animation.as_ref())?;
    // The hole test's ground truth of a large scene runs in parts.
    renderer.set_progress(super::progress::parts_bar());

    // The keyframes' views, each with its frame number.
    let views = frames
        .iter()
        .map(|&k| {
            let cam = keyframe(&scene, &args.gpu.scene, k)?;
            let mut view = View::new(&cam, args.gpu.size, eps, lambda, SHADE_NORMAL);
            view.params.flags |= split.flag();
            Ok((k, view))
        })
        .collect::<anyhow::Result<Vec<_>>>()?;
    let mut results = Vec::new();
    if renderer.method().ready().is_some() {
        renderer.capture = true;
        for (k, view) in &views {
            results.extend(oracle_checks(&mut renderer, &geo, view, *k)?);
        }
        renderer.capture = false;
    }
    if renderer.method().culls_occluded() && args.gpu.occlusion != Some(false) {
        let debug = args.debug_dir.as_deref();
        results.extend(occlusion_checks(&mut renderer, &views, debug)?);
    }
    if let Some(make) = info.checks {
        let check = make(&geo);
        renderer.capture = check.capture();
        for (k, view) in &views {
            renderer.render(view)?;
            results.extend(check.keyframe(&renderer, *k)?);
        }
        renderer.capture = false;
    }
    if !args.skip_holes {
        let debug = args.debug_dir.as_deref();
        results.extend(hole_checks(
            &mut renderer,
            &geo,
            (eps, lambda, split),
            debug,
        )?);
        if args.gpu.lod {
            results.extend(level_hole_checks(
                &mut renderer,
                &geo,
                (eps, lambda, split),
                args.gpu.lod_shading,
                debug,
            )?);
        }
    }
    if args.gpu.validation {
        let errors = ctx.validation_errors();
        results.push(CheckResult::new(
            "validation layer",
            None,
            errors.is_empty(),
            match errors.first() {
                None => "no errors".into(),
                Some(first) => format!("{} errors, first: {first}", errors.len()),
            },
        ));
    }
    let at = loaded.animation.as_ref().map(|a| (time, a.wrap(time)));
    let table = table(args, &renderer, (eps, lambda, split), at, &results);
    Ok(ValidateReport { results, table })
}

/// The position capture of a frame's first `nodes` ready nodes; an error
/// where one storage buffer of this device cannot hold them.
fn read_capture(
    ctx: &crate::vk::Context,
    list: &ReadyList,
    nodes: usize,
) -> anyhow::Result<Vec<[f32; 4]>> {
    let capture: Vec<[f32; 4]> = list.capture.read(ctx)?;
    let held = capture.len() / NODE_MESH_SLOTS as usize;
    if held < nodes {
        // One binding holds NODE_MESH_SLOTS vec4s per node up to the
        // device's storage-buffer range; the shaders wrote no further.
        anyhow::bail!(
            "the position capture holds {} of the frame's {} ready nodes (one storage buffer \
             of this device); validate a nearer view, a higher --eps or a smaller --size",
            thousands(held as u64),
            thousands(nodes as u64)
        );
    }
    Ok(capture)
}

/// The oracle comparisons of one keyframe: the ready set, the drawn
/// positions, the §4.4 test.
fn oracle_checks(
    renderer: &mut Renderer,
    geo: &SceneGeometry,
    view: &View,
    k: usize,
) -> anyhow::Result<Vec<CheckResult>> {
    let report = renderer.render(view)?;
    let ready_count = report.stats.get_u64("ready_quads").unwrap_or(0) as u32;
    let ctx = renderer.context().clone();
    let stage: &ReadyStage = renderer
        .method()
        .ready()
        .context("the method has no ready list")?;
    let list = stage.list();
    let gpu_ready = list.read_ready(&ctx, ready_count)?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let params = renderer.effective_params(view);
    let displaced = Displaced::of(geo);
    let oracle = match &displaced {
        Some(dc) => subdivide_displaced(dc, &params, threads),
        None => {
            subdivide_parallel_weighted(&geo.patches, &geo.weights, &geo.flags, &params, threads)
        }
    };
    let weighted = WeightedPatches {
        patches: &geo.patches,
        weights: &geo.weights,
        flags: &geo.flags,
    };
    let surfaces: &dyn Surfaces = match &displaced {
        Some(dc) => dc,
        None => &weighted,
    };
    let (ok, detail) = compare_ready(&gpu_ready, &oracle.ready);
    let mut out = vec![CheckResult::new("ready set", Some(k), ok, detail)];

    let wedges = params.flags & FLAG_WEDGES != 0;
    let (compared, bad, source) = match stage.path() {
        DrawPath::Mesh => {
            let capture = read_capture(&ctx, list, gpu_ready.len())?;
            let (compared, bad) = compare_capture(surfaces, &gpu_ready, &capture, wedges);
            (compared, bad, positions_source(DrawPath::Mesh).to_owned())
        }
        DrawPath::Fallback => {
            // The vertex buffer holds the list's last chunk; the expansion
            // of every chunk wrote the capture from the same positions.
            let chunk = FALLBACK_CHUNK_NODES as usize;
            let last = gpu_ready.len().saturating_sub(1) / chunk * chunk;
            let words: Vec<u32> = list.vertices.read(&ctx)?;
            let (mut compared, mut bad) =
                compare_vertices(surfaces, &gpu_ready[last..], &words, wedges);
            let mut source = positions_source(DrawPath::Fallback).to_owned();
            if last > 0 {
                let capture = read_capture(&ctx, list, last)?;
                let (c, b) = compare_capture(surfaces, &gpu_ready[..last], &capture, wedges);
                (compared, bad) = (compared + c, bad + b);
                let chunks = gpu_ready.len().div_ceil(chunk);
                source = format!(
                    "{source}: the last of {chunks} chunks; the {} before it: the expansion's \
                     capture",
                    chunks - 1
                );
            }
            (compared, bad, source)
        }
    };
    out.push(CheckResult::new(
        "positions",
        Some(k),
        bad == 0 && compared > 0,
        format!(
            "{} of {} vertices bit-identical to the oracle ({source})",
            thousands(compared - bad),
            thousands(compared),
        ),
    ));

    let reorder = ReorderCheck::new(&ctx, stage, renderer.scene_spec())?;
    let (checked, failed) = reorder.run(renderer, ready_count)?;
    out.push(CheckResult::new(
        "reorder (§4.4)",
        Some(k),
        failed == 0 && checked == ready_count,
        format!(
            "{} nodes x 8 domain orderings on the GPU, {failed} differ",
            thousands(u64::from(checked))
        ),
    ));
    Ok(out)
}

/// The most bytes of unculled images and depths the occlusion check holds
/// at once: keyframes are checked in batches that fit.
const OCCLUSION_REFERENCE_BYTES: usize = 256 << 20;

/// Occlusion culling hides nothing that is seen: each keyframe drawn with
/// it, on its first frame (from the scene's first state, whatever was drawn
/// before: everything counts as visible, so it culls what that frame's
/// early phase hides) and on a second (the early phase takes what the first
/// found visible), has the unculled frame's depth at every pixel, bit for
/// bit: the nearest surface is the same everywhere. Colours may still differ
/// where two surfaces meet at exactly that depth (the early and late lists
/// draw in another order than one list does, and the first drawn wins a
/// tie); such pixels are counted, not failed. The oracle has no depth
/// buffer, so this, and not a ready-set comparison, is occlusion culling's
/// check; the detail says what was culled, and `debug_dir` gets the images
/// of a failure.
///
/// Turning culling on or off makes the method again (new pipelines, about
/// a second on lavapipe), so the unculled references of a batch of
/// keyframes are drawn first and culling is switched once per batch.
fn occlusion_checks(
    renderer: &mut Renderer,
    views: &[(usize, View)],
    debug_dir: Option<&Path>,
) -> anyhow::Result<Vec<CheckResult>> {
    let (w, h) = renderer.target().size();
    let per_view = (w as usize * h as usize * 8).max(1);
    let batch = (OCCLUSION_REFERENCE_BYTES / per_view).max(1);
    let off = renderer.options().clone();
    let on = crate::methods::MethodOptions {
        occlusion: true,
        ..off.clone()
    };
    renderer.set_keep_depth(true);
    let mut out = Vec::new();
    let checked = views.chunks(batch).try_for_each(|views| {
        renderer.set_options(off.clone())?;
        let mut unculled = Vec::new();
        for (_, view) in views {
            let report = renderer.render(view)?;
            let image = (renderer.read_image()?, renderer.read_depth()?);
            unculled.push((report.triangles(), image));
        }
        renderer.set_options(on.clone())?;
        for ((k, view), (triangles, reference)) in views.iter().zip(&unculled) {
            let check = culled_frames(renderer, view, *k, reference, debug_dir)?;
            out.push(check.result(*k, *triangles));
        }
        anyhow::Ok(())
    });
    renderer.set_keep_depth(false);
    let restored = renderer.set_options(off);
    checked?;
    restored?;
    Ok(out)
}

/// What two culled frames of one keyframe showed against its unculled
/// reference.
struct CulledFrames {
    differ: u64,
    ties: u64,
    instances_hidden: u64,
    nodes_hidden: u64,
    triangles: u64,
}

/// Draws keyframe `k` twice with culling on, from the scene's first
/// visibility, and holds each frame against `reference`.
fn culled_frames(
    renderer: &mut Renderer,
    view: &View,
    k: usize,
    reference: &(Vec<u8>, Vec<f32>),
    debug_dir: Option<&Path>,
) -> anyhow::Result<CulledFrames> {
    renderer.reset_visibility()?;
    let (mut differ, mut ties) = (0, 0);
    let mut last = None;
    let mut failed = None;
    for frame in 0..2 {
        last = Some(renderer.render(view)?);
        let culled = (renderer.read_image()?, renderer.read_depth()?);
        let d = OcclusionDiff::new(reference, &culled);
        differ += d.depth;
        ties += d.ties;
        if d.depth > 0 && failed.is_none() {
            failed = Some((frame, culled, d));
        }
    }
    if let (Some(dir), Some((frame, culled, d))) = (debug_dir, &failed) {
        d.write(
            dir,
            k,
            *frame,
            renderer.target().size(),
            &reference.0,
            &culled.0,
        );
    }
    let last = last.context("no culled frame")?;
    let own = |key| last.stats.get_u64(key).unwrap_or(0);
    Ok(CulledFrames {
        differ,
        ties,
        instances_hidden: own("instances_occluded"),
        nodes_hidden: own("occluded"),
        triangles: last.triangles(),
    })
}

impl CulledFrames {
    /// The check's line, against the unculled frame's `unculled` triangles.
    fn result(&self, k: usize, unculled: u64) -> CheckResult {
        CheckResult::new(
            "occlusion",
            Some(k),
            self.differ == 0,
            format!(
                "2 frames culled: the nearest surface differs at {} px{}; {} instances \
                 and {} nodes hidden, {} of {} triangles drawn",
                self.differ,
                if self.ties > 0 {
                    format!(
                        " ({} px tie at equal depth in another colour: draw order)",
                        self.ties
                    )
                } else {
                    String::new()
                },
                self.instances_hidden,
                thousands(self.nodes_hidden),
                thousands(self.triangles),
                thousands(unculled)
            ),
        )
    }
}

/// Where a culled frame differs from the unculled one: pixels whose depth
/// differs (a surface lost, or one drawn that should not be), and pixels of
/// equal depth in another colour (a tie between two surfaces).
struct OcclusionDiff {
    depth: u64,
    ties: u64,
    /// Per pixel: 0 same, 1 tie, 2 depth differs.
    marks: Vec<u8>,
}

impl OcclusionDiff {
    fn new(reference: &(Vec<u8>, Vec<f32>), culled: &(Vec<u8>, Vec<f32>)) -> Self {
        let marks: Vec<u8> = reference
            .1
            .iter()
            .zip(&culled.1)
            .zip(reference.0.chunks_exact(4).zip(culled.0.chunks_exact(4)))
            .map(
                |((a, b), (ca, cb))| match (a.to_bits() != b.to_bits(), ca != cb) {
                    (true, _) => 2,
                    (false, true) => 1,
                    (false, false) => 0,
                },
            )
            .collect();
        let count = |m| marks.iter().filter(|&&x| x == m).count() as u64;
        Self {
            depth: count(2),
            ties: count(1),
            marks,
        }
    }

    /// The unculled and culled images and the differences (depth red, ties
    /// yellow, over the unculled image darkened) as
    /// `occlusion-frame<k>-{unculled,culled,diff}.png` in `dir`.
    fn write(&self, dir: &Path, k: usize, frame: usize, (w, h): (u32, u32), a: &[u8], b: &[u8]) {
        let mut diff: Vec<u8> = a.iter().map(|&c| c / 3).collect();
        for (i, &m) in self.marks.iter().enumerate() {
            let c = match m {
                2 => [255, 0, 0, 255],
                1 => [255, 255, 0, 255],
                _ => continue,
            };
            diff[4 * i..4 * i + 4].copy_from_slice(&c);
        }
        let _ = std::fs::create_dir_all(dir);
        for (tag, img) in [("unculled", a), ("culled", b), ("diff", &diff[..])] {
            let file = dir.join(format!("occlusion-frame{k}-culled{}-{tag}.png", frame + 1));
            if let Err(e) = crate::gpu::write_png(&file, w, h, img) {
                log::warn!("{e}");
            }
        }
    }
}

/// The first instance of every distinct model file that has patches, as
/// a geometry of its own, with the file's name: what the hole tests look
/// at, one model at a time.
fn distinct_models(geo: &SceneGeometry) -> Vec<(String, SceneGeometry)> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    let mut offset = 0usize;
    for (index, m) in geo.models.iter().enumerate() {
        let start = offset;
        offset += m.patches_per_instance * m.instances;
        if !seen.insert(m.file.clone()) || m.patches_per_instance == 0 {
            continue;
        }
        let one = geo.subset(start..start + m.patches_per_instance, (index, m.clone()));
        let name = m
            .file
            .file_name()
            .map_or("model".into(), |f| f.to_string_lossy().into_owned());
        out.push((name, one));
    }
    out
}

/// The hole test for the first instance of every distinct model file.
fn hole_checks(
    renderer: &mut Renderer,
    geo: &SceneGeometry,
    eps_lambda: (f64, f64, Split),
    debug_dir: Option<&Path>,
) -> anyhow::Result<Vec<CheckResult>> {
    let mut out = Vec::new();
    for (name, one) in distinct_models(geo) {
        let views = run_model(renderer, &one, eps_lambda, &name, debug_dir)?;
        let (ok, detail) = holes::verdict(&views);
        out.push(CheckResult::new(&format!("holes {name}"), None, ok, detail));
    }
    Ok(out)
}

/// Levels of detail in a model's image narrower than this (pixels) are
/// not hole-tested by pixels: the test's erosion would leave nothing to
/// check.
const LEVEL_TEST_MIN_SPAN: f64 = 48.0;

/// The hole test of the levels of detail (`--lod on`): for the first
/// instance of every distinct model file with levels, each level whose
/// model still spans [`LEVEL_TEST_MIN_SPAN`] pixels at the distance where
/// its measured error projects to ε, drawn from that level from there and
/// held against the reference drawn from patches; each smaller one by its
/// mesh: open nowhere its model is closed ([`crate::lod::edges_opened`])
/// (the levels made with the shading bound `shading`, degrees, as the run
/// draws them).
fn level_hole_checks(
    renderer: &mut Renderer,
    geo: &SceneGeometry,
    eps_lambda: (f64, f64, Split),
    shading: f32,
    debug_dir: Option<&Path>,
) -> anyhow::Result<Vec<CheckResult>> {
    let mut out = Vec::new();
    let height = renderer.target().size().1;
    let cache = crate::lod::cache::LevelCache::from_env();
    for (name, one) in distinct_models(geo) {
        let levels =
            crate::lod::SceneLevels::build_cached(&one, shading.to_radians(), cache.as_ref());
        let Some(model) = levels.models.first().filter(|m| !m.levels.is_empty()) else {
            continue;
        };
        for (l, level) in model.levels.iter().enumerate() {
            let (cameras, span) =
                holes::level_cameras(&one.patches, level.error, eps_lambda.0, height);
            let tag = format!("{name} level {l}");
            if span < LEVEL_TEST_MIN_SPAN {
                let opened = crate::lod::edges_opened(&one, model, level);
                let detail = format!(
                    "{} open edges where the model is closed (by its mesh: {span:.0} px \
                     across at ε, too small for the pixel test); {} triangles",
                    crate::figures::thousands(opened as u64),
                    level.mesh.triangles()
                );
                out.push(CheckResult::new(
                    &format!("holes {tag}"),
                    None,
                    opened == 0,
                    detail,
                ));
                continue;
            }
            let views = run_model_from(
                renderer,
                &one,
                eps_lambda,
                (&tag, &cameras, Some((&levels, l))),
                debug_dir,
            )?;
            renderer.set_levels(None)?;
            let (ok, detail) = holes::verdict(&views);
            let detail = format!(
                "{detail}; {} triangles, error {:.3e} (model units), {span:.0} px across",
                level.mesh.triangles(),
                level.error
            );
            out.push(CheckResult::new(&format!("holes {tag}"), None, ok, detail));
        }
    }
    Ok(out)
}

/// The printed table, its first column as wide as the longest check name.
fn table(
    args: &ValidateArgs,
    renderer: &Renderer,
    (eps, lambda, split): (f64, f64, Split),
    time: Option<(f64, f64)>,
    results: &[CheckResult],
) -> String {
    let info = renderer.context().info();
    let split = if crate::methods::reads(renderer.method().name()).split {
        format!(", split {}", split.name())
    } else {
        String::new()
    };
    let (w, h) = args.gpu.size;
    let method = renderer.method();
    let split = match time {
        Some((t, wrapped)) if t != wrapped => format!("{split}, time {t} s (= {wrapped} s)"),
        Some((t, _)) => format!("{split}, time {t} s"),
        None => split,
    };
    let width = results
        .iter()
        .map(|r| r.check.chars().count())
        .chain([5])
        .max()
        .unwrap_or(5);
    let mut table = format!(
        "validate {} (method {}, {} path, {w}x{h}, eps {eps}, lambda {lambda}{split}) on {}{}\n\n{:<width$} {:>5}  {:<6} {}\n",
        args.gpu.scene.display(),
        method.name(),
        method.draw_path(),
        info.name,
        if info.is_cpu { " (CPU device)" } else { "" },
        "check",
        "frame",
        "result",
        "detail"
    );
    for r in results {
        table += &format!(
            "{:<width$} {:>5}  {:<6} {}\n",
            r.check,
            r.frame.map_or("-".into(), |f| f.to_string()),
            if r.ok { "ok" } else { "FAIL" },
            r.detail
        );
    }
    let failed = results.iter().filter(|r| !r.ok).count();
    table += &if failed == 0 {
        format!("\nall {} checks passed\n", results.len())
    } else {
        format!("\n{failed} of {} checks FAILED\n", results.len())
    };
    table
}

#[cfg(test)]
mod tests {
    use super::OcclusionDiff;

    /// Four pixels: the same; another colour at the same depth (a tie);
    /// another depth (a surface lost); another depth by one ulp.
    #[test]
    fn a_tie_is_counted_apart_and_any_other_depth_fails() {
        let colour = |c: u8| vec![c, c, c, 255];
        let reference = (
            [colour(1), colour(2), colour(3), colour(4)].concat(),
            vec![0.5f32; 4],
        );
        let next = f32::from_bits(0.5f32.to_bits() + 1);
        let culled = (
            [colour(1), colour(9), colour(3), colour(4)].concat(),
            vec![0.5, 0.5, 1.0, next],
        );
        let d = OcclusionDiff::new(&reference, &culled);
        assert_eq!((d.depth, d.ties), (2, 1));
        assert_eq!(d.marks, [0, 1, 2, 2]);
    }
}
