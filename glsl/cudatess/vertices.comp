// cudatess, stage 5 (their Fig. 1: "determine vertex buffer data", k threads
// per patch): CT_VERTEX_THREADS invocations share a patch. They load its
// homogeneous control points into shared memory together, then each writes
// every CT_VERTEX_THREADS-th vertex of the patch's slot (the scan's offset):
// position, the base patch's (u, v), and the patch id word.
//
// - Corners are the corner control points themselves.
// - Edge vertices come from the edge's own four control points (and
//   weights) at ct_edge_param, through the reversal-symmetric curve()/
//   curve4(): the patch across the edge, running it the other way, computes
//   the same bits. Whether an edge is rational is decided by its own weights
//   (all 1: the polynomial curve), so both sides decide alike.
// - Interior grid vertices at (i / m, j / n): the patch evaluated (rows at u,
//   then the column at v), or with CT_OPT_FORWARD_DIFF one row per
//   invocation by forward differences along u (Wallis; the paper's option).
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"
#include "common/texture.glsl"
#include "common/displace.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

const uint PATCHES_PER_GROUP = CT_GROUP_SIZE / CT_VERTEX_THREADS;

// Homogeneous control points (w p, w) of the group's patches; w = 1 exactly
// reproduces p in xyz.
shared vec4 points[PATCHES_PER_GROUP * 16u];

// A displaced model's vertices move by n̂·d, each by its point's owner
// (common/displace.glsl): shared edge vertices, at exactly complementary
// parameters from either side, move alike.
vec3 displaced(uint id, vec3 p, vec2 uv) {
    DispModel dm;
    if (!displaced_model(patch_flags_of(id) >> PATCH_MODEL_SHIFT, dm)) {
        return p;
    }
    precise vec3 r = p + displacement_offset(instances[instance_of(id)], id, dm, uv);
    return r;
}

void write_vertex(uint at, vec3 p, vec2 uv, uint word) {
    uint o = at * CT_VERTEX_WORDS;
    ct_vertices[o] = floatBitsToUint(p.x);
    ct_vertices[o + 1u] = floatBitsToUint(p.y);
    ct_vertices[o + 2u] = floatBitsToUint(p.z);
    ct_vertices[o + 3u] = floatBitsToUint(uv.x);
    ct_vertices[o + 4u] = floatBitsToUint(uv.y);
    ct_vertices[o + 5u] = word;
}

// The corner control point k (0: (0,0), 1: (1,0), 2: (1,1), 3: (0,1)), as
// stored: exact, and the same for every patch that has the corner.
vec3 corner_point(uint id, uint k) {
    const uint at[4] = uint[4](0u, 3u, 15u, 12u);
    return patch_point(id, at[k]);
}

// Vertex s (1 .. e - 1) of edge k.
vec3 edge_point(uint g, uint k, uint s, uint e, out float t) {
    uvec4 idx = ct_edge_indices(k);
    vec4 h0 = points[g + idx.x];
    vec4 h1 = points[g + idx.y];
    vec4 h2 = points[g + idx.z];
    vec4 h3 = points[g + idx.w];
    t = ct_edge_param(s, e);
    if (h0.w == 1.0 && h1.w == 1.0 && h2.w == 1.0 && h3.w == 1.0) {
        precise vec3 p = curve(t, h0.xyz, h1.xyz, h2.xyz, h3.xyz);
        return p;
    }
    precise vec3 p = project(curve4(t, h0, h1, h2, h3));
    return p;
}

void boundary_vertex(uint g, uint id, CtPattern t, uint base, uint k, uint word_base) {
    const vec2 corner_uv[4] = vec2[4](vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 1.0));
    if (k < 4u) {
        // Corner k lies on edges k and (k + 1) % 4: (0,0) on 0 and 1, (1,0)
        // on 1 and 2, (1,1) on 2 and 3, (0,1) on 3 and 0.
        uint a = k;
        uint b = (k + 1u) & 3u;
        bool transition = t.strip[a] || t.strip[b];
        write_vertex(base + k, displaced(id, corner_point(id, k), corner_uv[k]), corner_uv[k],
            word_base | ((transition ? 1u : 0u) << CT_TRANSITION_SHIFT));
        return;
    }
    uint edge = 0u;
    uint s = k - 4u;
    while (s >= t.e[edge] - 1u) {
        s -= t.e[edge] - 1u;
        edge += 1u;
    }
    s += 1u;
    float param;
    vec3 p = edge_point(g, edge, s, t.e[edge], param);
    vec2 uv = edge == 0u ? vec2(0.0, param) : edge == 1u ? vec2(param, 0.0)
        : edge == 2u ? vec2(1.0, param) : vec2(param, 1.0);
    write_vertex(base + k, displaced(id, p, uv), uv,
        word_base | ((t.strip[edge] ? 1u : 0u) << CT_TRANSITION_SHIFT));
}

