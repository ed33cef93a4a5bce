// cudatess's PN triangles (Vlachos et al. 2001; Schwarz and Stamminger 2009
// §4): the triangle buffers of set 1, the conversion of a triangle into
// its cubic Bézier net and quadratic normal field (src/scene/pn.rs is the
// CPU twin), and the triangle's tessellation pattern.
//
// A net is CT_PN_NET_VEC4 vec4s: the points b300, b030, b003 (the corners
// P0, P1, P2), b210, b120 (edge 0: P0 -> P1), b021, b012 (edge 1: P1 -> P2),
// b102, b201 (edge 2: P2 -> P0), b111; then the normal coefficients n200,
// n020, n002, n110, n011, n101. Domain point (u, v) is barycentric
// (1 - u - v, u, v): u towards P1, v towards P2.
//
// The pattern (the triangular analogue of cudatess.glsl's) from the final
// factors e.x, e.y, e.z of edges 0, 1, 2: the core factor m = max(e) (their
// §4: the uniform part follows the largest boundary factor); the core is
// the uniform grid of the points (a + 1, b + 1) / m, a, b >= 0, a + b <= r,
// r = m - 3 (for m < 3 the single centroid, r = 0), i.e. the factor-m grid
// without its outermost ring; the ring between each edge and the core's
// side facing it is one strip, zipped like the patch path's transitions
// (e[k] segments outside, r inside). An edge whose factor is below m is a
// transition (the "wedges" of this method).
//
// Vertices of a triangle, in this order: the corners P0, P1, P2; the
// e[k] - 1 interior vertices of edge 0, 1, 2 in the edge's direction; the
// core points row by row (b, then a).
#ifndef PN_GLSL
#define PN_GLSL

#include "constants.glsl"
#include "cudatess/constants.glsl"

#ifndef CT_ACCESS
#define CT_ACCESS
#endif

// Per vertex: position (xyz, 1), unit normal (xyz, 0).
layout(std430, set = SET_PASS, binding = BIND_CT_PN_VERTICES) readonly buffer CtPnVertices {
    vec4 pn_vertices[];
};

// Per triangle: its three vertices and its flags word (model index).
layout(std430, set = SET_PASS, binding = BIND_CT_PN_TRIANGLES) readonly buffer CtPnTriangles {
    uvec4 pn_triangles[];
};

// Per triangle: the edge ids (into the edge factors, after the patches'
// edges) of its sides P0 -> P1, P1 -> P2, P2 -> P0.
layout(std430, set = SET_PASS, binding = BIND_CT_PN_EDGE_IDS) readonly buffer CtPnEdgeIds {
    uvec4 pn_edge_ids[];
};

// Per triangle: its converted net (cudatess/pn_factors.comp writes it).
layout(std430, set = SET_PASS, binding = BIND_CT_PN_NETS) CT_ACCESS buffer CtPnNets {
    vec4 pn_nets[];
};

// Vlachos's edge point next to p towards q: (2 p + q - ((q - p).n) n) / 3.
// From (p, q, n) alone, so both triangles of an edge compute the same bits.
precise vec3 pn_edge_point(vec3 p, vec3 q, vec3 n) {
    precise float w = dot(q - p, n);
    precise vec3 r = (p * 2.0 + q - n * w) / 3.0;
    return r;
}

// Vlachos's normal coefficient of the edge p -> q.
vec3 pn_edge_normal(vec3 p, vec3 q, vec3 np, vec3 nq) {
    vec3 d = q - p;
    float dd = dot(d, d);
    float v = dd > 0.0 ? 2.0 * dot(d, np + nq) / dd : 0.0;
    vec3 n = np + nq - d * v;
    return dot(n, n) > 0.0 ? normalize(n) : vec3(0.0);
}

// Net storage indices of edge k's four points, in the edge's direction.
uvec4 pn_edge_indices(uint k) {
    if (k == 0u) return uvec4(0u, 3u, 4u, 1u);
    if (k == 1u) return uvec4(1u, 5u, 6u, 2u);
    return uvec4(2u, 7u, 8u, 0u);
}

