// Texture coordinates and albedo maps (src/scene/material.rs and
// src/scene/texture.rs): a UV patch per model patch, evaluated at the base
// patch's (u, v), and each model's mip-mapped map, read from a storage
// buffer by texel fetches and filtered here, trilinearly, in linear light.
// The filtering is this file's arithmetic on every device, so every method
// samples a map the same way (FLIP compares them fairly). Include after
// scene.glsl.
#ifndef TEXTURE_GLSL
#define TEXTURE_GLSL

// 16 (s, t) pairs per model patch, u fastest.
layout(std430, set = SET_SCENE, binding = BIND_UV_PATCHES) readonly buffer UvPatches {
    float uv_patch_data[];
};

// Per scene model: first texel word, width (0: no map), height, levels.
layout(std430, set = SET_SCENE, binding = BIND_MATERIALS) readonly buffer Materials {
    uvec4 materials[];
};

// sRGB-encoded RGBA8, red in the low byte, rows top to bottom, level
// after level.
layout(std430, set = SET_SCENE, binding = BIND_TEXELS) readonly buffer Texels {
    uint texels[];
};

// curve2(), eval_patch2(): the patches' evaluation (bezier_template.glsl)
// on (s, t) points, the operation order of the CPU twin
// (`SceneGeometry::surface_uv`).
#define BEZ_T vec2
#define BEZ_FN(name) name##2
#include "bezier_template.glsl"

// Whether the scene has maps or UVs from a cage: false drops every read
// below (the UVs are then the patch's own parameters).
layout(constant_id = SPEC_SCENE_MATERIALS) const bool SCENE_MATERIALS = true;

// The texture coordinates at base patch `id`'s (u, v): its model patch's
// UV patch there (at (v, u) for a mirrored instance, whose base patch is
// the model patch with u and v swapped).
vec2 surface_uv(uint id, vec2 uv) {
    if (!SCENE_MATERIALS) {
        return uv;
    }
    Instance t = instances[instance_of(id)];
    uint o = 32u * (t.source + (id - t.first));
    if (o + 32u > uint(uv_patch_data.length())) {
        return uv;
    }
    vec2 p = (t.flags & INSTANCE_MIRRORED) != 0u ? uv.yx : uv;
    vec2 P[16];
    for (uint k = 0u; k < 16u; ++k) {
        P[k] = vec2(uv_patch_data[o + 2u * k], uv_patch_data[o + 2u * k + 1u]);
    }
    return eval_patch2(P, p.x, p.y);
}

// Model `model`'s material record (all zero: no map).
uvec4 material_of(uint model) {
    if (!SCENE_MATERIALS || model >= uint(materials.length())) {
        return uvec4(0u);
    }
    return materials[model];
}

bool has_map(uvec4 mat) {
    return mat.y != 0u;
}

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), greaterThan(c, vec3(0.04045)));
}

vec3 linear_to_srgb(vec3 l) {
    l = clamp(l, 0.0, 1.0);
    return mix(l * 12.92, 1.055 * pow(l, vec3(1.0 / 2.4)) - 0.055, greaterThan(l, vec3(0.0031308)));
}

// Texel (x, y) of a level `size` texels large starting at word `at`,
// wrapped (the map repeats), in linear light.
vec3 map_texel(uint at, ivec2 size, ivec2 q) {
    ivec2 w = ((q % size) + size) % size;
    uint c = texels[at + uint(w.y * size.x + w.x)];
    vec3 rgb = vec3(float(c & 255u), float((c >> 8) & 255u), float((c >> 16) & 255u)) / 255.0;
    return srgb_to_linear(rgb);
}

// Level `level` of map `mat` at (s, t), bilinear. t = 0 is the image's
// bottom row (OBJ's convention), and texel centres lie at half-integers.
vec3 map_level(uvec4 mat, uint level, vec2 st) {
    uint at = mat.x;
    ivec2 size = ivec2(mat.yz);
    for (uint k = 0u; k < level; ++k) {
        at += uint(size.x * size.y);
        size = max(size / 2, ivec2(1));
    }
    vec2 f = vec2(fract(st.x), 1.0 - fract(st.y)) * vec2(size) - 0.5;
    vec2 c = floor(f);
    vec2 w = f - c;
    ivec2 q = ivec2(c);
    vec3 t00 = map_texel(at, size, q);
    vec3 t10 = map_texel(at, size, q + ivec2(1, 0));
    vec3 t01 = map_texel(at, size, q + ivec2(0, 1));
    vec3 t11 = map_texel(at, size, q + ivec2(1, 1));
    return mix(mix(t00, t10, w.x), mix(t01, t11, w.x), w.y);
}

// Map `mat` at (s, t), trilinear: the level where a pixel step (the
// coordinates' screen derivatives `dx`, `dy`) spans one texel. A display
// value (sRGB-encoded), as every colour of shade() is.
vec3 map_albedo(uvec4 mat, vec2 st, vec2 dx, vec2 dy) {
    vec2 size = vec2(mat.yz);
    float rho = max(length(dx * size), length(dy * size));
    float lod = clamp(log2(max(rho, 1e-8)), 0.0, float(mat.w - 1u));
    uint l0 = uint(floor(lod));
    uint l1 = min(l0 + 1u, mat.w - 1u);
    vec3 c = mix(map_level(mat, l0, st), map_level(mat, l1, st), lod - float(l0));
    return linear_to_srgb(c);
}

#endif
