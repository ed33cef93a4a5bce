//! The `bezier-subdiv` command line.

use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;

use clap::{Parser, Subcommand};

use bezier_subdiv::commands::bench::{BenchArgs, DEFAULT_EPS, DEFAULT_LAMBDA};
use bezier_subdiv::commands::render::{RenderArgs, Shade};
use bezier_subdiv::commands::validate::ValidateArgs;
use bezier_subdiv::commands::{self, parse_size, resolve_scene, stats::StatsArgs, GpuRequest};
use bezier_subdiv::draw::DrawRequest;
use bezier_subdiv::validate::raster::PreviewShade;
use bezier_subdiv::vk::DeviceSelector;

/// View-adaptive, crack-free recursive subdivision of bicubic Bézier surfaces
/// (Tabaei, Kuth et al. 2026) on Vulkan, with a CPU reference of every
/// decision.
///
/// `render` draws one frame offscreen to a PNG with its statistics as JSON;
/// `view` opens a window to fly around and change everything live;
/// `validate` checks the GPU against the CPU reference and looks for holes;
/// `bench` measures every method along a camera path and writes the
/// paper's tables; `stats` prints the CPU reference's figures; `import`
/// converts models;
/// `info` lists the Vulkan devices.
#[derive(Parser)]
#[command(name = "bezier-subdiv", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Seconds one wait for the GPU may take before the run fails (default
    /// 60, or BEZIER_SUBDIV_TIMEOUT). Long work is submitted in parts, each
    /// waited for within this; raise it on a slow or busy device.
    #[arg(long, global = true, value_name = "SECONDS", value_parser = parse_timeout,
          allow_negative_numbers = true)]
    timeout: Option<std::time::Duration>,
}

