// cudatess, stage 6 (their Fig. 1: "determine index buffer data", one
// thread per patch): the patch's triangles into its slot of the index
// buffer (the scan's offset), as absolute vertex indices. The core's cells
// as two triangles each, (00, 10, 11) and (00, 11, 01), counter-clockwise in
// (u, v) like every other method's quads; each transition strip by a
// Bresenham-like walk along its two sides (their Fig. 3, after Moreton): a
// decision variable, initially the difference of the two sides' segment
// counts, picks the side whose next segment's midpoint comes first, so the
// triangles fan evenly between the edge's e[k] segments and the core's.
// Every strip triangle starts with a vertex of the edge (the provoking
// vertex carries the transition bit to the fragment shader).
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

void tri(inout uint at, uint base, uint a, uint b, uint c) {
    ct_indices[at] = base + a;
    ct_indices[at + 1u] = base + b;
    ct_indices[at + 2u] = base + c;
    at += 3u;
}

// Inner-side vertex l of strip k: the core's boundary row or column next to
// edge k, in the edge's direction.
uint inner_vertex(CtPattern t, uint k, uint l) {
    if (k == 0u) return ct_grid_vertex(t, t.core.x, t.core.z + l);
    if (k == 1u) return ct_grid_vertex(t, t.core.x + l, t.core.z);
    if (k == 2u) return ct_grid_vertex(t, t.core.y, t.core.z + l);
    return ct_grid_vertex(t, t.core.x + l, t.core.w);
}

// The strip along edge k: a segments on the edge, b on the inner side.
// Edges 0 and 3 run with the inside on their left in (u, v) where the
// others have it on their right, so their triangles are mirrored to stay
// counter-clockwise.
void strip(inout uint at, uint base, CtPattern t, uint k) {
    uint a = t.e[k];
    uint b = (k == 0u || k == 2u) ? t.core.w - t.core.z : t.core.y - t.core.x;
    bool mirror = k == 0u || k == 3u;
    uint i = 0u;
    uint l = 0u;
    // Q = (2l + 1) a - (2i + 1) b: the edge's next midpoint (2i + 1) / 2a
    // comes no later than the inner side's (2l + 1) / 2b while Q >= 0.
    int q = int(a) - int(b);
    while (i < a || l < b) {
        bool edge_step = l == b || (i < a && q >= 0);
        uint o = ct_edge_vertex(t, k, i);
        uint x;
        uint y;
        if (edge_step) {
            x = ct_edge_vertex(t, k, i + 1u);
            y = inner_vertex(t, k, l);
            i += 1u;
            q -= 2 * int(b);
        } else {
            x = inner_vertex(t, k, l + 1u);
            y = inner_vertex(t, k, l);
            l += 1u;
            q += 2 * int(a);
        }
        if (mirror) {
            tri(at, base, o, y, x);
        } else {
            tri(at, base, o, x, y);
        }
    }
}

void process(uint id) {
    uint rec = id * CT_PATCH_WORDS;
    if (ct_patches[rec + CT_REC_M] == 0u) {
        return;
    }
    uvec4 e = uvec4(ct_patches[rec + CT_REC_EDGES], ct_patches[rec + CT_REC_EDGES + 1u],
        ct_patches[rec + CT_REC_EDGES + 2u], ct_patches[rec + CT_REC_EDGES + 3u]);
    CtPattern t = ct_pattern(e);
    uvec2 offsets = ct_scan[id];
    uint base = offsets.x;
    uint at = offsets.y;
    for (uint j = t.core.z; j < t.core.w; ++j) {
        for (uint i = t.core.x; i < t.core.y; ++i) {
            uint v00 = ct_grid_vertex(t, i, j);
            uint v10 = ct_grid_vertex(t, i + 1u, j);
            uint v11 = ct_grid_vertex(t, i + 1u, j + 1u);
            uint v01 = ct_grid_vertex(t, i, j + 1u);
            tri(at, base, v00, v10, v11);
            tri(at, base, v00, v11, v01);
        }
    }
    for (uint k = 0u; k < 4u; ++k) {
        if (t.strip[k]) {
            strip(at, base, t, k);
        }
    }
}

void main() {
    if (ct_counters[CT_ERROR] != 0u) {
        return;
    }
    uint stride = gl_NumWorkGroups.x * CT_GROUP_SIZE;
    for (uint id = gl_GlobalInvocationID.x; id < ct.patch_count; id += stride) {
        process(id);
    }
}
