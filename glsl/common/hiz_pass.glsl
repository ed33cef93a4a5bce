// The depth pyramid's passes (hiz_init.comp, hiz_init_ms.comp,
// hiz_reduce.comp): set 1 holds the depth image the early phase drew and
// the pyramid (layout in common/hiz.glsl); one invocation per texel of the
// level written. The Rust side is src/draw/hiz.rs.
#ifndef HIZ_PASS_GLSL
#define HIZ_PASS_GLSL

layout(std430, set = SET_PASS, binding = BIND_HIZ_PYRAMID) buffer Pyramid {
    float pyramid[];
};

// src/gpu/blocks.rs HizPush.
layout(push_constant) uniform HizPush {
    uint src_offset;  // first float of the level read (levels 1 and up)
    uint dst_offset;  // first float of the level written
    uint src_width;
    uint src_height;
    uint dst_width;
    uint dst_height;
    uint samples;     // per pixel of the depth image (level 0)
    uint pad;
} pc;

layout(local_size_x = HIZ_GROUP, local_size_y = HIZ_GROUP) in;

#endif