#[derive(Subcommand)]
enum Command {
    /// Subdivision statistics of the CPU oracle for one view of a scene.
    ///
    /// Prints base patches, frustum-culled and back-facing nodes, ready quads,
    /// triangles and the wedge share, the deepest level reached and how many
    /// nodes hit the depth limit l_max = 10.
    Stats {
        #[command(flatten)]
        view: ViewArgs,
        /// Camera keyframe: 0 is the scene camera, k ≥ 1 the path's key k.
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Print JSON instead of the table.
        #[arg(long)]
        json: bool,
        /// Also rasterise the ready nodes on the CPU at --size and write the
        /// picture here (PNG).
        #[arg(long, value_name = "FILE.png")]
        preview: Option<PathBuf>,
        /// Preview colours: normal (shaded, one tint per model; a one-sided
        /// surface seen from behind is dark red), smooth (the same, lit with
        /// the tangent patches' shading normals), depth (QuadNode depth 0
        /// dark blue … 10 dark red), wedges (depth darkened, wedges magenta).
        #[arg(long, value_name = "MODE", default_value = "normal", value_parser = PreviewShade::from_str)]
        preview_shade: PreviewShade,
        /// Also break the figures down per model: patches drawn, ready
        /// quads, triangles, the wedge share, and why nodes split (edges
        /// along both directions, along one only, or the inner tier alone).
        #[arg(long)]
        by_model: bool,
    },
    /// Render one frame offscreen: a PNG plus its statistics as JSON.
    ///
    /// The stats file (same path, .json) holds the scene, device, method,
    /// draw path, ε, λ, the commit the binary was built from, the keys every
    /// method reports (triangles, culled patches), GPU time per pass, memory
    /// per purpose, and the method's own figures under `method_stats`
    /// (subdiv: ready quads, wedges, depth, queue use). Output paths are
    /// checked before any GPU work; a failed run leaves no file behind.
    Render {
        #[command(flatten)]
        frame: FrameArgs,
        /// Shading: normal (lit), depth (QuadNode depth heat map), wedges
        /// (depth map with the crack-closing wedges highlighted), wireframe
        /// (the outline of every drawn cell), normals (as colours).
        #[arg(long, value_enum, default_value = "normal")]
        shade: Shade,
        /// Output PNG (default: out/<scene name>.png; out/ is created).
        #[arg(long, value_name = "FILE.png")]
        out: Option<PathBuf>,
        /// Untimed frames of the same view before the timed one: the first
        /// frame pays for shader compilation and caches (seconds on a fresh
        /// machine). Its figures stay in the stats file as gpu_ms_cold; 0
        /// times the first, cold frame itself. Default 1, and 0 for
        /// ground-truth, whose image is what it is for (at grid 64 a frame
        /// of the kitchen takes half a minute on a CPU device).
        #[arg(long, value_name = "N")]
        warmup: Option<u32>,
        /// Time N frames after the warm-up instead of one: the stats file's
        /// gpu_ms become the medians, with gpu_ms_min and gpu_ms_max beside
        /// them.
        #[arg(long, value_name = "N", default_value_t = 0)]
        repeat: u32,
        /// Also draw the same view with ground-truth (at --grid) and compare:
        /// the mean FLIP goes into the stats file (flip_mean), the FLIP heat
        /// map to NAME.flip.png beside the image, and the geometric error
        /// (px between the drawn surface and the ground truth's, mean and
        /// p99 off silhouettes; geometric_error) beside it.
        #[arg(long)]
        flip: bool,
    },
    /// Check the GPU against the CPU reference on every keyframe (or one):
    /// the ready QuadNode set, vertex positions bit for bit, the paper's §4.4
    /// reordering test on the GPU; then the hole test on every model.
    /// Prints a table; exits non-zero if any check fails.
    Validate {
        #[command(flatten)]
        frame: FrameArgs,
        /// Check these keyframes, in this order (e.g. 1,2); default: every
        /// keyframe (--frame K: one). Each check starts from the same state,
        /// so the order changes no result.
        #[arg(
            long,
            value_name = "K,K,...",
            value_delimiter = ',',
            conflicts_with = "frame"
        )]
        frames: Vec<usize>,
        /// Skip the hole test.
        #[arg(long)]
        no_holes: bool,
        /// Write the images of views where the hole test found holes, or checked
        /// no pixel, here.
        #[arg(long, value_name = "DIR")]
        debug_dir: Option<PathBuf>,
    },
    /// Open a window on a scene: fly around it, change the method, ε, λ
    /// and the view live, and watch the GPU's figures.
    ///
    /// Mouse: left drag orbits, right drag looks around, the wheel zooms.
    /// Keys: W A S D (and Q E) fly, R resets the camera, P plays or pauses
    /// the scene's camera path, F12 saves a screenshot (the rendered frame
    /// without the overlay, with the same stats JSON as `render`; to
    /// --screenshot, else out/<scene>-view-<k>.png), Tab hides the
    /// overlay, Escape quits. The overlay switches method, draw path, ε, λ,
    /// l_max, culling, wedges, the view (shaded, wireframe, depth heat map,
    /// wedges, normals) and MSAA, and computes FLIP against the ground
    /// truth on demand. Needs a display (X11); `xvfb-run -a` gives one.
    View {
        #[command(flatten)]
        frame: FrameArgs,
        /// Shading at start (changed live in the overlay).
        #[arg(long, value_enum, default_value = "normal")]
        shade: Shade,
        /// on: wait for vertical blank (FIFO); off: present as fast as
        /// possible (mailbox or immediate where the display offers them).
        #[arg(long, value_name = "on|off", default_value = "on", action = clap::ArgAction::Set, value_parser = parse_on_off)]
        vsync: bool,
        /// Close after N presented frames (scripted captures); with
        /// --screenshot the last one is saved.
        #[arg(long, value_name = "N")]
        frames: Option<u64>,
        /// Where screenshots go (F12, and the end of --frames): a PNG, with
        /// its stats beside it as .json.
        #[arg(long, value_name = "FILE.png")]
        screenshot: Option<PathBuf>,
        /// With --frames: resize the window to WxH halfway through (checks
        /// the swapchain's remaking; the screenshot is at the new size).
        #[arg(long, value_name = "WxH", value_parser = parse_size)]
        resize: Option<(u32, u32)>,
    },
    /// Measure every method at every ε and λ along the scene's camera path
    /// and write the paper's tables.
    ///
    /// Per frame: GPU time per named pass and the whole frame, triangles,
    /// wedge share, memory by purpose and the method's own figures (the
    /// `render` stats keys), into DIR/frames.csv as they are measured. At
    /// --flip-frames perspectives each configuration's image is compared
    /// with the ground truth by FLIP (renders and heat maps in DIR/flip/).
    /// Then DIR/summary.json (medians per method × ε × λ), DIR/report.md
    /// (the paper's Tables 1 and 2, time per pass, memory by purpose, the
    /// targets) and plots. Ctrl-C stops after the current frame and writes
    /// every report from what was measured.
    Bench(BenchFlags),
    /// List the Vulkan devices and what they support.
    Info {
        /// Also enable the Khronos validation layer (checks it is installed).
        #[arg(long)]
        vk_validation: bool,
    },
    /// Import a Catmull-Clark cage (.obj) or Bézier patch file (.bpt): print a
    /// summary and any warnings, optionally write the patches.
    ///
    /// With --out, writes PATCHES.bpt and, for cages, PATCHES.bpt.json giving
    /// the boundary rule and, for each patch, the cage face it came from, the
    /// face-parameter coordinates of its corners (null for patches of
    /// non-quad faces) and the rules it was made with.
    Import {
        /// The .obj cage or .bpt file.
        file: PathBuf,
        /// Write the patches here as .bpt (plus the .bpt.json sidecar).
        #[arg(long, value_name = "PATCHES.bpt")]
        out: Option<PathBuf>,
        /// Boundary rule for a cage without a `t interpolateboundary` tag:
        /// none, edge-only or edge-and-corner (the default).
        #[arg(long, value_name = "RULE")]
        boundary: Option<bezier_subdiv::cage::sharpness::BoundaryRule>,
        /// Catmull-Clark steps before conversion for the parts of the cage
        /// whose patches would only approximate the limit surface
        /// (extraordinary vertices, darts, semi-sharp or irregular creases,
        /// non-quads): each step quarters their faces and the approximation
        /// shrinks to the faces around the irregular vertices (0..6; the
        /// scene key `isolate`).
        #[arg(long, value_name = "N", default_value_t = 0,
              value_parser = clap::value_parser!(u32).range(0..=bezier_subdiv::cage::isolate::MAX_ISOLATE as i64))]
        isolate: u32,
        /// How a cage's texture coordinates are interpolated:
        /// corners-only (OpenSubdiv's and USD's default: smooth, UV seams
        /// kept, their corners pinned) or all (bilinear in each face); the
        /// scene key `fvar`.
        #[arg(long, value_name = "RULE", default_value = "corners-only")]
        fvar: bezier_subdiv::cage::uv::FvarRule,
    },
}

