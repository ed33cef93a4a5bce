//! Buffers and images backed by gpu-allocator, freed on drop.
//!
//! Each resource holds the shared device core, so it can free itself without
//! a context and can never outlive the device. Dropping a resource the GPU
//! still uses is the caller's bug, exactly as in Vulkan; one-shot helpers
//! wait before returning, so resources used only through them are safe.

use super::barrier::{buffer_barrier_info, image_barrier_info, Access};
use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// A buffer and its memory.
pub struct Buffer {
    core: Arc<Core>,
    handle: vk::Buffer,
    allocation: Option<Allocation>,
    size: u64,
    location: MemoryLocation,
    name: String,
}

impl Buffer {
    /// Creates a buffer of `size` bytes.
    ///
    /// TRANSFER_SRC and TRANSFER_DST are always added to `usage` so every
    /// buffer can be uploaded to and read back (tests and debugging rely on it).
    pub fn new(
        ctx: &Context,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> VkResult<Self> {
        if size == 0 {
            return Err(VkError::Usage(format!("buffer `{name}` has size 0")));
        }
        let core = ctx.core.clone();
        let usage = usage | vk::BufferUsageFlags::TRANSFER_SRC | vk::BufferUsageFlags::TRANSFER_DST;
        let info = vk::BufferCreateInfo::default()
            .size(size)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        let handle = unsafe { core.device.create_buffer(&info, None) }
            .ctx(&format!("vkCreateBuffer({name})"))?;
        let requirements = unsafe { core.device.get_buffer_memory_requirements(handle) };
        let allocated = core.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        });
        let allocation = match allocated {
            Ok(a) => a,
            Err(cause) => {
                unsafe { core.device.destroy_buffer(handle, None) };
                return Err(VkError::Allocation {
                    name: name.to_owned(),
                    cause,
                });
            }
        };
        // Built before binding so a bind failure drops (and frees) it.
        let buffer = Self {
            core,
            handle,
            allocation: Some(allocation),
            size,
            location,
            name: name.to_owned(),
        };
        let (memory, offset) = buffer.memory();
        unsafe {
            buffer
                .core
                .device
                .bind_buffer_memory(handle, memory, offset)
        }
        .ctx(&format!("vkBindBufferMemory({name})"))?;
        buffer.core.set_name(handle, name);
        Ok(buffer)
    }

    /// Creates a buffer holding `data` (uploaded as [`Buffer::write`] does).
    pub fn with_data<T: bytemuck::Pod>(
        ctx: &Context,
        name: &str,
        data: &[T],
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> VkResult<Self> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let mut buffer = Self::new(ctx, name, bytes.len() as u64, usage, location)?;
        buffer.write(ctx, 0, data)?;
        Ok(buffer)
    }

    fn memory(&self) -> (vk::DeviceMemory, u64) {
        let a = self
            .allocation
            .as_ref()
            .expect("allocation present until drop");
        (unsafe { a.memory() }, a.offset())
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::Buffer {
        self.handle
    }

    /// Size in bytes.
    pub fn size(&self) -> u64 {
        self.size
    }

    /// Where the memory lives.
    pub fn location(&self) -> MemoryLocation {
        self.location
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The persistently mapped bytes, if the memory is host visible. Reading
    /// them after GPU writes needs a [`super::barrier::host_read_barrier`]
    /// in the writing command buffer; [`Buffer::read_bytes`] does that itself.
    pub fn mapped(&self) -> Option<&[u8]> {
        let a = self.allocation.as_ref()?;
        a.mapped_slice().map(|s| &s[..self.size as usize])
    }

    /// Mutable mapped bytes (host-coherent: no flush needed).
    pub fn mapped_mut(&mut self) -> Option<&mut [u8]> {
        let size = self.size as usize;
        let a = self.allocation.as_mut()?;
        a.mapped_slice_mut().map(|s| &mut s[..size])
    }

    fn host_access(&self) -> bool {
        // GpuOnly memory may happen to be mappable (lavapipe, resizable BAR),
        // but it goes through staging anyway so the path real GPUs take is
        // the one that gets tested.
        self.location != MemoryLocation::GpuOnly
    }

    /// Writes `data` at byte `offset`: through the mapping for host-visible
    /// locations, through a staging buffer and a copy for `GpuOnly`.
    pub fn write<T: bytemuck::Pod>(
        &mut self,
        ctx: &Context,
        offset: u64,
        data: &[T],
    ) -> VkResult<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let fits = offset
            .checked_add(bytes.len() as u64)
            .is_some_and(|end| end <= self.size);
        if !fits {
            return Err(VkError::Usage(format!(
                "writing {} bytes at {offset} overflows buffer `{}` of {} bytes",
                bytes.len(),
                self.name,
                self.size
            )));
        }
        if bytes.is_empty() {
            return Ok(());
        }
        if self.host_access() {
            let name = self.name.clone();
            let map = self.mapped_mut().ok_or_else(|| {
                VkError::Usage(format!("buffer `{name}` is host-visible but not mapped"))
            })?;
            map[offset as usize..offset as usize + bytes.len()].copy_from_slice(bytes);
            return Ok(());
        }
        let staging = Buffer::with_data(
            ctx,
            &format!("{} (upload staging)", self.name),
            bytes,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        let (dst, len) = (self.handle, bytes.len() as u64);
        let label = format!("upload to `{}`", self.name);
        ctx.one_shot_keeping(&label, ctx.fence_timeout, vec![staging], |cmd, kept| {
            // Earlier submissions may still read or write the destination.
            buffer_barrier(ctx, cmd, self, Access::ALL, Access::TRANSFER_WRITE);
            let region = [vk::BufferCopy::default()
                .src_offset(0)
                .dst_offset(offset)
                .size(len)];
            unsafe {
                ctx.device()
                    .cmd_copy_buffer(cmd, kept[0].handle, dst, &region)
            };
            buffer_barrier(ctx, cmd, self, Access::TRANSFER_WRITE, Access::ALL);
            Ok(())
        })?;
        Ok(())
    }

    /// Reads the whole buffer back, waiting for all earlier GPU work.
    pub fn read_bytes(&self, ctx: &Context) -> VkResult<Vec<u8>> {
        let label = format!("read back `{}`", self.name);
        if self.host_access() {
            // A barrier in a later submission covers writes from earlier
            // ones; the fence then makes them visible to the host.
            ctx.one_shot_with(&label, ctx.fence_timeout, |cmd| {
                buffer_barrier(ctx, cmd, self, Access::ALL, Access::HOST_READ);
                Ok(())
            })?;
            let map = self.mapped().ok_or_else(|| {
                VkError::Usage(format!(
                    "buffer `{}` is host-visible but not mapped",
                    self.name
                ))
            })?;
            return Ok(map.to_vec());
        }
        let staging = Buffer::new(
            ctx,
            &format!("{} (readback staging)", self.name),
            self.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        // The staging buffer travels with the submission, so a timed-out
        // wait cannot free it under the GPU.
        let (_, kept) =
            ctx.one_shot_keeping(&label, ctx.fence_timeout, vec![staging], |cmd, kept| {
                let staging = &kept[0];
                buffer_barrier(ctx, cmd, self, Access::ALL, Access::TRANSFER_READ);
                let region = [vk::BufferCopy::default().size(self.size)];
                unsafe {
                    ctx.device()
                        .cmd_copy_buffer(cmd, self.handle, staging.handle, &region)
                };
                buffer_barrier(ctx, cmd, staging, Access::TRANSFER_WRITE, Access::HOST_READ);
                Ok(())
            })?;
        kept[0]
            .mapped()
            .map(<[u8]>::to_vec)
            .ok_or_else(|| VkError::Usage(String::from("readback staging buffer is not mapped")))
    }

    /// Reads the buffer back as `T`s (trailing bytes that do not fill a `T`
    /// are an error).
    pub fn read<T: bytemuck::Pod>(&self, ctx: &Context) -> VkResult<Vec<T>> {
        let bytes = self.read_bytes(ctx)?;
        if bytes.len() % std::mem::size_of::<T>().max(1) != 0 {
            return Err(VkError::Usage(format!(
                "buffer `{}` of {} bytes is not a whole number of {}-byte elements",
                self.name,
                bytes.len(),
                std::mem::size_of::<T>()
            )));
        }
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_buffer(self.handle, None) };
        if let Some(a) = self.allocation.take() {
            if let Err(e) = self.core.allocator().free(a) {
                log::error!("freeing buffer `{}` failed: {e}", self.name);
            }
        }
    }
}

/// What an [`Image`] should be.
#[derive(Debug, Clone, Copy)]
pub struct ImageDesc<'a> {
    /// Debug name.
    pub name: &'a str,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Pixel format; depth formats get a depth aspect.
    pub format: vk::Format,
    /// Usage (TRANSFER_SRC is added so every image can be read back).
    pub usage: vk::ImageUsageFlags,
    /// Samples per pixel (`TYPE_1` unless multisampled).
    pub samples: vk::SampleCountFlags,
}

