//! A small CPU z-buffer rasterizer for the oracle's triangles: a way to look
//! at what the oracle produced without a GPU, and later a reference to
//! compare GPU images with.
//!
//! Vertices go through the Vulkan-convention `view_proj` (clip space y down,
//! depth in [0, 1]), are clipped in homogeneous space against the near plane
//! (z ≥ 0) and a guard band (|x|, |y| ≤ 8w), then snapped to a fixed-point
//! grid of 1/256 pixel. Coverage uses exact integer edge functions at pixel
//! centres with a top-left fill rule, so two triangles sharing an edge cover
//! each pixel centre on it exactly once. Depth test: LESS on z_ndc, buffer
//! cleared to 1. Single-threaded and deterministic.

use std::fmt;
use std::path::Path;
use std::str::FromStr;

use glam::{DMat4, DVec2, DVec3, Vec3};

pub use super::coverage::cover_triangle;
use super::coverage::{rasterize, ClipVert, Fragment};
use crate::constants::{PATCH_MODEL_SHIFT, PATCH_TWO_SIDED};
use crate::patch::bezier::BezierPatch;
use crate::patch::oracle::Triangle;
use crate::patch::shading::ShadingPatch;

/// What the preview colours encode.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PreviewShade {
    /// Lambert + ambient with the base patch's true normal at each pixel's
    /// (u, v), tinted per model. Two-sided patches are lit from the side the
    /// viewer sees; a one-sided patch seen clearly from behind is tinted dark
    /// red (it should have been hidden or culled: it shows orientation
    /// mistakes).
    #[default]
    Normal,
    /// As `Normal`, lit with the shading normals of the tangent patches
    /// (`patch::shading`) instead: what a renderer shading with them shows.
    Smooth,
    /// Heat map of the QuadNode depth, 0 (dark blue) … 10 (dark red), flat per
    /// triangle with a little face shading to keep shapes readable.
    Depth,
    /// The depth map darkened, with crack-closing wedge triangles in magenta.
    Wedges,
}

impl PreviewShade {
    /// Every mode with its command-line name.
    pub const ALL: [(PreviewShade, &'static str); 4] = [
        (PreviewShade::Normal, "normal"),
        (PreviewShade::Smooth, "smooth"),
        (PreviewShade::Depth, "depth"),
        (PreviewShade::Wedges, "wedges"),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(s, _)| *s == self)
            .map_or("?", |x| x.1)
    }
}

impl fmt::Display for PreviewShade {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PreviewShade {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Self::ALL
            .iter()
            .find(|(_, n)| n.eq_ignore_ascii_case(s.trim()))
            .map(|x| x.0)
            .ok_or_else(|| {
                format!("unknown preview shade '{s}': expected normal, smooth, depth or wedges")
            })
    }
}

/// The colour of QuadNode depth `l` in the depth ramp (clamped to 10): the
/// GPU's heat map colours (`palette::depth_color`).
pub fn depth_color(l: u32) -> [u8; 3] {
    crate::palette::depth_color(l)
}

const WEDGE_COLOR: [u8; 3] = [255, 0, 255];
/// A one-sided surface seen clearly from behind (it should be hidden or
/// culled): dark red.
const BACK_FACE_TINT: [f32; 3] = [0.45, 0.05, 0.05];

/// A colour image with a depth buffer.
#[derive(Clone, Debug)]
pub struct Raster {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA8 (sRGB) pixels, row-major from the top-left.
    pub color: Vec<[u8; 4]>,
    /// z_ndc of the nearest surface per pixel; 1 where nothing was drawn.
    pub depth: Vec<f32>,
}

fn scale_rgb(c: [u8; 3], k: f32) -> [u8; 4] {
    let f = |x: u8| (x as f32 * k).clamp(0.0, 255.0).round() as u8;
    [f(c[0]), f(c[1]), f(c[2]), 255]
}

impl Raster {
    /// A `width`×`height` image cleared to `background`, depth cleared to 1.
    pub fn new(width: u32, height: u32, background: [u8; 4]) -> Self {
        let n = width as usize * height as usize;
        Raster {
            width,
            height,
            color: vec![background; n],
            depth: vec![1.0; n],
        }
    }

