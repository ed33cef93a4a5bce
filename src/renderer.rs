//! One GPU frame of a method: upload once, then per view record the
//! subdivision pass and the draw into one command buffer, submit, and read
//! back the counters and timestamps. Used by `render`, `validate` and
//! `bench`.

use glam::{DMat4, Vec3};

use crate::constants::ERR_READY_FULL;
use crate::draw::{draw_push, headlight, DrawPath, DrawTarget, Drawer};
use crate::gpu::{Capacities, FrameGpu, SceneGpu, SceneLayout};
use crate::methods::sort::ReadySort;
use crate::methods::subdiv::{GpuSubdivStats, Subdivider};
use crate::patch::view::ViewParams;
use crate::scene::camera::Camera;
use crate::scene::file::SceneGeometry;
use crate::vk::{Context, GpuTimer, VkError, VkResult};

/// Largest ready list the renderer grows to (8 bytes per entry, plus the
/// fallback's 240 bytes of vertices per entry).
pub const MAX_READY_CAPACITY: u32 = 1 << 24;

/// Everything created once per scene and device.
pub struct Renderer<'a> {
    ctx: &'a Context,
    layout: SceneLayout,
    scene: SceneGpu,
    frame: FrameGpu,
    subdiv: Subdivider,
    sort: ReadySort,
    /// Sort the ready list before drawing (on by default: see
    /// `methods::sort`; benchmarks may time the method without it).
    pub sort_ready: bool,
    drawer: Drawer,
    target: DrawTarget,
    timer: GpuTimer,
}

/// What one frame reported.
#[derive(Clone, Debug)]
pub struct FrameReport {
    /// The subdivision pass's counters.
    pub stats: GpuSubdivStats,
    /// GPU time per named pass, in milliseconds.
    pub gpu_ms: Vec<(String, f64)>,
    /// Times the ready list had to grow and the frame re-run.
    pub regrown: u32,
}

/// One view: the criterion's constants plus what drawing needs.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Criterion and culling constants (flags included).
    pub params: ViewParams,
    /// World → clip.
    pub view_proj: DMat4,
    /// Direction towards the light.
    pub light_dir: Vec3,
    /// `SHADE_*`.
    pub shade: u32,
    /// `SHADE_DISTANCE`: the distance coded as 1.0 (0 for other modes).
    pub distance_scale: f32,
}

impl View {
    /// The view of `camera` in a `size` image with tolerance `eps`, blend
    /// `lambda`, shading `shade` and the default headlight.
    pub fn new(camera: &Camera, size: (u32, u32), eps: f64, lambda: f64, shade: u32) -> Self {
        let (w, h) = size;
        View {
            params: camera.view_params(w, h, eps, lambda),
            view_proj: camera.view_proj(w, h),
            light_dir: headlight(camera),
            shade,
            distance_scale: 0.0,
        }
    }
}

impl<'a> Renderer<'a> {
    /// Uploads `geo` and creates the passes for `path` and a
    /// `width`×`height` target cleared to `background`.
    pub fn new(
        ctx: &'a Context,
        geo: &SceneGeometry,
        path: DrawPath,
        mut caps: Capacities,
        size: (u32, u32),
        background: [f32; 4],
        groups: Option<u32>,
    ) -> VkResult<Self> {
        let layout = SceneLayout::new(ctx)?;
        let scene = SceneGpu::upload(ctx, &geo.patches, &geo.flags)?;
        caps.vertices = path == DrawPath::Fallback;
        // The sort pass works on power-of-two lists of at least one block.
        caps.ready = caps
            .ready
            .max(crate::constants::SORT_BLOCK)
            .next_power_of_two();
        let frame = FrameGpu::new(ctx, &layout, &scene, caps)?;
        let subdiv = Subdivider::new(ctx, &layout, groups)?;
        let sort = ReadySort::new(ctx, &layout)?;
        let drawer = Drawer::new(ctx, &layout, path)?;
        let target = DrawTarget::new(ctx, size.0, size.1, background)?;
        let timer = GpuTimer::new(ctx, 8)?;
        Ok(Self {
            ctx,
            layout,
            scene,
            frame,
            subdiv,
            sort,
            sort_ready: true,
            drawer,
            target,
            timer,
        })
    }

    /// The draw path in use.
    pub fn path(&self) -> DrawPath {
        self.drawer.path()
    }

