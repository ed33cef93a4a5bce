// cudatess (Schwarz and Stamminger 2009): set 1 of its passes and draw, and
// the tessellation pattern every pass agrees on. The Rust side is
// src/methods/cudatess.rs (buffers, passes) and src/methods/cudatess/
// pattern.rs (the pattern's CPU twin, for the tests).
//
// The pattern of a patch (their Fig. 3) follows from its four edge factors
// e.x..e.w (edges 0: u = 0, 1: v = 0, 2: u = 1, 3: v = 1; each the largest
// factor any patch on that edge asked for): a uniform core of m x n cells,
// m = min(e.y, e.w) along u and n = min(e.x, e.z) along v, and a transition
// strip along each edge whose factor exceeds the core's in its direction (at
// most one per direction, since the core takes the smaller). A strip takes
// the row (or column) of cells next to its edge: its outer side is the edge
// with e[k] segments, its inner side the core's boundary there, and a
// Bresenham-like walk zips the two into triangles.
//
// Vertices of a patch, in this order: the corners (0,0), (1,0), (1,1),
// (0,1); the e[k] - 1 interior vertices of edge 0, 1, 2, 3 in the edge's
// parameter order; the (m - 1)(n - 1) interior grid vertices row by row.
// A core or strip vertex at grid point (i, j) on the patch boundary is the
// edge's own vertex there (an edge without a strip has the core's factor).
#ifndef CUDATESS_GLSL
#define CUDATESS_GLSL

#include "rational.glsl"
#include "cudatess/constants.glsl"

// The draw reads what the compute passes write: it defines CT_ACCESS as
// readonly before this include.
#ifndef CT_ACCESS
#define CT_ACCESS
#endif

layout(std430, set = SET_PASS, binding = BIND_CT_COUNTERS) CT_ACCESS buffer CtCounters {
    uint ct_counters[];
};

// The edge id of each patch side (the scene's edge table).
layout(std430, set = SET_PASS, binding = BIND_CT_EDGE_IDS) readonly buffer CtEdgeIds {
    uvec4 ct_edge_ids[];
};

// The factor of each edge: the largest any of its patches asked for.
layout(std430, set = SET_PASS, binding = BIND_CT_EDGE_FACTORS) CT_ACCESS buffer CtEdgeFactors {
    uint ct_edge_factors[];
};

// CT_PATCH_WORDS per patch (CT_REC_*).
layout(std430, set = SET_PASS, binding = BIND_CT_PATCHES) CT_ACCESS buffer CtPatches {
    uint ct_patches[];
};

// The scan: (vertex count, index count) per patch, then a zero, scanned in
// place to exclusive offsets (entry patch_count then holds the totals);
// beyond that the block sums of the scan's higher levels.
layout(std430, set = SET_PASS, binding = BIND_CT_SCAN) CT_ACCESS buffer CtScan {
    uvec2 ct_scan[];
};

// CT_VERTEX_WORDS words per vertex (float bits and the packed id word).
layout(std430, set = SET_PASS, binding = BIND_CT_VERTICES) CT_ACCESS buffer CtVertices {
    uint ct_vertices[];
};

layout(std430, set = SET_PASS, binding = BIND_CT_INDICES) CT_ACCESS buffer CtIndices {
    uint ct_indices[];
};

// A patch's tessellation pattern.
struct CtPattern {
    uvec4 e;            // edge factors
    uint m;             // core factor along u
    uint n;             // core factor along v
    bvec4 strip;        // a transition strip along edge k
    uvec4 edge_base;    // local index of edge k's first interior vertex
    uint interior_base; // local index of grid vertex (1, 1)
    uint vertices;
    uint indices;
    uvec4 core;         // core cells i in [core.x, core.y), j in [core.z, core.w)
};

