//! Constants shared with the shaders: a mirror of `glsl/common/constants.glsl`,
//! name for name and value for value (`tests/constants.rs` checks that they
//! agree). The GLSL file explains each group.

pub const L_MAX: u32 = 10;

// QuadNode word 1 layout: depth 4 | m 10 | n 10 | l0 4 | l1 4.
pub const NODE_DEPTH_SHIFT: u32 = 0;
pub const NODE_M_SHIFT: u32 = 4;
pub const NODE_N_SHIFT: u32 = 14;
pub const NODE_L0_SHIFT: u32 = 24;
pub const NODE_L1_SHIFT: u32 = 28;

// f32(1/3) and f32(2/3) as bits: the literals cannot be misread.
pub const THIRD_BITS: u32 = 0x3eaa_aaab;
pub const TWO_THIRDS_BITS: u32 = 0x3f2a_aaab;

// ViewParams.flags.
pub const FLAG_FRUSTUM_CULL: u32 = 1;
pub const FLAG_BACKFACE_CULL: u32 = 2;
pub const FLAG_WEDGES: u32 = 4;
// Test-only: donate to the work queue on every split, not only when some
// invocation is idle, to exercise the queue (and its overflow) hard.
pub const FLAG_QUEUE_STRESS: u32 = 0x4000_0000;

// Per-patch flags word.
pub const PATCH_TWO_SIDED: u32 = 1;
pub const PATCH_MODEL_SHIFT: u32 = 16;

// Descriptor bindings of the one scene set every pass uses.
pub const BIND_VIEW: u32 = 0;
pub const BIND_PATCHES: u32 = 1;
pub const BIND_PATCH_FLAGS: u32 = 2;
pub const BIND_READY: u32 = 3;
pub const BIND_COUNTERS: u32 = 4;
pub const BIND_QUEUE_ITEMS: u32 = 5;
pub const BIND_QUEUE_SEQS: u32 = 6;
pub const BIND_VERTICES: u32 = 7;
pub const BIND_CAPTURE: u32 = 8;
pub const BIND_COUNT: u32 = 9;

// Indices into the counters buffer (uint words).
pub const C_READY_COUNT: u32 = 0;
pub const C_IN_FLIGHT: u32 = 1;
pub const C_NEXT_BASE: u32 = 2;
pub const C_QUEUE_HEAD: u32 = 3;
pub const C_QUEUE_TAIL: u32 = 4;
pub const C_IDLE: u32 = 5;
pub const C_ERROR: u32 = 6;
pub const C_PROCESSED: u32 = 7;
pub const C_CULLED: u32 = 8;
pub const C_BACKFACE: u32 = 9;
pub const C_MAX_DEPTH: u32 = 10;
pub const C_AT_LMAX: u32 = 11;
pub const C_SPILLS: u32 = 12;
pub const C_QUEUE_PEAK: u32 = 13;
pub const C_QUEUE_PUSHED: u32 = 14;
pub const C_TRIANGLES: u32 = 15;
pub const C_WEDGES: u32 = 16;
pub const C_ITERATIONS_MAX: u32 = 17;
// Validation passes (reorder_check.comp): nodes checked, nodes failing.
pub const C_CHECK_NODES: u32 = 18;
pub const C_CHECK_FAILS: u32 = 19;
// counters[C_IN_FLIGHT]: items in flight in the low 24 bits (so at most
// 2^24 - 1 base patches), a wrapping progress tick in the top byte.
pub const IN_FLIGHT_MASK: u32 = 0x00ff_ffff;
pub const IN_FLIGHT_TICK: u32 = 0x0100_0000;
// Indirect arguments, written by the subdivision pass.
/// vkCmdDrawMeshTasksIndirectEXT: x, y, z
pub const C_MESH_ARGS: u32 = 32;
/// vkCmdDispatchIndirect: x, y, z
pub const C_EXPAND_ARGS: u32 = 36;
/// vkCmdDrawIndirect: vertices, instances, first vertex, first instance
pub const C_DRAW_ARGS: u32 = 40;
// Sorting the ready list (sort.comp): the padded length, and dispatch
// arguments for the padding fill, the global and the in-block passes.
pub const C_SORT_LENGTH: u32 = 44;
pub const C_SORT_FILL_ARGS: u32 = 48;
pub const C_SORT_GLOBAL_ARGS: u32 = 52;
pub const C_SORT_BLOCK_ARGS: u32 = 56;
pub const COUNTER_WORDS: u32 = 64;

