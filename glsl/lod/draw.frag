// Levels of detail (src/lod), fragment stage: shade() as the patches are
// shaded, with the interpolated vertex normal in place of a patch's
// (SHADE_LEVEL). A mirroring instance reverses the triangles' winding, so
// its front faces are the rasterizer's back faces.
#version 460

#define SHADE_LEVEL
#include "common/scene.glsl"
#include "common/draw.glsl"
#include "common/shade.glsl"

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec2 in_st;
layout(location = 2) flat in uint in_patch;
layout(location = 3) in vec3 in_normal;
layout(location = 4) flat in uint in_mirrored;

layout(location = 0) out vec4 out_color;

void main() {
    g_level_normal = in_normal;
    g_level_st = in_st;
    bool front = gl_FrontFacing != (in_mirrored != 0u);
    out_color = shade(in_world, in_st, in_patch, same_depths(0u), WEDGE_NONE, front);
}
