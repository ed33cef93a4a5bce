// The hardware-tessellation baselines of Buchenau and Guthe (2021): the
// tessellation levels of a bicubic patch from bounds on its second
// derivatives (their §3.1-3.2, after Filip et al.), the pixel tolerance
// turned into an object-space one from the camera (§5.1), and for
// `tess-reparam` the curvature-adaptive placement of the samples (§4) and
// the tighter bound on the mixed derivative (§5.2). Shared by tess/patch.tesc and
// tess/patch.tese; the Rust side is src/methods/tess.rs.
//
// Crack-freeness rests on two patches computing the same level and the same
// sample positions for their shared edge, from opposite directions. So every
// quantity an edge decision or an edge position depends on is computed from
// the edge's four control points and the view alone, by an expression that
// is symmetric under reversing the edge: sums of two terms (which commute)
// rather than chains, minima and maxima, and a single call site for
// anything orientation-dependent. Everything is `precise`, as in patch.glsl.
#ifndef TESS_GLSL
#define TESS_GLSL

#include "common/scene.glsl"
#include "constants.glsl"

// Set 1 of the tessellation methods.
layout(std430, set = SET_PASS, binding = BIND_TESS_COUNTERS) buffer TessCounters {
    uint tess_counters[];
};

// Captured for validation: per patch, TESS_LEVEL_WORDS floats (outer levels
// 0-3, the metric's inner 0-1, the mixed-derivative bound, 1.0 if culled,
// the inner levels drawn 0-1).
layout(std430, set = SET_PASS, binding = BIND_TESS_LEVELS) buffer TessLevels {
    float tess_levels[];
};

// Captured for validation: vertices strictly inside a patch edge,
// TESS_EDGE_VERTEX_WORDS words each (patch, edge, the tessellator's
// coordinate along the edge as float bits, position xyz as float bits).
layout(std430, set = SET_PASS, binding = BIND_TESS_EDGE_VERTICES) buffer TessEdgeVertices {
    uint tess_edge_vertices[];
};

// Variant: 0 `tess` (uniform, Filip bound), 1 `tess-reparam` (their §4 and
// §5.2). The device's largest level. Both set by the host.
layout(constant_id = 0) const uint TESS_REPARAM = 0u;
layout(constant_id = 1) const float TESS_MAX_LEVEL = 64.0;

// Displaced patches (tess/displaced.glsl): their state, set per patch.
#include "displaced.glsl"

// The bound on the second derivative at the start of the cubic p0..p3
// (when called with p0, p1, p2) or at its end (p1, p2, p3): the norm of
// 6 ((p_i + p_i+2) - 2 p_i+1). The outer sum is the same two terms from
// either direction, so the start of an edge seen from one side equals its
// end seen from the other, bit for bit.
precise float second_bound(vec3 p0, vec3 p1, vec3 p2) {
    precise vec3 d = (p0 + p2) - p1 * 2.0;
    precise float r = 6.0 * sqrt(dot3(d, d));
    return r;
}

// The bounds at both ends of an edge: x at p[0], y at p[3].
precise vec2 edge_bounds(vec3 p[4]) {
    precise float a = second_bound(p[0], p[1], p[2]);
    precise float b = second_bound(p[1], p[2], p[3]);
    return vec2(a, b);
}

// The object-space tolerance for points that all lie at view depth
// `depth` or further: ε pixels at that depth (clamped to the near plane,
// as the subdivision's tolerance is). `eps_k` is ε · 2 tan(fov/2) / height.
precise float tolerance_at(float depth) {
    precise float d = g_displaced ? depth - g_dm.margin : depth;
    precise float t = view.eps_k * maxf(d, view.near);
    return t;
}

