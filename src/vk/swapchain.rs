//! The window's swapchain: images to present, made for the surface's
//! current size and remade when the window changes (`OUT_OF_DATE`,
//! `SUBOPTIMAL`, a resize). Images are written by transfers (a blit of the
//! renderer's target) and by the overlay's colour attachment, so a UNORM
//! format is preferred: the renderer's pixels are display values already.

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use ash::vk;
use std::sync::Arc;

/// How frames are paced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PresentPacing {
    /// Wait for vertical blank (FIFO, always available).
    Vsync,
    /// As fast as possible (MAILBOX or IMMEDIATE where offered, else FIFO).
    Unlimited,
}

/// One swapchain and the views of its images.
pub struct Swapchain {
    core: Arc<Core>,
    loader: ash::khr::swapchain::Device,
    handle: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    views: Vec<vk::ImageView>,
    /// Signalled when image i's commands are done, waited on by its present.
    render_done: Vec<vk::Semaphore>,
    format: vk::Format,
    extent: vk::Extent2D,
    mode: vk::PresentModeKHR,
}

/// What acquiring an image gave.
pub enum Acquired {
    /// Image `index` is ours once `ready` (the semaphore given) signals.
    Image {
        /// Index into the swapchain's images.
        index: u32,
        /// The swapchain works but no longer matches the surface exactly.
        suboptimal: bool,
    },
    /// The swapchain no longer fits the surface: make a new one.
    OutOfDate,
}

fn choose_format(formats: &[vk::SurfaceFormatKHR]) -> Option<vk::SurfaceFormatKHR> {
    let wanted = [vk::Format::B8G8R8A8_UNORM, vk::Format::R8G8B8A8_UNORM];
    wanted
        .iter()
        .find_map(|f| formats.iter().find(|s| s.format == *f).copied())
        .or_else(|| formats.first().copied())
}

fn choose_mode(modes: &[vk::PresentModeKHR], pacing: PresentPacing) -> vk::PresentModeKHR {
    let wanted: &[vk::PresentModeKHR] = match pacing {
        PresentPacing::Vsync => &[],
        PresentPacing::Unlimited => &[vk::PresentModeKHR::MAILBOX, vk::PresentModeKHR::IMMEDIATE],
    };
    wanted
        .iter()
        .copied()
        .find(|m| modes.contains(m))
        .unwrap_or(vk::PresentModeKHR::FIFO)
}

