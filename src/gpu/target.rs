//! The offscreen render target: an RGBA8 colour image and a D32 depth
//! image, drawn with dynamic rendering, read back and saved as PNG.
//!
//! Layout contract: [`DrawTarget::begin`] discards both images' previous
//! contents (transition from UNDEFINED, then clear), and
//! [`DrawTarget::end`] leaves the colour image in [`DrawTarget::FINAL_LAYOUT`]
//! (TRANSFER_SRC_OPTIMAL), ready for a copy or a blit.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use ash::vk;
use image::ImageEncoder;

use crate::vk::{Access, Context, Image, ImageDesc, Pass, Recorder, Res, VkError, VkResult};

/// Errors of saving images (drawing itself reports [`VkError`]).
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// A Vulkan failure (readback).
    #[error(transparent)]
    Vk(#[from] VkError),
    /// Creating, writing or renaming a file failed. The cause is part of
    /// the message, not an error source, so that error chains (`{:#}`)
    /// print it once (as `SceneError::Io` does).
    #[error("{}: {cause}", path.display())]
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// What the OS said.
        cause: std::io::Error,
    },
    /// PNG encoding failed (the cause in the message, as for `Io`).
    #[error("encoding {} as PNG: {cause}", path.display())]
    Png {
        /// The file.
        path: std::path::PathBuf,
        /// The encoder's error.
        cause: image::ImageError,
    },
}

/// Colour format of every draw pipeline.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// Depth format of every draw pipeline.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Sample counts a target accepts.
pub fn sample_count(samples: u32) -> Option<vk::SampleCountFlags> {
    match samples {
        1 => Some(vk::SampleCountFlags::TYPE_1),
        2 => Some(vk::SampleCountFlags::TYPE_2),
        4 => Some(vk::SampleCountFlags::TYPE_4),
        8 => Some(vk::SampleCountFlags::TYPE_8),
        _ => None,
    }
}

/// Colour + depth images of one view size, optionally multisampled: then
/// the colour is rendered into a multisampled image and resolved into the
/// single-sampled one every reader (readback, blit, FLIP) sees.
pub struct DrawTarget {
    /// The single-sampled colour image: the result.
    color: Image,
    /// The multisampled colour image rendered into, when samples > 1.
    msaa: Option<Image>,
    depth: Image,
    samples: vk::SampleCountFlags,
    /// Background colour (RGBA in 0..1) the colour image is cleared to.
    pub clear: [f32; 4],
    /// Whether `end` was ever recorded, i.e. whether the colour image can be
    /// in FINAL_LAYOUT rather than UNDEFINED.
    rendered: AtomicBool,
    /// Whether the last part stores its depth (for [`DrawTarget::read_depth`];
    /// otherwise the depth is dropped once drawn).
    keep_depth: AtomicBool,
    /// A part follows the method's last one (the levels of detail's draw,
    /// src/lod): the method's last part then stores what it drew.
    more_parts: AtomicBool,
}

impl DrawTarget {
    /// Layout the colour image is left in by [`DrawTarget::end`].
    pub const FINAL_LAYOUT: vk::ImageLayout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    /// Layout of the colour images while a part draws.
    const COLOR_LAYOUT: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    /// Layout of the depth image while a part draws (and between parts).
    const DEPTH_LAYOUT: vk::ImageLayout = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;

    /// Creates a single-sampled `width`×`height` target cleared to `clear`.
    pub fn new(ctx: &Context, width: u32, height: u32, clear: [f32; 4]) -> VkResult<Self> {
        Self::with_samples(ctx, width, height, clear, 1)
    }

