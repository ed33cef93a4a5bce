//! Method `corners`: the worked example of docs/ARCHITECTURE.md ("Adding a
//! method"). Every base patch is drawn as the two triangles of its four
//! corner control points: a compute pass (`glsl/corners/cull.comp`) drops
//! the patches whose corners lie outside the view frustum and appends the
//! others to a visible list, counting them into the arguments of one
//! indirect draw (`glsl/corners/corners.vert`). Everything it adds is in
//! this folder (constants, push block, buffers) and in `glsl/corners/`,
//! plus its line in the registry; it is kept building and tested
//! (`tests/corners.rs`) so the example cannot drift from the trait.

pub mod constants;
pub mod push;

use ash::vk;
use serde_json::json;

use self::constants::*;
use self::push::CornersCullPush;
use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, Reads, RenderError, Role};
use crate::constants::SET_PASS;
use crate::frame::{CopyRange, FrameOut, FrameRec};
use crate::gpu::blocks::block;
use crate::gpu::DrawPush;
use crate::vk::{
    Access, Buffer, DescriptorSet, MemoryLocation, Pass, Pipeline, PipelineLayout, Recorder, Res,
    SetLayout, VkError, VkResult,
};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "corners",
    about: "every patch as the two triangles of its corners (the worked example of a method)",
    rational: false,
    pn: false,
    // Two triangles per visible patch whatever the view: no setting
    // changes them.
    reads: Reads {
        draw_path: false,
        eps: false,
        lambda: false,
        l_max: false,
        split: false,
        wedges: false,
        backface: false,
        occlusion: false,
        grid: false,
        displacement: false,
    },
    role: Role::Example,
    targets: &[],
    heat_map: "nothing (depth 0 everywhere)",
    seams: "wedges (none for this method)",
    checks: None,
    blocks: &[block::<CornersCullPush>],
    build: |setup| Ok(Box::new(Corners::new(setup)?)),
};

/// The shaders that share set 1 (its layout is reflected from them).
const SHADERS: &[&str] = &["corners/cull.comp", "corners/corners.vert"];

/// The visible list, sized by the scene, and set 1 pointing at it.
struct Visible {
    list: Buffer,
    capacity: u32,
    set: DescriptorSet,
}

/// The pipelines and buffers of `corners`.
pub struct Corners {
    set_layout: SetLayout,
    cull_layout: PipelineLayout<CornersCullPush>,
    draw_layout: PipelineLayout<DrawPush>,
    cull: Pipeline,
    draw: Pipeline,
    /// The draw's VkDrawIndirectCommand.
    draw_args: Buffer,
    visible: Option<Visible>,
    /// Where the last frame's draw arguments were copied out, and its
    /// base patches.
    copied: Option<(CopyRange, u32)>,
}

