// Fragment stage of ground-truth: draw_vert.frag's shading, with rational
// patches lit and keyed by their own rational normal (SHADE_RATIONAL, as
// cudatess/draw.frag), so the hole test's reference shows which side of a
// rational surface is seen.
#version 460

#define SHADE_RATIONAL
#include "common/scene.glsl"
#include "common/draw.glsl"
#include "common/shade.glsl"

layout(location = 0) centroid in vec3 in_world;
layout(location = 1) centroid in vec2 in_uv;
layout(location = 2) flat in uint in_patch;
layout(location = 3) flat in uint in_depth;
layout(location = 4) flat in uint in_wedge;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = shade(in_world, in_uv, in_patch, same_depths(in_depth), in_wedge, gl_FrontFacing);
}
