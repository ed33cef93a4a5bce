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
    uint width;      // viewport size in pixels
    uint height;
    vec4 clip[4];    // rows of the view-projection matrix (occlusion test only)
};

// ---------------------------------------------------------------- Bézier

// curve(), eval_patch(), curve_derivative() (bezier_template.glsl) on
// Cartesian points.
#define BEZ_T vec3
#define BEZ_FN(name) name
#include "bezier_template.glsl"

// The tangents dS/du and dS/dv at v from the rows' points pu and
// u-derivatives du at u (shading only).
void column_tangents(vec3 pu[4], vec3 du[4], float v, out vec3 su, out vec3 sv) {
    su = curve(v, du[0], du[1], du[2], du[3]);
    sv = curve_derivative(v, pu[0], pu[1], pu[2], pu[3]);
}

// patch_normal() (normal_template.glsl): dS/du x dS/dv.
#define BEZ_T vec3
#define BEZ_FN(name) name
#include "normal_template.glsl"

// ---------------------------------------------------------------- blossoms

// bilerp(), reconstruct() (blossom_template.glsl) on Cartesian points.
#define BEZ_T vec3
#define BEZ_FN(name) name
#include "blossom_template.glsl"

// ---------------------------------------------------------------- QuadNode

// Layout in src/patch/quadnode.rs: x = patch (24 bits) | bottom (4) | top (4),
// y = u code (11) | v code (11) | left (4) | right (4); a code is
// (1 << depth) | index, an edge state its flat depth or NODE_EDGE_PENDING.
uint node_patch(uvec2 q) { return q.x & NODE_PATCH_MASK; }
uint node_du(uvec2 q) { return uint(findMSB((q.y >> NODE_U_SHIFT) & 0x7ffu)); }
uint node_dv(uvec2 q) { return uint(findMSB((q.y >> NODE_V_SHIFT) & 0x7ffu)); }
uint node_m(uvec2 q) { return ((q.y >> NODE_U_SHIFT) & 0x7ffu) ^ (1u << node_du(q)); }
uint node_n(uvec2 q) { return ((q.y >> NODE_V_SHIFT) & 0x7ffu) ^ (1u << node_dv(q)); }
// The deeper of the two depths (equal under iso): statistics, heat map.
uint node_depth(uvec2 q) { return max(node_du(q), node_dv(q)); }

// The states of the four edges, indexed by EDGE_* (0 bottom, 1 right,
// 2 top, 3 left).
uvec4 edge_states(uvec2 q) {
    return uvec4((q.x >> NODE_BOTTOM_SHIFT) & 0xfu, (q.y >> NODE_RIGHT_SHIFT) & 0xfu,
                 (q.x >> NODE_TOP_SHIFT) & 0xfu, (q.y >> NODE_LEFT_SHIFT) & 0xfu);
}

uvec2 make_node(uint patch_id, uint du, uint m, uint dv, uint n, uvec4 e) {
    uint x = patch_id | (e.x << NODE_BOTTOM_SHIFT) | (e.z << NODE_TOP_SHIFT);
    uint y = (((1u << du) | m) << NODE_U_SHIFT) | (((1u << dv) | n) << NODE_V_SHIFT)
        | (e.w << NODE_LEFT_SHIFT) | (e.y << NODE_RIGHT_SHIFT);
    return uvec2(x, y);
}

// The whole base patch: depth 0 both ways, every edge pending.
uvec2 root_node(uint patch_id) {
    return make_node(patch_id, 0u, 0u, 0u, 0u, uvec4(NODE_EDGE_PENDING));
}

