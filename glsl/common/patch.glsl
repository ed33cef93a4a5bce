// The patch math shared by every pass that touches a position or a decision:
// curve and surface evaluation, blossom reconstruction of sub-patches, the
// subdivision criterion, culling, QuadNodes and wedges. It is the twin of
// src/patch/{bezier,blossom,criterion,cull,quadnode,wedge}.rs, operation for
// operation; the GPU-vs-oracle tests compare the results bit for bit. Change
// one side only together with the other.
//
// Patches are `vec3 P[16]`, point (u index i, v index j) at P[4*j + i].
#ifndef PATCH_GLSL
#define PATCH_GLSL

#include "ops.glsl"

// ---------------------------------------------------------------- view

// Per-frame constants (std140/std430 layout = Rust's ViewParams).
struct ViewParams {
    vec4 depth_row;  // view-space depth of p: affine_row(depth_row, p)
    vec4 planes[6];  // frustum planes, inside when affine_row >= 0
    vec4 eye;        // camera position
    float eps_k;     // eps * 2 tan(fov_y/2) / height
    float near;      // depth clamp
    float w_orth;    // 1 - lambda
    float w_par;     // lambda
    uint l_max;
    uint flags;
    uint pad0;
    uint pad1;
};

// ---------------------------------------------------------------- Bézier

// Cubic curve, the paper's operation order (§3.4): reversal-symmetric.
precise vec3 curve(float u0, vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
    precise float u1 = 1.0 - u0;
    precise float b0 = u1 * u1 * u1;
    precise float b1 = 3.0 * u1 * u0 * u1;
    precise float b2 = 3.0 * u0 * u1 * u0;
    precise float b3 = u0 * u0 * u0;
    precise vec3 r = (p0 * b0 + p1 * b1) + (p2 * b2 + p3 * b3);
    return r;
}

// Surface point, curve of curves: rows at u, then the column curve at v.
precise vec3 eval_patch(vec3 P[16], float u, float v) {
    precise vec3 c0 = curve(u, P[0], P[1], P[2], P[3]);
    precise vec3 c1 = curve(u, P[4], P[5], P[6], P[7]);
    precise vec3 c2 = curve(u, P[8], P[9], P[10], P[11]);
    precise vec3 c3 = curve(u, P[12], P[13], P[14], P[15]);
    precise vec3 r = curve(v, c0, c1, c2, c3);
    return r;
}

// Curve derivative (shading only).
vec3 curve_derivative(float u0, vec3 p0, vec3 p1, vec3 p2, vec3 p3) {
    float u1 = 1.0 - u0;
    return ((p1 - p0) * (u1 * u1) + (p2 - p1) * (2.0 * u1 * u0) + (p3 - p2) * (u0 * u0)) * 3.0;
}

// Unnormalised normal dS/du x dS/dv (shading only); where a boundary curve
// collapses to a point the normal is taken a little way into the domain.
vec3 patch_normal(vec3 P[16], float u, float v) {
    vec3 n = vec3(0.0);
    for (int attempt = 0; attempt < 2; ++attempt) {
        vec3 du[4];
        vec3 pu[4];
        for (int j = 0; j < 4; ++j) {
            du[j] = curve_derivative(u, P[4 * j], P[4 * j + 1], P[4 * j + 2], P[4 * j + 3]);
            pu[j] = curve(u, P[4 * j], P[4 * j + 1], P[4 * j + 2], P[4 * j + 3]);
        }
        vec3 su = curve(v, du[0], du[1], du[2], du[3]);
        vec3 sv = curve_derivative(v, pu[0], pu[1], pu[2], pu[3]);
        n = cross(su, sv);
        if (dot(n, n) > 1e-12 * dot(su, su) * dot(sv, sv) && dot(su, su) * dot(sv, sv) > 0.0) {
            return n;
        }
        u += (0.5 - u) * 1e-3;
        v += (0.5 - v) * 1e-3;
    }
    return n;
}

