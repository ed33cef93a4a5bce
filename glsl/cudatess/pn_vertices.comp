// cudatess for PN triangles, stage 5: CT_VERTEX_THREADS invocations share a
// triangle and write every CT_VERTEX_THREADS-th of its vertices into its
// slot (the scan's offset): position, domain (u, v), and the word (triangle
// id, the PN bit, log2 of the core factor, the transition bit).
//
// - Corners are the vertex positions themselves (exact).
// - Edge vertices come from the edge's own four net points at
//   ct_edge_param through the reversal-symmetric curve(): the triangle
//   across the edge built the same points from the same two vertices
//   (pn_edge_point), runs the edge the other way and writes the same bits.
// - Core vertices are the cubic evaluated in Bernstein form.
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"
#include "common/pn.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

void write_vertex(uint at, vec3 p, vec2 uv, uint word) {
    uint o = at * CT_VERTEX_WORDS;
    ct_vertices[o] = floatBitsToUint(p.x);
    ct_vertices[o + 1u] = floatBitsToUint(p.y);
    ct_vertices[o + 2u] = floatBitsToUint(p.z);
    ct_vertices[o + 3u] = floatBitsToUint(uv.x);
    ct_vertices[o + 4u] = floatBitsToUint(uv.y);
    ct_vertices[o + 5u] = word;
}

uint with_transition(uint word, bool transition) {
    return word | ((transition ? 1u : 0u) << CT_TRANSITION_SHIFT);
}

void emit_vertex(uint tri, PnPattern t, uint base, uint k, uint word) {
    bvec3 tr = bvec3(t.e.x != t.m, t.e.y != t.m, t.e.z != t.m);
    if (k < 3u) {
        const vec2 corner_uv[3] = vec2[3](vec2(0.0), vec2(1.0, 0.0), vec2(0.0, 1.0));
        // Corner k lies on edges k and k + 2 (mod 3).
        bool transition = tr[k] || tr[(k + 2u) % 3u];
        write_vertex(base + k, pn_point(tri, k), corner_uv[k], with_transition(word, transition));
        return;
    }
    if (k < t.inner_base) {
        uint edge = 0u;
        uint s = k - 3u;
        while (s >= t.e[edge] - 1u) {
            s -= t.e[edge] - 1u;
            edge += 1u;
        }
        s += 1u;
        uvec4 idx = pn_edge_indices(edge);
        float param = ct_edge_param(s, t.e[edge]);
        precise vec3 p = curve(param, pn_point(tri, idx.x), pn_point(tri, idx.y),
            pn_point(tri, idx.z), pn_point(tri, idx.w));
        vec2 uv = edge == 0u ? vec2(param, 0.0)
            : edge == 1u ? vec2(1.0 - param, param) : vec2(0.0, 1.0 - param);
        write_vertex(base + k, p, uv, with_transition(word, tr[edge]));
        return;
    }
    uint i = k - t.inner_base;
    uint b = 0u;
    while (i > t.r - b) {
        i -= t.r + 1u - b;
        b += 1u;
    }
    vec2 uv = pn_core_uv(t, i, b);
    write_vertex(base + k, pn_eval(tri, uv), uv, word);
}

void main() {
    if (ct_counters[CT_ERROR] != 0u) {
        return;
    }
    uint per_group = CT_GROUP_SIZE / CT_VERTEX_THREADS;
    uint lane = gl_LocalInvocationID.x % CT_VERTEX_THREADS;
    uint stride = gl_NumWorkGroups.x * per_group;
    for (uint tri = gl_GlobalInvocationID.x / CT_VERTEX_THREADS; tri < ct.tri_count; tri += stride) {
        uint id = ct.patch_count + tri;
        uint rec = id * CT_PATCH_WORDS;
        if (ct_patches[rec + CT_REC_M] == 0u) {
            continue;
        }
        uvec3 e = uvec3(ct_patches[rec + CT_REC_EDGES], ct_patches[rec + CT_REC_EDGES + 1u],
            ct_patches[rec + CT_REC_EDGES + 2u]);
        PnPattern t = pn_pattern(e);
        uint base = ct_scan[id].x;
        uint word = (tri & ((1u << CT_PATCH_BITS) - 1u)) | (1u << CT_PN_SHIFT)
            | (min(uint(findMSB(t.m)), 15u) << CT_DEPTH_SHIFT);
        for (uint k = lane; k < t.vertices; k += CT_VERTEX_THREADS) {
            emit_vertex(tri, t, base, k, word);
        }
    }
}
