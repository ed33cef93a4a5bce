// The animation update pass (src/gpu/anim.rs): cage vertices through the
// model's deformers, the stencil tables' point and shading rows, the moving
// models' patches and shading patches written over their model patches in
// set 0 (model space), and the keyed instances' records over theirs. Everything here feeds positions: every value is `precise`, sums
// are written out in the order of the CPU twins (src/anim/deform.rs,
// src/scene/stencil.rs Table::points/vectors), no fma, no mix, no built-in
// sin/cos.
#ifndef ANIM_GLSL
#define ANIM_GLSL

#include "constants.glsl"

struct AnimDeformer {
    uint kind;
    uint axis;
    uint other;
    uint pad;
    vec4 center;
    vec4 p;
};

layout(push_constant) uniform AnimPush {
    uint pass;
    uint count;
    uint targets;
    uint rows;
    uint patches;
    uint pad[3];
} anim;

// Static: every animated vertex at rest (3 floats each), its model, and per
// model (deformer first, deformer count, first input in the frame's inputs
// or ANIM_NO_SEQUENCE, first vertex).
layout(std430, set = 0, binding = BIND_ANIM_REST) readonly buffer AnimRest { float anim_rest[]; };
layout(std430, set = 0, binding = BIND_ANIM_VERTEX_MODEL) readonly buffer AnimVertexModel { uint anim_vertex_model[]; };
layout(std430, set = 0, binding = BIND_ANIM_MODELS) readonly buffer AnimModels { uvec4 anim_models[]; };
// The tables: per row (first term, terms, reference, the point row's own
// index or the shading row's float in set 0's shading patches),
// ordered by their number of terms (src/gpu/anim.rs `by_terms`); per term
// (input, weight bits).
layout(std430, set = 0, binding = BIND_ANIM_POINT_ROWS) readonly buffer AnimPointRows { uvec4 anim_point_rows[]; };
layout(std430, set = 0, binding = BIND_ANIM_POINT_TERMS) readonly buffer AnimPointTerms { uvec2 anim_point_terms[]; };
layout(std430, set = 0, binding = BIND_ANIM_SHADING_ROWS) readonly buffer AnimShadingRows { uvec4 anim_shading_rows[]; };
layout(std430, set = 0, binding = BIND_ANIM_SHADING_TERMS) readonly buffer AnimShadingTerms { uvec2 anim_shading_terms[]; };
// The point row of each control point of each model patch (16 per patch).
layout(std430, set = 0, binding = BIND_ANIM_PATCH_ROWS) readonly buffer AnimPatchRows { uint anim_patch_rows[]; };
// Per deforming model (first thread of the write step, its first model
// patch in set 0, its first patch here, 0), and one more for the end.
layout(std430, set = 0, binding = BIND_ANIM_TARGETS) readonly buffer AnimTargets { uvec4 anim_targets[]; };
// Per keyed instance, its index in set 0's instances.
layout(std430, set = 0, binding = BIND_ANIM_KEYED) readonly buffer AnimKeyed { uint anim_keyed[]; };
// Scratch: deformed vertices and point rows (xyz of a vec4: one load per
// term).
layout(std430, set = 0, binding = BIND_ANIM_VERTS) buffer AnimVerts { vec4 anim_verts[]; };
layout(std430, set = 0, binding = BIND_ANIM_POINTS) buffer AnimPoints { vec4 anim_points[]; };
// The frame's: deformers, keyed instances' records (INSTANCE_WORDS each,
// made on the host), the sequences' vertices.
layout(std430, set = 0, binding = BIND_ANIM_DEFORMERS) readonly buffer AnimDeformers { AnimDeformer anim_deformers[]; };
layout(std430, set = 0, binding = BIND_ANIM_RECORDS) readonly buffer AnimRecords { uint anim_records[]; };
layout(std430, set = 0, binding = BIND_ANIM_INPUTS) readonly buffer AnimInputs { float anim_inputs[]; };
// Set 0's model patches, shading patches and instances (scene.glsl,
// shading.glsl), written.
layout(std430, set = 0, binding = BIND_ANIM_PATCHES) writeonly buffer AnimScenePatches { float anim_patch_data[]; };
layout(std430, set = 0, binding = BIND_ANIM_SHADING) writeonly buffer AnimSceneShading { float anim_shading[]; };
layout(std430, set = 0, binding = BIND_ANIM_INSTANCES) writeonly buffer AnimSceneInstances { uint anim_instance_words[]; };

