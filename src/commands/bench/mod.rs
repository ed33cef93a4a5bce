//! `bench`: every method at every ε and λ along a camera path, GPU time
//! per pass and the frame's figures per frame; at a few perspectives the
//! image error against the ground truth; then the reports (see
//! `eval::record`, `eval::report`, `eval::plot`).
//!
//! Everything that can be refused is refused before any GPU work: the
//! lists, the methods, the scene and its path, the output directory, the
//! plot font. A run stopped early (Ctrl-C, or a frame that failed) still
//! writes every report from what was measured; `frames.csv` is written
//! row by row as the run goes.

mod measure;

use measure::{measure, Measured};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::{anyhow, Context as _};

use super::render::commit_id;
use super::GpuRequest;
use crate::anim::AnimatedScene;
use crate::eval::plot;
use crate::eval::record::{
    flip_columns, Config, ConfigSummary, CsvLog, BREAKDOWN_COLUMNS, FRAME_COLUMNS,
};
use crate::eval::report::{markdown, summary_json, Setup};
use crate::files::{check_writable, write_atomic};
use crate::methods;
use crate::renderer::Renderer;
use crate::scene::desc::Scene;
use crate::scene::geometry::SceneGeometry;
use crate::scene::path::ScenePath;
use crate::vk::{Context, DeviceSelector};

/// Default ε list (the paper's Table 2).
pub const DEFAULT_EPS: [f64; 3] = [0.5, 1.0, 2.0];
/// Default λ list (the paper's Table 2).
pub const DEFAULT_LAMBDA: [f64; 2] = [0.0, 0.5];
/// Warm-up frames per configuration unless told.
pub const DEFAULT_WARMUP: u32 = 5;
/// FLIP perspectives unless told (the paper's six).
pub const DEFAULT_FLIP_FRAMES: u32 = 6;
/// `--quick`: frames, warm-up frames and FLIP perspectives.
pub const QUICK: (u32, u32, u32) = (5, 2, 2);

/// What `bench` is asked for; `None` takes the default (or `--quick`'s).
#[derive(Clone, Debug)]
pub struct BenchArgs {
    /// Scene file.
    pub scene: PathBuf,
    /// Methods (`None`: every built method but the ground truth).
    pub methods: Option<Vec<String>>,
    /// ε list.
    pub eps: Vec<f64>,
    /// λ list.
    pub lambda: Vec<f64>,
    /// Frames along the path (`None`: the path's own count).
    pub frames: Option<u32>,
    /// Image size.
    pub size: (u32, u32),
    /// Untimed frames before each configuration.
    pub warmup: Option<u32>,
    /// FLIP perspectives spread along the path (0: none).
    pub flip_frames: Option<u32>,
    /// The ground truth's grid.
    pub grid: u32,
    /// Output directory (created).
    pub out: PathBuf,
    /// Device.
    pub device: DeviceSelector,
    /// A few frames per configuration.
    pub quick: bool,
    /// Khronos validation layer on.
    pub validation: bool,
    /// How `subdiv` and `subdiv-indirect` split (`None`: the scene's).
    pub split: Option<crate::patch::view::Split>,
    /// Occlusion culling of `subdiv` and `subdiv-indirect`.
    pub occlusion: bool,
    /// Levels of detail below one patch for the measured methods.
    pub lod: bool,
    /// Their shading bound in degrees (`GpuRequest::lod_shading`).
    pub lod_shading: f32,
}

impl BenchArgs {
    /// The defaults for `scene` writing to `out`.
    pub fn new(scene: PathBuf, out: PathBuf) -> Self {
        BenchArgs {
            scene,
            methods: None,
            eps: DEFAULT_EPS.to_vec(),
            lambda: DEFAULT_LAMBDA.to_vec(),
            frames: None,
            size: (1920, 1080),
            warmup: None,
            flip_frames: None,
            grid: methods::REFERENCE_DEFAULT_GRID,
            out,
            device: DeviceSelector::Auto,
            quick: false,
            validation: false,
            split: None,
            occlusion: false,
            lod: false,
            lod_shading: crate::lod::MOST_NORMAL_ERROR_DEG,
        }
    }
}

