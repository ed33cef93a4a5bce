// Ground truth, the draw: instance k is visible patch visible[k], vertex
// j * (grid + 1) + i its sample at (i / grid, j / grid), evaluated by the
// shared precise function on the model patch and placed by the patch's
// instance (one point placed per vertex, not sixteen). The grid is a power
// of two, so the parameters are exact and neighbouring patches compute
// their shared edge's points bit for bit. Shaded by draw_vert.frag like the fallback path; the depth
// heat map shows log2(grid), the level a uniform subdivision to the same
// density would reach. A rational patch (PATCH_RATIONAL) is evaluated in
// homogeneous coordinates (common/rational.glsl, Schwarz and Stamminger
// §3) and projected; curve4 is reversal-symmetric like curve, so its shared
// edges meet bit for bit too. Shaded by ground_truth/grid.frag (its own rational normal).
// A displaced model's grid points move by n̂·d like the subdivision's
// vertices (common/displace.glsl, each shared point by its owner), so the
// displaced reference is as watertight as the base one.
#version 460

#include "grid.glsl"
#include "common/rational.glsl"
#include "common/draw.glsl"
#include "common/texture.glsl"
#include "common/displace.glsl"

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;
layout(location = 2) flat out uint out_patch;
layout(location = 3) flat out uint out_depth;
layout(location = 4) flat out uint out_wedge;

void main() {
    uint id = visible[gl_InstanceIndex];
    uint row = pc.grid + 1u;
    uint i = uint(gl_VertexIndex) % row;
    uint j = uint(gl_VertexIndex) / row;
    float step = 1.0 / float(pc.grid);
    vec2 uv = vec2(float(i) * step, float(j) * step);
    Instance t = instances[instance_of(id)];
    vec3 p;
    if (flags_rational(patch_flags_in(t, id))) {
        vec4 H[16];
        load_model_homogeneous_in(t, id, H);
        p = place_in(t, project(eval_patch4(H, uv.x, uv.y)));
    } else {
        vec3 P[16];
        load_model_patch_in(t, id, P);
        p = place_in(t, eval_patch(P, uv.x, uv.y));
        DispModel dm;
        if (displaced_model(patch_flags_in(t, id) >> PATCH_MODEL_SHIFT, dm)) {
            precise vec3 moved = p + displacement_offset(t, id, dm, uv);
            p = moved;
        }
    }
    gl_Position = clip_position(p);
    out_world = p;
    out_uv = uv;
    out_patch = id;
    out_depth = uint(findMSB(pc.grid));
    out_wedge = 0u;
}