// ---------------------------------------------------------------- blossoms

// Bilinear interpolation, pairwise: (P00 + P11) + (P10 + P01).
precise vec3 bilerp(float u0, float v0, vec3 p00, vec3 p10, vec3 p01, vec3 p11) {
    precise float u1 = 1.0 - u0;
    precise float v1 = 1.0 - v0;
    precise vec3 w00 = p00 * (u1 * v1);
    precise vec3 w10 = p10 * (u0 * v1);
    precise vec3 w01 = p01 * (u1 * v0);
    precise vec3 w11 = p11 * (u0 * v0);
    precise vec3 r = (w00 + w11) + (w10 + w01);
    return r;
}

// Sub-patch of P over [a,b]x[c,d] from tensor-product blossoms (§3.3.2):
// output point (u 2j+i, v 2l+k) = s(U[j], U[j], U[i] | V[l], V[l], V[k]).
void reconstruct(vec3 P[16], float a, float b, float c, float d, out vec3 S[16]) {
    float U[2] = float[2](a, b);
    float V[2] = float[2](c, d);
    precise vec3 D[36];  // [l][k][3x3]
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 3; ++j)
                for (int i = 0; i < 3; ++i)
                    D[(2 * l + k) * 9 + 3 * j + i] = bilerp(U[k], V[l],
                        P[4 * j + i], P[4 * j + i + 1], P[4 * (j + 1) + i], P[4 * (j + 1) + i + 1]);
    precise vec3 E[16];  // [l][k][2x2]
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    int o = (2 * l + k) * 9;
                    E[(2 * l + k) * 4 + 2 * j + i] = bilerp(U[k], V[l],
                        D[o + 3 * j + i], D[o + 3 * j + i + 1], D[o + 3 * (j + 1) + i], D[o + 3 * (j + 1) + i + 1]);
                }
    for (int l = 0; l < 2; ++l)
        for (int k = 0; k < 2; ++k)
            for (int j = 0; j < 2; ++j)
                for (int i = 0; i < 2; ++i) {
                    int o = (2 * l + j) * 4;
                    S[4 * (2 * l + k) + 2 * j + i] = bilerp(U[i], V[k], E[o], E[o + 1], E[o + 2], E[o + 3]);
                }
}

// ---------------------------------------------------------------- QuadNode

uint node_depth(uvec2 q) { return (q.y >> NODE_DEPTH_SHIFT) & 0xfu; }
uint node_m(uvec2 q) { return (q.y >> NODE_M_SHIFT) & 0x3ffu; }
uint node_n(uvec2 q) { return (q.y >> NODE_N_SHIFT) & 0x3ffu; }
uint node_l0(uvec2 q) { return (q.y >> NODE_L0_SHIFT) & 0xfu; }
uint node_l1(uvec2 q) { return (q.y >> NODE_L1_SHIFT) & 0xfu; }

uvec2 make_node(uint patch_id, uint depth, uint m, uint n, uint l0, uint l1) {
    return uvec2(patch_id, (depth << NODE_DEPTH_SHIFT) | (m << NODE_M_SHIFT) | (n << NODE_N_SHIFT)
        | (l0 << NODE_L0_SHIFT) | (l1 << NODE_L1_SHIFT));
}

// [a,b]x[c,d], exact.
vec4 node_domain(uvec2 q) {
    float s = pow2_neg(node_depth(q));
    float m = float(node_m(q));
    float n = float(node_n(q));
    return vec4(m * s, (m + 1.0) * s, n * s, (n + 1.0) * s);
}

// ---------------------------------------------------------------- criterion

const uint EDGE_BOTTOM = 0u;
const uint EDGE_RIGHT = 1u;
const uint EDGE_TOP = 2u;
const uint EDGE_LEFT = 3u;

