//! Method `subdiv`: the paper's recursive subdivision in one dispatch of
//! persistent workgroups (`glsl/subdivide.comp`), which also writes the
//! indirect arguments of the draw.

use ash::vk;

use crate::constants::*;
use crate::gpu::{FrameGpu, PushConstants, SceneGpu, SceneLayout};
use crate::vk::{
    buffer_barrier, Access, Context, GpuTimer, Pipeline, ShaderModule, VkError, VkResult,
};

/// Polls without observed progress before the kernel gives up. One idle
/// poll costs about 8 µs on this project's lavapipe (2 cores), so the cap
/// is about 2 s there and far less on a GPU; any item finishing anywhere
/// resets it, so only a truly stuck kernel reaches it.
pub const DEFAULT_IDLE_POLL_CAP: u32 = 1 << 18;

/// The persistent subdivision pass.
pub struct Subdivider {
    pipeline: Pipeline,
    /// Workgroups launched per dispatch.
    pub groups: u32,
    /// Polls without progress before `ERR_ITERATION_CAP`.
    pub idle_poll_cap: u32,
    /// Test-only fault: count one phantom item in flight that never
    /// completes, so the kernel can only end through its iteration cap.
    pub plant_endless_loop: bool,
}

/// How many workgroups to launch: about as many as the device keeps
/// resident. On a CPU device that is one per worker thread (lavapipe runs
/// each workgroup to completion on one thread); on a GPU a generous fixed
/// number, since a workgroup that starts late only finds the work taken.
pub fn default_groups(ctx: &Context) -> u32 {
    if ctx.info().is_cpu {
        let threads = std::env::var("LP_NUM_THREADS")
            .ok()
            .and_then(|s| s.parse::<u32>().ok())
            .filter(|&n| n > 0)
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get() as u32));
        threads.max(1)
    } else {
        512
    }
}

impl Subdivider {
    /// Creates the pipeline; `groups` overrides [`default_groups`].
    pub fn new(ctx: &Context, layout: &SceneLayout, groups: Option<u32>) -> VkResult<Self> {
        let shader = ShaderModule::load(ctx, "subdivide.comp")?;
        let pipeline = Pipeline::compute(ctx, "subdivide", &layout.layout, &shader, &[])?;
        Ok(Self {
            pipeline,
            groups: groups.unwrap_or_else(|| default_groups(ctx)).max(1),
            idle_poll_cap: DEFAULT_IDLE_POLL_CAP,
            plant_endless_loop: false,
        })
    }

    /// Records the reset of `frame`'s counters and queue, the subdivision
    /// dispatch, and a barrier making its results (ready list, counters and
    /// indirect arguments) visible to the draw and to transfers.
    pub fn record(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        layout: &SceneLayout,
        scene: &SceneGpu,
        frame: &FrameGpu,
        mut timer: Option<&mut GpuTimer>,
    ) -> VkResult<()> {
        if scene.count > IN_FLIGHT_MASK {
            return Err(VkError::Usage(format!(
                "{} base patches: the subdivision kernel counts at most {IN_FLIGHT_MASK}",
                scene.count
            )));
        }
        frame.record_reset(ctx, cmd);
        let in_flight = scene.count + self.plant_endless_loop as u32;
        unsafe {
            ctx.device().cmd_update_buffer(
                cmd,
                frame.counters.handle(),
                C_IN_FLIGHT as u64 * 4,
                &in_flight.to_le_bytes(),
            )
        };
        buffer_barrier(
            ctx,
            cmd,
            &frame.counters,
            Access::TRANSFER_WRITE,
            Access::ALL,
        );
        let pc = PushConstants {
            ready_capacity: frame.caps.ready,
            queue_capacity: frame.caps.queue,
            patch_count: scene.count,
            idle_poll_cap: self.idle_poll_cap,
            ..bytemuck::Zeroable::zeroed()
        };
        self.pipeline.bind(cmd);
        frame.bind(ctx, cmd, layout, vk::PipelineBindPoint::COMPUTE);
        layout.push(cmd, &pc)?;
        if let Some(t) = timer.as_deref_mut() {
            t.begin(cmd, "subdivide")?;
        }
        unsafe { ctx.device().cmd_dispatch(cmd, self.groups, 1, 1) };
        if let Some(t) = timer {
            t.end(cmd, "subdivide")?;
        }
        buffer_barrier(
            ctx,
            cmd,
            &frame.counters,
            Access::COMPUTE_READ_WRITE,
            Access::ALL,
        );
        buffer_barrier(
            ctx,
            cmd,
            &frame.ready,
            Access::COMPUTE_READ_WRITE,
            Access::ALL,
        );
        Ok(())
    }
}

/// What the subdivision pass reported through its counters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GpuSubdivStats {
    /// Ready nodes appended (may exceed the capacity: see `errors`).
    pub ready_quads: u32,
    /// Work items processed.
    pub nodes_processed: u32,
    /// Nodes dropped by the frustum test.
    pub culled_patches: u32,
    /// Ready nodes dropped as back-facing.
    pub backface_culled: u32,
    /// Deepest ready node.
    pub max_depth: u32,
    /// Ready nodes at l_max.
    pub nodes_at_lmax: u32,
    /// Triangles of the ready nodes (2 per quad + wedges).
    pub triangles: u32,
    /// Wedge triangles.
    pub wedge_triangles: u32,
    /// Donations refused because the queue was full or contended.
    pub queue_spills: u32,
    /// Items that went through the queue.
    pub queue_pushed: u32,
    /// Most items in the queue at once (sampled at pushes).
    pub queue_peak_items: u32,
    /// Most outer iterations of one invocation.
    pub iterations_max: u32,
    /// `ERR_*` bits.
    pub errors: u32,
    /// Items still counted in flight at the end (0 unless stuck).
    pub in_flight_left: u32,
}

impl GpuSubdivStats {
    /// Reads the counters words.
    pub fn from_counters(c: &[u32]) -> Self {
        let at = |i: u32| c[i as usize];
        GpuSubdivStats {
            ready_quads: at(C_READY_COUNT),
            nodes_processed: at(C_PROCESSED),
            culled_patches: at(C_CULLED),
            backface_culled: at(C_BACKFACE),
            max_depth: at(C_MAX_DEPTH),
            nodes_at_lmax: at(C_AT_LMAX),
            triangles: at(C_TRIANGLES),
            wedge_triangles: at(C_WEDGES),
            queue_spills: at(C_SPILLS),
            queue_pushed: at(C_QUEUE_PUSHED),
            queue_peak_items: at(C_QUEUE_PEAK),
            iterations_max: at(C_ITERATIONS_MAX),
            errors: at(C_ERROR),
            in_flight_left: at(C_IN_FLIGHT) & IN_FLIGHT_MASK,
        }
    }

    /// The error bits as a sentence, or `None`.
    pub fn error_message(&self) -> Option<String> {
        if self.errors == 0 {
            return None;
        }
        let mut parts = Vec::new();
        if self.errors & ERR_ITERATION_CAP != 0 {
            parts.push(format!(
                "the subdivision kernel made no progress for its whole iteration cap and gave up \
                 ({} items still in flight)",
                self.in_flight_left
            ));
        }
        if self.errors & ERR_READY_FULL != 0 {
            parts.push(format!(
                "the ready list overflowed ({} ready nodes)",
                self.ready_quads
            ));
        }
        if self.errors & ERR_STACK_OVERFLOW != 0 {
            parts.push("an invocation's depth-first stack overflowed".into());
        }
        Some(parts.join("; "))
    }
}
