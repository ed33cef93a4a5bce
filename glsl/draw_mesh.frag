// Fragment stage of draw path A: depth and wedge bit arrive per primitive.
#version 460
#extension GL_EXT_mesh_shader : require

// Rational patches are lit with their own rational normal (shade.glsl).
#define SHADE_RATIONAL
#include "common/scene.glsl"
#include "common/draw.glsl"
#include "common/shade.glsl"

layout(location = 0) centroid in vec3 in_world;
layout(location = 1) centroid in vec2 in_uv;
layout(location = 2) flat in uint in_patch;
layout(location = 3) perprimitiveEXT flat in uint in_depth;
layout(location = 4) perprimitiveEXT flat in uint in_wedge;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = shade(in_world, in_uv, in_patch, in_depth, in_wedge, gl_FrontFacing);
}