impl Swapchain {
    /// A swapchain for the context's window surface at `size` (clamped to
    /// what the surface allows), replacing `old` if given. `None` when the
    /// surface has no area (a minimised window): try again later.
    pub fn new(
        ctx: &Context,
        size: (u32, u32),
        pacing: PresentPacing,
        old: Option<&Swapchain>,
    ) -> VkResult<Option<Self>> {
        let (surface_loader, surface) = ctx.surface().ok_or_else(|| {
            VkError::Usage("a swapchain needs a context made with a window".into())
        })?;
        let loader = ctx
            .swapchain_loader()
            .ok_or_else(|| VkError::Usage("VK_KHR_swapchain is not enabled".into()))?
            .clone();
        let pd = ctx.physical_device();
        let caps = unsafe { surface_loader.get_physical_device_surface_capabilities(pd, surface) }
            .ctx("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .0
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: size
                    .1
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        if extent.width == 0 || extent.height == 0 {
            return Ok(None);
        }
        let formats = unsafe { surface_loader.get_physical_device_surface_formats(pd, surface) }
            .ctx("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        let format = choose_format(&formats)
            .ok_or_else(|| VkError::Usage("the window surface offers no image format".into()))?;
        let modes =
            unsafe { surface_loader.get_physical_device_surface_present_modes(pd, surface) }
                .ctx("vkGetPhysicalDeviceSurfacePresentModesKHR")?;
        let mode = choose_mode(&modes, pacing);
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_DST;
        if !caps.supported_usage_flags.contains(usage) {
            return Err(VkError::FeatureMissing {
                device: ctx.info().name.clone(),
                feature: "swapchain images that are transfer destinations".into(),
                hint: String::new(),
            });
        }
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(mode)
            .clipped(true)
            .old_swapchain(old.map_or(vk::SwapchainKHR::null(), |o| o.handle));
        let handle = unsafe { loader.create_swapchain(&info, None) }.ctx("vkCreateSwapchainKHR")?;
        let mut chain = Self {
            core: ctx.core.clone(),
            loader,
            handle,
            images: Vec::new(),
            views: Vec::new(),
            render_done: Vec::new(),
            format: format.format,
            extent,
            mode,
        };
        chain.images =
            unsafe { chain.loader.get_swapchain_images(handle) }.ctx("vkGetSwapchainImagesKHR")?;
        for (i, &image) in chain.images.clone().iter().enumerate() {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(chain.format)
                .subresource_range(color_range());
            let view = unsafe { ctx.device().create_image_view(&view_info, None) }
                .ctx("vkCreateImageView(swapchain)")?;
            chain.views.push(view);
            let sem = unsafe {
                ctx.device()
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            }
            .ctx("vkCreateSemaphore(present)")?;
            ctx.set_name(sem, &format!("swapchain image {i} rendered"));
            chain.render_done.push(sem);
        }
        Ok(Some(chain))
    }

    /// Image size.
    pub fn extent(&self) -> vk::Extent2D {
        self.extent
    }

    /// Image format.
    pub fn format(&self) -> vk::Format {
        self.format
    }

    /// The present mode in use.
    pub fn present_mode(&self) -> vk::PresentModeKHR {
        self.mode
    }

    /// Image `i`.
    pub fn image(&self, i: u32) -> vk::Image {
        self.images[i as usize]
    }

    /// The view of image `i`.
    pub fn view(&self, i: u32) -> vk::ImageView {
        self.views[i as usize]
    }

    /// The semaphore the commands writing image `i` signal.
    pub fn render_done(&self, i: u32) -> vk::Semaphore {
        self.render_done[i as usize]
    }

    /// Acquires the next image; `ready` is signalled when it may be written.
    pub fn acquire(
        &self,
        ready: vk::Semaphore,
        timeout: std::time::Duration,
    ) -> VkResult<Acquired> {
        let ns = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
        match unsafe {
            self.loader
                .acquire_next_image(self.handle, ns, ready, vk::Fence::null())
        } {
            Ok((index, suboptimal)) => Ok(Acquired::Image { index, suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(vk::Result::ERROR_DEVICE_LOST) => Err(VkError::DeviceLost {
                label: "acquiring a swapchain image".into(),
            }),
            Err(result) => Err(VkError::Call {
                context: "vkAcquireNextImageKHR".into(),
                result,
            }),
        }
    }

    /// Presents image `i` once its commands signalled [`Swapchain::render_done`];
    /// returns false when the swapchain should be remade.
    pub fn present(&self, ctx: &Context, i: u32) -> VkResult<bool> {
        let waits = [self.render_done(i)];
        let chains = [self.handle];
        let indices = [i];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&chains)
            .image_indices(&indices);
        let result = ctx.with_queue(|q| unsafe { self.loader.queue_present(q, &info) });
        match result {
            Ok(false) => Ok(true),
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(false),
            Err(vk::Result::ERROR_DEVICE_LOST) => Err(VkError::DeviceLost {
                label: "presenting".into(),
            }),
            Err(result) => Err(VkError::Call {
                context: "vkQueuePresentKHR".into(),
                result,
            }),
        }
    }
}

/// The whole colour subresource of a one-mip, one-layer image.
pub fn color_range() -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(vk::ImageAspectFlags::COLOR)
        .level_count(1)
        .layer_count(1)
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        if self.core.hung.load(std::sync::atomic::Ordering::SeqCst) {
            return;
        }
        unsafe {
            // Presents may still wait on the semaphores.
            let _ = self.core.device.device_wait_idle();
            for &s in &self.render_done {
                self.core.device.destroy_semaphore(s, None);
            }
            for &v in &self.views {
                self.core.device.destroy_image_view(v, None);
            }
            self.loader.destroy_swapchain(self.handle, None);
        }
    }
}