// Boundary curve e, counter-clockwise around the domain.
void patch_edge(vec3 S[16], uint e, out vec3 c[4]) {
    if (e == EDGE_BOTTOM) {
        c = vec3[4](S[0], S[1], S[2], S[3]);
    } else if (e == EDGE_RIGHT) {
        c = vec3[4](S[3], S[7], S[11], S[15]);
    } else if (e == EDGE_TOP) {
        c = vec3[4](S[15], S[14], S[13], S[12]);
    } else {
        c = vec3[4](S[12], S[8], S[4], S[0]);
    }
}

precise float tolerance2(vec3 p, ViewParams vp) {
    precise float z = maxf(affine_row(vp.depth_row, p), vp.near);
    precise float t = vp.eps_k * z;
    precise float t2 = t * t;
    return t2;
}

// Flat when lhs <= rhs: see src/patch/criterion.rs for the derivation.
precise vec2 line_sample_terms(vec3 s, vec3 a, vec3 b, float t, float t2, ViewParams vp) {
    precise vec3 chord = b - a;
    precise vec3 d = s - a;
    precise vec3 on_line = a * (1.0 - t) + b * t;
    precise vec3 par = s - on_line;
    precise float chord2 = dot3(chord, chord);
    if (chord2 == 0.0) {
        return vec2(dot3(d, d), t2);
    }
    precise vec3 x = cross3(d, chord);
    precise float lhs = vp.w_orth * dot3(x, x) + (vp.w_par * dot3(par, par)) * chord2;
    precise float rhs = t2 * chord2;
    return vec2(lhs, rhs);
}

bool line_sample_flat(vec3 s, vec3 a, vec3 b, float t, float t2, ViewParams vp) {
    precise vec2 r = line_sample_terms(s, a, b, t, t2, vp);
    return r.x <= r.y;
}

// Inner-tier candidates (src/patch/criterion.rs): `s` against the plane of
// triangle (a, b, c) when its foot lies inside the triangle, and against the
// diagonal a -> b when its foot lies within the segment.
bool triangle_candidate_flat(vec3 s, vec3 a, vec3 b, vec3 c, float w_par2, float t2, ViewParams vp) {
    precise vec3 n = cross3(b - a, c - a);
    precise float n2 = dot3(n, n);
    precise vec3 sa = s - a;
    precise float e_ab = dot3(cross3(b - a, sa), n);
    precise float e_bc = dot3(cross3(c - b, s - b), n);
    precise float e_ca = dot3(cross3(a - c, s - c), n);
    precise float h = dot3(n, sa);
    precise float lhs = vp.w_orth * (h * h) + w_par2 * n2;
    precise float rhs = t2 * n2;
    bool inside = ((e_ab >= 0.0) && (e_bc >= 0.0)) && (e_ca >= 0.0);
    return ((n2 > 0.0) && (lhs <= rhs)) && inside;
}

bool diagonal_candidate_flat(vec3 s, vec3 a, vec3 b, float w_par2, float t2, ViewParams vp) {
    precise vec3 chord = b - a;
    precise float chord2 = dot3(chord, chord);
    precise vec3 d = s - a;
    precise float along = dot3(d, chord);
    precise vec3 x = cross3(d, chord);
    precise float lhs = vp.w_orth * dot3(x, x) + w_par2 * chord2;
    precise float rhs = t2 * chord2;
    return ((chord2 > 0.0) && (lhs <= rhs)) && ((along >= 0.0) && (along <= chord2));
}

// One inner sample `s` with drawn point `p`, against the closest of the
// quad's triangles (q00, q10, q11) and (q00, q11, q01).
bool inner_sample_flat(vec3 s, vec3 p, vec3 q00, vec3 q10, vec3 q11, vec3 q01, float t2, ViewParams vp) {
    precise vec3 par = s - p;
    precise float par2 = dot3(par, par);
    precise float w_par2 = vp.w_par * par2;
    bool at_p = par2 <= t2;
    bool diagonal = diagonal_candidate_flat(s, q00, q11, w_par2, t2, vp);
    bool first = triangle_candidate_flat(s, q00, q10, q11, w_par2, t2, vp);
    bool second = triangle_candidate_flat(s, q00, q11, q01, w_par2, t2, vp);
    return (at_p || diagonal) || (first || second);
}

