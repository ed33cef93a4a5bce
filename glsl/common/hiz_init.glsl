// Level 0 of the depth pyramid: each pixel's farthest depth sample (with
// multisampling a pixel is covered by the nearest surface only where all
// its samples are). Included by hiz_init.comp and, with HIZ_MULTISAMPLED,
// hiz_init_ms.comp.
#include "constants.glsl"
#include "hiz_pass.glsl"

#ifdef HIZ_MULTISAMPLED
layout(set = SET_PASS, binding = BIND_HIZ_DEPTH) uniform sampler2DMS depth_image;
#else
layout(set = SET_PASS, binding = BIND_HIZ_DEPTH) uniform sampler2D depth_image;
#endif

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.dst_width || p.y >= pc.dst_height) {
        return;
    }
#ifdef HIZ_MULTISAMPLED
    float z = 0.0;
    for (int s = 0; s < int(pc.samples); ++s) {
        z = max(z, texelFetch(depth_image, ivec2(p), s).r);
    }
#else
    float z = texelFetch(depth_image, ivec2(p), 0).r;
#endif
    pyramid[pc.dst_offset + p.y * pc.dst_width + p.x] = z;
}
