//! Compute and graphics pipelines built against a [`PipelineLayout`] owned
//! elsewhere, with specialization constants; graphics state comes from a
//! [`GraphicsDesc`] with room for every kind of draw the renderer has:
//! vertex pulling, task + mesh, tessellation.

use std::collections::BTreeMap;

use super::context::{Context, Core};
use super::error::{VkError, VkResult};
use super::layout::PipelineLayout;
use super::shader::ShaderModule;
use ash::vk;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Specialization data: one 32-bit value per constant id.
pub struct Specialization {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u8>,
}

impl Specialization {
    /// From (constant_id, value) pairs; bools are 32-bit in SPIR-V too.
    pub fn new(constants: &[(u32, u32)]) -> Self {
        let entries = constants
            .iter()
            .enumerate()
            .map(|(i, &(id, _))| vk::SpecializationMapEntry {
                constant_id: id,
                offset: 4 * i as u32,
                size: 4,
            })
            .collect();
        let data = constants
            .iter()
            .flat_map(|&(_, v)| v.to_ne_bytes())
            .collect();
        Self { entries, data }
    }

    /// The Vulkan struct borrowing this data.
    pub fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default()
            .map_entries(&self.entries)
            .data(&self.data)
    }

    fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

/// One shader stage of a pipeline: `main` of `module`, specialized by
/// `spec` when it has constants.
fn stage_info<'a>(
    stage: vk::ShaderStageFlags,
    module: &ShaderModule,
    spec: &'a vk::SpecializationInfo<'a>,
    specialized: bool,
) -> vk::PipelineShaderStageCreateInfo<'a> {
    let info = vk::PipelineShaderStageCreateInfo::default()
        .stage(stage)
        .module(module.handle())
        .name(c"main");
    if specialized {
        info.specialization_info(spec)
    } else {
        info
    }
}

/// Depth test and write settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DepthState {
    /// Test against the depth attachment.
    pub test: bool,
    /// Write the depth attachment.
    pub write: bool,
    /// The comparison.
    pub compare: vk::CompareOp,
}

impl DepthState {
    /// Test LESS and write: opaque surfaces.
    pub const OPAQUE: Self = Self {
        test: true,
        write: true,
        compare: vk::CompareOp::LESS,
    };
    /// No depth at all.
    pub const NONE: Self = Self {
        test: false,
        write: false,
        compare: vk::CompareOp::ALWAYS,
    };
}

/// Everything a graphics pipeline is made of besides its layout. Built with
/// [`GraphicsDesc::new`] and the chained setters; viewport and scissor are
/// always dynamic, rendering is always dynamic rendering.
#[derive(Clone)]
pub struct GraphicsDesc<'a> {
    /// Debug name.
    pub name: &'a str,
    /// Stages and their modules: vertex (+ tessellation control and
    /// evaluation) or task + mesh, and fragment.
    pub stages: Vec<(vk::ShaderStageFlags, &'a ShaderModule)>,
    /// (constant_id, value) pairs given to every stage.
    pub specialization: Vec<(u32, u32)>,
    /// Input topology (vertex pipelines; PATCH_LIST with tessellation).
    pub topology: vk::PrimitiveTopology,
    /// Control points per patch; non-zero adds tessellation state.
    pub patch_control_points: u32,
    /// Fill or lines (wireframe needs `fillModeNonSolid`).
    pub polygon_mode: vk::PolygonMode,
    /// Which faces the rasterizer drops.
    pub cull_mode: vk::CullModeFlags,
    /// Winding of front faces.
    pub front_face: vk::FrontFace,
    /// Depth test and write.
    pub depth: DepthState,
    /// Colour attachment formats.
    pub color_formats: Vec<vk::Format>,
    /// Depth attachment format (`UNDEFINED`: none).
    pub depth_format: vk::Format,
    /// Rasterization samples.
    pub samples: vk::SampleCountFlags,
}

