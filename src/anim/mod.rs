//! Animated scenes: deforming cages (procedural deformers, OBJ sequences)
//! and moving instances, converted again every frame by the stencil tables
//! (`scene/stencil.rs`) on the GPU (`gpu/anim.rs`, the update pass) and, for
//! the oracle, on the CPU here, in the same f32 operations.
//!
//! One frame, at time t:
//! 1. the inputs: per animated model its cage vertices (the rest pose, or
//!    the sequence's frames interpolated) and its deformers' numbers at t;
//!    per animated instance its transform at t, as f32 3×4 ([`Frame`],
//!    computed on the CPU once and handed to both sides);
//! 2. *deform*: each vertex through its model's deformers in order
//!    ([`deform::apply`]);
//! 3. *points*: every point row of the model's table;
//! 4. *vectors*: every shading row;
//! 5. *instances*: every patch of every animated instance, its 16 points
//!    and 24 vectors transformed (points x' = ((m₀x + m₁y) + m₂z) + m₃ per
//!    row, vectors without m₃ and + 0), u and v swapped for a mirroring
//!    transform, written over the scene's base patches and shading patches.
//!
//! Which instances: every instance of a model whose cage moves, and every
//! instance with keys. The others keep the transform applied at load (f64,
//! rounded once); an animated one is transformed in f32 in every frame,
//! also at rest.

pub mod deform;
pub mod keys;
pub mod sequence;

use std::sync::Arc;

use glam::{DMat4, Vec3};

use crate::patch::bezier::BezierPatch;
use crate::scene::file::{Scene, SceneGeometry, SceneShading};
use crate::scene::shading::ShadingPatch;
use crate::scene::stencil::CageModel;
use crate::scene::SceneError;
use deform::GpuDeformer;

/// Frames per second unless the scene says.
pub const DEFAULT_FPS: f64 = 24.0;
/// Seconds of an animation whose curves give no end (steady waves).
pub const DEFAULT_DURATION: f64 = 4.0;

/// One animated model.
#[derive(Clone, Debug)]
pub struct AnimModel {
    /// Its index among the scene's models.
    pub scene_model: usize,
    /// Its stencils and rest pose.
    pub cage: Arc<CageModel>,
    /// Its deformers, in order.
    pub deform: Vec<keys::Deformer>,
    /// The cage vertices of each frame of its OBJ sequence (empty: none).
    pub sequence: Vec<Vec<Vec3>>,
}

/// Where an animated instance takes its transform from.
#[derive(Clone, Debug)]
pub enum Placement {
    /// The same at every time.
    Fixed(DMat4),
    /// Keys.
    Keyed(keys::InstanceKeys),
}

/// One animated instance.
#[derive(Clone, Debug)]
pub struct AnimInstance {
    /// Its model, an index into [`Animation::models`].
    pub model: usize,
    /// Its first base patch in the scene.
    pub first_patch: u32,
    /// Its transform.
    pub placement: Placement,
    /// The transform mirrors: u and v are swapped.
    pub mirror: bool,
}

/// What moves in a scene, and how.
#[derive(Clone, Debug)]
pub struct Animation {
    /// Seconds of one pass.
    pub duration: f64,
    /// Frames per second.
    pub fps: f64,
    /// Whether time wraps at the end.
    pub looping: bool,
    /// The models whose cage or instances move.
    pub models: Vec<AnimModel>,
    /// The instances that move.
    pub instances: Vec<AnimInstance>,
}

/// The inputs of one frame: everything that depends on time alone.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Frame {
    /// The time, after wrapping.
    pub time: f64,
    /// Per model, the cage vertices where they are not the rest pose (a
    /// sequence), else empty.
    pub inputs: Vec<Vec<Vec3>>,
    /// Per model, its deformers at this time.
    pub deformers: Vec<Vec<GpuDeformer>>,
    /// Per instance, its transform: rows of a 3×4 matrix.
    pub transforms: Vec<[f32; 12]>,
}

/// The f32 rows of the affine part of `m`, -0 made +0.
pub fn rows_of(m: &DMat4) -> [f32; 12] {
    let r = m.transpose();
    let mut out = [0.0f32; 12];
    for (i, row) in [r.x_axis, r.y_axis, r.z_axis].iter().enumerate() {
        for (j, v) in row.to_array().iter().enumerate() {
            out[4 * i + j] = *v as f32 + 0.0;
        }
    }
    out
}

/// `m` applied to the point `p` in f32, the twin of `anim_point`.
pub fn transform_point(m: &[f32; 12], p: Vec3) -> Vec3 {
    let row =
        |i: usize| ((m[4 * i] * p.x + m[4 * i + 1] * p.y) + m[4 * i + 2] * p.z) + m[4 * i + 3];
    Vec3::new(row(0), row(1), row(2))
}

