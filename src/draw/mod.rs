//! Drawing a ready list (paper §3.4): 2 triangles + up to 2 wedges per
//! ready QuadNode, every vertex the base patch evaluated by the one shared
//! precise function, so positions equal the oracle's bit for bit.
//!
//! [`ReadyStage`] is what every ready-list producer (`subdiv`,
//! `subdiv-indirect`) shares: the list and its counters ([`ready`]), the
//! sort that makes the draw order canonical for a producer whose order
//! depends on timing ([`sort`]; the level kernels write a canonical order
//! and skip it), and one of two draw
//! paths sharing the push block and the fragment shading
//! (`glsl/common/shade.glsl`):
//! - [`DrawPath::Mesh`]: task + mesh shaders ([`mesh`]), one indirect
//!   `vkCmdDrawMeshTasksIndirectEXT` from `counters[C_MESH_ARGS]`;
//! - [`DrawPath::Fallback`], for devices without VK_EXT_mesh_shader
//!   ([`fallback`]): a compute pass writes 18 vertices per node, then a
//!   `vkCmdDrawIndirect` pulls them in a pass-through vertex shader, both
//!   once per chunk of the list.
//!
//! Barrier contract: [`ReadyStage::record_draw`] starts with a global
//! barrier from compute-shader storage writes (the producer's ready list and
//! counters, indirect arguments included) to indirect-command reads and to
//! storage/uniform reads in the compute, task, mesh and vertex stages. A
//! producer that writes these buffers some other way (e.g. a transfer in the
//! same command buffer) must make the writes available itself.

pub mod fallback;
pub mod hiz;
pub mod mesh;
pub mod ready;
pub mod sort;

use std::fmt;
use std::str::FromStr;

use ash::vk;

use crate::constants::{
    COUNTERS_BUFFER_WORDS, C_ERROR, C_READY_COUNT, ERR_READY_FULL, EXPAND_GROUP_SIZE,
    FALLBACK_CHUNK_NODES, MESH_NODES, SET_PASS, TASK_MESH_GROUPS,
};
use crate::frame::{FrameRec, Retired};
use crate::gpu::{DrawPush, ListPush, SceneLayout, Shaders};
use crate::patch::quadnode::QuadNode;
use crate::vk::{
    Access, Context, DeviceInfo, Pass, PipelineLayout, Recorder, Res, SetLayout, VkError, VkResult,
};

pub use ready::{indirect_args, ReadyCaps, ReadyList, MAX_READY_CAPACITY};

/// How ready nodes become triangles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawPath {
    /// Task + mesh shaders (VK_EXT_mesh_shader).
    Mesh,
    /// Compute expansion into a vertex buffer + one indirect draw.
    Fallback,
}

impl DrawPath {
    /// Lower-case name, as the CLI spells it.
    pub fn name(self) -> &'static str {
        match self {
            DrawPath::Mesh => "mesh",
            DrawPath::Fallback => "fallback",
        }
    }
}

impl fmt::Display for DrawPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// What the user asked for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DrawRequest {
    /// Mesh shaders where the device has them, else the fallback.
    #[default]
    Auto,
    /// Mesh shaders or an error.
    Mesh,
    /// The fallback even where mesh shaders exist.
    Fallback,
}

impl FromStr for DrawRequest {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "auto" => Ok(DrawRequest::Auto),
            "mesh" => Ok(DrawRequest::Mesh),
            "fallback" => Ok(DrawRequest::Fallback),
            other => Err(format!(
                "unknown draw path `{other}`: expected auto, mesh or fallback"
            )),
        }
    }
}

impl fmt::Display for DrawRequest {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            DrawRequest::Auto => "auto",
            DrawRequest::Mesh => "mesh",
            DrawRequest::Fallback => "fallback",
        })
    }
}

/// The draw path for `requested` on the context's device.
pub fn choose(ctx: &Context, requested: DrawRequest) -> VkResult<DrawPath> {
    choose_for(ctx.info(), requested)
}

/// [`choose`] for a described device (testable without such a device).
pub fn choose_for(info: &DeviceInfo, requested: DrawRequest) -> VkResult<DrawPath> {
    match (requested, info.has_mesh_shader()) {
        (DrawRequest::Fallback, _) | (DrawRequest::Auto, false) => Ok(DrawPath::Fallback),
        (DrawRequest::Auto, true) | (DrawRequest::Mesh, true) => Ok(DrawPath::Mesh),
        (DrawRequest::Mesh, false) => Err(mesh_missing(info)),
    }
}