// The smallest view depth of an edge's control points (min commutes, so
// both directions agree); the edge lies in their convex hull.
precise float edge_depth(vec3 p[4]) {
    precise float d0 = affine_row(view.depth_row, p[0]);
    precise float d1 = affine_row(view.depth_row, p[1]);
    precise float d2 = affine_row(view.depth_row, p[2]);
    precise float d3 = affine_row(view.depth_row, p[3]);
    return minf(minf(d0, d3), minf(d1, d2));
}

precise float patch_depth(vec3 P[16]) {
    precise float d = affine_row(view.depth_row, P[0]);
    for (int i = 1; i < 16; ++i) {
        d = minf(d, affine_row(view.depth_row, P[i]));
    }
    return d;
}

// Density bounds a and b (second-derivative bounds at the two ends, growing
// linearly in between) this close are treated as equal: uniform samples,
// level from the larger. Keeps the warp below away from 0/0 where its
// inputs nearly cancel, and is conservative.
bool nearly_equal(float a, float b) {
    precise float lo = minf(a, b);
    precise float hi = maxf(a, b);
    return hi - lo <= hi * (1.0 / 64.0);
}

// ∫_0^1 sqrt((1-s) a + s b) ds: the number of samples per unit tolerance
// scale a bound growing linearly from a to b needs (their eq. 19-20 and
// 23-26 integrated in closed form): (2/3)(a + b + √a√b) / (√a + √b). The
// uniform metric uses sqrt(max(a, b)) instead. Symmetric in a and b.
precise float density(float a, float b) {
    if (TESS_REPARAM == 0u || g_displaced || nearly_equal(a, b)) {
        precise float r = sqrt(maxf(a, b));
        return r;
    }
    precise float sa = sqrt(a);
    precise float sb = sqrt(b);
    precise float r = (2.0 / 3.0) * (((a + b) + sa * sb) / (sa + sb));
    return r;
}

// A tessellation level: `dens` samples per unit of sqrt(4 tol) (their
// eq. 12 and 16: t >= sqrt(M / (4 ε))), clamped to [1, max]. NaN (from
// a degenerate patch) becomes 1 rather than a dropped patch.
precise float tess_level(float dens, float tol) {
    precise float t = dens / sqrt(4.0 * tol);
    return t >= 1.0 ? minf(t, TESS_MAX_LEVEL) : 1.0;
}

// The level of an edge: only its own points and the view.
precise float edge_level(vec3 p[4], vec2 ab) {
    return tess_level(density(ab.x, ab.y), tolerance_at(edge_depth(p)));
}

// ---------------------------------------------------------------- bounds

// Bound on the mixed derivative: 9 × the largest mixed difference
// (P00 + P11) - (P10 + P01) of the net (Filip et al.), or with `tight`
// the largest after one midpoint subdivision of that biquadratic net
// (their §5.2): per direction the points 0, 1/2 (p0+p1), 1/2 (p1+p2), p2;
// the dropped middle point (p0 + 2 p1 + p2) / 4 is the mean of its
// neighbours and cannot raise the maximum.
precise float mixed_bound(vec3 P[16], bool tight) {
    precise vec3 D[9];
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
            D[3 * j + i] = (P[4 * j + i] + P[4 * (j + 1) + i + 1])
                - (P[4 * j + i + 1] + P[4 * (j + 1) + i]);
        }
    }
    precise float m = 0.0;
    if (!tight) {
        for (int k = 0; k < 9; ++k) {
            m = maxf(m, dot3(D[k], D[k]));
        }
    } else {
        precise vec3 R[12];  // [row j][4]: the rows split in u
        for (int j = 0; j < 3; ++j) {
            R[4 * j] = D[3 * j];
            R[4 * j + 1] = (D[3 * j] + D[3 * j + 1]) * 0.5;
            R[4 * j + 2] = (D[3 * j + 1] + D[3 * j + 2]) * 0.5;
            R[4 * j + 3] = D[3 * j + 2];
        }
        for (int i = 0; i < 4; ++i) {
            precise vec3 c0 = R[i];
            precise vec3 c1 = (R[i] + R[4 + i]) * 0.5;
            precise vec3 c2 = (R[4 + i] + R[8 + i]) * 0.5;
            precise vec3 c3 = R[8 + i];
            m = maxf(m, maxf(maxf(dot3(c0, c0), dot3(c1, c1)), maxf(dot3(c2, c2), dot3(c3, c3))));
        }
    }
    precise float r = 9.0 * sqrt(m);
    return r;
}

