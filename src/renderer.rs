//! The renderer: one uploaded scene, any number of methods, frames in
//! flight. Used by `render`, `validate` and the tests (and by `bench` and
//! the window to come).
//!
//! - The scene is uploaded once; methods are made on first use and kept,
//!   so switching methods, ε or λ reuses the scene, the shader modules and
//!   each method's pipelines and buffers.
//! - [`Renderer::submit`] records a frame into the next of N frame slots
//!   (each with its own command buffer, fence, view constants, timestamp
//!   queries and copy-out area) and returns without waiting;
//!   [`Renderer::collect`] waits for that slot and reads its figures.
//!   [`Renderer::render`] is both, repeated while the method asks to redo
//!   the frame (a list that overflowed was grown).
//! - Buffers a method replaces go to a deferred-release list and are freed
//!   only after every frame submitted before the replacement has finished.
//! - Dropping the renderer waits for its frames; work that never finishes
//!   makes it leak instead of freeing memory the GPU may still use.

use std::any::Any;
use std::sync::Arc;
use std::time::Duration;

use ash::vk;

mod levels;

use crate::anim::Animation;
use crate::constants::FALLBACK_MAX_CHUNKS;
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired, View, COPY_OUT_WORDS};
use crate::gpu::anim::AnimGpu;
use crate::gpu::{DrawTarget, SceneGpu, SceneLayout, SceneSpec, Shaders};
use crate::lod::gpu::{Lod, LodFrame};
use crate::methods::{
    self, Finished, Method, MethodOptions, MethodSetup, MethodStats, RenderError,
};
use crate::patch::view::ViewParams;
use crate::scene::geometry::{SceneGeometry, SceneShading};
use crate::vk::{
    Access, Buffer, Context, FrameRing, GpuTimer, MemoryLocation, PrimitiveCounter, PrimitiveQuery,
    ProgressSink, Recorder, Res, VkError, VkResult, MAX_FRAME_PARTS,
};

/// Frames in flight unless told otherwise.
pub const DEFAULT_FRAMES_IN_FLIGHT: usize = 2;

/// Timestamp scopes per frame: the frame, and a method's passes, some of
/// them once per part of a frame recorded in parts, and the fallback's
/// expansion and draw once per chunk in each of occlusion culling's two
/// phases.
const MAX_SCOPES: u32 = 12 + 3 * MAX_FRAME_PARTS + 2 * 2 * FALLBACK_MAX_CHUNKS;

/// How a renderer is set up.
#[derive(Clone, Debug)]
pub struct RendererOptions {
    /// Target size in pixels (the tolerance is measured in them).
    pub size: (u32, u32),
    /// Background the target is cleared to.
    pub background: [f32; 4],
    /// Frame slots (frames in flight).
    pub frames_in_flight: usize,
    /// The methods' knobs.
    pub methods: MethodOptions,
}

/// What one frame reported.
#[derive(Clone, Debug)]
pub struct FrameReport {
    /// The method that drew it.
    pub method: &'static str,
    /// Its draw path, in words.
    pub draw_path: &'static str,
    /// The common keys and the method's own section.
    pub stats: MethodStats,
    /// GPU time per named scope, in milliseconds ("frame" is the whole).
    pub gpu_ms: Vec<(String, f64)>,
    /// Times the frame was drawn again after the method grew a buffer.
    pub redone: u32,
    /// The frame (or one it was redone after) ran a pipeline for the first
    /// time on a device that compiles at first use: its times include the
    /// compile.
    pub compiled: bool,
    /// The primitives the frame's draws generated, counted by a query (the
    /// same for every method), and which query; `None` where the device
    /// has no query for the frame's kind of pipeline.
    pub primitives: Option<(PrimitiveQuery, u64)>,
    /// What levels of detail drew (nothing unless the renderer has levels,
    /// [`Renderer::set_levels`]).
    pub lod: LodFrame,
}

impl FrameReport {
    /// Triangles drawn: the query's count less the placeholders the method
    /// drew (which cover nothing), else the method's own count; and the
    /// levels of detail's (counted on the host: their draw is recorded
    /// after the method's query).
    pub fn triangles(&self) -> u64 {
        self.method_triangles() + self.lod.triangles
    }

    /// The method's share of [`FrameReport::triangles`].
    pub fn method_triangles(&self) -> u64 {
        self.primitives.map_or(self.stats.triangles, |(_, n)| {
            n.saturating_sub(self.stats.placeholder_triangles)
        })
    }

