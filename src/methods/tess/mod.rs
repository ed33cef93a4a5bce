//! Methods `tess` and `tess-reparam`: the hardware-tessellation baselines
//! of Buchenau and Guthe, *Real-Time Re-Parameterized Bézier Tessellation*
//! (2021). One draw of every base patch as a 16-point patch through a
//! tessellation control and evaluation stage (`glsl/tess.{vert,tesc,tese}`,
//! the math in `glsl/tess/tess.glsl`):
//!
//! - `tess`: uniform levels from the Filip et al. bound on the second
//!   derivatives (their §3.1-3.2): inner levels from M_u + M_uv and
//!   M_v + M_uv, edge levels from the edge curve's own bound, ε pixels
//!   turned into an object-space tolerance at the smallest view depth of
//!   the patch's (or the edge's) control points (§5.1);
//! - `tess-reparam`: their method, §4 and §5.2: levels from the integral of
//!   the local sample density, the samples moved to follow it in the
//!   evaluation stage, and the mixed bound after one midpoint subdivision.
//!
//! The control stage culls patches outside the frustum (and wholly
//! back-facing ones, where the view asks for back-face culling) by writing
//! level 0; levels are clamped to the device's maximum. An edge's level and
//! its vertices depend only on the edge's control points and the view, in
//! an order that is the same from both sides, so shared edges meet without
//! cracks. There is no count of its own: the frame's triangles come from
//! the renderer's primitive query, which is why the method needs one.

pub mod checks;
pub mod constants;

use ash::vk;
use serde_json::json;

use self::constants::*;
use super::edges::{EdgeVertex, PatchLevels};
use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, Reads, RenderError, Role};
use crate::constants::*;
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::{DrawPush, COLOR_FORMAT, DEPTH_FORMAT};
use crate::vk::{
    Access, Buffer, Context, DescriptorSet, GraphicsDesc, MemoryLocation, Pass, Pipeline,
    PipelineLayout, Recorder, Res, SetLayout, VkError, VkResult,
};

/// The registry entry of the uniform metric.
pub const INFO: MethodInfo = MethodInfo {
    name: "tess",
    about: "hardware tessellation, uniform levels from the Filip et al. bound (Buchenau-Guthe §3)",
    rational: false,
    pn: false,
    reads: Reads::TESSELLATES,
    role: Role::Baseline,
    targets: &[],
    heat_map: "log2 of the inner tessellation level",
    seams: "wedges (none for this method)",
    checks: Some(checks::make),
    blocks: &[],
    build: |setup| Ok(Box::new(Tess::new(setup, Variant::Uniform)?)),
};

/// The registry entry of the re-parameterised metric: the uniform one's
/// but for its name and variant.
pub const INFO_REPARAM: MethodInfo = MethodInfo {
    name: "tess-reparam",
    about: "hardware tessellation with Buchenau-Guthe's curvature re-parameterisation (§4, §5.2)",
    role: Role::Compared,
    build: |setup| Ok(Box::new(Tess::new(setup, Variant::Reparam)?)),
    ..INFO
};

/// Specialization constant ids of `glsl/tess/tess.glsl` (glslang takes
/// only literals there, so they are not in the shared constants).
const SPEC_REPARAM: u32 = 0;
const SPEC_MAX_LEVEL: u32 = 1;

/// Most edge vertices a capture holds (24 bytes each); more are counted,
/// not stored.
pub const MAX_EDGE_CAPTURE: u32 = 1 << 20;

/// Which metric.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variant {
    /// `tess`.
    Uniform,
    /// `tess-reparam`.
    Reparam,
}

/// The set-1 buffers: counters, and the capture buffers (a word each
/// unless a frame captures).
struct Buffers {
    levels: Buffer,
    edge_vertices: Buffer,
    /// Patches the levels buffer holds (0: not capturing).
    patches: u32,
    /// Edge vertices the capture holds.
    edge_capacity: u32,
    set: DescriptorSet,
}

/// The tessellation stages, which read set 1 (the vertex and fragment
/// stages do not).
pub const TESS_SHADERS: &[&str] = &["tess/patch.tesc", "tess/patch.tese"];

