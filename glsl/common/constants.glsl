// Generated from src/constants.rs by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in src/constants.rs, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
#ifndef CONSTANTS_GLSL
#define CONSTANTS_GLSL

// Quad-tree depth limit (10-bit m, n in the 8-byte QuadNode).
const uint L_MAX = 10;

// QuadNode layout (src/patch/quadnode.rs). Word 0: patch id (24 bits),
// then the states of the bottom and top edges (4 bits each). Word 1: the
// u code (1 << du) | m and the v code (1 << dv) | n (11 bits each),
// then the states of the left and right edges. An edge's state is the
// depth, in its own direction, at which it was found flat, or
// NODE_EDGE_PENDING.
const uint NODE_PATCH_MASK = 0xffffff;
const uint NODE_BOTTOM_SHIFT = 24;
const uint NODE_TOP_SHIFT = 28;
const uint NODE_U_SHIFT = 0;
const uint NODE_V_SHIFT = 11;
const uint NODE_LEFT_SHIFT = 22;
const uint NODE_RIGHT_SHIFT = 26;
const uint NODE_EDGE_PENDING = 15;

// f32(1/3) and f32(2/3) as bits: the literals cannot be misread.
const uint THIRD_BITS = 0x3eaaaaab;
const uint TWO_THIRDS_BITS = 0x3f2aaaab;

// The animation's sine and cosine (`anim::deform::sin_cos`, twin
// `anim_sin_cos` in `glsl/common/anim.glsl`), as f32 bits: 2/π, π/2 in
// two parts (the high part has 12 significant bits, so q·HI is exact
// for |q| < 4096), and the Taylor coefficients of sin and cos on
// [−π/4, π/4] (error below 4e-7).
const uint ANIM_TWO_OVER_PI_BITS = 0x3f22f983;
const uint ANIM_PIO2_HI_BITS = 0x3fc91000;
const uint ANIM_PIO2_LO_BITS = 0xb695777au;
const uint ANIM_SIN_1_BITS = 0xbe2aaaabu;
const uint ANIM_SIN_2_BITS = 0x3c088889;
const uint ANIM_SIN_3_BITS = 0xb9500d01u;
const uint ANIM_COS_1_BITS = 0xbf000000u;
const uint ANIM_COS_2_BITS = 0x3d2aaaab;
const uint ANIM_COS_3_BITS = 0xbab60b61u;
const uint ANIM_COS_4_BITS = 0x37d00d01;

// The animation update pass's set (`gpu/anim.rs`, `glsl/common/anim.glsl`).
const uint BIND_ANIM_REST = 0;
const uint BIND_ANIM_VERTEX_MODEL = 1;
const uint BIND_ANIM_MODELS = 2;
const uint BIND_ANIM_POINT_ROWS = 3;
const uint BIND_ANIM_POINT_TERMS = 4;
const uint BIND_ANIM_SHADING_ROWS = 5;
const uint BIND_ANIM_SHADING_TERMS = 6;
const uint BIND_ANIM_PATCH_ROWS = 7;
const uint BIND_ANIM_TARGETS = 8;
const uint BIND_ANIM_VERTS = 9;
const uint BIND_ANIM_POINTS = 10;
const uint BIND_ANIM_DEFORMERS = 11;
const uint BIND_ANIM_RECORDS = 12;
const uint BIND_ANIM_INPUTS = 13;
const uint BIND_ANIM_PATCHES = 14;
const uint BIND_ANIM_SHADING = 15;
const uint BIND_ANIM_KEYED = 16;
const uint BIND_ANIM_INSTANCES = 17;
const uint ANIM_BINDINGS = 18;

// The update pass's steps (`AnimPush.pass`), in order, and its
// workgroup size.
const uint ANIM_PASS_DEFORM = 0;
const uint ANIM_PASS_POINTS = 1;
// Shading rows, then patches' points, then instance records.
const uint ANIM_PASS_WRITE = 2;
const uint ANIM_GROUP_SIZE = 64;
// AnimModel.seq_base of a model without a sequence.
const uint ANIM_NO_SEQUENCE = 0xffffffffu;

