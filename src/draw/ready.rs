//! The ready list and what travels with it (descriptor set 1 of every
//! ready-list pass, `glsl/common/ready.glsl`): the ready QuadNodes, the
//! counters (statistics, producer state and every indirect argument), the
//! fallback path's vertices and the validation capture of positions.

use ash::vk;

use crate::constants::*;
use crate::patch::quadnode::QuadNode;
use crate::vk::{
    Access, Buffer, BufferBinding, Context, DescriptorSet, MemoryLocation, PipelineLayout,
    Recorder, Res, SetLayout, VkError, VkResult,
};

/// Sizes of the ready-list buffers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadyCaps {
    /// Ready-list entries (8 bytes each; a power of two of at least
    /// `SORT_BLOCK`, which the sort needs).
    pub ready: u32,
    /// Allocate the fallback path's vertex buffer (`VERTICES_PER_NODE`
    /// vertices per ready entry of one chunk, `FALLBACK_CHUNK_NODES`).
    pub vertices: bool,
    /// Allocate the capture of world positions (`NODE_MESH_SLOTS` per ready
    /// entry).
    pub capture: bool,
    /// Allocate the sort's second buffer (only a producer whose order
    /// depends on timing sorts).
    pub sort: bool,
}

impl ReadyCaps {
    /// `ready` rounded up to what the sort needs.
    pub fn rounded(self) -> Self {
        Self {
            ready: self.ready.max(SORT_BLOCK).next_power_of_two(),
            ..self
        }
    }

    /// Chunks the fallback path records to draw a full list.
    pub fn chunks(&self) -> u32 {
        self.ready.div_ceil(FALLBACK_CHUNK_NODES)
    }

    fn vertex_bytes(&self) -> u64 {
        if self.vertices {
            u64::from(self.ready.min(FALLBACK_CHUNK_NODES))
                * u64::from(VERTICES_PER_NODE * VERTEX_WORDS * 4)
        } else {
            16
        }
    }

    fn sort_bytes(&self) -> u64 {
        if self.sort {
            u64::from(self.ready) * 8
        } else {
            16
        }
    }

    /// The capture holds the first this many ready nodes: all of them
    /// where one binding allows, else as many as it can (the shaders write
    /// no further, and `validate` refuses a frame with more).
    fn capture_bytes(&self, limit: u64) -> u64 {
        const NODE_BYTES: u64 = NODE_MESH_SLOTS as u64 * 16;
        if self.capture {
            (u64::from(self.ready) * NODE_BYTES).min(limit / NODE_BYTES * NODE_BYTES)
        } else {
            16
        }
    }

    /// Refuses sizes beyond one storage-buffer binding of this device, or
    /// beyond the fallback's chunks.
    fn check(&self, ctx: &Context) -> VkResult<()> {
        if self.vertices && self.chunks() > FALLBACK_MAX_CHUNKS {
            return Err(VkError::Usage(format!(
                "a ready list of {} nodes needs {} chunks of the fallback draw path; it \
                 records at most {FALLBACK_MAX_CHUNKS} (raise ε or lower the resolution)",
                self.ready,
                self.chunks()
            )));
        }
        let limit = u64::from(ctx.info().limits.max_storage_buffer_range);
        for (what, bytes) in [
            ("ready list", u64::from(self.ready) * 8),
            ("fallback vertex buffer", self.vertex_bytes()),
        ] {
            if bytes > limit {
                return Err(VkError::OverDeviceLimit {
                    what: format!("{what} for {} ready nodes", self.ready),
                    bytes,
                    limit,
                    hint: "raise ε, lower the resolution, or take the mesh path (--draw mesh) \
                           where the device has mesh shaders: it needs no vertex buffer",
                });
            }
        }
        Ok(())
    }
}

/// Largest ready list a method grows to (8 bytes per entry, plus the
/// fallback's 240 bytes of vertices per entry).
pub const MAX_READY_CAPACITY: u32 = 1 << 24;

/// Every shader whose pipelines bind the ready set as set 1: the
/// ready-list passes, both draw paths and the producers that fill it.
pub const READY_SHADERS: &[&str] = &[
    "sort.comp",
    "expand.comp",
    "draw.vert",
    "draw.task",
    "draw.mesh",
    "levels/init.comp",
    "levels/clusters.comp",
    "levels/round.comp",
    "levels/persistent.comp",
    "subdiv/queue.comp",
    "subdiv/queue_reset.comp",
    "reorder_check.comp",
];

/// The layout of set 1 for ready-list passes (ready, counters, vertices,
/// capture, sort scratch), as [`READY_SHADERS`] declare it.
pub fn ready_set_layout(ctx: &Context) -> VkResult<SetLayout> {
    SetLayout::reflect(ctx, "ready-list set", SET_PASS, READY_SHADERS)
}

/// The ready-list buffers and set 1 pointing at them.
pub struct ReadyList {
    /// Ready QuadNodes.
    pub ready: Buffer,
    /// `COUNTERS_BUFFER_WORDS` counters, including the indirect arguments
    /// (the host reads the first `COUNTER_WORDS`).
    pub counters: Buffer,
    /// Fallback vertices of one chunk (or a 16-byte placeholder).
    pub vertices: Buffer,
    /// Capture of world positions (or a 16-byte placeholder).
    pub capture: Buffer,
    /// The sort's second buffer, as large as the list (or a 16-byte
    /// placeholder when the producer does not sort).
    pub sort_temp: Buffer,
    /// What was allocated.
    pub caps: ReadyCaps,
    set: DescriptorSet,
}