/// A tessellation method.
pub struct Tess {
    variant: Variant,
    max_level: u32,
    /// Patches one draw call covers (lavapipe: `patches_per_draw`).
    patches_per_draw: u32,
    counters: Buffer,
    buffers: Option<Buffers>,
    set_layout: SetLayout,
    layout: PipelineLayout<DrawPush>,
    pipeline: Pipeline,
    copied: Option<CopyRange>,
    captured: bool,
}

impl Tess {
    /// Creates the pipeline of `variant`; a device without tessellation
    /// shaders, storage writes in them or a primitive query is refused
    /// with a sentence.
    pub fn new(setup: &mut MethodSetup<'_>, variant: Variant) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        let name = match variant {
            Variant::Uniform => INFO.name,
            Variant::Reparam => INFO_REPARAM.name,
        };
        check_device(ctx, name)?;
        let max_level = ctx.info().limits.max_tessellation_generation_level;
        let patches_per_draw = patches_per_draw(ctx.info(), max_level);
        let set_layout = SetLayout::reflect(ctx, "tess set", SET_PASS, TESS_SHADERS)?;
        let scene = setup.scene_layout;
        let layout = scene.pipeline_layout::<DrawPush>(
            ctx,
            &format!("{name} layout"),
            &[&set_layout],
            scene.stages(),
        )?;
        let vert = setup.shaders.get(ctx, "tess/patch.vert")?;
        let tesc = setup.shaders.get(ctx, "tess/patch.tesc")?;
        let tese = setup.shaders.get(ctx, "tess/patch.tese")?;
        let frag = setup.shaders.get(ctx, "draw_vert.frag")?;
        let title = format!("draw ({name})");
        let desc = GraphicsDesc::new(
            &title,
            &[
                (vk::ShaderStageFlags::VERTEX, vert.as_ref()),
                (vk::ShaderStageFlags::TESSELLATION_CONTROL, tesc.as_ref()),
                (vk::ShaderStageFlags::TESSELLATION_EVALUATION, tese.as_ref()),
                (vk::ShaderStageFlags::FRAGMENT, frag.as_ref()),
            ],
        )
        .targets(&[COLOR_FORMAT], DEPTH_FORMAT)
        .samples(setup.shaders.samples)
        .tessellation(16)
        .specialize(&setup.shaders.specialization(&[
            (SPEC_REPARAM, u32::from(variant == Variant::Reparam)),
            (SPEC_MAX_LEVEL, (max_level as f32).to_bits()),
        ]));
        let pipeline = Pipeline::graphics(ctx, &layout, &desc)?;
        let counters = Buffer::new(
            ctx,
            "tess counters",
            u64::from(TESS_WORDS) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        Ok(Self {
            variant,
            max_level,
            patches_per_draw,
            counters,
            buffers: None,
            set_layout,
            layout,
            pipeline,
            copied: None,
            captured: false,
        })
    }

    /// The set for this frame: capture buffers for `patches` patches when
    /// `capture`, else one word each; remade (the old one retired) when
    /// that changes.
    fn ensure_buffers(&mut self, f: &mut FrameRec<'_>) -> VkResult<()> {
        let patches = if f.capture { f.scene.count } else { 0 };
        if self.buffers.as_ref().is_some_and(|b| b.patches == patches) {
            return Ok(());
        }
        let edge_capacity = if f.capture {
            // Worst case: every edge at the largest level.
            let worst = u64::from(patches) * 4 * u64::from(self.max_level.max(2) - 1);
            worst.min(u64::from(MAX_EDGE_CAPTURE)) as u32
        } else {
            0
        };
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let levels = Buffer::new(
            f.ctx,
            "tess levels (capture)",
            4 * u64::from(TESS_LEVEL_WORDS) * u64::from(patches.max(1)),
            storage,
            gpu,
        )?;
        let edge_vertices = Buffer::new(
            f.ctx,
            "tess edge vertices (capture)",
            4 * u64::from(TESS_EDGE_VERTEX_WORDS) * u64::from(edge_capacity.max(1)),
            storage,
            gpu,
        )?;
        let mut bound = [(&self.counters).into(); TESS_BINDINGS as usize];
        bound[BIND_TESS_LEVELS as usize] = (&levels).into();
        bound[BIND_TESS_EDGE_VERTICES as usize] = (&edge_vertices).into();
        let set = DescriptorSet::new(f.ctx, "tess set", &self.set_layout, &bound)?;
        let new = Buffers {
            levels,
            edge_vertices,
            patches,
            edge_capacity,
            set,
        };
        if let Some(old) = self.buffers.replace(new) {
            f.retired.push(old);
        }
        Ok(())
    }

