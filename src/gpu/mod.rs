//! GPU resources shared by every pass: the one descriptor-set layout and
//! push-constant block (twin of `glsl/common/scene.glsl`), the uploaded
//! scene, and the per-view buffers (ready list, counters, work queue,
//! fallback vertices, debug capture).

use ash::vk;
use bytemuck::{Pod, Zeroable};

use crate::constants::*;
use crate::patch::bezier::BezierPatch;
use crate::patch::quadnode::QuadNode;
use crate::patch::view::ViewParams;
use crate::vk::{
    write_buffers, Access, Buffer, Context, DescriptorPool, MemoryLocation, PipelineLayout,
    SetLayout, VkError, VkResult,
};

/// The push-constant block of every pipeline (`Push` in scene.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct PushConstants {
    /// World → Vulkan clip space, column-major.
    pub view_proj: [f32; 16],
    /// Direction towards the light (xyz).
    pub light_dir: [f32; 4],
    /// `SHADE_*`.
    pub shade: u32,
    /// Entries in the ready list.
    pub ready_capacity: u32,
    /// Entries in the work queue.
    pub queue_capacity: u32,
    /// Base patches.
    pub patch_count: u32,
    /// Subdivision: polls without any progress anywhere before the kernel
    /// gives up with `ERR_ITERATION_CAP`.
    pub idle_poll_cap: u32,
    /// Draw: write world positions to the capture buffer.
    pub capture_enabled: u32,
    /// Sort: which pass (`sort.comp`).
    pub sort_mode: u32,
    /// Sort: bitonic stage.
    pub sort_k: u32,
    /// Sort: compare distance.
    pub sort_j: u32,
    /// Padding.
    pub pad: u32,
}

/// Bytes of [`PushConstants`].
pub const PUSH_SIZE: u32 = std::mem::size_of::<PushConstants>() as u32;

/// Shader stages that see the scene set and push constants.
pub fn scene_stages(ctx: &Context) -> vk::ShaderStageFlags {
    let mut s = vk::ShaderStageFlags::COMPUTE
        | vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::FRAGMENT;
    if ctx.info().has_mesh_shader() {
        s |= vk::ShaderStageFlags::TASK_EXT | vk::ShaderStageFlags::MESH_EXT;
    }
    s
}

/// The scene set layout and the pipeline layout built on it.
pub struct SceneLayout {
    /// Set 0: `BIND_*` bindings.
    pub set_layout: SetLayout,
    /// Set 0 plus [`PushConstants`].
    pub layout: PipelineLayout,
}

impl SceneLayout {
    /// Creates the layouts.
    pub fn new(ctx: &Context) -> VkResult<Self> {
        let mut types = vec![vk::DescriptorType::STORAGE_BUFFER; BIND_COUNT as usize];
        types[BIND_VIEW as usize] = vk::DescriptorType::UNIFORM_BUFFER;
        let stages = scene_stages(ctx);
        let set_layout = SetLayout::new(ctx, "scene set", &types, stages)?;
        let layout = PipelineLayout::new(ctx, "scene layout", &[&set_layout], PUSH_SIZE, stages)?;
        Ok(Self { set_layout, layout })
    }

    /// Records the push constants.
    pub fn push(&self, cmd: vk::CommandBuffer, pc: &PushConstants) -> VkResult<()> {
        self.layout.push(cmd, bytemuck::bytes_of(pc))
    }
}

/// The base patches on the GPU, uploaded once per scene.
pub struct SceneGpu {
    /// 48 floats per patch.
    pub patches: Buffer,
    /// One flags word per patch.
    pub flags: Buffer,
    /// Number of base patches.
    pub count: u32,
}

impl SceneGpu {
    /// Uploads patches and their flags.
    pub fn upload(ctx: &Context, patches: &[BezierPatch], flags: &[u32]) -> VkResult<Self> {
        if patches.is_empty() || patches.len() != flags.len() {
            return Err(VkError::Usage(format!(
                "{} patches with {} flag words",
                patches.len(),
                flags.len()
            )));
        }
        let floats: Vec<f32> = patches
            .iter()
            .flat_map(|p| p.pts.iter().flat_map(|q| q.to_array()))
            .collect();
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
        Ok(Self {
            patches: Buffer::with_data(
                ctx,
                "base patches",
                &floats,
                usage,
                MemoryLocation::GpuOnly,
            )?,
            flags: Buffer::with_data(ctx, "patch flags", flags, usage, MemoryLocation::GpuOnly)?,
            count: patches.len() as u32,
        })
    }
}

