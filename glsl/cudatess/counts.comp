// cudatess, stage 3 (their Fig. 1: "determine required number of vertices
// and indices"): one invocation per base patch reads its four edges' final
// factors (the largest of every patch on the edge, stage 1), records them
// with its pattern's vertex and index counts, and writes the counts as the
// scan's input. A culled patch counts nothing. Invocation 0 also writes the
// zero after the last patch, whose exclusive sum becomes the totals.
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

void process(uint id) {
    uint rec = id * CT_PATCH_WORDS;
    uvec2 counts = uvec2(0u);
    uvec4 e = uvec4(0u);
    if (ct_patches[rec + CT_REC_M] != 0u) {
        uvec4 edges = ct_edge_ids[id];
        e = uvec4(ct_edge_factors[edges.x], ct_edge_factors[edges.y],
            ct_edge_factors[edges.z], ct_edge_factors[edges.w]);
        CtPattern t = ct_pattern(e);
        counts = uvec2(t.vertices, t.indices);
    }
    for (uint k = 0u; k < 4u; ++k) {
        ct_patches[rec + CT_REC_EDGES + k] = e[k];
    }
    ct_patches[rec + CT_REC_VERTICES] = counts.x;
    ct_patches[rec + CT_REC_INDICES] = counts.y;
    ct_scan[id] = counts;
}

void main() {
    if (gl_GlobalInvocationID.x == 0u) {
        // After the PN triangles' entries (cudatess/pn_counts.comp), if any.
        ct_scan[ct.patch_count + ct.tri_count] = uvec2(0u);
    }
    uint stride = gl_NumWorkGroups.x * CT_GROUP_SIZE;
    for (uint id = gl_GlobalInvocationID.x; id < ct.patch_count; id += stride) {
        process(id);
    }
}
