// Displaced surfaces (issue 40): the GPU twin of src/patch/displace.rs and
// src/scene/displacement.rs, operation for operation, because a displaced
// vertex is a position and a displaced node's bound is a decision. The
// buffer layout is SceneDisplacement::gpu_words (BIND_DISPLACEMENT).
// Include after scene.glsl and texture.glsl (the UV patches).
#ifndef DISPLACE_GLSL
#define DISPLACE_GLSL

layout(std430, set = SET_SCENE, binding = BIND_DISPLACEMENT) readonly buffer Displacement {
    uint disp_words[];
};

// Whether some model is displaced: false drops every read below.
layout(constant_id = SPEC_SCENE_DISPLACED) const bool SCENE_DISPLACED = true;

struct DispModel {
    uint heights;  // first word of the heights
    uint width;    // 0: not displaced
    uint height;
    uint pyramid;  // first word of the pyramid
    uint levels;
    float scale;
    float bias;
    float margin;  // largest |displacement|, a little enlarged
};

// Scene model `model`'s displacement; false where it has none, or where
// the view draws every model undisplaced (FLAG_UNDISPLACED).
bool displaced_model(uint model, out DispModel m) {
    m = DispModel(0u, 0u, 0u, 0u, 0u, 0.0, 0.0, 0.0);
    if (!SCENE_DISPLACED || (view.flags & FLAG_UNDISPLACED) != 0u || model >= disp_words[2]) {
        return false;
    }
    uint o = DISPLACEMENT_HEADER_WORDS + model * DISPLACEMENT_MODEL_WORDS;
    m = DispModel(disp_words[o], disp_words[o + 1u], disp_words[o + 2u], disp_words[o + 3u],
                  disp_words[o + 4u], uintBitsToFloat(disp_words[o + 5u]),
                  uintBitsToFloat(disp_words[o + 6u]), uintBitsToFloat(disp_words[o + 7u]));
    return m.width != 0u;
}

// ------------------------------------------------------------ the normal

precise float soft_rsqrt(float x) {
    precise float y = uintBitsToFloat(RSQRT_MAGIC - (floatBitsToUint(x) >> 1u));
    precise float half_x = 0.5 * x;
    for (uint i = 0u; i < RSQRT_STEPS; ++i) {
        y = y * (1.5 - half_x * (y * y));
    }
    return y;
}

// BezierPatch::partials in its operation order.
precise vec3 curve_derivative_exact(float u0, vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
    precise float u1 = 1.0 - u0;
    precise vec3 d0 = p1 - p0;
    precise vec3 d1 = p2 - p1;
    precise vec3 d2 = p3 - p2;
    precise vec3 r = ((d0 * (u1 * u1) + d1 * ((2.0 * u1) * u0)) + d2 * (u0 * u0)) * 3.0;
    return r;
}

void exact_partials(vec3 P[16], float u, float v, out vec3 su, out vec3 sv) {
    vec3 du[4];
    vec3 pu[4];
    for (int j = 0; j < 4; ++j) {
        du[j] = curve_derivative_exact(u, P[4 * j], P[4 * j + 1], P[4 * j + 2], P[4 * j + 3]);
        pu[j] = curve(u, P[4 * j], P[4 * j + 1], P[4 * j + 2], P[4 * j + 3]);
    }
    su = curve(v, du[0], du[1], du[2], du[3]);
    sv = curve_derivative_exact(v, pu[0], pu[1], pu[2], pu[3]);
}

// Twin of displace::unit_normal.
precise vec3 displaced_normal(vec3 P[16], float u, float v) {
    precise vec3 n = vec3(0.0);
    precise float uu = u;
    precise float vv = v;
    for (int attempt = 0; attempt < 2; ++attempt) {
        vec3 su, sv;
        exact_partials(P, uu, vv, su, sv);
        n = cross3(su, sv);
        if (dot3(n, n) > 0.0) {
            break;
        }
        uu = uu + (0.5 - uu) * (1.0 / 256.0);
        vv = vv + (0.5 - vv) * (1.0 / 256.0);
    }
    precise float n2 = dot3(n, n);
    precise vec3 r = n2 > 0.0 ? n * soft_rsqrt(n2) : vec3(0.0);
    return r;
}

