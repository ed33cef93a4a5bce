//! One open window: the Vulkan context made for its surface, the renderer,
//! the presenter and the overlay, and what one frame does.
//!
//! A frame: the actions asked for last frame (screenshot, FLIP, camera
//! reset, path), the camera, the controls applied to the renderer, the
//! oldest frame in flight collected for the statistics, the new frame
//! submitted, the overlay laid out and the image presented. Frames stay in
//! flight across calls: the renderer's slots let the host prepare frame
//! n+1 while the GPU draws frame n.

use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{anyhow, Context as _};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use serde_json::json;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::window::Window;

use super::camera::CameraRig;
use super::input::{self, Command, Input};
use super::overlay::Gui;
use super::panel::{Action, AnimControls, Controls, DeviceOffer, FlipView, LiveStats};
use super::present::Presenter;
use super::ViewArgs;
use crate::commands::render::{stats_json, stats_path, write_outputs, RenderArgs};
use crate::constants::{
    FLAG_BACKFACE_CULL, FLAG_FRUSTUM_CULL, FLAG_UNDISPLACED, FLAG_WEDGES, L_MAX, SHADE_NORMAL,
};
use crate::frame::View;
use crate::methods::{MethodOptions, RenderError};
use crate::renderer::{FrameReport, FrameTicket, Renderer, DEFAULT_FRAMES_IN_FLIGHT};
use crate::scene::camera::Camera;
use crate::scene::desc::Scene;
use crate::scene::geometry::{SceneGeometry, SceneShading};
use crate::vk::{Context, ContextOptions, PresentPacing, WindowHandles};

/// What the session is made from.
pub struct Start {
    /// The command line.
    pub args: ViewArgs,
    /// The scene.
    pub scene: Scene,
    /// Its patches.
    pub geo: SceneGeometry,
    /// Their shading normals.
    pub shading: SceneShading,
    /// What moves, if anything.
    pub animation: Option<crate::anim::Animation>,
    /// The animation's time at start.
    pub time: f64,
    /// Where the camera starts.
    pub camera: Camera,
    /// The command line's ε, λ and split mode, else the scene's.
    pub view: crate::commands::ViewRequest,
}

/// Whether the window stays open.
pub enum Flow {
    /// Keep going.
    Continue,
    /// Close the window.
    Exit,
}

/// The open window and everything drawn into it.
pub struct Session {
    // Vulkan objects first: fields drop in order, and the window (whose
    // surface the context owns) must outlive them all.
    gui: Gui,
    presenter: Presenter,
    renderer: Renderer,
    ctx: Arc<Context>,
    window: Arc<Window>,
    args: ViewArgs,
    scene: Scene,
    rig: CameraRig,
    input: Input,
    controls: Controls,
    stats: LiveStats,
    flip: Option<FlipView>,
    /// Submitted frames not collected yet, oldest first.
    pending: VecDeque<FrameTicket>,
    /// The view and camera of the last submitted frame.
    last: Option<(View, Camera)>,
    /// The last collected frame was incomplete (the method grew a buffer).
    last_redone: bool,
    /// Asked for in the last frame's overlay or by keys.
    actions: Vec<Action>,
    show_overlay: bool,
    clock: Instant,
    presented: u64,
    written: Vec<PathBuf>,
}