// Error bits in counters[C_ERROR].
pub const ERR_ITERATION_CAP: u32 = 1;
pub const ERR_READY_FULL: u32 = 2;
pub const ERR_STACK_OVERFLOW: u32 = 4;

// Workgroup sizes.
pub const SUBDIV_GROUP_SIZE: u32 = 64;
pub const EXPAND_GROUP_SIZE: u32 = 64;
// Ready nodes per mesh workgroup (2 triangles + up to 2 wedges each:
// at most 192 vertices and 128 primitives).
pub const MESH_NODES: u32 = 32;
// Mesh workgroups launched by one task workgroup.
pub const TASK_MESH_GROUPS: u32 = 32;

// Sorting: threads per workgroup; a block of 2 * SORT_GROUP_SIZE entries is
// sorted in shared memory. Ready-list capacities are powers of two and at
// least one block.
pub const SORT_GROUP_SIZE: u32 = 512;
pub const SORT_BLOCK: u32 = 1024;

// Depth-first stack of one invocation: a subtree of depth L_MAX needs at
// most 3 * L_MAX + 1 entries.
pub const STACK_SIZE: u32 = 31;

// Fallback path: each ready node owns 4 triangle slots (12 vertices); a
// missing wedge is written as a degenerate triangle.
pub const VERTICES_PER_NODE: u32 = 12;
// Fallback vertex: vec3 position, uint patch id, uint packed (u*1024: 11
// bits | v*1024: 11 bits << 11 | depth: 4 bits << 22 | wedge: 1 bit << 26).
pub const VERTEX_WORDS: u32 = 5;
pub const PACK_V_SHIFT: u32 = 11;
pub const PACK_DEPTH_SHIFT: u32 = 22;
pub const PACK_WEDGE_SHIFT: u32 = 26;

// Shading modes (push constant of the draw pipelines).
pub const SHADE_NORMAL: u32 = 0;
pub const SHADE_DEPTH: u32 = 1;
pub const SHADE_WEDGES: u32 = 2;
// Hole test: front faces white, back faces in the key colour.
pub const SHADE_KEY: u32 = 3;
// Hole test: distance from the eye / pc.light_dir.w as a 24-bit RGB code.
pub const SHADE_DISTANCE: u32 = 4;
// Tests: the rasterizer's facing (winding) as is: front white, back key.
pub const SHADE_FACING: u32 = 5;