/// `m`'s linear part applied to the vector `d` in f32, the twin of
/// `anim_vector`.
pub fn transform_vector(m: &[f32; 12], d: Vec3) -> Vec3 {
    let row = |i: usize| ((m[4 * i] * d.x + m[4 * i + 1] * d.y) + m[4 * i + 2] * d.z) + 0.0;
    Vec3::new(row(0), row(1), row(2))
}

impl Animation {
    /// What of `scene` moves, with the models as loaded in `models` (see
    /// `Scene::load_animated`); `None` where nothing does.
    pub fn new(
        scene: &Scene,
        geo: &SceneGeometry,
        cage_of: &dyn Fn(usize) -> Option<Arc<CageModel>>,
    ) -> Result<Option<Self>, SceneError> {
        if !scene.models.iter().any(|m| m.anim.moves()) {
            return Ok(None);
        }
        let mut models = Vec::new();
        let mut instances = Vec::new();
        let mut first = 0u32;
        let mut end = 0.0f64;
        for (index, m) in scene.models.iter().enumerate() {
            let summary = &geo.models[index];
            let per = summary.patches_per_instance as u32;
            let base = first;
            first += per * summary.instances as u32;
            if !m.anim.moves() {
                continue;
            }
            let model_error = |msg: String| SceneError::Model {
                scene: scene.path.clone(),
                model: m.name.clone(),
                msg,
            };
            let cage = cage_of(index).ok_or_else(|| {
                model_error("cannot be animated: its cage's faces could not be matched to the file's `f` lines".into())
            })?;
            let mut sequence = Vec::new();
            if m.anim.sequence.len() > 1 {
                sequence.push(cage.rest.clone());
                for frame in &m.anim.sequence[1..] {
                    sequence.push(sequence::read_frame(frame, &cage)?);
                }
            }
            end = end.max((sequence.len().max(1) - 1) as f64 / scene_fps(scene));
            for d in &m.anim.deform {
                end = end.max(d.end());
            }
            let model = models.len();
            for (k, xf) in m.instances.iter().enumerate() {
                let keyed = m.anim.keys.get(k).cloned().flatten();
                if !m.anim.deforms() && keyed.is_none() {
                    continue;
                }
                let placement = match keyed {
                    Some(keys) => {
                        end = end.max(keys.end());
                        Placement::Keyed(keys)
                    }
                    None => Placement::Fixed(*xf),
                };
                let mirror = match &placement {
                    Placement::Fixed(m) => m.determinant() < 0.0,
                    Placement::Keyed(keys) => keys.at(0.0).determinant() < 0.0,
                };
                instances.push(AnimInstance {
                    model,
                    first_patch: base + per * k as u32,
                    placement,
                    mirror,
                });
            }
            models.push(AnimModel {
                scene_model: index,
                cage,
                deform: m.anim.deform.clone(),
                sequence,
            });
        }
        let a = &scene.animation;
        let duration = a
            .duration
            .unwrap_or(if end > 0.0 { end } else { DEFAULT_DURATION });
        if !(duration.is_finite() && duration > 0.0) {
            return Err(SceneError::invalid(
                &scene.path,
                format!("[animation] duration must be > 0 (got {duration})"),
            ));
        }
        let fps = scene_fps(scene);
        Ok(Some(Animation {
            duration,
            fps,
            looping: a.looping.unwrap_or(true),
            models,
            instances,
        }))
    }

    /// Patches the update pass writes per frame.
    pub fn patches(&self) -> usize {
        self.instances
            .iter()
            .map(|i| self.models[i.model].cage.stencils.patches())
            .sum()
    }

    /// The time `t` falls on: wrapped into one pass, or held at the end.
    pub fn wrap(&self, t: f64) -> f64 {
        if self.looping {
            t.rem_euclid(self.duration)
        } else {
            t.clamp(0.0, self.duration)
        }
    }

    /// The inputs of the frame at time `t`.
    pub fn frame(&self, t: f64) -> Frame {
        let time = self.wrap(t);
        let inputs = self
            .models
            .iter()
            .map(|m| sequence_at(&m.sequence, time * self.fps))
            .collect();
        let deformers = self
            .models
            .iter()
            .map(|m| m.deform.iter().map(|d| d.at(time)).collect())
            .collect();
        let transforms = self
            .instances
            .iter()
            .map(|i| match &i.placement {
                Placement::Fixed(m) => rows_of(m),
                Placement::Keyed(k) => rows_of(&k.at(time)),
            })
            .collect();
        Frame {
            time,
            inputs,
            deformers,
            transforms,
        }
    }