impl Session {
    /// Opens the window and makes the context, renderer, presenter and
    /// overlay for it.
    pub fn new(event_loop: &ActiveEventLoop, start: Start) -> anyhow::Result<Self> {
        let Start {
            args,
            scene,
            geo,
            shading,
            animation,
            time,
            camera,
            view,
        } = start;
        let (w, h) = args.gpu.size;
        let attrs = Window::default_attributes()
            .with_title(format!("bezier-subdiv: {}", scene.name))
            .with_inner_size(PhysicalSize::new(w, h));
        let window = Arc::new(
            event_loop
                .create_window(attrs)
                .context("opening the window")?,
        );
        let handles = WindowHandles {
            display: window.display_handle()?.as_raw(),
            window: window.window_handle()?.as_raw(),
        };
        let ctx = Arc::new(Context::new(&ContextOptions {
            selector: args.gpu.device.clone(),
            validation: args.gpu.validation,
            window: Some(handles),
            notice: Some(crate::commands::print_notice),
            ..ContextOptions::default()
        })?);
        let size = window.inner_size();
        let mut request = args.gpu.clone();
        request.size = (size.width.max(1), size.height.max(1));
        let mut renderer = request.renderer(&ctx, &geo, &shading)?;
        let anim = animation.as_ref().map(|a| AnimControls {
            playing: true,
            time,
            speed: 1.0,
            duration: a.duration,
            fps: a.fps,
            looping: a.looping,
        });
        renderer.set_animation(animation)?;
        renderer.set_time(time);
        let pacing = if args.vsync {
            PresentPacing::Vsync
        } else {
            PresentPacing::Unlimited
        };
        let presenter = Presenter::new(Arc::clone(&ctx), pacing)?;
        let gui = Gui::new(&ctx, &window)?;
        let controls = Controls {
            method: renderer.method().name().to_string(),
            draw: renderer.options().draw,
            eps: view.eps,
            lambda: view.lambda,
            l_max: L_MAX,
            split: view.split,
            frustum: true,
            backface: true,
            wedges: true,
            occlusion: renderer.options().occlusion,
            displacement: geo.displacement.in_use().then_some(true),
            levels: renderer.levels().is_some().then_some(true),
            shade: args.shade,
            msaa: args.gpu.msaa,
            grid: args.gpu.per_method.reference_grid(),
            anim,
        };
        let stats = LiveStats {
            device: ctx.info().name.clone(),
            ..LiveStats::default()
        };
        Ok(Self {
            gui,
            presenter,
            renderer,
            ctx,
            window,
            args,
            scene,
            rig: CameraRig::new(camera),
            input: Input::default(),
            controls,
            stats,
            flip: None,
            pending: VecDeque::new(),
            last: None,
            last_redone: false,
            actions: Vec::new(),
            show_overlay: true,
            clock: Instant::now(),
            presented: 0,
            written: Vec::new(),
        })
    }

    /// Whether the window has an area to draw into.
    pub fn visible(&self) -> bool {
        let s = self.window.inner_size();
        s.width > 0 && s.height > 0 && self.window.is_minimized() != Some(true)
    }

    /// Asks winit for the next frame.
    pub fn request_redraw(&self) {
        self.window.request_redraw();
    }

    /// Handles one window event: the window's own keys first (whatever
    /// widget has focus), then egui, then the camera and the other keys.
    pub fn on_window_event(&mut self, event: &WindowEvent) -> anyhow::Result<Flow> {
        // egui takes Tab for moving the focus and swallows every key while
        // a widget (a button clicked last) has it, until Escape; the
        // window's keys must work regardless, unless text is being typed,
        // and F12 and Tab, which type nothing, even then.
        let typing_text = self.gui.editing_text();
        if input::is_window_key(event) && (!typing_text || input::acts_while_typing(event)) {
            let pointer_free = !self.gui.wants_pointer();
            let command = self.input.on_event(event, &mut self.rig, pointer_free);
            return Ok(self.command(command));
        }
        let used = self.gui.on_event(&self.window, event);
        match event {
            WindowEvent::CloseRequested => return Ok(Flow::Exit),
            WindowEvent::Resized(_) | WindowEvent::ScaleFactorChanged { .. } => {
                self.presenter.invalidate();
            }
            WindowEvent::RedrawRequested => return self.frame(),
            _ => {}
        }
        // Releases always reach the camera, so a drag that ends over the
        // overlay does not stick.
        let release = matches!(
            event,
            WindowEvent::MouseInput {
                state: ElementState::Released,
                ..
            } | WindowEvent::KeyboardInput {
                event: KeyEvent {
                    state: ElementState::Released,
                    ..
                },
                ..
            }
        );
        let typing =
            matches!(event, WindowEvent::KeyboardInput { .. }) && self.gui.wants_keyboard();
        if (used || typing) && !release {
            return Ok(Flow::Continue);
        }
        let pointer_free = !self.gui.wants_pointer();
        let command = self.input.on_event(event, &mut self.rig, pointer_free);
        Ok(self.command(command))
    }

    /// Carries out what a key asked for.
    fn command(&mut self, command: Option<Command>) -> Flow {
        match command {
            Some(Command::Action(a)) => self.actions.push(a),
            Some(Command::ToggleOverlay) => self.show_overlay = !self.show_overlay,
            Some(Command::Quit) => return Flow::Exit,
            None => {}
        }
        Flow::Continue
    }