/// What a view is made of: the scene and the tolerance in an image size.
/// `bench`'s flags, as clap reads them (see the variant for the verb).
#[derive(clap::Args)]
struct BenchFlags {
    /// Scene file (TOML); its [camera_orbit] is the path, else its
    /// [camera_path] keys, else an orbit of its bounding box.
    #[arg(long, default_value = commands::DEFAULT_SCENE)]
    scene: PathBuf,
    /// Methods, comma-separated (default: every built method except
    /// ground-truth, the reference).
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Pixel tolerances, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_values_t = DEFAULT_EPS,
          allow_negative_numbers = true)]
    eps: Vec<f64>,
    /// Distance blends, comma-separated.
    #[arg(long, value_name = "LIST", value_delimiter = ',', default_values_t = DEFAULT_LAMBDA,
          allow_negative_numbers = true)]
    lambda: Vec<f64>,
    /// Frames timed along the path per configuration (default: the
    /// path's `frames`; 5 with --quick).
    #[arg(long, value_name = "N")]
    frames: Option<u32>,
    /// Image size; ε is measured in its pixels.
    #[arg(long, value_name = "WxH", default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
    /// Untimed frames before each configuration (default 5; 2 with --quick).
    #[arg(long, value_name = "N")]
    warmup: Option<u32>,
    /// FLIP perspectives spread along the path, 0 for none (default 6,
    /// like the paper's Table 1; 2 with --quick).
    #[arg(long, value_name = "N")]
    flip_frames: Option<u32>,
    /// The ground truth's grid cells per patch side (a power of two;
    /// lower it on CPU devices: 32 is ~18 s per kitchen image there).
    #[arg(long, value_name = "N", default_value_t = bezier_subdiv::methods::REFERENCE_DEFAULT_GRID)]
    grid: u32,
    /// Output directory (created).
    #[arg(long, value_name = "DIR", default_value = "out/bench")]
    out: PathBuf,
    /// Vulkan device: an index from `info`, or part of its name.
    #[arg(long, value_name = "ID", default_value = "auto")]
    device: DeviceSelector,
    /// A few frames per configuration, every method: a run of minutes
    /// on a GPU that still writes every report file.
    #[arg(long)]
    quick: bool,
    /// Enable the Khronos validation layer; any error fails the run.
    #[arg(long)]
    vk_validation: bool,
    /// How subdiv and subdiv-indirect split a node: iso (1:4, the
    /// paper's) or aniso (1:2 where one direction suffices); default:
    /// the scene's, else iso. One mode per run: compare two runs'
    /// flip.csv with tools/bench/equal_error.py.
    #[arg(long, value_name = "MODE", value_enum)]
    split: Option<bezier_subdiv::patch::view::Split>,
    /// Occlusion culling of subdiv and subdiv-indirect, on or off
    /// (default off: the paper's comparison culls by frustum and back
    /// faces alone, like the tessellators).
    #[arg(long, value_name = "on|off", value_parser = parse_on_off, default_value = "off", action = clap::ArgAction::Set)]
    occlusion: bool,
    /// Levels of detail below one patch for every measured method, on or
    /// off (default off; see `render --help`). The ground truth never
    /// uses them, so the error figures measure them.
    #[arg(long, value_name = "on|off", value_parser = parse_on_off, default_value = "off", action = clap::ArgAction::Set)]
    lod: bool,
    /// With --lod on: the largest mean angle in degrees between a level's
    /// shading normals and the surface's (see `render --help`).
    #[arg(long, value_name = "DEG", value_parser = parse_degrees, default_value_t = bezier_subdiv::lod::MOST_NORMAL_ERROR_DEG)]
    lod_shading: f32,
}

