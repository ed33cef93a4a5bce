//! GPU resources above the Vulkan core that every method shares: the scene
//! (patches, flags, per-slot views: descriptor set 0), the offscreen draw
//! target, the host twins of the shaders' constant blocks, and the cache of
//! loaded shader modules.

pub mod anim;
pub mod blocks;
pub mod scene;
pub mod target;

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use crate::vk::{Context, GraphicsDesc, Pipeline, PipelineLayout, ShaderModule, VkResult};

pub use crate::vk::all_stages;
pub use blocks::{AnimPush, DrawPush, GpuBlock, HizPush, ListPush};
pub use scene::{scene_set_types, SceneGpu, SceneLayout};
pub use target::{sample_count, write_png, DrawTarget, ImageError, COLOR_FORMAT, DEPTH_FORMAT};

/// What the uploaded scene holds that pipelines are specialized on (the
/// `SPEC_*` constants): a pipeline for a scene without rational patches
/// carries none of their code. Lavapipe compiles on the CPU, and the
/// rational paths were half of the subdivision kernels' compile time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneSpec {
    /// The scene has rational patches (`SPEC_SCENE_RATIONAL`).
    pub rational: bool,
    /// The scene has albedo maps or UVs from a cage (`SPEC_SCENE_MATERIALS`).
    pub materials: bool,
    /// Some model is displaced (`SPEC_SCENE_DISPLACED`).
    pub displaced: bool,
}

impl Default for SceneSpec {
    /// Every path kept: right for any scene.
    fn default() -> Self {
        Self {
            rational: true,
            materials: true,
            displaced: true,
        }
    }
}

impl SceneSpec {
    /// What `scene` needs.
    pub fn of(scene: &SceneGpu) -> Self {
        Self {
            rational: scene.rational_patches > 0,
            materials: scene.materials,
            displaced: scene.displaced,
        }
    }

    /// `own` (a pipeline's own `(constant_id, value)` pairs) followed by
    /// the scene's.
    pub fn constants(self, own: &[(u32, u32)]) -> Vec<(u32, u32)> {
        let mut all = own.to_vec();
        all.push((
            crate::constants::SPEC_SCENE_RATIONAL,
            u32::from(self.rational),
        ));
        all.push((
            crate::constants::SPEC_SCENE_MATERIALS,
            u32::from(self.materials),
        ));
        all.push((
            crate::constants::SPEC_SCENE_DISPLACED,
            u32::from(self.displaced),
        ));
        all
    }
}

/// Shader modules by name, loaded once per renderer: switching methods
/// or rebuilding one reuses them; the draw target's sample count, which
/// every draw pipeline made through [`Shaders::draw_pipeline`] matches;
/// and what the scene holds, which every pipeline made here (or with
/// [`Shaders::specialization`]) is specialized on.
pub struct Shaders {
    modules: HashMap<String, Arc<ShaderModule>>,
    /// Samples per pixel of the draw target.
    pub samples: vk::SampleCountFlags,
    /// What the scene holds (the renderer remakes its methods when a new
    /// scene needs other pipelines).
    pub scene: SceneSpec,
}

impl Default for Shaders {
    fn default() -> Self {
        Self {
            modules: HashMap::new(),
            samples: vk::SampleCountFlags::TYPE_1,
            scene: SceneSpec::default(),
        }
    }
}

impl Shaders {
    /// The module for shader `name` (e.g. `sort.comp`), loaded on first use.
    pub fn get(&mut self, ctx: &Context, name: &str) -> VkResult<Arc<ShaderModule>> {
        if let Some(m) = self.modules.get(name) {
            return Ok(Arc::clone(m));
        }
        let m = Arc::new(ShaderModule::load(ctx, name)?);
        self.modules.insert(name.to_owned(), Arc::clone(&m));
        Ok(m)
    }

    /// A compute pipeline from shader `file` with `layout`.
    pub fn compute(
        &mut self,
        ctx: &Context,
        layout: &PipelineLayout<impl bytemuck::Pod>,
        name: &str,
        file: &str,
    ) -> VkResult<Pipeline> {
        let module = self.get(ctx, file)?;
        Pipeline::compute(ctx, name, layout, &module, &self.specialization(&[]))
    }

    /// A pipeline's own specialization constants `own` with the scene's:
    /// for pipelines made without [`Shaders::compute`] or
    /// [`Shaders::draw_pipeline`].
    pub fn specialization(&self, own: &[(u32, u32)]) -> Vec<(u32, u32)> {
        self.scene.constants(own)
    }

    /// A graphics pipeline drawing into the [`DrawTarget`]'s formats and
    /// sample count from
    /// the shader files of `stages`, with the default state of
    /// [`GraphicsDesc::new`] (no culling: SHADE_KEY shows back faces and the
    /// teapot is open; counter-clockwise front faces; opaque depth).
    pub fn draw_pipeline(
        &mut self,
        ctx: &Context,
        layout: &PipelineLayout<impl bytemuck::Pod>,
        name: &str,
        stages: &[(vk::ShaderStageFlags, &str)],
    ) -> VkResult<Pipeline> {
        let modules = stages
            .iter()
            .map(|(stage, file)| Ok((*stage, self.get(ctx, file)?)))
            .collect::<VkResult<Vec<_>>>()?;
        let refs: Vec<_> = modules.iter().map(|(s, m)| (*s, m.as_ref())).collect();
        let desc = GraphicsDesc::new(name, &refs)
            .targets(&[COLOR_FORMAT], DEPTH_FORMAT)
            .samples(self.samples)
            .specialize(&self.specialization(&[]));
        Pipeline::graphics(ctx, layout, &desc)
    }

    /// How many modules are loaded.
    pub fn loaded(&self) -> usize {
        self.modules.len()
    }
}
