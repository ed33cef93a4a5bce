//! The shared constants agree with what their comments promise.
//!
//! `src/constants.rs` is the one place they are declared; the GLSL header is
//! generated from it, and `tools/compile-shaders` tests that the committed
//! header is current (so is its `--check` in CI). What can still go wrong is
//! a value changed without the values that depend on it: those relations are
//! checked here.

use bezier_subdiv::constants::*;
use bezier_subdiv::methods::{
    cudatess::constants::*, ground_truth::constants::*, subdiv::constants::*, tess::constants::*,
};

/// Whether `value` fits in the low `bits` bits.
fn fits(value: u32, bits: u32) -> bool {
    u64::from(value) < 1 << bits
}

/// The fields tile `0..end` in order, without gaps or overlaps.
fn assert_packed(what: &str, fields: &[(&str, u32, u32)], end: u32) {
    let mut at = 0;
    for &(name, shift, width) in fields {
        assert_eq!(shift, at, "{what}: {name} starts at bit {shift}, not {at}");
        at += width;
    }
    assert_eq!(at, end, "{what}: the fields end at bit {at}, not {end}");
}

#[test]
fn quad_node_words_hold_patch_codes_and_edge_states() {
    // Word 0: patch 24 | bottom 4 | top 4. Word 1: u code 11 | v code 11 |
    // left 4 | right 4, two bits spare. A direction's code is (1 << depth) | index: 11 bits
    // hold depths up to L_MAX = 10.
    assert_packed(
        "QuadNode word 0",
        &[
            ("patch", 0, NODE_PATCH_MASK.count_ones()),
            ("bottom", NODE_BOTTOM_SHIFT, 4),
            ("top", NODE_TOP_SHIFT, 4),
        ],
        32,
    );
    assert_packed(
        "QuadNode word 1",
        &[
            ("u code", NODE_U_SHIFT, 11),
            ("v code", NODE_V_SHIFT, 11),
            ("left", NODE_LEFT_SHIFT, 4),
            ("right", NODE_RIGHT_SHIFT, 4),
        ],
        30,
    );
    assert!(
        fits((2 << L_MAX) - 1, 11),
        "a code up to depth L_MAX in 11 bits"
    );
    assert!(
        NODE_EDGE_PENDING > L_MAX && fits(NODE_EDGE_PENDING, 4),
        "an edge state is a depth up to L_MAX or PENDING, in 4 bits"
    );
}

#[test]
fn fallback_vertex_packing_fits() {
    // u*1024: 11 bits | v*1024: 11 bits << 11 | u depth 4, v depth 4 << 22
    // | wedge code: 2 bits << 30.
    let fields = [
        ("u", 0, 11),
        ("v", PACK_V_SHIFT, 11),
        ("depths", PACK_DEPTH_SHIFT, 8),
        ("wedge", PACK_WEDGE_SHIFT, 2),
    ];
    assert_packed("packed vertex word", &fields, 32);
    let codes = [WEDGE_NONE, WEDGE_LIT_FRONT, WEDGE_LIT_BACK];
    assert!(codes.iter().all(|&c| fits(c, 2)), "wedge codes in 2 bits");
    assert!(codes[0] != codes[1] && codes[1] != codes[2] && codes[0] != codes[2]);
    // u*1024 is exact for depths up to L_MAX <= 10: the QuadNode test.
    assert_eq!(
        VERTICES_PER_NODE,
        NODE_MESH_TRIS * 3,
        "a node's triangle slots: two of its quad, one wedge per edge"
    );
    assert_eq!(NODE_MESH_TRIS, 2 + 4);
    assert_eq!(NODE_MESH_SLOTS, 4 + 4, "four corners and four pivots");
}

#[test]
fn thirds_are_the_f32_bits_of_one_and_two_thirds() {
    assert_eq!(f32::from_bits(THIRD_BITS), 1.0f32 / 3.0);
    assert_eq!(f32::from_bits(TWO_THIRDS_BITS), 2.0f32 / 3.0);
}