impl ReadyList {
    /// Allocates the buffers for `caps` (rounded, see [`ReadyCaps::rounded`])
    /// and writes set 1.
    pub fn new(ctx: &Context, layout: &SetLayout, caps: ReadyCaps) -> VkResult<Self> {
        let caps = caps.rounded();
        caps.check(ctx)?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let ready = Buffer::new(ctx, "ready list", u64::from(caps.ready) * 8, storage, gpu)?;
        let counters = Buffer::new(
            ctx,
            "counters",
            u64::from(COUNTERS_BUFFER_WORDS) * 4,
            storage | vk::BufferUsageFlags::INDIRECT_BUFFER,
            gpu,
        )?;
        let vertices = Buffer::new(ctx, "fallback vertices", caps.vertex_bytes(), storage, gpu)?;
        let limit = u64::from(ctx.info().limits.max_storage_buffer_range);
        let capture_bytes = caps.capture_bytes(limit);
        let capture = Buffer::new(ctx, "position capture", capture_bytes, storage, gpu)?;
        let sort_temp = Buffer::new(ctx, "sort temp", caps.sort_bytes(), storage, gpu)?;
        let mut bound = [BufferBinding::from(&ready); READY_BINDINGS as usize];
        bound[BIND_READY as usize] = (&ready).into();
        bound[BIND_COUNTERS as usize] = (&counters).into();
        bound[BIND_VERTICES as usize] = (&vertices).into();
        bound[BIND_CAPTURE as usize] = (&capture).into();
        bound[BIND_SORT_TEMP as usize] = (&sort_temp).into();
        let set = DescriptorSet::new(ctx, "ready-list set", layout, &bound)?;
        Ok(Self {
            ready,
            counters,
            vertices,
            capture,
            sort_temp,
            caps,
            set,
        })
    }

    /// Set 1: the list's buffers.
    pub fn set(&self) -> &DescriptorSet {
        &self.set
    }

    /// Records binding set 1 for `layout`.
    pub fn bind(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout<impl bytemuck::Pod>,
    ) {
        self.set.bind(ctx, cmd, bind_point, layout, SET_PASS, &[]);
    }

    /// Records zeroing the counters, with barriers from any earlier use and
    /// towards every later one (the passes after it are other recorders').
    pub fn record_reset(&self, ctx: &Context, cmd: vk::CommandBuffer) {
        let mut rec = Recorder::new(ctx, cmd);
        let counters = Res::Buffer(&self.counters);
        rec.after(counters, Access::ALL);
        rec.fill("ready list reset", &self.counters, 0);
        rec.hand_off(counters, Access::ALL);
    }

    /// The counters (waits for all submitted work).
    pub fn read_counters(&self, ctx: &Context) -> VkResult<Vec<u32>> {
        self.counters.read(ctx)
    }

    /// The first `count` ready nodes (waits for all submitted work).
    pub fn read_ready(&self, ctx: &Context, count: u32) -> VkResult<Vec<QuadNode>> {
        let all: Vec<QuadNode> = self.ready.read(ctx)?;
        Ok(all[..(count.min(self.caps.ready)) as usize].to_vec())
    }

    /// Bytes per purpose, for the stats file.
    pub fn memory_bytes(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![("ready_list", self.ready.size())];
        if self.caps.sort {
            v.push(("sort_temp", self.sort_temp.size()));
        }
        v.push(("counters", self.counters.size()));
        if self.caps.vertices {
            v.push(("fallback_vertices", self.vertices.size()));
        }
        if self.caps.capture {
            v.push(("position_capture", self.capture.size()));
        }
        v
    }
}

/// The indirect arguments a producer writes for `ready` nodes, as `(word
/// index in the counters buffer, value)` pairs. The shaders compute the
/// same (`write_ready_args` in `glsl/common/ready.glsl`); tests that feed a
/// CPU-made ready list use this.
pub fn indirect_args(ready: u32) -> Vec<(u32, u32)> {
    let per_task = MESH_NODES * TASK_MESH_GROUPS;
    let mut args = vec![
        (C_READY_COUNT, ready),
        (C_READY_FIRST, 0),
        (C_MESH_ARGS, ready.div_ceil(per_task)),
        (C_MESH_ARGS + 1, 1),
        (C_MESH_ARGS + 2, 1),
        (C_SORT_BLOCK_ARGS, ready.div_ceil(SORT_BLOCK)),
        (C_SORT_BLOCK_ARGS + 1, 1),
        (C_SORT_BLOCK_ARGS + 2, 1),
    ];
    for i in 0..SORT_MAX_MERGES {
        let a = C_SORT_MERGE_ARGS + 4 * i;
        let groups = if (SORT_BLOCK << i) < ready {
            ready.div_ceil(SORT_GROUP_SIZE)
        } else {
            0
        };
        args.extend([(a, groups), (a + 1, 1), (a + 2, 1)]);
    }
    for c in 0..FALLBACK_MAX_CHUNKS {
        let nodes = ready
            .saturating_sub(c * FALLBACK_CHUNK_NODES)
            .min(FALLBACK_CHUNK_NODES);
        let a = C_CHUNK_ARGS + CHUNK_ARG_WORDS * c;
        let expand = [nodes.div_ceil(EXPAND_GROUP_SIZE), 1, 1, 0];
        let draw = [nodes * VERTICES_PER_NODE, 1, 0, 0];
        args.extend((a..).zip(expand.into_iter().chain(draw)));
    }
    args
}
