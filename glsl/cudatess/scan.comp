// cudatess, stage 4 (their Fig. 1: "derive vertex and index buffer offsets"
// by an exclusive parallel scan, after Sengupta et al.): pairs (vertex count,
// index count) are scanned together, CT_SCAN_BLOCK entries per workgroup in
// shared memory (up-sweep and down-sweep of a balanced tree). A level longer
// than a block is scanned block by block, each block's sum going to the next
// level, which is scanned the same way until one block holds it all; then
// the add pass hands each block of a level the exclusive sum of the blocks
// before it, top level first. The host plans the levels (src/methods/
// cudatess/scan.rs); any length works, 0 and 1 included.
#version 460

#include "push.glsl"

layout(local_size_x = CT_SCAN_GROUP_SIZE) in;

layout(std430, set = SET_PASS, binding = BIND_CT_SCAN) buffer CtScan {
    uvec2 ct_scan[];
};

shared uvec2 block[CT_SCAN_BLOCK];

void main() {
    uint base = gl_WorkGroupID.x * CT_SCAN_BLOCK;
    uint lid = gl_LocalInvocationID.x;
    if (ct.pass == CT_SCAN_PASS_ADD) {
        uvec2 before = ct_scan[ct.scan_sums + gl_WorkGroupID.x];
        for (uint k = 0u; k < 2u; ++k) {
            uint g = base + 2u * lid + k;
            if (g < ct.scan_count) {
                ct_scan[ct.scan_offset + g] += before;
            }
        }
        return;
    }
    for (uint k = 0u; k < 2u; ++k) {
        uint i = 2u * lid + k;
        uint g = base + i;
        block[i] = g < ct.scan_count ? ct_scan[ct.scan_offset + g] : uvec2(0u);
    }
    // Up-sweep: partial sums up a balanced tree.
    uint stride = 1u;
    for (uint d = CT_SCAN_BLOCK >> 1; d > 0u; d >>= 1) {
        barrier();
        if (lid < d) {
            uint a = stride * (2u * lid + 1u) - 1u;
            uint b = stride * (2u * lid + 2u) - 1u;
            block[b] += block[a];
        }
        stride <<= 1;
    }
    barrier();
    if (lid == 0u) {
        if (ct.scan_sums != 0xffffffffu) {
            ct_scan[ct.scan_sums + gl_WorkGroupID.x] = block[CT_SCAN_BLOCK - 1u];
        }
        block[CT_SCAN_BLOCK - 1u] = uvec2(0u);
    }
    // Down-sweep: each node passes its sum to the right and the sum before
    // it to the left.
    for (uint d = 1u; d < CT_SCAN_BLOCK; d <<= 1) {
        stride >>= 1;
        barrier();
        if (lid < d) {
            uint a = stride * (2u * lid + 1u) - 1u;
            uint b = stride * (2u * lid + 2u) - 1u;
            uvec2 left = block[a];
            block[a] = block[b];
            block[b] += left;
        }
    }
    barrier();
    for (uint k = 0u; k < 2u; ++k) {
        uint i = 2u * lid + k;
        uint g = base + i;
        if (g < ct.scan_count) {
            ct_scan[ct.scan_offset + g] = block[i];
        }
    }
}