// The inner tier on the corners and the samples at (1/3,1/3), (2/3,2/3),
// (2/3,1/3), (1/3,2/3), in that order.
bool inner_flat_of(vec3 q00, vec3 q10, vec3 q11, vec3 q01, vec3 s[4], ViewParams vp) {
    precise vec3 center = ((q00 + q11) + (q10 + q01)) * 0.25;
    precise float t2 = tolerance2(center, vp);
    precise vec3 l1 = q00 * (1.0 - THIRD) + q11 * THIRD;
    precise vec3 l2 = q00 * (1.0 - TWO_THIRDS) + q11 * TWO_THIRDS;
    precise vec3 m0 = (q00 * THIRD + q10 * THIRD) + q11 * THIRD;
    precise vec3 m1 = (q00 * THIRD + q11 * THIRD) + q01 * THIRD;
    bool d1 = inner_sample_flat(s[0], l1, q00, q10, q11, q01, t2, vp);
    bool d2 = inner_sample_flat(s[1], l2, q00, q10, q11, q01, t2, vp);
    bool t0 = inner_sample_flat(s[2], m0, q00, q10, q11, q01, t2, vp);
    bool t1 = inner_sample_flat(s[3], m1, q00, q10, q11, q01, t2, vp);
    return (d1 && d2) && (t0 && t1);
}

// Edge tier: samples at 1/3 on the curve and at 1/3 on the reversed curve,
// each entirely in its own direction, so both patches sharing the edge
// compute the same pair of samples bit for bit.
bool edge_flat(vec3 p[4], ViewParams vp) {
    precise vec3 mid = (p[0] + p[3]) * 0.5;
    precise float t2 = tolerance2(mid, vp);
    precise vec3 fwd = curve(THIRD, p[0], p[1], p[2], p[3]);
    precise vec3 bwd = curve(THIRD, p[3], p[2], p[1], p[0]);
    bool f = line_sample_flat(fwd, p[0], p[3], THIRD, t2, vp);
    bool b = line_sample_flat(bwd, p[3], p[0], THIRD, t2, vp);
    return f && b;
}

// Inner tier against the closest of the triangles (00,10,11) and (00,11,01).
bool inner_flat(vec3 S[16], ViewParams vp) {
    vec3 s[4] = vec3[4](eval_patch(S, THIRD, THIRD), eval_patch(S, TWO_THIRDS, TWO_THIRDS),
                        eval_patch(S, TWO_THIRDS, THIRD), eval_patch(S, THIRD, TWO_THIRDS));
    return inner_flat_of(S[0], S[3], S[15], S[12], s, vp);
}

// ---------------------------------------------------------------- culling

void patch_bbox(vec3 S[16], out vec3 lo, out vec3 hi) {
    lo = S[0];
    hi = S[0];
    for (int i = 1; i < 16; ++i) {
        lo = min3(lo, S[i]);
        hi = max3(hi, S[i]);
    }
}

bool outside_frustum(vec3 lo, vec3 hi, ViewParams vp) {
    bool outside = false;
    for (int i = 0; i < 6; ++i) {
        vec4 p = vp.planes[i];
        vec3 corner = vec3(p.x >= 0.0 ? hi.x : lo.x, p.y >= 0.0 ? hi.y : lo.y, p.z >= 0.0 ? hi.z : lo.z);
        outside = outside || affine_row(p, corner) < 0.0;
    }
    return outside;
}

precise vec2 imul(vec2 a, vec2 b) {
    precise float p0 = a.x * b.x;
    precise float p1 = a.x * b.y;
    precise float p2 = a.y * b.x;
    precise float p3 = a.y * b.y;
    return vec2(minf(minf(p0, p1), minf(p2, p3)), maxf(maxf(p0, p1), maxf(p2, p3)));
}

