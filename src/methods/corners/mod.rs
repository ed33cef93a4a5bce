//! Method `corners`: the worked example of docs/ARCHITECTURE.md ("Adding a
//! method"). Every base patch is drawn as the two triangles of its four
//! corner control points (`glsl/corners/corners.vert`), in one draw with no pass
//! before it: the smallest self-drawing method, kept building and tested
//! (`tests/corners.rs`) so the example cannot drift from the trait.

use ash::vk;

use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, Reads, RenderError, Role};
use crate::frame::{FrameOut, FrameRec};
use crate::gpu::DrawPush;
use crate::vk::{Pipeline, PipelineLayout};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "corners",
    about: "every patch as the two triangles of its corners (the worked example of a method)",
    rational: false,
    pn: false,
    // Two triangles per patch whatever the view: no setting changes them.
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
    },
    role: Role::Example,
    targets: &[],
    heat_map: "nothing (depth 0 everywhere)",
    seams: "wedges (none for this method)",
    checks: None,
    blocks: &[],
    build: |setup| Ok(Box::new(Corners::new(setup)?)),
};

/// The pipeline; the method holds no buffer of its own.
pub struct Corners {
    layout: PipelineLayout<DrawPush>,
    pipeline: Pipeline,
}

impl Corners {
    /// Builds the draw pipeline: set 0 (the scene) and the shared
    /// [`DrawPush`], the corner vertex shader and the shared fragment shader.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        let scene = setup.scene_layout;
        let layout =
            scene.pipeline_layout::<DrawPush>(ctx, "corners layout", &[], scene.stages())?;
        let pipeline = setup.shaders.draw_pipeline(
            ctx,
            &layout,
            "draw (corners)",
            &[
                (vk::ShaderStageFlags::VERTEX, "corners/corners.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "draw_vert.frag"),
            ],
        )?;
        Ok(Self { layout, pipeline })
    }
}

impl Method for Corners {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn draw_path(&self) -> &'static str {
        "corners"
    }

    /// One draw of six vertices per base patch. It reads only set 0, which
    /// the renderer has made visible to every stage before any method
    /// records, so there is no pass to declare.
    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        let pc = f.view.draw_push(0, false, 0);
        let vertices = 6 * f.scene.count;
        f.scoped("draw", |f| {
            let (ctx, cmd) = (f.ctx, f.cmd);
            f.target.begin(ctx, cmd);
            self.pipeline.bind(cmd);
            f.bind_scene(vk::PipelineBindPoint::GRAPHICS, &self.layout);
            self.layout.push(cmd, &pc);
            unsafe { ctx.device().cmd_draw(cmd, vertices, 1, 0, 0) };
            f.target.end(ctx, cmd);
            Ok(())
        })?;
        Ok(())
    }

    /// Nothing to read back: the renderer's primitive query counts the
    /// triangles, and nothing is culled.
    fn finish(&mut self, _out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        Ok(Finished::Done(MethodStats::default()))
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        Vec::new()
    }
}