    /// Draws and presents one frame.
    fn frame(&mut self) -> anyhow::Result<Flow> {
        let now = Instant::now();
        let interval = (now - self.clock).as_secs_f64();
        // The camera moves at most a quarter second's worth per frame; the
        // panel shows the real interval (a CPU device's frames take longer).
        let dt = interval.min(0.25);
        self.clock = now;
        self.stats.add_frame_time(interval * 1000.0);
        for action in std::mem::take(&mut self.actions) {
            // A screenshot or FLIP asked for before the first frame waits
            // for it (a key pressed as the window opens is not lost).
            if self.last.is_none() && matches!(action, Action::Screenshot | Action::Flip) {
                self.actions.push(action);
                continue;
            }
            self.act(action)?;
        }
        let size = self.window.inner_size();
        if !self.presenter.prepare((size.width, size.height))? {
            return Ok(Flow::Continue);
        }
        let extent = self
            .presenter
            .extent()
            .ok_or_else(|| anyhow!("no swapchain after preparing one"))?;
        if let Some(a) = &mut self.controls.anim {
            a.advance(dt);
            self.renderer.set_time(a.time);
        }
        let camera = match self.rig.advance_path(&self.scene, dt) {
            Some(c) => c,
            None => {
                self.rig.fly(self.input.fly_keys(), dt);
                self.rig.camera()
            }
        };
        self.apply_controls(extent)?;
        let view = self.view(&camera, extent);
        self.submit(&view, camera)?;
        self.lay_out_overlay()?;
        self.presenter
            .present(self.renderer.target(), &mut self.gui)?;
        self.presented += 1;
        self.scripted()
    }

    /// The frame's view: the camera, the window's size and the controls.
    fn view(&self, camera: &Camera, size: (u32, u32)) -> View {
        let c = &self.controls;
        let mut view = View::new(camera, size, c.eps, c.lambda, c.shade.code());
        view.params.l_max = c.l_max;
        let mut flags = view.params.flags & !(FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL | FLAG_WEDGES);
        for (on, flag) in [
            (c.frustum, FLAG_FRUSTUM_CULL),
            (c.backface, FLAG_BACKFACE_CULL),
            (c.wedges, FLAG_WEDGES),
        ] {
            if on {
                flags |= flag;
            }
        }
        if c.displacement == Some(false) {
            flags |= FLAG_UNDISPLACED;
        }
        view.params.flags = flags | c.split.flag();
        view
    }

    /// Brings the renderer in line with the window's size and the
    /// controls. A change the device refuses (a sample count it lacks) is
    /// shown in the overlay and the control set back; a lost device ends
    /// the session.
    fn apply_controls(&mut self, size: (u32, u32)) -> anyhow::Result<()> {
        let c = &self.controls;
        // Chosen per frame on the host: no drain needed.
        self.renderer.enable_levels(c.levels.unwrap_or(false));
        let mut wanted = MethodOptions {
            draw: c.draw,
            samples: c.msaa,
            occlusion: c.occlusion,
            ..self.renderer.options().clone()
        };
        wanted.per_method.set_reference_grid(c.grid);
        let resize = self.renderer.target().size() != size;
        let reconfigure = wanted != *self.renderer.options();
        let switch = c.method != self.renderer.method().name();
        if !(resize || reconfigure || switch) {
            return Ok(());
        }
        // Frames in flight belong to the old setup, and the presenter may
        // still be copying the old target.
        self.drain()?;
        self.presenter.wait_idle()?;
        self.stats.gpu_ms.clear();
        if resize {
            self.renderer.set_size(size)?;
        }
        let method = self.controls.method.clone();
        let changed = (if reconfigure {
            self.renderer.set_options(wanted)
        } else {
            Ok(())
        })
        .and_then(|()| self.renderer.set_method(&method));
        if let Err(e) = changed {
            if self.ctx.is_hung() {
                return Err(e.into());
            }
            self.stats.notice = Some(e.to_string());
            let o = self.renderer.options();
            self.controls.draw = o.draw;
            self.controls.grid = o.per_method.reference_grid();
            self.controls.msaa = o.samples;
            self.controls.method = self.renderer.method().name().to_string();
        }
        Ok(())
    }

    /// Collects the oldest frames until a slot is free, then submits.
    fn submit(&mut self, view: &View, camera: Camera) -> anyhow::Result<()> {
        while self.pending.len() >= DEFAULT_FRAMES_IN_FLIGHT {
            self.collect_oldest()?;
        }
        self.pending.push_back(self.renderer.submit(view)?);
        self.last = Some((*view, camera));
        Ok(())
    }

