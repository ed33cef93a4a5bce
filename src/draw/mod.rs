//! Drawing the ready QuadNodes (paper §3.4): 2 triangles + up to 2 wedges
//! per node, every vertex the base patch evaluated by the one shared precise
//! function, so positions equal the oracle's bit for bit.
//!
//! Two paths share the scene layout, the push constants and the fragment
//! shading (`glsl/common/shade.glsl`):
//! - [`DrawPath::Mesh`]: task + mesh shaders (`glsl/draw.task`,
//!   `glsl/draw.mesh`), one indirect `vkCmdDrawMeshTasksIndirectEXT` from
//!   `counters[C_MESH_ARGS]`.
//! - [`DrawPath::Fallback`], for devices without VK_EXT_mesh_shader: a compute
//!   pass (`glsl/expand.comp`, indirect from `counters[C_EXPAND_ARGS]`) writes
//!   12 vertices per node into the frame's vertex buffer, then one
//!   `vkCmdDrawIndirect` from `counters[C_DRAW_ARGS]` pulls them in a
//!   pass-through vertex shader.
//!
//! Barrier contract: [`Drawer::record`] starts with a global barrier from
//! compute-shader storage writes (the subdivision pass's ready list and
//! counters, indirect arguments included) to indirect-command reads and to
//! storage/uniform reads in the compute, task, mesh and vertex stages. A
//! producer that writes these buffers some other way (e.g. a transfer in the
//! same command buffer) must make the writes available to those stages
//! itself.

pub mod fallback;
pub mod mesh;
pub mod target;

use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

use ash::vk;
use glam::{DMat4, DVec3, Vec3};

use crate::constants::{EXPAND_GROUP_SIZE, MESH_NODES, TASK_MESH_GROUPS};
use crate::gpu::{FrameGpu, PushConstants, SceneLayout};
use crate::scene::camera::Camera;
use crate::vk::{
    buffer_barrier, memory_barrier, Access, Context, DeviceInfo, GpuTimer, Pipeline, ShaderModule,
    VkError, VkResult,
};

pub use target::{write_png, DrawTarget, COLOR_FORMAT, DEPTH_FORMAT};

/// Errors of saving images (drawing itself reports [`VkError`]).
#[derive(Debug, thiserror::Error)]
pub enum DrawError {
    /// A Vulkan failure (readback).
    #[error(transparent)]
    Vk(#[from] VkError),
    /// Creating, writing or renaming a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// PNG encoding failed.
    #[error("encoding {} as PNG: {source}", path.display())]
    Png {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: image::ImageError,
    },
}

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

enum Inner {
    Mesh(mesh::MeshDraw),
    Fallback(fallback::FallbackDraw),
}

/// The pipelines of one draw path, created once, recorded per frame.
pub struct Drawer {
    inner: Inner,
}

impl Drawer {
    /// Creates the path's pipelines against the scene layout.
    pub fn new(ctx: &Context, layout: &SceneLayout, path: DrawPath) -> VkResult<Self> {
        let inner = match path {
            DrawPath::Mesh => {
                if !ctx.info().has_mesh_shader() {
                    return Err(mesh_missing(ctx.info()));
                }
                Inner::Mesh(mesh::MeshDraw::new(ctx, layout)?)
            }
            DrawPath::Fallback => Inner::Fallback(fallback::FallbackDraw::new(ctx, layout)?),
        };
        Ok(Self { inner })
    }

    /// Which path this is.
    pub fn path(&self) -> DrawPath {
        match self.inner {
            Inner::Mesh(_) => DrawPath::Mesh,
            Inner::Fallback(_) => DrawPath::Fallback,
        }
    }

