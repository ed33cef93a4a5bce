//! Constants shared with the shaders, declared once, here: those more than
//! one method's shaders read. A method's own live in its folder
//! (`src/methods/<method>/constants.rs`, declared with the same macro) and
//! reach its shaders as `glsl/<method>/constants.glsl`.
//!
//! `shared_constants!` turns each entry of the list below into a
//! `pub const NAME: u32` and a row of [`ALL`]; `tools/compile-shaders`
//! generates `glsl/common/constants.glsl` from [`ALL`] (comments included)
//! and its `--check` fails while the committed header differs. To add or
//! change a constant, edit the list and run
//! `cargo run --release -p compile-shaders`; never edit the GLSL header.
//!
//! This file, and every method's `constants.rs`, is also compiled into
//! `tools/compile-shaders` by path, so they must not use anything from the
//! rest of the crate but this module.

/// One constant shared with the shaders: a row of [`ALL`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SharedConst {
    /// The name, the same in Rust and GLSL.
    pub name: &'static str,
    /// The value, the same in Rust and GLSL.
    pub value: u32,
    /// The constant's own doc comment, as the compiler hands it over: one
    /// string per `///` line, each still starting with the space after `///`.
    pub doc: &'static [&'static str],
    /// Whether the GLSL spells the value in hex: it does when the list below does.
    pub hex: bool,
    /// `Some(comment)` on the first constant of each group: the GLSL puts a
    /// blank line and the group's comment (lines as in `doc`) before it.
    pub group: Option<&'static [&'static str]>,
}

/// Whether a literal, as `stringify!` spells it, is written in hex.
pub const fn is_hex(literal: &str) -> bool {
    let b = literal.as_bytes();
    b.len() > 2 && b[0] == b'0' && (b[1] == b'x' || b[1] == b'X')
}