// [a,b]x[c,d], exact.
vec4 node_domain(uvec2 q) {
    float su = pow2_neg(node_du(q));
    float sv = pow2_neg(node_dv(q));
    float m = float(node_m(q));
    float n = float(node_n(q));
    return vec4(m * su, (m + 1.0) * su, n * sv, (n + 1.0) * sv);
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

// tolerance2 with t reduced by `reach` (a displaced node's height
// variation), or -1 where nothing is left (twin of tolerance2_within).
precise float tolerance2_within(vec3 p, ViewParams vp, float reach) {
    precise float z = maxf(affine_row(vp.depth_row, p), vp.near);
    precise float t = vp.eps_k * z - reach;
    precise float t2 = t * t;
    return t > 0.0 ? t2 : -1.0;
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
// The inner tier's four samples at tolerance t2.
bool inner_flat_at(vec3 q00, vec3 q10, vec3 q11, vec3 q01, vec3 s[4], float t2, ViewParams vp) {
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

bool inner_flat_of(vec3 q00, vec3 q10, vec3 q11, vec3 q01, vec3 s[4], ViewParams vp) {
    precise vec3 center = ((q00 + q11) + (q10 + q01)) * 0.25;
    precise float t2 = tolerance2(center, vp);
    return inner_flat_at(q00, q10, q11, q01, s, t2, vp);
}

// inner_flat_of with the tolerance reduced by `reach` (a displaced node).
bool inner_flat_of_within(vec3 q00, vec3 q10, vec3 q11, vec3 q01, vec3 s[4], ViewParams vp,
                          float reach) {
    precise vec3 center = ((q00 + q11) + (q10 + q01)) * 0.25;
    precise float t2 = tolerance2_within(center, vp, reach);
    return inner_flat_at(q00, q10, q11, q01, s, t2, vp);
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

// edge_flat with the tolerance reduced by `reach` (a displaced edge's
// height variation, the same from both sides).
bool edge_flat_within(vec3 p[4], ViewParams vp, float reach) {
    precise vec3 mid = (p[0] + p[3]) * 0.5;
    precise float t2 = tolerance2_within(mid, vp, reach);
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

// inner_flat with the tolerance reduced by `reach`.
bool inner_flat_within(vec3 S[16], ViewParams vp, float reach) {
    vec3 s[4] = vec3[4](eval_patch(S, THIRD, THIRD), eval_patch(S, TWO_THIRDS, TWO_THIRDS),
                        eval_patch(S, TWO_THIRDS, THIRD), eval_patch(S, THIRD, TWO_THIRDS));
    return inner_flat_of_within(S[0], S[3], S[15], S[12], s, vp, reach);
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

// Whether edge e runs along u (bottom, top).
bool edge_along_u(uint e) { return e == EDGE_BOTTOM || e == EDGE_TOP; }

// The node's depth in the direction edge e runs.
uint depth_along(uvec2 q, uint e) { return edge_along_u(e) ? node_du(q) : node_dv(q); }

// Twin of wedge::resolve: a pending edge found flat now takes the node's
// depth in its direction, one not flat stays pending; others are kept.
uvec4 resolve_states(uvec2 q, bvec4 flat_now) {
    uvec4 s = edge_states(q);
    for (uint e = 0u; e < 4u; ++e) {
        if (s[e] == NODE_EDGE_PENDING && flat_now[e]) {
            s[e] = depth_along(q, e);
        }
    }
    return s;
}

// Twin of wedge::children: the children of a split halving u (split.x)
// and/or v (split.y), in the order (0,0), (1,0), (0,1), (1,1) of those that
// exist, each with the resolved states of the parent edges it lies on and
// pending new edges. Returns how many (2 or 4).
uint node_children(uvec2 q, bvec2 split, uvec4 r, out uvec2 kids[4]) {
    kids = uvec2[4](q, q, q, q);
    uint du = node_du(q), dv = node_dv(q), m = node_m(q), n = node_n(q);
    uint k = 0u;
    for (uint y = 0u; y <= (split.y ? 1u : 0u); ++y) {
        for (uint x = 0u; x <= (split.x ? 1u : 0u); ++x) {
            uvec4 e = uvec4(NODE_EDGE_PENDING);
            if (y == 0u) e.x = r.x;
            if (y == 1u || !split.y) e.z = r.z;
            if (x == 0u) e.w = r.w;
            if (x == 1u || !split.x) e.y = r.y;
            uint cu = split.x ? du + 1u : du;
            uint cm = split.x ? 2u * m + x : m;
            uint cv = split.y ? dv + 1u : dv;
            uint cn = split.y ? 2u * n + y : n;
            kids[k] = make_node(node_patch(q), cu, cm, cv, cn, e);
            k += 1u;
        }
    }
    return k;
}

// A ready node's triangles in parameter space: vertices 0..3 are the corners
// (a,c), (b,c), (b,d), (a,d); slot 4 + e is the pivot of the wedge on edge
// e. Triangles 0 and 1 are the quad; 2 + e the wedge on edge e (present
// when wedge[e]), wound opposite to the quad's traversal of that edge.
// Pivots round the node coordinate down to the coarse depth.
struct NodeMesh {
    vec2 uv[8];
    uvec3 tris[6];
    bvec4 wedge;
};

// The pivots of the node's wedges, per edge (twin of wedge::wedge_pivots):
// the coordinate along an edge flat at a coarser depth than the node's in
// that direction, rounded down to it; absent where that is the node's own
// corner.
bvec4 wedge_pivots(uvec2 q, out vec2 pivots[4]) {
    uint du = node_du(q), dv = node_dv(q), m = node_m(q), n = node_n(q);
    float su = pow2_neg(du), sv = pow2_neg(dv);
    uvec4 s = edge_states(q);
    bvec4 has = bvec4(false);
    pivots = vec2[4](vec2(0.0), vec2(0.0), vec2(0.0), vec2(0.0));
    for (uint e = 0u; e < 4u; ++e) {
        uint d = edge_along_u(e) ? du : dv;
        uint le = s[e];
        if (le == NODE_EDGE_PENDING || le >= d) {
            continue;
        }
        if (edge_along_u(e)) {
            uint mp = (m >> (d - le)) << (d - le);
            uint ve = e == EDGE_BOTTOM ? n : n + 1u;
            if (mp != m) {
                pivots[e] = vec2(float(mp) * su, float(ve) * sv);
                has[e] = true;
            }
        } else {
            uint np = (n >> (d - le)) << (d - le);
            uint ue = e == EDGE_LEFT ? m : m + 1u;
            if (np != n) {
                pivots[e] = vec2(float(ue) * su, float(np) * sv);
                has[e] = true;
            }
        }
    }
    return has;
}

NodeMesh node_mesh(uvec2 q, bool with_wedges) {
    vec4 dom = node_domain(q);
    NodeMesh mesh;
    mesh.uv[0] = vec2(dom.x, dom.z);
    mesh.uv[1] = vec2(dom.y, dom.z);
    mesh.uv[2] = vec2(dom.y, dom.w);
    mesh.uv[3] = vec2(dom.x, dom.w);
    mesh.tris[0] = uvec3(0, 1, 2);
    mesh.tris[1] = uvec3(0, 2, 3);
    // The wedge on edge e: the edge as the quad does not run it, then the
    // pivot in slot 4 + e.
    mesh.tris[2] = uvec3(1, 0, 4);
    mesh.tris[3] = uvec3(2, 1, 5);
    mesh.tris[4] = uvec3(3, 2, 6);
    mesh.tris[5] = uvec3(0, 3, 7);
    vec2 pivots[4];
    bvec4 has = wedge_pivots(q, pivots);
    for (uint e = 0u; e < 4u; ++e) {
        mesh.uv[4u + e] = pivots[e];
    }
    mesh.wedge = with_wedges ? has : bvec4(false);
    return mesh;
}

// How many wedges a ready node draws.
uint wedge_count(NodeMesh mesh) {
    return (mesh.wedge.x ? 1u : 0u) + (mesh.wedge.y ? 1u : 0u) + (mesh.wedge.z ? 1u : 0u)
        + (mesh.wedge.w ? 1u : 0u);
}

// wedges_face_away() (wedges_template.glsl) on Cartesian points.
#define BEZ_T vec3
#define BEZ_FN(name) name
#define BEZ_POINT(P, u, v) eval_patch(P, u, v)
#include "wedges_template.glsl"

#endif