fn mesh_missing(info: &DeviceInfo) -> VkError {
    VkError::FeatureMissing {
        device: info.name.clone(),
        feature: String::from("task and mesh shaders (VK_EXT_mesh_shader)"),
        hint: String::from(
            "; the `mesh` draw path was requested: use `fallback`, or `auto`, which picks \
             the fallback on this device",
        ),
    }
}

enum PathPipelines {
    Mesh(mesh::MeshDraw),
    Fallback(fallback::FallbackDraw),
}

/// The ready list with its sort and draw path: everything after a
/// producer's passes.
pub struct ReadyStage {
    set_layout: SetLayout,
    list: ReadyList,
    draw_layout: PipelineLayout<DrawPush>,
    list_layout: PipelineLayout<ListPush>,
    sort: sort::ReadySort,
    path: PathPipelines,
}

impl ReadyStage {
    /// Creates the list for `caps` (vertices added for the fallback path),
    /// the layouts and the pipelines of `path`.
    pub fn new(
        ctx: &Context,
        shaders: &mut Shaders,
        scene: &SceneLayout,
        path: DrawPath,
        caps: ReadyCaps,
    ) -> VkResult<Self> {
        if path == DrawPath::Mesh && !ctx.info().has_mesh_shader() {
            return Err(mesh_missing(ctx.info()));
        }
        let set_layout = ready::ready_set_layout(ctx)?;
        let caps = ReadyCaps {
            vertices: path == DrawPath::Fallback,
            ..caps
        };
        let list = ReadyList::new(ctx, &set_layout, caps)?;
        let draw_layout = scene.pipeline_layout::<DrawPush>(
            ctx,
            "ready-list draw layout",
            &[&set_layout],
            scene.stages(),
        )?;
        let list_layout = scene.pipeline_layout::<ListPush>(
            ctx,
            "ready-list pass layout",
            &[&set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let sort = sort::ReadySort::new(ctx, shaders, &list_layout)?;
        let path = match path {
            DrawPath::Mesh => PathPipelines::Mesh(mesh::MeshDraw::new(ctx, shaders, &draw_layout)?),
            DrawPath::Fallback => {
                PathPipelines::Fallback(fallback::FallbackDraw::new(ctx, shaders, &draw_layout)?)
            }
        };
        Ok(Self {
            set_layout,
            list,
            draw_layout,
            list_layout,
            sort,
            path,
        })
    }

    /// The layout of set 1, for producers' pipeline layouts.
    pub fn set_layout(&self) -> &SetLayout {
        &self.set_layout
    }

    /// The list and its counters.
    pub fn list(&self) -> &ReadyList {
        &self.list
    }

    /// The pipeline layout of the non-draw ready-list passes (scene set,
    /// ready set, [`ListPush`]).
    pub fn list_layout(&self) -> &PipelineLayout<ListPush> {
        &self.list_layout
    }

    /// Which draw path this is.
    pub fn path(&self) -> DrawPath {
        match self.path {
            PathPipelines::Mesh(_) => DrawPath::Mesh,
            PathPipelines::Fallback(_) => DrawPath::Fallback,
        }
    }

    /// Makes sure the list has a capture buffer exactly when the frame
    /// captures (the old list is retired).
    pub fn ensure_capture(
        &mut self,
        ctx: &Context,
        capture: bool,
        retired: &mut Retired,
    ) -> VkResult<()> {
        if self.list.caps.capture == capture {
            return Ok(());
        }
        self.replace_list(
            ctx,
            ReadyCaps {
                capture,
                ..self.list.caps
            },
            retired,
        )
    }

    /// After a frame: if the producer found the list full, grows it to hold
    /// the count it reached (plus a quarter) and says why; `None` if it fit.
    pub fn grow_if_full(
        &mut self,
        ctx: &Context,
        counters: &[u32],
        limit: u32,
        retired: &mut Retired,
    ) -> VkResult<Option<String>> {
        let wanted = counters[C_READY_COUNT as usize];
        if counters[C_ERROR as usize] & ERR_READY_FULL == 0 || self.list.caps.ready >= limit {
            return Ok(None);
        }
        let ready = (u64::from(wanted) * 5 / 4)
            .next_power_of_two()
            .min(u64::from(limit)) as u32;
        let reason = format!(
            "ready list of {} overflowed ({wanted} nodes): growing to {ready}",
            self.list.caps.ready
        );
        self.replace_list(
            ctx,
            ReadyCaps {
                ready,
                ..self.list.caps
            },
            retired,
        )?;
        Ok(Some(reason))
    }

    fn replace_list(
        &mut self,
        ctx: &Context,
        caps: ReadyCaps,
        retired: &mut Retired,
    ) -> VkResult<()> {
        // Made first: a failure leaves the old list in place and usable.
        let list = ReadyList::new(ctx, &self.set_layout, caps)?;
        retired.push(std::mem::replace(&mut self.list, list));
        Ok(())
    }

    /// Fills the list with `nodes` made on the host (e.g. the CPU oracle's
    /// ready list) and the counters with the indirect arguments a producer
    /// would write, growing the list if needed (the old one is retired):
    /// the draw paths then draw exactly these nodes.
    pub fn upload(
        &mut self,
        ctx: &Context,
        nodes: &[QuadNode],
        retired: &mut Retired,
    ) -> VkResult<()> {
        let n = u32::try_from(nodes.len())
            .map_err(|_| VkError::Usage(format!("{} ready nodes", nodes.len())))?;
        if n > self.list.caps.ready {
            self.replace_list(
                ctx,
                ReadyCaps {
                    ready: n,
                    ..self.list.caps
                },
                retired,
            )?;
        }
        let mut counters = vec![0u32; COUNTERS_BUFFER_WORDS as usize];
        for (word, value) in indirect_args(n) {
            counters[word as usize] = value;
        }
        self.list.ready.write(ctx, 0, nodes)?;
        self.list.counters.write(ctx, 0, &counters)
    }

    /// Records zeroing the counters (the start of a producer's frame).
    pub fn record_reset(&self, f: &FrameRec<'_>) {
        self.list.record_reset(f.ctx, f.cmd);
    }

    /// `pass` binding sets 0 and 1 (the scene, the list): a compute pass so
    /// declares the buffers of both its pipeline uses.
    pub fn bind_to<'p>(&'p self, f: &FrameRec<'p>, pass: Pass<'p>) -> Pass<'p> {
        f.with_scene(pass.bind(SET_PASS, self.list.set()))
    }

