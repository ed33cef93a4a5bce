//! Displacement (issue 40): a scalar height map moves the surface along its
//! unit normal, `S(u, v) = P(u, v) + n̂(u, v)·(bias + scale·h(s, t))`, with
//! (s, t) the UV patch's texture coordinates. Everything here has a twin in
//! `glsl/common/displace.glsl` doing the same IEEE operations in the same
//! order, because a displaced vertex is a position: the oracle and every
//! GPU must agree on it bit for bit, and so must the two patches sharing it.
//!
//! - **Heights** are read by texel fetches and a bilinear blend written out
//!   here ([`HeightMap::sample`]); a sampler's filtering is the driver's
//!   own arithmetic and differs between devices.
//! - **The unit normal** needs a square root, which Vulkan does not round
//!   correctly (nor a division), so [`unit_normal`] scales `Su × Sv` by a
//!   reciprocal square root made of a bit-pattern first guess and a fixed
//!   number of Newton steps, only multiplications and subtractions: the
//!   same bits wherever IEEE f32 arithmetic is.
//! - **The bound** the criterion uses ([`HeightMap::range`]): the heights a
//!   bilinear lookup can return anywhere in a UV box, from a min/max
//!   pyramid, so a node whose texture region is flat costs nothing extra.
//!   The box of a node's texture coordinates ([`uv_box`]) is its corners'
//!   box grown by the bilinear interpolation error bound of the UV patch
//!   (`h²/8 · max|∂²|` per direction), which holds for any UV patch.

use glam::Vec3;

use super::bezier::{curve, BezierPatch};
use super::ops::{cross3, dot3};
use super::quadnode::QuadNode;

/// The first guess of [`rsqrt`] (`RSQRT_MAGIC`) puts `1/√x` within 3.5 %
/// for every normal f32 `x`; each Newton step (`RSQRT_STEPS` of them)
/// squares the relative error (3.5e-2, 1.8e-3, 5e-6, 4e-11): four reach
/// f32's own rounding.
pub use crate::constants::{RSQRT_MAGIC, RSQRT_STEPS};
/// Texture coordinates are clamped to ±2^16 before lookups, so their
/// texel indices (at most 8192 a side) fit an int on every device.
pub const UV_LIMIT: f32 = (1u32 << crate::constants::UV_LIMIT_LOG2) as f32;

/// `1/√x` for a positive, normal `x`, to within a few ulp, by the same
/// operations on every device (see the module notes).
#[inline]
pub fn rsqrt(x: f32) -> f32 {
    let mut y = f32::from_bits(RSQRT_MAGIC.wrapping_sub(x.to_bits() >> 1));
    let half = 0.5 * x;
    for _ in 0..RSQRT_STEPS {
        y = y * (1.5 - half * (y * y));
    }
    y
}

/// The unit normal of `p` at (u, v): `Su × Sv` scaled by [`rsqrt`] of its
/// squared length. Where the cross product vanishes (a boundary collapsed
/// to a point, like the teapot's poles) it is taken a 256th of the way
/// towards the domain's centre, as the shading normal is.
pub fn unit_normal(p: &BezierPatch, u: f32, v: f32) -> Vec3 {
    let (mut u, mut v) = (u, v);
    let mut n = Vec3::ZERO;
    for _ in 0..2 {
        let (su, sv) = p.partials(u, v);
        n = cross3(su, sv);
        if dot3(n, n) > 0.0 {
            break;
        }
        u = u + (0.5 - u) * (1.0 / 256.0);
        v = v + (0.5 - v) * (1.0 / 256.0);
    }
    let n2 = dot3(n, n);
    if n2 > 0.0 {
        n * rsqrt(n2)
    } else {
        Vec3::ZERO
    }
}

/// A pyramid cell: least and greatest height, x difference and y
/// difference over the texels it covers (`[h_lo, h_hi, dx_lo, dx_hi,
/// dy_lo, dy_hi]`).
pub type Cell = [f32; 6];

/// The cell holding both `a` and `b`.
#[inline]
fn merge(a: Cell, b: Cell) -> Cell {
    [
        minf(a[0], b[0]),
        maxf(a[1], b[1]),
        minf(a[2], b[2]),
        maxf(a[3], b[3]),
        minf(a[4], b[4]),
        maxf(a[5], b[5]),
    ]
}