/// A checked request: what the run will do.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The configurations (method, then λ, then ε), taken in turn per frame.
    pub configs: Vec<Config>,
    /// Frames timed per configuration (0 from [`check`] when the path's
    /// own count applies, which is known once the path is chosen).
    pub frames: u32,
    /// Warm-up frames per configuration.
    pub warmup: u32,
    /// FLIP perspectives.
    pub flip_frames: u32,
    /// The scene.
    pub scene: Scene,
    /// How `subdiv` and `subdiv-indirect` split a node: `--split`, else
    /// the scene's `[view] split` (ε and λ are the lists, never the
    /// scene's).
    pub split: crate::patch::view::Split,
}

impl Plan {
    /// Frames the run renders, for the progress bar: per configuration
    /// its warm-up, timed and FLIP frames; plus one probe per method and
    /// one ground-truth image per perspective.
    pub fn total_steps(&self) -> u64 {
        let per = u64::from(self.warmup + self.frames + self.flip_frames);
        let methods = self.methods().len() as u64;
        self.configs.len() as u64 * per + methods + u64::from(self.flip_frames)
    }

    /// The methods, in run order.
    pub fn methods(&self) -> Vec<String> {
        let mut m: Vec<String> = Vec::new();
        for c in &self.configs {
            if !m.contains(&c.method) {
                m.push(c.method.clone());
            }
        }
        m
    }
}

fn check_list(name: &str, v: &[f64], ok: impl Fn(f64) -> bool, want: &str) -> anyhow::Result<()> {
    if v.is_empty() {
        return Err(anyhow!("--{name} needs at least one value"));
    }
    if let Some(x) = v.iter().find(|&&x| !ok(x)) {
        return Err(anyhow!("--{name}: {x} is not {want}"));
    }
    if let Some((_, x)) = v.iter().enumerate().find(|(i, x)| v[..*i].contains(x)) {
        return Err(anyhow!("--{name}: {x} is given twice"));
    }
    Ok(())
}

/// Refuses an output directory that cannot be made, without making it:
/// its nearest existing ancestor must be a directory that accepts files.
fn can_create_dir(dir: &Path) -> anyhow::Result<()> {
    let refuse = |why: String| anyhow!("cannot write to {}: {why}", dir.display());
    let mut probe_dir = dir;
    while !probe_dir.exists() {
        probe_dir = match probe_dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
    }
    if !probe_dir.is_dir() {
        return Err(refuse(format!(
            "{} is not a directory",
            probe_dir.display()
        )));
    }
    check_writable(&probe_dir.join("bench-probe"), false).map_err(refuse)
}

/// Creates the output directory (and `flip/` when perspectives are
/// measured) once nothing else can refuse the run, and checks every file
/// the run writes there.
fn prepare_output(dir: &Path, flip_frames: u32) -> anyhow::Result<()> {
    let sub = if flip_frames > 0 {
        dir.join("flip")
    } else {
        dir.to_path_buf()
    };
    std::fs::create_dir_all(&sub).map_err(|e| anyhow!("cannot write to {}: {e}", dir.display()))?;
    let mut files = vec![
        "frames.csv",
        "flip.csv",
        "breakdown.csv",
        "summary.json",
        "report.md",
    ];
    if flip_frames > 0 {
        files.push("flip/x.png");
    }
    for f in files {
        check_writable(&dir.join(f), false).map_err(|e| anyhow!(e))?;
    }
    Ok(())
}