// Deformer kinds (`anim::deform::Kind`).
const uint DEFORM_TWIST = 0;
const uint DEFORM_BEND = 1;
const uint DEFORM_WAVE = 2;

// ViewParams.flags.
const uint FLAG_FRUSTUM_CULL = 1;
const uint FLAG_BACKFACE_CULL = 2;
const uint FLAG_WEDGES = 4;
// Anisotropic splits: halve only the direction whose edges are not
// flat (1:2), 1:4 when both are or the inner tier fails.
const uint FLAG_ANISO = 8;
// Draw displaced models undisplaced (the window's "displacement"
// toggle; the CPU reference does not read it).
const uint FLAG_UNDISPLACED = 16;
// Test-only: donate to the work queue on every split, not only when some
// invocation is idle, to exercise the queue (and its overflow) hard.
const uint FLAG_QUEUE_STRESS = 0x40000000;

// Per-patch flags word.
const uint PATCH_TWO_SIDED = 1;
// Some of the patch's weights differ from 1 (set 0's BIND_WEIGHTS holds
// them); only methods that draw rational patches accept such a scene.
const uint PATCH_RATIONAL = 2;
const uint PATCH_MODEL_SHIFT = 16;

// Specialization constant ids that every pipeline made through
// `gpu::Shaders` receives (a shader that does not declare one ignores
// it): what the scene holds, so a pipeline carries no code for what the
// scene cannot reach. A driver that compiles on the CPU (lavapipe)
// spends minutes on code that is only dead at run time.
// Bool: the scene has patches flagged PATCH_RATIONAL (default true:
// a pipeline made without it keeps the rational paths).
const uint SPEC_SCENE_RATIONAL = 16;
// Bool: the scene has albedo maps or UVs from a cage (default true);
// false: the shading reads no UV patch, material or texel.
const uint SPEC_SCENE_MATERIALS = 17;
// Bool: some model is displaced (default true); false: no node
// reads the displacement buffer.
const uint SPEC_SCENE_DISPLACED = 18;

// An instance's flags word (set 0's BIND_INSTANCES): PATCH_TWO_SIDED and
// the model index << PATCH_MODEL_SHIFT as in a patch's flags, and these.
// The transform mirrors (negative determinant): the instance's
// patches are the model's with u and v swapped, so ∂u × ∂v stays
// outward.
const uint INSTANCE_MIRRORED = 4;
// The transform is the identity: control points are read unchanged.
const uint INSTANCE_IDENTITY = 8;
// This frame draws the instance from a level of detail (src/lod):
// every method leaves its patches alone (set per frame, never for
// the reference).
const uint INSTANCE_LOD = 16;
// u32 words per level-of-detail vertex (src/lod/gpu.rs): position
// (3 floats), the unit normal (octahedral, two snorm16), the
// texture coordinates (2 floats).
const uint LOD_VERTEX_WORDS = 6;
// u32 words per instance record: 3 rows of 4 floats (the affine
// transform), first global patch id, first model patch, patch count,
// flags, and the box of its world control points (lo xyz, hi xyz,
// each padded to 4 words).
const uint INSTANCE_WORDS = 24;

// Descriptor set numbers: every pipeline layout starts with the scene
// set, then the set of its pass family, then a producer's own.
const uint SET_SCENE = 0;
const uint SET_PASS = 1;
const uint SET_PRODUCER = 2;