    /// Creates a target with `samples` samples per pixel (1, 2, 4 or 8, and
    /// what the device supports for colour and depth).
    pub fn with_samples(
        ctx: &Context,
        width: u32,
        height: u32,
        clear: [f32; 4],
        samples: u32,
    ) -> VkResult<Self> {
        let flags = sample_count(samples)
            .filter(|f| ctx.info().limits.framebuffer_sample_counts.contains(*f))
            .ok_or_else(|| VkError::NotOffered {
                device: ctx.info().name.clone(),
                what: format!("{samples} samples per pixel (--msaa {samples})"),
                hint: format!(
                    "; it renders with {} (`info` lists them under MSAA)",
                    ctx.info()
                        .limits
                        .msaa_sample_counts()
                        .iter()
                        .map(u32::to_string)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })?;
        let image = |name, format, usage, samples| {
            Image::new(
                ctx,
                &ImageDesc {
                    name,
                    width,
                    height,
                    format,
                    usage,
                    samples,
                },
            )
        };
        let attachment = vk::ImageUsageFlags::COLOR_ATTACHMENT;
        let color = image(
            "draw target colour",
            COLOR_FORMAT,
            attachment | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::SampleCountFlags::TYPE_1,
        )?;
        let msaa = if samples > 1 {
            Some(image(
                "draw target colour (multisampled)",
                COLOR_FORMAT,
                attachment,
                flags,
            )?)
        } else {
            None
        };
        // Sampled: occlusion culling builds its depth pyramid from it; a
        // transfer source: validate reads it back.
        let depth = image(
            "draw target depth",
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC,
            flags,
        )?;
        Ok(Self {
            color,
            msaa,
            depth,
            samples: flags,
            clear,
            rendered: AtomicBool::new(false),
            keep_depth: AtomicBool::new(false),
            more_parts: AtomicBool::new(false),
        })
    }

    /// Samples per pixel of the attachments (the pipelines must match).
    pub fn samples(&self) -> vk::SampleCountFlags {
        self.samples
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.color.extent().width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.color.extent().height
    }

    /// (width, height) in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width(), self.height())
    }

    /// Size in pixels.
    pub fn extent(&self) -> vk::Extent2D {
        self.color.extent()
    }

    /// The depth image (multisampled with the colour), in
    /// DEPTH_ATTACHMENT_OPTIMAL between parts.
    pub fn depth(&self) -> &Image {
        &self.depth
    }

    /// The (resolved) colour image, in FINAL_LAYOUT after a recorded `end`.
    pub fn color(&self) -> &Image {
        &self.color
    }

    /// Records: the images to attachment layouts, `vkCmdBeginRendering`
    /// clearing colour to `clear` and depth to 1 (and resolving the
    /// multisampled colour into the result at the end), full-target
    /// viewport and scissor.
    pub fn begin(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        self.begin_part(ctx, cmd, true, true);
    }

    /// [`DrawTarget::begin`] for one of several parts of a frame
    /// (`FrameRec::split`): the `first` part clears, the others load what
    /// the earlier parts drew (colour samples and depth); every part but
    /// the `last` stores them for the next, and every part resolves.
    pub fn begin_part(&self, ctx: &Context, cmd: vk::CommandBuffer, first: bool, last: bool) {
        let last = last && !self.more_parts.load(Ordering::Relaxed);
        self.to_attachment_layouts(ctx, cmd, first);
        let load = if first {
            vk::AttachmentLoadOp::CLEAR
        } else {
            vk::AttachmentLoadOp::LOAD
        };
        // Samples and depth are only needed until they are resolved, or
        // until the last part has drawn.
        let keep = if last {
            vk::AttachmentStoreOp::DONT_CARE
        } else {
            vk::AttachmentStoreOp::STORE
        };
        let extent = self.extent();
        let colors = [self.color_attachment(load, keep)];
        let depth_keep = if self.keep_depth.load(Ordering::Relaxed) {
            vk::AttachmentStoreOp::STORE
        } else {
            keep
        };
        let depth = self.depth_attachment(load, depth_keep);
        let area = vk::Rect2D {
            offset: vk::Offset2D { x: 0, y: 0 },
            extent,
        };
        let info = vk::RenderingInfo::default()
            .render_area(area)
            .layer_count(1)
            .color_attachments(&colors)
            .depth_attachment(&depth);
        // The projection already flips y (Camera::projection), so the
        // viewport is the plain one.
        let viewport = [vk::Viewport {
            x: 0.0,
            y: 0.0,
            width: extent.width as f32,
            height: extent.height as f32,
            min_depth: 0.0,
            max_depth: 1.0,
        }];
        let dev = ctx.device();
        unsafe {
            dev.cmd_begin_rendering(cmd, &info);
            dev.cmd_set_viewport(cmd, 0, &viewport);
            dev.cmd_set_scissor(cmd, 0, &[area]);
        }
    }