    /// Records binding sets 0 and 1 for a pipeline with `layout`.
    pub fn bind_sets(
        &self,
        f: &FrameRec<'_>,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout<impl bytemuck::Pod>,
    ) {
        f.bind_scene(bind_point, layout);
        self.list.bind(f.ctx, f.cmd, bind_point, layout);
    }

    /// Records binding sets 0 and 1 and pushing `pc` for a draw-path
    /// pipeline (draw layout).
    fn bind_draw(
        &self,
        f: &FrameRec<'_>,
        bind_point: vk::PipelineBindPoint,
        pc: &DrawPush,
    ) -> VkResult<()> {
        self.bind_sets(f, bind_point, &self.draw_layout);
        self.draw_layout.push(f.cmd, pc);
        Ok(())
    }

    /// Records the draw of the list into the frame's target: the barrier
    /// from the producer (module docs), the sort (scope "sort") when asked,
    /// for the fallback the expansion (scope "expand"), then rendering with
    /// clears and the indirect draw (scope "draw"), leaving the colour image
    /// in `DrawTarget::FINAL_LAYOUT`. The fallback does the last two once
    /// per chunk of the list (`fallback` module docs).
    pub fn record_draw(&self, f: &mut FrameRec<'_>, sort: bool) -> VkResult<()> {
        self.record_draw_part(f, sort, true, true)
    }