    /// Where [`FrameReport::triangles`] comes from, in words.
    pub fn triangles_source(&self) -> String {
        match self.primitives {
            None => "method".into(),
            Some((q, _)) if self.stats.placeholder_triangles > 0 => {
                format!("{}, less the fallback's placeholder slots", q.name())
            }
            Some((q, _)) => q.name().into(),
        }
    }

    /// GPU milliseconds of scope `name`, if it was timed.
    pub fn ms(&self, name: &str) -> Option<f64> {
        self.gpu_ms
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, ms)| *ms)
    }
}

/// A submitted frame, to hand to [`Renderer::collect`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[must_use = "a submitted frame's figures are read by collect()"]
pub struct FrameTicket {
    slot: usize,
    serial: u64,
}

/// Per frame slot: its timestamps, its copy-out area, and what it ran.
struct SlotData {
    timer: GpuTimer,
    primitives: PrimitiveCounter,
    copy_out: Buffer,
    /// (method index, serial) of the frame recorded here and not yet
    /// collected.
    frame: Option<(usize, u64)>,
    /// Whether that frame may wait for a compile ([`FrameReport::compiled`]).
    compiled: bool,
    /// Where the level cull's counters landed in the copy-out area, and
    /// the levels' bytes, when levels drew in it.
    lod: Option<(CopyRange, u64)>,
}

/// The renderer.
pub struct Renderer {
    // Dropped first: waits for the frames still running (or declares the
    // device hung) before anything they use is freed.
    frames: FrameRing,
    slots: Vec<SlotData>,
    methods: Vec<Box<dyn Method>>,
    active: usize,
    options: MethodOptions,
    target: DrawTarget,
    scene: SceneGpu,
    scene_layout: SceneLayout,
    shaders: Shaders,
    /// Released once the slot in `.0` has finished (see `collect`).
    retired: Vec<(usize, Box<dyn Any>)>,
    last_submitted: Option<usize>,
    serial: u64,
    /// Capture drawn positions for validation (ready-list methods).
    pub capture: bool,
    /// What moves, its update pass, and the time frames are drawn at.
    anim: Option<(Animation, AnimGpu)>,
    time: f64,
    /// Levels of detail below a patch (`None`: every instance from its
    /// patches, as before they existed).
    lod: Option<Lod>,
    ctx: Arc<Context>,
}

impl Renderer {
    /// Uploads `geo` and the shading normals' tangent patches `shading`
    /// (`Scene::geometry_and_shading`; `SceneShading::from_geometry` shades
    /// with the patches' own derivatives), creates the frame slots and the
    /// target, and makes method `method`.
    pub fn new(
        ctx: Arc<Context>,
        geo: &SceneGeometry,
        shading: &SceneShading,
        method: &str,
        options: RendererOptions,
    ) -> Result<Self, RenderError> {
        options
            .methods
            .per_method
            .check()
            .map_err(RenderError::Request)?;
        let n = options.frames_in_flight.max(1);
        let scene_layout = SceneLayout::new(&ctx)?;
        let scene = SceneGpu::for_geometry(&ctx, &scene_layout, geo, shading, n)?;
        let (w, h) = options.size;
        let target =
            DrawTarget::with_samples(&ctx, w, h, options.background, options.methods.samples)?;
        let mut shaders = Shaders::default();
        shaders.samples = target.samples();
        shaders.scene = SceneSpec::of(&scene);
        let frames = FrameRing::new(&ctx, n)?;
        let slots = (0..n)
            .map(|i| {
                Ok(SlotData {
                    timer: GpuTimer::new(&ctx, MAX_SCOPES)?,
                    primitives: PrimitiveCounter::new(&ctx)?,
                    copy_out: Buffer::new(
                        &ctx,
                        &format!("copy-out of frame slot {i}"),
                        u64::from(COPY_OUT_WORDS) * 4,
                        vk::BufferUsageFlags::TRANSFER_DST,
                        MemoryLocation::GpuToCpu,
                    )?,
                    frame: None,
                    compiled: false,
                    lod: None,
                })
            })
            .collect::<VkResult<Vec<_>>>()?;
        let mut r = Self {
            frames,
            slots,
            methods: Vec::new(),
            active: 0,
            options: options.methods,
            target,
            scene,
            scene_layout,
            shaders,
            retired: Vec::new(),
            last_submitted: None,
            serial: 0,
            capture: false,
            anim: None,
            time: 0.0,
            lod: None,
            ctx,
        };
        r.set_method(method)?;
        Ok(r)
    }