/// Declares the shared constants. The input is a list of groups, each with
/// its own doc comment:
///
/// ```text
/// /// What the group is (written above it in the GLSL).
/// group {
///     NAME = 1;
///     /// What this one is, when the group comment does not say.
///     MASK = 0x00ff_ffff;   // hex here, hex in the GLSL
/// }
/// ```
///
/// Each constant becomes `pub const NAME: u32`, documented by its own
/// comment followed by its group's, and a [`SharedConst`] row of the
/// module's `ALL`.
macro_rules! shared_constants {
    // One group's items; the group comment comes as a single `[..]` token
    // tree so that it can be repeated for every constant.
    (@group $group_doc:tt $([$($doc:literal)*] $name:ident = $value:literal;)*) => {
        $(shared_constants!(@item $group_doc [$($doc)*] $name = $value);)*
    };
    (@item [$($group_doc:literal)*] [] $name:ident = $value:literal) => {
        $(#[doc = $group_doc])*
        pub const $name: u32 = $value;
    };
    (@item [$($group_doc:literal)*] [$($doc:literal)+] $name:ident = $value:literal) => {
        $(#[doc = $doc])*
        #[doc = ""]
        $(#[doc = $group_doc])*
        pub const $name: u32 = $value;
    };
    ($(
        $(#[doc = $group_doc:literal])*
        group {
            $(#[doc = $first_doc:literal])*
            $first:ident = $first_value:literal;
            $(
                $(#[doc = $doc:literal])*
                $name:ident = $value:literal;
            )*
        }
    )*) => {
        $(shared_constants!(@group [$($group_doc)*]
            [$($first_doc)*] $first = $first_value;
            $([$($doc)*] $name = $value;)*
        );)*

        /// Every constant of this module in declaration order: the table
        /// `tools/compile-shaders` writes the module's GLSL header from.
        pub const ALL: &[$crate::constants::SharedConst] = &[$(
            $crate::constants::SharedConst {
                name: stringify!($first),
                value: $first,
                doc: &[$($first_doc),*],
                hex: $crate::constants::is_hex(stringify!($first_value)),
                group: Some(&[$($group_doc),*]),
            },
            $($crate::constants::SharedConst {
                name: stringify!($name),
                value: $name,
                doc: &[$($doc),*],
                hex: $crate::constants::is_hex(stringify!($value)),
                group: None,
            },)*
        )*];
    };
}

// For the methods' own constants modules.
pub(crate) use shared_constants;

shared_constants! {
    /// Quad-tree depth limit (10-bit m, n in the 8-byte QuadNode).
    group {
        L_MAX = 10;
    }

    /// QuadNode layout (src/patch/quadnode.rs). Word 0: patch id (24 bits),
    /// then the states of the bottom and top edges (4 bits each). Word 1: the
    /// u code (1 << du) | m and the v code (1 << dv) | n (11 bits each),
    /// then the states of the left and right edges. An edge's state is the
    /// depth, in its own direction, at which it was found flat, or
    /// NODE_EDGE_PENDING.
    group {
        NODE_PATCH_MASK = 0x00ff_ffff;
        NODE_BOTTOM_SHIFT = 24;
        NODE_TOP_SHIFT = 28;
        NODE_U_SHIFT = 0;
        NODE_V_SHIFT = 11;
        NODE_LEFT_SHIFT = 22;
        NODE_RIGHT_SHIFT = 26;
        NODE_EDGE_PENDING = 15;
    }

    /// f32(1/3) and f32(2/3) as bits: the literals cannot be misread.
    group {
        THIRD_BITS = 0x3eaa_aaab;
        TWO_THIRDS_BITS = 0x3f2a_aaab;
    }

    /// The animation's sine and cosine (`anim::deform::sin_cos`, twin
    /// `anim_sin_cos` in `glsl/common/anim.glsl`), as f32 bits: 2/π, π/2 in
    /// two parts (the high part has 12 significant bits, so q·HI is exact
    /// for |q| < 4096), and the Taylor coefficients of sin and cos on
    /// [−π/4, π/4] (error below 4e-7).
    group {
        ANIM_TWO_OVER_PI_BITS = 0x3f22_f983;
        ANIM_PIO2_HI_BITS = 0x3fc9_1000;
        ANIM_PIO2_LO_BITS = 0xb695_777a;
        ANIM_SIN_1_BITS = 0xbe2a_aaab;
        ANIM_SIN_2_BITS = 0x3c08_8889;
        ANIM_SIN_3_BITS = 0xb950_0d01;
        ANIM_COS_1_BITS = 0xbf00_0000;
        ANIM_COS_2_BITS = 0x3d2a_aaab;
        ANIM_COS_3_BITS = 0xbab6_0b61;
        ANIM_COS_4_BITS = 0x37d0_0d01;
    }

    /// The animation update pass's set (`gpu/anim.rs`, `glsl/common/anim.glsl`).
    group {
        BIND_ANIM_REST = 0;
        BIND_ANIM_VERTEX_MODEL = 1;
        BIND_ANIM_MODELS = 2;
        BIND_ANIM_POINT_ROWS = 3;
        BIND_ANIM_POINT_TERMS = 4;
        BIND_ANIM_SHADING_ROWS = 5;
        BIND_ANIM_SHADING_TERMS = 6;
        BIND_ANIM_PATCH_ROWS = 7;
        BIND_ANIM_TARGETS = 8;
        BIND_ANIM_VERTS = 9;
        BIND_ANIM_POINTS = 10;
        BIND_ANIM_DEFORMERS = 11;
        BIND_ANIM_RECORDS = 12;
        BIND_ANIM_INPUTS = 13;
        BIND_ANIM_PATCHES = 14;
        BIND_ANIM_SHADING = 15;
        BIND_ANIM_KEYED = 16;
        BIND_ANIM_INSTANCES = 17;
        ANIM_BINDINGS = 18;
    }

    /// The update pass's steps (`AnimPush.pass`), in order, and its
    /// workgroup size.
    group {
        ANIM_PASS_DEFORM = 0;
        ANIM_PASS_POINTS = 1;
        /// Shading rows, then patches' points, then instance records.
        ANIM_PASS_WRITE = 2;
        ANIM_GROUP_SIZE = 64;
        /// AnimModel.seq_base of a model without a sequence.
        ANIM_NO_SEQUENCE = 0xffff_ffff;
    }

    /// Deformer kinds (`anim::deform::Kind`).
    group {
        DEFORM_TWIST = 0;
        DEFORM_BEND = 1;
        DEFORM_WAVE = 2;
    }

    /// ViewParams.flags.
    group {
        FLAG_FRUSTUM_CULL = 1;
        FLAG_BACKFACE_CULL = 2;
        FLAG_WEDGES = 4;
        /// Anisotropic splits: halve only the direction whose edges are not
        /// flat (1:2), 1:4 when both are or the inner tier fails.
        FLAG_ANISO = 8;
        /// Draw displaced models undisplaced (the window's "displacement"
        /// toggle; the CPU reference does not read it).
        FLAG_UNDISPLACED = 16;
        /// Test-only: donate to the work queue on every split, not only when some
        /// invocation is idle, to exercise the queue (and its overflow) hard.
        FLAG_QUEUE_STRESS = 0x4000_0000;
    }

    /// Per-patch flags word.
    group {
        PATCH_TWO_SIDED = 1;
        /// Some of the patch's weights differ from 1 (set 0's BIND_WEIGHTS holds
        /// them); only methods that draw rational patches accept such a scene.
        PATCH_RATIONAL = 2;
        PATCH_MODEL_SHIFT = 16;
    }

    /// Specialization constant ids that every pipeline made through
    /// `gpu::Shaders` receives (a shader that does not declare one ignores
    /// it): what the scene holds, so a pipeline carries no code for what the
    /// scene cannot reach. A driver that compiles on the CPU (lavapipe)
    /// spends minutes on code that is only dead at run time.
    group {
        /// Bool: the scene has patches flagged PATCH_RATIONAL (default true:
        /// a pipeline made without it keeps the rational paths).
        SPEC_SCENE_RATIONAL = 16;
        /// Bool: the scene has albedo maps or UVs from a cage (default true);
        /// false: the shading reads no UV patch, material or texel.
        SPEC_SCENE_MATERIALS = 17;
        /// Bool: some model is displaced (default true); false: no node
        /// reads the displacement buffer.
        SPEC_SCENE_DISPLACED = 18;
    }

    /// An instance's flags word (set 0's BIND_INSTANCES): PATCH_TWO_SIDED and
    /// the model index << PATCH_MODEL_SHIFT as in a patch's flags, and these.
    group {
        /// The transform mirrors (negative determinant): the instance's
        /// patches are the model's with u and v swapped, so ∂u × ∂v stays
        /// outward.
        INSTANCE_MIRRORED = 4;
        /// The transform is the identity: control points are read unchanged.
        INSTANCE_IDENTITY = 8;
        /// This frame draws the instance from a level of detail (src/lod):
        /// every method leaves its patches alone (set per frame, never for
        /// the reference).
        INSTANCE_LOD = 16;
        /// u32 words per level-of-detail vertex (src/lod/gpu.rs): position
        /// (3 floats), the unit normal (octahedral, two snorm16), the
        /// texture coordinates (2 floats).
        LOD_VERTEX_WORDS = 6;
        /// u32 words per instance record: 3 rows of 4 floats (the affine
        /// transform), first global patch id, first model patch, patch count,
        /// flags, and the box of its world control points (lo xyz, hi xyz,
        /// each padded to 4 words).
        INSTANCE_WORDS = 24;
    }

    /// Descriptor set numbers: every pipeline layout starts with the scene
    /// set, then the set of its pass family, then a producer's own.
    group {
        SET_SCENE = 0;
        SET_PASS = 1;
        SET_PRODUCER = 2;
    }
    /// Set 0, the scene (every pass): the view (a dynamic uniform buffer,
    /// one ViewParams per frame slot), the models' patches, their flags, their
    /// shading (tangent) patches, their weights and the instances that place
    /// them. A base patch's id is global (instance by instance); its control
    /// points are its model patch's, transformed by its instance.
    group {
        BIND_VIEW = 0;
        /// 48 floats per model patch (each distinct model once).
        BIND_PATCHES = 1;
        /// One word per model patch: PATCH_RATIONAL.
        BIND_PATCH_FLAGS = 2;
        /// SHADING_FLOATS per model patch: the two tangent patches whose cross
        /// product is the shading normal (src/patch/shading.rs), in model space.
        BIND_SHADING = 3;
        /// 16 weights per model patch (u fastest, as the control points) for a
        /// scene with rational patches; 16 ones for any other scene.
        BIND_WEIGHTS = 4;
        /// INSTANCE_WORDS per instance, ordered by first global patch id.
        BIND_INSTANCES = 5;
        /// One word per instance, kept from frame to frame: 1 where the last
        /// frame's occlusion test found it visible (the next frame draws it
        /// in its early phase), 0 otherwise.
        BIND_VISIBILITY = 7;
        /// The level kernels' depth 0 (written each frame by level_init): per
        /// instance that survived culling, its index and the dense index of
        /// its first patch among the surviving patches (2 words each); under
        /// occlusion culling the dense index of its first cluster, and after
        /// the instances the cluster filter's kept clusters and block scan
        /// (glsl/levels/level.glsl, "Depth 0").
        BIND_ROOTS = 6;
        /// Per model patch, the model-space box of its control points (6
        /// floats: lo xyz, hi xyz), a little enlarged: the late phase of
        /// occlusion culling tests the clusters the early phase drew by them.
        BIND_PATCH_BOXES = 8;
        /// Per model patch, its UV patch: 16 (s, t) pairs, u fastest
        /// (src/scene/material.rs); one placeholder for a scene without
        /// UVs or maps.
        BIND_UV_PATCHES = 9;
        /// MATERIAL_WORDS per scene model: its albedo map's first texel
        /// word, width (0: no map), height and mip levels.
        BIND_MATERIALS = 10;
        /// The albedo maps' mip chains: sRGB-encoded RGBA8 words, red in
        /// the low byte, rows top to bottom, level after level.
        BIND_TEXELS = 11;
        /// The displaced models (src/scene/displacement.rs `gpu_words`):
        /// a header, DISPLACEMENT_MODEL_WORDS per scene model, the owner
        /// words and UV curvature bounds per model patch, the height maps
        /// and their pyramids; one placeholder word for a scene without.
        BIND_DISPLACEMENT = 12;
        SCENE_BINDINGS = 13;
    }
    /// Words per model in set 0's BIND_MATERIALS.
    group {
        MATERIAL_WORDS = 4;
    }
    /// The layout of set 0's BIND_DISPLACEMENT.
    group {
        /// Header: the owner words' first word, the curvature bounds'
        /// first word, the number of model records, unused.
        DISPLACEMENT_HEADER_WORDS = 4;
        /// Per scene model: heights' first word, width (0: not displaced),
        /// height, pyramid's first word, pyramid levels, scale, bias and
        /// margin (f32 bits).
        DISPLACEMENT_MODEL_WORDS = 8;
        /// Owner words per model patch: 4 edges, then 4 corners.
        OWNER_WORDS = 8;
        /// In an owner word: the owner's edge or corner (low 2 bits).
        OWNER_INDEX_MASK = 3;
        /// In an edge's owner word: the owner runs the edge the other way.
        OWNER_REVERSED = 4;
        /// In an edge's owner word: the edge is one point; its points take
        /// the corner's owner.
        OWNER_COLLAPSED = 8;
        /// The owner's model patch is the word shifted down by this.
        OWNER_PATCH_SHIFT = 4;
        /// Floats per height-pyramid cell: height, x-slope and y-slope
        /// ranges (lo, hi each).
        PYRAMID_CELL_FLOATS = 6;
        /// The software reciprocal square root's first guess (bit pattern).
        RSQRT_MAGIC = 0x5f375a86;
        /// Its Newton steps.
        RSQRT_STEPS = 4;
        /// Texture coordinates are clamped to ±2^UV_LIMIT_LOG2 before
        /// height lookups, so texel indices fit an int on every device.
        UV_LIMIT_LOG2 = 16;
    }
    /// Floats per base patch in the shading buffer: the 12 control vectors of
    /// the u tangent patch, then the 12 of the v tangent patch, x, y, z each.
    group {
        SHADING_FLOATS = 72;
    }
    /// Set 1 of the ready-list passes: the ready QuadNodes, the counters, the
    /// fallback's vertices, the validation capture.
    group {
        BIND_READY = 0;
        BIND_COUNTERS = 1;
        BIND_VERTICES = 2;
        BIND_CAPTURE = 3;
        /// The sort's second buffer (merge passes ping-pong).
        BIND_SORT_TEMP = 4;
        READY_BINDINGS = 5;
    }
    /// Set 2 of the level kernels (subdiv's persistent kernel and
    /// subdiv-indirect's per-depth rounds, glsl/levels/level.glsl): the node
    /// memory (a region of child slots per depth 1..levels, then two ready
    /// scratch regions), the block scans of each region, the schedule state,
    /// and the depth pyramid occlusion culling tests against.
    group {
        BIND_LEVEL_NODES = 0;
        BIND_LEVEL_SCANS = 1;
        BIND_LEVEL_STATE = 2;
        BIND_LEVEL_HIZ = 3;
        LEVEL_BINDINGS = 4;
    }
    /// LevelPush.phase: one pass without occlusion culling, or the early
    /// phase (instances visible last frame) and the late phase (the others,
    /// tested against the early phase's depth pyramid) of occlusion culling.
    group {
        PHASE_ALL = 0;
        PHASE_EARLY = 1;
        PHASE_LATE = 2;
    }
    /// Occlusion culling's visibility kept between frames (set 0's
    /// BIND_VISIBILITY): a word per instance, the parity word, then two
    /// sets of one bit per cluster of VISIBILITY_CLUSTER base patches
    /// (global ids), read and written in turn (glsl/levels/level.glsl).
    group {
        VISIBILITY_CLUSTER = 32;
    }
    /// The depth pyramid (glsl/hiz_*.comp, glsl/common/hiz.glsl): level 0 is
    /// the depth of every pixel (the farthest of its samples), level k + 1
    /// the farthest of 2 x 2 texels of level k (ceil sizes), down to 1 x 1,
    /// all in one buffer of floats; its pass set: the depth image, the
    /// pyramid.
    group {
        BIND_HIZ_DEPTH = 0;
        BIND_HIZ_PYRAMID = 1;
        HIZ_BINDINGS = 2;
        /// Invocations per side of a pyramid pass's 2D workgroup.
        HIZ_GROUP = 8;
    }
    /// Most children one split makes (1:4 today; a 1:2 split would make 2):
    /// each block of LEVEL_GROUP_SIZE nodes owns LEVEL_GROUP_SIZE *
    /// SPLIT_MAX_CHILDREN child slots in the next depth's region.
    group {
        SPLIT_MAX_CHILDREN = 4;
    }
    /// Per block of a round, beside its children and ready counts: culled,
    /// back-facing, at l_max, triangles, wedges, occluded, nodes processed,
    /// global atomics (occlusion culling's visibility bits), and the
    /// deepest ready depth (a maximum, the last).
    group {
        LEVEL_BLOCK_STATS = 9;
    }
    /// The most nodes one round takes: LEVEL_GROUP_SIZE^3, so that the last
    /// workgroup's finish of a round walks at most LEVEL_GROUP_SIZE block
    /// totals per invocation.
    group {
        LEVEL_MAX_CHUNK = 262144;
    }
    /// Words of the level kernels' state buffer. Words that workgroups
    /// synchronise on sit on cache lines of their own (16 words apart).
    /// Every word below S_DEPTH_NODES is the schedule's working state,
    /// zeroed by every pass's first step; from S_DEPTH_NODES on, the
    /// frame's totals, zeroed by its first pass only (the late phase of
    /// occlusion culling adds to the early one's).
    group {
        /// The next dispatch's vkCmdDispatchIndirect arguments x, y, z
        /// (the cluster filter's, then each round's).
        S_ARGS = 0;
        /// The round barrier, one word (SYNC_*): the workgroups that
        /// arrived at the end of this round (acquire-release; the last one
        /// scans the round's block totals and schedules the next), the
        /// rounds released (the persistent kernel's participants poll it
        /// with acquire) and the persistent kernel's abort bit (a watchdog
        /// tripped, every workgroup leaves): one load per poll sees all three.
        S_SYNC = 16;
        /// Persistent kernel, occupancy discovery: workgroups that asked to
        /// join, with JOIN_CLOSED set once the first one closed the window.
        S_JOIN = 32;
        /// Persistent kernel: workgroups that joined (0 until the window closed).
        S_PARTICIPANTS = 48;
        /// This round: the depth of its chunk, the chunk's first dense index
        /// and node count, the previous round's ready blocks it copies and
        /// where in the ready list they go.
        S_LEVEL = 64;
        S_FIRST = 65;
        S_COUNT = 66;
        S_COPY_BLOCKS = 67;
        S_COPY_BASE = 68;
        /// 1 once nothing is left to process or copy.
        S_DONE = 69;
        /// Bit d set while depth d holds nodes not yet taken: the next round
        /// takes the deepest (findMSB), with no walk over the depths.
        S_PENDING = 70;
        /// Instances whose patches are depth 0 of this pass (the entries of
        /// BIND_ROOTS) and, under occlusion culling, their clusters (the
        /// cluster filter's work).
        S_ROOT_INSTANCES = 71;
        S_ROOT_CLUSTERS = 72;
        /// Per depth d (0..=LEVEL_DEPTHS_MAX): nodes it holds, nodes already
        /// taken, and the blocks of the chunk that filled it (the length of
        /// its scan); 32 words apart.
        S_LEVEL_COUNT = 80;
        S_LEVEL_NEXT = 112;
        S_LEVEL_BLOCKS = 144;
        /// Per depth d: nodes processed over the frame.
        S_DEPTH_NODES = 176;
        /// Ready nodes found so far.
        S_READY = 208;
        /// Rounds finished (the cluster filters not counted).
        S_ROUND = 209;
        /// Rounds that took a chunk of a depth holding more than one chunk.
        S_SPLIT_ROUNDS = 210;
        /// Most nodes one depth held at once.
        S_PEAK_NODES = 211;
        /// Instances culled whole in the frame (their box outside the
        /// frustum), and the patches of those (counted as culled, never
        /// processed).
        S_CULLED_INSTANCES = 212;
        S_CULLED_INSTANCE_PATCHES = 213;
        /// Occlusion culling: instances the late phase found hidden behind
        /// the early phase's depth, and their patches (never processed).
        S_OCCLUDED_INSTANCES = 214;
        S_OCCLUDED_INSTANCE_PATCHES = 215;
        /// Occlusion culling: instances drawn in the early phase (0 for a
        /// frame of one pass).
        S_EARLY_INSTANCES = 216;
        /// Instances listed by the frame's last pass that no earlier pass
        /// listed (occlusion culling's late phase lists the early phase's
        /// again, for their clusters not drawn yet): with S_EARLY_INSTANCES,
        /// the instances the frame drew from.
        S_NEW_INSTANCES = 217;
        /// Occlusion culling: 1 when the early phase ran out of recorded
        /// rounds before its schedule was done (the frame is drawn again
        /// with more).
        S_EARLY_UNFINISHED = 218;
        /// Occlusion culling: the rounds of the early phase (S_ROUND when
        /// the late phase began).
        S_EARLY_ROUNDS = 219;
        /// Occlusion culling's cluster filters: clusters the early phase
        /// drew (their bit set last frame), clusters the late phase took
        /// (not drawn early), the early phase's clusters whose box the late
        /// phase tested against the pyramid, and those it found hidden (their
        /// bit cleared for the next frame).
        S_CLUSTERS_EARLY = 220;
        S_CLUSTERS_LATE = 221;
        S_CLUSTERS_TESTED = 222;
        S_CLUSTERS_HIDDEN = 223;
        /// Occlusion culling: the read-modify-writes of the visibility bits
        /// (also among the counters' global atomics).
        S_VISIBILITY_ATOMICS = 224;
        LEVEL_STATE_WORDS = 240;
    }
    /// S_SYNC: the arrivals in the low bits, the generation (rounds
    /// released, wrapping) above them, the abort bit on top. At most
    /// SYNC_ARRIVALS workgroups take part.
    group {
        SYNC_ARRIVALS = 0x1fff;
        SYNC_GENERATION_ONE = 0x2000;
        SYNC_GENERATION = 0x7fff_e000;
        SYNC_ABORT = 0x8000_0000;
    }
    /// The deepest depth of the level schedule (its rounds of splits): a
    /// 1:4 split deepens both directions at once, a 1:2 split one, so under
    /// `--split aniso` a node can be split L_MAX times in each direction,
    /// 2 L_MAX times in all (iso: L_MAX). The state's per-depth words hold
    /// depths 0..=LEVEL_DEPTHS_MAX.
    group {
        LEVEL_DEPTHS_MAX = 20;
    }
    /// S_JOIN: the window-closed bit above the count.
    group {
        JOIN_CLOSED = 0x8000_0000;
    }
    /// Test-only faults of the persistent level kernel (LevelPush.faults),
    /// to show that its watchdog turns a broken promise into a fallback,
    /// and that validate's occlusion check sees a culling error.
    group {
        /// One participant more than joined: a barrier that never completes.
        FAULT_PHANTOM = 1;
        /// Every launched workgroup joins, latecomers too: with more than the
        /// device keeps resident, the first ones wait for ones that cannot start.
        FAULT_NO_DISCOVERY = 2;
        /// Occlusion culling's late phase takes every node in view, and every
        /// cluster the early phase drew, for hidden.
        FAULT_HIDE_LATE = 4;
    }
    /// PN triangles (src/scene/pn.rs, glsl/common/pn.glsl), which cudatess
    /// tessellates, the ground truth samples and the shading lights: the patch
    /// id in a cudatess vertex word is its low CT_PATCH_BITS; with bit
    /// CT_PN_SHIFT set it names a PN triangle rather than a patch; a
    /// triangle's converted net is CT_PN_NET_VEC4 vec4s (10 points, 6 normal
    /// coefficients).
    group {
        CT_PATCH_BITS = 24;
        CT_PN_SHIFT = 29;
        CT_PN_NET_VEC4 = 16;
    }

    /// Indices into the counters buffer (uint words).
    group {
        C_READY_COUNT = 0;
        C_IN_FLIGHT = 1;
        C_NEXT_BASE = 2;
        /// Polls of the in-flight count by idle workgroups.
        C_IDLE_POLLS = 3;
        /// Atomic read-modify-write operations the kernel issued on global
        /// memory (the cost that contention multiplies on a GPU).
        C_GLOBAL_ATOMICS = 4;
        /// Workgroups without work right now.
        C_IDLE = 5;
        C_ERROR = 6;
        C_PROCESSED = 7;
        C_CULLED = 8;
        C_BACKFACE = 9;
        C_MAX_DEPTH = 10;
        C_AT_LMAX = 11;
        /// Items a full queue refused (they stay in their workgroup).
        C_SPILLS = 12;
        C_QUEUE_PEAK = 13;
        C_QUEUE_PUSHED = 14;
        C_TRIANGLES = 15;
        C_WEDGES = 16;
        C_ITERATIONS_MAX = 17;
        /// Queue operations that lost a compare-and-swap and were retried.
        C_QUEUE_RETRIES = 20;
        /// Nodes the late phase of occlusion culling found hidden behind the
        /// early phase's depth (counted among the culled too).
        C_OCCLUDED = 21;
        /// The first ready-list entry the next draw draws: 0, or for the late
        /// phase of occlusion culling the end of the early phase's list.
        C_READY_FIRST = 22;
    }
    /// Validation passes (reorder_check.comp): nodes checked, nodes failing.
    group {
        C_CHECK_NODES = 18;
        C_CHECK_FAILS = 19;
    }
    /// counters[C_IN_FLIGHT]: items in flight in the low 24 bits (so at most
    /// 2^24 - 1 base patches), a wrapping progress tick in the top byte.
    group {
        IN_FLIGHT_MASK = 0x00ff_ffff;
        IN_FLIGHT_TICK = 0x0100_0000;
    }
    /// Indirect arguments in the counters buffer, written by the subdivision pass.
    group {
        /// vkCmdDrawMeshTasksIndirectEXT: x, y, z
        C_MESH_ARGS = 32;
    }
    /// Sorting the ready list (sort.comp, the queue kernel only): dispatch
    /// arguments of the block pass (one workgroup per SORT_BLOCK entries)
    /// and, four words apart, of merge pass i (one invocation per entry, or
    /// none once the runs span the list), for i < SORT_MAX_MERGES.
    group {
        C_SORT_BLOCK_ARGS = 48;
        C_SORT_MERGE_ARGS = 64;
        SORT_MAX_MERGES = 15;
    }
    /// The counters the host reads back after a frame (statistics, state
    /// and every indirect argument but the fallback's chunks), in uint words.
    group {
        COUNTER_WORDS = 128;
    }
    /// The fallback path draws its ready nodes in chunks of at most
    /// FALLBACK_CHUNK_NODES (its vertex buffer holds one chunk, 94 MB,
    /// under the 128 MiB every Vulkan device binds), at most
    /// FALLBACK_MAX_CHUNKS of them. Chunk c's arguments are CHUNK_ARG_WORDS
    /// words from C_CHUNK_ARGS + CHUNK_ARG_WORDS * c: vkCmdDispatchIndirect
    /// of the expansion (x, y, z, unused), then vkCmdDrawIndirect (vertices,
    /// instances, first vertex, first instance). The counters buffer holds
    /// COUNTERS_BUFFER_WORDS words.
    group {
        FALLBACK_CHUNK_NODES = 262144;
        FALLBACK_MAX_CHUNKS = 64;
        C_CHUNK_ARGS = 128;
        CHUNK_ARG_WORDS = 8;
        COUNTERS_BUFFER_WORDS = 640;
    }

    /// Error bits in counters[C_ERROR].
    group {
        ERR_ITERATION_CAP = 1;
        ERR_READY_FULL = 2;
        /// A workgroup's local deque would have overflowed (never expected:
        /// batches are sized so it cannot).
        ERR_STACK_OVERFLOW = 4;
        /// The persistent level kernel's watchdog: a barrier or the occupancy
        /// discovery saw no progress for its whole poll cap (the frame is
        /// redone with the per-depth rounds).
        ERR_WATCHDOG = 8;
        /// A level round had children for a depth beyond the node memory's
        /// regions (pc.levels): they were dropped, not written past the
        /// region, and the frame is refused.
        ERR_LEVEL_REGION = 16;
    }

    /// Workgroup sizes.
    group {
        SUBDIV_GROUP_SIZE = 64;
        EXPAND_GROUP_SIZE = 64;
        /// The level kernels: a block of one node per invocation.
        LEVEL_GROUP_SIZE = 64;
        /// The ground truth's culling pass: one invocation per base patch.
        GRID_CULL_GROUP_SIZE = 64;
        /// Ready nodes per mesh workgroup (2 triangles + up to 4 wedges each:
        /// at most 256 vertices and 192 primitives).
        MESH_NODES = 32;
        /// A ready node's vertex slots (4 corners, a pivot per edge) and
        /// triangle slots (the quad's two, a wedge per edge).
        NODE_MESH_SLOTS = 8;
        NODE_MESH_TRIS = 6;
        /// Mesh workgroups launched by one task workgroup.
        TASK_MESH_GROUPS = 32;
    }

    /// Sorting: threads per workgroup; the block pass sorts blocks of
    /// 2 * SORT_GROUP_SIZE entries in shared memory, then merge passes double
    /// the sorted runs until one spans the list.
    group {
        SORT_GROUP_SIZE = 512;
        SORT_BLOCK = 1024;
    }

    /// The persistent kernel's workgroup-local deque of work items (shared
    /// memory, a power of two): a workgroup keeps SUBDIV_KEEP items for its next
    /// batch and hands the rest to the global queue, or, when the queue is
    /// full, keeps them here and takes smaller batches so it never overflows.
    /// It refills from the base patches or the queue when fewer than
    /// SUBDIV_REFILL_BELOW are left.
    group {
        SUBDIV_LOCAL_CAP = 2048;
        SUBDIV_KEEP = 64;
        SUBDIV_REFILL_BELOW = 32;
    }

    /// Fallback path: each ready node owns 6 triangle slots (18 vertices); a
    /// missing wedge is written as a degenerate triangle.
    group {
        VERTICES_PER_NODE = 18;
    }
    /// Fallback vertex: vec3 position, uint patch id, uint packed (u*1024: 11
    /// bits | v*1024: 11 bits << 11 | depth along u: 4 bits << 22 | along v:
    /// 4 bits << 26 | wedge code: 2 bits << 30).
    group {
        VERTEX_WORDS = 5;
        PACK_V_SHIFT = 11;
        PACK_DEPTH_SHIFT = 22;
        PACK_WEDGE_SHIFT = 30;
    }

    /// What a drawn triangle hands the fragment stage beside its depths
    /// (the mesh path per primitive, the fallback in its packed word): 0 for
    /// a quad triangle; a wedge is lit from the side its node's quad
    /// triangle along the same edge shows (that triangle's winding seen from
    /// the eye), as its own winding says little (issue 21).
    group {
        WEDGE_NONE = 0;
        WEDGE_LIT_FRONT = 1;
        WEDGE_LIT_BACK = 2;
    }

    /// Shading modes (push constant of the draw pipelines).
    group {
        SHADE_NORMAL = 0;
        SHADE_DEPTH = 1;
        SHADE_WEDGES = 2;
        /// Hole test: front faces white, back faces in the key colour.
        SHADE_KEY = 3;
        /// Hole test: distance from the eye / pc.light_dir.w as a 24-bit RGB code.
        SHADE_DISTANCE = 4;
        /// Tests: the rasterizer's facing (winding) as is: front white, back key.
        SHADE_FACING = 5;
        /// Lit surface with the outline of every drawn cell: QuadNodes (their
        /// depth's grid in the patch's parameters), tessellation or grid cells.
        SHADE_WIREFRAME = 6;
        /// The shading normal as colour (x, y, z to r, g, b).
        SHADE_NORMALS = 7;
        /// Tests: the base patch id as a 24-bit RGB code.
        SHADE_PATCH_ID = 8;
        /// Tests: the base patch parameters (u, v) as 12 bits each
        /// (round(u * 4095) in r and the top of g, v below it and in b).
        SHADE_PARAMS = 9;
        /// Tests: the model's tint unlit (`palette::model_tint`, the
        /// shaders' `model_tint`).
        SHADE_TINT = 10;
        /// The surface's texture coordinates (s, t) as red and green, a
        /// checker of eighths in blue, unlit.
        SHADE_UV = 11;
        /// The albedo unlit: the model's map where it has one, else its tint.
        SHADE_TEXTURE = 12;
        /// The height the displaced models' maps give at the fragment, dark
        /// blue (0) to yellow (1), unlit; grey where a model is not displaced.
        SHADE_DISPLACEMENT = 13;
    }

    /// The depth heat map's colours (0xRRGGBB, display values): depth 0
    /// dark blue through cyan, green and yellow to dark red at 10, the
    /// lightness rising to the middle and falling again, so neighbouring
    /// depths stay apart. The shaders, the CPU preview and the window's
    /// legend all read these.
    group {
        DEPTH_RAMP_0 = 0x29_338c;
        DEPTH_RAMP_1 = 0x29_66e0;
        DEPTH_RAMP_2 = 0x1f_a3eb;
        DEPTH_RAMP_3 = 0x24_ccbd;
        DEPTH_RAMP_4 = 0x5c_e070;
        DEPTH_RAMP_5 = 0xa8_eb3d;
        DEPTH_RAMP_6 = 0xed_d933;
        DEPTH_RAMP_7 = 0xfa_9e29;
        DEPTH_RAMP_8 = 0xeb_6124;
        DEPTH_RAMP_9 = 0xc2_2924;
        DEPTH_RAMP_10 = 0x80_0f1f;
        /// Crack-closing wedges in the wedge view.
        WEDGE_RGB = 0xff_00ff;
    }
}

// The fallback's chunk arguments follow the host-read counters and fill the
// rest of the buffer; every ready list the device can bind (2^24 nodes at
// the 128 MiB minimum of maxStorageBufferRange) fits in the chunks.
const _: () = assert!(C_CHUNK_ARGS >= COUNTER_WORDS);
const _: () =
    assert!(COUNTERS_BUFFER_WORDS == C_CHUNK_ARGS + CHUNK_ARG_WORDS * FALLBACK_MAX_CHUNKS);
const _: () =
    assert!(FALLBACK_CHUNK_NODES as u64 * (VERTICES_PER_NODE * VERTEX_WORDS * 4) as u64 <= 1 << 27);
const _: () =
    assert!(FALLBACK_CHUNK_NODES / EXPAND_GROUP_SIZE * EXPAND_GROUP_SIZE == FALLBACK_CHUNK_NODES);