    /// Records the barriers that bring the images into their attachment
    /// layouts for a part: the colour image, the multisampled one if any,
    /// then the depth image.
    fn to_attachment_layouts(&self, ctx: &Context, cmd: vk::CommandBuffer, first: bool) {
        let attach = Access::new(
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_READ | vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let color_layout = Self::COLOR_LAYOUT;
        let depth_layout = Self::DEPTH_LAYOUT;
        // The first part comes from UNDEFINED: the old contents are cleared
        // anyway. A later part keeps them: the resolved colour image was
        // left in FINAL_LAYOUT, the others in their attachment layouts. The
        // source scope is everything, so this part's writes wait for any
        // earlier reads (readback copies, blits) and writes of the images.
        let (color_from, msaa_from, depth_from) = if first {
            let u = vk::ImageLayout::UNDEFINED;
            (u, u, u)
        } else {
            (Self::FINAL_LAYOUT, color_layout, depth_layout)
        };
        let mut rec = Recorder::new(ctx, cmd);
        let color = |layout| Res::Image(&self.color, layout);
        let depth = |layout| Res::Image(&self.depth, layout);
        rec.after(color(color_from), Access::ALL);
        rec.after(depth(depth_from), Access::ALL);
        let mut pass = Pass::new("attachments")
            .write(color(color_layout), attach)
            .write(depth(depth_layout), Access::DEPTH_ATTACHMENT);
        if let Some(ms) = &self.msaa {
            rec.after(Res::Image(ms, msaa_from), Access::ALL);
            pass = pass.write(Res::Image(ms, color_layout), attach);
        }
        rec.run(&pass, |_| ());
    }

    /// The colour attachment of a part: cleared to `clear` or loaded, and,
    /// when multisampled, rendered into the multisampled image (its samples
    /// stored as `keep` says) and resolved into the result.
    fn color_attachment(
        &self,
        load: vk::AttachmentLoadOp,
        keep: vk::AttachmentStoreOp,
    ) -> vk::RenderingAttachmentInfo<'static> {
        let clear = vk::ClearValue {
            color: vk::ClearColorValue {
                float32: self.clear,
            },
        };
        let color = vk::RenderingAttachmentInfo::default()
            .image_layout(Self::COLOR_LAYOUT)
            .load_op(load)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(clear);
        match &self.msaa {
            Some(ms) => color
                .image_view(ms.view())
                .store_op(keep)
                .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                .resolve_image_view(self.color.view())
                .resolve_image_layout(Self::COLOR_LAYOUT),
            None => color.image_view(self.color.view()),
        }
    }

