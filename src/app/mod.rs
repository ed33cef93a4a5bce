//! `view`: the window. A winit window with a Vulkan swapchain, the
//! renderer drawing into its own target at the window's size, the target
//! blitted to the swapchain image and the egui overlay drawn on top.
//!
//! The event loop is winit's: window events go to egui first, then to the
//! camera ([`input`]); every redraw is one [`session::Session::frame`]. All
//! Vulkan objects live in the session, which is dropped while the window
//! and its display connection still exist.

pub mod camera;
mod input;
pub mod overlay;
pub mod panel;
pub mod present;
mod session;

use std::path::PathBuf;

use anyhow::{anyhow, Context as _};
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::WindowId;

use crate::commands::render::Shade;
use crate::commands::{keyframe, GpuRequest};
use crate::files::check_writable;
use crate::scene::desc::Scene;
use session::Session;

/// What `view` is asked for.
#[derive(Clone, Debug)]
pub struct ViewArgs {
    /// Scene, method, tolerance, the window's first size, MSAA, device.
    pub gpu: GpuRequest,
    /// Keyframe the camera starts at.
    pub frame: usize,
    /// Shading at start.
    pub shade: Shade,
    /// Wait for vertical blank.
    pub vsync: bool,
    /// Close after this many presented frames.
    pub frames: Option<u64>,
    /// Screenshot path (F12, and the last frame of `frames`).
    pub screenshot: Option<PathBuf>,
    /// Halfway through `frames`, resize the window to this.
    pub resize: Option<(u32, u32)>,
}

/// Opens the window and runs until it is closed (or `frames` are done);
/// returns a short summary.
pub fn run(args: &ViewArgs) -> anyhow::Result<String> {
    args.gpu.method_info()?;
    if args.resize.is_some() && args.frames.is_none() {
        return Err(anyhow!(
            "--resize needs --frames (it happens halfway through them)"
        ));
    }
    if let Some(p) = &args.screenshot {
        check_writable(p, false).map_err(|e| anyhow!(e))?;
    }
    let scene = Scene::load(&args.gpu.scene)?;
    let camera = keyframe(&scene, &args.gpu.scene, args.frame)?;
    let view = args.gpu.view_request(&scene)?;
    let loaded = scene
        .load_animated()
        .with_context(|| format!("loading the models of {}", args.gpu.scene.display()))?;
    let time = args.gpu.seconds(loaded.animation.as_ref())?;
    crate::commands::note_undisplaced(&loaded.geometry, std::slice::from_ref(&args.gpu.method));
    let event_loop = EventLoop::new().map_err(|e| {
        anyhow!(
            "cannot open a window: {e} (is DISPLAY set? without a display, run under \
             `xvfb-run -a`, or use `render`)"
        )
    })?;
    let mut app = App {
        start: Some(session::Start {
            args: args.clone(),
            scene,
            geo: loaded.geometry,
            shading: loaded.shading,
            animation: loaded.animation,
            time,
            camera,
            view,
        }),
        session: None,
        error: None,
        summary: String::new(),
    };
    event_loop.run_app(&mut app)?;
    match app.error {
        Some(e) => Err(e.context("the window closed on an error")),
        None => Ok(app.summary),
    }
}

/// winit's application: makes the session once the loop is running, hands
/// it the events, and keeps the first error.
struct App {
    start: Option<session::Start>,
    session: Option<Session>,
    error: Option<anyhow::Error>,
    summary: String,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        event_loop.exit();
    }

    /// Ends the session (its Vulkan objects go before the window).
    fn finish(&mut self) {
        if let Some(s) = self.session.take() {
            match s.close() {
                Ok(summary) => self.summary = summary,
                Err(e) => {
                    if self.error.is_none() {
                        self.error = Some(e);
                    }
                }
            }
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        let Some(start) = self.start.take() else {
            return;
        };
        match Session::new(event_loop, start) {
            Ok(s) => self.session = Some(s),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(s) = self.session.as_mut() else {
            return;
        };
        match s.on_window_event(&event) {
            Ok(session::Flow::Continue) => {}
            Ok(session::Flow::Exit) => {
                self.finish();
                event_loop.exit();
            }
            Err(e) => {
                self.finish();
                self.fail(event_loop, e);
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(s) = &self.session {
            // Draw continuously while there is something to show; sleep
            // while minimised.
            if s.visible() {
                event_loop.set_control_flow(ControlFlow::Poll);
                s.request_redraw();
            } else {
                event_loop.set_control_flow(ControlFlow::Wait);
            }
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        self.finish();
    }
}