/// Every constant above by name, for the test that compares them with the GLSL.
pub const ALL: &[(&str, u32)] = &[
    ("L_MAX", L_MAX),
    ("NODE_DEPTH_SHIFT", NODE_DEPTH_SHIFT),
    ("NODE_M_SHIFT", NODE_M_SHIFT),
    ("NODE_N_SHIFT", NODE_N_SHIFT),
    ("NODE_L0_SHIFT", NODE_L0_SHIFT),
    ("NODE_L1_SHIFT", NODE_L1_SHIFT),
    ("THIRD_BITS", THIRD_BITS),
    ("TWO_THIRDS_BITS", TWO_THIRDS_BITS),
    ("FLAG_FRUSTUM_CULL", FLAG_FRUSTUM_CULL),
    ("FLAG_BACKFACE_CULL", FLAG_BACKFACE_CULL),
    ("FLAG_WEDGES", FLAG_WEDGES),
    ("FLAG_QUEUE_STRESS", FLAG_QUEUE_STRESS),
    ("PATCH_TWO_SIDED", PATCH_TWO_SIDED),
    ("PATCH_MODEL_SHIFT", PATCH_MODEL_SHIFT),
    ("BIND_VIEW", BIND_VIEW),
    ("BIND_PATCHES", BIND_PATCHES),
    ("BIND_PATCH_FLAGS", BIND_PATCH_FLAGS),
    ("BIND_READY", BIND_READY),
    ("BIND_COUNTERS", BIND_COUNTERS),
    ("BIND_QUEUE_ITEMS", BIND_QUEUE_ITEMS),
    ("BIND_QUEUE_SEQS", BIND_QUEUE_SEQS),
    ("BIND_VERTICES", BIND_VERTICES),
    ("BIND_CAPTURE", BIND_CAPTURE),
    ("BIND_COUNT", BIND_COUNT),
    ("C_READY_COUNT", C_READY_COUNT),
    ("C_IN_FLIGHT", C_IN_FLIGHT),
    ("C_NEXT_BASE", C_NEXT_BASE),
    ("C_QUEUE_HEAD", C_QUEUE_HEAD),
    ("C_QUEUE_TAIL", C_QUEUE_TAIL),
    ("C_IDLE", C_IDLE),
    ("C_ERROR", C_ERROR),
    ("C_PROCESSED", C_PROCESSED),
    ("C_CULLED", C_CULLED),
    ("C_BACKFACE", C_BACKFACE),
    ("C_MAX_DEPTH", C_MAX_DEPTH),
    ("C_AT_LMAX", C_AT_LMAX),
    ("C_SPILLS", C_SPILLS),
    ("C_QUEUE_PEAK", C_QUEUE_PEAK),
    ("C_QUEUE_PUSHED", C_QUEUE_PUSHED),
    ("C_TRIANGLES", C_TRIANGLES),
    ("C_WEDGES", C_WEDGES),
    ("C_ITERATIONS_MAX", C_ITERATIONS_MAX),
    ("C_CHECK_NODES", C_CHECK_NODES),
    ("C_CHECK_FAILS", C_CHECK_FAILS),
    ("IN_FLIGHT_MASK", IN_FLIGHT_MASK),
    ("IN_FLIGHT_TICK", IN_FLIGHT_TICK),
    ("C_MESH_ARGS", C_MESH_ARGS),
    ("C_EXPAND_ARGS", C_EXPAND_ARGS),
    ("C_DRAW_ARGS", C_DRAW_ARGS),
    ("C_SORT_LENGTH", C_SORT_LENGTH),
    ("C_SORT_FILL_ARGS", C_SORT_FILL_ARGS),
    ("C_SORT_GLOBAL_ARGS", C_SORT_GLOBAL_ARGS),
    ("C_SORT_BLOCK_ARGS", C_SORT_BLOCK_ARGS),
    ("COUNTER_WORDS", COUNTER_WORDS),
    ("ERR_ITERATION_CAP", ERR_ITERATION_CAP),
    ("ERR_READY_FULL", ERR_READY_FULL),
    ("ERR_STACK_OVERFLOW", ERR_STACK_OVERFLOW),
    ("SUBDIV_GROUP_SIZE", SUBDIV_GROUP_SIZE),
    ("EXPAND_GROUP_SIZE", EXPAND_GROUP_SIZE),
    ("MESH_NODES", MESH_NODES),
    ("TASK_MESH_GROUPS", TASK_MESH_GROUPS),
    ("SORT_GROUP_SIZE", SORT_GROUP_SIZE),
    ("SORT_BLOCK", SORT_BLOCK),
    ("STACK_SIZE", STACK_SIZE),
    ("VERTICES_PER_NODE", VERTICES_PER_NODE),
    ("VERTEX_WORDS", VERTEX_WORDS),
    ("PACK_V_SHIFT", PACK_V_SHIFT),
    ("PACK_DEPTH_SHIFT", PACK_DEPTH_SHIFT),
    ("PACK_WEDGE_SHIFT", PACK_WEDGE_SHIFT),
    ("SHADE_NORMAL", SHADE_NORMAL),
    ("SHADE_DEPTH", SHADE_DEPTH),
    ("SHADE_WEDGES", SHADE_WEDGES),
    ("SHADE_KEY", SHADE_KEY),
    ("SHADE_DISTANCE", SHADE_DISTANCE),
    ("SHADE_FACING", SHADE_FACING),
];