#[test]
fn sizes_derived_from_others() {
    assert!(
        SUBDIV_LOCAL_CAP.is_power_of_two(),
        "the deque wraps by mask"
    );
    let (cap, keep, group, refill) = (
        SUBDIV_LOCAL_CAP,
        SUBDIV_KEEP,
        SUBDIV_GROUP_SIZE,
        SUBDIV_REFILL_BELOW,
    );
    assert!(
        cap >= keep + 4 * group,
        "a kept batch and its children fit the deque"
    );
    assert!(refill <= group && keep >= group, "{refill} {keep} {group}");
    assert_eq!(
        SORT_BLOCK,
        2 * SORT_GROUP_SIZE,
        "a block is 2 * SORT_GROUP_SIZE"
    );
    assert!(SORT_BLOCK.is_power_of_two());
    assert_eq!(IN_FLIGHT_MASK, (1 << 24) - 1, "in flight: the low 24 bits");
    assert_eq!(
        IN_FLIGHT_TICK,
        IN_FLIGHT_MASK + 1,
        "the tick: the top byte's unit"
    );
    // Per node 4 corners and 2 wedge pivots, 2 quad and 2 wedge triangles;
    // VK_EXT_mesh_shader guarantees 256 output vertices and primitives.
    let (vertices, primitives) = (MESH_NODES * 6, MESH_NODES * 4);
    assert!(vertices <= 256, "{vertices} vertices per mesh workgroup");
    assert!(
        primitives <= 256,
        "{primitives} primitives per mesh workgroup"
    );
}

#[test]
fn flags_and_error_bits_are_distinct_single_bits() {
    for (what, bits) in [
        (
            "ViewParams.flags",
            &[
                FLAG_FRUSTUM_CULL,
                FLAG_BACKFACE_CULL,
                FLAG_WEDGES,
                FLAG_QUEUE_STRESS,
            ][..],
        ),
        (
            "error bits",
            &[
                ERR_ITERATION_CAP,
                ERR_READY_FULL,
                ERR_STACK_OVERFLOW,
                ERR_WATCHDOG,
            ][..],
        ),
    ] {
        let mut seen = 0;
        for &b in bits {
            assert!(b.is_power_of_two() && seen & b == 0, "{what}: {b:#x}");
            seen |= b;
        }
    }
    assert!(
        fits(PATCH_TWO_SIDED, PATCH_MODEL_SHIFT),
        "patch flags lie below the model index"
    );
}