// ------------------------------------------------------------ the heights

precise float height_coord(float s, uint n) {
    float limit = float(1u << UV_LIMIT_LOG2);
    precise float c = minf(maxf(s, -limit), limit);
    precise float r = c * float(n) - 0.5;
    return r;
}

float height_texel(DispModel m, int x, int y) {
    uint xi = uint(x & int(m.width - 1u));
    uint yi = uint(y & int(m.height - 1u));
    return uintBitsToFloat(disp_words[m.heights + yi * m.width + xi]);
}

// Twin of HeightMap::sample.
precise float height_at(DispModel m, float s, float t) {
    precise float x = height_coord(s, m.width);
    precise float y = height_coord(t, m.height);
    precise float x0 = floor(x);
    precise float y0 = floor(y);
    precise float fx = x - x0;
    precise float fy = y - y0;
    int i = int(x0);
    int j = int(y0);
    precise float a = height_texel(m, i, j) * (1.0 - fx) + height_texel(m, i + 1, j) * fx;
    precise float b = height_texel(m, i, j + 1) * (1.0 - fx) + height_texel(m, i + 1, j + 1) * fx;
    precise float r = a * (1.0 - fy) + b * fy;
    return r;
}

// The map's gradient (dh/ds, dh/dt) at (s, t): the bilinear blend's own
// derivative inside its texel cell (for lighting, not for positions).
vec2 height_gradient(DispModel m, float s, float t) {
    float x = height_coord(s, m.width);
    float y = height_coord(t, m.height);
    float fx = x - floor(x);
    float fy = y - floor(y);
    int i = int(floor(x));
    int j = int(floor(y));
    float h00 = height_texel(m, i, j);
    float h10 = height_texel(m, i + 1, j);
    float h01 = height_texel(m, i, j + 1);
    float h11 = height_texel(m, i + 1, j + 1);
    return vec2(mix(h10 - h00, h11 - h01, fy) * float(m.width),
        mix(h01 - h00, h11 - h10, fx) * float(m.height));
}

// A pyramid cell: h lo, hi; x-slope lo, hi; y-slope lo, hi.
struct HCell {
    float v[6];
};

HCell hcell_merge(HCell a, HCell b) {
    HCell r;
    r.v[0] = minf(a.v[0], b.v[0]);
    r.v[1] = maxf(a.v[1], b.v[1]);
    r.v[2] = minf(a.v[2], b.v[2]);
    r.v[3] = maxf(a.v[3], b.v[3]);
    r.v[4] = minf(a.v[4], b.v[4]);
    r.v[5] = maxf(a.v[5], b.v[5]);
    return r;
}

HCell hcell_at(uint at) {
    HCell c;
    for (uint k = 0u; k < PYRAMID_CELL_FLOATS; ++k) {
        c.v[k] = uintBitsToFloat(disp_words[at + k]);
    }
    return c;
}

// Twin of HeightMap::cells: the merged cells covering the box lo..hi, and
// whether that is one level-0 cell.
HCell height_cells(DispModel m, vec2 lo, vec2 hi, out bool one_cell) {
    int x0 = int(floor(height_coord(lo.x, m.width)));
    int x1 = int(floor(height_coord(hi.x, m.width)));
    int y0 = int(floor(height_coord(lo.y, m.height)));
    int y1 = int(floor(height_coord(hi.y, m.height)));
    uint top = m.levels - 1u;
    uint l = 0u;
    uint at = m.pyramid;
    while (l < top && ((x1 >> l) - (x0 >> l) > 1 || (y1 >> l) - (y0 >> l) > 1)) {
        at += PYRAMID_CELL_FLOATS * max(m.width >> l, 1u) * max(m.height >> l, 1u);
        ++l;
    }
    int w = int(max(m.width >> l, 1u));
    int h = int(max(m.height >> l, 1u));
    HCell r;
    float inf = uintBitsToFloat(0x7f800000u);
    r.v = float[6](inf, -inf, inf, -inf, inf, -inf);
    int ys[2] = int[2](y0 >> l, y1 >> l);
    int xs[2] = int[2](x0 >> l, x1 >> l);
    for (int b = 0; b < 2; ++b) {
        for (int a = 0; a < 2; ++a) {
            uint cell = uint((ys[b] & (h - 1)) * w + (xs[a] & (w - 1)));
            r = hcell_merge(r, hcell_at(at + PYRAMID_CELL_FLOATS * cell));
        }
    }
    one_cell = x0 == x1 && y0 == y1;
    return r;
}

