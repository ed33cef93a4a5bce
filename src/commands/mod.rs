//! The command-line verbs, as library functions the binary and the tests call.

pub mod bench;
pub mod import;
pub mod info;
pub mod progress;
pub mod render;
pub mod stats;
pub mod validate;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::anyhow;

use crate::renderer::{Renderer, RendererOptions};
use crate::scene::camera::Camera;
use crate::scene::desc::Scene;

/// The scene used when `--scene` is not given.
pub const DEFAULT_SCENE: &str = "scenes/kitchen.toml";

/// Where `render` and the window's screenshots go when no file is named.
pub const DEFAULT_OUT_DIR: &str = "out";

/// Resolves a scene path: as given if it exists, else relative to the
/// source tree (so `cargo run` works from any directory).
pub fn resolve_scene(path: Option<&Path>) -> PathBuf {
    let p = path.map_or_else(|| PathBuf::from(DEFAULT_SCENE), Path::to_path_buf);
    if p.exists() || p.is_absolute() {
        return p;
    }
    let in_tree = Path::new(env!("CARGO_MANIFEST_DIR")).join(&p);
    if in_tree.exists() {
        in_tree
    } else {
        p
    }
}

/// What every command that runs the GPU is asked for: the scene, the
/// method and its tolerance, the image, the device.
#[derive(Clone, Debug)]
pub struct GpuRequest {
    /// Scene file.
    pub scene: PathBuf,
    /// Method name.
    pub method: String,
    /// ε override.
    pub eps: Option<f64>,
    /// λ override.
    pub lambda: Option<f64>,
    /// Image size (the tolerance is measured in its pixels).
    pub size: (u32, u32),
    /// Draw path request.
    pub draw: crate::draw::DrawRequest,
    /// Each method's own knobs, as the renderer takes them.
    pub per_method: crate::methods::PerMethod,
    /// Samples per pixel of the image.
    pub msaa: u32,
    /// Device choice.
    pub device: crate::vk::DeviceSelector,
    /// Khronos validation layer on (any error fails the run).
    pub validation: bool,
    /// `subdiv`, `subdiv-indirect`: how a node splits (`None`: the
    /// scene's `[view] split`).
    pub split: Option<crate::patch::view::Split>,
    /// The animation's time (`None`: 0 where the scene moves).
    pub time: Option<AnimTime>,
    /// `subdiv`, `subdiv-indirect`: occlusion culling (`None`: the
    /// command's default, on for render and view, off for bench).
    pub occlusion: Option<bool>,
    /// Levels of detail below one patch (src/lod) for the methods the
    /// reference measures.
    pub lod: bool,
    /// The largest mean angle, in degrees, between a level's shading
    /// normals and the surface's (`lod::MOST_NORMAL_ERROR` by default).
    pub lod_shading: f32,
}

/// When in a scene's animation a frame is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnimTime {
    /// Seconds from the start.
    Seconds(f64),
    /// Frame K at the animation's frames per second.
    Frame(u64),
}

impl GpuRequest {
    /// The defaults for `scene`: method subdiv, the scene's ε and λ,
    /// 1920×1080, automatic draw path and device, no validation layer.
    pub fn new(scene: PathBuf) -> Self {
        GpuRequest {
            scene,
            method: crate::methods::DEFAULT_METHOD.into(),
            eps: None,
            lambda: None,
            size: (1920, 1080),
            draw: crate::draw::DrawRequest::Auto,
            per_method: crate::methods::PerMethod::default(),
            msaa: 1,
            device: crate::vk::DeviceSelector::Auto,
            validation: false,
            split: None,
            time: None,
            occlusion: None,
            lod: false,
            lod_shading: crate::lod::MOST_NORMAL_ERROR_DEG,
        }
    }

    /// The time in seconds the request asks for in `anim` (0 by default),
    /// or the sentence why it cannot (a time for a scene that does not
    /// move, a negative or non-finite time).
    pub fn seconds(&self, anim: Option<&crate::anim::Animation>) -> anyhow::Result<f64> {
        match (self.time, anim) {
            (None, _) => Ok(0.0),
            (Some(_), None) => Err(anyhow!(
                "--time/--anim-frame: {} does not move (no [[model.deform]], OBJ sequence or instance keys)",
                self.scene.display()
            )),
            (Some(AnimTime::Seconds(t)), Some(_)) if !(t.is_finite() && t >= 0.0) => Err(anyhow!(
                "--time must be a number of seconds ≥ 0 (got {t})"
            )),
            (Some(AnimTime::Seconds(t)), Some(_)) => Ok(t),
            (Some(AnimTime::Frame(k)), Some(a)) => Ok(k as f64 / a.fps),
        }
    }

