//! The `bezier-subdiv` command line.

use std::path::PathBuf;
use std::process::ExitCode;
use std::str::FromStr;

use clap::{Parser, Subcommand};

use bezier_subdiv::commands::render::{RenderArgs, Shade};
use bezier_subdiv::commands::validate::ValidateArgs;
use bezier_subdiv::commands::{self, parse_size, resolve_scene, stats::StatsArgs, GpuRequest};
use bezier_subdiv::draw::DrawRequest;
use bezier_subdiv::raster::PreviewShade;
use bezier_subdiv::vk::DeviceSelector;

/// View-adaptive, crack-free recursive subdivision of bicubic Bézier surfaces
/// (Tabaei, Kuth et al. 2026) on Vulkan, with a CPU reference of every
/// decision.
///
/// `render` draws one frame offscreen to a PNG with its statistics as JSON;
/// `validate` checks the GPU against the CPU reference and looks for holes;
/// `stats` prints the CPU reference's figures; `import` converts models;
/// `info` lists the Vulkan devices.
#[derive(Parser)]
#[command(name = "bezier-subdiv", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
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
        /// surface seen from behind is dark red), depth (QuadNode depth 0 dark
        /// blue … 10 dark red), wedges (depth darkened, wedges magenta).
        #[arg(long, value_name = "MODE", default_value = "normal", value_parser = PreviewShade::from_str)]
        preview_shade: PreviewShade,
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
        /// (depth map with the crack-closing wedges highlighted).
        #[arg(long, value_enum, default_value = "normal")]
        shade: Shade,
        /// Output PNG (default: out/<scene name>.png; out/ is created).
        #[arg(long, value_name = "FILE.png")]
        out: Option<PathBuf>,
        /// Time N more frames of the same view after the first (a warm-up):
        /// the stats file's gpu_ms become the medians, with gpu_ms_min and
        /// gpu_ms_max beside them.
        #[arg(long, value_name = "N", default_value_t = 0)]
        repeat: u32,
        /// Also draw the same view with ground-truth (at --grid) and compare:
        /// the mean FLIP goes into the stats file (flip_mean), the FLIP heat
        /// map to NAME.flip.png beside the image.
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
        /// Skip the hole test.
        #[arg(long)]
        no_holes: bool,
        /// Write the images of views where the hole test found holes here.
        #[arg(long, value_name = "DIR")]
        debug_dir: Option<PathBuf>,
    },
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
    /// for each patch the cage face it came from and the face-parameter
    /// coordinates of its corners (null for patches of non-quad faces).
    Import {
        /// The .obj cage or .bpt file.
        file: PathBuf,
        /// Write the patches here as .bpt (plus the .bpt.json sidecar).
        #[arg(long, value_name = "PATCHES.bpt")]
        out: Option<PathBuf>,
    },
}

/// What a view is made of: the scene and the tolerance in an image size.
#[derive(clap::Args)]
struct ViewArgs {
    /// Scene file (TOML).
    #[arg(long, default_value = commands::DEFAULT_SCENE)]
    scene: PathBuf,
    /// Pixel tolerance ε (default: the scene's, else 1).
    #[arg(long, value_name = "PX")]
    eps: Option<f64>,
    /// Blend λ ∈ [0,1] of orthogonal (0) and parametric (1) distance
    /// (default: the scene's, else 0.5).
    #[arg(long, value_name = "L")]
    lambda: Option<f64>,
    /// Image size; ε is measured in its pixels.
    #[arg(long, value_name = "WxH", default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
}