/// The cell holding nothing.
const EMPTY: Cell = [
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::INFINITY,
    f32::NEG_INFINITY,
];

/// One displaced model's settings: its height map (an index into the
/// scene's maps), scale and bias.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModelDisplacement {
    /// Index into the scene's height maps.
    pub map: usize,
    /// World units per unit of height.
    pub scale: f32,
    /// World units added to every height's displacement.
    pub bias: f32,
}

impl ModelDisplacement {
    /// Displacement of height `h`: `bias + scale·h`.
    #[inline]
    pub fn at(&self, h: f32) -> f32 {
        self.bias + self.scale * h
    }

    /// The world-space reach of a height variation: how far the displaced
    /// surface may stray from what its corners span.
    #[inline]
    pub fn reach(&self, variation: f32) -> f32 {
        variation * self.scale.abs()
    }

    /// The largest |displacement| any height gives (heights lie in [0, 1]),
    /// a little enlarged: what a node's box grows by.
    pub fn margin(&self) -> f32 {
        let m = self.bias.abs().max((self.bias + self.scale).abs());
        m * (1.0 + 1.0 / 1024.0)
    }
}

/// What the oracle needs of a displaced scene (`scene::displaced` has the
/// scene's): its world patches, which of them are displaced and how, the
/// bounds of the criterion and the offsets of drawn points.
pub trait Displacer: Sync {
    /// The world-space base patches, their weights (empty: all 1) and flags.
    fn patches(&self) -> (&[BezierPatch], &[super::rational::Weights], &[u32]);
    /// Base patch `g`'s displacement, if its model is displaced.
    fn model_of(&self, g: usize) -> Option<&ModelDisplacement>;
    /// How far the displacement along edge `e` of `node` of base patch `g`
    /// can stray from its ends' blend (world units), the same bits from
    /// both sides of a shared edge.
    fn edge_reach(&self, g: usize, m: &ModelDisplacement, node: QuadNode, e: usize) -> f32;
    /// How far the displacement over `node` can stray (world units).
    fn inner_reach(&self, g: usize, m: &ModelDisplacement, node: QuadNode) -> f32;
    /// The offset `n̂·d` of base patch `g`'s point (u, v).
    fn offset(&self, g: usize, m: &ModelDisplacement, u: f32, v: f32) -> Vec3;
}

/// A height map: heights in [0, 1], rows from t = 0 (the image's bottom)
/// up, repeating in both directions; its sides are powers of two so that
/// every level of the min/max pyramid wraps exactly.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Texels per row (a power of two).
    pub width: u32,
    /// Rows (a power of two).
    pub height: u32,
    /// `width × height` heights, row after row from t = 0.
    pub heights: Vec<f32>,
    /// The min/max pyramid, finest first: level 0 has a cell per texel
    /// holding, for the 2×2 texels a bilinear lookup in that cell blends,
    /// the least and greatest height, difference along x and difference
    /// along y ([`Cell`]); each next level halves each side (down to 1)
    /// and keeps the extremes of the cells it covers.
    pub pyramid: Vec<Vec<Cell>>,
}