    /// Draws the oracle's triangles. `patches` and `flags` are the scene's
    /// base patches and per-patch flags (indexed by `Triangle::node.patch`);
    /// `normals` their tangent patches, used by `PreviewShade::Smooth`
    /// (without them it shades as `Normal`); `eye` is the camera position,
    /// used for shading only; `light` the direction towards the light
    /// (the GPU's: `frame::headlight` of the camera).
    #[allow(clippy::too_many_arguments)]
    pub fn draw_triangles(
        &mut self,
        tris: &[Triangle],
        patches: &[BezierPatch],
        flags: &[u32],
        normals: Option<&[ShadingPatch]>,
        view_proj: &DMat4,
        (eye, light): (Vec3, Vec3),
        shade: PreviewShade,
    ) {
        let eye = eye.as_dvec3();
        let light = light.as_dvec3().normalize_or(DVec3::Z);
        let (w, h) = (self.width, self.height);
        for t in tris {
            let patch_id = t.node.patch() as usize;
            let clip = [0, 1, 2].map(|k| {
                let p = t.v[k].as_dvec3();
                ClipVert {
                    pos: *view_proj * p.extend(1.0),
                    uv: DVec2::new(t.uv[k].0 as f64, t.uv[k].1 as f64),
                    world: p,
                }
            });
            // Flat colour for the depth modes, with a little face shading.
            let flat = match shade {
                PreviewShade::Normal | PreviewShade::Smooth => [0; 4],
                PreviewShade::Depth | PreviewShade::Wedges => {
                    let base = if t.wedge && shade == PreviewShade::Wedges {
                        WEDGE_COLOR
                    } else {
                        depth_color(t.node.depth())
                    };
                    let k = face_light(t, eye);
                    let dim = if shade == PreviewShade::Wedges && !t.wedge {
                        0.4
                    } else {
                        1.0
                    };
                    scale_rgb(base, k * dim)
                }
            };
            let lit = matches!(shade, PreviewShade::Normal | PreviewShade::Smooth);
            let tangents = normals
                .filter(|_| shade == PreviewShade::Smooth)
                .map(|n| &n[patch_id]);
            let patch = lit.then(|| (&patches[patch_id], tangents, flags[patch_id]));
            let (color, depth) = (&mut self.color, &mut self.depth);
            rasterize(clip, w, h, |f| {
                let i = f.y as usize * w as usize + f.x as usize;
                let z = f.z as f32;
                // Depth test LESS (a NaN depth never passes).
                if z.partial_cmp(&depth[i]) != Some(std::cmp::Ordering::Less) {
                    return;
                }
                depth[i] = z;
                color[i] = match patch {
                    Some((base, tangents, flag)) => {
                        let (u, v) = (f.uv.x as f32, f.uv.y as f32);
                        let n = match tangents {
                            Some(t) => t.normal(u, v),
                            None => base.normal(u, v),
                        };
                        shade_normal(n.as_dvec3(), flag, &f, eye, light)
                    }
                    None => flat,
                };
            });
        }
    }

    /// Writes the image as PNG, whole or not at all (`draw::write_png`).
    pub fn save_png(&self, path: &Path) -> anyhow::Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(&self.color);
        crate::gpu::write_png(path, self.width, self.height, bytes)?;
        Ok(())
    }
}

/// Shading factor from the geometric face normal: 0.6 (edge-on) … 1 (facing).
fn face_light(t: &Triangle, eye: DVec3) -> f32 {
    let [a, b, c] = t.v.map(|p| p.as_dvec3());
    let n = (b - a).cross(c - a);
    let to_eye = eye - (a + b + c) / 3.0;
    let len = n.length() * to_eye.length();
    if len > 0.0 && len.is_finite() {
        (0.6 + 0.4 * (n.dot(to_eye) / len).abs()) as f32
    } else {
        1.0
    }
}