/// A 2D single-mip image with a view, in device memory.
pub struct Image {
    core: Arc<Core>,
    handle: vk::Image,
    view: vk::ImageView,
    allocation: Option<Allocation>,
    format: vk::Format,
    extent: vk::Extent2D,
    aspect: vk::ImageAspectFlags,
    name: String,
}

/// The aspect(s) a format has.
pub fn format_aspect(format: vk::Format) -> vk::ImageAspectFlags {
    match format {
        vk::Format::D16_UNORM | vk::Format::D32_SFLOAT | vk::Format::X8_D24_UNORM_PACK32 => {
            vk::ImageAspectFlags::DEPTH
        }
        vk::Format::D16_UNORM_S8_UINT
        | vk::Format::D24_UNORM_S8_UINT
        | vk::Format::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        vk::Format::S8_UINT => vk::ImageAspectFlags::STENCIL,
        _ => vk::ImageAspectFlags::COLOR,
    }
}

/// Bytes per pixel for the formats [`Image::read_pixels`] supports.
pub fn format_texel_size(format: vk::Format) -> Option<u32> {
    Some(match format {
        vk::Format::R8_UNORM | vk::Format::R8_UINT => 1,
        vk::Format::R8G8B8A8_UNORM
        | vk::Format::R8G8B8A8_SRGB
        | vk::Format::B8G8R8A8_UNORM
        | vk::Format::B8G8R8A8_SRGB
        | vk::Format::R32_UINT
        | vk::Format::R32_SFLOAT
        | vk::Format::D32_SFLOAT => 4,
        vk::Format::R16G16B16A16_SFLOAT | vk::Format::R32G32_UINT | vk::Format::R32G32_SFLOAT => 8,
        vk::Format::R32G32B32A32_SFLOAT | vk::Format::R32G32B32A32_UINT => 16,
        _ => return None,
    })
}

