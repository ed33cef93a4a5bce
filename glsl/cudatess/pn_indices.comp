// cudatess for PN triangles, stage 6: one invocation per triangle writes
// its triangles into its slot of the index buffer: the core's uniform grid
// (r^2 triangles), then a strip per edge between the edge (e[k] segments)
// and the core's side facing it (r segments), zipped by the patch path's
// Bresenham-like walk (cudatess/indices.comp). The core side runs in the edge's
// direction with the inside on the left of both, so (edge i, edge i + 1,
// core l) and (edge i, core l + 1, core l) are counter-clockwise like the
// triangle. Every strip triangle starts with an edge vertex.
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"
#include "common/pn.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

void tri(inout uint at, uint base, uint a, uint b, uint c) {
    ct_indices[at] = base + a;
    ct_indices[at + 1u] = base + b;
    ct_indices[at + 2u] = base + c;
    at += 3u;
}

void strip(inout uint at, uint base, PnPattern t, uint k) {
    uint a = t.e[k];
    uint b = t.r;
    uint i = 0u;
    uint l = 0u;
    int q = int(a) - int(b);
    while (i < a || l < b) {
        bool edge_step = l == b || (i < a && q >= 0);
        uint o = pn_edge_vertex(t, k, i);
        if (edge_step) {
            tri(at, base, o, pn_edge_vertex(t, k, i + 1u), pn_side_vertex(t, k, l));
            i += 1u;
            q -= 2 * int(b);
        } else {
            tri(at, base, o, pn_side_vertex(t, k, l + 1u), pn_side_vertex(t, k, l));
            l += 1u;
            q += 2 * int(a);
        }
    }
}

void process(uint t_id) {
    uint id = ct.patch_count + t_id;
    uint rec = id * CT_PATCH_WORDS;
    if (ct_patches[rec + CT_REC_M] == 0u) {
        return;
    }
    uvec3 e = uvec3(ct_patches[rec + CT_REC_EDGES], ct_patches[rec + CT_REC_EDGES + 1u],
        ct_patches[rec + CT_REC_EDGES + 2u]);
    PnPattern t = pn_pattern(e);
    uvec2 offsets = ct_scan[id];
    uint base = offsets.x;
    uint at = offsets.y;
    for (uint b = 0u; b < t.r; ++b) {
        for (uint a = 0u; a + b < t.r; ++a) {
            tri(at, base, pn_core_vertex(t, a, b), pn_core_vertex(t, a + 1u, b),
                pn_core_vertex(t, a, b + 1u));
            if (a + b + 2u <= t.r) {
                tri(at, base, pn_core_vertex(t, a + 1u, b), pn_core_vertex(t, a + 1u, b + 1u),
                    pn_core_vertex(t, a, b + 1u));
            }
        }
    }
    for (uint k = 0u; k < 3u; ++k) {
        strip(at, base, t, k);
    }
}

void main() {
    if (ct_counters[CT_ERROR] != 0u) {
        return;
    }
    uint stride = gl_NumWorkGroups.x * CT_GROUP_SIZE;
    for (uint t = gl_GlobalInvocationID.x; t < ct.tri_count; t += stride) {
        process(t);
    }
}