    /// [`ReadyStage::record_draw`] as one of several draws into the frame's
    /// target (occlusion culling's early and late phases): the `first`
    /// clears the target, the others load what it holds; all but the
    /// `last` keep the depth and samples for the next. Each draws the
    /// entries from `counters[C_READY_FIRST]` on.
    pub fn record_draw_part(
        &self,
        f: &mut FrameRec<'_>,
        sort: bool,
        first: bool,
        last: bool,
    ) -> VkResult<()> {
        let pc = f.view.draw_push(self.list.caps.ready, f.capture, 0);
        self.check(f.ctx, &pc)?;
        hand_off_from_producers(f.ctx, f.cmd);
        if sort && !self.list.caps.sort {
            return Err(VkError::Usage(
                "a sort was recorded for a ready list made without its second buffer".into(),
            ));
        }
        if sort {
            f.scoped("sort", |f| self.sort.record(f, self))?;
        }
        match &self.path {
            PathPipelines::Mesh(m) => {
                Self::record_rendering(f, first, last, |f| m.record_draw(f, self, &pc))
            }
            PathPipelines::Fallback(fb) => {
                // Each chunk's expansion overwrites the vertices the last
                // chunk's draw read: the recorder orders the two.
                let mut rec = Recorder::new(f.ctx, f.cmd);
                let vertices = Res::Buffer(&self.list.vertices);
                let chunks = self.list.caps.chunks();
                for chunk in 0..chunks {
                    let pc = DrawPush { chunk, ..pc };
                    f.scoped("expand", |f| fb.record_expand(f, &mut rec, self, &pc))?;
                    let (first, last) = (first && chunk == 0, last && chunk + 1 == chunks);
                    let pass = Pass::new("draw chunk").read(vertices, fallback::VERTEX_READ);
                    rec.run(&pass, |_| {
                        Self::record_rendering(f, first, last, |f| fb.record_draw(f, self, &pc))
                    })?;
                }
                Ok(())
            }
        }
    }

    /// Records `draw` inside rendering into the frame's target (scope
    /// "draw"), as part `first`/`last` of the frame's draws.
    fn record_rendering(
        f: &mut FrameRec<'_>,
        first: bool,
        last: bool,
        draw: impl FnOnce(&FrameRec<'_>) -> VkResult<()>,
    ) -> VkResult<()> {
        f.scoped("draw", |f| {
            f.target.begin_part(f.ctx, f.cmd, first, last);
            let drawn = draw(f);
            // Rendering is closed even on error so the command buffer stays
            // well formed until it is discarded.
            f.target.end(f.ctx, f.cmd);
            drawn
        })
    }

    /// Misuse that would make the shaders read or write out of bounds.
    fn check(&self, ctx: &Context, pc: &DrawPush) -> VkResult<()> {
        let caps = self.list.caps;
        let usage = |msg: String| Err(VkError::Usage(msg));
        if pc.capture_enabled != 0 && !caps.capture {
            return usage(
                "position capture requested but the ready list has no capture buffer".into(),
            );
        }
        let (groups, max, what) = match self.path {
            PathPipelines::Mesh(_) => (
                caps.ready.div_ceil(MESH_NODES * TASK_MESH_GROUPS),
                ctx.info()
                    .mesh
                    .map_or(0, |m| m.max_task_work_group_count[0]),
                "task",
            ),
            PathPipelines::Fallback(_) => (
                caps.ready
                    .min(FALLBACK_CHUNK_NODES)
                    .div_ceil(EXPAND_GROUP_SIZE),
                ctx.info().limits.max_compute_work_group_count[0],
                "expansion",
            ),
        };
        if groups > max {
            return usage(format!(
                "{} ready entries need {groups} {what} workgroups; the device allows {max}",
                caps.ready
            ));
        }
        Ok(())
    }

    /// Bytes per purpose.
    pub fn memory_bytes(&self) -> Vec<(&'static str, u64)> {
        self.list.memory_bytes()
    }
}

/// The barrier of the module docs' contract. Source: storage writes in
/// compute (the producer) and in the draw stages (the previous frame's
/// capture); destination: everything a draw reads or writes before the
/// rasterizer. Earlier reads in the vertex stage are in the source scope
/// too, so the expansion cannot overwrite vertices a previous draw in the
/// same command buffer still reads.
fn hand_off_from_producers(ctx: &Context, cmd: vk::CommandBuffer) {
    let mut stages =
        vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::VERTEX_SHADER;
    if ctx.info().has_mesh_shader() {
        stages |=
            vk::PipelineStageFlags2::TASK_SHADER_EXT | vk::PipelineStageFlags2::MESH_SHADER_EXT;
    }
    let src = Access::new(stages, vk::AccessFlags2::SHADER_STORAGE_WRITE);
    let dst = Access::new(
        stages | vk::PipelineStageFlags2::DRAW_INDIRECT,
        vk::AccessFlags2::INDIRECT_COMMAND_READ
            | vk::AccessFlags2::SHADER_STORAGE_READ
            | vk::AccessFlags2::SHADER_STORAGE_WRITE
            | vk::AccessFlags2::UNIFORM_READ,
    );
    // The producers were recorded elsewhere: declared here as what came
    // before, handed off to the draw's stages.
    let mut rec = Recorder::new(ctx, cmd);
    rec.after(Res::Memory, src);
    rec.hand_off(Res::Memory, dst);
}
