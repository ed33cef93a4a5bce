//! Descriptor set layouts, pipeline layouts and descriptor sets.
//!
//! Every pass binds a few small sets (the scene set every pass shares, then
//! the buffers of its own pass family) and pushes its own constant block, so
//! a new pass adds a set or a push block instead of growing one union of
//! everything.

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use super::memory::Buffer;
use ash::vk;
use std::sync::Arc;

/// A descriptor set layout whose binding `i` is `types[i]` (one descriptor
/// each), all visible to the same stages.
pub struct SetLayout {
    core: Arc<Core>,
    handle: vk::DescriptorSetLayout,
    types: Vec<vk::DescriptorType>,
    name: String,
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
            name: name.to_owned(),
        })
    }

    /// A layout of `count` storage buffers (bindings 0..count).
    pub fn storage(
        ctx: &Context,
        name: &str,
        count: usize,
        stages: vk::ShaderStageFlags,
    ) -> VkResult<Self> {
        Self::new(
            ctx,
            name,
            &vec![vk::DescriptorType::STORAGE_BUFFER; count],
            stages,
        )
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

    /// Bytes of the push-constant range.
    pub fn push_size(&self) -> u32 {
        self.push_size
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

    /// Records a typed push-constant block.
    pub fn push_block<T: bytemuck::Pod>(&self, cmd: vk::CommandBuffer, block: &T) -> VkResult<()> {
        self.push(cmd, bytemuck::bytes_of(block))
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        unsafe { self.core.device.destroy_pipeline_layout(self.handle, None) };
    }
}

/// A buffer bound to one descriptor: the whole buffer, or for a dynamic
/// uniform buffer the `range` bytes one dynamic offset selects.
#[derive(Clone, Copy)]
pub struct BufferBinding<'a> {
    /// The buffer.
    pub buffer: &'a Buffer,
    /// Bytes visible through the descriptor (`vk::WHOLE_SIZE` for all).
    pub range: u64,
}

impl<'a> From<&'a Buffer> for BufferBinding<'a> {
    fn from(buffer: &'a Buffer) -> Self {
        Self {
            buffer,
            range: vk::WHOLE_SIZE,
        }
    }
}

/// What one descriptor points at: a buffer, or an image read through a
/// sampler (a `COMBINED_IMAGE_SAMPLER` binding, e.g. a depth image).
#[derive(Clone, Copy)]
pub enum Binding<'a> {
    /// A storage or uniform buffer.
    Buffer(BufferBinding<'a>),
    /// An image view in `layout`, read through `sampler`.
    Image {
        /// The view.
        view: vk::ImageView,
        /// Its layout when the set is used.
        layout: vk::ImageLayout,
        /// The sampler.
        sampler: &'a Sampler,
    },
}

impl<'a> From<BufferBinding<'a>> for Binding<'a> {
    fn from(b: BufferBinding<'a>) -> Self {
        Binding::Buffer(b)
    }
}

impl<'a> From<&'a Buffer> for Binding<'a> {
    fn from(b: &'a Buffer) -> Self {
        Binding::Buffer(b.into())
    }
}

/// A nearest-texel, clamp-to-edge sampler (shaders read it with
/// `texelFetch`, so filtering never applies).
pub struct Sampler {
    core: Arc<Core>,
    handle: vk::Sampler,
}