    /// Hands `anim` (the scene's, as loaded) to `renderer` at the request's
    /// time; returns the time.
    pub fn animate(
        &self,
        renderer: &mut Renderer,
        anim: Option<&crate::anim::Animation>,
    ) -> anyhow::Result<f64> {
        let t = self.seconds(anim)?;
        renderer.set_animation(anim.cloned())?;
        renderer.set_time(t);
        Ok(t)
    }

    /// This request's ε, λ and split mode resolved against `scene`.
    pub fn view_request(&self, scene: &Scene) -> anyhow::Result<ViewRequest> {
        ViewRequest::resolve(scene, self.eps, self.lambda, self.split)
    }

    /// The method's registry entry, or the sentence why there is none
    /// (checked before any GPU work).
    pub fn method_info(&self) -> anyhow::Result<&'static crate::methods::MethodInfo> {
        self.per_method.check().map_err(|e| anyhow!(e))?;
        if crate::gpu::sample_count(self.msaa).is_none() {
            return Err(anyhow!("--msaa must be 1, 2, 4 or 8 (got {})", self.msaa));
        }
        Ok(crate::methods::find(&self.method)?)
    }

    /// The renderer for `geo` and its shading patches on `ctx`: the
    /// requested method and draw path, the default buffer budget, the
    /// requested size, the render background.
    pub fn renderer(
        &self,
        ctx: &Arc<crate::vk::Context>,
        geo: &crate::scene::geometry::SceneGeometry,
        shading: &crate::scene::geometry::SceneShading,
    ) -> anyhow::Result<Renderer> {
        let draw = crate::draw::choose(ctx, self.draw)?;
        // Occlusion culling's late phase tests model-space patch boxes that
        // do not yet hold a displaced surface: off for displaced scenes.
        let displaced = geo.displacement.in_use();
        if displaced && self.occlusion == Some(true) {
            anyhow::bail!(
                "--occlusion on: occlusion culling does not cover displaced models yet; \
                 leave it out (it is off for displaced scenes)"
            );
        }
        let methods = crate::methods::MethodOptions {
            samples: self.msaa,
            occlusion: self.occlusion.unwrap_or(!displaced),
            per_method: self.per_method.clone(),
            ..crate::methods::MethodOptions::new(draw)
        };
        let options = RendererOptions {
            size: self.size,
            background: render::BACKGROUND,
            frames_in_flight: crate::renderer::DEFAULT_FRAMES_IN_FLIGHT,
            methods,
        };
        let mut renderer = Renderer::new(Arc::clone(ctx), geo, shading, &self.method, options)?;
        if self.lod {
            renderer.set_levels(Some(build_levels(geo, self.lod_shading)))?;
        }
        Ok(renderer)
    }

    /// A Vulkan context on the requested device.
    pub fn context(&self) -> crate::vk::VkResult<Arc<crate::vk::Context>> {
        crate::vk::Context::new(&crate::vk::ContextOptions {
            selector: self.device.clone(),
            validation: self.validation,
            notice: Some(print_notice),
            ..crate::vk::ContextOptions::default()
        })
        .map(Arc::new)
    }
}

/// The levels of detail of `geo`'s models, saying on stderr what was
/// made and how long it took (seconds for a model of thousands of
/// patches), and which models got none and why.
pub fn build_levels(
    geo: &crate::scene::geometry::SceneGeometry,
    shading_degrees: f32,
) -> crate::lod::SceneLevels {
    let start = std::time::Instant::now();
    let cache = crate::lod::cache::LevelCache::from_env();
    let levels =
        crate::lod::SceneLevels::build_cached(geo, shading_degrees.to_radians(), cache.as_ref());
    let (patch_bytes, level_bytes) = levels.bytes();
    let with = levels
        .models
        .iter()
        .filter(|m| !m.levels.is_empty())
        .count();
    // Where the levels came from: read back, or made (and stored).
    let cached = cache.map_or_else(String::new, |c| {
        format!(
            "; level cache {}: {} models' levels read, {} made and stored",
            c.dir().display(),
            c.hits.get(),
            c.stored.get()
        )
    });
    eprintln!(
        "levels of detail: {with} of {} models, {} levels, {} bytes ({:.2}× their patches'), ready in {:.1} s{cached}",
        levels.models.len(),
        levels.models.iter().map(|m| m.levels.len()).sum::<usize>(),
        crate::figures::thousands(level_bytes),
        level_bytes as f64 / patch_bytes.max(1) as f64,
        start.elapsed().as_secs_f64()
    );
    for m in levels.models.iter().filter_map(|m| m.none_because) {
        eprintln!("levels of detail: a model gets none ({m})");
    }
    levels
}