// Twin of HeightMap::variation.
precise float height_variation(DispModel m, vec2 lo, vec2 hi, float grow) {
    precise vec2 glo = vec2(lo.x - grow, lo.y - grow);
    precise vec2 ghi = vec2(hi.x + grow, hi.y + grow);
    bool one_cell;
    HCell c = height_cells(m, glo, ghi, one_cell);
    precise float w = float(m.width);
    precise float h = float(m.height);
    precise float gx = (c.v[2] + c.v[3]) * 0.5;
    precise float sx = (c.v[3] - c.v[2]) * 0.5;
    precise float gy = (c.v[4] + c.v[5]) * 0.5;
    precise float sy = (c.v[5] - c.v[4]) * 0.5;
    precise float wx = (hi.x - lo.x) * w;
    precise float wy = (hi.y - lo.y) * h;
    precise float grow_x = grow * w;
    precise float grow_y = grow * h;
    precise float reach_x = wx * 0.5 + grow_x;
    precise float reach_y = wy * 0.5 + grow_y;
    precise float detrended = (sx * reach_x + sy * reach_y) + (abs(gx) * grow_x + abs(gy) * grow_y);
    precise float bound = minf(c.v[1] - c.v[0], detrended);
    if (one_cell) {
        precise float a = maxf(abs(c.v[2]), abs(c.v[3]));
        precise float b = maxf(abs(c.v[4]), abs(c.v[5]));
        precise float twist = c.v[3] - c.v[2];
        precise float bilinear = (((twist * wx) * wy) * 0.5) + (a * grow_x + b * grow_y);
        bound = minf(bound, bilinear);
    }
    precise float r = bound * (1.0 + 1.0 / 1024.0);
    return r;
}

// ------------------------------------------------------------ UV boxes

void load_uv_patch(uint k, out vec2 P[16]) {
    uint o = 32u * k;
    for (uint i = 0u; i < 16u; ++i) {
        P[i] = vec2(uv_patch_data[o + 2u * i], uv_patch_data[o + 2u * i + 1u]);
    }
}

vec2 uv_curvature_of(uint k) {
    uint o = disp_words[1] + 2u * k;
    return vec2(uintBitsToFloat(disp_words[o]), uintBitsToFloat(disp_words[o + 1u]));
}

float min4f(float a, float b, float c, float d) {
    return minf(minf(a, b), minf(c, d));
}

float max4f(float a, float b, float c, float d) {
    return maxf(maxf(a, b), maxf(c, d));
}

// Twin of displace::uv_box, from the UVs q0..q3 at the corners (a, c),
// (b, c), (a, d), (b, d) of dom = (a, b, c, d): their box and how far the
// UVs stray from their blend (m: the UV patch's curvature bounds).
void uv_box_from(vec2 q0, vec2 q1, vec2 q2, vec2 q3, vec2 m, vec4 dom, out vec2 lo, out vec2 hi,
    out float grow) {
    precise float du = dom.y - dom.x;
    precise float dv = dom.w - dom.z;
    precise float tw_s = abs((q0.x - q1.x) - (q2.x - q3.x));
    precise float tw_t = abs((q0.y - q1.y) - (q2.y - q3.y));
    precise float split = maxf(tw_s, tw_t) * 0.25;
    precise float g = ((du * du) * m.x + (dv * dv) * m.y) * 0.125 + split;
    grow = g;
    lo = vec2(min4f(q0.x, q1.x, q2.x, q3.x), min4f(q0.y, q1.y, q2.y, q3.y));
    hi = vec2(max4f(q0.x, q1.x, q2.x, q3.x), max4f(q0.y, q1.y, q2.y, q3.y));
}

