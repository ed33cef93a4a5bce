//! The on-screen overlay: egui, fed by winit's events (egui-winit) and
//! drawn on the swapchain image after the blit of the rendered frame
//! (egui-ash-renderer, dynamic rendering).

use ash::vk;
use egui_ash_renderer::{DynamicRendering, Options, RenderMode, Renderer};
use winit::window::Window;

use super::present::{Overlay, PRESENT_SLOTS};
use crate::vk::{Context, VkError, VkResult};

fn gui_error(e: egui_ash_renderer::RendererError) -> VkError {
    VkError::Usage(format!("the overlay renderer failed: {e}"))
}

/// egui's state and its Vulkan renderer.
pub struct Gui {
    // Dropped before the device it was made with (field order).
    renderer: Option<Renderer<egui_ash_renderer::allocator::DefaultAllocator>>,
    ctx: egui::Context,
    state: egui_winit::State,
    primitives: Vec<egui::ClippedPrimitive>,
    pixels_per_point: f32,
    /// Textures egui released last frame, freed once the GPU is idle.
    to_free: Vec<egui::TextureId>,
    pool: vk::CommandPool,
    device: ash::Device,
}

impl Gui {
    /// The overlay for `window`.
    pub fn new(ctx: &Context, window: &Window) -> VkResult<Self> {
        let egui_ctx = egui::Context::default();
        egui_ctx.set_visuals(egui::Visuals::dark());
        let state = egui_winit::State::new(
            egui_ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(4096),
        );
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.info().queue_family)
            .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        let pool = unsafe { ctx.device().create_command_pool(&info, None) }.map_err(|result| {
            VkError::Call {
                context: "vkCreateCommandPool(overlay)".into(),
                result,
            }
        })?;
        Ok(Self {
            renderer: None,
            ctx: egui_ctx,
            state,
            primitives: Vec::new(),
            pixels_per_point: 1.0,
            to_free: Vec::new(),
            pool,
            device: ctx.device().clone(),
        })
    }

    /// Hands a window event to egui; true when egui used it (the camera
    /// should then ignore it).
    pub fn on_event(&mut self, window: &Window, event: &winit::event::WindowEvent) -> bool {
        self.state.on_window_event(window, event).consumed
    }

    /// egui's context (to upload images for the overlay).
    pub fn egui(&self) -> &egui::Context {
        &self.ctx
    }

    /// Whether the pointer is over an egui area (a drag there is not for
    /// the camera).
    pub fn wants_pointer(&self) -> bool {
        self.ctx.egui_wants_pointer_input()
    }

    /// Whether egui has keyboard focus (any widget, e.g. a button clicked
    /// last).
    pub fn wants_keyboard(&self) -> bool {
        self.ctx.egui_wants_keyboard_input()
    }

    /// Whether text is being typed into a widget (a slider's value being
    /// edited): then every key is the widget's.
    pub fn editing_text(&self) -> bool {
        self.ctx.text_edit_focused()
    }

    /// Runs one frame of UI: `build` lays it out; the result is tessellated
    /// and its textures uploaded, ready for [`Overlay::record`] on a
    /// swapchain image of `format`.
    pub fn run(
        &mut self,
        ctx: &Context,
        window: &Window,
        format: vk::Format,
        mut build: impl FnMut(&egui::Context),
    ) -> VkResult<()> {
        self.ensure_renderer(ctx, format)?;
        let renderer = self
            .renderer
            .as_mut()
            .ok_or_else(|| VkError::Usage("no overlay renderer".into()))?;
        if !self.to_free.is_empty() {
            // Earlier frames may still sample them.
            ctx.with_queue(|q| unsafe { self.device.queue_wait_idle(q) })
                .map_err(|result| VkError::Call {
                    context: "vkQueueWaitIdle(overlay textures)".into(),
                    result,
                })?;
            renderer
                .free_textures(&std::mem::take(&mut self.to_free))
                .map_err(gui_error)?;
        }
        let input = self.state.take_egui_input(window);
        let output = self.ctx.run_ui(input, |ui| build(ui.ctx()));
        self.state
            .handle_platform_output(window, output.platform_output);
        self.pixels_per_point = output.pixels_per_point;
        self.primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        if !output.textures_delta.set.is_empty() {
            let pool = self.pool;
            ctx.with_queue(|q| renderer.set_textures(q, pool, &output.textures_delta.set))
                .map_err(gui_error)?;
        }
        self.to_free = output.textures_delta.free;
        Ok(())
    }

    fn ensure_renderer(&mut self, ctx: &Context, format: vk::Format) -> VkResult<()> {
        if self.renderer.is_some() {
            return Ok(());
        }
        let mode = RenderMode::DynamicRendering(DynamicRendering {
            color_attachment_format: format,
            depth_attachment_format: None,
            stencil_attachment_format: None,
        });
        let options = Options {
            in_flight_frames: PRESENT_SLOTS,
            enable_depth_test: false,
            enable_depth_write: false,
            // The swapchain is UNORM: egui writes display values itself.
            srgb_framebuffer: false,
        };
        let renderer = Renderer::with_default_allocator(
            ctx.instance(),
            ctx.physical_device(),
            self.device.clone(),
            mode,
            options,
        )
        .map_err(gui_error)?;
        self.renderer = Some(renderer);
        Ok(())
    }
}

impl Overlay for Gui {
    fn record(
        &mut self,
        _ctx: &Context,
        cmd: vk::CommandBuffer,
        extent: vk::Extent2D,
    ) -> VkResult<()> {
        let Some(renderer) = self.renderer.as_mut() else {
            return Ok(());
        };
        renderer
            .cmd_draw(cmd, extent, self.pixels_per_point, &self.primitives)
            .map_err(gui_error)
    }
}

impl Drop for Gui {
    fn drop(&mut self) {
        unsafe {
            let _ = self.device.device_wait_idle();
        }
        self.renderer = None;
        unsafe { self.device.destroy_command_pool(self.pool, None) };
    }
}