/// Flags shared by the commands that render.
#[derive(clap::Args)]
struct FrameArgs {
    #[command(flatten)]
    view: ViewArgs,
    /// Camera keyframe: 0 is the scene camera, k ≥ 1 the path's key k
    /// (validate: every keyframe when not given).
    #[arg(long)]
    frame: Option<usize>,
    /// Method: subdiv (recursive subdivision, persistent threads),
    /// subdiv-indirect (the same, one indirect dispatch per depth),
    /// ground-truth (a dense grid per patch, the reference images are
    /// compared with), tess (hardware tessellation, Buchenau-Guthe uniform
    /// levels) or tess-reparam (their re-parameterised samples). Planned:
    /// cudatess.
    #[arg(long, default_value = "subdiv")]
    method: String,
    /// Draw path of the subdivision methods: auto (mesh shaders where
    /// available), mesh, fallback (compute expansion + vertex shader).
    #[arg(long, default_value = "auto")]
    draw: DrawRequest,
    /// ground-truth: grid cells per patch side, a power of two up to 256
    /// (64, the paper's tessellation factor, costs 8,192 triangles per
    /// patch; lower it for quick references on a CPU device).
    #[arg(long, value_name = "N", default_value_t = bezier_subdiv::methods::ground_truth::DEFAULT_GRID)]
    grid: u32,
    /// subdiv-indirect: the deepest level, at most 10 (6, as in the paper:
    /// its node buffers are sized for the worst case, which grows fourfold
    /// per level).
    #[arg(long, value_name = "D", default_value_t = bezier_subdiv::methods::subdiv_indirect::DEFAULT_MAX_DEPTH)]
    max_depth: u32,
    /// subdiv: persistent workgroups to launch (default: about what the
    /// device keeps resident), for profiling.
    #[arg(long, value_name = "N")]
    groups: Option<u32>,
    /// Vulkan device: an index from `info`, or part of its name.
    #[arg(long, value_name = "ID", default_value = "auto")]
    device: DeviceSelector,
    /// Enable the Khronos validation layer; any error fails the run.
    #[arg(long)]
    vk_validation: bool,
}

impl FrameArgs {
    fn request(&self) -> GpuRequest {
        GpuRequest {
            scene: resolve_scene(Some(&self.view.scene)),
            method: self.method.clone(),
            eps: self.view.eps,
            lambda: self.view.lambda,
            size: self.view.size,
            draw: self.draw,
            grid: self.grid,
            max_depth: self.max_depth,
            groups: self.groups,
            device: self.device.clone(),
            validation: self.vk_validation,
        }
    }
}

fn main() -> ExitCode {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    let cli = Cli::parse();
    match run(cli.command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Stats {
            view,
            frame,
            json,
            preview,
            preview_shade,
        } => {
            let mut args = StatsArgs::new(resolve_scene(Some(&view.scene)));
            args.frame = frame;
            args.eps = view.eps;
            args.lambda = view.lambda;
            args.size = view.size;
            args.preview = preview;
            args.preview_shade = preview_shade;
            let report = commands::stats::run(&args)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{}", report.to_text());
                if let Some(p) = &report.preview {
                    println!("preview         {p} ({preview_shade})");
                }
                println!("note: these are the CPU reference's figures; `render` runs the GPU.");
            }
            Ok(())
        }
        Command::Render {
            frame,
            shade,
            out,
            repeat,
            flip,
        } => {
            let args = RenderArgs {
                frame: frame.frame.unwrap_or(0),
                gpu: frame.request(),
                shade,
                out,
                repeat,
                flip,
            };
            print!("{}", commands::render::run(&args)?);
            Ok(())
        }
        Command::Validate {
            frame,
            no_holes,
            debug_dir,
        } => {
            let args = ValidateArgs {
                frame: frame.frame,
                gpu: frame.request(),
                skip_holes: no_holes,
                debug_dir,
            };
            let report = commands::validate::run(&args)?;
            print!("{}", report.table);
            if report.ok() {
                Ok(())
            } else {
                Err(anyhow::anyhow!("validation failed"))
            }
        }
        Command::Info { vk_validation } => {
            print!("{}", commands::info::run(vk_validation)?);
            Ok(())
        }
        Command::Import { file, out } => {
            print!("{}", commands::import::run(&file, out.as_deref())?);
            Ok(())
        }
    }
}