// The same over dom of the UV patch P.
void uv_box_of(vec2 P[16], vec2 m, vec4 dom, out vec2 lo, out vec2 hi, out float grow) {
    precise vec2 q0 = eval_patch2(P, dom.x, dom.z);
    precise vec2 q1 = eval_patch2(P, dom.y, dom.z);
    precise vec2 q2 = eval_patch2(P, dom.x, dom.w);
    precise vec2 q3 = eval_patch2(P, dom.y, dom.w);
    uv_box_from(q0, q1, q2, q3, m, dom, lo, hi, grow);
}

// How far displacement over dom of a model patch can stray (world units),
// from its UV patch P and that patch's bounds c.
precise float reach_in(DispModel m, vec2 P[16], vec2 c, vec4 dom) {
    vec2 lo, hi;
    float grow;
    uv_box_of(P, c, dom, lo, hi, grow);
    precise float r = height_variation(m, lo, hi, grow) * abs(m.scale);
    return r;
}

// reach_in over dom of model patch k.
precise float reach_of_box(DispModel m, uint k, vec4 dom) {
    vec2 P[16];
    load_uv_patch(k, P);
    return reach_in(m, P, uv_curvature_of(k), dom);
}

// ------------------------------------------------------------ owners

uint owner_word(uint k, uint i) {
    return disp_words[disp_words[0] + OWNER_WORDS * k + i];
}

float edge_param(uint e, float u, float v) {
    precise float r = e == EDGE_BOTTOM ? u : (e == EDGE_RIGHT ? v : (e == EDGE_TOP ? 1.0 - u : 1.0 - v));
    return r;
}

vec2 edge_point(uint e, float s) {
    precise float c = 1.0 - s;
    if (e == EDGE_BOTTOM) {
        return vec2(s, 0.0);
    } else if (e == EDGE_RIGHT) {
        return vec2(1.0, s);
    } else if (e == EDGE_TOP) {
        return vec2(c, 1.0);
    }
    return vec2(0.0, c);
}

vec2 corner_point(uint c) {
    return vec2(c == 1u || c == 2u ? 1.0 : 0.0, c >= 2u ? 1.0 : 0.0);
}

// Twin of displacement::owner_of: the model patch that displaces model
// patch k's point uv, and the point's parameters there.
uint owner_of(uint k, vec2 uv, out vec2 at) {
    float u = uv.x;
    float v = uv.y;
    int corner = -1;
    if (u == 0.0 && v == 0.0) {
        corner = 0;
    } else if (u == 1.0 && v == 0.0) {
        corner = 1;
    } else if (u == 1.0 && v == 1.0) {
        corner = 2;
    } else if (u == 0.0 && v == 1.0) {
        corner = 3;
    }
    int e = -1;
    if (corner < 0) {
        e = v == 0.0 ? int(EDGE_BOTTOM)
            : (u == 1.0 ? int(EDGE_RIGHT) : (v == 1.0 ? int(EDGE_TOP) : (u == 0.0 ? int(EDGE_LEFT) : -1)));
        if (e < 0) {
            at = uv;
            return k;
        }
        uint w = owner_word(k, uint(e));
        if ((w & OWNER_COLLAPSED) != 0u) {
            corner = e;
        } else {
            precise float s = edge_param(uint(e), u, v);
            precise float so = (w & OWNER_REVERSED) != 0u ? 1.0 - s : s;
            at = edge_point(w & OWNER_INDEX_MASK, so);
            return w >> OWNER_PATCH_SHIFT;
        }
    }
    uint w = owner_word(k, 4u + uint(corner));
    at = corner_point(w & OWNER_INDEX_MASK);
    return w >> OWNER_PATCH_SHIFT;
}

