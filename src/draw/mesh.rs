//! Draw path A: task + mesh shaders (`glsl/draw.task`, `glsl/draw.mesh`,
//! `glsl/draw_mesh.frag`).
//!
//! One task workgroup per `MESH_NODES * TASK_MESH_GROUPS` = 1024 ready nodes
//! (the producer writes that count to `counters[C_MESH_ARGS]`), each
//! launching up to `TASK_MESH_GROUPS` mesh workgroups of `MESH_NODES` = 32
//! lanes, one node per lane, at most 192 vertices and 128 primitives out. 32
//! nodes per mesh workgroup is the paper's choice and fits every device's
//! 256-vertex minimum; the task stage does no per-node work, so it is a
//! single invocation.

use ash::vk;

use super::ReadyStage;
use crate::constants::C_MESH_ARGS;
use crate::frame::FrameRec;
use crate::gpu::{DrawPush, Shaders};
use crate::vk::{Context, Pipeline, PipelineLayout, VkError, VkResult};

/// Bytes of one `VkDrawMeshTasksIndirectCommandEXT` (x, y, z).
const MESH_ARGS_STRIDE: u32 = 12;

/// The task/mesh/fragment pipeline.
pub(super) struct MeshDraw {
    pipeline: Pipeline,
}

impl MeshDraw {
    /// Creates the pipeline (the device must have mesh shaders).
    pub(super) fn new(
        ctx: &Context,
        shaders: &mut Shaders,
        layout: &PipelineLayout<impl bytemuck::Pod>,
    ) -> VkResult<Self> {
        let pipeline = shaders.draw_pipeline(
            ctx,
            layout,
            "draw (task + mesh)",
            &[
                (vk::ShaderStageFlags::TASK_EXT, "draw.task"),
                (vk::ShaderStageFlags::MESH_EXT, "draw.mesh"),
                (vk::ShaderStageFlags::FRAGMENT, "draw_mesh.frag"),
            ],
        )?;
        Ok(Self { pipeline })
    }

    /// Records the indirect mesh draw (inside rendering).
    pub(super) fn record_draw(
        &self,
        f: &FrameRec<'_>,
        stage: &ReadyStage,
        pc: &DrawPush,
    ) -> VkResult<()> {
        let loader = f.ctx.mesh_shader().ok_or_else(|| {
            VkError::Usage(String::from(
                "the mesh draw path was recorded on a context without mesh shaders",
            ))
        })?;
        self.pipeline.bind(f.cmd);
        stage.bind_draw(f, vk::PipelineBindPoint::GRAPHICS, pc)?;
        unsafe {
            loader.cmd_draw_mesh_tasks_indirect(
                f.cmd,
                stage.list().counters.handle(),
                u64::from(C_MESH_ARGS) * 4,
                1,
                MESH_ARGS_STRIDE,
            )
        };
        Ok(())
    }
}