// Set 0, the scene (every pass): the view (a dynamic uniform buffer,
// one ViewParams per frame slot), the models' patches, their flags, their
// shading (tangent) patches, their weights and the instances that place
// them. A base patch's id is global (instance by instance); its control
// points are its model patch's, transformed by its instance.
const uint BIND_VIEW = 0;
// 48 floats per model patch (each distinct model once).
const uint BIND_PATCHES = 1;
// One word per model patch: PATCH_RATIONAL.
const uint BIND_PATCH_FLAGS = 2;
// SHADING_FLOATS per model patch: the two tangent patches whose cross
// product is the shading normal (src/patch/shading.rs), in model space.
const uint BIND_SHADING = 3;
// 16 weights per model patch (u fastest, as the control points) for a
// scene with rational patches; 16 ones for any other scene.
const uint BIND_WEIGHTS = 4;
// INSTANCE_WORDS per instance, ordered by first global patch id.
const uint BIND_INSTANCES = 5;
// One word per instance, kept from frame to frame: 1 where the last
// frame's occlusion test found it visible (the next frame draws it
// in its early phase), 0 otherwise.
const uint BIND_VISIBILITY = 7;
// The level kernels' depth 0 (written each frame by level_init): per
// instance that survived culling, its index and the dense index of
// its first patch among the surviving patches (2 words each); under
// occlusion culling the dense index of its first cluster, and after
// the instances the cluster filter's kept clusters and block scan
// (glsl/levels/level.glsl, "Depth 0").
const uint BIND_ROOTS = 6;
// Per model patch, the model-space box of its control points (6
// floats: lo xyz, hi xyz), a little enlarged: the late phase of
// occlusion culling tests the clusters the early phase drew by them.
const uint BIND_PATCH_BOXES = 8;
// Per model patch, its UV patch: 16 (s, t) pairs, u fastest
// (src/scene/material.rs); one placeholder for a scene without
// UVs or maps.
const uint BIND_UV_PATCHES = 9;
// MATERIAL_WORDS per scene model: its albedo map's first texel
// word, width (0: no map), height and mip levels.
const uint BIND_MATERIALS = 10;
// The albedo maps' mip chains: sRGB-encoded RGBA8 words, red in
// the low byte, rows top to bottom, level after level.
const uint BIND_TEXELS = 11;
// The displaced models (src/scene/displacement.rs `gpu_words`):
// a header, DISPLACEMENT_MODEL_WORDS per scene model, the owner
// words and UV curvature bounds per model patch, the height maps
// and their pyramids; one placeholder word for a scene without.
const uint BIND_DISPLACEMENT = 12;
const uint SCENE_BINDINGS = 13;

// Words per model in set 0's BIND_MATERIALS.
const uint MATERIAL_WORDS = 4;

// The layout of set 0's BIND_DISPLACEMENT.
// Header: the owner words' first word, the curvature bounds'
// first word, the number of model records, unused.
const uint DISPLACEMENT_HEADER_WORDS = 4;
// Per scene model: heights' first word, width (0: not displaced),
// height, pyramid's first word, pyramid levels, scale, bias and
// margin (f32 bits).
const uint DISPLACEMENT_MODEL_WORDS = 8;
// Owner words per model patch: 4 edges, then 4 corners.
const uint OWNER_WORDS = 8;
// In an owner word: the owner's edge or corner (low 2 bits).
const uint OWNER_INDEX_MASK = 3;
// In an edge's owner word: the owner runs the edge the other way.
const uint OWNER_REVERSED = 4;
// In an edge's owner word: the edge is one point; its points take
// the corner's owner.
const uint OWNER_COLLAPSED = 8;
// The owner's model patch is the word shifted down by this.
const uint OWNER_PATCH_SHIFT = 4;
// Floats per height-pyramid cell: height, x-slope and y-slope
// ranges (lo, hi each).
const uint PYRAMID_CELL_FLOATS = 6;
// The software reciprocal square root's first guess (bit pattern).
const uint RSQRT_MAGIC = 0x5f375a86;
// Its Newton steps.
const uint RSQRT_STEPS = 4;
// Texture coordinates are clamped to ±2^UV_LIMIT_LOG2 before
// height lookups, so texel indices fit an int on every device.
const uint UV_LIMIT_LOG2 = 16;

// Floats per base patch in the shading buffer: the 12 control vectors of
// the u tangent patch, then the 12 of the v tangent patch, x, y, z each.
const uint SHADING_FLOATS = 72;

