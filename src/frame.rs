//! What one frame is recorded with: the [`View`] (criterion constants and
//! how to draw), and the [`FrameRec`] a method records its passes through:
//! the command buffer of the frame slot, the scene, the draw target, named
//! GPU timestamp scopes, and a copy-out area for whatever the host reads
//! back once the slot's fence has signalled.

use ash::vk;
use glam::{DMat4, DVec3, Vec3};

use crate::gpu::{DrawPush, DrawTarget, SceneGpu};
use crate::patch::view::ViewParams;
use crate::scene::camera::Camera;
use crate::vk::{
    Access, Buffer, Context, FrameRing, GpuTimer, Pass, PipelineLayout, PrimitiveCounter, Recorder,
    Res, VkError, VkResult, MAX_FRAME_PARTS,
};

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

    /// The draw push constants of this view for a list of `capacity`
    /// entries (`grid` cells per patch side for grid draws, else 0).
    pub fn draw_push(&self, capacity: u32, capture: bool, grid: u32) -> DrawPush {
        DrawPush {
            view_proj: self.view_proj.as_mat4().to_cols_array(),
            light_dir: self.light_dir.extend(self.distance_scale).to_array(),
            shade: self.shade,
            capacity,
            capture_enabled: capture as u32,
            grid,
            chunk: 0,
            pad: [0; 3],
        }
    }
}

/// Direction towards the light for `camera`: from above and to the left of
/// the eye, so silhouettes get a shaded side.
pub fn headlight(camera: &Camera) -> Vec3 {
    let f = camera.forward();
    let up = DVec3::from_array(camera.up);
    let right = f.cross(up).normalize_or_zero();
    let cam_up = right.cross(f).normalize_or_zero();
    (-f + cam_up * 0.6 - right * 0.5).normalize().as_vec3()
}

/// Resources replaced while earlier frames may still use them; the
/// renderer frees them once those frames have finished.
#[derive(Default)]
pub struct Retired {
    items: Vec<Box<dyn std::any::Any>>,
}

impl Retired {
    /// Keeps `resource` alive until the frames that may use it are done.
    pub fn push<T: 'static>(&mut self, resource: T) {
        self.items.push(Box::new(resource));
    }

    /// Takes everything retired so far.
    pub fn take(&mut self) -> Vec<Box<dyn std::any::Any>> {
        std::mem::take(&mut self.items)
    }

    /// Whether nothing is retired.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}

/// Words of a frame slot's copy-out area.
pub const COPY_OUT_WORDS: u32 = 1024;

/// Where a copy landed in the slot's copy-out area (in words).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CopyRange {
    /// First word.
    pub offset: u32,
    /// Number of words.
    pub len: u32,
}

/// What lets a recorder split its frame into parts: the ring whose slot it
/// records into and the slot's primitive counter (a query cannot span
/// command buffers).
struct Parts<'a> {
    frames: &'a mut FrameRing,
    primitives: &'a mut PrimitiveCounter,
    count: u32,
}

/// A method recording one frame. Created by the renderer per frame.
pub struct FrameRec<'a> {
    /// The context.
    pub ctx: &'a Context,
    /// The command buffer being recorded (the current part's, see
    /// [`FrameRec::split`]).
    pub cmd: vk::CommandBuffer,
    /// The frame slot (selects the view in set 0 and the copy-out area).
    pub slot: usize,
    /// The uploaded scene.
    pub scene: &'a SceneGpu,
    /// The view being drawn.
    pub view: &'a View,
    /// What to draw into.
    pub target: &'a DrawTarget,
    /// Capture drawn positions for validation, where the method can.
    pub capture: bool,
    /// Where a method puts buffers it replaces while recording.
    pub retired: &'a mut Retired,
    timer: &'a mut GpuTimer,
    copy_out: &'a Buffer,
    copied: u32,
    parts: Option<Parts<'a>>,
}