// Largest u-second-derivative bound over the column of the net at the
// start (i = 0: points 0, 1, 2 of each row) or the end (i = 1: 1, 2, 3).
precise float u_bound(vec3 P[16], int i) {
    precise float m = 0.0;
    for (int j = 0; j < 4; ++j) {
        m = maxf(m, second_bound(P[4 * j + i], P[4 * j + i + 1], P[4 * j + i + 2]));
    }
    return m;
}

precise float v_bound(vec3 P[16], int j) {
    precise float m = 0.0;
    for (int i = 0; i < 4; ++i) {
        m = maxf(m, second_bound(P[4 * j + i], P[4 * (j + 1) + i], P[4 * (j + 2) + i]));
    }
    return m;
}

// ---------------------------------------------------------------- border strips

// The bound above holds inside the tessellator's inner grid and along each
// outer edge, but not in the strip between them: there an outer level set
// by a straight edge (level 1) meets an inner ring set by a curved
// interior, and the strip's triangles span the whole edge. Buchenau and
// Guthe close this as Hjelmervik does, by narrowing the border strips:
// interior samples are moved so that the first inner ring sits at a width
// δ from the edge at which the strip's error is within the tolerance.
// Only interior vertices move, so edges stay bit-exact with their
// neighbours. For the strip along an edge of level m, in a patch whose
// ring spacing along the edge is h, its triangles span at most
// U = max(1/m, h) along the edge and δ across, and (as for the grid) the
// error is below (1/8)(M_along U² + 2 M_uv U δ + M_across δ²), with
// M_along the along-edge second-derivative bound of the net restricted to
// the strip. Interior-only arithmetic: none of it needs to be `precise`.

// Control point (a, b) of the net seen from outer edge k: a steps away
// from the edge, b along it in the edge's parameter direction.
int strip_index(uint k, int a, int b) {
    if (k == 0u) {
        return 4 * b + a;
    } else if (k == 1u) {
        return 4 * a + b;
    } else if (k == 2u) {
        return 4 * b + 3 - a;
    }
    return 4 * (3 - a) + b;
}

// The along-edge second-derivative bound within `width` of outer edge k:
// the net restricted to that strip (de Casteljau across the edge), its
// second differences along it.
float strip_along_bound(vec3 P[16], uint k, float width) {
    float m = 0.0;
    vec3 Q[16];
    for (int b = 0; b < 4; ++b) {
        vec3 p0 = P[strip_index(k, 0, b)];
        vec3 p1 = P[strip_index(k, 1, b)];
        vec3 p2 = P[strip_index(k, 2, b)];
        vec3 p3 = P[strip_index(k, 3, b)];
        vec3 a01 = mix(p0, p1, width);
        vec3 a12 = mix(p1, p2, width);
        vec3 a23 = mix(p2, p3, width);
        vec3 b012 = mix(a01, a12, width);
        vec3 b123 = mix(a12, a23, width);
        Q[4 * b] = p0;
        Q[4 * b + 1] = a01;
        Q[4 * b + 2] = b012;
        Q[4 * b + 3] = mix(b012, b123, width);
    }
    for (int a = 0; a < 4; ++a) {
        m = max(m, second_bound(Q[a], Q[4 + a], Q[8 + a]));
        m = max(m, second_bound(Q[4 + a], Q[8 + a], Q[12 + a]));
    }
    return m;
}

// The error bound of outer edge k's strip at `width` across it.
float strip_error(vec3 P[16], uint k, float width, float across, float mixed, float span) {
    float along = strip_along_bound(P, k, width);
    return 0.125 * ((along * span * span + 2.0 * mixed * span * width) + across * width * width)
        + strip_reach(k, width, span);
}

