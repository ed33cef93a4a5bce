// Descriptor set 1 of method `corners` (src/methods/corners/): the visible
// patches its cull appends, and the VkDrawIndirectCommand of its draw, whose
// instance count the cull counts into.
#ifndef CORNERS_GLSL
#define CORNERS_GLSL

#include "common/scene.glsl"
#include "constants.glsl"

layout(std430, set = SET_PASS, binding = BIND_CORNERS_VISIBLE) buffer CornersVisible {
    uint visible[];
};

layout(std430, set = SET_PASS, binding = BIND_CORNERS_DRAW) buffer CornersDraw {
    uint draw_args[];
};

#endif