// Set 1 of the ready-list passes: the ready QuadNodes, the counters, the
// fallback's vertices, the validation capture.
const uint BIND_READY = 0;
const uint BIND_COUNTERS = 1;
const uint BIND_VERTICES = 2;
const uint BIND_CAPTURE = 3;
// The sort's second buffer (merge passes ping-pong).
const uint BIND_SORT_TEMP = 4;
const uint READY_BINDINGS = 5;

// Set 2 of the level kernels (subdiv's persistent kernel and
// subdiv-indirect's per-depth rounds, glsl/levels/level.glsl): the node
// memory (a region of child slots per depth 1..levels, then two ready
// scratch regions), the block scans of each region, the schedule state,
// and the depth pyramid occlusion culling tests against.
const uint BIND_LEVEL_NODES = 0;
const uint BIND_LEVEL_SCANS = 1;
const uint BIND_LEVEL_STATE = 2;
const uint BIND_LEVEL_HIZ = 3;
const uint LEVEL_BINDINGS = 4;

// LevelPush.phase: one pass without occlusion culling, or the early
// phase (instances visible last frame) and the late phase (the others,
// tested against the early phase's depth pyramid) of occlusion culling.
const uint PHASE_ALL = 0;
const uint PHASE_EARLY = 1;
const uint PHASE_LATE = 2;

// Occlusion culling's visibility kept between frames (set 0's
// BIND_VISIBILITY): a word per instance, the parity word, then two
// sets of one bit per cluster of VISIBILITY_CLUSTER base patches
// (global ids), read and written in turn (glsl/levels/level.glsl).
const uint VISIBILITY_CLUSTER = 32;

// The depth pyramid (glsl/hiz_*.comp, glsl/common/hiz.glsl): level 0 is
// the depth of every pixel (the farthest of its samples), level k + 1
// the farthest of 2 x 2 texels of level k (ceil sizes), down to 1 x 1,
// all in one buffer of floats; its pass set: the depth image, the
// pyramid.
const uint BIND_HIZ_DEPTH = 0;
const uint BIND_HIZ_PYRAMID = 1;
const uint HIZ_BINDINGS = 2;
// Invocations per side of a pyramid pass's 2D workgroup.
const uint HIZ_GROUP = 8;

// Most children one split makes (1:4 today; a 1:2 split would make 2):
// each block of LEVEL_GROUP_SIZE nodes owns LEVEL_GROUP_SIZE *
// SPLIT_MAX_CHILDREN child slots in the next depth's region.
const uint SPLIT_MAX_CHILDREN = 4;

// Per block of a round, beside its children and ready counts: culled,
// back-facing, at l_max, triangles, wedges, occluded, nodes processed,
// global atomics (occlusion culling's visibility bits), and the
// deepest ready depth (a maximum, the last).
const uint LEVEL_BLOCK_STATS = 9;

// The most nodes one round takes: LEVEL_GROUP_SIZE^3, so that the last
// workgroup's finish of a round walks at most LEVEL_GROUP_SIZE block
// totals per invocation.
const uint LEVEL_MAX_CHUNK = 262144;