impl BenchFlags {
    /// The library's arguments: the flags, the scene resolved.
    fn into_args(self) -> BenchArgs {
        BenchArgs {
            methods: self.methods,
            eps: self.eps,
            lambda: self.lambda,
            frames: self.frames,
            size: self.size,
            warmup: self.warmup,
            flip_frames: self.flip_frames,
            grid: self.grid,
            device: self.device,
            quick: self.quick,
            validation: self.vk_validation,
            split: self.split,
            occlusion: self.occlusion,
            lod: self.lod,
            lod_shading: self.lod_shading,
            ..BenchArgs::new(resolve_scene(Some(&self.scene)), self.out)
        }
    }
}

#[derive(clap::Args)]
struct ViewArgs {
    /// Scene file (TOML).
    #[arg(long, default_value = commands::DEFAULT_SCENE)]
    scene: PathBuf,
    /// Pixel tolerance ε (default: the scene's, else 1).
    // A negative value reaches the range check, which says what is wrong,
    // instead of clap's "unexpected argument '-1'".
    #[arg(long, value_name = "PX", allow_negative_numbers = true)]
    eps: Option<f64>,
    /// Blend λ ∈ [0,1] of orthogonal (0) and parametric (1) distance
    /// (default: the scene's, else 0.5).
    #[arg(long, value_name = "L", allow_negative_numbers = true)]
    lambda: Option<f64>,
    /// Image size; ε is measured in its pixels (default 1920x1080, the
    /// paper's; view: the window's first size, default 1280x720).
    #[arg(long, value_name = "WxH", value_parser = parse_size)]
    size: Option<(u32, u32)>,
    /// How subdivision splits a node: iso (always 1:4, the paper's) or
    /// aniso (halve only the direction whose edges are not flat, 1:2; 1:4
    /// when both are or the inner tier fails). Default: the scene's, else
    /// iso. Only subdiv and subdiv-indirect read it.
    #[arg(long, value_name = "MODE", value_enum)]
    split: Option<bezier_subdiv::patch::view::Split>,
}