impl HeightMap {
    /// A map of `width × height` heights (sides powers of two, rows from
    /// t = 0) and its pyramid.
    pub fn new(width: u32, height: u32, heights: Vec<f32>) -> Self {
        assert!(width.is_power_of_two() && height.is_power_of_two());
        assert_eq!(heights.len(), (width * height) as usize);
        let mut map = HeightMap {
            width,
            height,
            heights,
            pyramid: Vec::new(),
        };
        let mut level = Vec::with_capacity(map.heights.len());
        for y in 0..height as i32 {
            for x in 0..width as i32 {
                let h = [
                    map.texel(x, y),
                    map.texel(x + 1, y),
                    map.texel(x, y + 1),
                    map.texel(x + 1, y + 1),
                ];
                let (dx0, dx1) = (h[1] - h[0], h[3] - h[2]);
                let (dy0, dy1) = (h[2] - h[0], h[3] - h[1]);
                level.push([
                    min4(h),
                    max4(h),
                    minf(dx0, dx1),
                    maxf(dx0, dx1),
                    minf(dy0, dy1),
                    maxf(dy0, dy1),
                ]);
            }
        }
        map.pyramid.push(level);
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let prev = map.pyramid.last().expect("level 0");
            let mut next = Vec::with_capacity((nw * nh) as usize);
            for y in 0..nh {
                for x in 0..nw {
                    let mut cell = EMPTY;
                    for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                        let (px, py) = ((2 * x + dx).min(w - 1), (2 * y + dy).min(h - 1));
                        cell = merge(cell, prev[(py * w + px) as usize]);
                    }
                    next.push(cell);
                }
            }
            map.pyramid.push(next);
            (w, h) = (nw, nh);
        }
        map
    }

    /// Texel (x, y), wrapped.
    #[inline]
    pub fn texel(&self, x: i32, y: i32) -> f32 {
        let x = (x & (self.width as i32 - 1)) as u32;
        let y = (y & (self.height as i32 - 1)) as u32;
        self.heights[(y * self.width + x) as usize]
    }

    /// The texel-space coordinate of texture coordinate `s` along a side of
    /// `n` texels, whose floor is the first of the two texels a bilinear
    /// lookup blends.
    #[inline]
    fn texel_coord(s: f32, n: u32) -> f32 {
        let s = clampf(s, -UV_LIMIT, UV_LIMIT);
        s * n as f32 - 0.5
    }

    /// The height at (s, t): the bilinear blend of the four texels around
    /// it, written out (twin of `height_at` in displace.glsl).
    pub fn sample(&self, s: f32, t: f32) -> f32 {
        let x = Self::texel_coord(s, self.width);
        let y = Self::texel_coord(t, self.height);
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i32, y0 as i32);
        let a = self.texel(i, j) * (1.0 - fx) + self.texel(i + 1, j) * fx;
        let b = self.texel(i, j + 1) * (1.0 - fx) + self.texel(i + 1, j + 1) * fx;
        a * (1.0 - fy) + b * fy
    }

    /// How far the heights over a node can stray from the bilinear blend
    /// of its corners' heights, in height units, for a node whose texture
    /// coordinates' corners span the box `lo..hi` and stray from their own
    /// bilinear blend by at most `grow` (see [`uv_box`]); the least of the
    /// bounds below, from the pyramid cells covering the grown box ([`HeightMap::cells`];
    /// twin of `height_variation`):
    ///
    /// - the heights' range there;
    /// - a linear function, which the blend reproduces exactly, taken out:
    ///   with slopes halfway between the least and greatest texel
    ///   differences there, what is left has slopes within half their
    ///   spreads, so it strays from the blend by at most that times half
    ///   the corners' extent plus the UVs' stray (a blend's weighted
    ///   distance from the points it blends is at most half their extent);
    ///   plus the linear part's slope times the UVs' own stray. A ramp
    ///   costs nothing, a smooth bump in proportion to its curvature times
    ///   the node's size squared;
    /// - a box within one bilinear cell: there the height is `h00 + a·x +
    ///   b·y + c·x·y` (x, y in texels), whose blend reproduces all but the
    ///   twist: |c|·wx·wy/2 over the corners' extents, plus the gradient
    ///   times the UVs' stray.
    pub fn variation(&self, lo: [f32; 2], hi: [f32; 2], grow: f32) -> f32 {
        let glo = [lo[0] - grow, lo[1] - grow];
        let ghi = [hi[0] + grow, hi[1] + grow];
        let (c, one_cell) = self.cells(glo, ghi);
        let (w, h) = (self.width as f32, self.height as f32);
        let (gx, sx) = ((c[2] + c[3]) * 0.5, (c[3] - c[2]) * 0.5);
        let (gy, sy) = ((c[4] + c[5]) * 0.5, (c[5] - c[4]) * 0.5);
        let (wx, wy) = ((hi[0] - lo[0]) * w, (hi[1] - lo[1]) * h);
        let (grow_x, grow_y) = (grow * w, grow * h);
        // A drawn point's texture coordinates are its corners' blend, so
        // their weighted distance from the corners' is at most half the
        // corners' extent (each axis), the surface's a stray further.
        let reach_x = wx * 0.5 + grow_x;
        let reach_y = wy * 0.5 + grow_y;
        let detrended = (sx * reach_x + sy * reach_y) + (gx.abs() * grow_x + gy.abs() * grow_y);
        let mut bound = minf(c[1] - c[0], detrended);
        if one_cell {
            // In one cell the x differences are a (bottom) and a + c (top).
            let a = maxf(c[2].abs(), c[3].abs());
            let b = maxf(c[4].abs(), c[5].abs());
            let twist = c[3] - c[2];
            let bilinear = ((twist * wx) * wy * 0.5) + (a * grow_x + b * grow_y);
            bound = minf(bound, bilinear);
        }
        bound * (1.0 + 1.0 / 1024.0)
    }

    /// The least and greatest height [`HeightMap::sample`] can return in
    /// the UV box lo..hi.
    pub fn range(&self, lo: [f32; 2], hi: [f32; 2]) -> [f32; 2] {
        let (c, _) = self.cells(lo, hi);
        [c[0], c[1]]
    }

    /// The pyramid cells covering the bilinear cells the UV box lo..hi
    /// touches, merged (at most 2×2 of them, on the finest level that
    /// needs no more), and whether that is one level-0 cell (twin of
    /// `height_cells`).
    pub fn cells(&self, lo: [f32; 2], hi: [f32; 2]) -> (Cell, bool) {
        let x0 = Self::texel_coord(lo[0], self.width).floor() as i32;
        let x1 = Self::texel_coord(hi[0], self.width).floor() as i32;
        let y0 = Self::texel_coord(lo[1], self.height).floor() as i32;
        let y1 = Self::texel_coord(hi[1], self.height).floor() as i32;
        let top = self.pyramid.len() - 1;
        let mut l = 0;
        while l < top && ((x1 >> l) - (x0 >> l) > 1 || (y1 >> l) - (y0 >> l) > 1) {
            l += 1;
        }
        let w = (self.width >> l).max(1) as i32;
        let h = (self.height >> l).max(1) as i32;
        let cells = &self.pyramid[l];
        let mut r = EMPTY;
        for y in [y0 >> l, y1 >> l] {
            for x in [x0 >> l, x1 >> l] {
                r = merge(r, cells[((y & (h - 1)) * w + (x & (w - 1))) as usize]);
            }
        }
        (r, x0 == x1 && y0 == y1)
    }
}