    /// The depth attachment of a part: cleared to 1 or loaded, stored as
    /// `keep` says.
    fn depth_attachment(
        &self,
        load: vk::AttachmentLoadOp,
        keep: vk::AttachmentStoreOp,
    ) -> vk::RenderingAttachmentInfo<'static> {
        vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view())
            .image_layout(Self::DEPTH_LAYOUT)
            .load_op(load)
            .store_op(keep)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue {
                    depth: 1.0,
                    stencil: 0,
                },
            })
    }

    /// Records `vkCmdEndRendering` and moves the (resolved) colour image to
    /// [`DrawTarget::FINAL_LAYOUT`], its writes visible to transfers.
    pub fn end(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        unsafe { ctx.device().cmd_end_rendering(cmd) };
        let mut rec = Recorder::new(ctx, cmd);
        let attached = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
        rec.after(
            Res::Image(&self.color, attached),
            Access::COLOR_ATTACHMENT_WRITE,
        );
        rec.hand_off(
            Res::Image(&self.color, Self::FINAL_LAYOUT),
            Access::TRANSFER_READ,
        );
        self.rendered.store(true, Ordering::Relaxed);
    }

    /// The colour image as tightly packed RGBA8 rows, top row first (waits
    /// for all submitted work; call after the command buffer that recorded
    /// `end` was submitted).
    pub fn read_rgba(&self, ctx: &Context) -> VkResult<Vec<u8>> {
        if !self.rendered.load(Ordering::Relaxed) {
            return Err(VkError::Usage(String::from(
                "the draw target was read before anything was rendered into it",
            )));
        }
        self.color.read_pixels(ctx, Self::FINAL_LAYOUT)
    }

    /// Whether a part follows what the method records as its last (the
    /// levels of detail's draw): its last part then stores samples and
    /// depth for that part to load.
    pub fn set_more_parts(&self, more: bool) {
        self.more_parts.store(more, Ordering::Relaxed);
    }

    /// Whether frames from now on keep their depth for
    /// [`DrawTarget::read_depth`] (off by default: the last part drops it).
    pub fn set_keep_depth(&self, keep: bool) {
        self.keep_depth.store(keep, Ordering::Relaxed);
    }

    /// The depth image as f32 rows, top row first, of a frame drawn with
    /// [`DrawTarget::set_keep_depth`] on; single-sampled targets only (waits
    /// for all submitted work).
    pub fn read_depth(&self, ctx: &Context) -> VkResult<Vec<f32>> {
        if !self.rendered.load(Ordering::Relaxed) || !self.keep_depth.load(Ordering::Relaxed) {
            return Err(VkError::Usage(
                "the draw target's depth was read without a frame drawn to keep it".into(),
            ));
        }
        if self.msaa.is_some() {
            return Err(VkError::Usage(
                "the depth of a multisampled draw target cannot be read back".into(),
            ));
        }
        let bytes = self.depth.read_pixels(ctx, Self::DEPTH_LAYOUT)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Reads the colour image back and writes it to `path` as PNG (see
    /// [`write_png`]).
    pub fn save_png(&self, ctx: &Context, path: &Path) -> Result<(), ImageError> {
        let rgba = self.read_rgba(ctx)?;
        write_png(path, self.width(), self.height(), &rgba)
    }
}

/// Writes RGBA8 pixels to `path` as PNG: first to a temporary file in the
/// same directory, then renamed over `path`, so a reader never sees a half
/// written image and a failure leaves nothing behind.
pub fn write_png(path: &Path, width: u32, height: u32, rgba: &[u8]) -> Result<(), ImageError> {
    let expected = width as usize * height as usize * 4;
    if rgba.len() != expected {
        return Err(ImageError::Vk(VkError::Usage(format!(
            "{} bytes of pixels for a {width}x{height} RGBA8 image ({expected} expected)",
            rgba.len()
        ))));
    }
    // Encoded in memory, then written through a temporary file and a
    // rename (crate::files).
    let mut png = Vec::new();
    image::codecs::png::PngEncoder::new(&mut png)
        .write_image(rgba, width, height, image::ExtendedColorType::Rgba8)
        .map_err(|cause| ImageError::Png {
            path: path.to_path_buf(),
            cause,
        })?;
    crate::files::write_atomic(path, &png).map_err(|cause| ImageError::Io {
        path: path.to_path_buf(),
        cause,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PNGs appear whole or not at all.
    #[test]
    fn png_writes_are_atomic() {
        let dir = std::env::temp_dir().join(format!("draw-png-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let pixels: Vec<u8> = (0..4 * 3 * 2).map(|i| (i * 10) as u8).collect();
        let path = dir.join("ok.png");
        write_png(&path, 3, 2, &pixels).unwrap();
        let back = image::load_from_memory(&std::fs::read(&path).unwrap())
            .unwrap()
            .to_rgba8();
        assert_eq!(back.dimensions(), (3, 2));
        assert_eq!(back.into_raw(), pixels);
        // Wrong size and a missing directory fail and leave nothing behind.
        assert!(write_png(&dir.join("short.png"), 3, 3, &pixels).is_err());
        let missing = write_png(&dir.join("missing/x.png"), 3, 2, &pixels).unwrap_err();
        // The chain `main` prints says the OS's words once.
        let chain = format!("{:#}", anyhow::Error::from(missing));
        assert_eq!(chain.matches("No such file").count(), 1, "{chain}");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, ["ok.png"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