#[test]
fn bindings_number_each_set_from_zero() {
    let sets: [(&str, Vec<u32>, u32); 8] = [
        (
            "scene",
            vec![
                BIND_VIEW,
                BIND_PATCHES,
                BIND_PATCH_FLAGS,
                BIND_SHADING,
                BIND_WEIGHTS,
                BIND_INSTANCES,
                BIND_ROOTS,
                BIND_PATCH_BOXES,
                BIND_UV_PATCHES,
                BIND_MATERIALS,
                BIND_TEXELS,
                BIND_DISPLACEMENT,
                BIND_VISIBILITY,
            ],
            SCENE_BINDINGS,
        ),
        (
            "ready list",
            vec![
                BIND_READY,
                BIND_COUNTERS,
                BIND_VERTICES,
                BIND_CAPTURE,
                BIND_SORT_TEMP,
            ],
            READY_BINDINGS,
        ),
        (
            "queue",
            vec![BIND_QUEUE_ITEMS, BIND_QUEUE_SEQS, BIND_QUEUE_STATE],
            QUEUE_BINDINGS,
        ),
        (
            "level",
            vec![
                BIND_LEVEL_NODES,
                BIND_LEVEL_SCANS,
                BIND_LEVEL_STATE,
                BIND_LEVEL_HIZ,
            ],
            LEVEL_BINDINGS,
        ),
        (
            "grid",
            vec![BIND_GRID_VISIBLE, BIND_GRID_COUNTERS],
            GRID_BINDINGS,
        ),
        (
            "cudatess",
            vec![
                BIND_CT_COUNTERS,
                BIND_CT_EDGE_IDS,
                BIND_CT_EDGE_FACTORS,
                BIND_CT_PATCHES,
                BIND_CT_SCAN,
                BIND_CT_VERTICES,
                BIND_CT_INDICES,
                BIND_CT_PN_VERTICES,
                BIND_CT_PN_TRIANGLES,
                BIND_CT_PN_EDGE_IDS,
                BIND_CT_PN_NETS,
            ],
            CT_BINDINGS,
        ),
        (
            "tess",
            vec![
                BIND_TESS_COUNTERS,
                BIND_TESS_LEVELS,
                BIND_TESS_EDGE_VERTICES,
            ],
            TESS_BINDINGS,
        ),
        (
            "depth pyramid",
            vec![BIND_HIZ_DEPTH, BIND_HIZ_PYRAMID],
            HIZ_BINDINGS,
        ),
    ];
    for (name, mut bindings, count) in sets {
        bindings.sort();
        assert_eq!(bindings, (0..count).collect::<Vec<_>>(), "{name} set");
    }
    let mut sets = [SET_SCENE, SET_PASS, SET_PRODUCER];
    sets.sort();
    assert_eq!(sets, [0, 1, 2]);
}

#[test]
fn grid_counters_hold_the_indexed_draw() {
    // VkDrawIndexedIndirectCommand is five words after G_DRAW_ARGS.
    let (culled, args, words) = (G_CULLED, G_DRAW_ARGS, GRID_WORDS);
    assert!(
        culled < args && args + 5 <= words,
        "{culled} {args} {words}"
    );
}

#[test]
fn counter_slots_do_not_overlap_and_fit_the_buffer() {
    let scalars = [
        C_READY_COUNT,
        C_IN_FLIGHT,
        C_NEXT_BASE,
        C_IDLE_POLLS,
        C_GLOBAL_ATOMICS,
        C_IDLE,
        C_ERROR,
        C_PROCESSED,
        C_CULLED,
        C_BACKFACE,
        C_MAX_DEPTH,
        C_AT_LMAX,
        C_SPILLS,
        C_QUEUE_PEAK,
        C_QUEUE_PUSHED,
        C_TRIANGLES,
        C_WEDGES,
        C_ITERATIONS_MAX,
        C_QUEUE_RETRIES,
        C_OCCLUDED,
        C_READY_FIRST,
        C_CHECK_NODES,
        C_CHECK_FAILS,
    ];
    // Indirect arguments: x, y, z for dispatches and mesh tasks; the
    // fallback's chunks (after the words the host reads) a dispatch and a
    // vkCmdDrawIndirect each.
    let ranges = [(C_MESH_ARGS, 3), (C_SORT_BLOCK_ARGS, 3)];
    let merges = (0..SORT_MAX_MERGES).map(|i| (C_SORT_MERGE_ARGS + 4 * i, 3));
    let chunks =
        (0..FALLBACK_MAX_CHUNKS).map(|c| (C_CHUNK_ARGS + CHUNK_ARG_WORDS * c, CHUNK_ARG_WORDS));
    let mut owner = vec![None; COUNTERS_BUFFER_WORDS as usize];
    let read = scalars.iter().map(|&c| (c, 1)).chain(ranges).chain(merges);
    for (start, len) in read.clone() {
        assert!(
            start + len <= COUNTER_WORDS,
            "word {start} is not read back"
        );
    }
    for (i, (start, len)) in read.chain(chunks).enumerate() {
        for word in start..start + len {
            let slot = owner
                .get_mut(word as usize)
                .unwrap_or_else(|| panic!("word {word} is beyond COUNTERS_BUFFER_WORDS"));
            assert_eq!(*slot, None, "word {word} is used twice");
            *slot = Some(i);
        }
    }
}