/// Drops the configurations of methods that cannot draw the scene's
/// geometry (rational patches, PN triangles), saying so on stderr, when
/// the methods are the default list; a method the user named refuses the
/// whole run instead.
fn fit_methods_to_scene(plan: &mut Plan, geo: &SceneGeometry, named: bool) -> anyhow::Result<()> {
    let mut left_out = Vec::new();
    for name in plan.methods() {
        if let Err(why) = methods::check_geometry(methods::find(&name)?, geo) {
            if named {
                return Err(anyhow!("--methods: {why}"));
            }
            eprintln!("bench: leaving out {name}: {why}");
            left_out.push(name);
        }
    }
    plan.configs.retain(|c| !left_out.contains(&c.method));
    if plan.configs.is_empty() {
        return Err(anyhow!("no method can draw this scene"));
    }
    Ok(())
}

/// Checks `args` without touching the GPU: the lists, the methods, the
/// scene, the output directory (created) and the plot font.
pub fn check(args: &BenchArgs) -> anyhow::Result<Plan> {
    check_list(
        "eps",
        &args.eps,
        |x| x.is_finite() && x > 0.0,
        "a positive number of pixels",
    )?;
    check_list(
        "lambda",
        &args.lambda,
        |x| (0.0..=1.0).contains(&x),
        "in [0, 1]",
    )?;
    let methods: Vec<String> = match &args.methods {
        Some(list) => {
            if list.is_empty() {
                return Err(anyhow!("--methods needs at least one method"));
            }
            for (i, m) in list.iter().enumerate() {
                methods::find(m).map_err(|e| anyhow!("--methods: {e}"))?;
                if list[..i].contains(m) {
                    return Err(anyhow!("--methods: {m} is given twice"));
                }
            }
            list.clone()
        }
        None => methods::METHODS
            .iter()
            .filter(|m| m.benched())
            .map(|m| m.name.to_string())
            .collect(),
    };
    let mut request = GpuRequest::new(args.scene.clone());
    // Off unless asked: the paper's comparison culls by frustum and back
    // faces alone, like the tessellators.
    request.occlusion = Some(args.occlusion);
    request.per_method.set_reference_grid(args.grid);
    request.method_info()?;
    if args.frames == Some(0) {
        return Err(anyhow!("--frames must be at least 1"));
    }
    let scene = Scene::load(&args.scene)?;
    can_create_dir(&args.out)?;
    plot::load_font().map_err(|e| anyhow!(e))?;
    // Given, else --quick's, else the full run's (0 frames: the path's own).
    let pick = |given: Option<u32>, quick: u32, full: u32| {
        given.unwrap_or(if args.quick { quick } else { full })
    };
    let (qf, qw, qp) = QUICK;
    // A method that ignores λ is measured once per ε.
    let mut configs = Vec::new();
    for m in &methods {
        let lambdas: Vec<Option<f64>> = if methods::find(m)?.reads.lambda {
            args.lambda.iter().copied().map(Some).collect()
        } else {
            vec![None]
        };
        for &lambda in &lambdas {
            for &eps in &args.eps {
                configs.push(Config {
                    method: m.clone(),
                    eps,
                    lambda,
                    draw_path: String::new(),
                });
            }
        }
    }
    Ok(Plan {
        configs,
        frames: pick(args.frames, qf, 0),
        warmup: pick(args.warmup, qw, DEFAULT_WARMUP),
        flip_frames: pick(args.flip_frames, qp, DEFAULT_FLIP_FRAMES),
        split: args.split.unwrap_or(scene.view.split),
        scene,
    })
}

/// What the run tells whoever watches it, after every frame.
#[derive(Clone, Debug)]
pub struct Step<'a> {
    /// Frames rendered so far (of `total`).
    pub done: u64,
    /// All the frames the run will render.
    pub total: u64,
    /// The configuration being measured (or the ground truth).
    pub what: &'a str,
    /// Rows in `frames.csv` so far.
    pub rows: usize,
}

/// How the run ended.
#[derive(Clone, Debug)]
pub struct BenchOutcome {
    /// The output directory.
    pub out: PathBuf,
    /// Frames timed (rows of `frames.csv`).
    pub rows: usize,
    /// FLIP images compared.
    pub flips: usize,
    /// `None` if complete, else why it stopped early.
    pub stopped: Option<String>,
    /// The report, for printing.
    pub report: String,
}

