// Geometry-side helpers of the two draw paths (task/mesh and the compute
// expansion + pass-through vertex shader), so both turn a ready QuadNode
// into the same clip-space positions and the same attributes. Include after
// scene.glsl (uses the push constants).
#ifndef DRAW_GLSL
#define DRAW_GLSL

// World -> clip with the sums written out in a fixed order: the mesh shader
// and the vertex shader are compiled separately, and the image comparison
// between the two paths should not depend on how each one happens to fuse
// or reorder mat4 * vec4.
precise vec4 clip_position(vec3 p) {
    precise vec4 r = ((pc.view_proj[0] * p.x + pc.view_proj[1] * p.y) + pc.view_proj[2] * p.z)
        + pc.view_proj[3];
    return r;
}

// Ready nodes the subdivision pass published, never more than the list
// holds (a full list sets ERR_READY_FULL but must not make us read past it).
uint ready_count() {
    uint n = counters[C_READY_COUNT];
    return n < pc.ready_capacity ? n : pc.ready_capacity;
}

// Fallback vertex attributes in one word. Node parameters are dyadic with
// at most L_MAX = 10 fraction bits, so u * 1024 and v * 1024 are exact
// integers in 0..1024 (11 bits) and unpacking gives the same floats back.
uint pack_attrs(vec2 uv, uint depth, bool wedge) {
    return uint(uv.x * 1024.0) | (uint(uv.y * 1024.0) << PACK_V_SHIFT)
        | (depth << PACK_DEPTH_SHIFT) | ((wedge ? 1u : 0u) << PACK_WEDGE_SHIFT);
}

vec2 unpack_uv(uint w) {
    return vec2(float(w & 0x7ffu), float((w >> PACK_V_SHIFT) & 0x7ffu)) * (1.0 / 1024.0);
}

uint unpack_depth(uint w) {
    return (w >> PACK_DEPTH_SHIFT) & 0xfu;
}

uint unpack_wedge(uint w) {
    return (w >> PACK_WEDGE_SHIFT) & 1u;
}

// Triangle slot t (0, 1: the quad; 2: wedge along u; 3: wedge along v) of a
// node mesh, and whether it exists. Fixed slots keep the output layout
// independent of which wedges a node has.
bool mesh_tri(NodeMesh mesh, uint t, out uvec3 tri) {
    tri = mesh.tris[t];
    if (t == 2u) return mesh.wedge.x;
    if (t == 3u) return mesh.wedge.y;
    return true;
}

#endif
