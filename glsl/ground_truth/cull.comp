// Ground truth, pass 1: one invocation per base patch. A patch whose control
// points lie wholly outside the view frustum cannot draw a pixel (the patch
// lies in their convex hull, a rational one too, its weights being
// positive) and is counted as culled; the others are appended to the
// visible list of their part of the frame (patches_per_part consecutive
// base patches each), their count going straight into the instance count of
// that part's indexed indirect draw. Part k's list starts at entry
// k * patches_per_part, its draw's first instance (set by the host). A
// displaced model's box grows by its largest |displacement|.
#version 460

#include "grid.glsl"
#include "common/texture.glsl"
#include "common/displace.glsl"

layout(local_size_x = GRID_CULL_GROUP_SIZE) in;

// src/methods/ground_truth/push.rs GridPush.
layout(push_constant) uniform GridPush {
    uint patch_count;        // base patches
    uint indices_per_patch;  // 6 per grid cell (the host sets the draws' index counts)
    uint patches_per_part;   // base patches drawn by one part of the frame
    uint pad0;
} pc;

void main() {
    uint id = gl_GlobalInvocationID.x;
    if (id >= pc.patch_count) {
        return;
    }
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u) {
        vec3 P[16];
        load_patch(id, P);
        vec3 lo, hi;
        patch_bbox(P, lo, hi);
        DispModel dm;
        if (displaced_model(patch_flags_of(id) >> PATCH_MODEL_SHIFT, dm)) {
            lo -= vec3(dm.margin);
            hi += vec3(dm.margin);
        }
        if (outside_frustum(lo, hi, view)) {
            atomicAdd(grid_counters[G_CULLED], 1u);
            return;
        }
    }
    uint part = id / pc.patches_per_part;
    uint slot = atomicAdd(grid_counters[G_DRAW_ARGS + part * G_ARGS_WORDS + 1u], 1u);
    visible[part * pc.patches_per_part + slot] = id;
}