precise vec2 isub(vec2 a, vec2 b) {
    precise float lo = a.x - b.y;
    precise float hi = a.y - b.x;
    return vec2(lo, hi);
}

// Conservative: culled only if every normal faces away at every point
// (interval bound of (dS/du x dS/dv) . (p - eye) > 0); see cull.rs.
bool back_facing(vec3 S[16], vec3 lo, vec3 hi, vec3 eye) {
    precise vec3 ulo = S[1] - S[0];
    precise vec3 uhi = ulo;
    precise vec3 vlo = S[4] - S[0];
    precise vec3 vhi = vlo;
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 3; ++i) {
            precise vec3 du = S[4 * j + i + 1] - S[4 * j + i];
            ulo = min3(ulo, du);
            uhi = max3(uhi, du);
            precise vec3 dv = S[4 * (i + 1) + j] - S[4 * i + j];
            vlo = min3(vlo, dv);
            vhi = max3(vhi, dv);
        }
    }
    vec2 ux = vec2(ulo.x, uhi.x), uy = vec2(ulo.y, uhi.y), uz = vec2(ulo.z, uhi.z);
    vec2 vx = vec2(vlo.x, vhi.x), vy = vec2(vlo.y, vhi.y), vz = vec2(vlo.z, vhi.z);
    precise vec2 nx = isub(imul(uy, vz), imul(uz, vy));
    precise vec2 ny = isub(imul(uz, vx), imul(ux, vz));
    precise vec2 nz = isub(imul(ux, vy), imul(uy, vx));
    precise vec3 wlo = lo - eye;
    precise vec3 whi = hi - eye;
    precise vec2 dx = imul(nx, vec2(wlo.x, whi.x));
    precise vec2 dy = imul(ny, vec2(wlo.y, whi.y));
    precise vec2 dz = imul(nz, vec2(wlo.z, whi.z));
    precise float low = (dx.x + dy.x) + dz.x;
    return low > 0.0;
}

// ---------------------------------------------------------------- wedges

// Flat depths of the four edges; equal to the node's depth = still pending.
uvec4 edge_depths(uvec2 q) {
    uint l = node_depth(q);
    uvec4 d = uvec4(l);
    if ((node_n(q) & 1u) == 0u) d[EDGE_BOTTOM] = node_l0(q); else d[EDGE_TOP] = node_l0(q);
    if ((node_m(q) & 1u) == 0u) d[EDGE_LEFT] = node_l1(q); else d[EDGE_RIGHT] = node_l1(q);
    return d;
}

uvec4 resolve_depths(uint l, uvec4 depths, bvec4 flat_now) {
    uvec4 r = depths;
    for (int e = 0; e < 4; ++e) {
        if (depths[e] >= l) {
            r[e] = flat_now[e] ? l : l + 1u;
        }
    }
    return r;
}

// Child (x, y) inheriting the resolved depths of the parent edges it lies on.
uvec2 child_node(uvec2 q, uvec4 resolved, uint x, uint y) {
    uint l0 = resolved[y == 0u ? EDGE_BOTTOM : EDGE_TOP];
    uint l1 = resolved[x == 0u ? EDGE_LEFT : EDGE_RIGHT];
    return make_node(q.x, node_depth(q) + 1u, 2u * node_m(q) + x, 2u * node_n(q) + y, l0, l1);
}

// A ready node's triangles in parameter space: vertices 0..3 are the corners
// (a,c), (b,c), (b,d), (a,d); slot 4 is the pivot of the wedge along u, slot
// 5 of the wedge along v. Triangles 0 and 1 are the quad; 2 and 3 the wedges
// (present when the bit is set), wound opposite to the quad's traversal of
// the shared edge. Pivots round the node coordinate down to the coarse depth.
struct NodeMesh {
    vec2 uv[6];
    uvec3 tris[4];
    bvec2 wedge;  // x: along u (tris[2]), y: along v (tris[3])
};