impl Sampler {
    /// Creates the sampler.
    pub fn nearest(ctx: &Context, name: &str) -> VkResult<Self> {
        let clamp = vk::SamplerAddressMode::CLAMP_TO_EDGE;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(clamp)
            .address_mode_v(clamp)
            .address_mode_w(clamp)
            .max_lod(0.0);
        let handle = unsafe { ctx.device().create_sampler(&info, None) }
            .ctx(&format!("vkCreateSampler({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::Sampler {
        self.handle
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_sampler(self.handle, None) };
    }
}

/// One descriptor set with the pool it came from; freed with it. Each set
/// has its own small pool: sets are few and long-lived here.
pub struct DescriptorSet {
    core: Arc<Core>,
    pool: vk::DescriptorPool,
    handle: vk::DescriptorSet,
}

impl DescriptorSet {
    /// Allocates a set of `layout` and points binding `i` at `buffers[i]`.
    pub fn new(
        ctx: &Context,
        name: &str,
        layout: &SetLayout,
        buffers: &[BufferBinding<'_>],
    ) -> VkResult<Self> {
        let bindings: Vec<Binding<'_>> = buffers.iter().map(|&b| b.into()).collect();
        Self::with_bindings(ctx, name, layout, &bindings)
    }

    /// Allocates a set of `layout` and points binding `i` at
    /// `bindings[i]` (buffers and sampled images).
    pub fn with_bindings(
        ctx: &Context,
        name: &str,
        layout: &SetLayout,
        buffers: &[Binding<'_>],
    ) -> VkResult<Self> {
        if buffers.len() != layout.types.len() {
            return Err(VkError::Usage(format!(
                "the set layout `{}` has {} bindings but {} buffers were given for `{name}`",
                layout.name,
                layout.types.len(),
                buffers.len()
            )));
        }
        let pool = create_pool(ctx, name, &layout.types)?;
        let layouts = [layout.handle()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        let allocated = unsafe { ctx.device().allocate_descriptor_sets(&info) }
            .ctx(&format!("vkAllocateDescriptorSets({name})"));
        let handle = match allocated {
            Ok(sets) => sets[0],
            Err(e) => {
                unsafe { ctx.device().destroy_descriptor_pool(pool, None) };
                return Err(e);
            }
        };
        ctx.set_name(handle, name);
        write(ctx, handle, &layout.types, buffers);
        Ok(Self {
            core: ctx.core.clone(),
            pool,
            handle,
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::DescriptorSet {
        self.handle
    }

    /// Records binding this set as set `index` of `layout`, with one dynamic
    /// offset per dynamic descriptor.
    pub fn bind(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout,
        index: u32,
        dynamic_offsets: &[u32],
    ) {
        unsafe {
            ctx.device().cmd_bind_descriptor_sets(
                cmd,
                bind_point,
                layout.handle(),
                index,
                &[self.handle],
                dynamic_offsets,
            )
        };
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_descriptor_pool(self.pool, None) };
    }
}

/// A pool with room for exactly one set of these descriptor types.
fn create_pool(
    ctx: &Context,
    name: &str,
    types: &[vk::DescriptorType],
) -> VkResult<vk::DescriptorPool> {
    let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
    for &ty in types {
        match sizes.iter_mut().find(|s| s.ty == ty) {
            Some(s) => s.descriptor_count += 1,
            None => sizes.push(vk::DescriptorPoolSize::default().ty(ty).descriptor_count(1)),
        }
    }
    let info = vk::DescriptorPoolCreateInfo::default()
        .max_sets(1)
        .pool_sizes(&sizes);
    let pool = unsafe { ctx.device().create_descriptor_pool(&info, None) }
        .ctx(&format!("vkCreateDescriptorPool({name})"))?;
    ctx.set_name(pool, name);
    Ok(pool)
}

/// Points binding `i` of `set` at `bindings[i]` with the layout's types.
fn write(
    ctx: &Context,
    set: vk::DescriptorSet,
    types: &[vk::DescriptorType],
    bindings: &[Binding<'_>],
) {
    // One info per write, built first: each write points into these vectors.
    let buffers: Vec<[vk::DescriptorBufferInfo; 1]> = bindings
        .iter()
        .map(|b| match b {
            Binding::Buffer(b) => [vk::DescriptorBufferInfo::default()
                .buffer(b.buffer.handle())
                .offset(0)
                .range(b.range)],
            Binding::Image { .. } => [vk::DescriptorBufferInfo::default()],
        })
        .collect();
    let images: Vec<[vk::DescriptorImageInfo; 1]> = bindings
        .iter()
        .map(|b| match b {
            Binding::Image {
                view,
                layout,
                sampler,
            } => [vk::DescriptorImageInfo::default()
                .image_view(*view)
                .image_layout(*layout)
                .sampler(sampler.handle())],
            Binding::Buffer(_) => [vk::DescriptorImageInfo::default()],
        })
        .collect();
    let writes: Vec<_> = bindings
        .iter()
        .zip(types)
        .enumerate()
        .map(|(i, (b, &ty))| {
            let w = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(i as u32)
                .descriptor_type(ty);
            match b {
                Binding::Buffer(_) => w.buffer_info(&buffers[i]),
                Binding::Image { .. } => w.image_info(&images[i]),
            }
        })
        .collect();
    unsafe { ctx.device().update_descriptor_sets(&writes, &[]) };
}
