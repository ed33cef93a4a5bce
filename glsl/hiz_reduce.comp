// One level of the depth pyramid from the one below: each texel the
// farthest of the (up to) 2 x 2 texels it covers.
#version 460

#include "common/constants.glsl"
#include "common/hiz_pass.glsl"

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.dst_width || p.y >= pc.dst_height) {
        return;
    }
    uvec2 a = 2u * p;
    uvec2 b = min(a + 1u, uvec2(pc.src_width, pc.src_height) - 1u);
    float z = max(max(pyramid[pc.src_offset + a.y * pc.src_width + a.x],
                      pyramid[pc.src_offset + a.y * pc.src_width + b.x]),
                  max(pyramid[pc.src_offset + b.y * pc.src_width + a.x],
                      pyramid[pc.src_offset + b.y * pc.src_width + b.x]));
    pyramid[pc.dst_offset + p.y * pc.dst_width + p.x] = z;
}
