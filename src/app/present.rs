//! Getting a frame to the window: acquire a swapchain image, blit the
//! renderer's (resolved) target into it, draw the overlay on top, present.
//! Its own ring of frame slots, so the host prepares the next frame while
//! the GPU presents this one; an image-acquired semaphore per slot, a
//! rendering-done semaphore per swapchain image.

use std::time::Duration;

use ash::vk;

use crate::gpu::DrawTarget;
use crate::vk::{
    Access, Acquired, Context, FrameRing, Pass, PresentPacing, Recorder, Res, Swapchain, VkError,
    VkResult,
};

/// Frames the presenter keeps in flight.
pub const PRESENT_SLOTS: usize = 2;

/// What one presented frame needs recorded into it besides the blit.
pub trait Overlay {
    /// Records the overlay into `cmd` inside rendering on the swapchain
    /// image (colour attachment, loaded).
    fn record(
        &mut self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        extent: vk::Extent2D,
    ) -> VkResult<()>;
}

/// The presenter.
pub struct Presenter {
    // Dropped first: waits for the frames still presenting.
    ring: FrameRing,
    acquired: Vec<vk::Semaphore>,
    swapchain: Option<Swapchain>,
    pacing: PresentPacing,
    /// The swapchain must be remade before the next frame.
    stale: bool,
    ctx: std::sync::Arc<Context>,
}

impl Presenter {
    /// A presenter for the context's window.
    pub fn new(ctx: std::sync::Arc<Context>, pacing: PresentPacing) -> VkResult<Self> {
        let ring = FrameRing::new(&ctx, PRESENT_SLOTS)?;
        let mut acquired = Vec::new();
        for i in 0..PRESENT_SLOTS {
            let s = unsafe {
                ctx.device()
                    .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
            }
            .map_err(|result| VkError::Call {
                context: "vkCreateSemaphore(image acquired)".into(),
                result,
            })?;
            ctx.set_name(s, &format!("image acquired {i}"));
            acquired.push(s);
        }
        Ok(Self {
            ring,
            acquired,
            swapchain: None,
            pacing,
            stale: true,
            ctx,
        })
    }

    /// The swapchain's format (after the first [`Presenter::prepare`]).
    pub fn format(&self) -> Option<vk::Format> {
        self.swapchain.as_ref().map(Swapchain::format)
    }

    /// The swapchain's size (after the first [`Presenter::prepare`]).
    pub fn extent(&self) -> Option<(u32, u32)> {
        self.swapchain.as_ref().map(|s| {
            let e = s.extent();
            (e.width, e.height)
        })
    }

    /// The swapchain's present mode, in words (after the first
    /// [`Presenter::prepare`]).
    pub fn present_mode(&self) -> Option<&'static str> {
        self.swapchain.as_ref().map(|s| match s.present_mode() {
            vk::PresentModeKHR::FIFO => "fifo",
            vk::PresentModeKHR::MAILBOX => "mailbox",
            vk::PresentModeKHR::IMMEDIATE => "immediate",
            _ => "other",
        })
    }

    /// Marks the swapchain for remaking (the window was resized).
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Makes the swapchain fit `size` if it is stale; false while the
    /// window has no area (minimised).
    pub fn prepare(&mut self, size: (u32, u32)) -> VkResult<bool> {
        if size.0 == 0 || size.1 == 0 {
            return Ok(false);
        }
        let fits = self.swapchain.as_ref().is_some_and(|s| {
            let e = s.extent();
            (e.width, e.height) == size
        });
        if self.stale || !fits {
            // Nothing may still use the old swapchain's images.
            self.ring.wait_all()?;
            let new = Swapchain::new(&self.ctx, size, self.pacing, self.swapchain.as_ref())?;
            self.swapchain = new;
            self.stale = false;
        }
        Ok(self.swapchain.is_some())
    }

    /// Presents `target` (left in `DrawTarget::FINAL_LAYOUT` by the frame
    /// submitted before) with `overlay` on top. Returns false when the frame
    /// was dropped because the swapchain must be remade.
    pub fn present(&mut self, target: &DrawTarget, overlay: &mut dyn Overlay) -> VkResult<bool> {
        let Some(chain) = self.swapchain.as_ref() else {
            return Ok(false);
        };
        let slot = self.ring.next_slot();
        // The slot's previous frame has finished with its semaphore.
        self.ring.wait(slot)?;
        let ready = self.acquired[slot];
        let index = match chain.acquire(ready, Duration::from_secs(10))? {
            Acquired::Image { index, suboptimal } => {
                self.stale |= suboptimal;
                index
            }
            Acquired::OutOfDate => {
                self.stale = true;
                return Ok(false);
            }
        };
        let (slot, cmd) = self.ring.begin()?;
        let recorded = record(&self.ctx, cmd, chain, index, target, overlay);
        if let Err(e) = recorded {
            self.ring.abandon(slot);
            return Err(e);
        }
        let waits = [(
            ready,
            vk::PipelineStageFlags2::ALL_TRANSFER
                | vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        )];
        let signals = [chain.render_done(index)];
        self.ring
            .submit_with(&self.ctx, slot, "present", &waits, &signals)?;
        if !chain.present(&self.ctx, index)? {
            self.stale = true;
        }
        Ok(true)
    }

    /// Waits for every frame still presenting.
    pub fn wait_idle(&mut self) -> VkResult<()> {
        self.ring.wait_all()
    }
}