/// The command line that repeats a run.
fn command_line(args: &BenchArgs, plan: &Plan) -> String {
    let join = |v: &[f64]| {
        v.iter()
            .map(|x| x.to_string())
            .collect::<Vec<_>>()
            .join(",")
    };
    let mut c = format!(
        "bezier-subdiv bench --scene {} --methods {} --eps {} --lambda {} --frames {} --warmup {} --flip-frames {} --size {}x{} --grid {} --out {}",
        args.scene.display(),
        plan.methods().join(","),
        join(&args.eps),
        join(&args.lambda),
        plan.frames,
        plan.warmup,
        plan.flip_frames,
        args.size.0,
        args.size.1,
        args.grid,
        args.out.display()
    );
    if args.device != DeviceSelector::Auto {
        c += &format!(" --device {}", args.device);
    }
    if let Some(s) = args.split {
        c += &format!(" --split {}", s.name());
    }
    if args.lod {
        c += " --lod on";
        if args.lod_shading != crate::lod::MOST_NORMAL_ERROR_DEG {
            c += &format!(" --lod-shading {}", args.lod_shading);
        }
    }
    if args.occlusion {
        c += " --occlusion on";
    }
    c
}

/// Says when the ground truth's `grid` samples a displaced model's map
/// more coarsely than two samples per texel: its geometric error and FLIP
/// then measure against a reference that misses some of the map.
fn note_reference_grid(geo: &crate::scene::geometry::SceneGeometry, grid: u32, flip_frames: u32) {
    let d = &geo.displacement;
    let needed = d.resolving_grid().min(methods::REFERENCE_MAX_GRID);
    if flip_frames > 0 && d.in_use() && grid < needed {
        eprintln!(
            "note: the ground truth's grid {grid} samples the displaced maps at {:.2} samples \
             per texel where a patch spans most texels ({:.0}); --grid {needed} gives 2",
            grid as f32 / d.texel_span,
            d.texel_span
        );
    }
}

