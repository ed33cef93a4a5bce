// Fragment shading shared by both draw paths (draw_mesh.frag and
// draw_vert.frag differ only in how the per-primitive values arrive).
// Include after scene.glsl. Colours are display values written straight to
// the UNORM target.
#ifndef SHADE_GLSL
#define SHADE_GLSL

#include "shading.glsl"
#include "texture.glsl"
#include "displace.glsl"
// A shader that draws rational patches defines SHADE_RATIONAL before this
// include: patches flagged PATCH_RATIONAL are then lit (and keyed) with
// their own rational normal; everything else is shaded exactly as before.
#ifdef SHADE_RATIONAL
#include "rational.glsl"
#endif
// A shader that draws cudatess's PN triangles defines SHADE_PN (and
// includes pn.glsl) before this include: a patch id with bit CT_PN_SHIFT
// set is then a PN triangle, lit and keyed with its quadratic normal field.
#ifdef SHADE_PN
bool shade_is_pn(uint patch_id) {
    return (patch_id & (1u << CT_PN_SHIFT)) != 0u;
}

uint shade_pn_triangle(uint patch_id) {
    return patch_id & ((1u << CT_PATCH_BITS) - 1u);
}
#endif

#ifdef SHADE_LEVEL
// A level of detail's draw (lod/draw.frag) has no patch to take the normal
// or the texture coordinates from: its triangles span patches. It sets
// these, interpolated from its vertices (the limit surface's there), before
// calling shade().
vec3 g_level_normal;
vec2 g_level_st;
#endif

// SHADE_DISPLACEMENT's colours (display values; src/commands/render.rs
// `Shade::Displacement` and the window's legend say the same).
const vec3 DISPLACEMENT_LOW = vec3(0.05, 0.10, 0.45);
const vec3 DISPLACEMENT_HIGH = vec3(1.0, 0.85, 0.2);
const vec3 UNDISPLACED_GREY = vec3(0.35);

// The flags word (model index, two-sided) of the patch or PN triangle.
uint shade_flags(uint patch_id) {
#ifdef SHADE_PN
    if (shade_is_pn(patch_id)) {
        return pn_flags(shade_pn_triangle(patch_id));
    }
#endif
    return patch_flags_of(patch_id);
}

// Per-model tint (model index = patch_flags >> PATCH_MODEL_SHIFT), the twin
// of src/palette.rs model_tint: eight hand-picked tints, then hues stepping
// by the golden ratio at three brightness levels, so no colour comes back.
const vec3 FIRST_TINTS[8] = vec3[8](
    vec3(0.90, 0.62, 0.38),
    vec3(0.42, 0.62, 0.90),
    vec3(0.52, 0.80, 0.45),
    vec3(0.88, 0.46, 0.56),
    vec3(0.80, 0.74, 0.46),
    vec3(0.60, 0.55, 0.88),
    vec3(0.42, 0.80, 0.78),
    vec3(0.78, 0.78, 0.78));