impl<'a> FrameRec<'a> {
    /// A recorder for slot `slot` (used by the renderer).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &'a Context,
        cmd: vk::CommandBuffer,
        slot: usize,
        scene: &'a SceneGpu,
        view: &'a View,
        target: &'a DrawTarget,
        capture: bool,
        retired: &'a mut Retired,
        timer: &'a mut GpuTimer,
        copy_out: &'a Buffer,
    ) -> Self {
        Self {
            ctx,
            cmd,
            slot,
            scene,
            view,
            target,
            capture,
            retired,
            timer,
            copy_out,
            copied: 0,
            parts: None,
        }
    }

    /// Lets the recorder split the frame (see [`FrameRec::split`]): `frames`
    /// holds the slot being recorded, `primitives` its counter, begun in
    /// the current command buffer (used by the renderer).
    pub fn with_parts(
        mut self,
        frames: &'a mut FrameRing,
        primitives: &'a mut PrimitiveCounter,
    ) -> Self {
        self.parts = Some(Parts {
            frames,
            primitives,
            count: 1,
        });
        self
    }

    /// The most parts this frame can be recorded in: 1 for a recorder
    /// without a frame ring (a one-shot command buffer).
    pub fn max_parts(&self) -> u32 {
        if self.parts.is_some() {
            MAX_FRAME_PARTS
        } else {
            1
        }
    }

    /// Parts recorded so far (1 before any split).
    pub fn parts(&self) -> u32 {
        self.parts.as_ref().map_or(1, |p| p.count)
    }

    /// Ends the current part of the frame and starts the next in a new
    /// command buffer ([`FrameRec::cmd`]): its own submission and fence, so
    /// that long work waits in pieces, each bounded by the fence timeout.
    /// Nothing carries over between parts but memory: a method re-binds its
    /// pipelines and sets, and begins rendering again (loading the target,
    /// `DrawTarget::begin_part`). Timestamp scopes may repeat in every part
    /// (they are summed); no scope may be open across a split.
    pub fn split(&mut self) -> VkResult<()> {
        let parts = self.parts.as_mut().ok_or_else(|| {
            VkError::Usage("this frame recorder cannot split (a one-shot command buffer)".into())
        })?;
        // A query begins and ends in one command buffer.
        parts.primitives.pause(self.cmd)?;
        let next = parts.frames.next_part(self.ctx, self.slot)?;
        parts.primitives.resume(next)?;
        parts.count += 1;
        self.cmd = next;
        Ok(())
    }

    /// Records binding set 0 (the scene with this slot's view) for `layout`.
    pub fn bind_scene(
        &self,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout<impl bytemuck::Pod>,
    ) {
        self.scene
            .bind(self.ctx, self.cmd, bind_point, layout, self.slot);
    }

    /// `pass` binding set 0 with this slot's view: a compute pass so
    /// declares the scene buffers its pipeline uses.
    pub fn with_scene<'p>(&self, pass: Pass<'p>) -> Pass<'p>
    where
        'a: 'p,
    {
        self.scene.bind_to(pass, self.slot)
    }

    /// Words of the slot's copy-out area taken so far.
    pub fn copied(&self) -> u32 {
        self.copied
    }

    /// The recorder of a frame's later part, whose earlier recorder took
    /// the first `words` words of the copy-out area (used by the renderer).
    pub fn after_copies(mut self, words: u32) -> Self {
        self.copied = words;
        self
    }

    /// Records `f` between the timestamps of scope `name`.
    pub fn scoped<R>(
        &mut self,
        name: &str,
        f: impl FnOnce(&mut Self) -> VkResult<R>,
    ) -> VkResult<R> {
        self.timer.begin(self.cmd, name)?;
        let out = f(self)?;
        self.timer.end(self.cmd, name)?;
        Ok(out)
    }

    /// Records copying the first `words` words of `buffer` into this slot's
    /// copy-out area (after every earlier write to `buffer`); the host reads
    /// them from the frame's [`FrameOut`].
    pub fn copy_out(&mut self, buffer: &Buffer, words: u32) -> VkResult<CopyRange> {
        let offset = self.copied;
        if offset + words > COPY_OUT_WORDS || u64::from(words) * 4 > buffer.size() {
            return Err(VkError::Usage(format!(
                "copying {words} words of `{}` out of a frame: {} of {COPY_OUT_WORDS} are taken",
                buffer.name(),
                offset
            )));
        }
        // After every earlier write of `buffer`; the copy-out area's last
        // reader, the host, waited for the slot's fence.
        let mut rec = Recorder::new(self.ctx, self.cmd);
        rec.after(Res::Buffer(buffer), Access::ALL);
        let pass = Pass::new("copy out")
            .read(Res::Buffer(buffer), Access::TRANSFER_READ)
            .write(Res::Buffer(self.copy_out), Access::TRANSFER_WRITE);
        let region = [vk::BufferCopy::default()
            .src_offset(0)
            .dst_offset(u64::from(offset) * 4)
            .size(u64::from(words) * 4)];
        let device = self.ctx.device();
        rec.run(&pass, |cmd| unsafe {
            device.cmd_copy_buffer(cmd, buffer.handle(), self.copy_out.handle(), &region)
        });
        self.copied += words;
        Ok(CopyRange { offset, len: words })
    }
}

/// A finished frame, as its method sees it: what it left for the host,
/// and where to put buffers the method replaces (a list grown after an
/// overflow).
pub struct FrameOut<'a> {
    /// The context.
    pub ctx: &'a Context,
    /// Where replaced resources go.
    pub retired: &'a mut Retired,
    words: &'a [u32],
}

impl<'a> FrameOut<'a> {
    /// Wraps the slot's copy-out words (used by the renderer).
    pub fn new(ctx: &'a Context, retired: &'a mut Retired, words: &'a [u32]) -> Self {
        Self {
            ctx,
            retired,
            words,
        }
    }

    /// The words a [`FrameRec::copy_out`] produced.
    pub fn words(&self, range: CopyRange) -> &'a [u32] {
        let end = (range.offset + range.len) as usize;
        &self.words[range.offset as usize..end.min(self.words.len())]
    }
}