/// Runs the benchmark on `ctx`; `cancel` stops it after the current frame,
/// `watch` hears of every frame. Reports are written however it ends; an
/// error comes back only when no report could be written.
pub fn run_on(
    ctx: &Arc<Context>,
    args: &BenchArgs,
    cancel: &AtomicBool,
    watch: &mut dyn FnMut(&Step<'_>),
) -> anyhow::Result<BenchOutcome> {
    let mut plan = check(args)?;
    let loaded = plan
        .scene
        .load_animated()
        .with_context(|| format!("loading the models of {}", args.scene.display()))?;
    let geo = &loaded.geometry;
    fit_methods_to_scene(&mut plan, geo, args.methods.is_some())?;
    crate::commands::note_undisplaced(geo, &plan.methods());
    note_reference_grid(geo, args.grid, plan.flip_frames);
    prepare_output(&args.out, plan.flip_frames)?;
    let path = ScenePath::of(&plan.scene, geo);
    if plan.frames == 0 {
        plan.frames = path.default_frames();
    }
    // Rows of an earlier run must not pass for this one's.
    for f in ["frames.csv", "flip.csv", "breakdown.csv"] {
        let _ = std::fs::remove_file(args.out.join(f));
    }
    let mut renderer = bench_renderer(ctx, args, &plan, &loaded)?;
    let mut setup = describe_setup(ctx, args, &plan, &loaded, &path);
    let mut m = Measured {
        configs: plan.configs.clone(),
        rows: Vec::new(),
        flips: Vec::new(),
        steps: 0,
    };
    let result = measure(
        &mut renderer,
        geo,
        args,
        &plan,
        &path,
        &setup,
        cancel,
        watch,
        &mut m,
    );
    setup.stopped = match &result {
        Ok(()) if cancel.load(Ordering::Relaxed) => Some("interrupted".into()),
        Ok(()) => None,
        Err(e) => Some(format!("{e:#}")),
    };
    let report = finish(&args.out, &setup, &m).map_err(|e| match &result {
        Err(r) => e.context(format!("writing the reports after the run failed: {r:#}")),
        Ok(()) => e,
    })?;
    if let (Err(e), true) = (result, m.rows.is_empty()) {
        return Err(e.context("no frame was measured"));
    }
    Ok(BenchOutcome {
        out: args.out.clone(),
        rows: m.rows.len(),
        flips: m.flips.len(),
        stopped: setup.stopped,
        report,
    })
}

/// The renderer the run measures, on the first configuration's method,
/// with the scene's animation (if any) set.
fn bench_renderer(
    ctx: &Arc<Context>,
    args: &BenchArgs,
    plan: &Plan,
    loaded: &AnimatedScene,
) -> anyhow::Result<Renderer> {
    let mut request = GpuRequest::new(args.scene.clone());
    // Off unless asked: the paper's comparison culls by frustum and back
    // faces alone, like the tessellators.
    request.occlusion = Some(args.occlusion);
    request.lod = args.lod;
    request.lod_shading = args.lod_shading;
    request.per_method.set_reference_grid(args.grid);
    request.size = args.size;
    request.method = plan.configs[0].method.clone();
    let mut renderer = request.renderer(ctx, &loaded.geometry, &loaded.shading)?;
    // An animated scene runs along the path at its own pace: path frame i
    // is at time i / fps.
    renderer.set_animation(loaded.animation.clone())?;
    Ok(renderer)
}

/// What the reports say about the run's setup: the command, the scene,
/// the device, the path (and animation), the FLIP perspectives.
fn describe_setup(
    ctx: &Arc<Context>,
    args: &BenchArgs,
    plan: &Plan,
    loaded: &AnimatedScene,
    path: &ScenePath,
) -> Setup {
    let geo = &loaded.geometry;
    let anim = loaded.animation.as_ref().map(|a| {
        format!(
            "; animation running: path frame i at {:.4} s × i ({} fps, {} s loop), \
             {} model patches and {} instance records updated per frame",
            1.0 / a.fps,
            a.fps,
            a.duration,
            a.patches(),
            a.keyed.len()
        )
    });
    let info = ctx.info();
    let flip_t: Vec<f64> = (0..plan.flip_frames)
        .map(|k| path.t(k, plan.flip_frames))
        .collect();
    let split = plan.split;
    Setup {
        command: command_line(args, plan),
        scene: args.scene.display().to_string(),
        scene_name: plan.scene.name.clone(),
        patches: geo.patches.len(),
        device: info.name.clone(),
        device_is_cpu: info.is_cpu,
        driver: format!("{} {}", info.driver_name, info.driver_info),
        size: args.size,
        path: format!("{}{}", path.describe(), anim.unwrap_or_default()),
        frames: plan.frames,
        warmup: plan.warmup,
        flip_t,
        grid: args.grid,
        commit: commit_id().to_string(),
        models: geo.models.iter().map(|m| m.name.clone()).collect(),
        split: split.name(),
        stopped: None,
    }
}

/// Writes `summary.json`, `report.md` and the plots; returns the report.
fn finish(out: &Path, setup: &Setup, m: &Measured) -> anyhow::Result<String> {
    // Stopped before the columns were known (during the probes): the CSV
    // files still exist, with the columns every run has.
    let flip = flip_columns();
    for (f, cols) in [
        ("frames.csv", &FRAME_COLUMNS[..]),
        ("flip.csv", &flip[..]),
        ("breakdown.csv", &BREAKDOWN_COLUMNS[..]),
    ] {
        if !out.join(f).exists() {
            let cols: Vec<String> = cols.iter().map(|s| s.to_string()).collect();
            CsvLog::create(&out.join(f), &cols)?;
        }
    }
    let summaries: Vec<ConfigSummary> = (0..m.configs.len())
        .map(|i| ConfigSummary::of(i, &m.rows, &m.flips))
        .filter(|s| s.stats.frames > 0 || !s.flips.is_empty())
        .collect();
    let json = summary_json(setup, &m.configs, &summaries);
    write_atomic(
        &out.join("summary.json"),
        (serde_json::to_string_pretty(&json)? + "\n").as_bytes(),
    )
    .with_context(|| format!("writing {}", out.join("summary.json").display()))?;
    let plots = plot::write_plots(out, &m.configs, &m.rows, &summaries).map_err(|e| anyhow!(e))?;
    let md = markdown(setup, &m.configs, &summaries, &plots);
    write_atomic(&out.join("report.md"), md.as_bytes())
        .with_context(|| format!("writing {}", out.join("report.md").display()))?;
    Ok(md)
}

/// Set by Ctrl-C: the run stops after the frame in flight.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The command: checks, a context on the requested device, a progress bar,
/// Ctrl-C handling (a second Ctrl-C ends the process at once; the CSV
/// files are whole up to the last row either way), the run.
pub fn run(args: &BenchArgs) -> anyhow::Result<BenchOutcome> {
    check(args)?;
    if let Err(e) = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            eprintln!("\nbench: stopped at once (frames.csv holds every whole row)");
            std::process::exit(130);
        }
        eprintln!("\nbench: stopping after this frame and writing the reports (Ctrl-C again to stop at once)");
    }) {
        log::warn!("Ctrl-C will not stop bench cleanly: {e}");
    }
    let mut request = GpuRequest::new(args.scene.clone());
    request.device = args.device.clone();
    request.validation = args.validation;
    let ctx = request.context()?;
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} frames, ETA {eta}: {msg}",
        )
        .map_err(|e| anyhow!("progress bar: {e}"))?
        .progress_chars("=> "),
    );
    // Without a terminal the bar draws nothing: a line when the run moves
    // to another configuration, or half a minute after the last line, so a
    // log shows the run going on.
    let lines = !std::io::stderr().is_terminal();
    let started = std::time::Instant::now();
    let mut last = (String::new(), started);
    let outcome = run_on(&ctx, args, &INTERRUPTED, &mut |s| {
        bar.set_length(s.total);
        bar.set_position(s.done);
        bar.set_message(s.what.to_string());
        let config = s.what.split(" (").next().unwrap_or(s.what);
        if lines && (config != last.0 || last.1.elapsed().as_secs() >= 30) {
            last = (config.to_string(), std::time::Instant::now());
            eprintln!(
                "bench: {} of {} frames after {}: {}",
                s.done,
                s.total,
                crate::vk::seconds_text(started.elapsed()),
                s.what
            );
        }
    });
    bar.finish_and_clear();
    if args.validation {
        ctx.check_validation()?;
    }
    outcome
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The default method list drops what cannot draw a rational scene;
    /// a method the user names refuses the run.
    #[test]
    fn methods_that_cannot_draw_the_scene_are_left_out_or_refused() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let out = std::env::temp_dir().join(format!("bench-fit-{}", std::process::id()));
        let mut args = BenchArgs::new(root.join("scenes/rational.toml"), out.clone());
        let mut plan = check(&args).unwrap();
        let geo = plan.scene.geometry().unwrap();
        let benched = |rational: bool| -> Vec<String> {
            methods::METHODS
                .iter()
                .filter(|m| m.benched() && m.rational == rational)
                .map(|m| m.name.to_string())
                .collect()
        };
        let (can, cannot) = (benched(true), benched(false));
        assert!(!can.is_empty() && !cannot.is_empty());
        assert!(cannot.iter().all(|m| plan.methods().contains(m)));
        fit_methods_to_scene(&mut plan, &geo, false).unwrap();
        assert_eq!(plan.methods(), can);

        args.methods = Some(vec![can[0].clone(), cannot[0].clone()]);
        let mut plan = check(&args).unwrap();
        let e = fit_methods_to_scene(&mut plan, &geo, true).unwrap_err();
        let refused = format!("`{}` cannot draw rational patches", cannot[0]);
        assert!(e.to_string().contains(&refused), "{e}");
        let _ = std::fs::remove_dir_all(out);
    }
}
