//! Animated scenes: deforming cages (procedural deformers, OBJ sequences)
//! and moving instances, converted again every frame by the stencil tables
//! (`cage/stencil.rs`) on the GPU (`gpu/anim.rs`, the update pass) and, for
//! the oracle, on the CPU here, in the same f32 operations.
//!
//! The GPU holds each model's patches once, in model space, and an instance
//! record per instance that places them (`scene/instances.rs`). A model
//! whose cage moves has a copy of its own (`Scene::build_with_models`), and
//! the animation rewrites it and its shading patches in place, in model
//! space; a moving instance gets a new record every frame. Every method
//! then reads the frame through set 0 as always.
//!
//! One frame, at time t:
//! 1. the inputs: per deforming model its cage vertices (the rest pose, or
//!    the sequence's frames interpolated) and its deformers' numbers at t;
//!    per keyed instance its record at t (`Instance::new` of its transform,
//!    rounded to f32 once) ([`Frame`], computed on the CPU once and handed
//!    to both sides);
//! 2. *deform*: each vertex through its model's deformers in order
//!    ([`deform::apply`]);
//! 3. *points*: every point row of the model's table;
//! 4. *vectors*: every shading row;
//! 5. *write*: every patch of every deforming model, its 16 points and 24
//!    vectors, over its model patches and shading patches; every keyed
//!    instance's record over its record.

pub mod deform;
pub mod sequence;

use std::sync::Arc;

use glam::{DMat4, DVec3, Vec3};

use crate::cage::stencil::CageModel;
use crate::patch::bezier::BezierPatch;
use crate::patch::shading::ShadingPatch;
use crate::scene::desc::Scene;
use crate::scene::geometry::{SceneGeometry, SceneShading};
use crate::scene::instances::Instance;
use crate::scene::keys;
use crate::scene::SceneError;
use deform::GpuDeformer;

/// Frames per second unless the scene says.
pub const DEFAULT_FPS: f64 = 24.0;
/// Seconds of an animation whose curves give no end (steady waves).
pub const DEFAULT_DURATION: f64 = 4.0;

/// One model whose cage moves.
#[derive(Clone, Debug)]
pub struct AnimModel {
    /// Its index among the scene's models.
    pub scene_model: usize,
    /// Its first patch among the model patches (its own copy).
    pub source: u32,
    /// Its stencils and rest pose.
    pub cage: Arc<CageModel>,
    /// Its deformers, in order.
    pub deform: Vec<keys::Deformer>,
    /// The cage vertices of each frame of its OBJ sequence (empty: none).
    pub sequence: Vec<Vec<Vec3>>,
}

/// One instance whose transform follows keys.
#[derive(Clone, Debug)]
pub struct KeyedInstance {
    /// Its index among the scene's instances.
    pub index: usize,
    /// Its record as loaded (first patch, source, count, flags).
    pub base: Instance,
    /// Its keys.
    pub keys: keys::InstanceKeys,
    /// The model-space box of its patches' control points, each frame's
    /// record gets it placed (`Instance::placed_box`); `None` where the
    /// model's cage moves too or the model is displaced, so the record
    /// holds everything.
    pub model_box: Option<(DVec3, DVec3)>,
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
    /// The models whose cage moves.
    pub models: Vec<AnimModel>,
    /// The instances that move.
    pub keyed: Vec<KeyedInstance>,
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
    /// Per keyed instance, its record at this time.
    pub records: Vec<Instance>,
}

