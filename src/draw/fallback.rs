//! Draw path B, for devices without mesh shaders: `glsl/expand.comp` writes
//! `VERTICES_PER_NODE` = 18 vertices per ready node (6 triangle slots, a
//! missing wedge as a degenerate triangle) into the list's vertex buffer,
//! then one non-indexed `vkCmdDrawIndirect` pulls them by `gl_VertexIndex`
//! in `glsl/draw.vert` (no vertex input state) and shades with
//! `glsl/draw_vert.frag`.
//!
//! The list is drawn in chunks of `FALLBACK_CHUNK_NODES` (an expansion, then
//! its draw, per chunk): the vertex buffer holds one chunk, 94 MB, so any
//! list the device can bind is drawn, where one buffer for the whole list
//! (360 bytes a node) would pass the 128 MiB a binding may hold at 372,827
//! nodes. The producer writes every chunk's arguments (`write_ready_args`);
//! the chunks past the list's end dispatch and draw nothing.
//!
//! Fixed slots cost up to a third more vertices than a compacted buffer
//! would, but need no prefix sum and keep the output order equal to the
//! ready-list order, which the oracle comparison relies on.

use ash::vk;

use super::ReadyStage;
use crate::constants::{CHUNK_ARG_WORDS, C_CHUNK_ARGS};
use crate::frame::FrameRec;
use crate::gpu::{DrawPush, Shaders};
use crate::vk::{Access, Context, Pass, Pipeline, PipelineLayout, Recorder, Res, VkResult};

/// Bytes of one `VkDrawIndirectCommand`.
const DRAW_ARGS_STRIDE: u32 = 16;

/// The vertex shader's reads of the expanded vertices.
pub(super) const VERTEX_READ: Access = Access::new(
    vk::PipelineStageFlags2::VERTEX_SHADER,
    vk::AccessFlags2::SHADER_STORAGE_READ,
);

/// Byte offset in the counters of chunk `pc.chunk`'s expansion arguments
/// (its draw arguments follow 16 bytes later).
fn chunk_args(pc: &DrawPush) -> u64 {
    u64::from(C_CHUNK_ARGS + CHUNK_ARG_WORDS * pc.chunk) * 4
}

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
        layout: &PipelineLayout<impl bytemuck::Pod>,
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

    /// Records the indirect expansion dispatch of chunk `pc.chunk` (outside
    /// rendering) as a pass writing the vertices: `rec` makes it wait for
    /// the previous chunk's draw to have read them.
    pub(super) fn record_expand(
        &self,
        f: &FrameRec<'_>,
        rec: &mut Recorder<'_>,
        stage: &ReadyStage,
        pc: &DrawPush,
    ) -> VkResult<()> {
        self.expand.bind(f.cmd);
        stage.bind_draw(f, vk::PipelineBindPoint::COMPUTE, pc)?;
        let list = stage.list();
        let pass = Pass::new("expand").write(Res::Buffer(&list.vertices), Access::COMPUTE_WRITE);
        rec.dispatch_indirect(&pass, &list.counters, chunk_args(pc));
        Ok(())
    }

    /// Records the indirect draw of chunk `pc.chunk` (inside rendering).
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
                chunk_args(pc) + 16,
                1,
                DRAW_ARGS_STRIDE,
            )
        };
        Ok(())
    }
}