/// The indirect arguments the subdivision pass writes for `ready` nodes,
/// as `(word index in the counters buffer, value)` pairs. The shader computes
/// the same; tests that feed a CPU-made ready list use this.
pub fn indirect_args(ready: u32) -> Vec<(u32, u32)> {
    let per_task = MESH_NODES * TASK_MESH_GROUPS;
    vec![
        (C_READY_COUNT, ready),
        (C_MESH_ARGS, ready.div_ceil(per_task)),
        (C_MESH_ARGS + 1, 1),
        (C_MESH_ARGS + 2, 1),
        (C_EXPAND_ARGS, ready.div_ceil(EXPAND_GROUP_SIZE)),
        (C_EXPAND_ARGS + 1, 1),
        (C_EXPAND_ARGS + 2, 1),
        (C_DRAW_ARGS, ready * VERTICES_PER_NODE),
        (C_DRAW_ARGS + 1, 1),
        (C_DRAW_ARGS + 2, 0),
        (C_DRAW_ARGS + 3, 0),
    ]
    .into_iter()
    .chain(sort_args(ready))
    .collect()
}

/// The sort pass's arguments for `ready` nodes (see `glsl/sort.comp`).
fn sort_args(ready: u32) -> Vec<(u32, u32)> {
    let len = ready.max(SORT_BLOCK).next_power_of_two();
    vec![
        (C_SORT_LENGTH, len),
        (C_SORT_FILL_ARGS, (len - ready).div_ceil(SORT_GROUP_SIZE)),
        (C_SORT_FILL_ARGS + 1, 1),
        (C_SORT_FILL_ARGS + 2, 1),
        (C_SORT_GLOBAL_ARGS, len / (2 * SORT_GROUP_SIZE)),
        (C_SORT_GLOBAL_ARGS + 1, 1),
        (C_SORT_GLOBAL_ARGS + 2, 1),
        (C_SORT_BLOCK_ARGS, len / SORT_BLOCK),
        (C_SORT_BLOCK_ARGS + 1, 1),
        (C_SORT_BLOCK_ARGS + 2, 1),
    ]
}

/// Sizes of the per-view buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capacities {
    /// Ready-list entries (8 bytes each).
    pub ready: u32,
    /// Work-queue entries (16 bytes each: node, sequence number, and the
    /// copy the sequence numbers are reset from).
    pub queue: u32,
    /// Allocate the fallback path's vertex buffer (`VERTICES_PER_NODE`
    /// vertices per ready entry).
    pub vertices: bool,
    /// Allocate the debug capture of world positions (6 per ready entry).
    pub capture: bool,
}

impl Default for Capacities {
    fn default() -> Self {
        Capacities {
            ready: 1 << 18,
            queue: 1 << 16,
            vertices: false,
            capture: false,
        }
    }
}

/// The buffers of one view and the descriptor set pointing at them.
pub struct FrameGpu {
    /// `ViewParams` uniform buffer.
    pub view: Buffer,
    /// Ready QuadNodes.
    pub ready: Buffer,
    /// `COUNTER_WORDS` counters, including the indirect arguments.
    pub counters: Buffer,
    /// Work-queue nodes.
    pub queue_items: Buffer,
    /// Work-queue sequence numbers.
    pub queue_seqs: Buffer,
    /// 0, 1, 2, … copied into `queue_seqs` at the start of every frame.
    queue_seq_init: Buffer,
    /// Fallback vertices (or a 16-byte placeholder).
    pub vertices: Buffer,
    /// Capture of world positions (or a 16-byte placeholder).
    pub capture: Buffer,
    /// What was allocated.
    pub caps: Capacities,
    _pool: DescriptorPool,
    /// The scene set (set 0).
    pub set: vk::DescriptorSet,
}

