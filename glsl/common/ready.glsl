// Descriptor set 1 of the ready-list passes (producers, sort, draw paths,
// validation): the ready QuadNodes, the counters with every indirect
// argument, the fallback's vertices and the validation capture. A shader
// declares what it touches by defining USE_<NAME> before including this
// file (USE_READY_WRITE / USE_READY_RW / USE_VERTICES_WRITE make the
// writable variants; USE_LIST_PUSH declares the ListPush block of the
// non-draw passes). The Rust side is src/draw/ready.rs.
#ifndef READY_GLSL
#define READY_GLSL

#include "scene.glsl"

#if defined(USE_READY_WRITE)
layout(std430, set = SET_PASS, binding = BIND_READY) writeonly buffer Ready {
    uvec2 ready[];
};
#elif defined(USE_READY_RW)
layout(std430, set = SET_PASS, binding = BIND_READY) buffer Ready {
    uvec2 ready[];
};
#else
layout(std430, set = SET_PASS, binding = BIND_READY) readonly buffer Ready {
    uvec2 ready[];
};
#endif

layout(std430, set = SET_PASS, binding = BIND_COUNTERS) coherent buffer Counters {
    uint counters[];
};

// Fallback vertices, VERTEX_WORDS words each (see constants.glsl): written
// by the expansion pass, read by the vertex shader (which may not write
// storage buffers without vertexPipelineStoresAndAtomics).
#if defined(USE_VERTICES_WRITE)
layout(std430, set = SET_PASS, binding = BIND_VERTICES) writeonly buffer Vertices {
    uint vertex_words[];
};
#elif defined(USE_VERTICES)
layout(std430, set = SET_PASS, binding = BIND_VERTICES) readonly buffer Vertices {
    uint vertex_words[];
};
#endif

#ifdef USE_CAPTURE
// Debug capture of world positions (validation): one vec4 per vertex slot.
layout(std430, set = SET_PASS, binding = BIND_CAPTURE) writeonly buffer Capture {
    vec4 capture[];
};
#endif

#ifdef USE_SORT_TEMP
layout(std430, set = SET_PASS, binding = BIND_SORT_TEMP) buffer SortTemp {
    uvec2 sort_temp[];
};
#endif

#ifdef USE_LIST_PUSH
// src/gpu/blocks.rs ListPush.
layout(push_constant) uniform ListPush {
    uint ready_capacity;  // entries in `ready`
    uint mode;            // sort: which pass
    uint k;               // sort: width of the sorted runs merged
    uint j;               // unused (0)
} pc;
#endif

// Ready nodes a producer published, never more than the list holds (a full
// list sets ERR_READY_FULL but must not make anyone read past it).
uint ready_count(uint capacity) {
    uint n = counters[C_READY_COUNT];
    return n < capacity ? n : capacity;
}

// The first ready node the next draw draws (0, or the end of the early
// phase's list for the late phase of occlusion culling).
uint ready_first() {
    return counters[C_READY_FIRST];
}

// The indirect arguments of everything after a producer, for the ready
// nodes first .. total: the mesh draw, the fallback's expansions and draws
// chunk by chunk, and the sort's block and merge passes (a merge pass not
// needed gets none; only the queue kernel sorts, with first = 0), written
// by the invocations t of a group of `stride` together. src/draw/ready.rs
// `indirect_args` is the host's copy.
void write_ready_args_by(uint first, uint total, uint t, uint stride) {
    uint n = total - min(first, total);
    if (t == 0u) {
        counters[C_MESH_ARGS] = (n + MESH_NODES * TASK_MESH_GROUPS - 1u) / (MESH_NODES * TASK_MESH_GROUPS);
        counters[C_MESH_ARGS + 1u] = 1u;
        counters[C_MESH_ARGS + 2u] = 1u;
        counters[C_SORT_BLOCK_ARGS] = (n + SORT_BLOCK - 1u) / SORT_BLOCK;
        counters[C_SORT_BLOCK_ARGS + 1u] = 1u;
        counters[C_SORT_BLOCK_ARGS + 2u] = 1u;
    }
    for (uint c = t; c < FALLBACK_MAX_CHUNKS; c += stride) {
        // The fallback's chunk c: nodes first + c * FALLBACK_CHUNK_NODES on,
        // expanded into the start of the vertex buffer and drawn from there.
        uint start = c * FALLBACK_CHUNK_NODES;
        uint m = n > start ? min(n - start, FALLBACK_CHUNK_NODES) : 0u;
        uint a = C_CHUNK_ARGS + CHUNK_ARG_WORDS * c;
        counters[a] = (m + EXPAND_GROUP_SIZE - 1u) / EXPAND_GROUP_SIZE;
        counters[a + 1u] = 1u;
        counters[a + 2u] = 1u;
        counters[a + 3u] = 0u;
        counters[a + 4u] = m * VERTICES_PER_NODE;
        counters[a + 5u] = 1u;
        counters[a + 6u] = 0u;
        counters[a + 7u] = 0u;
    }
    for (uint i = t; i < SORT_MAX_MERGES; i += stride) {
        // Merge pass i merges runs of SORT_BLOCK << i: none once one spans n.
        uint a = C_SORT_MERGE_ARGS + 4u * i;
        counters[a] = (SORT_BLOCK << i) < n ? (n + SORT_GROUP_SIZE - 1u) / SORT_GROUP_SIZE : 0u;
        counters[a + 1u] = 1u;
        counters[a + 2u] = 1u;
    }
}

// write_ready_args_by from one invocation.
void write_ready_args(uint first, uint total) {
    write_ready_args_by(first, total, 0u, 1u);
}

#endif
