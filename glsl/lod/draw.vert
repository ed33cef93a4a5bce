// Levels of detail (src/lod), vertex stage: an indexed draw per instance
// drawn from a level (written by cull.comp), its instance index the
// instance record's. Vertices
// are pulled from the level buffer (LOD_VERTEX_WORDS each, model space) and
// placed by the instance like a patch's control points.
#version 460

#include "common/scene.glsl"
#include "common/draw.glsl"
#include "constants.glsl"

layout(std430, set = SET_PASS, binding = BIND_LOD_VERTICES) readonly buffer LodVertices {
    uint lod_vertices[];
};

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_st;
layout(location = 2) flat out uint out_patch;
layout(location = 3) out vec3 out_normal;
layout(location = 4) flat out uint out_mirrored;

// The unit vector of an octahedral code (src/lod/gpu.rs oct_encode).
vec3 oct_decode(uint w) {
    vec2 e = unpackSnorm2x16(w);
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) {
        vec2 s = vec2(e.x >= 0.0 ? 1.0 : -1.0, e.y >= 0.0 ? 1.0 : -1.0);
        n.xy = (1.0 - abs(n.yx)) * s;
    }
    return normalize(n);
}

void main() {
    Instance t = instances[gl_InstanceIndex];
    uint o = uint(gl_VertexIndex) * LOD_VERTEX_WORDS;
    vec3 p = vec3(uintBitsToFloat(lod_vertices[o]), uintBitsToFloat(lod_vertices[o + 1u]),
        uintBitsToFloat(lod_vertices[o + 2u]));
    vec3 n = oct_decode(lod_vertices[o + 3u]);
    bool identity = (t.flags & INSTANCE_IDENTITY) != 0u;
    vec3 w = identity ? p : place_point(t.rows[0], t.rows[1], t.rows[2], p);
    // Normals go by the inverse transpose of the linear part (whose rows
    // are the records' rows: mat3() takes them as columns, the transpose).
    mat3 linear_t = mat3(t.rows[0].xyz, t.rows[1].xyz, t.rows[2].xyz);
    out_normal = identity ? n : normalize(inverse(linear_t) * n);
    bool mirrored = (t.flags & INSTANCE_MIRRORED) != 0u;
    out_st = vec2(uintBitsToFloat(lod_vertices[o + 4u]), uintBitsToFloat(lod_vertices[o + 5u]));
    // Its first patch: shade() reads the model's flags and material there.
    out_patch = t.first;
    out_mirrored = mirrored ? 1u : 0u;
    out_world = w;
    gl_Position = clip_position(w);
}