// Words of the level kernels' state buffer. Words that workgroups
// synchronise on sit on cache lines of their own (16 words apart).
// Every word below S_DEPTH_NODES is the schedule's working state,
// zeroed by every pass's first step; from S_DEPTH_NODES on, the
// frame's totals, zeroed by its first pass only (the late phase of
// occlusion culling adds to the early one's).
// The next dispatch's vkCmdDispatchIndirect arguments x, y, z
// (the cluster filter's, then each round's).
const uint S_ARGS = 0;
// The round barrier, one word (SYNC_*): the workgroups that
// arrived at the end of this round (acquire-release; the last one
// scans the round's block totals and schedules the next), the
// rounds released (the persistent kernel's participants poll it
// with acquire) and the persistent kernel's abort bit (a watchdog
// tripped, every workgroup leaves): one load per poll sees all three.
const uint S_SYNC = 16;
// Persistent kernel, occupancy discovery: workgroups that asked to
// join, with JOIN_CLOSED set once the first one closed the window.
const uint S_JOIN = 32;
// Persistent kernel: workgroups that joined (0 until the window closed).
const uint S_PARTICIPANTS = 48;
// This round: the depth of its chunk, the chunk's first dense index
// and node count, the previous round's ready blocks it copies and
// where in the ready list they go.
const uint S_LEVEL = 64;
const uint S_FIRST = 65;
const uint S_COUNT = 66;
const uint S_COPY_BLOCKS = 67;
const uint S_COPY_BASE = 68;
// 1 once nothing is left to process or copy.
const uint S_DONE = 69;
// Bit d set while depth d holds nodes not yet taken: the next round
// takes the deepest (findMSB), with no walk over the depths.
const uint S_PENDING = 70;
// Instances whose patches are depth 0 of this pass (the entries of
// BIND_ROOTS) and, under occlusion culling, their clusters (the
// cluster filter's work).
const uint S_ROOT_INSTANCES = 71;
const uint S_ROOT_CLUSTERS = 72;
// Per depth d (0..=LEVEL_DEPTHS_MAX): nodes it holds, nodes already
// taken, and the blocks of the chunk that filled it (the length of
// its scan); 32 words apart.
const uint S_LEVEL_COUNT = 80;
const uint S_LEVEL_NEXT = 112;
const uint S_LEVEL_BLOCKS = 144;
// Per depth d: nodes processed over the frame.
const uint S_DEPTH_NODES = 176;
// Ready nodes found so far.
const uint S_READY = 208;
// Rounds finished (the cluster filters not counted).
const uint S_ROUND = 209;
// Rounds that took a chunk of a depth holding more than one chunk.
const uint S_SPLIT_ROUNDS = 210;
// Most nodes one depth held at once.
const uint S_PEAK_NODES = 211;
// Instances culled whole in the frame (their box outside the
// frustum), and the patches of those (counted as culled, never
// processed).
const uint S_CULLED_INSTANCES = 212;
const uint S_CULLED_INSTANCE_PATCHES = 213;
// Occlusion culling: instances the late phase found hidden behind
// the early phase's depth, and their patches (never processed).
const uint S_OCCLUDED_INSTANCES = 214;
const uint S_OCCLUDED_INSTANCE_PATCHES = 215;
// Occlusion culling: instances drawn in the early phase (0 for a
// frame of one pass).
const uint S_EARLY_INSTANCES = 216;
// Instances listed by the frame's last pass that no earlier pass
// listed (occlusion culling's late phase lists the early phase's
// again, for their clusters not drawn yet): with S_EARLY_INSTANCES,
// the instances the frame drew from.
const uint S_NEW_INSTANCES = 217;
// Occlusion culling: 1 when the early phase ran out of recorded
// rounds before its schedule was done (the frame is drawn again
// with more).
const uint S_EARLY_UNFINISHED = 218;
// Occlusion culling: the rounds of the early phase (S_ROUND when
// the late phase began).
const uint S_EARLY_ROUNDS = 219;
// Occlusion culling's cluster filters: clusters the early phase
// drew (their bit set last frame), clusters the late phase took
// (not drawn early), the early phase's clusters whose box the late
// phase tested against the pyramid, and those it found hidden (their
// bit cleared for the next frame).
const uint S_CLUSTERS_EARLY = 220;
const uint S_CLUSTERS_LATE = 221;
const uint S_CLUSTERS_TESTED = 222;
const uint S_CLUSTERS_HIDDEN = 223;
// Occlusion culling: the read-modify-writes of the visibility bits
// (also among the counters' global atomics).
const uint S_VISIBILITY_ATOMICS = 224;
const uint LEVEL_STATE_WORDS = 240;