// Twin of Displaced::offset: n̂·d of base patch `id`'s point uv (instance
// t, displacement m), evaluated by its owner.
vec3 displacement_offset(Instance t, uint id, DispModel m, vec2 uv) {
    bool mirrored = (t.flags & INSTANCE_MIRRORED) != 0u;
    uint k = t.source + (id - t.first);
    vec2 at;
    uint o = owner_of(k, mirrored ? uv.yx : uv, at);
    uint og = t.first + (o - t.source);
    vec2 b = mirrored ? at.yx : at;
    vec3 P[16];
    load_patch_in(t, og, P);
    vec3 n = displaced_normal(P, b.x, b.y);
    vec2 UP[16];
    load_uv_patch(o, UP);
    precise vec2 st = eval_patch2(UP, at.x, at.y);
    precise float h = height_at(m, st.x, st.y);
    precise float d = m.bias + m.scale * h;
    precise vec3 r = n * d;
    return r;
}

// The UV line edge e of domain dom (of base patch id, instance t) lies on,
// in the terms of the edge's owner (twin of Displaced::edge_reach's
// owned_line): the owner's model patch o and the line as a box, sorted
// along it; false on a pole (a collapsed edge, one point).
bool edge_owner_line(Instance t, uint id, vec4 dom, uint e, out uint o, out vec4 line,
    out bool along) {
    uint k = t.source + (id - t.first);
    bool along_u = e == EDGE_BOTTOM || e == EDGE_TOP;
    float fixed_at = e == EDGE_BOTTOM ? dom.z : (e == EDGE_TOP ? dom.w : (e == EDGE_LEFT ? dom.x : dom.y));
    float t0 = along_u ? dom.x : dom.z;
    float t1 = along_u ? dom.y : dom.w;
    along_u = along_u != ((t.flags & INSTANCE_MIRRORED) != 0u);
    o = k;
    int me = -1;
    if (fixed_at == 0.0 || fixed_at == 1.0) {
        me = along_u ? (fixed_at == 0.0 ? int(EDGE_BOTTOM) : int(EDGE_TOP))
                     : (fixed_at == 0.0 ? int(EDGE_LEFT) : int(EDGE_RIGHT));
    }
    if (me >= 0) {
        uint w = owner_word(k, uint(me));
        if ((w & OWNER_COLLAPSED) != 0u) {
            line = vec4(0.0);
            along = true;
            return false;
        }
        vec2 p[2];
        float ts[2] = float[2](t0, t1);
        for (int i = 0; i < 2; ++i) {
            vec2 uv = along_u ? vec2(ts[i], fixed_at) : vec2(fixed_at, ts[i]);
            precise float s = edge_param(uint(me), uv.x, uv.y);
            precise float so = (w & OWNER_REVERSED) != 0u ? 1.0 - s : s;
            p[i] = edge_point(w & OWNER_INDEX_MASK, so);
        }
        uint oe = w & OWNER_INDEX_MASK;
        along_u = oe == EDGE_BOTTOM || oe == EDGE_TOP;
        fixed_at = along_u ? p[0].y : p[0].x;
        float s0 = along_u ? p[0].x : p[0].y;
        float s1 = along_u ? p[1].x : p[1].y;
        t0 = s1 < s0 ? s1 : s0;
        t1 = s1 < s0 ? s0 : s1;
        o = w >> OWNER_PATCH_SHIFT;
    }
    line = along_u ? vec4(t0, t1, fixed_at, fixed_at) : vec4(fixed_at, fixed_at, t0, t1);
    along = along_u;
    return true;
}

// Twin of Displaced::edge_reach: how far edge e of node q (base patch id
// of instance t) can stray, from the edge owner's UVs; 0 on a pole.
float displaced_edge_reach(Instance t, uint id, DispModel m, uvec2 q, uint e) {
    uint o;
    vec4 line;
    bool along;
    if (!edge_owner_line(t, id, node_domain(q), e, o, line, along)) {
        return 0.0;
    }
    return reach_of_box(m, o, line);
}

// ------------------------------------------------------------ grids

