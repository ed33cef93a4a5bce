//! Draw path B, for devices without mesh shaders: `glsl/expand.comp` writes
//! `VERTICES_PER_NODE` = 18 vertices per ready node (6 triangle slots, a
//! missing wedge as a degenerate triangle) into the list's vertex buffer,
//! then one non-indexed `vkCmdDrawIndirect` pulls them by `gl_VertexIndex`
//! in `glsl/draw.vert` (no vertex input state) and shades with
//! `glsl/draw_vert.frag`.
//!
//! Fixed slots cost up to a third more vertices than a compacted buffer
//! would, but need no prefix sum and keep the output order equal to the
//! ready-list order, which the oracle comparison relies on.

use ash::vk;

use super::ReadyStage;
use crate::constants::{C_DRAW_ARGS, C_EXPAND_ARGS};
use crate::frame::FrameRec;
use crate::gpu::{DrawPush, Shaders};
use crate::vk::{buffer_barrier, Access, Context, Pipeline, PipelineLayout, VkResult};

/// Bytes of one `VkDrawIndirectCommand`.
const DRAW_ARGS_STRIDE: u32 = 16;

/// The expansion compute pipeline and the vertex-pulling graphics pipeline.
pub(super) struct FallbackDraw {
    expand: Pipeline,
    draw: Pipeline,
}

impl FallbackDraw {
    /// Creates both pipelines with the ready-list draw layout.
    pub(super) fn new(
        ctx: &Context,
        shaders: &mut Shaders,
        layout: &PipelineLayout,
    ) -> VkResult<Self> {
        let expand = shaders.compute(ctx, layout, "expand", "expand.comp")?;
        let draw = shaders.draw_pipeline(
            ctx,
            layout,
            "draw (fallback)",
            &[
                (vk::ShaderStageFlags::VERTEX, "draw.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "draw_vert.frag"),
            ],
        )?;
        Ok(Self { expand, draw })
    }

    /// Records the indirect expansion dispatch (outside rendering) and the
    /// barrier from its vertex writes to the vertex shader's reads.
    pub(super) fn record_expand(
        &self,
        f: &FrameRec<'_>,
        stage: &ReadyStage,
        pc: &DrawPush,
    ) -> VkResult<()> {
        self.expand.bind(f.cmd);
        stage.bind_draw(f, vk::PipelineBindPoint::COMPUTE, pc)?;
        let list = stage.list();
        unsafe {
            f.ctx.device().cmd_dispatch_indirect(
                f.cmd,
                list.counters.handle(),
                u64::from(C_EXPAND_ARGS) * 4,
            )
        };
        buffer_barrier(
            f.ctx,
            f.cmd,
            &list.vertices,
            Access::COMPUTE_WRITE,
            Access::new(
                vk::PipelineStageFlags2::VERTEX_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_READ,
            ),
        );
        Ok(())
    }

    /// Records the indirect draw (inside rendering).
    pub(super) fn record_draw(
        &self,
        f: &FrameRec<'_>,
        stage: &ReadyStage,
        pc: &DrawPush,
    ) -> VkResult<()> {
        self.draw.bind(f.cmd);
        stage.bind_draw(f, vk::PipelineBindPoint::GRAPHICS, pc)?;
        unsafe {
            f.ctx.device().cmd_draw_indirect(
                f.cmd,
                stage.list().counters.handle(),
                u64::from(C_DRAW_ARGS) * 4,
                1,
                DRAW_ARGS_STRIDE,
            )
        };
        Ok(())
    }
}