impl FrameGpu {
    /// Allocates the buffers for `caps` and writes the descriptor set.
    pub fn new(
        ctx: &Context,
        layout: &SceneLayout,
        scene: &SceneGpu,
        caps: Capacities,
    ) -> VkResult<Self> {
        if caps.ready == 0 || caps.queue == 0 {
            return Err(VkError::Usage(
                "ready and queue capacities must be > 0".into(),
            ));
        }
        // Every storage buffer must fit one binding's range on this device.
        let limit = u64::from(ctx.info().limits.max_storage_buffer_range);
        let vertex_bytes = if caps.vertices {
            u64::from(caps.ready) * u64::from(VERTICES_PER_NODE * VERTEX_WORDS * 4)
        } else {
            16
        };
        let capture_bytes = if caps.capture {
            u64::from(caps.ready) * 96
        } else {
            16
        };
        for (what, bytes) in [
            ("ready list", u64::from(caps.ready) * 8),
            ("fallback vertex buffer", vertex_bytes),
            ("position capture", capture_bytes),
        ] {
            if bytes > limit {
                return Err(VkError::Usage(format!(
                    "the {what} for {} ready nodes needs {bytes} bytes, more than this device's \
                     storage-buffer range of {limit} bytes (raise ε or lower the resolution)",
                    caps.ready
                )));
            }
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let view = Buffer::new(
            ctx,
            "view params",
            std::mem::size_of::<ViewParams>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let ready = Buffer::new(ctx, "ready list", caps.ready as u64 * 8, storage, gpu)?;
        let counters = Buffer::new(
            ctx,
            "counters",
            COUNTER_WORDS as u64 * 4,
            storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            gpu,
        )?;
        let queue_items = Buffer::new(ctx, "queue items", caps.queue as u64 * 8, storage, gpu)?;
        let queue_seqs = Buffer::new(ctx, "queue seqs", caps.queue as u64 * 4, storage, gpu)?;
        let seq_init: Vec<u32> = (0..caps.queue).collect();
        let queue_seq_init = Buffer::with_data(
            ctx,
            "queue seq init",
            &seq_init,
            vk::BufferUsageFlags::TRANSFER_SRC,
            gpu,
        )?;
        let vertices = Buffer::new(ctx, "fallback vertices", vertex_bytes, storage, gpu)?;
        let capture = Buffer::new(ctx, "position capture", capture_bytes, storage, gpu)?;
        let pool = DescriptorPool::for_layout(ctx, "scene set pool", &layout.set_layout, 1)?;
        let set = pool.allocate(&layout.set_layout)?;
        let mut bound: Vec<&Buffer> = vec![&view; BIND_COUNT as usize];
        bound[BIND_PATCHES as usize] = &scene.patches;
        bound[BIND_PATCH_FLAGS as usize] = &scene.flags;
        bound[BIND_READY as usize] = &ready;
        bound[BIND_COUNTERS as usize] = &counters;
        bound[BIND_QUEUE_ITEMS as usize] = &queue_items;
        bound[BIND_QUEUE_SEQS as usize] = &queue_seqs;
        bound[BIND_VERTICES as usize] = &vertices;
        bound[BIND_CAPTURE as usize] = &capture;
        write_buffers(ctx, set, &layout.set_layout, &bound)?;
        Ok(Self {
            view,
            ready,
            counters,
            queue_items,
            queue_seqs,
            queue_seq_init,
            vertices,
            capture,
            caps,
            _pool: pool,
            set,
        })
    }

    /// Sets the view constants (host-visible; takes effect for work
    /// submitted afterwards).
    pub fn set_view(&mut self, ctx: &Context, vp: &ViewParams) -> VkResult<()> {
        self.view.write(ctx, 0, std::slice::from_ref(vp))
    }

    /// Binds the scene set at `bind_point`.
    pub fn bind(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        bind_point: vk::PipelineBindPoint,
    ) {
        unsafe {
            ctx.device().cmd_bind_descriptor_sets(
                cmd,
                bind_point,
                layout.layout.handle(),
                0,
                &[self.set],
                &[],
            )
        };
    }

    /// Records the start-of-frame reset: counters to zero, queue sequence
    /// numbers to 0, 1, 2, …, then a barrier before compute uses them.
    pub fn record_reset(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        let dev = ctx.device();
        crate::vk::buffer_barrier(
            ctx,
            cmd,
            &self.counters,
            Access::ALL,
            Access::TRANSFER_WRITE,
        );
        crate::vk::buffer_barrier(
            ctx,
            cmd,
            &self.queue_seqs,
            Access::ALL,
            Access::TRANSFER_WRITE,
        );
        unsafe {
            dev.cmd_fill_buffer(cmd, self.counters.handle(), 0, vk::WHOLE_SIZE, 0);
            let region = [vk::BufferCopy::default().size(self.caps.queue as u64 * 4)];
            dev.cmd_copy_buffer(
                cmd,
                self.queue_seq_init.handle(),
                self.queue_seqs.handle(),
                &region,
            );
        }
        crate::vk::buffer_barrier(
            ctx,
            cmd,
            &self.counters,
            Access::TRANSFER_WRITE,
            Access::ALL,
        );
        crate::vk::buffer_barrier(
            ctx,
            cmd,
            &self.queue_seqs,
            Access::TRANSFER_WRITE,
            Access::ALL,
        );
    }

    /// The counters after a frame (waits for the GPU).
    pub fn read_counters(&self, ctx: &Context) -> VkResult<Vec<u32>> {
        self.counters.read(ctx)
    }

    /// The first `count` ready nodes (waits for the GPU).
    pub fn read_ready(&self, ctx: &Context, count: u32) -> VkResult<Vec<QuadNode>> {
        let all: Vec<QuadNode> = self.ready.read(ctx)?;
        Ok(all[..(count.min(self.caps.ready)) as usize].to_vec())
    }

    /// Bytes per purpose, for the stats file.
    pub fn memory_bytes(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![
            (
                "queue",
                self.queue_items.size() + self.queue_seqs.size() + self.queue_seq_init.size(),
            ),
            ("ready_list", self.ready.size()),
            ("counters", self.counters.size()),
        ];
        if self.caps.vertices {
            v.push(("fallback_vertices", self.vertices.size()));
        }
        if self.caps.capture {
            v.push(("position_capture", self.capture.size()));
        }
        v
    }
}