/// Flags shared by the commands that render.
#[derive(clap::Args)]
struct FrameArgs {
    #[command(flatten)]
    view: ViewArgs,
    /// An animated scene at this time in seconds (default 0; the
    /// animation wraps at its duration where it loops): deformed cages,
    /// sequence frames and keyed instances at that time, converted again
    /// on the GPU before the method runs (the "update" pass).
    #[arg(
        long,
        value_name = "SECONDS",
        conflicts_with = "anim_frame",
        allow_negative_numbers = true
    )]
    time: Option<f64>,
    /// An animated scene at frame K of its animation (K / the scene's
    /// [animation] fps, default 24).
    #[arg(long, value_name = "K")]
    anim_frame: Option<u64>,
    /// Camera keyframe: 0 is the scene camera, k ≥ 1 the path's key k
    /// (validate: every keyframe when not given).
    #[arg(long)]
    frame: Option<usize>,
    // The help lists the registry, so a new method appears by its entry.
    #[arg(long, default_value = bezier_subdiv::methods::DEFAULT_METHOD, help = method_help(false), long_help = method_help(true))]
    method: String,
    /// Draw path of the subdivision methods: auto (mesh shaders where
    /// available), mesh, fallback (compute expansion + vertex shader).
    #[arg(long, default_value = "auto")]
    draw: DrawRequest,
    /// Samples per pixel: 1 (no anti-aliasing), 2, 4 or 8 (default 1;
    /// view: 4). validate's oracle comparisons and hole test run
    /// single-sampled whatever this is.
    #[arg(long, value_name = "N")]
    msaa: Option<u32>,
    /// Vulkan device: an index from `info`, or part of its name.
    #[arg(long, value_name = "ID", default_value = "auto")]
    device: DeviceSelector,
    /// Enable the Khronos validation layer; any error fails the run.
    #[arg(long)]
    vk_validation: bool,
    /// subdiv and subdiv-indirect: occlusion culling, on or off. On, a
    /// frame draws the instances the last frame saw first, builds a depth
    /// pyramid from them, then tests every other instance, base patch and
    /// node against it; the image is the same, hidden work is skipped.
    /// Default: on for render and view, off for bench (the paper's
    /// comparison has none); validate compares with the oracle without it
    /// and checks that it changes no pixel.
    #[arg(long, value_name = "on|off", value_parser = parse_on_off)]
    occlusion: Option<bool>,
    /// Levels of detail below one patch, on or off (default off): far
    /// instances are drawn whole from a simplified triangle mesh of their
    /// model's limit surface, the coarsest whose measured error, projected
    /// at the instance's nearest depth, is within ε pixels. Made at the
    /// first load of a model (seconds per thousand patches) and kept for
    /// later runs of this build in $BEZIER_SUBDIV_CACHE (set empty: no
    /// cache), else $XDG_CACHE_HOME/bezier-subdiv or ~/.cache/bezier-subdiv;
    /// the reference never uses them.
    #[arg(long, value_name = "on|off", value_parser = parse_on_off, default_value = "off", action = clap::ArgAction::Set)]
    lod: bool,
    /// With --lod on: the largest mean angle, in degrees, between a
    /// level's shading normals and the limit surface's as seen at the
    /// instance's distance (measured per level at load over footprints of
    /// growing size; an instance takes a level only where the error over
    /// the footprint FLIP's filter averages, about 3.6 pixels, is within
    /// it). ε bounds a level's geometry only; rounded edges lose their
    /// highlights on coarse levels up close. Lower keeps the image nearer
    /// the patches', higher allows coarser levels.
    #[arg(long, value_name = "DEG", value_parser = parse_degrees, default_value_t = bezier_subdiv::lod::MOST_NORMAL_ERROR_DEG)]
    lod_shading: f32,
    // Each method's own flags, declared with its knobs in its file, under
    // a heading per method.
    #[command(flatten)]
    per_method: bezier_subdiv::methods::PerMethod,
    // clap carries the last heading on to the flags flattened after it
    // (the command's own): this puts them back under the default one.
    #[command(flatten, next_help_heading = None::<&str>)]
    _heading: DefaultHeading,
}

/// No flags: see `FrameArgs::_heading`.
#[derive(clap::Args)]
struct DefaultHeading {}

/// Image size of render, validate and stats when --size is not given.
const IMAGE_SIZE: (u32, u32) = (1920, 1080);
/// The window's first size in view.
const WINDOW_SIZE: (u32, u32) = (1280, 720);

