// cudatess, after the scan: one invocation turns the totals (the exclusive
// sum past the last patch) into the indexed indirect draw's arguments, or,
// where the vertices or indices do not fit their buffers, into an error bit
// and an empty draw (the host grows the buffers and draws the frame again;
// the vertex and index passes skip a frame with an error).
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"

layout(local_size_x = 1) in;

void main() {
    uvec2 total = ct_scan[ct.patch_count + ct.tri_count];
    ct_counters[CT_VERTEX_TOTAL] = total.x;
    ct_counters[CT_INDEX_TOTAL] = total.y;
    uint err = (total.x > ct.vertex_capacity ? CT_ERR_VERTICES_FULL : 0u)
        | (total.y > ct.index_capacity ? CT_ERR_INDICES_FULL : 0u);
    ct_counters[CT_ERROR] |= err;
    ct_counters[CT_DRAW_ARGS] = err == 0u ? total.y : 0u;
    ct_counters[CT_DRAW_ARGS + 1u] = 1u;
    ct_counters[CT_DRAW_ARGS + 2u] = 0u;
    ct_counters[CT_DRAW_ARGS + 3u] = 0u;
    ct_counters[CT_DRAW_ARGS + 4u] = 0u;
}