    fn collect_oldest(&mut self) -> anyhow::Result<()> {
        let Some(ticket) = self.pending.pop_front() else {
            return Ok(());
        };
        let (report, redone) = self.renderer.collect(ticket)?;
        self.last_redone = redone;
        if !redone {
            self.stats.add(report);
        }
        self.stats.memory = self.renderer.memory();
        Ok(())
    }

    /// Collects every frame in flight.
    fn drain(&mut self) -> anyhow::Result<()> {
        while !self.pending.is_empty() {
            self.collect_oldest()?;
        }
        Ok(())
    }

    fn lay_out_overlay(&mut self) -> anyhow::Result<()> {
        let format = self
            .presenter
            .format()
            .ok_or_else(|| anyhow!("no swapchain format"))?;
        let device = DeviceOffer {
            mesh: self.ctx.info().has_mesh_shader(),
            samples: self.ctx.info().limits.msaa_sample_counts(),
        };
        let Self {
            gui,
            controls,
            stats,
            flip,
            window,
            ctx,
            show_overlay,
            actions,
            ..
        } = self;
        gui.run(ctx, window, format, |c| {
            if *show_overlay {
                actions.extend(controls.ui(c, stats, flip.as_ref(), &device));
            }
        })?;
        Ok(())
    }

    fn act(&mut self, action: Action) -> anyhow::Result<()> {
        match action {
            Action::ResetCamera => self.rig.reset(),
            Action::TogglePath => self.rig.toggle_path(),
            Action::ToggleAnimation => {
                if let Some(a) = &mut self.controls.anim {
                    a.playing = !a.playing;
                }
            }
            Action::Screenshot => {
                let path = match &self.args.screenshot {
                    Some(p) => p.clone(),
                    None => self.free_path("view")?,
                };
                self.screenshot(&path)?;
            }
            Action::Flip => self.flip()?,
            Action::CloseFlip => self.flip = None,
        }
        Ok(())
    }

