//! What the subdivision kernels report through the ready list's counters
//! (every kernel of `subdiv` and `subdiv-indirect`, the queue kernel's
//! figures too), as the frame's figures and errors.

use serde_json::json;

use crate::constants::*;
use crate::draw::{DrawPath, ReadyStage};
use crate::methods::MethodStats;

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
    /// Nodes (base patches of visible instances included) the late phase
    /// of occlusion culling found hidden; among `culled_patches` too.
    pub occluded: u32,
    /// Deepest ready node.
    pub max_depth: u32,
    /// Ready nodes at l_max.
    pub nodes_at_lmax: u32,
    /// Triangles of the ready nodes (2 per quad + wedges).
    pub triangles: u32,
    /// Wedge triangles.
    pub wedge_triangles: u32,
    /// Items a full queue refused (they stayed in their workgroup).
    pub queue_spills: u32,
    /// Queue operations that lost a compare-and-swap (retried later).
    pub queue_retries: u32,
    /// Polls by waiting workgroups (the queue kernel's idle ones, the level
    /// kernel's at its barriers).
    pub idle_polls: u32,
    /// Atomic read-modify-write operations on global memory.
    pub global_atomics: u32,
    /// Items that went through the queue.
    pub queue_pushed: u32,
    /// Most items in the queue at once (sampled at pushes).
    pub queue_peak_items: u32,
    /// Most outer iterations of one workgroup (queue kernel).
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
            occluded: at(C_OCCLUDED),
            max_depth: at(C_MAX_DEPTH),
            nodes_at_lmax: at(C_AT_LMAX),
            triangles: at(C_TRIANGLES),
            wedge_triangles: at(C_WEDGES),
            queue_spills: at(C_SPILLS),
            queue_retries: at(C_QUEUE_RETRIES),
            idle_polls: at(C_IDLE_POLLS),
            global_atomics: at(C_GLOBAL_ATOMICS),
            queue_pushed: at(C_QUEUE_PUSHED),
            queue_peak_items: at(C_QUEUE_PEAK),
            iterations_max: at(C_ITERATIONS_MAX),
            errors: at(C_ERROR),
            in_flight_left: at(C_IN_FLIGHT) & IN_FLIGHT_MASK,
        }
    }

    /// The common keys plus the method's own section, for a frame drawn
    /// from `stage`'s list.
    pub fn method_stats(&self, stage: &ReadyStage) -> MethodStats {
        let ready_capacity = stage.list().caps.ready;
        // The fallback draws every node's NODE_MESH_TRIS slots, a missing
        // wedge as a degenerate triangle.
        let placeholder_triangles = match stage.path() {
            DrawPath::Mesh => 0,
            DrawPath::Fallback => (u64::from(NODE_MESH_TRIS) * u64::from(self.ready_quads))
                .saturating_sub(u64::from(self.triangles)),
        };
        MethodStats {
            triangles: u64::from(self.triangles),
            placeholder_triangles,
            culled_patches: u64::from(self.culled_patches),
            own: vec![
                ("ready_quads", json!(self.ready_quads)),
                ("wedge_triangles", json!(self.wedge_triangles)),
                ("backface_culled", json!(self.backface_culled)),
                ("occluded", json!(self.occluded)),
                ("max_depth", json!(self.max_depth)),
                ("nodes_at_lmax", json!(self.nodes_at_lmax)),
                ("nodes_processed", json!(self.nodes_processed)),
                ("queue_peak_items", json!(self.queue_peak_items)),
                ("queue_spills", json!(self.queue_spills)),
                ("queue_pushed", json!(self.queue_pushed)),
                ("queue_retries", json!(self.queue_retries)),
                ("iterations_max", json!(self.iterations_max)),
                ("idle_polls", json!(self.idle_polls)),
                ("global_atomics", json!(self.global_atomics)),
                (
                    "global_atomics_per_node",
                    json!(f64::from(self.global_atomics) / f64::from(self.nodes_processed.max(1))),
                ),
                ("ready_capacity_items", json!(ready_capacity)),
            ],
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
                "the ready list overflowed ({} ready nodes) and cannot grow further",
                self.ready_quads
            ));
        }
        if self.errors & ERR_STACK_OVERFLOW != 0 {
            parts.push("a workgroup's deque of the queue kernel overflowed".into());
        }
        if self.errors & ERR_WATCHDOG != 0 {
            parts.push("the persistent kernel's watchdog tripped".into());
        }
        if self.errors & ERR_LEVEL_REGION != 0 {
            parts.push(
                "nodes split deeper than the node memory has regions for (their children \
                 were dropped, not drawn)"
                    .into(),
            );
        }
        Some(parts.join("; "))
    }
}