    /// Records the draw of `frame`'s ready list into `target`: the barrier
    /// from the subdivision pass (module docs), for the fallback the
    /// expansion dispatch and its barrier, then rendering with clears, the
    /// indirect draw, and the colour image left in
    /// [`DrawTarget::FINAL_LAYOUT`]. Scopes "expand" and "draw" go to
    /// `timer` when given (the caller resets it).
    #[allow(clippy::too_many_arguments)]
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        target: &DrawTarget,
        pc: &PushConstants,
        mut timer: Option<&mut GpuTimer>,
    ) -> VkResult<()> {
        self.check(ctx, frame, pc)?;
        barrier_from_producers(ctx, cmd);
        if let Inner::Fallback(f) = &self.inner {
            if let Some(t) = timer.as_deref_mut() {
                t.begin(cmd, "expand")?;
            }
            f.record_expand(ctx, cmd, layout, frame, pc)?;
            if let Some(t) = timer.as_deref_mut() {
                t.end(cmd, "expand")?;
            }
            buffer_barrier(
                ctx,
                cmd,
                &frame.vertices,
                Access::COMPUTE_WRITE,
                Access::new(
                    vk::PipelineStageFlags2::VERTEX_SHADER,
                    vk::AccessFlags2::SHADER_STORAGE_READ,
                ),
            );
        }
        if let Some(t) = timer.as_deref_mut() {
            t.begin(cmd, "draw")?;
        }
        target.begin(ctx, cmd);
        let drawn = match &self.inner {
            Inner::Mesh(m) => m.record_draw(ctx, cmd, layout, frame, pc),
            Inner::Fallback(f) => f.record_draw(ctx, cmd, layout, frame, pc),
        };
        // Rendering is closed even on error so the command buffer stays
        // well formed for the caller's submit-and-discard.
        target.end(ctx, cmd);
        drawn?;
        if let Some(t) = timer {
            t.end(cmd, "draw")?;
        }
        Ok(())
    }

    /// Records, for the fallback path only, a draw of `vertices` vertices
    /// already in `frame.vertices` (written by the host in the
    /// `VERTEX_WORDS` format), into `target` with clears: how a mesh made on
    /// the CPU, such as the hole test's dense reference, is drawn through the
    /// same vertex and fragment shaders as the fallback path.
    #[allow(clippy::too_many_arguments)]
    pub fn record_vertices(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        frame: &FrameGpu,
        target: &DrawTarget,
        pc: &PushConstants,
        vertices: u32,
    ) -> VkResult<()> {
        let Inner::Fallback(f) = &self.inner else {
            return Err(VkError::Usage(
                "drawing a vertex buffer needs the fallback drawer".into(),
            ));
        };
        let capacity = frame.vertices.size() / (4 * crate::constants::VERTEX_WORDS as u64);
        if !frame.caps.vertices || u64::from(vertices) > capacity {
            return Err(VkError::Usage(format!(
                "{vertices} vertices do not fit the frame's vertex buffer ({capacity})"
            )));
        }
        memory_barrier(ctx, cmd, Access::ALL, Access::ALL);
        target.begin(ctx, cmd);
        let drawn = f.record_vertices(ctx, cmd, layout, frame, pc, vertices);
        target.end(ctx, cmd);
        drawn
    }

    /// Misuse that would make the shaders read or write out of bounds.
    fn check(&self, ctx: &Context, frame: &FrameGpu, pc: &PushConstants) -> VkResult<()> {
        let caps = frame.caps;
        let usage = |msg: String| Err(VkError::Usage(msg));
        if pc.ready_capacity > caps.ready {
            return usage(format!(
                "push constants claim {} ready entries but the ready list holds {}",
                pc.ready_capacity, caps.ready
            ));
        }
        if pc.capture_enabled != 0 && !caps.capture {
            return usage(
                "position capture requested but the frame has no capture buffer \
                 (Capacities::capture)"
                    .into(),
            );
        }
        match self.inner {
            Inner::Mesh(_) => {
                let groups = caps.ready.div_ceil(MESH_NODES * TASK_MESH_GROUPS);
                let max = ctx
                    .info()
                    .mesh
                    .map_or(0, |m| m.max_task_work_group_count[0]);
                if groups > max {
                    return usage(format!(
                        "{} ready entries need {groups} task workgroups; the device allows {max}",
                        caps.ready
                    ));
                }
            }
            Inner::Fallback(_) => {
                if !caps.vertices {
                    return usage(
                        "the fallback draw path needs the frame's vertex buffer \
                         (Capacities::vertices)"
                            .into(),
                    );
                }
                let groups = caps.ready.div_ceil(EXPAND_GROUP_SIZE);
                let max = ctx.info().limits.max_compute_work_group_count[0];
                if groups > max {
                    return usage(format!(
                        "{} ready entries need {groups} expansion workgroups; the device allows {max}",
                        caps.ready
                    ));
                }
            }
        }
        Ok(())
    }
}