/// The second-derivative bounds (max |∂²/∂u²|, max |∂²/∂v²| over both
/// coordinates) of UV patch `p` over its whole domain: 6 × its control
/// net's largest second difference in each direction.
pub fn uv_curvature(p: &[[f32; 2]; 16]) -> [f32; 2] {
    let second = |a: [f32; 2], b: [f32; 2], c: [f32; 2]| {
        let d = |k: usize| (a[k] - 2.0 * b[k] + c[k]).abs();
        maxf(d(0), d(1))
    };
    let mut m = [0.0f32; 2];
    for j in 0..4 {
        for i in 0..4 {
            if i < 2 {
                let (a, b, c) = (p[4 * j + i], p[4 * j + i + 1], p[4 * j + i + 2]);
                m[0] = maxf(m[0], second(a, b, c));
            }
            if j < 2 {
                let (a, b, c) = (p[4 * j + i], p[4 * (j + 1) + i], p[4 * (j + 2) + i]);
                m[1] = maxf(m[1], second(a, b, c));
            }
        }
    }
    [6.0 * m[0], 6.0 * m[1]]
}

/// UV patch `p` at (u, v), in the patches' operation order.
pub fn uv_at(p: &[[f32; 2]; 16], u: f32, v: f32) -> [f32; 2] {
    let pt = |k: usize| glam::Vec2::from(p[k]);
    let rows: [glam::Vec2; 4] = std::array::from_fn(|j| {
        curve(u, &[pt(4 * j), pt(4 * j + 1), pt(4 * j + 2), pt(4 * j + 3)])
    });
    curve(v, &rows).to_array()
}