/// What the Vulkan layer tells a user of the command line while it waits
/// (shaders compiling on their first use): one line on stderr.
pub fn print_notice(message: &str) {
    eprintln!("{message}");
}

/// Tells a user of a GPU command that `methods` (those of them that do
/// not displace) draw the scene's displaced models undisplaced.
pub fn note_undisplaced(geo: &crate::scene::geometry::SceneGeometry, methods: &[String]) {
    let names: Vec<&str> = geo
        .models
        .iter()
        .zip(&geo.displacement.models)
        .filter(|(_, d)| d.is_some())
        .map(|(m, _)| m.name.as_str())
        .collect();
    let plain: Vec<&str> = methods
        .iter()
        .map(String::as_str)
        .filter(|m| !crate::methods::reads(m).displacement)
        .collect();
    if !names.is_empty() && !plain.is_empty() {
        eprintln!(
            "note: {} draw{} the displaced models ({}) undisplaced: only {} displace so far",
            plain.join(", "),
            if plain.len() == 1 { "s" } else { "" },
            names.join(", "),
            crate::methods::names_that_read(|r| r.displacement)
        );
    }
}

/// Keyframe `k` of `scene` (read from `path`), or an error naming the
/// frames there are.
pub fn keyframe(scene: &Scene, path: &Path, k: usize) -> anyhow::Result<Camera> {
    scene.frame_camera(k).ok_or_else(|| {
        anyhow!(
            "{}: frame {k} does not exist (the scene has frames 0..={})",
            path.display(),
            scene.frame_count() - 1
        )
    })
}

/// How finely a command's views are drawn: ε, λ and the split mode, the
/// command line's where it gives them, else the scene's `[view]`. Resolved
/// and checked once, where the scene is first read, so every command (and
/// the window) draws with the same choices and refuses the same values in
/// the same words.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewRequest {
    /// Pixel tolerance ε.
    pub eps: f64,
    /// Blend λ between orthogonal (0) and parametric (1) distance.
    pub lambda: f64,
    /// How `subdiv` and `subdiv-indirect` split a node.
    pub split: crate::patch::view::Split,
}

impl ViewRequest {
    /// The overrides, else `scene`'s defaults; refused (with a sentence)
    /// when ε ≤ 0 or λ is outside [0, 1].
    pub fn resolve(
        scene: &Scene,
        eps: Option<f64>,
        lambda: Option<f64>,
        split: Option<crate::patch::view::Split>,
    ) -> anyhow::Result<Self> {
        let eps = eps.unwrap_or(scene.view.eps);
        let lambda = lambda.unwrap_or(scene.view.lambda);
        if !(eps.is_finite() && eps > 0.0) {
            return Err(anyhow!(
                "--eps must be a positive number of pixels (got {eps})"
            ));
        }
        if !(0.0..=1.0).contains(&lambda) {
            return Err(anyhow!("--lambda must be in [0, 1] (got {lambda})"));
        }
        Ok(ViewRequest {
            eps,
            lambda,
            split: split.unwrap_or(scene.view.split),
        })
    }
}

/// Parses `WxH` (e.g. `1920x1080`).
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("size '{s}' is not WIDTHxHEIGHT (e.g. 1920x1080)"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("bad height in '{s}'"))?;
    if w == 0 || h == 0 || w > 16384 || h > 16384 {
        return Err(format!("size '{s}' must be between 1x1 and 16384x16384"));
    }
    Ok((w, h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_parse_and_refuse() {
        assert_eq!(parse_size("640x360"), Ok((640, 360)));
        assert!(parse_size("640").is_err());
        assert!(parse_size("0x10").is_err());
        assert!(parse_size("axb").is_err());
    }
}