impl Image {
    /// Creates the image, its memory and a 2D view.
    pub fn new(ctx: &Context, desc: &ImageDesc<'_>) -> VkResult<Self> {
        let name = desc.name;
        if desc.width == 0 || desc.height == 0 {
            return Err(VkError::Usage(format!("image `{name}` has zero extent")));
        }
        let core = ctx.core.clone();
        let aspect = format_aspect(desc.format);
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(1)
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage | vk::ImageUsageFlags::TRANSFER_SRC)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        let handle = unsafe { core.device.create_image(&info, None) }
            .ctx(&format!("vkCreateImage({name})"))?;
        let requirements = unsafe { core.device.get_image_memory_requirements(handle) };
        let allocated = core.allocator().allocate(&AllocationCreateDesc {
            name,
            requirements,
            location: MemoryLocation::GpuOnly,
            linear: false,
            // Render targets are big and long-lived: dedicated memory is
            // what drivers prefer for them.
            allocation_scheme: AllocationScheme::DedicatedImage(handle),
        });
        let allocation = match allocated {
            Ok(a) => a,
            Err(cause) => {
                unsafe { core.device.destroy_image(handle, None) };
                return Err(VkError::Allocation {
                    name: name.to_owned(),
                    cause,
                });
            }
        };
        let mut image = Self {
            core,
            handle,
            view: vk::ImageView::null(),
            allocation: Some(allocation),
            format: desc.format,
            extent: vk::Extent2D {
                width: desc.width,
                height: desc.height,
            },
            aspect,
            name: name.to_owned(),
        };
        let (memory, offset) = {
            let a = image.allocation.as_ref().expect("just allocated");
            (unsafe { a.memory() }, a.offset())
        };
        unsafe { image.core.device.bind_image_memory(handle, memory, offset) }
            .ctx(&format!("vkBindImageMemory({name})"))?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(handle)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(desc.format)
            .subresource_range(image.full_range());
        image.view = unsafe { image.core.device.create_image_view(&view_info, None) }
            .ctx(&format!("vkCreateImageView({name})"))?;
        image.core.set_name(handle, name);
        image.core.set_name(image.view, &format!("{name} (view)"));
        Ok(image)
    }

    /// The image handle.
    pub fn handle(&self) -> vk::Image {
        self.handle
    }

    /// The 2D view.
    pub fn view(&self) -> vk::ImageView {
        self.view
    }

    /// The format.
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// The size in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// The aspect(s) of the format.
    pub fn aspect(&self) -> vk::ImageAspectFlags {
        self.aspect
    }

    /// The debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The subresource range covering the whole image.
    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange::default()
            .aspect_mask(self.aspect)
            .base_mip_level(0)
            .level_count(1)
            .base_array_layer(0)
            .layer_count(1)
    }

    /// Copies the pixels out (tightly packed rows), leaving the image in
    /// `layout`, which must be the layout it is in now.
    pub fn read_pixels(&self, ctx: &Context, layout: vk::ImageLayout) -> VkResult<Vec<u8>> {
        let texel = format_texel_size(self.format).ok_or_else(|| {
            VkError::Usage(format!(
                "read_pixels does not support format {:?}",
                self.format
            ))
        })?;
        if layout == vk::ImageLayout::UNDEFINED {
            return Err(VkError::Usage(format!(
                "image `{}` is in UNDEFINED layout: its contents are not defined",
                self.name
            )));
        }
        // A single aspect is copied: depth for depth formats.
        let copy_aspect = if self.aspect.contains(vk::ImageAspectFlags::DEPTH) {
            vk::ImageAspectFlags::DEPTH
        } else {
            vk::ImageAspectFlags::COLOR
        };
        let size = u64::from(texel) * u64::from(self.extent.width) * u64::from(self.extent.height);
        let staging = Buffer::new(
            ctx,
            &format!("{} (pixel readback)", self.name),
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let src_layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        let (_, kept) = ctx.one_shot_keeping(
            &format!("read pixels of `{}`", self.name),
            ctx.fence_timeout,
            vec![staging],
            |cmd, kept| {
                let staging = &kept[0];
                image_barrier(
                    ctx,
                    cmd,
                    self,
                    layout,
                    src_layout,
                    Access::ALL,
                    Access::TRANSFER_READ,
                );
                let region = [vk::BufferImageCopy::default()
                    .image_subresource(
                        vk::ImageSubresourceLayers::default()
                            .aspect_mask(copy_aspect)
                            .mip_level(0)
                            .base_array_layer(0)
                            .layer_count(1),
                    )
                    .image_extent(vk::Extent3D {
                        width: self.extent.width,
                        height: self.extent.height,
                        depth: 1,
                    })];
                unsafe {
                    ctx.device().cmd_copy_image_to_buffer(
                        cmd,
                        self.handle,
                        src_layout,
                        staging.handle,
                        &region,
                    )
                };
                image_barrier(
                    ctx,
                    cmd,
                    self,
                    src_layout,
                    layout,
                    Access::TRANSFER_READ,
                    Access::ALL,
                );
                buffer_barrier(ctx, cmd, staging, Access::TRANSFER_WRITE, Access::HOST_READ);
                Ok(())
            },
        )?;
        kept[0]
            .mapped()
            .map(<[u8]>::to_vec)
            .ok_or_else(|| VkError::Usage(String::from("pixel staging buffer is not mapped")))
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe {
            if self.view != vk::ImageView::null() {
                self.core.device.destroy_image_view(self.view, None);
            }
            self.core.device.destroy_image(self.handle, None);
        }
        if let Some(a) = self.allocation.take() {
            if let Err(e) = self.core.allocator().free(a) {
                log::error!("freeing image `{}` failed: {e}", self.name);
            }
        }
    }
}