// S_SYNC: the arrivals in the low bits, the generation (rounds
// released, wrapping) above them, the abort bit on top. At most
// SYNC_ARRIVALS workgroups take part.
const uint SYNC_ARRIVALS = 0x1fff;
const uint SYNC_GENERATION_ONE = 0x2000;
const uint SYNC_GENERATION = 0x7fffe000;
const uint SYNC_ABORT = 0x80000000u;

// The deepest depth of the level schedule (its rounds of splits): a
// 1:4 split deepens both directions at once, a 1:2 split one, so under
// `--split aniso` a node can be split L_MAX times in each direction,
// 2 L_MAX times in all (iso: L_MAX). The state's per-depth words hold
// depths 0..=LEVEL_DEPTHS_MAX.
const uint LEVEL_DEPTHS_MAX = 20;

// S_JOIN: the window-closed bit above the count.
const uint JOIN_CLOSED = 0x80000000u;

// Test-only faults of the persistent level kernel (LevelPush.faults),
// to show that its watchdog turns a broken promise into a fallback,
// and that validate's occlusion check sees a culling error.
// One participant more than joined: a barrier that never completes.
const uint FAULT_PHANTOM = 1;
// Every launched workgroup joins, latecomers too: with more than the
// device keeps resident, the first ones wait for ones that cannot start.
const uint FAULT_NO_DISCOVERY = 2;
// Occlusion culling's late phase takes every node in view, and every
// cluster the early phase drew, for hidden.
const uint FAULT_HIDE_LATE = 4;

// PN triangles (src/scene/pn.rs, glsl/common/pn.glsl), which cudatess
// tessellates, the ground truth samples and the shading lights: the patch
// id in a cudatess vertex word is its low CT_PATCH_BITS; with bit
// CT_PN_SHIFT set it names a PN triangle rather than a patch; a
// triangle's converted net is CT_PN_NET_VEC4 vec4s (10 points, 6 normal
// coefficients).
const uint CT_PATCH_BITS = 24;
const uint CT_PN_SHIFT = 29;
const uint CT_PN_NET_VEC4 = 16;

// Indices into the counters buffer (uint words).
const uint C_READY_COUNT = 0;
const uint C_IN_FLIGHT = 1;
const uint C_NEXT_BASE = 2;
// Polls of the in-flight count by idle workgroups.
const uint C_IDLE_POLLS = 3;
// Atomic read-modify-write operations the kernel issued on global
// memory (the cost that contention multiplies on a GPU).
const uint C_GLOBAL_ATOMICS = 4;
// Workgroups without work right now.
const uint C_IDLE = 5;
const uint C_ERROR = 6;
const uint C_PROCESSED = 7;
const uint C_CULLED = 8;
const uint C_BACKFACE = 9;
const uint C_MAX_DEPTH = 10;
const uint C_AT_LMAX = 11;
// Items a full queue refused (they stay in their workgroup).
const uint C_SPILLS = 12;
const uint C_QUEUE_PEAK = 13;
const uint C_QUEUE_PUSHED = 14;
const uint C_TRIANGLES = 15;
const uint C_WEDGES = 16;
const uint C_ITERATIONS_MAX = 17;
// Queue operations that lost a compare-and-swap and were retried.
const uint C_QUEUE_RETRIES = 20;
// Nodes the late phase of occlusion culling found hidden behind the
// early phase's depth (counted among the culled too).
const uint C_OCCLUDED = 21;
// The first ready-list entry the next draw draws: 0, or for the late
// phase of occlusion culling the end of the early phase's list.
const uint C_READY_FIRST = 22;

// Validation passes (reorder_check.comp): nodes checked, nodes failing.
const uint C_CHECK_NODES = 18;
const uint C_CHECK_FAILS = 19;

// counters[C_IN_FLIGHT]: items in flight in the low 24 bits (so at most
// 2^24 - 1 base patches), a wrapping progress tick in the top byte.
const uint IN_FLIGHT_MASK = 0xffffff;
const uint IN_FLIGHT_TICK = 0x1000000;

