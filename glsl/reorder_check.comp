// The paper's §4.4 crack-freeness test on the GPU: every ready node's
// sub-patch is rebuilt from the base patch with its parameter domain
// reordered in each of the 8 ways (swap u/v, flip u, flip v) and must come
// out as the same 16 points, bit for bit. Counts nodes checked and failed.
// Rational patches are checked on their homogeneous control points, the
// ones their subdivision rebuilds (rational_subdiv.glsl).
#version 460

#define USE_LIST_PUSH
#include "common/ready.glsl"
#include "common/rational_subdiv.glsl"

layout(local_size_x = EXPAND_GROUP_SIZE) in;

// R(u, v) = S(u'', v''): u' = 1 - u if flip_u, likewise v'; (u'', v'') =
// (v', u') if swap. Same index map as BezierPatch::reoriented in Rust.
void reorient(vec3 S[16], bool swap_uv, bool flip_u, bool flip_v, out vec3 R[16]) {
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            int ni = flip_u ? 3 - i : i;
            int nj = flip_v ? 3 - j : j;
            int oi = swap_uv ? nj : ni;
            int oj = swap_uv ? ni : nj;
            R[4 * j + i] = S[4 * oj + oi];
        }
    }
}

bool same_bits(vec3 a[16], vec3 b[16]) {
    bool same = true;
    for (int i = 0; i < 16; ++i) {
        same = same && all(equal(floatBitsToUint(a[i]), floatBitsToUint(b[i])));
    }
    return same;
}

// reorient() and same_bits() on homogeneous points.
void reorient4(vec4 S[16], bool swap_uv, bool flip_u, bool flip_v, out vec4 R[16]) {
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 4; ++i) {
            int ni = flip_u ? 3 - i : i;
            int nj = flip_v ? 3 - j : j;
            int oi = swap_uv ? nj : ni;
            int oj = swap_uv ? ni : nj;
            R[4 * j + i] = S[4 * oj + oi];
        }
    }
}

bool same_bits4(vec4 a[16], vec4 b[16]) {
    bool same = true;
    for (int i = 0; i < 16; ++i) {
        same = same && all(equal(floatBitsToUint(a[i]), floatBitsToUint(b[i])));
    }
    return same;
}

// The domain [a,b]x[c,d] of ordering g (bit 0 swap, 1 flip u, 2 flip v).
vec4 reordered_domain(vec4 dom, uint g) {
    bool swap_uv = (g & 1u) != 0u;
    vec2 du = swap_uv ? dom.zw : dom.xy;
    vec2 dv = swap_uv ? dom.xy : dom.zw;
    if ((g & 2u) != 0u) du = vec2(1.0 - du.y, 1.0 - du.x);
    if ((g & 4u) != 0u) dv = vec2(1.0 - dv.y, 1.0 - dv.x);
    return vec4(du, dv);
}

bool rational_node_ok(uvec2 q) {
    vec4 H[16];
    load_homogeneous(node_patch(q), H);
    vec4 dom = node_domain(q);
    vec4 S[16];
    reconstruct4(H, dom.x, dom.y, dom.z, dom.w, S);
    bool ok = true;
    for (uint g = 1u; g < 8u; ++g) {
        bool swap_uv = (g & 1u) != 0u;
        bool flip_u = (g & 2u) != 0u;
        bool flip_v = (g & 4u) != 0u;
        vec4 R[16];
        reorient4(H, swap_uv, flip_u, flip_v, R);
        vec4 d = reordered_domain(dom, g);
        vec4 got[16];
        reconstruct4(R, d.x, d.y, d.z, d.w, got);
        vec4 want[16];
        reorient4(S, swap_uv, flip_u, flip_v, want);
        ok = ok && same_bits4(got, want);
    }
    return ok;
}

void main() {
    uint idx = gl_GlobalInvocationID.x;
    uint n = ready_count(pc.ready_capacity);
    if (idx >= n) {
        return;
    }
    uvec2 q = ready[idx];
    if (patch_is_rational(node_patch(q))) {
        atomicAdd(counters[C_CHECK_NODES], 1u);
        if (!rational_node_ok(q)) {
            atomicAdd(counters[C_CHECK_FAILS], 1u);
        }
        return;
    }
    vec3 P[16];
    load_patch(node_patch(q), P);
    vec4 dom = node_domain(q);
    vec3 S[16];
    reconstruct(P, dom.x, dom.y, dom.z, dom.w, S);
    bool ok = true;
    for (uint g = 1u; g < 8u; ++g) {
        bool swap_uv = (g & 1u) != 0u;
        bool flip_u = (g & 2u) != 0u;
        bool flip_v = (g & 4u) != 0u;
        vec3 R[16];
        reorient(P, swap_uv, flip_u, flip_v, R);
        vec2 du = swap_uv ? dom.zw : dom.xy;
        vec2 dv = swap_uv ? dom.xy : dom.zw;
        if (flip_u) du = vec2(1.0 - du.y, 1.0 - du.x);
        if (flip_v) dv = vec2(1.0 - dv.y, 1.0 - dv.x);
        vec3 got[16];
        reconstruct(R, du.x, du.y, dv.x, dv.y, got);
        vec3 want[16];
        reorient(S, swap_uv, flip_u, flip_v, want);
        ok = ok && same_bits(got, want);
    }
    atomicAdd(counters[C_CHECK_NODES], 1u);
    if (!ok) {
        atomicAdd(counters[C_CHECK_FAILS], 1u);
    }
}
