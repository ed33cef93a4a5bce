//! `validate`: the GPU against the CPU oracle on every keyframe of a scene
//! (ready set, vertex positions bit for bit, the §4.4 reordering test on the
//! GPU), then the hole test on every model. Prints a table; the binary exits
//! non-zero when any check fails.

use std::collections::HashSet;
use std::path::PathBuf;

use anyhow::{anyhow, Context as _};

use super::{eps_lambda, keyframe, thousands, GpuRequest};
use crate::constants::SHADE_NORMAL;
use crate::draw::DrawPath;
use crate::methods::Method;
use crate::patch::oracle::subdivide_parallel;
use crate::patch::view::FLAG_WEDGES;
use crate::renderer::{Renderer, View};
use crate::scene::file::{Scene, SceneGeometry};
use crate::validate::holes::run_model;
use crate::validate::{
    compare_capture, compare_ready, compare_vertices, positions_source, CheckResult, ReorderCheck,
};
use crate::vk::Context;

/// What `validate` is asked for.
#[derive(Clone, Debug)]
pub struct ValidateArgs {
    /// Scene, method, tolerance, image, device.
    pub gpu: GpuRequest,
    /// One keyframe, or every keyframe.
    pub frame: Option<usize>,
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

fn line(check: &str, frame: Option<usize>, ok: bool, detail: String) -> CheckResult {
    CheckResult {
        check: check.into(),
        frame,
        ok,
        detail,
    }
}

/// Runs every check.
pub fn run(args: &ValidateArgs) -> anyhow::Result<ValidateReport> {
    let method = Method::parse(&args.gpu.method).map_err(|e| anyhow!(e))?;
    let scene = Scene::load(&args.gpu.scene)?;
    let frames: Vec<usize> = match args.frame {
        Some(k) => {
            keyframe(&scene, &args.gpu.scene, k)?;
            vec![k]
        }
        None => (0..scene.frame_count()).collect(),
    };
    let (eps, lambda) = eps_lambda(&scene, args.gpu.eps, args.gpu.lambda)?;
    let geo = scene
        .geometry()
        .with_context(|| format!("loading the models of {}", args.gpu.scene.display()))?;
    let ctx = args.gpu.context()?;
    let mut renderer = args.gpu.renderer(&ctx, &geo)?;
    let path = renderer.path();
    let (w, h) = args.gpu.size;
    let reorder = ReorderCheck::new(&ctx, renderer.layout())?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());

    let mut results = Vec::new();
    for &k in &frames {
        let cam = keyframe(&scene, &args.gpu.scene, k)?;
        let view = View::new(&cam, args.gpu.size, eps, lambda, SHADE_NORMAL);
        let report = renderer.render(&view, true)?;
        let frame = renderer.frame();
        let gpu_ready = frame.read_ready(&ctx, report.stats.ready_quads)?;
        let oracle = subdivide_parallel(&geo.patches, &geo.flags, &view.params, threads);
        let (ok, detail) = compare_ready(&gpu_ready, &oracle.ready);
        results.push(line("ready set", Some(k), ok, detail));

        let wedges = view.params.flags & FLAG_WEDGES != 0;
        let (compared, bad) = match path {
            DrawPath::Mesh => {
                let capture: Vec<[f32; 4]> = frame.capture.read(&ctx)?;
                compare_capture(&geo.patches, &gpu_ready, &capture, wedges)
            }
            DrawPath::Fallback => {
                let words: Vec<u32> = frame.vertices.read(&ctx)?;
                compare_vertices(&geo.patches, &gpu_ready, &words, wedges)
            }
        };
        results.push(line(
            "positions",
            Some(k),
            bad == 0 && compared > 0,
            format!(
                "{} of {} vertices bit-identical to the oracle ({})",
                thousands(compared - bad),
                thousands(compared),
                positions_source(path)
            ),
        ));

        let (checked, failed) = reorder.run(
            &ctx,
            renderer.layout(),
            renderer.frame(),
            report.stats.ready_quads,
        )?;
        results.push(line(
            "reorder (§4.4)",
            Some(k),
            failed == 0 && checked == report.stats.ready_quads,
            format!(
                "{} nodes x 8 domain orderings on the GPU, {failed} differ",
                thousands(checked as u64)
            ),
        ));
    }

    if !args.skip_holes {
        let debug = args.debug_dir.as_deref();
        results.extend(hole_checks(
            &ctx,
            &mut renderer,
            &geo,
            args.gpu.size,
            eps,
            lambda,
            debug,
        )?);
    }
    if args.gpu.validation {
        let errors = ctx.validation_errors();
        results.push(line(
            "validation layer",
            None,
            errors.is_empty(),
            if errors.is_empty() {
                "no errors".into()
            } else {
                format!("{} errors, first: {}", errors.len(), errors[0])
            },
        ));
    }

    let info = ctx.info();
    let mut table = format!(
        "validate {} (method {}, {} path, {w}x{h}, eps {eps}, lambda {lambda}) on {}{}\n\n{:<24} {:>5}  {:<6} {}\n",
        args.gpu.scene.display(),
        method.name(),
        path.name(),
        info.name,
        if info.is_cpu { " (CPU device)" } else { "" },
        "check",
        "frame",
        "result",
        "detail"
    );
    for r in &results {
        table += &format!(
            "{:<24} {:>5}  {:<6} {}\n",
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
    Ok(ValidateReport { results, table })
}

/// The hole test for the first instance of every distinct model file.
fn hole_checks(
    ctx: &Context,
    renderer: &mut Renderer<'_>,
    geo: &SceneGeometry,
    size: (u32, u32),
    eps: f64,
    lambda: f64,
    debug_dir: Option<&std::path::Path>,
) -> anyhow::Result<Vec<CheckResult>> {
    let mut out = Vec::new();
    let mut seen = HashSet::new();
    let mut offset = 0usize;
    for m in &geo.models {
        let start = offset;
        offset += m.patches_per_instance * m.instances;
        if !seen.insert(m.file.clone()) || m.patches_per_instance == 0 {
            continue;
        }
        let range = start..start + m.patches_per_instance;
        let one = SceneGeometry {
            patches: geo.patches[range.clone()].to_vec(),
            flags: geo.flags[range].to_vec(),
            models: vec![m.clone()],
        };
        let name = m
            .file
            .file_name()
            .map_or("model".into(), |f| f.to_string_lossy().into_owned());
        let views = run_model(ctx, renderer, &one, size, eps, lambda, &name, debug_dir)?;
        let holes: u64 = views.iter().map(|v| v.holes).sum();
        let without: u64 = views.iter().map(|v| v.holes_without_wedges).sum();
        let checked: u64 = views.iter().map(|v| v.checked_pixels).sum();
        out.push(line(
            &format!("holes {name}"),
            None,
            holes == 0,
            format!(
                "{holes} key pixels in {} views ({} px checked); wedges off: {}",
                views.len(),
                thousands(checked),
                thousands(without)
            ),
        ));
    }
    Ok(out)
}