// Indirect arguments in the counters buffer, written by the subdivision pass.
// vkCmdDrawMeshTasksIndirectEXT: x, y, z
const uint C_MESH_ARGS = 32;

// Sorting the ready list (sort.comp, the queue kernel only): dispatch
// arguments of the block pass (one workgroup per SORT_BLOCK entries)
// and, four words apart, of merge pass i (one invocation per entry, or
// none once the runs span the list), for i < SORT_MAX_MERGES.
const uint C_SORT_BLOCK_ARGS = 48;
const uint C_SORT_MERGE_ARGS = 64;
const uint SORT_MAX_MERGES = 15;

// The counters the host reads back after a frame (statistics, state
// and every indirect argument but the fallback's chunks), in uint words.
const uint COUNTER_WORDS = 128;

// The fallback path draws its ready nodes in chunks of at most
// FALLBACK_CHUNK_NODES (its vertex buffer holds one chunk, 94 MB,
// under the 128 MiB every Vulkan device binds), at most
// FALLBACK_MAX_CHUNKS of them. Chunk c's arguments are CHUNK_ARG_WORDS
// words from C_CHUNK_ARGS + CHUNK_ARG_WORDS * c: vkCmdDispatchIndirect
// of the expansion (x, y, z, unused), then vkCmdDrawIndirect (vertices,
// instances, first vertex, first instance). The counters buffer holds
// COUNTERS_BUFFER_WORDS words.
const uint FALLBACK_CHUNK_NODES = 262144;
const uint FALLBACK_MAX_CHUNKS = 64;
const uint C_CHUNK_ARGS = 128;
const uint CHUNK_ARG_WORDS = 8;
const uint COUNTERS_BUFFER_WORDS = 640;

// Error bits in counters[C_ERROR].
const uint ERR_ITERATION_CAP = 1;
const uint ERR_READY_FULL = 2;
// A workgroup's local deque would have overflowed (never expected:
// batches are sized so it cannot).
const uint ERR_STACK_OVERFLOW = 4;
// The persistent level kernel's watchdog: a barrier or the occupancy
// discovery saw no progress for its whole poll cap (the frame is
// redone with the per-depth rounds).
const uint ERR_WATCHDOG = 8;
// A level round had children for a depth beyond the node memory's
// regions (pc.levels): they were dropped, not written past the
// region, and the frame is refused.
const uint ERR_LEVEL_REGION = 16;

// Workgroup sizes.
const uint SUBDIV_GROUP_SIZE = 64;
const uint EXPAND_GROUP_SIZE = 64;
// The level kernels: a block of one node per invocation.
const uint LEVEL_GROUP_SIZE = 64;
// The ground truth's culling pass: one invocation per base patch.
const uint GRID_CULL_GROUP_SIZE = 64;
// Ready nodes per mesh workgroup (2 triangles + up to 4 wedges each:
// at most 256 vertices and 192 primitives).
const uint MESH_NODES = 32;
// A ready node's vertex slots (4 corners, a pivot per edge) and
// triangle slots (the quad's two, a wedge per edge).
const uint NODE_MESH_SLOTS = 8;
const uint NODE_MESH_TRIS = 6;
// Mesh workgroups launched by one task workgroup.
const uint TASK_MESH_GROUPS = 32;

// Sorting: threads per workgroup; the block pass sorts blocks of
// 2 * SORT_GROUP_SIZE entries in shared memory, then merge passes double
// the sorted runs until one spans the list.
const uint SORT_GROUP_SIZE = 512;
const uint SORT_BLOCK = 1024;

// The persistent kernel's workgroup-local deque of work items (shared
// memory, a power of two): a workgroup keeps SUBDIV_KEEP items for its next
// batch and hands the rest to the global queue, or, when the queue is
// full, keeps them here and takes smaller batches so it never overflows.
// It refills from the base patches or the queue when fewer than
// SUBDIV_REFILL_BELOW are left.
const uint SUBDIV_LOCAL_CAP = 2048;
const uint SUBDIV_KEEP = 64;
const uint SUBDIV_REFILL_BELOW = 32;

