// The animation update pass (src/gpu/anim.rs), one step per dispatch
// (AnimPush.pass): deform the cage vertices; evaluate the point rows; then
// the shading rows, written straight into the moving models' shading
// patches, the moving models' points gathered into their patches, and the
// keyed instances' records, all in set 0. Grid-stride loops: any count fits any launch.
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
    anim_verts[v] = vec4(p, 0.0);
}

void point_row(uint i) {
    uvec4 row = anim_point_rows[i];
    vec3 base;
    vec3 acc;
    ANIM_ROW_SUM(anim_point_terms, anim_verts, row, base, acc)
    precise vec3 q = base + acc;
    anim_points[row.w] = vec4(q, 0.0);
}

// The deforming model whose range of write-step threads (x: its first)
// holds `t`.
uvec4 target_of(uint t) {
    uint lo = 0u;
    uint hi = anim.targets;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        uint first = anim_targets[mid].x;
        if (first <= t) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return anim_targets[lo];
}

// A shading row, written straight into its model's shading patch in set
// 0, at the float the host found for it (row.w; src/gpu/anim.rs
// `shading_float`).
void shading_row(uint i) {
    uvec4 row = anim_shading_rows[i];
    vec3 base;
    vec3 acc;
    ANIM_ROW_SUM(anim_shading_terms, anim_points, row, base, acc)
    uint o = row.w;
    anim_shading[o] = acc.x;
    anim_shading[o + 1u] = acc.y;
    anim_shading[o + 2u] = acc.z;
}

// Thread t of the write step below the model patches: patch (t - first
// thread) of the deforming model whose thread range holds t, its points in
// model space.
void write_patch(uint t) {
    uvec4 target = target_of(t);
    uint k = t - target.x;
    uint dst = target.y + k;
    uint src = target.z + k;
    for (uint s = 0u; s < 16u; ++s) {
        vec3 q = anim_points[anim_patch_rows[16u * src + s]].xyz;
        uint o = 48u * dst + 3u * s;
        anim_patch_data[o] = q.x;
        anim_patch_data[o + 1u] = q.y;
        anim_patch_data[o + 2u] = q.z;
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
        } else if (i < anim.rows) {
            shading_row(i);
        } else if (i - anim.rows < anim.patches) {
            write_patch(i - anim.rows);
        } else {
            write_record(i - anim.rows - anim.patches);
        }
    }
}