/// Records a barrier on a whole buffer.
pub fn buffer_barrier(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    buffer: &Buffer,
    src: Access,
    dst: Access,
) {
    let barrier = [buffer_barrier_info(buffer.handle(), src, dst)];
    let dep = vk::DependencyInfo::default().buffer_memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}

/// Records filling the whole of `buffer` with the word `value`, after every
/// earlier use of it and before every later one.
pub fn fill_buffer(ctx: &Context, cmd: vk::CommandBuffer, buffer: &Buffer, value: u32) {
    buffer_barrier(ctx, cmd, buffer, Access::ALL, Access::TRANSFER_WRITE);
    unsafe {
        ctx.device()
            .cmd_fill_buffer(cmd, buffer.handle(), 0, vk::WHOLE_SIZE, value)
    };
    buffer_barrier(ctx, cmd, buffer, Access::TRANSFER_WRITE, Access::ALL);
}

/// Records an image layout transition (whole image, all mips and layers).
pub fn image_barrier(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    image: &Image,
    old_layout: vk::ImageLayout,
    new_layout: vk::ImageLayout,
    src: Access,
    dst: Access,
) {
    let barrier = [image_barrier_info(src, dst, old_layout, new_layout)
        .image(image.handle())
        .subresource_range(image.full_range())];
    let dep = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    unsafe { ctx.device().cmd_pipeline_barrier2(cmd, &dep) };
}