impl Corners {
    /// Builds the cull (set 0, set 1 and [`CornersCullPush`]) and the draw
    /// (set 0, set 1 and the shared [`DrawPush`]: the corner vertex shader
    /// and the shared fragment shader).
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        let scene = setup.scene_layout;
        let set_layout = SetLayout::reflect(ctx, "corners set", SET_PASS, SHADERS)?;
        let sets = [&set_layout];
        let compute = vk::ShaderStageFlags::COMPUTE;
        let cull_layout = scene.pipeline_layout(ctx, "corners cull layout", &sets, compute)?;
        let draw_layout = scene.pipeline_layout(ctx, "corners layout", &sets, scene.stages())?;
        let shaders = &mut setup.shaders;
        let cull = shaders.compute(ctx, &cull_layout, "corners cull", "corners/cull.comp")?;
        let draw = shaders.draw_pipeline(
            ctx,
            &draw_layout,
            "draw (corners)",
            &[
                (vk::ShaderStageFlags::VERTEX, "corners/corners.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "draw_vert.frag"),
            ],
        )?;
        let draw_args = Buffer::new(
            ctx,
            "corners draw arguments",
            u64::from(CORNERS_DRAW_WORDS) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        Ok(Self {
            set_layout,
            cull_layout,
            draw_layout,
            cull,
            draw,
            draw_args,
            visible: None,
            copied: None,
        })
    }

    /// The visible list for the frame's patches, made (or remade larger)
    /// on demand; a replaced one is retired.
    fn ensure_visible(&mut self, f: &mut FrameRec<'_>) -> VkResult<()> {
        let need = f.scene.count.max(1);
        if self.visible.as_ref().is_some_and(|v| v.capacity >= need) {
            return Ok(());
        }
        let list = Buffer::new(
            f.ctx,
            "corners visible patches",
            u64::from(need) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let mut bound = [(&list).into(); CORNERS_BINDINGS as usize];
        bound[BIND_CORNERS_DRAW as usize] = (&self.draw_args).into();
        let set = DescriptorSet::new(f.ctx, "corners set", &self.set_layout, &bound)?;
        let new = Visible {
            list,
            capacity: need,
            set,
        };
        if let Some(old) = self.visible.replace(new) {
            f.retired.push(old);
        }
        Ok(())
    }

    /// Records the draw arguments' reset and the cull. The cull is one
    /// [`Pass`] naming its pipeline and the sets it binds: the recorder
    /// binds them and, from the pipeline's reflection, declares the list
    /// and the arguments as written, so the barriers follow by themselves.
    fn record_cull(&self, f: &mut FrameRec<'_>, visible: &Visible) -> VkResult<()> {
        let (ctx, cmd) = (f.ctx, f.cmd);
        let args = Res::Buffer(&self.draw_args);
        let mut rec = Recorder::new(ctx, cmd);
        // The last frame's draw and copy-out read both buffers.
        rec.after(args, Access::ALL);
        rec.after(Res::Buffer(&visible.list), Access::ALL);
        let reset = Pass::new("draw arguments").write(args, Access::TRANSFER_WRITE);
        let words = [6u32, 0, 0, 0];
        rec.run(&reset, |cmd| unsafe {
            let bytes = bytemuck::cast_slice(&words);
            ctx.device()
                .cmd_update_buffer(cmd, self.draw_args.handle(), 0, bytes)
        });
        let pc = CornersCullPush {
            patch_count: f.scene.count,
            pad: [0; 3],
        };
        self.cull_layout.push(cmd, &pc);
        let cull = Pass::new("cull")
            .pipeline(&self.cull)
            .bind(SET_PASS, &visible.set);
        let cull = f.with_scene(cull);
        let groups = f.scene.count.div_ceil(CORNERS_CULL_GROUP);
        f.scoped("cull", |_| {
            rec.dispatch(&cull, [groups, 1, 1]);
            Ok(())
        })?;
        // The draw reads the arguments and, in its vertex shader, the list.
        let draw = Access::new(
            vk::PipelineStageFlags2::DRAW_INDIRECT | vk::PipelineStageFlags2::VERTEX_SHADER,
            vk::AccessFlags2::INDIRECT_COMMAND_READ | vk::AccessFlags2::SHADER_STORAGE_READ,
        );
        rec.hand_off_set(&visible.set, draw);
        Ok(())
    }

    /// Records the indirect draw: six vertices per visible patch.
    fn record_draw(&self, f: &mut FrameRec<'_>, visible: &Visible) -> VkResult<()> {
        let pc = f.view.draw_push(0, false, 0);
        f.scoped("draw", |f| {
            let (ctx, cmd) = (f.ctx, f.cmd);
            let bind = vk::PipelineBindPoint::GRAPHICS;
            f.target.begin(ctx, cmd);
            self.draw.bind(cmd);
            f.bind_scene(bind, &self.draw_layout);
            visible
                .set
                .bind(ctx, cmd, bind, &self.draw_layout, SET_PASS, &[]);
            self.draw_layout.push(cmd, &pc);
            let stride = CORNERS_DRAW_WORDS * 4;
            unsafe {
                ctx.device()
                    .cmd_draw_indirect(cmd, self.draw_args.handle(), 0, 1, stride)
            };
            f.target.end(ctx, cmd);
            Ok(())
        })
    }
}

impl Method for Corners {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn draw_path(&self) -> &'static str {
        "corners"
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.ensure_visible(f)?;
        let visible = self
            .visible
            .as_ref()
            .ok_or_else(|| VkError::Usage("no visible list".into()))?;
        self.record_cull(f, visible)?;
        self.record_draw(f, visible)?;
        let range = f.copy_out(&self.draw_args, CORNERS_DRAW_WORDS)?;
        self.copied = Some((range, f.scene.count));
        Ok(())
    }

    /// The visible patches, from the draw arguments the frame copied out.
    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let (range, patches) = self
            .copied
            .ok_or_else(|| RenderError::Request("finish() before any frame was recorded".into()))?;
        let visible = u64::from(out.words(range)[CORNERS_INSTANCES as usize]);
        Ok(Finished::Done(MethodStats {
            triangles: 2 * visible,
            placeholder_triangles: 0,
            culled_patches: u64::from(patches) - visible,
            own: vec![("visible_patches", json!(visible))],
        }))
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![("draw_arguments", self.draw_args.size())];
        if let Some(vis) = &self.visible {
            v.push(("visible_list", vis.list.size()));
        }
        v
    }
}
