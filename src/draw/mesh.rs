//! Draw path A: task + mesh shaders (`glsl/draw.task`, `glsl/draw.mesh`,
//! `glsl/draw_mesh.frag`).
//!
//! One task workgroup per `MESH_NODES * TASK_MESH_GROUPS` = 1024 ready nodes
//! (the subdivision pass writes that count to `counters[C_MESH_ARGS]`), each
//! launching up to `TASK_MESH_GROUPS` mesh workgroups of `MESH_NODES` = 32
//! lanes, one node per lane, at most 192 vertices and 128 primitives out. 32
//! nodes per mesh workgroup is the paper's choice and fits every device's
//! 256-vertex minimum; the task stage does no per-node work, so it is a
//! single invocation.

use ash::vk;

use super::{bind, graphics_pipeline};
use crate::constants::C_MESH_ARGS;
use crate::gpu::{FrameGpu, PushConstants, SceneLayout};
use crate::vk::{Context, Pipeline, ShaderModule, VkError, VkResult};

/// Bytes of one `VkDrawMeshTasksIndirectCommandEXT` (x, y, z).
const MESH_ARGS_STRIDE: u32 = 12;

/// The task/mesh/fragment pipeline.
pub(super) struct MeshDraw {
    pipeline: Pipeline,
}

impl MeshDraw {
    /// Creates the pipeline (the device must have mesh shaders).
    pub(super) fn new(ctx: &Context, layout: &SceneLayout) -> VkResult<Self> {
        let task = ShaderModule::load(ctx, "draw.task")?;
        let mesh = ShaderModule::load(ctx, "draw.mesh")?;
        let frag = ShaderModule::load(ctx, "draw_mesh.frag")?;
        let pipeline = graphics_pipeline(
            ctx,
            layout,
            &[
                (vk::ShaderStageFlags::TASK_EXT, &task),
                (vk::ShaderStageFlags::MESH_EXT, &mesh),
                (vk::ShaderStageFlags::FRAGMENT, &frag),
            ],
            false,
            "draw (task + mesh)",
        )?;
        Ok(Self { pipeline })
    }

    /// Records the indirect mesh draw (inside rendering).
    pub(super) fn record_draw(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        pc: &PushConstants,
    ) -> VkResult<()> {
        let loader = ctx.mesh_shader().ok_or_else(|| {
            VkError::Usage(String::from(
                "the mesh draw path was recorded on a context without mesh shaders",
            ))
        })?;
        bind(
            ctx,
            cmd,
            &self.pipeline,
            vk::PipelineBindPoint::GRAPHICS,
            layout,
            frame,
            pc,
        )?;
        unsafe {
            loader.cmd_draw_mesh_tasks_indirect(
                cmd,
                frame.counters.handle(),
                u64::from(C_MESH_ARGS) * 4,
                1,
                MESH_ARGS_STRIDE,
            )
        };
        Ok(())
    }
}