// Fallback path: each ready node owns 6 triangle slots (18 vertices); a
// missing wedge is written as a degenerate triangle.
const uint VERTICES_PER_NODE = 18;

// Fallback vertex: vec3 position, uint patch id, uint packed (u*1024: 11
// bits | v*1024: 11 bits << 11 | depth along u: 4 bits << 22 | along v:
// 4 bits << 26 | wedge code: 2 bits << 30).
const uint VERTEX_WORDS = 5;
const uint PACK_V_SHIFT = 11;
const uint PACK_DEPTH_SHIFT = 22;
const uint PACK_WEDGE_SHIFT = 30;

// What a drawn triangle hands the fragment stage beside its depths
// (the mesh path per primitive, the fallback in its packed word): 0 for
// a quad triangle; a wedge is lit from the side its node's quad
// triangle along the same edge shows (that triangle's winding seen from
// the eye), as its own winding says little (issue 21).
const uint WEDGE_NONE = 0;
const uint WEDGE_LIT_FRONT = 1;
const uint WEDGE_LIT_BACK = 2;

// Shading modes (push constant of the draw pipelines).
const uint SHADE_NORMAL = 0;
const uint SHADE_DEPTH = 1;
const uint SHADE_WEDGES = 2;
// Hole test: front faces white, back faces in the key colour.
const uint SHADE_KEY = 3;
// Hole test: distance from the eye / pc.light_dir.w as a 24-bit RGB code.
const uint SHADE_DISTANCE = 4;
// Tests: the rasterizer's facing (winding) as is: front white, back key.
const uint SHADE_FACING = 5;
// Lit surface with the outline of every drawn cell: QuadNodes (their
// depth's grid in the patch's parameters), tessellation or grid cells.
const uint SHADE_WIREFRAME = 6;
// The shading normal as colour (x, y, z to r, g, b).
const uint SHADE_NORMALS = 7;
// Tests: the base patch id as a 24-bit RGB code.
const uint SHADE_PATCH_ID = 8;
// Tests: the base patch parameters (u, v) as 12 bits each
// (round(u * 4095) in r and the top of g, v below it and in b).
const uint SHADE_PARAMS = 9;
// Tests: the model's tint unlit (`palette::model_tint`, the
// shaders' `model_tint`).
const uint SHADE_TINT = 10;
// The surface's texture coordinates (s, t) as red and green, a
// checker of eighths in blue, unlit.
const uint SHADE_UV = 11;
// The albedo unlit: the model's map where it has one, else its tint.
const uint SHADE_TEXTURE = 12;
// The height the displaced models' maps give at the fragment, dark
// blue (0) to yellow (1), unlit; grey where a model is not displaced.
const uint SHADE_DISPLACEMENT = 13;

// The depth heat map's colours (0xRRGGBB, display values): depth 0
// dark blue through cyan, green and yellow to dark red at 10, the
// lightness rising to the middle and falling again, so neighbouring
// depths stay apart. The shaders, the CPU preview and the window's
// legend all read these.
const uint DEPTH_RAMP_0 = 0x29338c;
const uint DEPTH_RAMP_1 = 0x2966e0;
const uint DEPTH_RAMP_2 = 0x1fa3eb;
const uint DEPTH_RAMP_3 = 0x24ccbd;
const uint DEPTH_RAMP_4 = 0x5ce070;
const uint DEPTH_RAMP_5 = 0xa8eb3d;
const uint DEPTH_RAMP_6 = 0xedd933;
const uint DEPTH_RAMP_7 = 0xfa9e29;
const uint DEPTH_RAMP_8 = 0xeb6124;
const uint DEPTH_RAMP_9 = 0xc22924;
const uint DEPTH_RAMP_10 = 0x800f1f;
// Crack-closing wedges in the wedge view.
const uint WEDGE_RGB = 0xff00ff;

#endif