    /// The context.
    pub fn context(&self) -> &Arc<Context> {
        &self.ctx
    }

    /// Where waits for frames recorded in more than one part report their
    /// progress (a terminal's progress bar; `None`: nowhere).
    pub fn set_progress(&mut self, sink: Option<ProgressSink>) {
        self.frames.set_progress(sink);
    }

    /// Switches to method `name`, making it on first use.
    pub fn set_method(&mut self, name: &str) -> Result<(), RenderError> {
        let info = methods::find(name)?;
        methods::check_rational(info, &self.scene)?;
        methods::check_pn(info, &self.scene)?;
        if let Some(i) = self.methods.iter().position(|m| m.name() == info.name) {
            self.active = i;
            return Ok(());
        }
        let method = (info.build)(&mut MethodSetup {
            ctx: &self.ctx,
            shaders: &mut self.shaders,
            scene_layout: &self.scene_layout,
            options: &self.options,
        })?;
        self.methods.push(method);
        self.active = self.methods.len() - 1;
        Ok(())
    }

    /// The active method.
    pub fn method(&self) -> &dyn Method {
        self.methods[self.active].as_ref()
    }

    /// The methods' knobs.
    pub fn options(&self) -> &MethodOptions {
        &self.options
    }

    /// Changes the methods' knobs (refused, with nothing changed, where a
    /// method's check refuses them). Each method made so far applies them in
    /// place where it can and is made again otherwise (the active one right
    /// away, the others on use).
    pub fn set_options(&mut self, options: MethodOptions) -> Result<(), RenderError> {
        if options == self.options {
            return Ok(());
        }
        options.per_method.check().map_err(RenderError::Request)?;
        // Methods are remade below, so frames in flight can no longer be
        // finished by the method that recorded them, and their first
        // frames compile again.
        self.forget_frames();
        if options.samples != self.options.samples {
            return self.set_samples(options);
        }
        let name = self.method().name();
        let mut retired = Retired::default();
        let mut kept = Vec::new();
        let mut result = Ok(());
        for mut m in std::mem::take(&mut self.methods) {
            let mut setup = MethodSetup {
                ctx: &self.ctx,
                shaders: &mut self.shaders,
                scene_layout: &self.scene_layout,
                options: &options,
            };
            match m.reconfigure(&mut setup, &mut retired) {
                Ok(true) => kept.push(m),
                Ok(false) => retired.push(m),
                Err(e) => {
                    retired.push(m);
                    result = Err(e);
                }
            }
        }
        // Methods dropped here may have frames in flight.
        self.defer(retired);
        self.methods = kept;
        self.options = options;
        result?;
        self.set_method(name)
    }

    /// A new sample count: a new target, and every method made again (their
    /// draw pipelines are per sample count).
    fn set_samples(&mut self, options: MethodOptions) -> Result<(), RenderError> {
        let (w, h) = self.target.size();
        let target = DrawTarget::with_samples(&self.ctx, w, h, self.target.clear, options.samples)?;
        let mut retired = Retired::default();
        retired.push(std::mem::replace(&mut self.target, target));
        self.defer(retired);
        self.shaders.samples = self.target.samples();
        self.options = options;
        self.remake_methods()
    }

    /// Drops the figures of the frames not yet collected: their tickets
    /// then get [`RenderError::Request`] from `collect`.
    fn forget_frames(&mut self) {
        for data in &mut self.slots {
            data.frame = None;
        }
    }

    /// Resizes the draw target (the old one is freed after the frames that
    /// may use it). ε is measured in the new size's pixels from the next
    /// view on.
    pub fn set_size(&mut self, size: (u32, u32)) -> Result<(), RenderError> {
        if size == self.target.size() {
            return Ok(());
        }
        let target = DrawTarget::with_samples(
            &self.ctx,
            size.0,
            size.1,
            self.target.clear,
            self.options.samples,
        )?;
        let mut retired = Retired::default();
        retired.push(std::mem::replace(&mut self.target, target));
        self.defer(retired);
        Ok(())
    }

    /// Replaces the scene and its shading patches. The new ones are uploaded
    /// first, so a failure leaves the renderer as it was and usable.
    pub fn set_geometry(
        &mut self,
        geo: &SceneGeometry,
        shading: &SceneShading,
    ) -> Result<(), RenderError> {
        let scene = SceneGpu::for_geometry(
            &self.ctx,
            &self.scene_layout,
            geo,
            shading,
            self.frames.len(),
        )?;
        methods::check_rational(methods::find(self.method().name())?, &scene)?;
        methods::check_pn(methods::find(self.method().name())?, &scene)?;
        self.frames.wait_all()?;
        self.scene = scene;
        // The animation wrote into the old scene's patches, and the levels
        // were the old scene's models.
        self.anim = None;
        self.lod = None;
        let spec = SceneSpec::of(&self.scene);
        if spec != self.shaders.scene {
            // The methods' pipelines were specialized for the old scene.
            self.shaders.scene = spec;
            self.remake_methods()?;
        }
        Ok(())
    }