impl Drop for Presenter {
    fn drop(&mut self) {
        let _ = self.ring.wait_all();
        if self.ctx.is_hung() {
            return;
        }
        for &s in &self.acquired {
            unsafe { self.ctx.device().destroy_semaphore(s, None) };
        }
    }
}

/// Records the blit of `target` into swapchain image `index`, the overlay,
/// and the transition for presenting.
fn record(
    ctx: &Context,
    cmd: vk::CommandBuffer,
    chain: &Swapchain,
    index: u32,
    target: &DrawTarget,
    overlay: &mut dyn Overlay,
) -> VkResult<()> {
    let image = chain.image(index);
    let transfer = vk::PipelineStageFlags2::ALL_TRANSFER;
    let color_out = vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT;
    let swap = |layout| Res::Swapchain(image, layout);
    let mut rec = Recorder::new(ctx, cmd);
    // The target was written by the renderer's frame, submitted earlier:
    // its transfer reads wait for all earlier commands. The swapchain
    // image's old contents are not kept: its transition only has to chain
    // with the acquire semaphore's wait in those stages.
    rec.after(
        Res::Image(target.color(), DrawTarget::FINAL_LAYOUT),
        Access::ALL,
    );
    rec.after(
        swap(vk::ImageLayout::UNDEFINED),
        Access::new(transfer | color_out, vk::AccessFlags2::NONE),
    );
    let blit = Pass::new("blit to swapchain")
        .read(
            Res::Image(target.color(), DrawTarget::FINAL_LAYOUT),
            Access::TRANSFER_READ,
        )
        .write(
            swap(vk::ImageLayout::TRANSFER_DST_OPTIMAL),
            Access::new(transfer, vk::AccessFlags2::TRANSFER_WRITE),
        );
    let src = target.extent();
    let dst = chain.extent();
    let corner = |e: vk::Extent2D| vk::Offset3D {
        x: e.width as i32,
        y: e.height as i32,
        z: 1,
    };
    let layers = vk::ImageSubresourceLayers::default()
        .aspect_mask(vk::ImageAspectFlags::COLOR)
        .layer_count(1);
    let region = [vk::ImageBlit::default()
        .src_subresource(layers)
        .src_offsets([vk::Offset3D::default(), corner(src)])
        .dst_subresource(layers)
        .dst_offsets([vk::Offset3D::default(), corner(dst)])];
    rec.run(&blit, |cmd| unsafe {
        ctx.device().cmd_blit_image(
            cmd,
            target.color().handle(),
            DrawTarget::FINAL_LAYOUT,
            image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &region,
            vk::Filter::NEAREST,
        )
    });
    let attach = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    let overlay_pass = Pass::new("overlay").write(
        swap(attach),
        Access::new(
            color_out,
            vk::AccessFlags2::COLOR_ATTACHMENT_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        ),
    );
    let colors = [vk::RenderingAttachmentInfo::default()
        .image_view(chain.view(index))
        .image_layout(attach)
        .load_op(vk::AttachmentLoadOp::LOAD)
        .store_op(vk::AttachmentStoreOp::STORE)];
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: dst,
    };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&colors);
    let drawn = rec.run(&overlay_pass, |cmd| {
        unsafe { ctx.device().cmd_begin_rendering(cmd, &info) };
        let drawn = overlay.record(ctx, cmd, dst);
        unsafe { ctx.device().cmd_end_rendering(cmd) };
        drawn
    });
    // Presentation waits on the submission's semaphore, not a stage.
    rec.hand_off(
        swap(vk::ImageLayout::PRESENT_SRC_KHR),
        Access::new(vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
    );
    drawn
}