    /// The levels every patch got in the last frame recorded with capture
    /// on (read after it finished).
    pub fn read_levels(&self, ctx: &Context) -> Result<Vec<PatchLevels>, RenderError> {
        let b = self.capture_buffers()?;
        let words: Vec<f32> = b.levels.read(ctx)?;
        Ok(words
            .chunks_exact(TESS_LEVEL_WORDS as usize)
            .take(b.patches as usize)
            .map(|w| PatchLevels {
                outer: [w[0], w[1], w[2], w[3]],
                inner: [w[4], w[5]],
                mixed: w[6],
                culled: w[7] != 0.0,
                drawn_inner: [w[8], w[9]],
            })
            .collect())
    }

    /// The edge vertices of the last frame recorded with capture on, and
    /// how many there were (more than returned when the capture was full).
    pub fn read_edge_vertices(&self, ctx: &Context) -> Result<(Vec<EdgeVertex>, u64), RenderError> {
        let b = self.capture_buffers()?;
        let counters: Vec<u32> = self.counters.read(ctx)?;
        let total = counters[T_EDGE_VERTICES as usize];
        let words: Vec<u32> = b.edge_vertices.read(ctx)?;
        let kept = total.min(b.edge_capacity) as usize;
        let v = words
            .chunks_exact(TESS_EDGE_VERTEX_WORDS as usize)
            .take(kept)
            .map(|w| EdgeVertex {
                patch: w[0],
                edge: w[1],
                t: f32::from_bits(w[2]),
                position: [
                    f32::from_bits(w[3]),
                    f32::from_bits(w[4]),
                    f32::from_bits(w[5]),
                ],
            })
            .collect();
        Ok((v, u64::from(total)))
    }

    fn capture_buffers(&self) -> Result<&Buffers, RenderError> {
        match &self.buffers {
            Some(b) if self.captured && b.patches > 0 => Ok(b),
            _ => Err(RenderError::Request(
                "no tessellation capture: render a frame with capture on first".into(),
            )),
        }
    }

