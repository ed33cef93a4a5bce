// Tessellation levels of displaced patches (issue 40), from the same bound
// the subdivision's criterion uses (common/displace.glsl's reach: how far
// the displacement can stray from the blend of a box's corners), so that
// `tess` and `subdiv` are compared at the same promise.
//
// The tessellator puts n equal segments on an edge of level n and an inner
// grid of cells 1/n_u by 1/n_v. A displaced patch's level is the fewest
// segments for which the base surface's error, tol·(base/n)² (the
// metric's level `base` keeps tol, and its bound falls with the square of
// the segments), plus the largest reach over the pieces stays within tol.
// An edge's pieces are cut from its owner's UV line (edge_owner_line), the
// same line from both sides, so both sides get the same level bit for bit.
// The samples stay uniform (tess-reparam's warp assumes the base
// surface's density alone), and the tolerance is taken `margin` nearer,
// where the displaced surface can come.
#ifndef TESS_DISPLACED_GLSL
#define TESS_DISPLACED_GLSL

#include "common/draw.glsl"
#include "common/texture.glsl"
#include "common/displace.glsl"

// Set by the control stage per patch (displaced_patch_begin): whether it
// is displaced, and how; for a displaced patch also its own UV net and
// that net's curvature bound, loaded once for the border strips' many
// reach queries.
bool g_displaced = false;
DispModel g_dm;
Instance g_instance;
uint g_id;
vec2 g_uv[16];
vec2 g_uv_curvature;

// Scene model of base patch `id`'s displacement (false: undisplaced).
bool patch_displacement(uint id, out DispModel m) {
    return displaced_model(patch_flags_of(id) >> PATCH_MODEL_SHIFT, m);
}

// Sets the globals above for base patch `id` of `instance`; returns
// whether the patch is displaced.
bool displaced_patch_begin(uint id, Instance instance) {
    g_displaced = patch_displacement(id, g_dm);
    g_instance = instance;
    g_id = id;
    if (g_displaced) {
        uint m = instance.source + (id - instance.first);
        load_uv_patch(m, g_uv);
        g_uv_curvature = uv_curvature_of(m);
    }
    return g_displaced;
}

// The largest reach over n equal pieces of a UV line (a box with equal
// ends in one direction) of model patch o; stops beyond `limit`.
float line_pieces_reach(uint o, vec4 line, bool along_u, float n, float limit) {
    vec2 P[16];
    load_uv_patch(o, P);
    vec2 c = uv_curvature_of(o);
    float r = 0.0;
    float a = along_u ? line.x : line.z;
    float b = along_u ? line.y : line.w;
    for (float i = 0.0; i < n; i += 1.0) {
        precise float s0 = a + (b - a) * (i / n);
        precise float s1 = a + (b - a) * ((i + 1.0) / n);
        vec4 box = along_u ? vec4(s0, s1, line.z, line.w) : vec4(line.x, line.y, s0, s1);
        r = max(r, reach_in(g_dm, P, c, box));
        if (r > limit) {
            return r;
        }
    }
    return r;
}

// Whether n segments of an edge keep tol: base error plus the pieces' reach.
bool edge_fits(float n, float base, float tol, uint o, vec4 line, bool along_u) {
    float scaled = base / n;
    float error = tol * (scaled * scaled);
    return error + line_pieces_reach(o, line, along_u, n, tol - error) <= tol;
}

// Outer edge k's level (k: 0 u = 0, 1 v = 0, 2 u = 1, 3 v = 1): the fewest
// segments from ceil(base) that fit, by doubling then halving the gap.
float displaced_edge_level(uint k, float base, float tol) {
    const uint edge_of[4] = uint[4](EDGE_LEFT, EDGE_BOTTOM, EDGE_RIGHT, EDGE_TOP);
    uint o;
    vec4 line;
    bool along_u;
    float n = max(ceil(base), 1.0);
    if (!edge_owner_line(g_instance, g_id, vec4(0.0, 1.0, 0.0, 1.0), edge_of[k], o, line, along_u)
        || edge_fits(n, base, tol, o, line, along_u)) {
        return n;
    }
    float lo = n;
    float hi = n;
    while (hi < TESS_MAX_LEVEL) {
        hi = min(hi * 2.0, TESS_MAX_LEVEL);
        if (edge_fits(hi, base, tol, o, line, along_u)) {
            break;
        }
        lo = hi;
    }
    if (lo == hi) {
        return hi;  // nothing up to the largest level fits
    }
    while (hi - lo > 1.0) {
        float mid = floor((lo + hi) * 0.5);
        if (edge_fits(mid, base, tol, o, line, along_u)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return hi;
}

// Inner levels: at least the metric's and the facing edges', scaled
// together (common/displace.glsl, displaced_grid) until every cell fits.
vec2 displaced_inner_levels(vec2 base, vec4 outer, float tol) {
    vec2 n0 = vec2(ceil(max(base.x, max(outer.y, outer.w))), ceil(max(base.y, max(outer.x, outer.z))));
    return displaced_grid(g_instance, g_id, g_dm, base, max(n0, vec2(1.0)), tol, TESS_MAX_LEVEL);
}

// The reach of outer edge k's border strip at `width` across it. Its
// triangles are at most `span` long along the edge but not aligned with
// any grid, so the windows are two pieces of `span` long, one piece
// apart: every triangle lies within one of them.
float strip_reach(uint k, float width, float span) {
    if (!g_displaced) {
        return 0.0;
    }
    bool mirrored = (g_instance.flags & INSTANCE_MIRRORED) != 0u;
    float pieces = ceil(1.0 / span);
    float lo = (k == 0u || k == 1u) ? 0.0 : 1.0 - width;
    float hi = (k == 0u || k == 1u) ? width : 1.0;
    float r = 0.0;
    for (float i = 0.0; i < pieces; i += 1.0) {
        float a = i / pieces;
        float b = min((i + 2.0) / pieces, 1.0);
        vec4 dom = (k & 1u) == 0u ? vec4(lo, hi, a, b) : vec4(a, b, lo, hi);
        r = max(r, reach_in(g_dm, g_uv, g_uv_curvature, mirrored ? dom.zwxy : dom));
    }
    return r;
}

#endif
