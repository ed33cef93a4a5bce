// Occlusion against the depth pyramid (set 2's BIND_LEVEL_HIZ of the level
// kernels), built by hiz_init*.comp and hiz_reduce.comp from the depth the
// early phase drew: level 0 holds every pixel's farthest sample, level k + 1
// the farthest of 2 x 2 texels of level k. A box is occluded when its nearest
// point lies farther than everything drawn in the pixels it could cover
// (those of the viewport: nothing is drawn beyond it): whatever it holds
// would fail the depth test there. Conservative in every step: a corner at
// or behind the near plane keeps the box, its pixel rectangle is widened by
// one pixel on every side, and a near tie keeps it. Include after
// scene.glsl (the view).
#ifndef HIZ_GLSL
#define HIZ_GLSL

// The pyramid's binding: the level kernels' unless the includer names
// another (the levels of detail's cull, glsl/lod/cull.comp).
#ifndef HIZ_SET
#define HIZ_SET SET_PRODUCER
#define HIZ_BINDING BIND_LEVEL_HIZ
#endif

layout(std430, set = HIZ_SET, binding = HIZ_BINDING) readonly buffer Hiz {
    float hiz[];
};

// Depth margin: what the projection's rounding and the rasterizer's depth
// interpolation may take from a fragment's depth (about 2^-20).
const float HIZ_MARGIN = 9.5367431640625e-7;

// Texels a side a box's rectangle may span at the level it is tested at:
// a node's test reads at most 4 x 4 (instead of the usual 2 x 2), an
// instance's 16 x 16 (few tests, each deciding a whole model), so a texel
// reaching far beyond the box (past an occluder's silhouette onto the
// empty background) keeps fewer hidden boxes.
const uint HIZ_NODE_SPAN = 4u;
const uint HIZ_INSTANCE_SPAN = 16u;

// Level k's first float and size, the levels stored one after the other
// (src/draw/hiz.rs pyramid_levels).
uint hiz_level(uint k, out uvec2 size) {
    uint w = view.width;
    uint h = view.height;
    uint offset = 0u;
    for (uint i = 0u; i < k; ++i) {
        offset += w * h;
        w = (w + 1u) / 2u;
        h = (h + 1u) / 2u;
    }
    size = uvec2(w, h);
    return offset;
}

// Whether everything in the box lo..hi lies behind the pyramid's depth,
// tested at the finest level where its rectangle spans at most `span`
// texels a side.
bool box_occluded(vec3 lo, vec3 hi, uint span) {
    float zmin = 1.0;
    vec2 smin = vec2(1.0);
    vec2 smax = vec2(-1.0);
    for (uint c = 0u; c < 8u; ++c) {
        vec3 p = vec3((c & 1u) != 0u ? hi.x : lo.x, (c & 2u) != 0u ? hi.y : lo.y,
            (c & 4u) != 0u ? hi.z : lo.z);
        float w = affine_row(view.clip[3], p);
        float z = affine_row(view.clip[2], p);
        if (!(w > 0.0) || !(z >= 0.0)) {
            return false;  // reaches the near plane or behind the eye
        }
        vec2 ndc = vec2(affine_row(view.clip[0], p), affine_row(view.clip[1], p)) / w;
        zmin = min(zmin, z / w);
        smin = min(smin, ndc);
        smax = max(smax, ndc);
    }
    vec2 size = vec2(float(view.width), float(view.height));
    // Pixels whose area the projection may touch, one more on every side,
    // within the viewport.
    vec2 a = floor((smin * 0.5 + 0.5) * size) - 1.0;
    vec2 b = floor((smax * 0.5 + 0.5) * size) + 1.0;
    if (b.x < 0.0 || b.y < 0.0 || a.x >= size.x || a.y >= size.y) {
        return false;  // off the viewport: the frustum test's business
    }
    uvec2 p0 = uvec2(max(a, vec2(0.0)));
    uvec2 p1 = uvec2(min(b, size - 1.0));
    // The finest level at which the rectangle spans at most `span` texels
    // a side; the farthest depth of those texels.
    uint k = 0u;
    while ((p1.x >> k) - (p0.x >> k) >= span || (p1.y >> k) - (p0.y >> k) >= span) {
        ++k;
    }
    uvec2 level;
    uint offset = hiz_level(k, level);
    uvec2 q0 = p0 >> k;
    uvec2 q1 = min(p1 >> k, level - 1u);
    float zmax = 0.0;
    for (uint y = q0.y; y <= q1.y; ++y) {
        for (uint x = q0.x; x <= q1.x; ++x) {
            zmax = max(zmax, hiz[offset + y * level.x + x]);
        }
    }
    return zmin > zmax + HIZ_MARGIN;
}

#endif