#[test]
fn level_state_words_do_not_overlap_and_sync_words_own_their_lines() {
    let depths = LEVEL_DEPTHS_MAX + 1;
    let mut slots: Vec<(u32, u32)> = vec![
        (S_ARGS, 3),
        (S_SYNC, 1),
        (S_JOIN, 1),
        (S_PARTICIPANTS, 1),
        (S_LEVEL_COUNT, depths),
        (S_LEVEL_NEXT, depths),
        (S_LEVEL_BLOCKS, depths),
        (S_DEPTH_NODES, depths),
    ];
    slots.extend(
        [
            S_LEVEL,
            S_FIRST,
            S_COUNT,
            S_COPY_BLOCKS,
            S_COPY_BASE,
            S_DONE,
            S_PENDING,
            S_ROOT_INSTANCES,
            S_ROOT_CLUSTERS,
            S_READY,
            S_ROUND,
            S_SPLIT_ROUNDS,
            S_PEAK_NODES,
            S_CULLED_INSTANCES,
            S_CULLED_INSTANCE_PATCHES,
            S_OCCLUDED_INSTANCES,
            S_OCCLUDED_INSTANCE_PATCHES,
            S_EARLY_INSTANCES,
            S_NEW_INSTANCES,
            S_EARLY_UNFINISHED,
            S_EARLY_ROUNDS,
            S_CLUSTERS_EARLY,
            S_CLUSTERS_LATE,
            S_CLUSTERS_TESTED,
            S_CLUSTERS_HIDDEN,
            S_VISIBILITY_ATOMICS,
        ]
        .map(|w| (w, 1)),
    );
    let mut owner = vec![None; LEVEL_STATE_WORDS as usize];
    for (i, (start, len)) in slots.iter().enumerate() {
        for word in *start..start + len {
            let slot = owner
                .get_mut(word as usize)
                .unwrap_or_else(|| panic!("word {word} is beyond LEVEL_STATE_WORDS"));
            assert_eq!(*slot, None, "word {word} is used twice");
            *slot = Some(i);
        }
    }
    // Every word that workgroups synchronise on sits on a 64-byte line of
    // its own.
    let line = |w: u32| w / 16;
    let sync = [S_SYNC, S_JOIN, S_PARTICIPANTS];
    for &a in &sync {
        for (start, len) in &slots {
            if *start != a {
                assert!(
                    (*start..start + len).all(|w| line(w) != line(a)),
                    "word {start} shares the line of {a}"
                );
            }
        }
    }
    // The schedule's words are zeroed by every pass, the frame's totals
    // only by its first (levels/init.comp).
    for w in [
        S_ARGS,
        S_SYNC,
        S_DONE,
        S_PENDING,
        S_ROOT_CLUSTERS,
        S_LEVEL_BLOCKS,
    ] {
        assert!(w < S_DEPTH_NODES, "{w}");
    }
    for w in [
        S_READY,
        S_ROUND,
        S_EARLY_UNFINISHED,
        S_CLUSTERS_HIDDEN,
        S_VISIBILITY_ATOMICS,
    ] {
        assert!(w >= S_DEPTH_NODES, "{w}");
    }
    // The barrier word's fields do not overlap and fill it.
    assert_eq!(SYNC_ARRIVALS & SYNC_GENERATION, 0);
    assert_eq!(SYNC_GENERATION & SYNC_ABORT, 0);
    assert_eq!(SYNC_ARRIVALS | SYNC_GENERATION | SYNC_ABORT, u32::MAX);
    assert_eq!(SYNC_GENERATION_ONE, SYNC_ARRIVALS + 1);
    const { assert!(JOIN_CLOSED.is_power_of_two() && JOIN_CLOSED > 1 << 30) };
    const { assert!(SPLIT_MAX_CHILDREN >= 2) };
}