vec3 pn_point(uint tri, uint k) {
    return pn_nets[tri * CT_PN_NET_VEC4 + k].xyz;
}

// The cubic at (u, v).
vec3 pn_eval(uint tri, vec2 uv) {
    float u = uv.x;
    float v = uv.y;
    float w = 1.0 - u - v;
    vec3 b[10];
    for (uint k = 0u; k < 10u; ++k) {
        b[k] = pn_point(tri, k);
    }
    return b[0] * (w * w * w) + b[1] * (u * u * u) + b[2] * (v * v * v)
        + (b[3] * (w * w * u) + b[4] * (w * u * u)) * 3.0
        + (b[5] * (u * u * v) + b[6] * (u * v * v)) * 3.0
        + (b[7] * (v * v * w) + b[8] * (v * w * w)) * 3.0
        + b[9] * (6.0 * w * u * v);
}

// The unnormalised normal field of triangle `tri` at (u, v) (Vlachos's sum,
// no binomial weights on the mixed terms).
vec3 pn_normal(uint tri, vec2 uv) {
    float u = uv.x;
    float v = uv.y;
    float w = 1.0 - u - v;
    uint o = tri * CT_PN_NET_VEC4 + 10u;
    return pn_nets[o].xyz * (w * w) + pn_nets[o + 1u].xyz * (u * u) + pn_nets[o + 2u].xyz * (v * v)
        + pn_nets[o + 3u].xyz * (w * u) + pn_nets[o + 4u].xyz * (u * v) + pn_nets[o + 5u].xyz * (w * v);
}

// The flags word of the triangle (as a patch's: model index, two-sided).
uint pn_flags(uint tri) {
    return pn_triangles[tri].w;
}

struct PnPattern {
    uvec3 e;            // edge factors
    uint m;             // core factor
    uint r;             // the core's own factor (m - 3, at least 0)
    uvec3 edge_base;    // local index of edge k's first interior vertex
    uint inner_base;    // local index of core point (0, 0)
    uint vertices;
    uint indices;
};

PnPattern pn_pattern(uvec3 e) {
    PnPattern t;
    t.e = e;
    t.m = max(e.x, max(e.y, e.z));
    t.r = t.m >= 3u ? t.m - 3u : 0u;
    t.edge_base.x = 3u;
    t.edge_base.y = t.edge_base.x + (e.x - 1u);
    t.edge_base.z = t.edge_base.y + (e.y - 1u);
    t.inner_base = t.edge_base.z + (e.z - 1u);
    t.vertices = t.inner_base + (t.r + 1u) * (t.r + 2u) / 2u;
    // r^2 core triangles; a strip has a triangle per segment of its sides.
    t.indices = 3u * (t.r * t.r + e.x + e.y + e.z + 3u * t.r);
    return t;
}

// Local index of vertex s (0..e[k]) along edge k.
uint pn_edge_vertex(PnPattern t, uint k, uint s) {
    if (s == 0u) {
        return k;
    }
    if (s == t.e[k]) {
        return (k + 1u) % 3u;
    }
    return t.edge_base[k] + s - 1u;
}

// Local index of core point (a, b), a + b <= r.
uint pn_core_vertex(PnPattern t, uint a, uint b) {
    return t.inner_base + b * (t.r + 1u) - b * (b - 1u) / 2u + a;
}

// Domain point of core point (a, b).
vec2 pn_core_uv(PnPattern t, uint a, uint b) {
    float m = float(max(t.m, 3u));
    return vec2(float(a + 1u) / m, float(b + 1u) / m);
}

// Core point l (0..r) of the core's side facing edge k, in the edge's
// direction.
uint pn_side_vertex(PnPattern t, uint k, uint l) {
    if (k == 0u) return pn_core_vertex(t, l, 0u);
    if (k == 1u) return pn_core_vertex(t, t.r - l, l);
    return pn_core_vertex(t, 0u, t.r - l);
}

#endif
