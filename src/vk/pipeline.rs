//! Descriptor set layouts, pipeline layouts, descriptor pools and compute
//! pipelines. The layout helpers are shared with the graphics and mesh
//! pipelines.

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use super::memory::Buffer;
use super::shader::ShaderModule;
use ash::vk;
use std::sync::atomic::Ordering;
use std::sync::Arc;

/// A descriptor set layout whose binding `i` is `types[i]` (one descriptor each).
pub struct SetLayout {
    core: Arc<Core>,
    handle: vk::DescriptorSetLayout,
    types: Vec<vk::DescriptorType>,
}

impl SetLayout {
    /// Creates the layout, visible to `stages`.
    pub fn new(
        ctx: &Context,
        name: &str,
        types: &[vk::DescriptorType],
        stages: vk::ShaderStageFlags,
    ) -> VkResult<Self> {
        let bindings: Vec<_> = types
            .iter()
            .enumerate()
            .map(|(i, &ty)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(ty)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        let handle = unsafe { ctx.device().create_descriptor_set_layout(&info, None) }
            .ctx(&format!("vkCreateDescriptorSetLayout({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
            types: types.to_vec(),
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::DescriptorSetLayout {
        self.handle
    }

    /// Descriptor type per binding.
    pub fn types(&self) -> &[vk::DescriptorType] {
        &self.types
    }
}

impl Drop for SetLayout {
    fn drop(&mut self) {
        unsafe {
            self.core
                .device
                .destroy_descriptor_set_layout(self.handle, None)
        };
    }
}

/// A pipeline layout: set layouts plus one push-constant range at offset 0.
pub struct PipelineLayout {
    core: Arc<Core>,
    handle: vk::PipelineLayout,
    push_size: u32,
    push_stages: vk::ShaderStageFlags,
}

impl PipelineLayout {
    /// Creates the layout; `push_size` 0 means no push constants.
    pub fn new(
        ctx: &Context,
        name: &str,
        sets: &[&SetLayout],
        push_size: u32,
        push_stages: vk::ShaderStageFlags,
    ) -> VkResult<Self> {
        let limit = ctx.info().limits.max_push_constants_size;
        if push_size % 4 != 0 || push_size > limit {
            return Err(VkError::Usage(format!(
                "push constants of `{name}` are {push_size} bytes; they must be a multiple of 4 \
                 and at most {limit} on this device"
            )));
        }
        let set_handles: Vec<_> = sets.iter().map(|s| s.handle).collect();
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(push_stages)
            .offset(0)
            .size(push_size)];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_handles)
            .push_constant_ranges(if push_size > 0 { &ranges } else { &[] });
        let handle = unsafe { ctx.device().create_pipeline_layout(&info, None) }
            .ctx(&format!("vkCreatePipelineLayout({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
            push_size,
            push_stages,
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::PipelineLayout {
        self.handle
    }

    /// Records push constants; `data` must be exactly the declared size.
    pub fn push(&self, cmd: vk::CommandBuffer, data: &[u8]) -> VkResult<()> {
        if data.len() != self.push_size as usize {
            return Err(VkError::Usage(format!(
                "pushing {} bytes into a {}-byte push-constant range",
                data.len(),
                self.push_size
            )));
        }
        if !data.is_empty() {
            unsafe {
                self.core
                    .device
                    .cmd_push_constants(cmd, self.handle, self.push_stages, 0, data)
            };
        }
        Ok(())
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        unsafe { self.core.device.destroy_pipeline_layout(self.handle, None) };
    }
}

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
}

/// What a compute pipeline binds: set 0 holds `storage_buffers` storage
/// buffers at bindings 0.., then (optionally) one uniform buffer.
#[derive(Debug, Clone, Copy)]
pub struct ComputePipelineDesc<'a> {
    /// Debug name.
    pub name: &'a str,
    /// Number of storage buffers (bindings 0..n).
    pub storage_buffers: u32,
    /// A uniform buffer at binding `storage_buffers`.
    pub uniform_buffer: bool,
    /// Push-constant bytes (multiple of 4; 0 for none).
    pub push_constant_size: u32,
    /// (constant_id, value) specialization constants.
    pub specialization: &'a [(u32, u32)],
}

impl ComputePipelineDesc<'_> {
    /// Descriptor types of set 0 in binding order.
    pub fn descriptor_types(&self) -> Vec<vk::DescriptorType> {
        let mut types = vec![vk::DescriptorType::STORAGE_BUFFER; self.storage_buffers as usize];
        if self.uniform_buffer {
            types.push(vk::DescriptorType::UNIFORM_BUFFER);
        }
        types
    }
}

/// A compute pipeline with its own set-0 layout and pipeline layout.
pub struct ComputePipeline {
    core: Arc<Core>,
    handle: vk::Pipeline,
    // Dropped after the pipeline (field order), which is what Vulkan wants.
    layout: PipelineLayout,
    set_layout: SetLayout,
}

impl ComputePipeline {
    /// Creates the pipeline from `shader`'s `main`.
    pub fn new(
        ctx: &Context,
        shader: &ShaderModule,
        desc: &ComputePipelineDesc<'_>,
    ) -> VkResult<Self> {
        let stage = vk::ShaderStageFlags::COMPUTE;
        let set_layout = SetLayout::new(
            ctx,
            &format!("{} set 0", desc.name),
            &desc.descriptor_types(),
            stage,
        )?;
        let layout = PipelineLayout::new(
            ctx,
            &format!("{} layout", desc.name),
            &[&set_layout],
            desc.push_constant_size,
            stage,
        )?;
        let spec = Specialization::new(desc.specialization);
        let spec_info = spec.info();
        let mut stage_info = vk::PipelineShaderStageCreateInfo::default()
            .stage(stage)
            .module(shader.handle())
            .name(c"main");
        if !desc.specialization.is_empty() {
            stage_info = stage_info.specialization_info(&spec_info);
        }
        let info = [vk::ComputePipelineCreateInfo::default()
            .stage(stage_info)
            .layout(layout.handle())];
        let handle = unsafe {
            ctx.device()
                .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
        }
        .map_err(|(_, result)| VkError::Call {
            context: format!("vkCreateComputePipelines({})", desc.name),
            result,
        })?[0];
        ctx.set_name(handle, desc.name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
            layout,
            set_layout,
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::Pipeline {
        self.handle
    }

    /// The pipeline layout.
    pub fn layout(&self) -> &PipelineLayout {
        &self.layout
    }

    /// The layout of descriptor set 0.
    pub fn set_layout(&self) -> &SetLayout {
        &self.set_layout
    }

    /// Binds the pipeline and `set`, pushes `push` and dispatches `groups`.
    pub fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        set: vk::DescriptorSet,
        push: &[u8],
        groups: [u32; 3],
    ) -> VkResult<()> {
        let device = &self.core.device;
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.handle);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.handle(),
                0,
                &[set],
                &[],
            );
        }
        self.layout.push(cmd, push)?;
        unsafe { device.cmd_dispatch(cmd, groups[0], groups[1], groups[2]) };
        Ok(())
    }
}