impl FrameArgs {
    /// The request, with `size` and `msaa` where they were not given.
    fn request(&self, size: (u32, u32), msaa: u32) -> GpuRequest {
        GpuRequest {
            scene: resolve_scene(Some(&self.view.scene)),
            method: self.method.clone(),
            eps: self.view.eps,
            lambda: self.view.lambda,
            size: self.view.size.unwrap_or(size),
            draw: self.draw,
            per_method: self.per_method.clone(),
            msaa: self.msaa.unwrap_or(msaa),
            device: self.device.clone(),
            validation: self.vk_validation,
            split: self.view.split,
            time: match (self.time, self.anim_frame) {
                (Some(t), _) => Some(commands::AnimTime::Seconds(t)),
                (None, Some(k)) => Some(commands::AnimTime::Frame(k)),
                (None, None) => None,
            },
            occlusion: self.occlusion,
            lod: self.lod,
            lod_shading: self.lod_shading,
        }
    }
}

/// `--method`'s help: every registered method by name, or (`about`) one
/// line each with what it draws.
fn method_help(about: bool) -> String {
    let methods = bezier_subdiv::methods::METHODS.iter();
    if about {
        let lines: Vec<String> = methods
            .map(|m| format!("  {}: {}", m.name, m.about))
            .collect();
        format!("Method, one of:\n{}", lines.join("\n"))
    } else {
        let names: Vec<&str> = methods.map(|m| m.name).collect();
        format!("Method: {}", names.join(", "))
    }
}

fn parse_timeout(s: &str) -> Result<std::time::Duration, String> {
    bezier_subdiv::vk::parse_timeout(s)
}

fn parse_on_off(s: &str) -> Result<bool, String> {
    match s {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("expected on or off, got `{s}`")),
    }
}

/// An angle in degrees, above 0 and at most 180.
fn parse_degrees(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(d) if d > 0.0 && d <= 180.0 => Ok(d),
        Ok(d) => Err(format!(
            "expected an angle above 0 and at most 180 degrees, got {d}"
        )),
        Err(_) => Err(format!("expected an angle in degrees, got `{s}`")),
    }
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    let code = match set_timeout(cli.timeout).and_then(|()| run(cli.command)) {
        Ok(()) => 0,
        Err(e) => {
            // Not eprintln!: it panics when stderr is a closed pipe.
            let _ = writeln!(std::io::stderr(), "error: {e:#}");
            1
        }
    };
    if bezier_subdiv::vk::device_leaked() {
        end_without_exit_handlers(code);
    }
    ExitCode::from(code)
}

/// Ends the process skipping its exit handlers, after flushing what it
/// printed: a leaked device's driver may still run our work on its own
/// threads, and unloading it under them (as the handlers do) crashed
/// lavapipe with SIGSEGV after a fence timeout.
fn end_without_exit_handlers(code: u8) -> ! {
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    // SAFETY: `_exit` only ends the process; everything worth keeping
    // (files, the streams above) is already written.
    unsafe { libc::_exit(i32::from(code)) }
}

/// Writes `text` to stdout. A reader that went away (a closed pipe, as in
/// `| head -1`) is not a failure of the command: its work is done and its
/// files are written, and what is left to print has nobody to read it, so
/// the rest is dropped and the exit status stays the command's own. Every
/// command prints through this, never through `print!` (which panics on a
/// closed pipe).
fn emit(text: &str) -> anyhow::Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        r => r.map_err(|e| anyhow::anyhow!("writing to stdout: {e}")),
    }
}

/// The fence timeout: `--timeout`, else the environment's (refused here, before
/// any work, when it is not a number of seconds), else the default.
fn set_timeout(flag: Option<std::time::Duration>) -> anyhow::Result<()> {
    let env = bezier_subdiv::vk::env_fence_timeout().map_err(|e| anyhow::anyhow!(e))?;
    if let Some(t) = flag.or(env) {
        bezier_subdiv::vk::set_fence_timeout(t);
    }
    Ok(())
}

/// Runs one command: its arguments to the library's request, the run, what
/// it prints.
fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Stats {
            view,
            frame,
            json,
            preview,
            preview_shade,
            by_model,
        } => run_stats(view, frame, json, preview, preview_shade, by_model),
        Command::Render {
            frame,
            shade,
            out,
            warmup,
            repeat,
            flip,
        } => run_render(frame, shade, out, warmup, repeat, flip),
        Command::Validate {
            frame,
            frames,
            no_holes,
            debug_dir,
        } => run_validate(frame, frames, no_holes, debug_dir),
        Command::View {
            frame,
            shade,
            vsync,
            frames,
            screenshot,
            resize,
        } => run_view(frame, shade, vsync, frames, screenshot, resize),
        Command::Bench(flags) => run_bench(&flags.into_args()),
        Command::Info { vk_validation } => emit(&commands::info::run(vk_validation)?),
        Command::Import {
            file,
            out,
            boundary,
            isolate,
            fvar,
        } => {
            let options = bezier_subdiv::cage::obj::CageOptions {
                boundary,
                isolate,
                fvar,
            };
            emit(&commands::import::run(&file, out.as_deref(), &options)?)
        }
    }
}

