//! The renderer's levels of detail (src/lod): what it is given, and the
//! choice per frame before the method records (the draw itself is one more
//! part of `Renderer::record`).

use ash::vk;

use super::Renderer;
use crate::lod::gpu::Lod;
use crate::lod::SceneLevels;
use crate::methods::{self, RenderError, Role};
use crate::patch::view::ViewParams;

impl Renderer {
    /// Draws far instances from levels of detail of their models (`levels`
    /// made for the uploaded scene by [`SceneLevels::build`]), or, with
    /// `None`, every instance from its patches again. Levels are never used
    /// by the reference (`ground-truth`), whose image the others' error is
    /// measured against, nor in an animated scene (its records change per
    /// frame).
    pub fn set_levels(&mut self, levels: Option<SceneLevels>) -> Result<(), RenderError> {
        self.frames.wait_all()?;
        self.forget_frames();
        if self.lod.take().is_some() {
            // Records flagged for the levels go back to their patches.
            let records = self.scene.instance_records.clone();
            self.scene.instances.write(&self.ctx, 0, &records)?;
        }
        if let Some(levels) = levels {
            self.lod = Some(Lod::new(
                &self.ctx,
                &self.scene,
                &self.scene_layout,
                levels,
            )?);
        }
        Ok(())
    }

    /// Draws every instance that has levels from level `level` (its
    /// model's coarsest where it has fewer) whatever its distance, or with
    /// `None` as its distance says: for the hole test of a level. No-op
    /// without levels.
    pub fn force_level(&mut self, level: Option<usize>) {
        if let Some(lod) = &mut self.lod {
            lod.set_force(level);
        }
    }

    /// Turns the levels given ([`Renderer::set_levels`]) on or off
    /// without making them again (the window's switch). No-op without
    /// levels.
    pub fn enable_levels(&mut self, on: bool) {
        if let Some(lod) = &mut self.lod {
            lod.set_enabled(on);
        }
    }

    /// The levels of detail in use.
    pub fn levels(&self) -> Option<&SceneLevels> {
        self.lod.as_ref().map(Lod::levels)
    }

    /// Chooses what draws each instance this frame and flags the records
    /// (before anything reads them); returns whether levels draw anything,
    /// after the method, which then leaves its target to be loaded.
    pub(super) fn prepare_levels(
        &mut self,
        cmd: vk::CommandBuffer,
        params: &ViewParams,
    ) -> Result<bool, RenderError> {
        let Some(lod) = &mut self.lod else {
            return Ok(false);
        };
        let reference = methods::find(self.methods[self.active].name())?.role == Role::Reference;
        let enabled = !reference && self.anim.is_none();
        lod.prepare(&self.ctx, cmd, &self.scene, params, enabled);
        self.target.set_more_parts(lod.draws_any());
        Ok(lod.draws_any())
    }
}