    /// Where a file of kind `what` goes: beside `--screenshot` as
    /// `<its name>-<what>-<k>.png` when it was given, else
    /// `out/<scene>-<what>-<k>.png`, for the first k not taken.
    fn free_path(&self, what: &str) -> anyhow::Result<PathBuf> {
        let (dir, stem) = match &self.args.screenshot {
            Some(shot) => (
                shot.parent().map_or_else(PathBuf::new, |d| d.to_path_buf()),
                shot.file_stem()
                    .map_or_else(|| self.scene.name.clone(), |s| s.to_string_lossy().into()),
            ),
            None => (
                PathBuf::from(crate::commands::DEFAULT_OUT_DIR),
                self.scene.name.clone(),
            ),
        };
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
        }
        (1..)
            .map(|k| dir.join(format!("{stem}-{what}-{k}.png")))
            .find(|p| !p.exists())
            .ok_or_else(|| anyhow!("no free file name in {}", dir.display()))
    }

    /// Saves the last frame (without the overlay) and the same stats JSON
    /// as `render`, plus the camera and the live controls.
    fn screenshot(&mut self, path: &std::path::Path) -> anyhow::Result<()> {
        self.drain()?;
        let Some((view, camera)) = self.last else {
            self.stats.notice = Some("nothing drawn yet to save".into());
            return Ok(());
        };
        let report = match (&self.stats.last, self.last_redone) {
            (Some(r), false) => r.clone(),
            // The last frame was incomplete: draw it again, complete.
            _ => self.renderer.render(&view)?,
        };
        let rgba = self.renderer.read_image()?;
        let size = self.renderer.target().size();
        let mut stats = stats_json(
            &self.render_args(path, size, &report),
            &self.scene,
            self.controls.eps,
            self.controls.lambda,
            &self.renderer,
            &report,
        );
        let c = &self.controls;
        stats["source"] = json!("view");
        stats["frame"] = serde_json::Value::Null;
        stats["l_max"] = json!(c.l_max);
        stats["culling"] = json!({
            "frustum": c.frustum,
            "backface": c.backface,
            "occlusion": c.occlusion,
        });
        stats["wedges"] = json!(c.wedges);
        stats["displacement"] = json!(c.displacement);
        stats["levels_of_detail_on"] = json!(c.levels);
        stats["split"] = json!(c.split.name());
        stats["present_mode"] = json!(self.presenter.present_mode());
        // What the window showed around the frame (the keys' effects).
        stats["overlay_shown"] = json!(self.show_overlay);
        stats["path_playing"] = json!(self.rig.path.is_some());
        stats["camera"] = json!({
            "position": camera.position,
            "target": camera.target,
            "up": camera.up,
            "fov_y_deg": camera.fov_y_deg,
            "near": camera.near,
            "far": camera.far,
        });
        write_outputs(path, &stats_path(path), size, &rgba, &stats, None)?;
        self.stats.notice = Some(format!("saved {}", path.display()));
        self.written.push(path.to_path_buf());
        Ok(())
    }

    /// The `render` request the live state amounts to (for the stats JSON).
    fn render_args(
        &self,
        path: &std::path::Path,
        size: (u32, u32),
        report: &FrameReport,
    ) -> RenderArgs {
        let c = &self.controls;
        let mut gpu = self.args.gpu.clone();
        gpu.method = report.method.to_string();
        gpu.eps = Some(c.eps);
        gpu.lambda = Some(c.lambda);
        gpu.size = size;
        gpu.per_method.set_reference_grid(c.grid);
        gpu.msaa = c.msaa;
        RenderArgs {
            gpu,
            frame: self.args.frame,
            shade: c.shade,
            out: Some(path.to_path_buf()),
            warmup: Some(0),
            repeat: 0,
            flip: false,
        }
    }

    /// FLIP of the last view (lit) against the ground truth, shown in the
    /// overlay and written as a heat map.
    fn flip(&mut self) -> anyhow::Result<()> {
        let Some((mut view, _)) = self.last else {
            return Ok(());
        };
        self.drain()?;
        // The ground truth is drawn into the target the presenter copies.
        self.presenter.wait_idle()?;
        view.shade = SHADE_NORMAL;
        let reference = crate::eval::ground_truth_image(&mut self.renderer, &view)?;
        self.renderer.render(&view)?;
        let test = self.renderer.read_image()?;
        let (w, h) = self.renderer.target().size();
        let result = crate::eval::flip::flip(&reference, &test, w, h)
            .ok_or_else(|| RenderError::Request("FLIP: the images differ in size".into()))?;
        let file = self.free_path("flip")?;
        result.save_heat_map(&file)?;
        let image = egui::ColorImage::from_rgba_unmultiplied(
            [w as usize, h as usize],
            &result.heat_map_rgba(),
        );
        let texture = self
            .gui
            .egui()
            .load_texture("flip", image, egui::TextureOptions::LINEAR);
        let scale = egui::ColorImage::from_rgba_unmultiplied(
            [256, 1],
            &crate::eval::flip::FlipResult::legend_rgba(256),
        );
        let legend =
            self.gui
                .egui()
                .load_texture("flip legend", scale, egui::TextureOptions::LINEAR);
        self.flip = Some(FlipView {
            mean: result.mean,
            texture,
            file: file.display().to_string(),
            legend,
        });
        Ok(())
    }

    /// `--frames N`: the resize halfway, the screenshot and the end.
    fn scripted(&mut self) -> anyhow::Result<Flow> {
        let Some(n) = self.args.frames else {
            return Ok(Flow::Continue);
        };
        if let Some((w, h)) = self.args.resize {
            if self.presented == n / 2 {
                // The new size arrives as a Resized event (or right away).
                if let Some(now) = self.window.request_inner_size(PhysicalSize::new(w, h)) {
                    log::info!("resized to {}x{}", now.width, now.height);
                }
                self.presenter.invalidate();
            }
        }
        if self.presented < n {
            return Ok(Flow::Continue);
        }
        if let Some(path) = self.args.screenshot.clone() {
            self.screenshot(&path)?;
        }
        Ok(Flow::Exit)
    }

    /// Waits for the GPU, checks the validation layer and says what was
    /// done; the Vulkan objects are dropped before the window.
    pub fn close(mut self) -> anyhow::Result<String> {
        let finished = self.drain();
        self.renderer.wait_idle()?;
        self.presenter.wait_idle()?;
        finished?;
        if self.args.gpu.validation {
            self.ctx.check_validation()?;
        }
        let (w, h) = self.renderer.target().size();
        let mut s = format!(
            "view: {} frames of {} on {}, last {w}x{h}, present mode {}\n",
            self.presented,
            self.scene.name,
            self.ctx.info().name,
            self.presenter.present_mode().unwrap_or("none")
        );
        for p in &self.written {
            s += &format!("wrote {} and {}\n", p.display(), stats_path(p).display());
        }
        Ok(s)
    }
}