// The strip width for outer edge k that keeps `tol`: the tessellator's
// own (`natural`) where that does, else found by halving the interval
// below it (six steps; 0 where no width does).
float strip_width(vec3 P[16], uint k, float natural, float across, float mixed, float span,
    float tol) {
    if (strip_error(P, k, natural, across, mixed, span) <= tol) {
        return natural;
    }
    float lo = 0.0;
    float hi = natural;
    for (int i = 0; i < 6; ++i) {
        float mid = 0.5 * (lo + hi);
        if (strip_error(P, k, mid, across, mixed, span) <= tol) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// The tessellator's segments for a clamped inner level of a quad with
// some outer level above 1 (the spec's rounding for equal spacing; a
// level of 1 is taken as 1 + ε, two segments).
float inner_segments(float level) {
    return level <= 1.0 ? 2.0 : ceil(level);
}

// An interior coordinate x of a narrowed direction: the tessellator puts
// its inner grid on [ring, 1 - ring] (ring = 1/segments); it goes to
// [lo, 1 - hi] instead, evenly spaced as before.
precise float narrow(float x, float ring, float lo, float hi) {
    precise float s = (1.0 - lo - hi) / (1.0 - 2.0 * ring);
    precise float r = lo + (x - ring) * s;
    return clamp(r, lo, 1.0 - hi);
}

// ---------------------------------------------------------------- warp

// The sample position s in [0, 1] for the uniform parameter t along a
// direction whose density bound rises linearly from lo (at 0) to hi (at 1),
// lo < hi: ∫_0^s sqrt(f) = t ∫_0^1 sqrt(f) (their eq. 28). With
// r = sqrt(lo / hi) and h = sqrt(f(s) / hi): h³ = r³ + t (1 - r³) and
// s = (h² - r²) / (1 - r²).
precise float warp_rising(float t, float lo, float hi) {
    precise float r = sqrt(lo / hi);
    precise float r2 = r * r;
    precise float r3 = r2 * r;
    precise float h = pow(r3 + t * (1.0 - r3), 1.0 / 3.0);
    precise float s = (h * h - r2) / (1.0 - r2);
    return clamp(s, 0.0, 1.0);
}

// The re-parameterised position of uniform parameter t, for density
// bounds a at 0 and b at 1. Computed from the flatter end, and rounded to
// a multiple of 2^-20, so that the edge seen from the other side (t' = 1 - t,
// a and b swapped) gets exactly 1 - this: both sides make the one call
// below with the same arguments, and 1 - s is exact for such s. The ends
// stay exact and nearly equal bounds leave t alone.
precise float warp(float t, float a, float b) {
    if (t == 0.0 || t == 1.0 || nearly_equal(a, b)) {
        return t;
    }
    bool flip = a > b;
    precise float from_flat = flip ? 1.0 - t : t;
    precise float s = warp_rising(from_flat, minf(a, b), maxf(a, b));
    precise float q = floor(s * float(TESS_WARP_STEPS) + 0.5) * (1.0 / float(TESS_WARP_STEPS));
    precise float r = flip ? 1.0 - q : q;
    return r;
}

// The tessellator's coordinate with its mirror image made exact: the spec
// promises that a vertex at x on an outer edge comes with one at exactly
// 1 - x; below 1/2 that float may not give x back as 1 - (1 - x), so the
// small side is replaced by 1 - (1 - x), which does. Both sides of an edge
// then hold x and 1 - x with each the exact complement of the other, which
// curve() needs to evaluate the same point from either direction. (On a
// tessellator working in fixed point, as lavapipe's, this changes nothing.)
precise float mirror_exact(float x) {
    precise float y = 1.0 - x;
    precise float r = x < 0.5 ? 1.0 - y : x;
    return r;
}

#endif