/// `stats`: the CPU reference's figures, as a table or JSON.
fn run_stats(
    view: ViewArgs,
    frame: usize,
    json: bool,
    preview: Option<PathBuf>,
    preview_shade: PreviewShade,
    by_model: bool,
) -> anyhow::Result<()> {
    let mut args = StatsArgs::new(resolve_scene(Some(&view.scene)));
    args.frame = frame;
    args.eps = view.eps;
    args.lambda = view.lambda;
    args.size = view.size.unwrap_or(IMAGE_SIZE);
    args.preview = preview;
    args.preview_shade = preview_shade;
    args.by_model = by_model;
    args.split = view.split;
    let report = commands::stats::run(&args)?;
    if json {
        emit(&(serde_json::to_string_pretty(&report)? + "\n"))
    } else {
        let mut text = report.to_text();
        if let Some(p) = &report.preview {
            text += &format!("preview         {p} ({preview_shade})\n");
        }
        text += "note: these are the CPU reference's figures, without occlusion culling: \
                 `render --occlusion off` draws the same triangles on the GPU (`render` culls \
                 what is hidden by default).\n";
        emit(&text)
    }
}

/// `render`: one frame to a PNG; prints its summary.
fn run_render(
    frame: FrameArgs,
    shade: Shade,
    out: Option<PathBuf>,
    warmup: Option<u32>,
    repeat: u32,
    flip: bool,
) -> anyhow::Result<()> {
    let args = RenderArgs {
        frame: frame.frame.unwrap_or(0),
        gpu: frame.request(IMAGE_SIZE, 1),
        shade,
        out,
        warmup,
        repeat,
        flip,
    };
    emit(&commands::render::run(&args)?)
}

/// `validate`: prints the table; fails when a check did.
fn run_validate(
    frame: FrameArgs,
    frames: Vec<usize>,
    no_holes: bool,
    debug_dir: Option<PathBuf>,
) -> anyhow::Result<()> {
    let args = ValidateArgs {
        frames: frame.frame.map_or(frames, |k| vec![k]),
        gpu: frame.request(IMAGE_SIZE, 1),
        skip_holes: no_holes,
        debug_dir,
    };
    let report = commands::validate::run(&args)?;
    emit(&report.table)?;
    if report.ok() {
        Ok(())
    } else {
        Err(anyhow::anyhow!("validation failed"))
    }
}

/// `view`: the interactive window; prints what it says when it closes.
fn run_view(
    frame: FrameArgs,
    shade: Shade,
    vsync: bool,
    frames: Option<u64>,
    screenshot: Option<PathBuf>,
    resize: Option<(u32, u32)>,
) -> anyhow::Result<()> {
    let args = bezier_subdiv::app::ViewArgs {
        frame: frame.frame.unwrap_or(0),
        gpu: frame.request(WINDOW_SIZE, 4),
        shade,
        vsync,
        frames,
        screenshot,
        resize,
    };
    emit(&bezier_subdiv::app::run(&args)?)
}

/// `bench`: prints what was written; fails when the run stopped early
/// (the reports are written either way).
fn run_bench(args: &BenchArgs) -> anyhow::Result<()> {
    let done = commands::bench::run(args)?;
    emit(&format!(
        "wrote {}: frames.csv ({} frames), flip.csv ({} images), summary.json, report.md, plots\n",
        done.out.display(),
        done.rows,
        done.flips
    ))?;
    match done.stopped {
        None => Ok(()),
        Some(why) => Err(anyhow::anyhow!(
            "the run stopped early ({why}); the reports cover what was measured"
        )),
    }
}

#[cfg(test)]
mod tests {
    use clap::CommandFactory;

    /// clap's own checks of the flags (names given twice, groups, headings),
    /// which it otherwise runs only in debug builds.
    #[test]
    fn the_flags_are_well_formed() {
        super::Cli::command().debug_assert();
    }
}
