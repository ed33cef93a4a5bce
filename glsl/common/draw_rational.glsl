// Drawn positions for both ready-list draw paths (draw.mesh, expand.comp),
// rational patches included: a patch flagged PATCH_RATIONAL evaluates its
// homogeneous surface at the node mesh's dyadic parameters and divides
// (oracle::node_positions_rational); every other patch takes
// node_positions() of draw.glsl exactly as before. Include after draw.glsl.
#ifndef DRAW_RATIONAL_GLSL
#define DRAW_RATIONAL_GLSL

#include "draw.glsl"
#include "rational_subdiv.glsl"

void patch_node_positions(uint id, NodeMesh mesh, out vec3 pos[NODE_MESH_SLOTS]) {
    Instance t = instances[instance_of(id)];
    if ((patch_flags_in(t, id) & PATCH_RATIONAL) != 0u) {
        vec4 H[16];
        load_homogeneous_in(t, id, H);
        for (uint s = 0u; s < NODE_MESH_SLOTS; ++s) {
            pos[s] = slot_used(mesh, s) ? eval_rational(H, mesh.uv[s].x, mesh.uv[s].y) : pos[0];
        }
        return;
    }
    vec3 P[16];
    load_patch_in(t, id, P);
    node_positions(P, mesh, pos);
}

#endif