impl Animation {
    /// What of `scene` moves, with the cages of its models as `cage_of`
    /// gives them (see `Scene::load_animated`); `None` where nothing does.
    pub fn new(
        scene: &Scene,
        geo: &SceneGeometry,
        cage_of: &dyn Fn(usize) -> Option<Arc<CageModel>>,
    ) -> Result<Option<Self>, SceneError> {
        if !scene.models.iter().any(|m| m.anim.moves()) {
            return Ok(None);
        }
        let table = &geo.instances.instances;
        let mut models = Vec::new();
        let mut keyed = Vec::new();
        let mut next_instance = 0usize;
        let mut end = 0.0f64;
        for (index, m) in scene.models.iter().enumerate() {
            let placed = geo.models[index].patches_per_instance > 0 && !m.instances.is_empty();
            let first_instance = next_instance;
            if placed {
                next_instance += m.instances.len();
            }
            if !m.anim.moves() || !placed {
                continue;
            }
            let model_error = |msg: String| SceneError::Model {
                scene: scene.path.clone(),
                model: m.name.clone(),
                msg,
            };
            if table.len() < next_instance {
                return Err(model_error(
                    "internal: its instances are not in the scene's instance table".into(),
                ));
            }
            for (k, keys) in m.anim.keys.iter().enumerate() {
                if let Some(keys) = keys {
                    end = end.max(keys.end());
                    let base = table[first_instance + k];
                    let model =
                        &geo.instances.patches[base.source as usize..][..base.count as usize];
                    keyed.push(KeyedInstance {
                        index: first_instance + k,
                        base,
                        keys: keys.clone(),
                        // A displaced model reaches beyond its control
                        // points: unbounded, as a deforming one.
                        model_box: (!m.anim.deforms()
                            && !model.is_empty()
                            && m.displacement.is_none())
                        .then(|| control_box(model)),
                    });
                }
            }
            if !m.anim.deforms() {
                continue;
            }
            let cage = cage_of(index).ok_or_else(|| {
                model_error(
                    "cannot be animated: its cage's faces could not be matched to the file's `f` lines"
                        .into(),
                )
            })?;
            let mut sequence = Vec::new();
            if m.anim.sequence.len() > 1 {
                sequence.push(cage.rest.clone());
                for frame in &m.anim.sequence[1..] {
                    sequence.push(sequence::read_frame(frame, &cage)?);
                }
            }
            // A sequence of N frames lasts N frames: the last one shows
            // for a frame's time before the loop returns to the first.
            end = end.max(sequence.len() as f64 / scene_fps(scene));
            for d in &m.anim.deform {
                end = end.max(d.end());
            }
            models.push(AnimModel {
                scene_model: index,
                source: table[first_instance].source,
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
        Ok(Some(Animation {
            duration,
            fps: scene_fps(scene),
            looping: a.looping.unwrap_or(true),
            models,
            keyed,
        }))
    }

    /// Gives every instance that moves (a deforming model's, a keyed one)
    /// the box that holds everything, in `geo` as loaded: the box made at
    /// load bounds the rest pose where it was placed, and culling the
    /// instance whole by it (the level kernels' roots, `levels::root_patches`
    /// for the oracle) would drop a frame's patches that moved out of it.
    /// The update pass writes no box: a deforming model's instances keep
    /// this one and are culled patch by patch only; a keyed instance's
    /// record is the CPU's (`frame`), with its model's box placed by the
    /// frame's transform where the model's cage does not move.
    pub fn unbound(&self, geo: &mut SceneGeometry) {
        let deforming: Vec<u32> = self.models.iter().map(|m| m.source).collect();
        let table = &mut geo.instances.instances;
        for k in &self.keyed {
            table[k.index] = table[k.index].unbounded();
        }
        for t in table.iter_mut() {
            if deforming.contains(&t.source) {
                *t = t.unbounded();
            }
        }
    }

    /// Model patches the update pass rewrites per frame.
    pub fn patches(&self) -> usize {
        self.models.iter().map(|m| m.cage.stencils.patches()).sum()
    }

    /// Cage vertices the update pass deforms per frame.
    pub fn vertices(&self) -> usize {
        self.models.iter().map(|m| m.cage.rest.len()).sum()
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
            .map(|m| sequence_at(&m.sequence, time * self.fps, self.looping))
            .collect();
        let deformers = self
            .models
            .iter()
            .map(|m| m.deform.iter().map(|d| d.at(time)).collect())
            .collect();
        let records = self
            .keyed
            .iter()
            .map(|k| {
                let b = &k.base;
                let m = k.keys.at(time);
                let record = Instance::new(&m, b.first, b.source, b.count, b.flags);
                match k.model_box {
                    Some((lo, hi)) => record.placed_box(&m, lo, hi),
                    // A deforming model's: see `unbound`.
                    None => record.unbounded(),
                }
            })
            .collect();
        Frame {
            time,
            inputs,
            deformers,
            records,
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
        let verts = deform::apply_all(&frame.deformers[m], input);
        model.cage.stencils.evaluate(&verts)
    }

    /// Writes frame `frame` over `geo` and `shading` (the scene as loaded):
    /// the moving models' patches and the keyed instances' records, and
    /// every world patch they place: the oracle's scene at that time.
    pub fn pose(&self, frame: &Frame, geo: &mut SceneGeometry, shading: &mut SceneShading) {
        let table = &mut geo.instances;
        let mut moved = vec![false; table.patches.len()];
        for (m, model) in self.models.iter().enumerate() {
            let (patches, vectors) = self.model_pose(frame, m);
            let first = model.source as usize;
            for (k, (p, s)) in patches.into_iter().zip(vectors).enumerate() {
                table.patches[first + k] = p;
                if let Some(slot) = shading.model.get_mut(first + k) {
                    *slot = s;
                }
                moved[first + k] = true;
            }
        }
        let mut keyed = vec![false; table.instances.len()];
        for (k, record) in self.keyed.iter().zip(&frame.records) {
            table.instances[k.index] = *record;
            keyed[k.index] = true;
        }
        for (i, t) in table.instances.iter().enumerate() {
            if !keyed[i] && !moved[t.source as usize] {
                continue;
            }
            let m = instance_matrix(t);
            for g in t.ids() {
                let source = t.source as usize + (g - t.first as usize);
                geo.patches[g] = t.patch(&table.patches[source]);
                if let (Some(out), Some(s)) =
                    (shading.patches.get_mut(g), shading.model.get(source))
                {
                    *out = s.transformed(&m);
                }
            }
        }
    }
}

/// The affine transform of an instance record, as f64.
fn instance_matrix(t: &Instance) -> DMat4 {
    let r = t.rows;
    DMat4::from_cols_array(&[
        f64::from(r[0][0]),
        f64::from(r[1][0]),
        f64::from(r[2][0]),
        0.0,
        f64::from(r[0][1]),
        f64::from(r[1][1]),
        f64::from(r[2][1]),
        0.0,
        f64::from(r[0][2]),
        f64::from(r[1][2]),
        f64::from(r[2][2]),
        0.0,
        f64::from(r[0][3]),
        f64::from(r[1][3]),
        f64::from(r[2][3]),
        1.0,
    ])
}

/// The frames per second of `scene`'s animation.
fn scene_fps(scene: &Scene) -> f64 {
    scene
        .animation
        .fps
        .filter(|f| f.is_finite() && *f > 0.0)
        .unwrap_or(DEFAULT_FPS)
}

/// The cage vertices of `frames` at frame position `f`: linear between
/// frames in f32; after the last, towards the first where the animation
/// loops, else held. Empty without frames.
fn sequence_at(frames: &[Vec<Vec3>], f: f64, looping: bool) -> Vec<Vec3> {
    if frames.is_empty() {
        return Vec::new();
    }
    let n = frames.len();
    let i = (f.floor().max(0.0) as usize).min(n - 1);
    let a = (f - i as f64).clamp(0.0, 1.0) as f32;
    let next = if i + 1 < n {
        i + 1
    } else if looping {
        0
    } else {
        i
    };
    if next == i || a == 0.0 {
        return frames[i].clone();
    }
    frames[i]
        .iter()
        .zip(&frames[next])
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
        let mut geometry = geometry;
        let animation = Animation::new(self, &geometry, &cage_of)?;
        if let Some(a) = &animation {
            a.unbound(&mut geometry);
        }
        Ok(AnimatedScene {
            geometry,
            shading,
            animation,
        })
    }
}

/// The box of `patches`' control points, in f64.
fn control_box(patches: &[BezierPatch]) -> (DVec3, DVec3) {
    let mut lo = DVec3::splat(f64::MAX);
    let mut hi = DVec3::splat(-f64::MAX);
    for q in patches.iter().flat_map(|p| p.pts) {
        lo = lo.min(q.as_dvec3());
        hi = hi.max(q.as_dvec3());
    }
    (lo, hi)
}