CtPattern ct_pattern(uvec4 e) {
    CtPattern t;
    t.e = e;
    t.m = min(e.y, e.w);
    t.n = min(e.x, e.z);
    t.strip = bvec4(e.x > t.n, e.y > t.m, e.z > t.n, e.w > t.m);
    t.edge_base.x = 4u;
    t.edge_base.y = t.edge_base.x + (e.x - 1u);
    t.edge_base.z = t.edge_base.y + (e.y - 1u);
    t.edge_base.w = t.edge_base.z + (e.z - 1u);
    t.interior_base = t.edge_base.w + (e.w - 1u);
    t.vertices = t.interior_base + (t.m - 1u) * (t.n - 1u);
    t.core = uvec4(t.strip.x ? 1u : 0u, t.strip.z ? t.m - 1u : t.m,
        t.strip.y ? 1u : 0u, t.strip.w ? t.n - 1u : t.n);
    uint cols = t.core.y - t.core.x;
    uint rows = t.core.w - t.core.z;
    // A strip has a triangle per segment of its two sides: its edge's e[k]
    // and the core's extent along it.
    uint tris = 2u * cols * rows;
    tris += t.strip.x ? e.x + rows : 0u;
    tris += t.strip.y ? e.y + cols : 0u;
    tris += t.strip.z ? e.z + rows : 0u;
    tris += t.strip.w ? e.w + cols : 0u;
    t.indices = 3u * tris;
    return t;
}

// Local index of vertex s (0..e[k]) along edge k; s = 0 and s = e[k] are
// the edge's corners.
uint ct_edge_vertex(CtPattern t, uint k, uint s) {
    const uint starts[4] = uint[4](0u, 0u, 1u, 3u);
    const uint ends[4] = uint[4](3u, 1u, 2u, 2u);
    if (s == 0u) {
        return starts[k];
    }
    if (s == t.e[k]) {
        return ends[k];
    }
    return t.edge_base[k] + s - 1u;
}

// Local index of grid point (i, j), 0 <= i <= m, 0 <= j <= n, of the core
// or a strip's inner side: on the boundary it is the edge's own vertex
// (there the edge has no strip, so its factor is the core's).
uint ct_grid_vertex(CtPattern t, uint i, uint j) {
    if (j == 0u) {
        return ct_edge_vertex(t, 1u, i);
    }
    if (j == t.n) {
        return ct_edge_vertex(t, 3u, i);
    }
    if (i == 0u) {
        return ct_edge_vertex(t, 0u, j);
    }
    if (i == t.m) {
        return ct_edge_vertex(t, 2u, j);
    }
    return t.interior_base + (j - 1u) * (t.m - 1u) + (i - 1u);
}

// The parameter of vertex k of e along an edge, the same float from both
// directions (src/patch/rational.rs edge_param): from the middle on k / e,
// before it 1 - (e - k) / e, so the patch that runs the edge the other way
// computes the exact complement and curve()/curve4() give it the same point.
precise float ct_edge_param(uint k, uint e) {
    if (2u * k >= e) {
        precise float t = float(k) / float(e);
        return t;
    }
    precise float t = 1.0 - float(e - k) / float(e);
    return t;
}

// Storage indices of edge k's control points, in the edge's direction.
uvec4 ct_edge_indices(uint k) {
    if (k == 0u) return uvec4(0u, 4u, 8u, 12u);
    if (k == 1u) return uvec4(0u, 1u, 2u, 3u);
    if (k == 2u) return uvec4(3u, 7u, 11u, 15u);
    return uvec4(12u, 13u, 14u, 15u);
}

// The vertex word beside the position and (u, v): patch id, log2 of the
// patch's larger factor (the depth heat map), whether the vertex lies on an
// edge with a transition strip (the "wedges" of this method).
uint ct_pack(uint patch_id, uint depth, bool transition) {
    return (patch_id & ((1u << CT_PATCH_BITS) - 1u)) | (min(depth, 15u) << CT_DEPTH_SHIFT)
        | ((transition ? 1u : 0u) << CT_TRANSITION_SHIFT);
}

#endif
