//! Which pixel centres a triangle covers, exactly as a rasterizer decides
//! it: clipping at the near plane and a guard band, vertices snapped to a
//! subpixel grid, edge functions in integers with the top-left rule, and
//! perspective-correct attributes. Below `raster` (the preview and the
//! hole test's coverage) and the tests that need to know where a surface
//! lies on screen.

use glam::{DMat4, DVec2, DVec3, DVec4};

/// Fixed-point subpixel bits of the snapped vertex positions.
const SUB_BITS: u32 = 8;
const SUB: i64 = 1 << SUB_BITS;
/// Guard band in NDC units: triangles are clipped to |x|, |y| ≤ GUARD·w, which
/// bounds snapped coordinates (and edge-function products) well inside i64.
const GUARD: f64 = 8.0;

/// One vertex during clipping: clip position plus the attributes that are
/// interpolated perspective-correctly.
#[derive(Clone, Copy, Debug)]
pub(super) struct ClipVert {
    pub(super) pos: DVec4,
    pub(super) uv: DVec2,
    pub(super) world: DVec3,
}

impl ClipVert {
    fn lerp(self, o: ClipVert, t: f64) -> ClipVert {
        ClipVert {
            pos: self.pos + (o.pos - self.pos) * t,
            uv: self.uv + (o.uv - self.uv) * t,
            world: self.world + (o.world - self.world) * t,
        }
    }
}

/// A convex polygon of at most 8 vertices (a triangle clipped by 5 planes).
#[derive(Clone, Copy)]
struct Poly {
    v: [ClipVert; 8],
    n: usize,
}

impl Poly {
    fn push(&mut self, v: ClipVert) {
        self.v[self.n] = v;
        self.n += 1;
    }
}

/// The signed distances of the clip planes: near (z ≥ 0) and the guard band.
fn plane_distance(plane: usize, p: DVec4) -> f64 {
    match plane {
        0 => p.z,
        1 => GUARD * p.w - p.x,
        2 => GUARD * p.w + p.x,
        3 => GUARD * p.w - p.y,
        _ => GUARD * p.w + p.y,
    }
}

/// Sutherland–Hodgman against one plane. The intersection is always
/// computed from the inside vertex towards the outside one, so two triangles
/// sharing a clipped edge get the same new vertex.
fn clip_poly(src: &Poly, plane: usize) -> Poly {
    let mut out = Poly { v: src.v, n: 0 };
    for i in 0..src.n {
        let a = src.v[i];
        let b = src.v[(i + 1) % src.n];
        let (da, db) = (plane_distance(plane, a.pos), plane_distance(plane, b.pos));
        let (ia, ib) = (da >= 0.0, db >= 0.0);
        if ia {
            out.push(a);
        }
        if ia != ib {
            let (inside, outside, di, dout) = if ia { (a, b, da, db) } else { (b, a, db, da) };
            out.push(inside.lerp(outside, di / (di - dout)));
        }
    }
    out
}

/// A vertex after the perspective divide, snapped to the subpixel grid.
#[derive(Clone, Copy, Debug)]
struct ScreenVert {
    x: i64,
    y: i64,
    /// z_ndc.
    z: f64,
    /// 1 / w_clip.
    inv_w: f64,
    uv: DVec2,
    world: DVec3,
}

fn to_screen(v: &ClipVert, width: u32, height: u32) -> ScreenVert {
    let inv_w = 1.0 / v.pos.w;
    let sx = (v.pos.x * inv_w * 0.5 + 0.5) * width as f64;
    let sy = (v.pos.y * inv_w * 0.5 + 0.5) * height as f64;
    ScreenVert {
        x: (sx * SUB as f64).round() as i64,
        y: (sy * SUB as f64).round() as i64,
        z: v.pos.z * inv_w,
        inv_w,
        uv: v.uv,
        world: v.world,
    }
}

/// One covered pixel centre of a triangle.
#[derive(Clone, Copy, Debug)]
pub(super) struct Fragment {
    pub(super) x: u32,
    pub(super) y: u32,
    /// z_ndc (linear in screen space).
    pub(super) z: f64,
    /// Perspective-correct parameter coordinates.
    pub(super) uv: DVec2,
    /// Perspective-correct world position.
    pub(super) world: DVec3,
}

/// Calls `f(x, y, world)` for every pixel whose centre the world-space
/// triangle `v` covers under `view_proj` (either winding, clipped to the
/// view volume, top-left rule), with the perspective-correct world position
/// there. For tests that need to know where a surface lies on screen.
pub fn cover_triangle(
    v: [DVec3; 3],
    view_proj: &DMat4,
    width: u32,
    height: u32,
    mut f: impl FnMut(u32, u32, DVec3),
) {
    let clip = v.map(|p| ClipVert {
        pos: *view_proj * p.extend(1.0),
        uv: DVec2::ZERO,
        world: p,
    });
    rasterize(clip, width, height, |fr| f(fr.x, fr.y, fr.world));
}

