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
        /// Scene file (TOML).
        #[arg(long, default_value = commands::DEFAULT_SCENE)]
        scene: PathBuf,
        /// Camera keyframe: 0 is the scene camera, k ≥ 1 the path's key k.
        #[arg(long, default_value_t = 0)]
        frame: usize,
        /// Pixel tolerance ε (default: the scene's, else 1).
        #[arg(long, value_name = "PX")]
        eps: Option<f64>,
        /// Blend λ ∈ [0,1] of orthogonal (0) and parametric (1) distance
        /// (default: the scene's, else 0.5).
        #[arg(long, value_name = "L")]
        lambda: Option<f64>,
        /// Viewport size the tolerance is measured in.
        #[arg(long, value_name = "WxH", default_value = "1920x1080", value_parser = parse_size)]
        size: (u32, u32),
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
    },
    /// Render one frame offscreen: a PNG plus its statistics as JSON.
    ///
    /// The stats file (same path, .json) holds the scene, device, draw path,
    /// method, ε, λ, the subdivision counts, queue use, GPU time per pass
    /// and memory per purpose. Output paths are checked before any GPU work;
    /// a failed run leaves no file behind.
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
        boundary: Option<bezier_subdiv::scene::sharpness::BoundaryRule>,
    },
}

/// Flags shared by the commands that render.
#[derive(clap::Args)]
struct FrameArgs {
    /// Scene file (TOML).
    #[arg(long, default_value = commands::DEFAULT_SCENE)]
    scene: PathBuf,
    /// Camera keyframe: 0 is the scene camera, k ≥ 1 the path's key k
    /// (validate: every keyframe when not given).
    #[arg(long)]
    frame: Option<usize>,
    /// Method: subdiv (later: subdiv-indirect, tess, tess-reparam, cudatess,
    /// ground-truth).
    #[arg(long, default_value = "subdiv")]
    method: String,
    /// Pixel tolerance ε (default: the scene's, else 1).
    #[arg(long, value_name = "PX")]
    eps: Option<f64>,
    /// Blend λ ∈ [0,1] of orthogonal (0) and parametric (1) distance
    /// (default: the scene's, else 0.5).
    #[arg(long, value_name = "L")]
    lambda: Option<f64>,
    /// Image size.
    #[arg(long, value_name = "WxH", default_value = "1920x1080", value_parser = parse_size)]
    size: (u32, u32),
    /// Draw path: auto (mesh shaders where available), mesh, fallback
    /// (compute expansion + vertex shader).
    #[arg(long, default_value = "auto")]
    draw: DrawRequest,
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
            scene: resolve_scene(Some(&self.scene)),
            method: self.method.clone(),
            eps: self.eps,
            lambda: self.lambda,
            size: self.size,
            draw: self.draw,
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
            scene,
            frame,
            eps,
            lambda,
            size,
            json,
            preview,
            preview_shade,
        } => {
            let mut args = StatsArgs::new(resolve_scene(Some(&scene)));
            args.frame = frame;
            args.eps = eps;
            args.lambda = lambda;
            args.size = size;
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
        Command::Render { frame, shade, out } => {
            let args = RenderArgs {
                frame: frame.frame.unwrap_or(0),
                gpu: frame.request(),
                shade,
                out,
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
        Command::Import {
            file,
            out,
            boundary,
        } => {
            let options = bezier_subdiv::scene::obj::CageOptions { boundary };
            print!(
                "{}",
                commands::import::run(&file, out.as_deref(), &options)?
            );
            Ok(())
        }
    }
}
