//! A scene as its file describes it: the models with their instances and
//! animation, the cameras, the view defaults. `file.rs` reads it from TOML;
//! `geometry.rs` loads its models; both depend on this and not on each
//! other.

use std::path::PathBuf;

use glam::DMat4;
use serde::Deserialize;

use super::camera::Camera;
use super::orbit::Orbit;
use crate::cage::obj::CageOptions;

/// Default ε and λ of a scene.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewDefaults {
    /// Pixel tolerance ε.
    #[serde(default = "default_eps")]
    pub eps: f64,
    /// Blend λ.
    #[serde(default = "default_lambda")]
    pub lambda: f64,
    /// How `subdiv` and `subdiv-indirect` split a node (`iso`, the paper's
    /// 1:4, or `aniso`).
    #[serde(default)]
    pub split: crate::patch::view::Split,
}

impl Default for ViewDefaults {
    fn default() -> Self {
        ViewDefaults {
            eps: default_eps(),
            lambda: default_lambda(),
            split: Default::default(),
        }
    }
}

fn default_eps() -> f64 {
    1.0
}
fn default_lambda() -> f64 {
    0.5
}
/// What a model file's faces are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Surface {
    /// A Catmull–Clark cage (or a patch file).
    #[default]
    Cage,
    /// A triangle mesh drawn as PN triangles ([`super::pn`]).
    PnTriangles,
}

/// One model of a scene with its instance transforms.
#[derive(Clone, Debug)]
pub struct ModelDesc {
    /// Display name.
    pub name: String,
    /// Resolved model file.
    pub file: PathBuf,
    /// Never back-face culled.
    pub two_sided: bool,
    /// Choices for a cage the file does not make itself.
    pub options: CageOptions,
    /// A cage or PN triangles.
    pub surface: Surface,
    /// The albedo map the scene file names (`texture`), which takes the
    /// place of the one the model's material names.
    pub texture: Option<PathBuf>,
    /// The height map that displaces the surface (`displacement`).
    pub displacement: Option<crate::scene::displacement::DisplacementDesc>,
    /// Object → world transforms.
    pub instances: Vec<DMat4>,
    /// What moves: deformers, an OBJ sequence, keyed instances.
    pub anim: ModelAnim,
}

/// What of a model moves (`src/anim/`).
#[derive(Clone, Debug, Default)]
pub struct ModelAnim {
    /// Deformers of its cage, applied in order.
    pub deform: Vec<crate::scene::keys::Deformer>,
    /// The frame files of an OBJ sequence (`file` with a run of `#`); the
    /// first is [`ModelDesc::file`].
    pub sequence: Vec<PathBuf>,
    /// Per instance (parallel to [`ModelDesc::instances`]): its keyed
    /// transform, if it has keys.
    pub keys: Vec<Option<crate::scene::keys::InstanceKeys>>,
}

impl ModelAnim {
    /// Whether the model's cage moves (deformers or a sequence).
    pub fn deforms(&self) -> bool {
        !self.deform.is_empty() || self.sequence.len() > 1
    }

    /// Whether anything of the model moves.
    pub fn moves(&self) -> bool {
        self.deforms() || self.keys.iter().any(Option::is_some)
    }
}

/// A parsed scene file.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The scene file.
    pub path: PathBuf,
    /// Display name.
    pub name: String,
    /// Default ε and λ.
    pub view: ViewDefaults,
    /// Frame 0's camera.
    pub camera: Camera,
    /// Camera path keyframes (frames 1..).
    pub keys: Vec<Camera>,
    /// Frames `bench` samples along the path.
    pub path_frames: u32,
    /// The orbit `bench` samples instead of the keyframe path, if given.
    pub orbit: Option<Orbit>,
    /// Models.
    pub models: Vec<ModelDesc>,
    /// The `[animation]` table (defaults where absent).
    pub animation: crate::scene::keys::AnimationToml,
}

impl Scene {
    /// Number of keyframes: the scene camera plus the path keys.
    pub fn frame_count(&self) -> usize {
        1 + self.keys.len()
    }

    /// Keyframe `k`: 0 is `[camera]`, `k ≥ 1` is path key `k`.
    pub fn frame_camera(&self, k: usize) -> Option<Camera> {
        match k {
            0 => Some(self.camera),
            _ => self.keys.get(k - 1).copied(),
        }
    }

    /// The camera at `t` ∈ [0, 1] along the piecewise-linear path through
    /// every keyframe (frame 0 first).
    pub fn path_camera(&self, t: f64) -> Camera {
        let frames: Vec<Camera> = (0..self.frame_count())
            .filter_map(|k| self.frame_camera(k))
            .collect();
        if frames.len() == 1 {
            return frames[0];
        }
        let x = t.clamp(0.0, 1.0) * (frames.len() - 1) as f64;
        let i = (x.floor() as usize).min(frames.len() - 2);
        frames[i].lerp(&frames[i + 1], x - i as f64)
    }
}
