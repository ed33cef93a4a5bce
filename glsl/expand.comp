// Draw path B (fallback for devices without mesh shaders), expansion of
// one chunk (pc.chunk) of the ready list: one invocation per ready QuadNode
// writes its NODE_MESH_TRIS triangle slots as VERTICES_PER_NODE vertices of
// VERTEX_WORDS words each (slots as in draw.mesh: quad, quad, the wedge on
// each edge), from the start of the vertex buffer, which holds one chunk. A
// missing wedge is written as a degenerate triangle, three copies of corner
// 0, which the rasterizer drops; fixed slots let one non-indexed indirect
// draw of the chunk's nodes * VERTICES_PER_NODE vertices follow.
#version 460

#define USE_VERTICES_WRITE
#define USE_CAPTURE
#include "common/ready.glsl"
#include "common/draw.glsl"
#include "common/draw_rational.glsl"

layout(local_size_x = EXPAND_GROUP_SIZE) in;

void write_vertex(uint index, vec3 p, uint patch_id, uint attrs) {
    uint o = index * VERTEX_WORDS;
    vertex_words[o] = floatBitsToUint(p.x);
    vertex_words[o + 1u] = floatBitsToUint(p.y);
    vertex_words[o + 2u] = floatBitsToUint(p.z);
    vertex_words[o + 3u] = patch_id;
    vertex_words[o + 4u] = attrs;
}

void main() {
    uint slot = gl_GlobalInvocationID.x;
    uint node = ready_first() + pc.chunk * FALLBACK_CHUNK_NODES + slot;
    if (slot >= FALLBACK_CHUNK_NODES || node >= ready_count(pc.capacity)) {
        return;
    }
    uvec2 q = ready[node];
    NodeMesh mesh = node_mesh(q, (view.flags & FLAG_WEDGES) != 0u);

    // The same evaluation as the mesh path.
    vec3 pos[NODE_MESH_SLOTS];
    patch_node_positions(node_patch(q), mesh, pos);
    for (uint s = 0u; s < NODE_MESH_SLOTS; ++s) {
        if (slot_used(mesh, s) && pc.capture_enabled != 0u
            && NODE_MESH_SLOTS * node + s < uint(capture.length())) {
            capture[NODE_MESH_SLOTS * node + s] = vec4(pos[s], 1.0);
        }
    }

    uint depths = node_depths(q);
    // Not unrolled: one copy of wedge_code (see there).
    [[dont_unroll]] for (uint t = 0u; t < NODE_MESH_TRIS; ++t) {
        uvec3 tri;
        bool present = mesh_tri(mesh, t, tri);
        if (!present) {
            tri = uvec3(0u);
        }
        uint wedge = wedge_code(q, mesh, pos, t, view.eye.xyz);
        for (uint k = 0u; k < 3u; ++k) {
            uint s = tri[k];
            write_vertex(slot * VERTICES_PER_NODE + 3u * t + k, pos[s], node_patch(q),
                pack_attrs(mesh.uv[s], depths, wedge));
        }
    }
}