    /// Every method made again (the active one now, the others on use):
    /// their pipelines depend on the sample count or on the scene.
    fn remake_methods(&mut self) -> Result<(), RenderError> {
        self.forget_frames();
        let name = self.method().name();
        let mut retired = Retired::default();
        for m in std::mem::take(&mut self.methods) {
            retired.push(m);
        }
        self.defer(retired);
        self.set_method(name)
    }

    /// Forgets what occlusion culling learnt from earlier frames: the next
    /// frame culls as the first frame of the scene does, whatever was drawn
    /// before (`validate` checks each keyframe from that state).
    pub fn reset_visibility(&mut self) -> Result<(), RenderError> {
        self.frames.wait_all()?;
        Ok(self.scene.reset_visibility(&self.ctx)?)
    }

    /// Whether frames from now on keep their depth, for
    /// [`Renderer::read_depth`].
    pub fn set_keep_depth(&mut self, keep: bool) {
        self.target.set_keep_depth(keep);
    }

    /// The last frame's depth, f32 rows top first (see
    /// [`Renderer::set_keep_depth`]; single-sampled targets).
    pub fn read_depth(&self) -> VkResult<Vec<f32>> {
        self.target.read_depth(&self.ctx)
    }

    /// What the uploaded scene holds that pipelines are specialized on.
    pub fn scene_spec(&self) -> SceneSpec {
        self.shaders.scene
    }

    /// Animates the uploaded scene (`None`: it stands still, and frames
    /// record no update pass): every frame from now on first runs the
    /// update pass at the time [`Renderer::set_time`] gave. The animation
    /// must be the uploaded scene's (its instances' patches lie in it).
    pub fn set_animation(&mut self, anim: Option<Animation>) -> Result<(), RenderError> {
        let made = match anim {
            Some(a) => {
                let gpu = AnimGpu::new(
                    &self.ctx,
                    &mut self.shaders,
                    &a,
                    &self.scene,
                    self.frames.len(),
                )?;
                Some((a, gpu))
            }
            None => None,
        };
        if let Some(old) = std::mem::replace(&mut self.anim, made) {
            let mut retired = Retired::default();
            retired.push(old.1);
            self.defer(retired);
        }
        Ok(())
    }

    /// The animation, if the scene moves.
    pub fn animation(&self) -> Option<&Animation> {
        self.anim.as_ref().map(|a| &a.0)
    }

    /// The time (seconds) the next frames are drawn at.
    pub fn set_time(&mut self, t: f64) {
        self.time = t;
    }

    /// The time frames are drawn at.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// How many shader modules are loaded (each once per renderer).
    pub fn shaders_loaded(&self) -> usize {
        self.shaders.loaded()
    }

    /// How many methods are made and kept.
    pub fn methods_made(&self) -> usize {
        self.methods.len()
    }

    /// The uploaded scene.
    pub fn scene(&self) -> &SceneGpu {
        &self.scene
    }

    /// The scene's set layout (set 0 of every pipeline layout).
    pub fn scene_layout(&self) -> &SceneLayout {
        &self.scene_layout
    }

    /// The draw target.
    pub fn target(&self) -> &DrawTarget {
        &self.target
    }

    /// The background the target is cleared to.
    pub fn set_background(&mut self, rgba: [f32; 4]) {
        self.target.clear = rgba;
    }

    /// The criterion constants the active method runs `view` with (its own
    /// depth limit, for one): what the oracle must be given to compare.
    pub fn effective_params(&self, view: &View) -> ViewParams {
        let mut params = view.params;
        self.method().adjust_view(&mut params);
        params
    }

    /// The image of the last frame as RGBA8 rows (waits for the GPU).
    pub fn read_image(&self) -> VkResult<Vec<u8>> {
        self.target.read_rgba(&self.ctx)
    }