vec3 model_tint(uint index) {
    if (index < 8u) {
        return FIRST_TINTS[index];
    }
    float h = fract(0.425 + fract(0.618034 * float(index % 4096u)));
    float v = index % 3u == 0u ? 0.92 : (index % 3u == 1u ? 0.78 : 0.64);
    vec3 c = clamp(abs(fract(h + vec3(1.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
    return v * ((1.0 - 0.55) + 0.55 * c);
}

// The texture coordinates at the base patch's (u, v) (texture.glsl); a PN
// triangle has none but its own (u, v).
vec2 shade_surface_uv(uint patch_id, vec2 uv) {
#ifdef SHADE_LEVEL
    return g_level_st;
#endif
#ifdef SHADE_PN
    if (shade_is_pn(patch_id)) {
        return uv;
    }
#endif
    return surface_uv(patch_id, uv);
}

// The surface's colour before lighting, a display value: its model's
// albedo map at `st` (screen derivatives `dx`, `dy`), else its tint.
vec3 surface_albedo(uint patch_id, vec2 st, vec2 dx, vec2 dy) {
    uint model = shade_flags(patch_id) >> PATCH_MODEL_SHIFT;
    uvec4 mat = material_of(model);
#ifdef SHADE_PN
    if (shade_is_pn(patch_id)) {
        mat = uvec4(0u);
    }
#endif
    return has_map(mat) ? map_albedo(mat, st, dx, dy) : model_tint(model);
}

// QuadNode depth 0..L_MAX as the heat map's colours (constants.glsl, where
// src/constants.rs documents them; the window's legend shows the same).
const uint DEPTH_RAMP[11] = uint[11](
    DEPTH_RAMP_0, DEPTH_RAMP_1, DEPTH_RAMP_2, DEPTH_RAMP_3, DEPTH_RAMP_4, DEPTH_RAMP_5,
    DEPTH_RAMP_6, DEPTH_RAMP_7, DEPTH_RAMP_8, DEPTH_RAMP_9, DEPTH_RAMP_10);

vec3 rgb_of(uint c) {
    return vec3(float(c >> 16), float((c >> 8) & 255u), float(c & 255u)) / 255.0;
}

const vec3 WEDGE_COLOR = vec3(1.0, 0.0, 1.0); // WEDGE_RGB
// SHADE_KEY: the hole test counts pixels of exactly this colour (surface
// seen from behind, or the background).
const vec3 KEY_BACK = vec3(0.0, 1.0, 0.0);
const vec3 KEY_FRONT = vec3(1.0, 1.0, 1.0);
// SHADE_KEY: front surface seen at a grazing angle, i.e. near a contour
// (silhouette) where front and back surface meet in the image. There the
// subdivided and the reference surfaces may legitimately show different
// sides by a pixel, so the hole test treats this colour as silhouette.
const vec3 KEY_GRAZING = vec3(1.0, 1.0, 0.0);
const float GRAZING_COS = 0.15;

// `n` (unnormalised) as a unit normal, turned round when the fragment
// shows the surface's back (`front` false): lighting is two-sided.
vec3 facing_normal(vec3 n, vec3 to_eye, bool front) {
    if (!(dot(n, n) > 0.0)) {
        return to_eye;
    }
    n = normalize(n);
    return front ? n : -n;
}

// The geometry patch's own unit normal at (u, v), unturned (the eye
// direction where it vanishes): which side of the surface is seen, for the
// hole test's key colours and for wedges.
vec3 surface_normal(uint patch_id, vec2 uv, vec3 to_eye) {
#ifdef SHADE_LEVEL
    return facing_normal(g_level_normal, to_eye, true);
#endif
#ifdef SHADE_PN
    if (shade_is_pn(patch_id)) {
        return facing_normal(pn_normal(shade_pn_triangle(patch_id), uv), to_eye, true);
    }
#endif
#ifdef SHADE_RATIONAL
    if (patch_is_rational(patch_id)) {
        return facing_normal(rational_patch_normal(patch_id, uv.x, uv.y), to_eye, true);
    }
#endif
    vec3 P[16];
    load_patch(patch_id, P);
    return facing_normal(patch_normal(P, uv.x, uv.y), to_eye, true);
}

// A displaced model's normal to light with (Blinn's bump mapping): the
// shading normal n̂ tilted by the displacement's slope, n̂|N| + d_u (n × S_v)
// + d_v (S_u × n), N = S_u × S_v the base patch's and n its unit normal
// (what the displacement moves along), d_u and d_v the
// derivatives of bias + scale·h along u and v (the map's gradient through
// the UV patch's derivatives, by central differences). The turning of n̂
// itself (d times its derivatives) is left out: second order for heights
// small against the curvature's radius.
vec3 bumped_normal(uint patch_id, vec2 uv, vec3 n, DispModel dm) {
    vec3 P[16];
    load_patch(patch_id, P);
    vec3 su, sv;
    exact_partials(P, uv.x, uv.y, su, sv);
    vec3 big_n = cross(su, sv);
    if (!(dot(n, n) > 0.0) || !(dot(big_n, big_n) > 0.0)) {
        return n;
    }
    n = normalize(n);
    // The displacement moves along N's unit normal; the tilt turns with n̂
    // where the shading normal faces the other way.
    vec3 n_g = normalize(big_n);
    float o = dot(n, n_g) < 0.0 ? -1.0 : 1.0;
    const float h = 1.0 / 4096.0;
    vec2 st = shade_surface_uv(patch_id, uv);
    vec2 st_u = (shade_surface_uv(patch_id, uv + vec2(h, 0.0)) - shade_surface_uv(patch_id, uv - vec2(h, 0.0))) / (2.0 * h);
    vec2 st_v = (shade_surface_uv(patch_id, uv + vec2(0.0, h)) - shade_surface_uv(patch_id, uv - vec2(0.0, h))) / (2.0 * h);
    vec2 g = height_gradient(dm, st.x, st.y) * dm.scale;
    float d_u = dot(g, st_u);
    float d_v = dot(g, st_v);
    return n * length(big_n) + o * (d_u * cross(n_g, sv) + d_v * cross(su, n_g));
}

// The normal to light with at the base patch's (u, v): the shading
// patches' (shading.glsl), not the flat triangle's nor the geometry
// patch's own, which jump across patch edges next to extraordinary
// vertices; a displaced model's tilted by its map (bumped_normal).
// `front`: which side of the surface the fragment shows (see shade()).
vec3 shading_normal(uint patch_id, vec2 uv, vec3 to_eye, bool front) {
#ifdef SHADE_LEVEL
    return facing_normal(g_level_normal, to_eye, front);
#endif
#ifdef SHADE_PN
    if (shade_is_pn(patch_id)) {
        return facing_normal(pn_normal(shade_pn_triangle(patch_id), uv), to_eye, front);
    }
#endif
#ifdef SHADE_RATIONAL
    if (patch_is_rational(patch_id)) {
        return facing_normal(rational_patch_normal(patch_id, uv.x, uv.y), to_eye, front);
    }
#endif
    vec3 n = shading_patch_normal(patch_id, uv.x, uv.y);
    DispModel dm;
    if (displaced_model(shade_flags(patch_id) >> PATCH_MODEL_SHIFT, dm)) {
        n = bumped_normal(patch_id, uv, n, dm);
    }
    return facing_normal(n, to_eye, front);
}

// |n·v| of the shading normal beyond which a wedge of a two-sided model
// takes the side the normal faces: away from silhouettes that side is
// plain (and quads, lit by their winding, show it).
const float WEDGE_PLAIN_COS = 0.3;

// Which side a wedge fragment is lit from: a one-sided model (closed, seen
// from outside) shows its outside; a two-sided one the side its shading
// normal faces where that is plain (WEDGE_PLAIN_COS), else, near a
// silhouette, the side the surface around the wedge's edge shows
// (`wedge_side`, the draws' wedge_code).
bool wedge_front(uint patch_id, vec2 uv, vec3 to_eye, uint wedge_side) {
    if ((shade_flags(patch_id) & PATCH_TWO_SIDED) == 0u) {
        return true;
    }
    float c = dot(shading_normal(patch_id, uv, to_eye, true), to_eye);
    return abs(c) >= WEDGE_PLAIN_COS ? c >= 0.0 : wedge_side == WEDGE_LIT_FRONT;
}

// Lambert term for the push-constant light; a zero light_dir means "light
// from the eye" so a caller that forgets it still gets a readable image.
float diffuse(vec3 n, vec3 to_eye) {
    vec3 l = pc.light_dir.xyz;
    l = dot(l, l) > 0.0 ? normalize(l) : to_eye;
    return max(dot(n, l), 0.0);
}

// A cell's depths as the draws hand them to shade(): the depth along u in
// the low 4 bits, along v in the next 4 (a QuadNode split 1:2 has two);
// draws whose cells are square pass one depth for both.
uint same_depths(uint depth) {
    return min(depth, 15u) | (min(depth, 15u) << 4);
}

uvec2 cell_depths(uint code) {
    return uvec2(code & 0xfu, (code >> 4) & 0xfu);
}

vec3 depth_color(uint depth) {
    return rgb_of(DEPTH_RAMP[min(depth, 10u)]);
}

// 1 on the outline of the cell the fragment lies in, fading to 0 a pixel
// away: cells are the patch's parameter grid at 2^du by 2^dv, which is
// exactly a QuadNode's domain (and a ground-truth grid cell at depth
// log2(grid) both ways).
float cell_outline(vec2 uv, uvec2 depths) {
    vec2 c = uv * vec2(float(1u << depths.x), float(1u << depths.y));
    vec2 to_line = min(fract(c), 1.0 - fract(c)) / max(fwidth(c), vec2(1e-6));
    return 1.0 - clamp(min(to_line.x, to_line.y) - 0.25, 0.0, 1.0);
}

// Three bytes of `code` (24 bits) as an exact UNORM8 colour.
vec4 code_color(uint code) {
    return vec4(float(code >> 16) / 255.0, float((code >> 8) & 255u) / 255.0, float(code & 255u) / 255.0, 1.0);
}

// `depth_code`: the cell's depths (cell_depths); the depth heat map shows
// the deeper. `wedge_side`: WEDGE_NONE, or the side a wedge is lit from.
// `front`: the rasterizer's facing (the triangle's winding).
//
// Which side of the surface a fragment is lit from: its triangle's
// winding, except on a wedge. Where the fine polyline dips below the
// coarse chord a wedge folds over and faces the other way than its
// neighbours, so its own winding says little (wedge_front).
// Rules that looked at the wedge alone each lit single wrong pixels:
// turning it towards the eye lit wedge pixels on dark silhouettes (the
// torus's inner rim, catmark_lefthanded), the side its shading normal
// faces lit the two-sided torus's rim, the geometry patch's normal
// darkened wedges of open cages under MSAA (tests/shading_wedges.rs,
// tests/shading_msaa.rs; issue 21).
vec4 shade(vec3 world, vec2 uv, uint patch_id, uint depth_code, uint wedge_side, bool front) {
    // Texture coordinates and their screen derivatives first, while every
    // invocation of the quad is here (derivatives need uniform control
    // flow); a scene without maps or UVs compiles this away.
    vec2 st = shade_surface_uv(patch_id, uv);
    vec2 st_dx = dFdx(st);
    vec2 st_dy = dFdy(st);
    bool wedge = wedge_side != WEDGE_NONE;
    uvec2 depths = cell_depths(depth_code);
    uint depth = max(depths.x, depths.y);
    if (pc.shade == SHADE_FACING) {
        return vec4(front ? KEY_FRONT : KEY_BACK, 1.0);
    }
    if (pc.shade == SHADE_PATCH_ID) {
        return code_color(patch_id & 0xffffffu);
    }
    if (pc.shade == SHADE_TINT) {
        return vec4(model_tint(shade_flags(patch_id) >> PATCH_MODEL_SHIFT), 1.0);
    }
    if (pc.shade == SHADE_UV) {
        vec2 f = fract(st);
        ivec2 cell = ivec2(floor(st * 8.0));
        return vec4(f, ((cell.x + cell.y) & 1) == 0 ? 0.85 : 0.25, 1.0);
    }
    if (pc.shade == SHADE_TEXTURE) {
        return vec4(surface_albedo(patch_id, st, st_dx, st_dy), 1.0);
    }
    if (pc.shade == SHADE_DISPLACEMENT) {
        // The height at the fragment's own texture coordinates (a seam's
        // owner evaluates the vertices there; the colour is the fragment's).
        DispModel dm;
        if (displaced_model(shade_flags(patch_id) >> PATCH_MODEL_SHIFT, dm)) {
            float h = clamp(height_at(dm, st.x, st.y), 0.0, 1.0);
            return vec4(mix(DISPLACEMENT_LOW, DISPLACEMENT_HIGH, h), 1.0);
        }
        return vec4(UNDISPLACED_GREY, 1.0);
    }
    if (pc.shade == SHADE_PARAMS) {
        uvec2 q = uvec2(clamp(uv, 0.0, 1.0) * 4095.0 + 0.5);
        return code_color((q.x << 12) | q.y);
    }
    vec3 to_eye = view.eye.xyz - world;
    if (pc.shade == SHADE_DISTANCE) {
        float d = clamp(length(to_eye) / pc.light_dir.w, 0.0, 1.0);
        return code_color(uint(d * 16777214.0));
    }
    to_eye = dot(to_eye, to_eye) > 0.0 ? normalize(to_eye) : vec3(0.0, 0.0, 1.0);
    if (pc.shade == SHADE_KEY) {
        // Which side of the SURFACE is seen, from the base patch's normal,
        // not the triangle's winding: where the curvature is high a wedge or
        // even a quad triangle can fold over and show its back from outside
        // without any hole. Through a crack one sees the background or the
        // far side of the model, whose normals face away.
        float c = dot(surface_normal(patch_id, uv, to_eye), to_eye);
        bool facing = c >= 0.0;
        if (!facing) {
            return vec4(KEY_BACK, 1.0);
        }
        return vec4(abs(c) < GRAZING_COS ? KEY_GRAZING : KEY_FRONT, 1.0);
    }
    vec3 n = shading_normal(patch_id, uv, to_eye, wedge ? wedge_front(patch_id, uv, to_eye, wedge_side) : front);
    float d = diffuse(n, to_eye);
    if (pc.shade == SHADE_DEPTH) {
        return vec4(depth_color(depth) * (0.55 + 0.45 * d), 1.0);
    }
    if (pc.shade == SHADE_NORMALS) {
        return vec4(n * 0.5 + 0.5, 1.0);
    }
    if (pc.shade == SHADE_WIREFRAME) {
        vec3 base = wedge ? WEDGE_COLOR * 0.8 : vec3(0.75) * (0.3 + 0.7 * d);
        return vec4(mix(base, vec3(0.05, 0.05, 0.08), cell_outline(uv, depths)), 1.0);
    }
    if (pc.shade == SHADE_WEDGES) {
        vec3 c = wedge ? WEDGE_COLOR * (0.75 + 0.25 * d) : depth_color(depth) * (0.25 + 0.2 * d);
        return vec4(c, 1.0);
    }
    // SHADE_NORMAL: Lambert + ambient + a little Blinn-Phong.
    vec3 base = surface_albedo(patch_id, st, st_dx, st_dy);
    vec3 l = pc.light_dir.xyz;
    l = dot(l, l) > 0.0 ? normalize(l) : to_eye;
    vec3 h = l + to_eye;
    h = dot(h, h) > 0.0 ? normalize(h) : n;
    float s = d > 0.0 ? pow(max(dot(n, h), 0.0), 48.0) : 0.0;
    return vec4(base * (0.16 + 0.84 * d) + vec3(0.22 * s), 1.0);
}

#endif
