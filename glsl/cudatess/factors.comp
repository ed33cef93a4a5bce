// cudatess, stage 1 (Schwarz and Stamminger, Fig. 1: "determine tessellation
// factors element-locally"): one invocation per base patch. A patch whose
// control points lie wholly outside the frustum gets factor 0 (culled), and
// so does a one-sided polynomial patch whose every normal faces away from
// the eye (back_facing, the test subdiv and tess make; their §2 allows
// back-face culling here), so a closed model's far side is not drawn. A
// one-sided rational patch takes subdiv's homogeneous form of the same test
// (back_facing4: the polynomial bound on the points w (p - eye), whose
// sign is that of (p - eye) . (p_u x p_v) for positive weights).
// Otherwise the Zheng–Sederberg bound of their §3 gives factors m along u
// and n along v for the tolerance of ε pixels at the patch's nearest control
// point (as tess.glsl turns ε into object space), and each edge's factor
// becomes the largest any of its patches asks for (atomicMax into the edge
// table): the consistent factors of stage 2, with no second pass over edges.
//
// A displaced patch (issue 40) takes its factors from the subdivision's own
// reach bound (common/displace.glsl, displaced_grid): the fewest m x n cells
// for which the base bound's error plus every cell's reach keeps the
// tolerance, taken `margin` nearer; its box grows by the margin and it is
// never back-face culled. The core the pattern draws is at least as fine,
// and a transition strip's triangles lie within one core cell.
#version 460

#include "common/cudatess.glsl"
#include "push.glsl"
#include "common/rational_subdiv.glsl"
#include "common/texture.glsl"
#include "common/displace.glsl"

layout(local_size_x = CT_GROUP_SIZE) in;

// |Δ b.xyz| + slack |Δ b.w| of a difference of homogeneous control points.
float zs_term(vec4 d, float slack) {
    return length(d.xyz) + slack * abs(d.w);
}

// A factor for ceil(sqrt(x)) steps, clamped to [1, CT_MAX_FACTOR]; NaN
// (a degenerate patch) gives 1.
uint factor_of(float x) {
    float f = ceil(sqrt(x));
    return f >= 1.0 ? uint(min(f, float(CT_MAX_FACTOR))) : 1u;
}

// Whether every normal of patch `id` (points P, box lo..hi) faces away
// from the eye.
bool faces_away(uint id, vec3 P[16], vec3 lo, vec3 hi) {
    if (!patch_is_rational(id)) {
        return back_facing(P, lo, hi, view.eye.xyz);
    }
    vec4 H[16];
    load_homogeneous(id, H);
    return back_facing4(H, view.eye.xyz);
}

void process(uint id) {
    uint rec = id * CT_PATCH_WORDS;
    vec3 P[16];
    load_patch(id, P);
    vec3 lo, hi;
    patch_bbox(P, lo, hi);
    DispModel dm;
    bool displaced = displaced_model(patch_flags_of(id) >> PATCH_MODEL_SHIFT, dm);
    if (displaced) {
        lo -= vec3(dm.margin);
        hi += vec3(dm.margin);
    }
    // An instance drawn from a level of detail (src/lod) counts as culled.
    bool frustum = ((view.flags & FLAG_FRUSTUM_CULL) != 0u && outside_frustum(lo, hi, view))
        || (instances[instance_of(id)].flags & INSTANCE_LOD) != 0u;
    bool one_sided = (patch_flags_of(id) & PATCH_TWO_SIDED) == 0u && !displaced;
    bool away = !frustum && (view.flags & FLAG_BACKFACE_CULL) != 0u && one_sided
        && faces_away(id, P, lo, hi);
    if (frustum || away) {
        ct_patches[rec + CT_REC_M] = 0u;
        ct_patches[rec + CT_REC_N] = 0u;
        atomicAdd(ct_counters[frustum ? CT_CULLED : CT_BACKFACE], 1u);
        return;
    }
    // ε pixels at the nearest control point's depth (the surface lies in
    // their hull, so nowhere nearer).
    float depth = affine_row(view.depth_row, P[0]);
    for (int i = 1; i < 16; ++i) {
        depth = minf(depth, affine_row(view.depth_row, P[i]));
    }
    if (displaced) {
        depth -= dm.margin;
    }
    float tol = view.eps_k * maxf(depth, view.near);
    // Homogeneous points about the centre of the box (the error does not
    // depend on the origin; a near one keeps r, the largest distance of a
    // control point from it, small). A polynomial patch has Δw = 0, so its
    // origin does not matter and its points are taken as they are.
    bool rational = patch_is_rational(id);
    vec3 c = rational ? (lo + hi) * 0.5 : vec3(0.0);
    vec4 G[16];
    float r = 0.0;
    float w_min = 1.0;
    for (int i = 0; i < 16; ++i) {
        float w = rational ? patch_weight(id, uint(i)) : 1.0;
        vec3 q = P[i] - c;
        G[i] = vec4(q * w, w);
        r = max(r, length(q));
        w_min = i == 0 ? w : min(w_min, w);
    }
    float slack = max(r - tol, 0.0);
    float duu = 0.0;
    float dvv = 0.0;
    float duv = 0.0;
    for (int j = 0; j < 4; ++j) {
        for (int i = 0; i < 2; ++i) {
            duu = max(duu, zs_term(G[4 * j + i] - 2.0 * G[4 * j + i + 1] + G[4 * j + i + 2], slack));
            dvv = max(dvv, zs_term(G[4 * i + j] - 2.0 * G[4 * (i + 1) + j] + G[4 * (i + 2) + j], slack));
        }
    }
    for (int j = 0; j < 3; ++j) {
        for (int i = 0; i < 3; ++i) {
            duv = max(duv, zs_term(G[4 * j + i] - G[4 * j + i + 1] - G[4 * (j + 1) + i]
                + G[4 * (j + 1) + i + 1], slack));
        }
    }
    duu *= 6.0;
    dvv *= 6.0;
    duv *= 9.0;
    // D_uu du^2 + 2 D_uv du dv + D_vv dv^2 <= 8 tol w_min holds when each
    // of (D_uu + D_uv) du^2 and (D_vv + D_uv) dv^2 is at most half of it.
    float budget = 4.0 * tol * w_min;
    uint m = factor_of((duu + duv) / budget);
    uint n = factor_of((dvv + duv) / budget);
    if (displaced) {
        // The base bound keeps tol at sqrt(x) segments per direction.
        vec2 base = sqrt(vec2((duu + duv) / budget, (dvv + duv) / budget));
        vec2 grid = displaced_grid(instances[instance_of(id)], id, dm, base,
            vec2(float(m), float(n)), tol, float(CT_MAX_FACTOR));
        m = uint(grid.x);
        n = uint(grid.y);
    }
    ct_patches[rec + CT_REC_M] = m;
    ct_patches[rec + CT_REC_N] = n;
    uvec4 edges = ct_edge_ids[id];
    atomicMax(ct_edge_factors[edges.x], n);
    atomicMax(ct_edge_factors[edges.y], m);
    atomicMax(ct_edge_factors[edges.z], n);
    atomicMax(ct_edge_factors[edges.w], m);
    atomicMax(ct_counters[CT_MAX_FACTOR_SEEN], max(m, n));
}

void main() {
    uint stride = gl_NumWorkGroups.x * CT_GROUP_SIZE;
    for (uint id = gl_GlobalInvocationID.x; id < ct.patch_count; id += stride) {
        process(id);
    }
}