    /// GPU memory per purpose: the scene's and the active method's.
    pub fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![
            ("base_patches", self.scene.bytes()),
            ("shading_patches", self.scene.shading_bytes()),
            ("instances", self.scene.instance_bytes()),
            ("occlusion_clusters", self.scene.cluster_bytes()),
        ];
        if let Some(bytes) = self.scene.weight_bytes() {
            v.push(("patch_weights", bytes));
        }
        if let Some(bytes) = self.scene.material_bytes() {
            v.push(("uv_patches_and_maps", bytes));
        }
        if let Some((_, gpu)) = &self.anim {
            v.push(("animation", gpu.bytes()));
        }
        if let Some(lod) = &self.lod {
            v.push(("levels_of_detail", lod.bytes()));
            // Their per-instance choice and draws, and the depth pyramid
            // their cull reads (with occlusion culling on).
            v.push(("levels_of_detail_cull", lod.memory() - lod.bytes()));
        }
        v.extend(self.method().memory());
        v
    }

    /// Records `view` with the active method into the next frame slot and
    /// submits it (waiting first, bounded, for the frame that used the slot
    /// before, whose figures are then lost unless it was collected). A
    /// recording that fails is discarded, never submitted.
    pub fn submit(&mut self, view: &View) -> Result<FrameTicket, RenderError> {
        let slot = self.frames.next_slot();
        // The slot's previous frame: its timestamps and copy-out area are
        // about to be overwritten, and its garbage can go.
        self.frames.wait(slot)?;
        self.release_garbage(slot);
        self.slots[slot].frame = None;
        let params = self.effective_params(view);
        self.scene.set_view(&self.ctx, slot, &params)?;
        let (slot, cmd) = self.frames.begin()?;
        let mut retired = Retired::default();
        let recorded = self.record(slot, cmd, view, &params, &mut retired);
        // Whatever was retired while recording may still be used by the
        // frames submitted before this one.
        self.defer(retired);
        if let Err(e) = recorded {
            self.frames.abandon(slot);
            return Err(e);
        }
        // A frame that runs a pipeline for the first time may also wait
        // for the driver's compile (Context::take_compile_allowance).
        let name = self.method().name();
        self.frames
            .submit(&self.ctx, slot, &format!("frame ({name})"))?;
        if let Some(lod) = &mut self.lod {
            lod.submitted();
        }
        self.slots[slot].compiled = self.frames.compile_allowance(slot) > Duration::ZERO;
        self.serial += 1;
        self.slots[slot].frame = Some((self.active, self.serial));
        self.last_submitted = Some(slot);
        Ok(FrameTicket {
            slot,
            serial: self.serial,
        })
    }

    fn record(
        &mut self,
        slot: usize,
        cmd: vk::CommandBuffer,
        view: &View,
        params: &ViewParams,
        retired: &mut Retired,
    ) -> Result<(), RenderError> {
        let levels_now = self.prepare_levels(cmd, params)?;
        let data = &mut self.slots[slot];
        data.timer.reset(cmd);
        data.primitives.reset(cmd);
        // The whole frame is one scope, across its parts: timestamps,
        // unlike queries, may begin and end in different command buffers.
        data.timer.begin(cmd, "frame")?;
        if let Some((anim, gpu)) = &mut self.anim {
            // The scene at this frame's time, before any method reads it.
            let frame = anim.frame(self.time);
            data.timer.begin(cmd, "update")?;
            gpu.record(&self.ctx, cmd, slot, &frame)?;
            data.timer.end(cmd, "update")?;
        }
        // Begun after the update pass (which draws nothing), so an update
        // that fails leaves no query open in the abandoned command buffer.
        let mesh = self.methods[self.active].uses_mesh_shaders();
        data.primitives.begin(cmd, mesh)?;
        // The command buffer of the last part the method recorded, and
        // whether it recorded the frame.
        let (recorded, last, copied) = {
            let mut f = FrameRec::new(
                &self.ctx,
                cmd,
                slot,
                &self.scene,
                view,
                &self.target,
                self.capture,
                retired,
                &mut data.timer,
                &data.copy_out,
            )
            .with_parts(&mut self.frames, &mut data.primitives);
            let recorded = self.methods[self.active].record(&mut f);
            (recorded, f.cmd, f.copied())
        };
        // The query ends even when the method refused the frame, so the
        // abandoned command buffer is still well formed.
        let ended = data.primitives.end(last);
        self.target.set_more_parts(false);
        recorded?;
        ended?;
        data.lod = None;
        if let Some(lod) = self.lod.as_mut().filter(|_| levels_now) {
            let mut f = FrameRec::new(
                &self.ctx,
                last,
                slot,
                &self.scene,
                view,
                &self.target,
                false,
                retired,
                &mut data.timer,
                &data.copy_out,
            )
            .after_copies(copied);
            let (shaders, layout) = (&mut self.shaders, &self.scene_layout);
            let occlusion = self.options.occlusion;
            let counters = f.scoped("levels", |f| lod.record(f, shaders, layout, occlusion))?;
            data.lod = Some((counters, lod.bytes()));
        }
        data.timer.end(last, "frame")?;
        // Everything the frame wrote, for the host after the fence.
        let mut rec = Recorder::new(&self.ctx, last);
        rec.after(Res::Memory, Access::ALL);
        rec.host_read();
        Ok(())
    }

    /// Waits for the frame of `ticket` and reads its figures.
    pub fn collect(&mut self, ticket: FrameTicket) -> Result<(FrameReport, bool), RenderError> {
        let slot = ticket.slot;
        let Some((method, serial)) = self.slots[slot].frame else {
            return Err(RenderError::Request(
                "that frame's figures are gone: it was already collected, or the \
                 methods were remade since"
                    .into(),
            ));
        };
        if serial != ticket.serial {
            return Err(RenderError::Request(
                "that frame's slot was reused before it was collected".into(),
            ));
        }
        self.frames.wait(slot)?;
        self.release_garbage(slot);
        self.slots[slot].frame = None;
        let data = &self.slots[slot];
        let compiled = data.compiled;
        let gpu_ms = data.timer.read()?;
        let primitives = data.primitives.read()?;
        let words: Vec<u32> = data
            .copy_out
            .mapped()
            .map(bytemuck::pod_collect_to_vec)
            .ok_or_else(|| VkError::Usage("a frame's copy-out area is not mapped".into()))?;
        let mut retired = Retired::default();
        let finished =
            self.methods[method].finish(&mut FrameOut::new(&self.ctx, &mut retired, &words));
        self.defer(retired);
        let (stats, redo) = match finished? {
            Finished::Done(stats) => (stats, false),
            Finished::Redo { reason } => {
                log::info!(
                    "{}: {reason}; drawing the frame again",
                    self.methods[method].name()
                );
                (MethodStats::default(), true)
            }
        };
        let m = &self.methods[method];
        Ok((
            FrameReport {
                method: m.name(),
                draw_path: m.draw_path(),
                stats,
                gpu_ms,
                redone: 0,
                compiled,
                primitives,
                lod: self.slots[slot]
                    .lod
                    .map(|(r, bytes)| {
                        let at = r.offset as usize;
                        LodFrame::from_counters(&words[at..at + r.len as usize], bytes)
                    })
                    .unwrap_or_default(),
            },
            redo,
        ))
    }

    /// Renders `view` completely: submit and collect, again while the
    /// method grows what overflowed.
    pub fn render(&mut self, view: &View) -> Result<FrameReport, RenderError> {
        let mut redone = 0;
        let mut compiled = false;
        loop {
            let ticket = self.submit(view)?;
            let (mut report, redo) = self.collect(ticket)?;
            compiled |= report.compiled;
            if !redo {
                report.redone = redone;
                report.compiled = compiled;
                return Ok(report);
            }
            redone += 1;
            if redone > 8 {
                return Err(RenderError::Method {
                    method: report.method,
                    message: "still incomplete after growing its buffers 8 times".into(),
                });
            }
        }
    }

    /// Waits for every frame in flight and frees what they kept alive.
    pub fn wait_idle(&mut self) -> VkResult<()> {
        self.frames.wait_all()?;
        self.collect_garbage_all();
        Ok(())
    }

    /// Frees now, or after the last submitted frame, what `retired` holds.
    fn defer(&mut self, mut retired: Retired) {
        let items = retired.take();
        match self.last_submitted {
            Some(s) if self.frames.in_flight(s) => {
                self.retired.extend(items.into_iter().map(|x| (s, x)));
            }
            _ => drop(items),
        }
    }

    /// Frees what waited for slot `slot`'s frame (which has finished; every
    /// earlier frame has too, the queue being in order).
    fn release_garbage(&mut self, slot: usize) {
        self.retired.retain(|(s, _)| *s != slot);
    }

    fn collect_garbage_all(&mut self) {
        self.retired.clear();
    }
}

/// What a method's own `validate` checks read of the frame just drawn.
impl crate::methods::checks::CheckFrame for Renderer {
    fn context(&self) -> &Context {
        Renderer::context(self)
    }

    fn method(&self) -> &dyn Method {
        Renderer::method(self)
    }
}