impl<'a> GraphicsDesc<'a> {
    /// Triangle lists, filled, no culling, counter-clockwise front faces,
    /// opaque depth, one sample, no attachments yet.
    pub fn new(name: &'a str, stages: &[(vk::ShaderStageFlags, &'a ShaderModule)]) -> Self {
        Self {
            name,
            stages: stages.to_vec(),
            specialization: Vec::new(),
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            patch_control_points: 0,
            polygon_mode: vk::PolygonMode::FILL,
            cull_mode: vk::CullModeFlags::NONE,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            depth: DepthState::OPAQUE,
            color_formats: Vec::new(),
            depth_format: vk::Format::UNDEFINED,
            samples: vk::SampleCountFlags::TYPE_1,
        }
    }

    /// The attachment formats drawn into.
    pub fn targets(mut self, color: &[vk::Format], depth: vk::Format) -> Self {
        self.color_formats = color.to_vec();
        self.depth_format = depth;
        self
    }

    /// Patch lists of `control_points` points through tessellation stages.
    pub fn tessellation(mut self, control_points: u32) -> Self {
        self.topology = vk::PrimitiveTopology::PATCH_LIST;
        self.patch_control_points = control_points;
        self
    }

    /// The input topology.
    pub fn topology(mut self, topology: vk::PrimitiveTopology) -> Self {
        self.topology = topology;
        self
    }

    /// Specialization constants for every stage.
    pub fn specialize(mut self, constants: &[(u32, u32)]) -> Self {
        self.specialization = constants.to_vec();
        self
    }

    /// Rasterizer polygon mode.
    pub fn polygon_mode(mut self, mode: vk::PolygonMode) -> Self {
        self.polygon_mode = mode;
        self
    }

    /// Face culling.
    pub fn cull(mut self, mode: vk::CullModeFlags) -> Self {
        self.cull_mode = mode;
        self
    }

    /// Depth state.
    pub fn depth(mut self, depth: DepthState) -> Self {
        self.depth = depth;
        self
    }

    /// Rasterization samples.
    pub fn samples(mut self, samples: vk::SampleCountFlags) -> Self {
        self.samples = samples;
        self
    }

    fn is_mesh(&self) -> bool {
        self.stages
            .iter()
            .any(|(s, _)| s.contains(vk::ShaderStageFlags::MESH_EXT))
    }

    fn check(&self) -> VkResult<()> {
        let has = |s: vk::ShaderStageFlags| self.stages.iter().any(|(x, _)| *x == s);
        let tess = has(vk::ShaderStageFlags::TESSELLATION_CONTROL)
            || has(vk::ShaderStageFlags::TESSELLATION_EVALUATION);
        let problem = if self.is_mesh() && has(vk::ShaderStageFlags::VERTEX) {
            Some("mixes mesh and vertex stages")
        } else if !self.is_mesh() && !has(vk::ShaderStageFlags::VERTEX) {
            Some("has neither a vertex nor a mesh stage")
        } else if tess != (self.patch_control_points > 0) {
            Some("needs tessellation stages and patch control points together")
        } else {
            None
        };
        match problem {
            Some(p) => Err(VkError::Usage(format!(
                "graphics pipeline `{}` {p}",
                self.name
            ))),
            None => Ok(()),
        }
    }
}

/// A compute or graphics pipeline, destroyed on drop.
pub struct Pipeline {
    core: Arc<Core>,
    handle: vk::Pipeline,
    bind_point: vk::PipelineBindPoint,
    /// The layout it was made with (owned by the method beside it), for
    /// binding sets through a [`crate::vk::Pass`].
    layout: vk::PipelineLayout,
    /// Every (set, binding) its shaders use, and whether any may write it.
    uses: BTreeMap<(u32, u32), bool>,
    /// Bound at least once (see [`Pipeline::bind`]).
    bound: AtomicBool,
}

impl Pipeline {
    fn from_handle(
        ctx: &Context,
        handle: vk::Pipeline,
        bind_point: vk::PipelineBindPoint,
        name: &str,
        layout: vk::PipelineLayout,
        modules: &[&ShaderModule],
    ) -> Self {
        ctx.set_name(handle, name);
        let mut uses = BTreeMap::new();
        for r in modules.iter().map(|m| m.reflection()) {
            for key in r.bindings.keys() {
                *uses.entry(*key).or_insert(false) |= r.written.contains(key);
            }
        }
        Self {
            core: ctx.core.clone(),
            handle,
            bind_point,
            layout,
            uses,
            bound: AtomicBool::new(false),
        }
    }

    /// The (set, binding)s its shaders use, each with whether they may write
    /// it (from the SPIR-V: a storage resource not declared `readonly`).
    pub fn uses(&self) -> &BTreeMap<(u32, u32), bool> {
        &self.uses
    }

