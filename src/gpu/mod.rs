//! GPU resources above the Vulkan core that every method shares: the scene
//! (patches, flags, per-slot views: descriptor set 0), the offscreen draw
//! target, the host twins of the shaders' constant blocks, and the cache of
//! loaded shader modules.

pub mod blocks;
pub mod scene;
pub mod target;

use std::collections::HashMap;
use std::sync::Arc;

use crate::vk::{Context, ShaderModule, VkResult};

pub use blocks::{DrawPush, GpuBlock, GridPush, ListPush, SubdivPush};
pub use scene::{all_stages, SceneGpu, SceneLayout};
pub use target::{write_png, DrawTarget, ImageError, COLOR_FORMAT, DEPTH_FORMAT};

/// Shader modules by name, loaded once per renderer: switching methods
/// or rebuilding one reuses them.
#[derive(Default)]
pub struct Shaders {
    modules: HashMap<String, Arc<ShaderModule>>,
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

    /// How many modules are loaded.
    pub fn loaded(&self) -> usize {
        self.modules.len()
    }
}