// Interior vertex (i, j) evaluated directly.
vec3 interior_point(uint g, bool rational, float u, float v) {
    if (!rational) {
        vec3 P[16];
        for (uint i = 0u; i < 16u; ++i) {
            P[i] = points[g + i].xyz;
        }
        precise vec3 p = eval_patch(P, u, v);
        return p;
    }
    vec4 H[16];
    for (uint i = 0u; i < 16u; ++i) {
        H[i] = points[g + i];
    }
    precise vec3 p = project(eval_patch4(H, u, v));
    return p;
}

// Row j of interior vertices by forward differences along u: the row's
// cubic (the columns evaluated at v) in power form, stepped by h = 1 / m.
void forward_row(uint g, uint id, bool rational, CtPattern t, uint base, uint j, uint word) {
    float v = float(j) / float(t.n);
    vec4 q0 = curve4(v, points[g + 0u], points[g + 4u], points[g + 8u], points[g + 12u]);
    vec4 q1 = curve4(v, points[g + 1u], points[g + 5u], points[g + 9u], points[g + 13u]);
    vec4 q2 = curve4(v, points[g + 2u], points[g + 6u], points[g + 10u], points[g + 14u]);
    vec4 q3 = curve4(v, points[g + 3u], points[g + 7u], points[g + 11u], points[g + 15u]);
    vec4 a1 = 3.0 * (q1 - q0);
    vec4 a2 = 3.0 * (q2 - 2.0 * q1 + q0);
    vec4 a3 = q3 - 3.0 * q2 + 3.0 * q1 - q0;
    float h = 1.0 / float(t.m);
    float h2 = h * h;
    float h3 = h2 * h;
    vec4 f = q0;
    vec4 d1 = a1 * h + a2 * h2 + a3 * h3;
    vec4 d2 = 2.0 * a2 * h2 + 6.0 * a3 * h3;
    vec4 d3 = 6.0 * a3 * h3;
    uint row = t.interior_base + (j - 1u) * (t.m - 1u);
    for (uint i = 1u; i < t.m; ++i) {
        f += d1;
        d1 += d2;
        d2 += d3;
        vec3 p = rational ? f.xyz / f.w : f.xyz;
        vec2 uv = vec2(float(i) / float(t.m), v);
        write_vertex(base + row + i - 1u, displaced(id, p, uv), uv, word);
    }
}

void emit(uint id, uint slot, uint lane) {
    uint rec = id * CT_PATCH_WORDS;
    uint m_own = ct_patches[rec + CT_REC_M];
    if (m_own == 0u) {
        return;
    }
    uint n_own = ct_patches[rec + CT_REC_N];
    uvec4 e = uvec4(ct_patches[rec + CT_REC_EDGES], ct_patches[rec + CT_REC_EDGES + 1u],
        ct_patches[rec + CT_REC_EDGES + 2u], ct_patches[rec + CT_REC_EDGES + 3u]);
    CtPattern t = ct_pattern(e);
    uint base = ct_scan[id].x;
    uint g = slot * 16u;
    bool rational = patch_is_rational(id);
    uint word = ct_pack(id, uint(findMSB(max(m_own, n_own))), false);
    for (uint k = lane; k < t.interior_base; k += CT_VERTEX_THREADS) {
        boundary_vertex(g, id, t, base, k, word);
    }
    uint cols = t.m - 1u;
    if ((ct.options & CT_OPT_FORWARD_DIFF) != 0u) {
        for (uint j = 1u + lane; j < t.n; j += CT_VERTEX_THREADS) {
            forward_row(g, id, rational, t, base, j, word);
        }
        return;
    }
    uint inner = cols * (t.n - 1u);
    for (uint k = lane; k < inner; k += CT_VERTEX_THREADS) {
        uint i = k % cols + 1u;
        uint j = k / cols + 1u;
        vec2 uv = vec2(float(i) / float(t.m), float(j) / float(t.n));
        write_vertex(base + t.interior_base + k, displaced(id, interior_point(g, rational, uv.x, uv.y), uv),
            uv, word);
    }
}

void main() {
    // The buffers were too small: the host grows them and redraws.
    if (ct_counters[CT_ERROR] != 0u) {
        return;
    }
    uint slot = gl_LocalInvocationID.x / CT_VERTEX_THREADS;
    uint lane = gl_LocalInvocationID.x % CT_VERTEX_THREADS;
    uint groups = (ct.patch_count + PATCHES_PER_GROUP - 1u) / PATCHES_PER_GROUP;
    for (uint gi = gl_WorkGroupID.x; gi < groups; gi += gl_NumWorkGroups.x) {
        uint id = gi * PATCHES_PER_GROUP + slot;
        bool live = id < ct.patch_count;
        if (live) {
            bool rational = patch_is_rational(id);
            for (uint k = lane; k < 16u; k += CT_VERTEX_THREADS) {
                vec3 p = patch_point(id, k);
                float w = rational ? patch_weight(id, k) : 1.0;
                precise vec4 h = vec4(p.x * w, p.y * w, p.z * w, w);
                points[slot * 16u + k] = h;
            }
        }
        barrier();
        if (live) {
            emit(id, slot, lane);
        }
        barrier();
    }
}