    /// The layout it was made with.
    pub fn layout(&self) -> vk::PipelineLayout {
        self.layout
    }

    /// A compute pipeline from `shader`'s `main` with `layout`.
    pub fn compute<P: bytemuck::Pod>(
        ctx: &Context,
        name: &str,
        layout: &PipelineLayout<P>,
        shader: &ShaderModule,
        specialization: &[(u32, u32)],
    ) -> VkResult<Self> {
        layout.check_shader(shader.name(), shader.reflection())?;
        let spec = Specialization::new(specialization);
        let spec_info = spec.info();
        let stage = stage_info(
            vk::ShaderStageFlags::COMPUTE,
            shader,
            &spec_info,
            !spec.is_empty(),
        );
        let info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage)
            .layout(layout.handle())];
        let handle = unsafe {
            ctx.device()
                .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
        }
        .map_err(|(_, result)| VkError::Call {
            context: format!("vkCreateComputePipelines({name})"),
            result,
        })?[0];
        Ok(Self::from_handle(
            ctx,
            handle,
            vk::PipelineBindPoint::COMPUTE,
            name,
            layout.handle(),
            &[shader],
        ))
    }

    /// A graphics pipeline as `desc` describes it, with `layout`.
    pub fn graphics<P: bytemuck::Pod>(
        ctx: &Context,
        layout: &PipelineLayout<P>,
        desc: &GraphicsDesc<'_>,
    ) -> VkResult<Self> {
        desc.check()?;
        for (_, module) in &desc.stages {
            layout.check_shader(module.name(), module.reflection())?;
        }
        let spec = Specialization::new(&desc.specialization);
        let spec_info = spec.info();
        let stages: Vec<_> = desc
            .stages
            .iter()
            .map(|(stage, module)| stage_info(*stage, module, &spec_info, !spec.is_empty()))
            .collect();
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default().topology(desc.topology);
        let tessellation = vk::PipelineTessellationStateCreateInfo::default()
            .patch_control_points(desc.patch_control_points);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(desc.polygon_mode)
            .cull_mode(desc.cull_mode)
            .front_face(desc.front_face)
            .line_width(1.0);
        let multisample =
            vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth.test)
            .depth_write_enable(desc.depth.write)
            .depth_compare_op(desc.depth.compare);
        let attachments: Vec<_> = desc
            .color_formats
            .iter()
            .map(|_| {
                vk::PipelineColorBlendAttachmentState::default()
                    .blend_enable(false)
                    .color_write_mask(vk::ColorComponentFlags::RGBA)
            })
            .collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&desc.color_formats)
            .depth_attachment_format(desc.depth_format);
        let mut info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.handle())
            .push_next(&mut rendering);
        // Mesh pipelines leave vertex input and input assembly null.
        if !desc.is_mesh() {
            info = info
                .vertex_input_state(&vertex_input)
                .input_assembly_state(&assembly);
        }
        if desc.patch_control_points > 0 {
            info = info.tessellation_state(&tessellation);
        }
        let handle = unsafe {
            ctx.device()
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        }
        .map_err(|(_, result)| VkError::Call {
            context: format!("vkCreateGraphicsPipelines({})", desc.name),
            result,
        })?[0];
        let modules: Vec<&ShaderModule> = desc.stages.iter().map(|(_, m)| *m).collect();
        Ok(Self::from_handle(
            ctx,
            handle,
            vk::PipelineBindPoint::GRAPHICS,
            desc.name,
            layout.handle(),
            &modules,
        ))
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::Pipeline {
        self.handle
    }

    /// Compute or graphics.
    pub fn bind_point(&self) -> vk::PipelineBindPoint {
        self.bind_point
    }

    /// Records `vkCmdBindPipeline` at the pipeline's bind point. The first
    /// bind is counted: the submission that runs it may wait for the
    /// driver's compile ([`crate::vk::Context::take_compile_allowance`]).
    pub fn bind(&self, cmd: vk::CommandBuffer) {
        if !self.bound.swap(true, Ordering::SeqCst) {
            self.core.first_uses.fetch_add(1, Ordering::SeqCst);
        }
        unsafe {
            self.core
                .device
                .cmd_bind_pipeline(cmd, self.bind_point, self.handle)
        };
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_pipeline(self.handle, None) };
    }
}
