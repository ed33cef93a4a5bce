// The animation update pass (src/gpu/anim.rs), one step per dispatch
// (AnimPush.pass): deform the cage vertices, evaluate the point rows, the
// shading rows, and write the moving models' patches and shading patches
// and the keyed instances' records over set 0's. Grid-stride loops: any count fits any launch.
#version 460

#include "common/anim.glsl"

layout(local_size_x = ANIM_GROUP_SIZE) in;

void deform_vertex(uint v) {
    uvec4 model = anim_models[anim_vertex_model[v]];
    vec3 p;
    if (model.z != ANIM_NO_SEQUENCE) {
        uint i = 3u * (model.z + v - model.w);
        p = vec3(anim_inputs[i], anim_inputs[i + 1u], anim_inputs[i + 2u]);
    } else {
        p = vec3(anim_rest[3u * v], anim_rest[3u * v + 1u], anim_rest[3u * v + 2u]);
    }
    for (uint k = 0u; k < model.y; ++k) {
        p = anim_deform(anim_deformers[model.x + k], p);
    }
    anim_verts[3u * v] = p.x;
    anim_verts[3u * v + 1u] = p.y;
    anim_verts[3u * v + 2u] = p.z;
}

void point_row(uint r) {
    vec3 base;
    vec3 acc;
    ANIM_ROW_SUM(anim_point_rows, anim_point_terms, anim_verts, r, base, acc)
    precise vec3 q = base + acc;
    anim_points[3u * r] = q.x;
    anim_points[3u * r + 1u] = q.y;
    anim_points[3u * r + 2u] = q.z;
}

void shading_row(uint r) {
    vec3 base;
    vec3 acc;
    ANIM_ROW_SUM(anim_shading_rows, anim_shading_terms, anim_points, r, base, acc)
    anim_vectors[3u * r] = acc.x;
    anim_vectors[3u * r + 1u] = acc.y;
    anim_vectors[3u * r + 2u] = acc.z;
}

// Thread t of the write step below the model patches: patch (t - first
// thread) of the deforming model whose thread range holds t, in model
// space, points and shading vectors.
void write_patch(uint t) {
    uint lo = 0u;
    uint hi = anim.targets;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (anim_targets[mid].x <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    uvec4 target = anim_targets[lo];
    uint k = t - target.x;
    uint dst = target.y + k;
    uint src = target.z + k;
    for (uint s = 0u; s < 16u; ++s) {
        uint r = 3u * anim_patch_rows[16u * src + s];
        uint o = 48u * dst + 3u * s;
        anim_patch_data[o] = anim_points[r];
        anim_patch_data[o + 1u] = anim_points[r + 1u];
        anim_patch_data[o + 2u] = anim_points[r + 2u];
    }
    for (uint n = 0u; n < 24u; ++n) {
        uint r = 3u * (24u * src + n);
        uint o = SHADING_FLOATS * dst + 3u * n;
        anim_shading[o] = anim_vectors[r];
        anim_shading[o + 1u] = anim_vectors[r + 1u];
        anim_shading[o + 2u] = anim_vectors[r + 2u];
    }
}

// Record k of the frame's keyed instances over its instance.
void write_record(uint k) {
    uint dst = INSTANCE_WORDS * anim_keyed[k];
    for (uint w = 0u; w < INSTANCE_WORDS; ++w) {
        anim_instance_words[dst + w] = anim_records[INSTANCE_WORDS * k + w];
    }
}

void main() {
    uint stride = gl_NumWorkGroups.x * ANIM_GROUP_SIZE;
    for (uint i = gl_GlobalInvocationID.x; i < anim.count; i += stride) {
        if (anim.pass == ANIM_PASS_DEFORM) {
            deform_vertex(i);
        } else if (anim.pass == ANIM_PASS_POINTS) {
            point_row(i);
        } else if (anim.pass == ANIM_PASS_VECTORS) {
            shading_row(i);
        } else if (i < anim.patches) {
            write_patch(i);
        } else {
            write_record(i - anim.patches);
        }
    }
}
