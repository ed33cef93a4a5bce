// cudatess's fragment stage: draw_vert.frag's shading, with rational
// patches lit and keyed by their own rational normal (SHADE_RATIONAL in
// common/shade.glsl); polynomial patches get exactly the shading of every
// other method (the shading patches at the base patch's (u, v)); PN
// triangles are lit with their quadratic normal field (SHADE_PN).
#version 460

#define SHADE_RATIONAL
#define SHADE_PN
#define CT_ACCESS readonly
#include "common/scene.glsl"
#include "common/pn.glsl"
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