// The most cells per side cells_reach takes (a lattice row's points are
// kept); a tessellator's largest level is 64 on every device known.
const float GRID_LARGEST = 64.0;

// The largest reach over an nu × nv grid of equal cells of base patch id
// (instance t): what a tessellator's cells can stray by. The cells' UV
// corners are evaluated once per lattice point, row by row (the same bits
// as per cell). Stops at the first cell beyond `limit` (the answer is then
// only known to exceed it).
float cells_reach(Instance t, uint id, DispModel m, float nu, float nv, float limit) {
    uint k = t.source + (id - t.first);
    // In the model patch's own parameters: a mirrored instance swaps them
    // (the largest over all cells does not depend on the order).
    if ((t.flags & INSTANCE_MIRRORED) != 0u) {
        float s = nu;
        nu = nv;
        nv = s;
    }
    vec2 P[16];
    load_uv_patch(k, P);
    vec2 c = uv_curvature_of(k);
    vec2 row[65];
    for (float i = 0.0; i <= nu; i += 1.0) {
        precise vec2 q = eval_patch2(P, i / nu, 0.0);
        row[int(i)] = q;
    }
    float r = 0.0;
    for (float j = 0.0; j < nv; j += 1.0) {
        float v0 = j / nv;
        float v1 = (j + 1.0) / nv;
        vec2 below = row[0];
        precise vec2 left = eval_patch2(P, 0.0, v1);
        row[0] = left;
        for (float i = 0.0; i < nu; i += 1.0) {
            int a = int(i);
            precise vec2 above = eval_patch2(P, (i + 1.0) / nu, v1);
            vec4 dom = vec4(i / nu, (i + 1.0) / nu, v0, v1);
            vec2 lo, hi;
            float grow;
            uv_box_from(below, row[a + 1], row[a], above, c, dom, lo, hi, grow);
            below = row[a + 1];
            row[a + 1] = above;
            r = max(r, height_variation(m, lo, hi, grow) * abs(m.scale));
            if (r > limit) {
                return r;
            }
        }
    }
    return r;
}

// Whether a grid of n cells keeps tol: the base surface's error, which a
// metric asking for `base` segments keeps within tol and which falls as
// the square of the segments, plus the cells' reach.
bool grid_fits(Instance t, uint id, DispModel m, vec2 n, vec2 base, float tol) {
    vec2 scaled = base / n;
    float error = tol * max(scaled.x * scaled.x, scaled.y * scaled.y);
    return error + cells_reach(t, id, m, n.x, n.y, tol - error) <= tol;
}

// A displaced patch's grid for a tessellator: n0 (at least the base
// metric's) scaled by the least factor, found by doubling and then four
// halvings of the gap, at which every cell fits; whole segments, at most
// `largest` (where nothing fits, the largest).
vec2 displaced_grid(Instance t, uint id, DispModel m, vec2 base, vec2 n0, float tol, float most) {
    float largest = min(most, GRID_LARGEST);
    n0 = min(n0, vec2(largest));
    if (grid_fits(t, id, m, n0, base, tol)) {
        return n0;
    }
    float lo = 1.0;
    float hi = 1.0;
    for (;;) {
        hi *= 2.0;
        vec2 n = min(ceil(n0 * hi), vec2(largest));
        if (grid_fits(t, id, m, n, base, tol)) {
            break;
        }
        if (min(n.x, n.y) >= largest) {
            return n;
        }
        lo = hi;
    }
    for (int i = 0; i < 4; ++i) {
        float mid = 0.5 * (lo + hi);
        if (grid_fits(t, id, m, min(ceil(n0 * mid), vec2(largest)), base, tol)) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    return min(ceil(n0 * hi), vec2(largest));
}

// Twin of Displaced::inner_reach.
float displaced_inner_reach(Instance t, uint id, DispModel m, uvec2 q) {
    uint k = t.source + (id - t.first);
    vec4 dom = node_domain(q);
    vec4 d = (t.flags & INSTANCE_MIRRORED) != 0u ? vec4(dom.z, dom.w, dom.x, dom.y) : dom;
    return reach_of_box(m, k, d);
}

#endif