    /// The model-space patches and shading patches of model `m` in `frame`
    /// (the CPU twin of the deform, points and vectors passes).
    pub fn model_pose(&self, frame: &Frame, m: usize) -> (Vec<BezierPatch>, Vec<ShadingPatch>) {
        let model = &self.models[m];
        let input = if frame.inputs[m].is_empty() {
            &model.cage.rest
        } else {
            &frame.inputs[m]
        };
        let verts: Vec<Vec3> = input
            .iter()
            .map(|p| {
                let q = frame.deformers[m]
                    .iter()
                    .fold(p.to_array(), |q, d| deform::apply(d, q));
                Vec3::from_array(q)
            })
            .collect();
        model.cage.stencils.evaluate(&verts)
    }

    /// Writes frame `frame`'s animated instances over `geo` and `shading`
    /// (the scene at rest): the oracle's scene at that time.
    pub fn pose(&self, frame: &Frame, geo: &mut SceneGeometry, shading: &mut SceneShading) {
        let poses: Vec<_> = (0..self.models.len())
            .map(|m| self.model_pose(frame, m))
            .collect();
        for (inst, m) in self.instances.iter().zip(&frame.transforms) {
            let (patches, vectors) = &poses[inst.model];
            for (k, (p, s)) in patches.iter().zip(vectors).enumerate() {
                let (p, s) = instance_patch(m, inst.mirror, p, s);
                let at = inst.first_patch as usize + k;
                geo.patches[at] = p;
                if let Some(slot) = shading.patches.get_mut(at) {
                    *slot = s;
                }
            }
        }
    }
}

/// One patch and its shading patch placed by `m` (the twin of the
/// instances pass).
pub fn instance_patch(
    m: &[f32; 12],
    mirror: bool,
    p: &BezierPatch,
    s: &ShadingPatch,
) -> (BezierPatch, ShadingPatch) {
    let mut out = BezierPatch {
        pts: p.pts.map(|q| transform_point(m, q)),
    };
    let mut sh = ShadingPatch {
        du: s.du.map(|d| transform_vector(m, d)),
        dv: s.dv.map(|d| transform_vector(m, d)),
    };
    if mirror {
        out = out.reoriented(true, false, false);
        sh = sh.transposed();
    }
    (out, sh)
}

/// The frames per second of `scene`'s animation.
fn scene_fps(scene: &Scene) -> f64 {
    scene
        .animation
        .fps
        .filter(|f| f.is_finite() && *f > 0.0)
        .unwrap_or(DEFAULT_FPS)
}

/// The cage vertices of `frames` at frame position `f` (linear between
/// frames in f32, held at the last); empty without frames.
fn sequence_at(frames: &[Vec<Vec3>], f: f64) -> Vec<Vec3> {
    if frames.is_empty() {
        return Vec::new();
    }
    let last = frames.len() - 1;
    let i = (f.floor().max(0.0) as usize).min(last);
    let a = (f - i as f64).clamp(0.0, 1.0) as f32;
    if i == last || a == 0.0 {
        return frames[i].clone();
    }
    frames[i]
        .iter()
        .zip(&frames[i + 1])
        .map(|(p, q)| *p + (*q - *p) * a + Vec3::ZERO)
        .collect()
}

/// A scene loaded with what of it moves.
#[derive(Clone, Debug)]
pub struct AnimatedScene {
    /// The geometry at rest (static instances baked as always).
    pub geometry: SceneGeometry,
    /// Its shading patches.
    pub shading: SceneShading,
    /// What moves; `None` for a static scene.
    pub animation: Option<Animation>,
}

impl AnimatedScene {
    /// The geometry and shading at time `t` (the rest scene where nothing
    /// moves): the oracle's scene.
    pub fn at(&self, t: f64) -> (SceneGeometry, SceneShading) {
        let (mut geo, mut shading) = (self.geometry.clone(), self.shading.clone());
        if let Some(a) = &self.animation {
            a.pose(&a.frame(t), &mut geo, &mut shading);
        }
        (geo, shading)
    }
}

impl Scene {
    /// Loads the models, bakes the instances and finds what moves.
    pub fn load_animated(&self) -> Result<AnimatedScene, SceneError> {
        let (geometry, shading, cache) = self.build_with_models(true)?;
        let cage_of = |index: usize| -> Option<Arc<CageModel>> {
            let m = &self.models[index];
            let model = &cache[&(m.file.clone(), m.options, m.surface)];
            match &model.stencils {
                Some(s) => Some(s.clone()),
                None if model.cage.is_none() => {
                    Some(Arc::new(CageModel::for_patches(&model.patches)))
                }
                None => None,
            }
        };
        let animation = Animation::new(self, &geometry, &cage_of)?;
        Ok(AnimatedScene {
            geometry,
            shading,
            animation,
        })
    }
}