// (sin x, cos x): anim::deform::sin_cos.
vec2 anim_sin_cos(float x0) {
    precise float x = clamp(x0, -6433.0, 6433.0);
    precise float q = floor(x * uintBitsToFloat(ANIM_TWO_OVER_PI_BITS) + 0.5);
    precise float r = (x - q * uintBitsToFloat(ANIM_PIO2_HI_BITS)) - q * uintBitsToFloat(ANIM_PIO2_LO_BITS);
    precise float r2 = r * r;
    precise float ps = uintBitsToFloat(ANIM_SIN_2_BITS) + r2 * uintBitsToFloat(ANIM_SIN_3_BITS);
    ps = uintBitsToFloat(ANIM_SIN_1_BITS) + r2 * ps;
    precise float s = r + r * (r2 * ps);
    precise float pc = uintBitsToFloat(ANIM_COS_3_BITS) + r2 * uintBitsToFloat(ANIM_COS_4_BITS);
    pc = uintBitsToFloat(ANIM_COS_2_BITS) + r2 * pc;
    pc = uintBitsToFloat(ANIM_COS_1_BITS) + r2 * pc;
    precise float c = 1.0 + r2 * pc;
    int quadrant = int(q) & 3;
    if (quadrant == 0) {
        return vec2(s, c);
    } else if (quadrant == 1) {
        return vec2(c, -s);
    } else if (quadrant == 2) {
        return vec2(-s, -c);
    }
    return vec2(-c, s);
}

// One deformer applied to p: anim::deform::apply.
vec3 anim_deform(AnimDeformer d, vec3 p0) {
    precise vec3 p = p0;
    vec4 c = d.center;
    uint a = d.axis % 3u;
    if (d.kind == DEFORM_TWIST) {
        uint b1 = (a + 1u) % 3u;
        uint b2 = (a + 2u) % 3u;
        precise float h = p[a] - c[a];
        precise float theta = h * d.p.x;
        precise vec2 sc = anim_sin_cos(theta);
        precise float u = p[b1] - c[b1];
        precise float v = p[b2] - c[b2];
        precise float u2 = u * sc.y - v * sc.x;
        precise float v2 = u * sc.x + v * sc.y;
        p[b1] = c[b1] + u2;
        p[b2] = c[b2] + v2;
    } else if (d.kind == DEFORM_BEND) {
        float k = d.p.x;
        float inv_k = d.p.y;
        float len = d.p.z;
        if (k == 0.0 || inv_k == 0.0) {
            return p;
        }
        uint t = d.other % 3u;
        precise float h = p[a] - c[a];
        precise float dist = p[t] - c[t];
        precise float hc = clamp(h, 0.0, len);
        precise float theta = hc * k;
        precise vec2 sc = anim_sin_cos(theta);
        precise vec2 sc2 = anim_sin_cos(theta * 0.5);
        precise float extra = h - hc;
        precise float along = (sc.x * inv_k - dist * sc.x) + extra * sc.y;
        precise float across = ((sc2.x * sc2.x) * (2.0 * inv_k) + dist * sc.y) + extra * sc.x;
        p[a] = c[a] + along;
        p[t] = c[t] + across;
    } else if (d.kind == DEFORM_WAVE) {
        uint t = d.other % 3u;
        precise float x = p[t];
        precise vec2 sc = anim_sin_cos(x * d.p.y + d.p.z);
        precise float ramp = 1.0;
        if (d.p.w > 0.0) {
            ramp = clamp((x - c[t]) * d.p.w, 0.0, 1.0);
        }
        p[a] = p[a] + (d.p.x * ramp) * sc.x;
    }
    return p;
}

// A row of a table over inputs `x` (vec4s, xyz used): the reference x_r
// and sum_k w_k (x_k - x_r), in stored order (stencil::Table::sum).
#define ANIM_ROW_SUM(TERMS, X, row, base, acc)                                       \
    {                                                                                \
        uint end = row.x + row.y;                                                    \
        base = X[row.z].xyz;                                                         \
        precise float ax = 0.0;                                                      \
        precise float ay = 0.0;                                                      \
        precise float az = 0.0;                                                      \
        for (uint k = row.x; k < end; ++k) {                                         \
            uvec2 term = TERMS[k];                                                   \
            float w = uintBitsToFloat(term.y);                                       \
            vec3 x = X[term.x].xyz;                                                  \
            ax = ax + (x.x - base.x) * w;                                            \
            ay = ay + (x.y - base.y) * w;                                            \
            az = az + (x.z - base.z) * w;                                            \
        }                                                                            \
        acc = vec3(ax, ay, az);                                                      \
    }

#endif