/// UV patch `p`'s texture coordinates over [a, b] × [c, d]: the box of
/// its corners' and how far the coordinates stray from the corners'
/// blend over the quad's two triangles: `(Δu²·Mu + Δv²·Mv)/8` (the
/// bilinear interpolation error bound, `m` from [`uv_curvature`]) plus a
/// quarter of the corners' twist; the corners' box grown by that holds them
/// all. With a = b (or c = d) it bounds a line of the domain, which is how
/// an edge's box is made (twin of `uv_box` in displace.glsl).
pub fn uv_box(
    p: &[[f32; 2]; 16],
    m: [f32; 2],
    [a, b, c, d]: [f32; 4],
) -> ([f32; 2], [f32; 2], f32) {
    let q = [
        uv_at(p, a, c),
        uv_at(p, b, c),
        uv_at(p, a, d),
        uv_at(p, b, d),
    ];
    let (du, dv) = (b - a, d - c);
    // The drawn quad is two triangles: their blend of the corners differs
    // from the bilinear one by at most a quarter of the corners' twist.
    let twist = |k: usize| ((q[0][k] - q[1][k]) - (q[2][k] - q[3][k])).abs();
    let split = maxf(twist(0), twist(1)) * 0.25;
    let grow = ((du * du) * m[0] + (dv * dv) * m[1]) * 0.125 + split;
    let lo = [min4(q.map(|x| x[0])), min4(q.map(|x| x[1]))];
    let hi = [max4(q.map(|x| x[0])), max4(q.map(|x| x[1]))];
    (lo, hi, grow)
}

#[inline]
fn minf(a: f32, b: f32) -> f32 {
    if b < a {
        b
    } else {
        a
    }
}

#[inline]
fn maxf(a: f32, b: f32) -> f32 {
    if b > a {
        b
    } else {
        a
    }
}

#[inline]
fn clampf(x: f32, lo: f32, hi: f32) -> f32 {
    minf(maxf(x, lo), hi)
}

#[inline]
fn min4(h: [f32; 4]) -> f32 {
    minf(minf(h[0], h[1]), minf(h[2], h[3]))
}

