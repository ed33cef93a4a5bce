// The push constants of cudatess's compute passes
// (src/methods/cudatess/push.rs CtPush). The draw uses DrawPush instead.
#ifndef CUDATESS_PUSH_GLSL
#define CUDATESS_PUSH_GLSL

#include "common/constants.glsl"
#include "constants.glsl"

layout(push_constant) uniform CtPush {
    uint patch_count;      // base patches
    uint vertex_capacity;  // vertices the vertex buffer holds
    uint index_capacity;   // indices the index buffer holds
    uint options;          // CT_OPT_*
    uint scan_offset;      // scan: the level's first entry
    uint scan_count;       // scan: entries in the level
    uint scan_sums;        // scan: the next level's first entry (block sums), or ~0u
    uint pass;             // scan: CT_SCAN_PASS_*
    uint tri_count;        // PN triangles (records and scan entries after the patches')
    uint pad0;
    uint pad1;
    uint pad2;
} ct;

#endif
