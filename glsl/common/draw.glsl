// What every draw shares: the DrawPush block (src/gpu/blocks.rs), the
// world-to-clip transform, and the geometry helpers of the two ready-list
// draw paths (task/mesh and the compute expansion + pass-through vertex
// shader), so both turn a ready QuadNode into the same clip-space positions
// and the same attributes. Include after scene.glsl.
#ifndef DRAW_GLSL
#define DRAW_GLSL

layout(push_constant) uniform DrawPush {
    mat4 view_proj;         // world -> Vulkan clip space
    vec4 light_dir;         // direction towards the light (xyz); w: SHADE_DISTANCE scale
    uint shade;             // SHADE_*
    uint capacity;          // entries of the list being drawn
    uint capture_enabled;   // write world positions to `capture`
    uint grid;              // grid draws: cells per patch side
    uint chunk;             // fallback: the chunk of the list being expanded and drawn
    uint pad[3];
} pc;

// World -> clip with the sums written out in a fixed order: the mesh shader
// and the vertex shaders are compiled separately, and the image comparison
// between the paths should not depend on how each one happens to fuse or
// reorder mat4 * vec4.
precise vec4 clip_position(vec3 p) {
    precise vec4 r = ((pc.view_proj[0] * p.x + pc.view_proj[1] * p.y) + pc.view_proj[2] * p.z)
        + pc.view_proj[3];
    return r;
}

// Fallback vertex attributes in one word. Node parameters are dyadic with
// at most L_MAX = 10 fraction bits, so u * 1024 and v * 1024 are exact
// integers in 0..1024 (11 bits) and unpacking gives the same floats back.
// `depths`: the node's depth along u (low 4 bits) and v (next 4); `wedge`
// the triangle's WEDGE_* code (wedge_code).
uint pack_attrs(vec2 uv, uint depths, uint wedge) {
    return uint(uv.x * 1024.0) | (uint(uv.y * 1024.0) << PACK_V_SHIFT)
        | (depths << PACK_DEPTH_SHIFT) | (wedge << PACK_WEDGE_SHIFT);
}

// A ready node's depths as shade() takes them: u in the low 4 bits, v above.
uint node_depths(uvec2 q) {
    return node_du(q) | (node_dv(q) << 4);
}

vec2 unpack_uv(uint w) {
    return vec2(float(w & 0x7ffu), float((w >> PACK_V_SHIFT) & 0x7ffu)) * (1.0 / 1024.0);
}

uint unpack_depth(uint w) {
    return (w >> PACK_DEPTH_SHIFT) & 0xffu;
}

uint unpack_wedge(uint w) {
    return (w >> PACK_WEDGE_SHIFT) & 3u;
}

// Triangle slot t (0, 1: the quad; 2 + e: the wedge on edge e) of a node
// mesh, and whether it exists. Fixed slots keep the output layout
// independent of which wedges a node has.
bool mesh_tri(NodeMesh mesh, uint t, out uvec3 tri) {
    tri = mesh.tris[t];
    return t < 2u || mesh.wedge[t - 2u];
}

// Whether vertex slot s (0-3 corners, 4 + e the pivot of edge e's wedge) of
// a node mesh is used.
bool slot_used(NodeMesh mesh, uint s) {
    return s < 4u || mesh.wedge[s - 4u];
}

// The positions of a node mesh's NODE_MESH_SLOTS vertex slots. Every
// position, corner or pivot, is the base patch evaluated by the one shared
// precise function at exact dyadic parameters: bit-identical to the oracle
// and to the neighbouring nodes that share it. Unused pivot slots get a
// copy of corner 0, so every output stays defined.
void node_positions(vec3 P[16], NodeMesh mesh, out vec3 pos[NODE_MESH_SLOTS]) {
    for (uint s = 0u; s < NODE_MESH_SLOTS; ++s) {
        pos[s] = slot_used(mesh, s) ? eval_patch(P, mesh.uv[s].x, mesh.uv[s].y) : pos[0];
    }
}

#endif