    /// The per-view buffers (capacities, memory report, readbacks).
    pub fn frame(&self) -> &FrameGpu {
        &self.frame
    }

    /// The uploaded scene.
    pub fn scene(&self) -> &SceneGpu {
        &self.scene
    }

    /// The image of the last frame.
    pub fn target(&self) -> &DrawTarget {
        &self.target
    }

    /// The shared scene layout.
    pub fn layout(&self) -> &SceneLayout {
        &self.layout
    }

    /// Replaces the scene (re-uploads the patches, rebuilds the per-view
    /// buffers with the same capacities); the pipelines are kept.
    pub fn set_geometry(&mut self, geo: &SceneGeometry) -> VkResult<()> {
        self.scene = SceneGpu::upload(self.ctx, &geo.patches, &geo.flags)?;
        self.rebuild(self.frame.caps)
    }

    /// The background the target is cleared to.
    pub fn set_background(&mut self, rgba: [f32; 4]) {
        self.target.clear = rgba;
    }

    /// The subdivision pass (to adjust its cap in tests).
    pub fn subdivider_mut(&mut self) -> &mut Subdivider {
        &mut self.subdiv
    }

    /// Renders one view; if the ready list overflowed, grows it and renders
    /// again, so the image is always complete. Errors of the kernel
    /// (iteration cap, stack) are returned as `VkError::Usage` sentences.
    pub fn render(&mut self, view: &View, capture: bool) -> VkResult<FrameReport> {
        let mut regrown = 0;
        loop {
            if capture != self.frame.caps.capture {
                self.rebuild(Capacities {
                    capture,
                    ..self.frame.caps
                })?;
            }
            let (stats, gpu_ms) = self.render_once(view)?;
            if stats.errors & ERR_READY_FULL != 0 && self.frame.caps.ready < MAX_READY_CAPACITY {
                let want = (stats.ready_quads as u64 * 5 / 4).next_power_of_two();
                let ready = want.min(MAX_READY_CAPACITY as u64) as u32;
                log::info!(
                    "ready list of {} overflowed ({} nodes): growing to {ready}",
                    self.frame.caps.ready,
                    stats.ready_quads
                );
                self.rebuild(Capacities {
                    ready,
                    ..self.frame.caps
                })?;
                regrown += 1;
                continue;
            }
            if let Some(msg) = stats.error_message() {
                return Err(VkError::Usage(msg));
            }
            return Ok(FrameReport {
                stats,
                gpu_ms,
                regrown,
            });
        }
    }

    fn rebuild(&mut self, caps: Capacities) -> VkResult<()> {
        self.frame = FrameGpu::new(self.ctx, &self.layout, &self.scene, caps)?;
        Ok(())
    }

    fn render_once(&mut self, view: &View) -> VkResult<(GpuSubdivStats, Vec<(String, f64)>)> {
        let ctx = self.ctx;
        self.frame.set_view(ctx, &view.params)?;
        let mut pc = draw_push(
            &view.view_proj,
            view.light_dir,
            view.shade,
            &self.frame,
            self.scene.count,
        );
        pc.capture_enabled = self.frame.caps.capture as u32;
        pc.light_dir[3] = view.distance_scale;
        let sort = self.sort_ready.then_some(&self.sort);
        let (subdiv, drawer, layout, scene, frame, target, timer) = (
            &self.subdiv,
            &self.drawer,
            &self.layout,
            &self.scene,
            &self.frame,
            &self.target,
            &mut self.timer,
        );
        ctx.one_shot_with("frame", ctx.fence_timeout(), |cmd| -> VkResult<()> {
            timer.reset(cmd);
            timer.begin(cmd, "frame")?;
            subdiv.record(ctx, cmd, layout, scene, frame, Some(&mut *timer))?;
            if let Some(sort) = sort {
                sort.record(ctx, cmd, layout, frame, Some(&mut *timer))?;
            }
            drawer.record(ctx, cmd, layout, frame, target, &pc, Some(&mut *timer))?;
            timer.end(cmd, "frame")?;
            Ok(())
        })??;
        let stats = GpuSubdivStats::from_counters(&self.frame.read_counters(ctx)?);
        let gpu_ms = self.timer.read()?;
        Ok((stats, gpu_ms))
    }
}