/// The GPU's `SHADE_NORMAL` (`glsl/common/shade.glsl`): the model's tint
/// (a display colour) times ambient plus Lambert towards the light, a
/// little Blinn-Phong; a clearly back-facing one-sided surface in the back
/// tint. (It once lit with a fixed world light and its own weights: the
/// kitchen's left wall bright where the GPU's image has it nearly black.)
fn shade_normal(n: DVec3, flags: u32, f: &Fragment, eye: DVec3, light: DVec3) -> [u8; 4] {
    let to_eye = (eye - f.world).normalize_or_zero();
    let mut n = n.normalize_or_zero();
    let mut tint = crate::palette::model_tint(flags >> PATCH_MODEL_SHIFT).map(f64::from);
    let facing = n.dot(to_eye);
    if facing < 0.0 {
        n = -n;
        // Slightly back-facing pixels occur at any silhouette of a coarse
        // tessellation; only a clearly back-facing one-sided surface is flagged.
        if flags & PATCH_TWO_SIDED == 0 && facing < -0.25 {
            tint = BACK_FACE_TINT.map(|c| f64::from(c).powf(1.0 / 2.2));
        }
    }
    let d = n.dot(light).max(0.0);
    let h = (light + to_eye).normalize_or(n);
    let s = if d > 0.0 {
        n.dot(h).max(0.0).powf(48.0)
    } else {
        0.0
    };
    let c =
        tint.map(|t| ((t * (0.16 + 0.84 * d) + 0.22 * s).clamp(0.0, 1.0) * 255.0).round() as u8);
    [c[0], c[1], c[2], 255]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patch::quadnode::QuadNode;
    use glam::DVec4;

    /// The preview shows each model in the tint every image gives it, lit
    /// as the GPU lights it: facing the light and the eye, the palette's
    /// colour plus the highlight; unlit, the ambient part alone.
    #[test]
    fn preview_lights_the_palette_as_the_gpu_does() {
        let f = Fragment {
            x: 0,
            y: 0,
            z: 0.5,
            uv: DVec2::ZERO,
            world: DVec3::ZERO,
        };
        let (n, eye) = (DVec3::Z, DVec3::new(0.0, 0.0, 5.0));
        for model in 0..40 {
            let flags = model << PATCH_MODEL_SHIFT;
            let want = crate::palette::model_tint(model);
            let lit = shade_normal(n, flags, &f, eye, DVec3::Z);
            let dark = shade_normal(n, flags, &f, eye, DVec3::X);
            for k in 0..3 {
                let full = ((want[k] + 0.22).min(1.0) * 255.0).round();
                assert!(
                    (f32::from(lit[k]) - full).abs() <= 1.0,
                    "model {model}: {lit:?}"
                );
                let ambient = (want[k] * 0.16 * 255.0).round();
                assert!(
                    (f32::from(dark[k]) - ambient).abs() <= 1.0,
                    "model {model}: {dark:?}"
                );
            }
        }
    }
    use crate::scene::camera::Camera;
    use rand::{rngs::SmallRng, Rng, SeedableRng};

    fn cv(x: f64, y: f64, z: f64) -> ClipVert {
        ClipVert {
            pos: DVec4::new(x, y, z, 1.0),
            uv: DVec2::ZERO,
            world: DVec3::ZERO,
        }
    }

    /// Pixel (px, py) of a `size`-pixel viewport as NDC (identity view_proj).
    fn px(x: f64, y: f64, size: f64) -> (f64, f64) {
        (x / size * 2.0 - 1.0, y / size * 2.0 - 1.0)
    }

    fn coverage(tris: &[[ClipVert; 3]], w: u32, h: u32) -> Vec<u32> {
        let mut count = vec![0u32; (w * h) as usize];
        for t in tris {
            rasterize(*t, w, h, |f| count[(f.y * w + f.x) as usize] += 1);
        }
        count
    }

    fn tri_px(p: [(f64, f64); 3], size: f64) -> [ClipVert; 3] {
        p.map(|(x, y)| {
            let (a, b) = px(x, y, size);
            cv(a, b, 0.5)
        })
    }

    #[test]
    fn triangle_covers_exactly_its_pixels_with_top_left_rule() {
        // Right triangle with legs on pixel-centre-free lines x=1, y=1 and a
        // hypotenuse x+y=8 through the centres with i+j=7; it is a bottom-right
        // edge here, so those centres belong to the other half of the square.
        let lower = tri_px([(1.0, 1.0), (7.0, 1.0), (1.0, 7.0)], 8.0);
        let upper = tri_px([(7.0, 7.0), (1.0, 7.0), (7.0, 1.0)], 8.0);
        let c = coverage(&[lower], 8, 8);
        for j in 0..8 {
            for i in 0..8 {
                let want = (i >= 1 && j >= 1 && i + j <= 6) as u32;
                assert_eq!(c[j * 8 + i], want, "pixel ({i}, {j})");
            }
        }
        assert_eq!(c.iter().sum::<u32>(), 15);
        // Together (either winding) they cover the 6×6 square exactly once.
        let reversed = [upper[0], upper[2], upper[1]];
        for pair in [[lower, upper], [lower, reversed]] {
            let c = coverage(&pair, 8, 8);
            for j in 0..8 {
                for i in 0..8 {
                    let inside = (1..7).contains(&i) && (1..7).contains(&j);
                    assert_eq!(c[j * 8 + i], inside as u32, "pixel ({i}, {j})");
                }
            }
        }
    }

    #[test]
    fn jittered_mesh_covers_every_pixel_exactly_once() {
        // A grid mesh over more than the viewport, vertices jittered (some
        // onto pixel centres; little enough that every quad stays convex)
        // and triangles in random winding: every pixel is covered exactly
        // once, with no gaps and no double coverage.
        let mut rng = SmallRng::seed_from_u64(3);
        let (w, h, n) = (37u32, 23u32, 6usize);
        let mut grid = vec![vec![(0.0, 0.0); n + 1]; n + 1];
        for (j, row) in grid.iter_mut().enumerate() {
            for (i, p) in row.iter_mut().enumerate() {
                let mut jitter = |k: usize| {
                    // Border vertices and some inner ones stay on the grid.
                    if k == 0 || k == n || rng.random_bool(0.3) {
                        0.0
                    } else {
                        rng.random_range(-0.12..0.12)
                    }
                };
                let x = -1.2 + 2.4 * (i as f64 + jitter(i)) / n as f64;
                let y = -1.2 + 2.4 * (j as f64 + jitter(j)) / n as f64;
                // Some vertices exactly on a pixel centre.
                *p = if rng.random_bool(0.2) {
                    let cx = ((x * 0.5 + 0.5) * w as f64).floor() + 0.5;
                    let cy = ((y * 0.5 + 0.5) * h as f64).floor() + 0.5;
                    (cx / w as f64 * 2.0 - 1.0, cy / h as f64 * 2.0 - 1.0)
                } else {
                    (x, y)
                };
            }
        }
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let q = [
                    grid[j][i],
                    grid[j][i + 1],
                    grid[j + 1][i + 1],
                    grid[j + 1][i],
                ];
                let v = q.map(|(x, y)| cv(x, y, 0.5));
                let (mut a, mut b) = if rng.random_bool(0.5) {
                    ([v[0], v[1], v[2]], [v[0], v[2], v[3]])
                } else {
                    ([v[0], v[1], v[3]], [v[1], v[2], v[3]])
                };
                if rng.random_bool(0.5) {
                    a.swap(0, 1);
                }
                if rng.random_bool(0.5) {
                    b.swap(1, 2);
                }
                tris.push(a);
                tris.push(b);
            }
        }
        let c = coverage(&tris, w, h);
        assert!(c.iter().all(|&k| k == 1), "{c:?}");
    }

    fn flat_patch() -> BezierPatch {
        crate::patch::fixtures::grid(|i, j| Vec3::new(i / 3.0, j / 3.0, 0.0))
    }

    /// The view-projection of a `w`×`h` image seen by a 60° camera (z up)
    /// at `eye` looking at `target`.
    fn view_proj(eye: Vec3, target: Vec3, w: u32, h: u32) -> DMat4 {
        let cam = Camera {
            position: eye.as_dvec3().to_array(),
            target: target.as_dvec3().to_array(),
            up: [0.0, 0.0, 1.0],
            fov_y_deg: 60.0,
            near: 0.1,
            far: 100.0,
        };
        cam.view_proj(w, h)
    }

    /// `tris` (of model 0, over `patches`) drawn on a black `w`×`h` raster.
    fn draw(
        (w, h): (u32, u32),
        tris: &[Triangle],
        patches: &[BezierPatch],
        (vp, eye): (&DMat4, Vec3),
        shade: PreviewShade,
    ) -> Raster {
        let mut r = Raster::new(w, h, [0, 0, 0, 255]);
        r.draw_triangles(tris, patches, &[0], None, vp, (eye, Vec3::Z), shade);
        r
    }

    fn tri(v: [Vec3; 3], depth: u32) -> Triangle {
        Triangle {
            v,
            uv: [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)],
            node: QuadNode::new(0, (depth, 0), (depth, 0), [depth; 4]),
            wedge: false,
        }
    }

    #[test]
    fn near_plane_clipping_is_finite_and_bounded() {
        let eye = Vec3::new(0.0, -5.0, 1.0);
        let vp = view_proj(eye, Vec3::new(0.0, 0.0, 1.0), 64, 48);
        let patches = [flat_patch()];
        let crossing = [
            // Through the camera plane, one vertex behind the eye.
            tri(
                [
                    Vec3::new(-1.0, 2.0, 0.5),
                    Vec3::new(1.0, 2.0, 1.5),
                    Vec3::new(0.5, -9.0, 0.2),
                ],
                3,
            ),
            // A vertex exactly at the eye (edge-on: nothing to draw, nothing to break).
            tri(
                [eye, Vec3::new(1.0, -5.0, 1.0), Vec3::new(0.0, 3.0, 0.0)],
                3,
            ),
            // Wholly behind the camera.
            tri(
                [
                    Vec3::new(0.0, -8.0, 0.0),
                    Vec3::new(1.0, -8.0, 2.0),
                    Vec3::new(-1.0, -7.0, 1.0),
                ],
                3,
            ),
        ];
        for shade in PreviewShade::ALL.map(|x| x.0) {
            let r = draw((64, 48), &crossing, &patches, (&vp, eye), shade);
            assert!(r
                .depth
                .iter()
                .all(|z| z.is_finite() && (0.0..=1.0).contains(z)));
            let drawn = r.depth.iter().filter(|&&z| z < 1.0).count();
            assert!(drawn > 0, "the crossing triangles draw something");
        }
        // The one behind the camera alone draws nothing.
        let r = draw(
            (64, 48),
            &crossing[2..],
            &patches,
            (&vp, eye),
            PreviewShade::Depth,
        );
        assert!(r.depth.iter().all(|&z| z == 1.0));
        // A triangle with a vertex on the eye itself (w = 0) does not poison anything.
        let c = coverage(
            &[
                [cv(0.0, 0.0, -0.1), cv(0.5, 0.0, 0.5), cv(0.0, 0.5, 0.5)].map(|mut v| {
                    v.pos.w = v.pos.z.max(0.0);
                    v
                }),
            ],
            16,
            16,
        );
        assert!(c.iter().all(|&k| k <= 1));
    }

    #[test]
    fn depth_test_keeps_the_nearer_triangle() {
        let eye = Vec3::new(0.0, -5.0, 0.0);
        let vp = view_proj(eye, Vec3::ZERO, 32, 32);
        let big = |y: f32, depth: u32| {
            tri(
                [
                    Vec3::new(-3.0, y, -3.0),
                    Vec3::new(3.0, y, -3.0),
                    Vec3::new(0.0, y, 3.0),
                ],
                depth,
            )
        };
        let (near, far) = (big(-1.0, 2), big(1.0, 8));
        let patches = [flat_patch()];
        let a = draw(
            (32, 32),
            &[near, far],
            &patches,
            (&vp, eye),
            PreviewShade::Depth,
        );
        let b = draw(
            (32, 32),
            &[far, near],
            &patches,
            (&vp, eye),
            PreviewShade::Depth,
        );
        assert_eq!(a.color, b.color);
        assert_eq!(a.depth, b.depth);
        let centre = 16 * 32 + 16;
        assert_eq!(
            a.color[centre],
            scale_rgb(depth_color(2), face_light(&near, eye.as_dvec3()))
        );
        // The near plane is at view depth 4, the far one at 6.
        let z_of = |d: f64| (vp * DVec4::new(0.0, -5.0 + d, 0.0, 1.0)).z / d;
        assert!((a.depth[centre] as f64 - z_of(4.0)).abs() < 1e-6);
    }

    #[test]
    fn png_round_trips_and_leaves_no_temp_file() {
        let dir = std::env::temp_dir().join(format!("raster-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.png");
        let mut r = Raster::new(5, 3, [10, 20, 30, 255]);
        r.color[7] = [200, 100, 50, 255];
        r.save_png(&path).unwrap();
        let img = image::open(&path).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (5, 3));
        assert_eq!(img.get_pixel(2, 1).0, [200, 100, 50, 255]);
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary file left"
        );
        // A directory that does not exist: an error, and nothing left behind.
        assert!(r.save_png(&dir.join("missing/x.png")).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn shade_names_parse() {
        for (s, n) in PreviewShade::ALL {
            assert_eq!(n.parse::<PreviewShade>(), Ok(s));
            assert_eq!(s.to_string(), n);
        }
        assert!("heat".parse::<PreviewShade>().is_err());
    }
}