#[inline]
fn max4(h: [f32; 4]) -> f32 {
    maxf(maxf(h[0], h[1]), maxf(h[2], h[3]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rsqrt_is_within_a_few_ulp_over_the_whole_range() {
        let mut worst = 0.0f64;
        let mut x = 1e-30f32;
        while x < 1e30 {
            let r = rsqrt(x) as f64;
            let exact = 1.0 / (x as f64).sqrt();
            worst = worst.max(((r - exact) / exact).abs());
            x *= 1.013;
        }
        assert!(
            worst < 4.0 * f32::EPSILON as f64,
            "relative error {worst:e}"
        );
    }

    fn noise_map(w: u32, h: u32) -> HeightMap {
        let mut s = 12345u32;
        let heights = (0..w * h)
            .map(|_| {
                s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                (s >> 8) as f32 / (1u32 << 24) as f32
            })
            .collect();
        HeightMap::new(w, h, heights)
    }

    #[test]
    fn range_holds_every_sample_in_its_box() {
        let map = noise_map(16, 8);
        let mut s = 7u32;
        let mut rnd = || {
            s = s.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (s >> 8) as f32 / (1u32 << 24) as f32 * 3.0 - 1.0
        };
        for _ in 0..2000 {
            let (a, b, c, d) = (rnd(), rnd(), rnd(), rnd());
            let size = rnd().abs() * 0.3;
            let lo = [a.min(b), c.min(d)];
            let hi = [lo[0] + size * (b - a).abs(), lo[1] + size * (d - c).abs()];
            let r = map.range(lo, hi);
            for i in 0..=8 {
                for j in 0..=8 {
                    let st = [
                        lo[0] + (hi[0] - lo[0]) * i as f32 / 8.0,
                        lo[1] + (hi[1] - lo[1]) * j as f32 / 8.0,
                    ];
                    let h = map.sample(st[0], st[1]);
                    assert!(
                        r[0] <= h && h <= r[1],
                        "{h} outside {r:?} in {lo:?}..{hi:?}"
                    );
                }
            }
        }
        // A box wider than the map sees all of it.
        let all = map.range([-5.0, -5.0], [5.0, 5.0]);
        let (lo, hi) = map
            .heights
            .iter()
            .fold((1.0f32, 0.0f32), |(a, b), &h| (a.min(h), b.max(h)));
        assert_eq!(all, [lo, hi]);
    }

    #[test]
    fn a_constant_map_has_no_range_and_samples_its_constant() {
        let map = HeightMap::new(8, 8, vec![0.25; 64]);
        assert_eq!(map.range([0.1, 0.2], [0.9, 0.3]), [0.25, 0.25]);
        assert_eq!(map.sample(0.37, -4.2), 0.25);
    }

    #[test]
    fn sample_reproduces_texels_at_their_centres_and_wraps() {
        let map = noise_map(8, 4);
        for y in 0..4 {
            for x in 0..8 {
                let (s, t) = ((x as f32 + 0.5) / 8.0, (y as f32 + 0.5) / 4.0);
                assert_eq!(map.sample(s, t), map.texel(x, y));
                assert_eq!(map.sample(s + 1.0, t - 2.0), map.texel(x, y));
            }
        }
    }

    /// The variation bounds how far heights along a UV patch's node stray
    /// from the blend of the node's corner heights, in one cell and across
    /// many, and shrinks to nothing as nodes do inside a cell.
    #[test]
    fn variation_bounds_the_heights_against_the_corners_blend() {
        let map = noise_map(8, 8);
        let p: [[f32; 2]; 16] = std::array::from_fn(|k| {
            let (i, j) = ((k % 4) as f32, (k / 4) as f32);
            [
                0.1 + i / 7.0 + 0.02 * (j * i).sin(),
                0.2 + j / 9.0 + 0.03 * (i + 2.0 * j).cos(),
            ]
        });
        let m = uv_curvature(&p);
        let mut in_cell = Vec::new();
        for l in 0..8 {
            let n = 1u32 << l;
            for k in 0..n {
                let s = 1.0 / n as f32;
                let dom = [
                    k as f32 * s,
                    (k + 1) as f32 * s,
                    0.5 * k as f32 * s,
                    0.5 * k as f32 * s + s,
                ];
                let (lo, hi, grow) = uv_box(&p, m, dom);
                let bound = map.variation(lo, hi, grow);
                let corner = |u: f32, v: f32| {
                    let q = uv_at(&p, u, v);
                    map.sample(q[0], q[1])
                };
                let h = [
                    corner(dom[0], dom[2]),
                    corner(dom[1], dom[2]),
                    corner(dom[0], dom[3]),
                    corner(dom[1], dom[3]),
                ];
                for i in 0..=8 {
                    for j in 0..=8 {
                        let (x, y) = (i as f32 / 8.0, j as f32 / 8.0);
                        let u = dom[0] + (dom[1] - dom[0]) * x;
                        let v = dom[2] + (dom[3] - dom[2]) * y;
                        let blend = (h[0] * (1.0 - x) + h[1] * x) * (1.0 - y)
                            + (h[2] * (1.0 - x) + h[3] * x) * y;
                        let q = uv_at(&p, u, v);
                        let off = (map.sample(q[0], q[1]) - blend).abs();
                        assert!(off <= bound + 1e-6, "depth {l}: {off} beyond {bound}");
                    }
                }
                if l == 7 {
                    in_cell.push(bound);
                }
            }
        }
        let worst = in_cell.iter().cloned().fold(0.0, f32::max);
        assert!(worst < 0.05, "small nodes vary by {worst}");
    }

    #[test]
    fn uv_box_holds_the_patch_over_its_domain() {
        let p: [[f32; 2]; 16] = std::array::from_fn(|k| {
            let (i, j) = ((k % 4) as f32, (k / 4) as f32);
            [
                i / 3.0 + 0.2 * (j * i).sin(),
                j / 3.0 + 0.3 * (i + 2.0 * j).cos(),
            ]
        });
        let m = uv_curvature(&p);
        for dom in [
            [0.0, 1.0, 0.0, 1.0],
            [0.25, 0.5, 0.5, 0.75],
            [0.5, 0.5, 0.0, 0.125],
        ] {
            let (lo, hi, grow) = uv_box(&p, m, dom);
            let lo = lo.map(|x| x - grow);
            let hi = hi.map(|x| x + grow);
            for i in 0..=16 {
                for j in 0..=16 {
                    let u = dom[0] + (dom[1] - dom[0]) * i as f32 / 16.0;
                    let v = dom[2] + (dom[3] - dom[2]) * j as f32 / 16.0;
                    let q = uv_at(&p, u, v);
                    for k in 0..2 {
                        assert!(
                            lo[k] <= q[k] && q[k] <= hi[k],
                            "{q:?} outside {lo:?}..{hi:?}"
                        );
                    }
                }
            }
        }
    }
}