// The pivots of the node's wedges along u and along v (twin of
// wedge::wedge_pivots): the coordinate along an outer edge flat at a coarser
// depth, rounded down to it; absent where that is the node's own corner.
bvec2 wedge_pivots(uvec2 q, out vec2 pivot_u, out vec2 pivot_v) {
    uint l = node_depth(q);
    uint m = node_m(q);
    uint n = node_n(q);
    float s = pow2_neg(l);
    bvec2 has = bvec2(false);
    pivot_u = vec2(0.0);
    pivot_v = vec2(0.0);
    uint le = node_l0(q);
    if (le < l) {
        uint mp = (m >> (l - le)) << (l - le);
        if (mp != m) {
            uint ne = (n & 1u) == 0u ? n : n + 1u;
            pivot_u = vec2(float(mp) * s, float(ne) * s);
            has.x = true;
        }
    }
    le = node_l1(q);
    if (le < l) {
        uint np = (n >> (l - le)) << (l - le);
        if (np != n) {
            uint me = (m & 1u) == 0u ? m : m + 1u;
            pivot_v = vec2(float(me) * s, float(np) * s);
            has.y = true;
        }
    }
    return has;
}

NodeMesh node_mesh(uvec2 q, bool with_wedges) {
    uint l = node_depth(q);
    uint m = node_m(q);
    uint n = node_n(q);
    float s = pow2_neg(l);
    float a = float(m) * s, b = float(m + 1u) * s;
    float c = float(n) * s, d = float(n + 1u) * s;
    NodeMesh mesh;
    mesh.uv[0] = vec2(a, c);
    mesh.uv[1] = vec2(b, c);
    mesh.uv[2] = vec2(b, d);
    mesh.uv[3] = vec2(a, d);
    mesh.uv[4] = vec2(0.0);
    mesh.uv[5] = vec2(0.0);
    mesh.tris[0] = uvec3(0, 1, 2);
    mesh.tris[1] = uvec3(0, 2, 3);
    mesh.tris[2] = uvec3(0);
    mesh.tris[3] = uvec3(0);
    mesh.wedge = bvec2(false);
    if (!with_wedges) {
        return mesh;
    }
    vec2 pivot_u, pivot_v;
    bvec2 has = wedge_pivots(q, pivot_u, pivot_v);
    if (has.x) {
        bool bottom = (n & 1u) == 0u;
        mesh.uv[4] = pivot_u;
        mesh.tris[2] = bottom ? uvec3(1, 0, 4) : uvec3(3, 2, 4);
        mesh.wedge.x = true;
    }
    if (has.y) {
        bool left = (m & 1u) == 0u;
        mesh.uv[5] = pivot_v;
        mesh.tris[3] = left ? uvec3(0, 3, 5) : uvec3(2, 1, 5);
        mesh.wedge.y = true;
    }
    return mesh;
}

// Twin of cull::wedges_face_away: every wedge triangle of the ready node
// faces away from the eye (positions as drawn, from the base patch P).
bool wedges_face_away(vec3 P[16], uvec2 q, vec3 eye, bool with_wedges) {
    NodeMesh mesh = node_mesh(q, with_wedges);
    bool away = true;
    for (uint t = 2u; t < 4u; ++t) {
        if (!(t == 2u ? mesh.wedge.x : mesh.wedge.y)) {
            continue;
        }
        uvec3 k = mesh.tris[t];
        precise vec3 a = eval_patch(P, mesh.uv[k.x].x, mesh.uv[k.x].y);
        precise vec3 b = eval_patch(P, mesh.uv[k.y].x, mesh.uv[k.y].y);
        precise vec3 c = eval_patch(P, mesh.uv[k.z].x, mesh.uv[k.z].y);
        precise vec3 n = cross3(b - a, c - a);
        away = away && dot3(n, a - eye) > 0.0;
    }
    return away;
}

#endif
