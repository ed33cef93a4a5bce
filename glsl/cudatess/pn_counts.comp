// cudatess for PN triangles, stage 3: one invocation per triangle reads its
// three edges' final factors, records them and its core factor after the
// patches' records, and writes its vertex and index counts as the scan's
// input after the patches' (the one scan covers both). A culled triangle
// counts nothing. Invocation 0 writes the zero after the last triangle,
// whose exclusive sum becomes the totals.
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"
#include "common/pn.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

void process(uint t) {
    uint id = ct.patch_count + t;
    uint rec = id * CT_PATCH_WORDS;
    uvec2 counts = uvec2(0u);
    uvec4 e = uvec4(0u);
    if (ct_patches[rec + CT_REC_M] != 0u) {
        uvec4 edges = pn_edge_ids[t];
        e.xyz = uvec3(ct_edge_factors[edges.x], ct_edge_factors[edges.y],
            ct_edge_factors[edges.z]);
        PnPattern p = pn_pattern(e.xyz);
        e.w = p.m;
        counts = uvec2(p.vertices, p.indices);
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
        ct_scan[ct.patch_count + ct.tri_count] = uvec2(0u);
    }
    uint stride = gl_NumWorkGroups.x * CT_GROUP_SIZE;
    for (uint t = gl_GlobalInvocationID.x; t < ct.tri_count; t += stride) {
        process(t);
    }
}
