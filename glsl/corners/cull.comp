// Method `corners`, pass 1 (the worked example's compute pass): one
// invocation per base patch. The two triangles a patch draws lie in the
// convex hull of its four corner points, so a patch whose corners lie wholly
// outside the view frustum cannot draw a pixel and is dropped; the others are
// appended to the visible list, counted straight into the instance count of
// the draw's indirect arguments. The corners are read exactly as
// corners.vert reads them (patch_point), so the test and the triangles see
// the same bits.
#version 460

#include "corners.glsl"

layout(local_size_x = CORNERS_CULL_GROUP) in;

// src/methods/corners/push.rs CornersCullPush.
layout(push_constant) uniform CornersCullPush {
    uint patch_count;  // base patches
    uint pad0;
    uint pad1;
    uint pad2;
} pc;

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.patch_count) {
        return;
    }
    if ((instances[instance_of(id)].flags & INSTANCE_LOD) != 0u) {
        return;  // drawn from a level of detail (src/lod)
    }
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        vec3 c0 = patch_point(id, 0u);
        vec3 c1 = patch_point(id, 3u);
        vec3 c2 = patch_point(id, 12u);
        vec3 c3 = patch_point(id, 15u);
        vec3 lo = min3(min3(c0, c1), min3(c2, c3));
        vec3 hi = max3(max3(c0, c1), max3(c2, c3));
        if (outside_frustum(lo, hi, view)) {
            return;
        }
    }
    uint slot = atomicAdd(draw_args[CORNERS_INSTANCES], 1u);
    visible[slot] = id;
}