/// Edge function of edge a→b at p, in subpixel² units: positive on the
/// interior side of a triangle with positive area.
fn edge(a: &ScreenVert, b: &ScreenVert, px: i64, py: i64) -> i64 {
    (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x)
}

/// Top-left rule for the edge a→b of a positive-area triangle (screen y
/// down): a left edge runs upwards, a top edge is horizontal running right.
fn is_top_left(a: &ScreenVert, b: &ScreenVert) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    dy < 0 || (dy == 0 && dx > 0)
}

/// Calls `frag` for every pixel centre a clip-space triangle covers, after
/// near-plane and guard-band clipping. Either winding is drawn.
pub(super) fn rasterize(
    tri: [ClipVert; 3],
    width: u32,
    height: u32,
    mut frag: impl FnMut(Fragment),
) {
    // Finite input only: a NaN would survive every comparison below.
    if !tri.iter().all(|v| v.pos.is_finite()) {
        return;
    }
    let mut poly = Poly {
        v: [tri[0]; 8],
        n: 0,
    };
    for v in tri {
        poly.push(v);
    }
    let all_inside = tri
        .iter()
        .all(|v| (0..5).all(|p| plane_distance(p, v.pos) >= 0.0));
    if !all_inside {
        for plane in 0..5 {
            poly = clip_poly(&poly, plane);
            if poly.n < 3 {
                return;
            }
        }
    }
    // z ≥ 0 after clipping implies w ≥ near > 0 for a perspective projection;
    // the check guards against other matrices.
    if poly.v[..poly.n].iter().any(|v| v.pos.w <= 1e-12) {
        return;
    }
    let s: Vec<ScreenVert> = poly.v[..poly.n]
        .iter()
        .map(|v| to_screen(v, width, height))
        .collect();
    for k in 1..poly.n - 1 {
        raster_screen_triangle([s[0], s[k], s[k + 1]], width, height, &mut frag);
    }
}

fn raster_screen_triangle(
    mut t: [ScreenVert; 3],
    width: u32,
    height: u32,
    frag: &mut impl FnMut(Fragment),
) {
    let mut area = edge(&t[0], &t[1], t[2].x, t[2].y);
    if area == 0 {
        return;
    }
    if area < 0 {
        t.swap(1, 2);
        area = -area;
    }
    // Pixel range whose centres (i + 1/2) can lie inside the bounding box.
    let (half, last_x, last_y) = (SUB / 2, width as i64 - 1, height as i64 - 1);
    let lo = |c: i64| (c - half).div_euclid(SUB) + ((c - half).rem_euclid(SUB) != 0) as i64;
    let hi = |c: i64| (c - half).div_euclid(SUB);
    let x0 = lo(t.iter().map(|v| v.x).min().unwrap()).max(0);
    let x1 = hi(t.iter().map(|v| v.x).max().unwrap()).min(last_x);
    let y0 = lo(t.iter().map(|v| v.y).min().unwrap()).max(0);
    let y1 = hi(t.iter().map(|v| v.y).max().unwrap()).min(last_y);
    if x0 > x1 || y0 > y1 {
        return;
    }
    // Edge k is opposite vertex k; its bias makes "on the edge" count only
    // for top and left edges.
    let edges = [(1, 2), (2, 0), (0, 1)];
    let bias = edges.map(|(a, b)| if is_top_left(&t[a], &t[b]) { 0 } else { -1 });
    let inv_area = 1.0 / area as f64;
    for py in y0..=y1 {
        let cy = py * SUB + half;
        for px in x0..=x1 {
            let cx = px * SUB + half;
            let w = edges.map(|(a, b)| edge(&t[a], &t[b], cx, cy));
            if (0..3).any(|k| w[k] + bias[k] < 0) {
                continue;
            }
            let b = w.map(|x| x as f64 * inv_area);
            let z = b[0] * t[0].z + b[1] * t[1].z + b[2] * t[2].z;
            let q = [0, 1, 2].map(|k| b[k] * t[k].inv_w);
            let inv_sum = 1.0 / (q[0] + q[1] + q[2]);
            let uv = (t[0].uv * q[0] + t[1].uv * q[1] + t[2].uv * q[2]) * inv_sum;
            let world = (t[0].world * q[0] + t[1].world * q[1] + t[2].world * q[2]) * inv_sum;
            frag(Fragment {
                x: px as u32,
                y: py as u32,
                z,
                uv,
                world,
            });
        }
    }
}