    /// Records the counters' reset and the draw.
    fn record_draw(&self, f: &mut FrameRec<'_>, b: &Buffers) -> VkResult<()> {
        // The draw's tessellation stages count culled patches and capture
        // edges: all memory, after the counters' reset (and any transfer
        // before it). The reset waits for every earlier use of the
        // counters (the last frame's readback).
        let mut rec = Recorder::new(f.ctx, f.cmd);
        rec.after(Res::Memory, Access::TRANSFER_WRITE)
            .after(Res::Buffer(&self.counters), Access::ALL);
        rec.fill("tess counters reset", &self.counters, 0);
        let draw = Pass::new("tessellated draw").write(
            Res::Memory,
            Access::new(
                vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER
                    | vk::PipelineStageFlags2::TESSELLATION_EVALUATION_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
        );
        let pc = f.view.draw_push(b.edge_capacity, f.capture, 0);
        let patches = f.scene.count;
        rec.run(&draw, |_| {
            f.scoped("draw", |f| {
                let (ctx, cmd) = (f.ctx, f.cmd);
                f.target.begin(ctx, cmd);
                let bind = vk::PipelineBindPoint::GRAPHICS;
                self.pipeline.bind(cmd);
                f.bind_scene(bind, &self.layout);
                b.set.bind(ctx, cmd, bind, &self.layout, SET_PASS, &[]);
                self.layout.push(cmd, &pc);
                for first in (0..patches).step_by(self.patches_per_draw as usize) {
                    let count = self.patches_per_draw.min(patches - first);
                    unsafe { ctx.device().cmd_draw(cmd, 16 * count, 1, 16 * first, 0) };
                }
                f.target.end(ctx, cmd);
                Ok(())
            })
        })
    }
}

/// The patches one draw call may cover so that the device tessellates them
/// correctly. lavapipe numbers the tessellated vertices of the patches it
/// takes together with 16 bits (Mesa's draw module, `draw_tess.c`): past
/// 65,535 vertices the indices wrap and join the wrong vertices into
/// shards (the teapot's lid rim at ε 0.15 and 1920x1080: geometric p99
/// 7.4 px against 0.10 px; measured on Mesa 25.0.7). A patch at level L
/// has at most (L + 1)² vertices, so on lavapipe each draw covers at most
/// 65,535 / (L + 1)² patches; elsewhere one draw covers all.
fn patches_per_draw(info: &crate::vk::DeviceInfo, max_level: u32) -> u32 {
    if info.driver_id == vk::DriverId::MESA_LLVMPIPE {
        let per_patch = (max_level + 1) * (max_level + 1);
        (u32::from(u16::MAX) / per_patch).max(1)
    } else {
        u32::MAX
    }
}

/// Refuses a device the method cannot run on, naming what is missing.
fn check_device(ctx: &Context, name: &str) -> Result<(), RenderError> {
    let info = ctx.info();
    let f = info.features;
    let missing = if !f.tessellation_shader {
        Some("tessellation shaders (`tessellationShader`)")
    } else if !f.vertex_pipeline_stores_and_atomics {
        Some("storage writes in tessellation shaders (`vertexPipelineStoresAndAtomics`), which count culled patches")
    } else if !(f.primitives_generated_query || f.pipeline_statistics_query) {
        Some("a query counting primitives (VK_EXT_primitives_generated_query or `pipelineStatisticsQuery`)")
    } else if info.limits.max_tessellation_generation_level < 2 {
        Some("a tessellation level above 1")
    } else {
        None
    };
    match missing {
        None => Ok(()),
        Some(what) => Err(RenderError::Request(format!(
            "method `{name}` needs {what}, which {} does not have; use `subdiv` or another device",
            info.name
        ))),
    }
}

impl Method for Tess {
    fn name(&self) -> &'static str {
        match self.variant {
            Variant::Uniform => INFO.name,
            Variant::Reparam => INFO_REPARAM.name,
        }
    }

    fn draw_path(&self) -> &'static str {
        "tessellation"
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.ensure_buffers(f)?;
        let b = self
            .buffers
            .as_ref()
            .ok_or_else(|| VkError::Usage("no tess set".into()))?;
        self.record_draw(f, b)?;
        self.captured = f.capture;
        self.copied = Some(f.copy_out(&self.counters, TESS_WORDS)?);
        Ok(())
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let range = self
            .copied
            .ok_or_else(|| RenderError::Request("finish() before any frame was recorded".into()))?;
        let words = out.words(range);
        let at = |k: u32| u64::from(words[k as usize]);
        Ok(Finished::Done(MethodStats {
            // Counted by the renderer's primitive query.
            triangles: 0,
            placeholder_triangles: 0,
            culled_patches: at(T_CULLED),
            own: vec![
                ("tessellated_patches", json!(at(T_TESSELLATED))),
                ("backface_culled_patches", json!(at(T_BACKFACE))),
                ("max_level", json!(self.max_level)),
                ("patches_per_draw", json!(self.patches_per_draw)),
            ],
        }))
    }

    fn reconfigure(
        &mut self,
        _setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        // Nothing of the tessellation depends on the knobs.
        Ok(true)
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![("counters", self.counters.size())];
        if let Some(b) = self.buffers.as_ref().filter(|b| b.patches > 0) {
            v.push(("capture", b.levels.size() + b.edge_vertices.size()));
        }
        v
    }
}
