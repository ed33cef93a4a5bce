// cudatess for PN triangles, stage 1 (Schwarz and Stamminger §4: "derive
// the control points b_ijk as well as their bounding box and test it
// against the viewing frustum"): one invocation per triangle converts its
// three vertices (positions, normals) into the cubic net and the normal
// field (pn.glsl), culls it (factor 0), and derives a factor per edge from
// Filip's bound over the triangular domain: along direction d of edge k
// (d01 = P1 - P0, d12, d20 in barycentric terms), with step 1 / f,
//   (max |D_d D_d'| over the other two directions d' + |D_d D_d|) / (8 f^2)
// must stay within half the tolerance ε (their 2 δu δv <= δu² + δv² split,
// the patch path's budget). Each second derivative of the cubic is a
// linear Bézier triangle with 6 x the net's second differences as control
// points, so its magnitude is at most 6 x the largest of them. ε is the
// pixel tolerance at the net's nearest point, as for patches. Each edge's
// factor becomes the largest any triangle on it asks for (atomicMax).
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"
#include "common/pn.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

// Net index of b_ijk (i + j + k = 3; i for P0, j for P1, k for P2) at
// 16 i + 4 k + j; -1 in the unused slots.
const int NET_INDEX[64] = int[64](
    // i = 0 (k = 0..3, j = 0..3 within)
    -1, -1, -1, 1, /**/ -1, -1, 5, -1, /**/ -1, 6, -1, -1, /**/ 2, -1, -1, -1,
    // i = 1 (k = 0..3, j = 0..3 within)
    -1, -1, 4, -1, /**/ -1, 9, -1, -1, /**/ 7, -1, -1, -1, /**/ -1, -1, -1, -1,
    // i = 2 (k = 0..3, j = 0..3 within)
    -1, 3, -1, -1, /**/ 8, -1, -1, -1, /**/ -1, -1, -1, -1, /**/ -1, -1, -1, -1,
    // i = 3 (k = 0..3, j = 0..3 within)
    0, -1, -1, -1, /**/ -1, -1, -1, -1, /**/ -1, -1, -1, -1, /**/ -1, -1, -1, -1);

vec3 B[10];

vec3 b_at(ivec3 ijk) {
    return B[NET_INDEX[16 * ijk.x + 4 * ijk.z + ijk.y]];
}

// max over i + j + k = 1 of |Δ_d Δ_e b| for barycentric directions d, e.
float second_difference(ivec3 d, ivec3 e) {
    float most = 0.0;
    for (int base = 0; base < 3; ++base) {
        ivec3 o = ivec3(base == 0 ? 1 : 0, base == 1 ? 1 : 0, base == 2 ? 1 : 0);
        vec3 sum = vec3(0.0);
        for (int l = 0; l < 3; ++l) {
            for (int n = 0; n < 3; ++n) {
                int c = d[l] * e[n];
                if (c != 0) {
                    ivec3 at = o;
                    at[l] += 1;
                    at[n] += 1;
                    sum += float(c) * b_at(at);
                }
            }
        }
        most = max(most, length(sum));
    }
    return most;
}

uint factor_of(float x) {
    float f = ceil(sqrt(x));
    return f >= 1.0 ? uint(min(f, float(CT_MAX_FACTOR))) : 1u;
}

void process(uint t) {
    uint rec = (ct.patch_count + t) * CT_PATCH_WORDS;
    uvec4 tri = pn_triangles[t];
    vec3 P[3];
    vec3 N[3];
    for (uint k = 0u; k < 3u; ++k) {
        P[k] = pn_vertices[2u * tri[k]].xyz;
        N[k] = pn_vertices[2u * tri[k] + 1u].xyz;
    }
    B[0] = P[0];
    B[1] = P[1];
    B[2] = P[2];
    B[3] = pn_edge_point(P[0], P[1], N[0]);
    B[4] = pn_edge_point(P[1], P[0], N[1]);
    B[5] = pn_edge_point(P[1], P[2], N[1]);
    B[6] = pn_edge_point(P[2], P[1], N[2]);
    B[7] = pn_edge_point(P[2], P[0], N[2]);
    B[8] = pn_edge_point(P[0], P[2], N[0]);
    vec3 e = (B[3] + B[4] + B[5] + B[6] + B[7] + B[8]) / 6.0;
    vec3 v = (P[0] + P[1] + P[2]) / 3.0;
    B[9] = e + (e - v) * 0.5;
    uint o = t * CT_PN_NET_VEC4;
    for (uint k = 0u; k < 10u; ++k) {
        pn_nets[o + k] = vec4(B[k], 1.0);
    }
    pn_nets[o + 10u] = vec4(N[0], 0.0);
    pn_nets[o + 11u] = vec4(N[1], 0.0);
    pn_nets[o + 12u] = vec4(N[2], 0.0);
    pn_nets[o + 13u] = vec4(pn_edge_normal(P[0], P[1], N[0], N[1]), 0.0);
    pn_nets[o + 14u] = vec4(pn_edge_normal(P[1], P[2], N[1], N[2]), 0.0);
    pn_nets[o + 15u] = vec4(pn_edge_normal(P[2], P[0], N[2], N[0]), 0.0);

    vec3 lo = B[0];
    vec3 hi = B[0];
    float depth = affine_row(view.depth_row, B[0]);
    for (int k = 1; k < 10; ++k) {
        lo = min(lo, B[k]);
        hi = max(hi, B[k]);
        depth = minf(depth, affine_row(view.depth_row, B[k]));
    }
    if ((view.flags & FLAG_FRUSTUM_CULL) != 0u && outside_frustum(lo, hi, view)) {
        ct_patches[rec + CT_REC_M] = 0u;
        ct_patches[rec + CT_REC_N] = 0u;
        atomicAdd(ct_counters[CT_CULLED], 1u);
        return;
    }
    float tol = view.eps_k * maxf(depth, view.near);
    const ivec3 d01 = ivec3(-1, 1, 0);
    const ivec3 d12 = ivec3(0, -1, 1);
    const ivec3 d20 = ivec3(1, 0, -1);
    float s0101 = second_difference(d01, d01);
    float s1212 = second_difference(d12, d12);
    float s2020 = second_difference(d20, d20);
    float s0112 = second_difference(d01, d12);
    float s1220 = second_difference(d12, d20);
    float s2001 = second_difference(d20, d01);
    // (6 s) / 8 * δ² <= tol / 2  <=>  f² >= 6 s / (4 tol)
    float budget = 4.0 * tol / 6.0;
    uvec3 f = uvec3(factor_of((max(s2001, s0112) + s0101) / budget),
        factor_of((max(s0112, s1220) + s1212) / budget),
        factor_of((max(s1220, s2001) + s2020) / budget));
    ct_patches[rec + CT_REC_M] = max(f.x, max(f.y, f.z));
    ct_patches[rec + CT_REC_N] = min(f.x, min(f.y, f.z));
    uvec4 edges = pn_edge_ids[t];
    atomicMax(ct_edge_factors[edges.x], f.x);
    atomicMax(ct_edge_factors[edges.y], f.y);
    atomicMax(ct_edge_factors[edges.z], f.z);
    atomicMax(ct_counters[CT_MAX_FACTOR_SEEN], max(f.x, max(f.y, f.z)));
}

void main() {
    uint stride = gl_NumWorkGroups.x * CT_GROUP_SIZE;
    for (uint t = gl_GlobalInvocationID.x; t < ct.tri_count; t += stride) {
        process(t);
    }
}
