// Ground truth, pass 1: one workgroup per part of the frame
// (patches_per_part consecutive base patches each), walking its patches in
// order, a workgroup-wide chunk at a time. A patch whose control points
// lie wholly outside the view frustum cannot draw a pixel (the patch lies
// in their convex hull, a rational one too, its weights being positive)
// and is counted as culled; the others are appended, in patch order, to
// the part's visible list (entry k * patches_per_part on), and their count
// becomes the instance count of that part's indexed indirect draw (its
// first instance set by the host). In order, not by atomic slots: where
// two surfaces tie in depth the first drawn wins, so the image must not
// depend on which invocation ran first. A displaced model's box grows by
// its largest |displacement|.
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

// Per invocation of a chunk: shown (1) or not, then its exclusive prefix.
shared uint slots[GRID_CULL_GROUP_SIZE];
// Visible patches of the part so far.
shared uint filled;

// Whether patch `id` may draw a pixel (counting it culled when not).
bool shown(uint id) {
    if ((view.flags & FLAG_FRUSTUM_CULL) == 0u) {
        return true;
    }
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
        return false;
    }
    return true;
}

void main() {
    uint part = gl_WorkGroupID.x;
    uint lane = gl_LocalInvocationID.x;
    uint first = part * pc.patches_per_part;
    uint end = min(first + pc.patches_per_part, pc.patch_count);
    if (lane == 0u) {
        filled = 0u;
    }
    barrier();
    for (uint chunk = first; chunk < end; chunk += GRID_CULL_GROUP_SIZE) {
        uint id = chunk + lane;
        bool here = id < end && shown(id);
        slots[lane] = here ? 1u : 0u;
        barrier();
        if (lane == 0u) {
            uint at = filled;
            for (uint i = 0u; i < GRID_CULL_GROUP_SIZE; ++i) {
                uint s = slots[i];
                slots[i] = at;
                at += s;
            }
            filled = at;
        }
        barrier();
        if (here) {
            visible[first + slots[lane]] = id;
        }
        barrier();
    }
    if (lane == 0u) {
        grid_counters[G_DRAW_ARGS + part * G_ARGS_WORDS + 1u] = filled;
    }
}
