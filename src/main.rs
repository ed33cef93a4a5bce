//! The `bezier-subdiv` command line.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use bezier_subdiv::commands::{self, parse_size, resolve_scene, stats::StatsArgs};

/// View-adaptive, crack-free recursive subdivision of bicubic Bézier surfaces
/// (Tabaei, Kuth et al. 2026) on Vulkan, with a CPU reference of every
/// decision. The GPU renderer is not built yet: `stats` runs the CPU oracle.
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
        } => {
            let mut args = StatsArgs::new(resolve_scene(Some(&scene)));
            args.frame = frame;
            args.eps = eps;
            args.lambda = lambda;
            args.size = size;
            let report = commands::stats::run(&args)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{}", report.to_text());
                println!("note: these are the CPU oracle's figures; the GPU renderer (`render`) is not built yet.");
            }
            Ok(())
        }
        Command::Import { file, out } => {
            print!("{}", commands::import::run(&file, out.as_deref())?);
            Ok(())
        }
    }
}