/// The barrier of the module docs' contract. Source: storage writes in
/// compute (the subdivision pass) and in the draw stages (the previous
/// frame's capture); destination: everything a draw reads or writes before
/// the rasterizer. Earlier reads in the vertex stage are in the source scope
/// too, so the expansion cannot overwrite vertices a previous draw in the
/// same command buffer still reads.
fn barrier_from_producers(ctx: &Context, cmd: vk::CommandBuffer) {
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
    memory_barrier(ctx, cmd, src, dst);
}

/// Binds `pipeline` with the scene set and pushes `pc`.
fn bind(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    pipeline: &Pipeline,
    bind_point: vk::PipelineBindPoint,
    layout: &SceneLayout,
    frame: &FrameGpu,
    pc: &PushConstants,
) -> VkResult<()> {
    pipeline.bind(cmd);
    frame.bind(ctx, cmd, layout, bind_point);
    layout.push(cmd, pc)
}

/// A graphics pipeline for the draw target: no culling (the teapot is open
/// and SHADE_KEY shows back faces), counter-clockwise front faces (quad
/// triangles wind counter-clockwise about dS/du × dS/dv, and the camera's
/// y-flipped projection keeps that counter-clockwise on screen), depth test
/// LESS with writes, dynamic viewport and scissor, dynamic rendering.
/// `vertex_stage`: a vertex shader with no vertex input; otherwise task +
/// mesh, whose pipelines leave vertex-input and input-assembly state null.
fn graphics_pipeline(
    ctx: &Context,
    layout: &SceneLayout,
    stages: &[(vk::ShaderStageFlags, &ShaderModule)],
    vertex_stage: bool,
    name: &str,
) -> VkResult<Pipeline> {
    let stage_infos: Vec<_> = stages
        .iter()
        .map(|(stage, module)| {
            vk::PipelineShaderStageCreateInfo::default()
                .stage(*stage)
                .module(module.handle())
                .name(c"main")
        })
        .collect();
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(vk::CullModeFlags::NONE)
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::TYPE_1);
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(true)
        .depth_write_enable(true)
        .depth_compare_op(vk::CompareOp::LESS);
    let attachments = [vk::PipelineColorBlendAttachmentState::default()
        .blend_enable(false)
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let color_formats = [COLOR_FORMAT];
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(DEPTH_FORMAT);
    let mut info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stage_infos)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout.layout.handle())
        .push_next(&mut rendering);
    if vertex_stage {
        info = info
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly);
    }
    let handle = unsafe {
        ctx.device()
            .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
    }
    .map_err(|(_, result)| VkError::Call {
        context: format!("vkCreateGraphicsPipelines({name})"),
        result,
    })?[0];
    Ok(Pipeline::from_handle(
        ctx,
        handle,
        vk::PipelineBindPoint::GRAPHICS,
        name,
    ))
}

/// Direction towards the light for `camera`: from above and to the left of
/// the eye, so silhouettes get a shaded side.
pub fn headlight(camera: &Camera) -> Vec3 {
    let f = camera.forward();
    let up = DVec3::from_array(camera.up);
    let right = f.cross(up).normalize_or_zero();
    let cam_up = right.cross(f).normalize_or_zero();
    (-f + cam_up * 0.6 - right * 0.5).normalize().as_vec3()
}

/// Push constants for drawing `frame` seen by `view_proj` with `shade`
/// (`SHADE_*`) and the light towards `light_dir`; capture off.
pub fn draw_push(
    view_proj: &DMat4,
    light_dir: Vec3,
    shade: u32,
    frame: &FrameGpu,
    patch_count: u32,
) -> PushConstants {
    PushConstants {
        view_proj: view_proj.as_mat4().to_cols_array(),
        light_dir: light_dir.extend(0.0).to_array(),
        shade,
        ready_capacity: frame.caps.ready,
        queue_capacity: frame.caps.queue,
        patch_count,
        idle_poll_cap: 0,
        ..bytemuck::Zeroable::zeroed()
    }
}