impl Drop for ComputePipeline {
    fn drop(&mut self) {
        if self.core.hung.load(Ordering::SeqCst) {
            return;
        }
        unsafe { self.core.device.destroy_pipeline(self.handle, None) };
    }
}

/// A descriptor pool; its sets are freed with it.
pub struct DescriptorPool {
    core: Arc<Core>,
    handle: vk::DescriptorPool,
}

impl DescriptorPool {
    /// A pool for `max_sets` sets drawing on `sizes` (type, descriptor count).
    pub fn new(
        ctx: &Context,
        name: &str,
        max_sets: u32,
        sizes: &[(vk::DescriptorType, u32)],
    ) -> VkResult<Self> {
        let sizes: Vec<_> = sizes
            .iter()
            .filter(|(_, n)| *n > 0)
            .map(|&(ty, n)| vk::DescriptorPoolSize::default().ty(ty).descriptor_count(n))
            .collect();
        let info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(max_sets)
            .pool_sizes(&sizes);
        let handle = unsafe { ctx.device().create_descriptor_pool(&info, None) }
            .ctx(&format!("vkCreateDescriptorPool({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
        })
    }

    /// A pool sized for `count` sets of `layout`.
    pub fn for_layout(ctx: &Context, name: &str, layout: &SetLayout, count: u32) -> VkResult<Self> {
        let mut sizes: Vec<(vk::DescriptorType, u32)> = Vec::new();
        for &ty in layout.types() {
            match sizes.iter_mut().find(|(t, _)| *t == ty) {
                Some((_, n)) => *n += count,
                None => sizes.push((ty, count)),
            }
        }
        Self::new(ctx, name, count, &sizes)
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::DescriptorPool {
        self.handle
    }

    /// Allocates one set of `layout`.
    pub fn allocate(&self, layout: &SetLayout) -> VkResult<vk::DescriptorSet> {
        let layouts = [layout.handle()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(self.handle)
            .set_layouts(&layouts);
        let sets = unsafe { self.core.device.allocate_descriptor_sets(&info) }
            .ctx("vkAllocateDescriptorSets")?;
        Ok(sets[0])
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        if self.core.hung.load(Ordering::SeqCst) {
            return;
        }
        unsafe { self.core.device.destroy_descriptor_pool(self.handle, None) };
    }
}

/// Points binding `i` of `set` at the whole of `buffers[i]`, with the
/// descriptor types `layout` declares.
pub fn write_buffers(
    ctx: &Context,
    set: vk::DescriptorSet,
    layout: &SetLayout,
    buffers: &[&Buffer],
) -> VkResult<()> {
    if buffers.len() != layout.types().len() {
        return Err(VkError::Usage(format!(
            "the set layout has {} bindings but {} buffers were given",
            layout.types().len(),
            buffers.len()
        )));
    }
    // One info per write, built first: each write points into this vector.
    let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
        .iter()
        .map(|b| {
            [vk::DescriptorBufferInfo::default()
                .buffer(b.handle())
                .offset(0)
                .range(vk::WHOLE_SIZE)]
        })
        .collect();
    let writes: Vec<_> = infos
        .iter()
        .zip(layout.types())
        .enumerate()
        .map(|(i, (info, &ty))| {
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(i as u32)
                .descriptor_type(ty)
                .buffer_info(info)
        })
        .collect();
    unsafe { ctx.device().update_descriptor_sets(&writes, &[]) };
    Ok(())
}

/// A pipeline (compute or graphics) built against a layout owned elsewhere,
/// e.g. the one scene layout every pass shares. Destroyed on drop.
pub struct Pipeline {
    core: Arc<Core>,
    handle: vk::Pipeline,
    bind_point: vk::PipelineBindPoint,
}

impl Pipeline {
    /// Takes ownership of a pipeline created by the caller.
    pub fn from_handle(
        ctx: &Context,
        handle: vk::Pipeline,
        bind_point: vk::PipelineBindPoint,
        name: &str,
    ) -> Self {
        ctx.set_name(handle, name);
        Self {
            core: ctx.core.clone(),
            handle,
            bind_point,
        }
    }

    /// A compute pipeline from `shader`'s `main` with `layout`.
    pub fn compute(
        ctx: &Context,
        name: &str,
        layout: &PipelineLayout,
        shader: &ShaderModule,
        specialization: &[(u32, u32)],
    ) -> VkResult<Self> {
        let spec = Specialization::new(specialization);
        let spec_info = spec.info();
        let mut stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(shader.handle())
            .name(c"main");
        if !specialization.is_empty() {
            stage = stage.specialization_info(&spec_info);
        }
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
        ))
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::Pipeline {
        self.handle
    }

    /// Records `vkCmdBindPipeline` at the pipeline's bind point.
    pub fn bind(&self, cmd: vk::CommandBuffer) {
        unsafe {
            self.core
                .device
                .cmd_bind_pipeline(cmd, self.bind_point, self.handle)
        };
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        if self.core.hung.load(Ordering::SeqCst) {
            return;
        }
        unsafe { self.core.device.destroy_pipeline(self.handle, None) };
    }
}
