//! Draw path B, for devices without mesh shaders: `glsl/expand.comp` writes
//! `VERTICES_PER_NODE` = 12 vertices per ready node (4 triangle slots, a
//! missing wedge as a degenerate triangle) into the frame's vertex buffer,
//! then one non-indexed `vkCmdDrawIndirect` pulls them by `gl_VertexIndex`
//! in `glsl/draw.vert` (no vertex input state) and shades with
//! `glsl/draw_vert.frag`.
//!
//! Fixed slots cost up to a third more vertices than a compacted buffer
//! would, but need no prefix sum and keep the output order equal to the
//! ready-list order, which the oracle comparison relies on.

use ash::vk;

use super::{bind, graphics_pipeline};
use crate::constants::{C_DRAW_ARGS, C_EXPAND_ARGS};
use crate::gpu::{FrameGpu, PushConstants, SceneLayout};
use crate::vk::{Context, Pipeline, ShaderModule, VkResult};

/// Bytes of one `VkDrawIndirectCommand`.
const DRAW_ARGS_STRIDE: u32 = 16;

/// The expansion compute pipeline and the vertex-pulling graphics pipeline.
pub(super) struct FallbackDraw {
    expand: Pipeline,
    draw: Pipeline,
}

impl FallbackDraw {
    /// Creates both pipelines.
    pub(super) fn new(ctx: &Context, layout: &SceneLayout) -> VkResult<Self> {
        let expand_shader = ShaderModule::load(ctx, "expand.comp")?;
        let expand = Pipeline::compute(ctx, "expand", &layout.layout, &expand_shader, &[])?;
        let vert = ShaderModule::load(ctx, "draw.vert")?;
        let frag = ShaderModule::load(ctx, "draw_vert.frag")?;
        let draw = graphics_pipeline(
            ctx,
            layout,
            &[
                (vk::ShaderStageFlags::VERTEX, &vert),
                (vk::ShaderStageFlags::FRAGMENT, &frag),
            ],
            true,
            "draw (fallback)",
        )?;
        Ok(Self { expand, draw })
    }

    /// Records the indirect expansion dispatch (outside rendering).
    pub(super) fn record_expand(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        pc: &PushConstants,
    ) -> VkResult<()> {
        bind(
            ctx,
            cmd,
            &self.expand,
            vk::PipelineBindPoint::COMPUTE,
            layout,
            frame,
            pc,
        )?;
        unsafe {
            ctx.device().cmd_dispatch_indirect(
                cmd,
                frame.counters.handle(),
                u64::from(C_EXPAND_ARGS) * 4,
            )
        };
        Ok(())
    }

    /// Records the indirect draw (inside rendering).
    pub(super) fn record_draw(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        pc: &PushConstants,
    ) -> VkResult<()> {
        bind(
            ctx,
            cmd,
            &self.draw,
            vk::PipelineBindPoint::GRAPHICS,
            layout,
            frame,
            pc,
        )?;
        unsafe {
            ctx.device().cmd_draw_indirect(
                cmd,
                frame.counters.handle(),
                u64::from(C_DRAW_ARGS) * 4,
                1,
                DRAW_ARGS_STRIDE,
            )
        };
        Ok(())
    }

    /// Records a direct draw of the first `vertices` vertices of the frame's
    /// vertex buffer (inside rendering): for meshes made on the CPU, such as
    /// the hole test's dense reference.
    pub(super) fn record_vertices(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        pc: &PushConstants,
        vertices: u32,
    ) -> VkResult<()> {
        bind(
            ctx,
            cmd,
            &self.draw,
            vk::PipelineBindPoint::GRAPHICS,
            layout,
            frame,
            pc,
        )?;
        unsafe { ctx.device().cmd_draw(cmd, vertices, 1, 0, 0) };
        Ok(())
    }
}
