//! The hole test. A model is rendered alone by the method under test, with
//! SHADE_KEY (front faces white, back faces in the key colour) over a
//! key-coloured background; a reference is drawn by the `ground-truth`
//! method (a dense uniform grid per patch) over a different background. Wherever
//! the reference shows front surface, more than ⌈2ε⌉+2 pixels away from
//! its silhouettes, the subdivided image must not show the key colour: such
//! a pixel is a crack through which the background or the inside of the
//! model is seen.
//!
//! The silhouettes are the outline *and* the contours inside it, where the
//! surface turns from front to back (the teapot's rim seen from above):
//! there the two approximations may show different sides by a pixel without
//! any crack. SHADE_KEY paints front surface seen at a grazing angle in its
//! own colour, and the reference's depth jumps mark the occluding contours
//! ([`depth_edges`]); the mask leaves both out before eroding. So does a
//! contour the reference image cannot show: a fold, where the surface turns
//! back under its own front layer without a depth jump (the creased car
//! seen edge on folds like this inside a patch). Those are found on the CPU
//! from the reference grid's normals ([`hidden_contours`]). What is left
//! is smooth front surface, where a key pixel lying well behind the
//! reference surface can only be a crack (see [`run_model`]). Comparing against the
//! reference's own front region keeps open models honest too: where the
//! reference itself sees into the model, nothing is counted.
//!
//! The reference draws what a one-sided model can show: its patches that
//! face away everywhere are left out ([`front_capable`]), so two sheets lying
//! on each other, wound against each other, show the front one.

use crate::constants::*;
use crate::frame::View;
use crate::methods::{self, RenderError};
use crate::patch::bezier::BezierPatch;
use crate::patch::rational::RationalPatch;
use crate::patch::view::{Split, FLAG_WEDGES};
use crate::renderer::Renderer;
use crate::scene::camera::Camera;
use crate::scene::geometry::{SceneGeometry, SceneShading};

/// Background of the subdivided image: the key colour.
pub const KEY_BACKGROUND: [f32; 4] = [0.0, 1.0, 0.0, 1.0];
/// Background of the reference image (neither white nor key).
pub const REFERENCE_BACKGROUND: [f32; 4] = [0.0, 0.0, 1.0, 1.0];
const WHITE: [u8; 4] = [255, 255, 255, 255];
const KEY: [u8; 4] = [0, 255, 0, 255];

/// One model seen from one camera.
#[derive(Clone, Debug)]
pub struct HoleView {
    /// Camera index.
    pub camera: usize,
    /// Key pixels inside the eroded front region, wedges on (must be 0).
    pub holes: u64,
    /// The same with wedges off (shows the test can see cracks), for
    /// methods with wedges.
    pub holes_without_wedges: Option<u64>,
    /// Pixels in the eroded front region (the test's reach).
    pub checked_pixels: u64,
}

/// The hole test's line for one model: passed when no view shows a hole
/// *and* some pixel was checked. A test that looked at nothing (the model
/// is too small to leave pixels after the erosion, or what it shows is all
/// silhouette) must not pass.
pub fn verdict(views: &[HoleView]) -> (bool, String) {
    let holes: u64 = views.iter().map(|v| v.holes).sum();
    let without: Option<u64> = views.iter().map(|v| v.holes_without_wedges).sum();
    let checked: u64 = views.iter().map(|v| v.checked_pixels).sum();
    let wedges = without.map_or(String::new(), |w| {
        format!("; wedges off: {}", crate::figures::thousands(w))
    });
    if checked == 0 {
        return (
            false,
            format!(
                "nothing checked: no view of {} showed front surface away from its silhouettes \
                 (too small at this --size? or seen edge on from every camera){wedges}",
                views.len()
            ),
        );
    }
    (
        holes == 0,
        format!(
            "{holes} key pixels in {} views ({} px checked){wedges}",
            views.len(),
            crate::figures::thousands(checked),
        ),
    )
}

/// Grid cells per patch side of the reference: fine for small models,
/// coarser for big ones to keep the reference quick on a CPU device.
pub fn reference_grid(patches: usize) -> u32 {
    if patches <= 64 {
        32
    } else if patches <= 800 {
        16
    } else {
        8
    }
}

/// Cameras all around the model's bounding box, outside it.
pub fn hole_cameras(patches: &[BezierPatch]) -> Vec<Camera> {
    let (lo, hi) = BezierPatch::bounds(patches).unwrap_or_default();
    let c = ((lo + hi) * 0.5).as_dvec3();
    let r = (((hi - lo).length() * 0.5) as f64).max(1e-3);
    let dirs = [
        [1.0, -1.3, 0.8],
        [-1.2, -0.7, 0.5],
        [0.3, 1.4, 0.6],
        [1.1, 0.9, -0.4],
        [-0.8, 0.6, 1.4],
        [0.2, -0.3, -1.5],
    ];
    dirs.iter()
        .map(|d| {
            let d = glam::DVec3::from_array(*d).normalize();
            Camera {
                position: (c + d * 2.4 * r).to_array(),
                target: c.to_array(),
                up: if d.z.abs() > 0.9 {
                    [0.0, 1.0, 0.0]
                } else {
                    [0.0, 0.0, 1.0]
                },
                fov_y_deg: 40.0,
                near: 0.01 * r,
                far: 100.0 * r,
            }
        })
        .collect()
}

/// The hole cameras of `patches` moved back until an error of `error`
/// (model units) projects to at most ε pixels at the model's nearest
/// point in an image `height` pixels high (the distance at which a level
/// with that error is drawn), and how many pixels the model's bounding
/// sphere then spans.
pub fn level_cameras(
    patches: &[BezierPatch],
    error: f32,
    eps: f64,
    height: u32,
) -> (Vec<Camera>, f64) {
    let mut cameras = hole_cameras(patches);
    let (lo, hi) = BezierPatch::bounds(patches).unwrap_or_default();
    let r = (((hi - lo).length() * 0.5) as f64).max(1e-3);
    let mut span = 0.0;
    for cam in &mut cameras {
        let pixel = 2.0 * (cam.fov_y_deg.to_radians() * 0.5).tan() / f64::from(height);
        // Nearest depth (the sphere's) where the error is 0.95 ε.
        let depth = f64::from(error) / (0.95 * eps * pixel);
        let target = glam::DVec3::from_array(cam.target);
        let eye = glam::DVec3::from_array(cam.position);
        let dist = (eye - target).length().max(depth + r);
        cam.position = (target + (eye - target).normalize() * dist).to_array();
        cam.far = dist + 100.0 * r;
        span = 2.0 * r / (dist * pixel);
    }
    (cameras, span)
}

/// `mask` eroded by a disk of radius `r` pixels.
pub fn erode(mask: &[bool], w: usize, h: usize, r: i64) -> Vec<bool> {
    let offsets: Vec<(i64, i64)> = (-r..=r)
        .flat_map(|y| (-r..=r).map(move |x| (x, y)))
        .filter(|(x, y)| x * x + y * y <= r * r)
        .collect();
    let mut out = vec![false; mask.len()];
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            if !mask[(y * w as i64 + x) as usize] {
                continue;
            }
            out[(y * w as i64 + x) as usize] = offsets.iter().all(|(dx, dy)| {
                let (px, py) = (x + dx, y + dy);
                px >= 0
                    && py >= 0
                    && px < w as i64
                    && py < h as i64
                    && mask[(py * w as i64 + px) as usize]
            });
        }
    }
    out
}

fn pixels(rgba: &[u8]) -> impl Iterator<Item = [u8; 4]> + '_ {
    rgba.chunks_exact(4).map(|c| [c[0], c[1], c[2], c[3]])
}

/// Pixels next to a jump in the reference's depth: occluding contours,
/// where the nearer surface turns away and hides what lies behind it. An
/// approximation within ε pixels may move such a contour by a pixel and
/// uncover the farther surface without any crack.
pub fn depth_edges(dist: &[f32], w: usize, h: usize) -> Vec<bool> {
    let mut out = vec![false; dist.len()];
    for y in 0..h {
        for x in 0..w {
            let d = dist[y * w + x];
            for (dx, dy) in [(1i64, 0i64), (0, 1), (1, 1), (1, -1)] {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let j = ny as usize * w + nx as usize;
                let e = dist[j];
                let jump = match (d.is_finite(), e.is_finite()) {
                    (true, true) => (d - e).abs() > CONTOUR_JUMP * d.min(e),
                    (false, false) => false,
                    _ => true,
                };
                if jump {
                    out[y * w + x] = true;
                    out[j] = true;
                }
            }
        }
    }
    out
}

/// Relative depth step between neighbouring reference pixels that marks an
/// occluding contour ([`depth_edges`]).
pub const CONTOUR_JUMP: f32 = 0.02;

/// A view's images: key colours and coded distances.
struct Shots {
    key: Vec<u8>,
    distance: Vec<f32>,
}

/// Decodes a `SHADE_DISTANCE` image (background white = infinitely far);
/// `eval` reads its distance images with it too.
pub fn decode_distances(rgba: &[u8], scale: f32) -> Vec<f32> {
    pixels(rgba)
        .map(|p| {
            if p == WHITE {
                f32::INFINITY
            } else {
                let code = (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32;
                code as f32 / 16_777_214.0 * scale
            }
        })
        .collect()
}

/// Contour pixels the reference image does not show: where the surface
/// turns from facing the camera to facing away (by the patches' own
/// normals at the reference grid's points: a grid cell whose corners
/// disagree, or a point on a patch border where the patches meeting there
/// disagree), at the depth the reference shows there (within
/// [`CONTOUR_JUMP`]), so a turn hidden behind other surface masks nothing.
pub fn hidden_contours(
    patches: &[BezierPatch],
    grid: u32,
    cam: &Camera,
    (w, h): (u32, u32),
    ref_dist: &[f32],
) -> Vec<bool> {
    let n = grid as usize;
    let eye = glam::DVec3::from_array(cam.position);
    let t = |k: usize| k as f32 / grid as f32;
    // Facing sign at every grid point; points on patch borders are shared
    // bit for bit, so the signs of all patches there can be compared.
    let mut facing: Vec<Vec<bool>> = Vec::with_capacity(patches.len());
    let mut at_point: std::collections::HashMap<[u32; 3], (bool, bool)> = Default::default();
    for p in patches {
        let signs: Vec<bool> = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| (i, j)))
            .map(|(i, j)| {
                let q = p.eval(t(i), t(j));
                let front = p.normal(t(i), t(j)).as_dvec3().dot(eye - q.as_dvec3()) > 0.0;
                if i == 0 || j == 0 || i == n || j == n {
                    let e = at_point.entry(q.to_array().map(f32::to_bits)).or_default();
                    *e = (e.0 || front, e.1 || !front);
                }
                front
            })
            .collect();
        facing.push(signs);
    }
    let view_proj = cam.view_proj(w, h);
    let mut mask = vec![false; (w * h) as usize];
    for (p, signs) in patches.iter().zip(&facing) {
        let turns = |i: usize, j: usize| {
            let border = i == 0 || j == 0 || i == n || j == n;
            border && {
                let q = p.eval(t(i), t(j)).to_array().map(f32::to_bits);
                at_point.get(&q).is_some_and(|&(f, b)| f && b)
            }
        };
        for j in 0..n {
            for i in 0..n {
                let corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let s = corners.map(|(a, b)| signs[b * (n + 1) + a]);
                let contour =
                    s.iter().any(|&x| x != s[0]) || corners.iter().any(|&(a, b)| turns(a, b));
                if !contour {
                    continue;
                }
                let v = corners.map(|(a, b)| p.eval(t(a), t(b)).as_dvec3());
                let mut mark = |x: u32, y: u32, world: glam::DVec3| {
                    let k = (y * w + x) as usize;
                    let d = world.distance(eye) as f32;
                    if (d - ref_dist[k]).abs() <= CONTOUR_JUMP * ref_dist[k] {
                        mask[k] = true;
                    }
                };
                for tri in [[v[0], v[1], v[2]], [v[0], v[2], v[3]]] {
                    super::raster::cover_triangle(tri, &view_proj, w, h, &mut mark);
                }
                // A cell seen edge on may cover no pixel centre: its corners'
                // pixels count too.
                for q in v {
                    let c = view_proj * q.extend(1.0);
                    if c.w > 0.0 {
                        let x = ((c.x / c.w * 0.5 + 0.5) * w as f64).floor();
                        let y = ((c.y / c.w * 0.5 + 0.5) * h as f64).floor();
                        if (0.0..w as f64).contains(&x) && (0.0..h as f64).contains(&y) {
                            mark(x as u32, y as u32, q);
                        }
                    }
                }
            }
        }
    }
    mask
}

/// Relative distance by which the subdivided surface must lie behind the
/// reference surface for a key pixel to count as seeing *through* it.
/// Cracks show the background or the far side of the model, many times
/// farther; a surface approximated within ε pixels stays far closer.
pub const SEE_THROUGH: f32 = 0.01;

/// Runs the hole test for one model geometry with `renderer` (whose scene
/// is replaced by `geo`) and its active method, from every
/// [`hole_cameras`] camera; the reference is the `ground-truth` method at
/// [`reference_grid`].
///
/// A pixel is a hole when the reference shows front surface there (away
/// from silhouettes, see the module docs), the tested image shows the key
/// colour (back side or background), and what it shows lies more than
/// [`SEE_THROUGH`] farther than the reference surface. The last condition
/// tells a crack from a contour that the approximation moved by a pixel
/// (where the curvature is high the nearer surface can overhang and show
/// its back, at the same depth). Methods with wedges are also drawn with
/// them off, which must show the cracks they close.
///
/// When `debug_dir` is given, every view with holes, or that checked no
/// pixel, leaves `<name>-cam<k>-{actual,nowedges,reference,holes,excluded}.png`
/// there (holes in red over the actual image; the reference with its depth
/// edges in red and its hidden contours in magenta, which the test leaves out).
pub fn run_model(
    renderer: &mut Renderer,
    geo: &SceneGeometry,
    view_setup: (f64, f64, Split),
    name: &str,
    debug_dir: Option<&std::path::Path>,
) -> Result<Vec<HoleView>, RenderError> {
    let cameras = hole_cameras(&geo.patches);
    run_model_from(renderer, geo, view_setup, (name, &cameras, None), debug_dir)
}

/// A level of detail under the hole test: the model's levels and the one
/// every instance is drawn from.
pub type LevelUnderTest<'a> = (&'a crate::lod::SceneLevels, usize);

/// [`run_model`] from `cameras`, and with `level` the tested method's
/// image drawn from that level of detail (the reference's from patches,
/// as always).
pub fn run_model_from(
    renderer: &mut Renderer,
    geo: &SceneGeometry,
    view_setup: (f64, f64, Split),
    (name, cameras, level): (&str, &[Camera], Option<LevelUnderTest<'_>>),
    debug_dir: Option<&std::path::Path>,
) -> Result<Vec<HoleView>, RenderError> {
    let (eps, lambda, split) = view_setup;
    // The key colours come from the patches' own normals (which side of
    // the surface is seen), never from the shading patches.
    renderer.set_geometry(geo, &SceneShading::own_derivatives(geo))?;
    let tested = renderer.method().name();
    // A level of detail has no wedges to turn off.
    let with_wedges_too = renderer.method().has_wedges() && level.is_none();
    let (w, h) = renderer.target().size();
    let size = (w, h);
    let radius = (2.0 * eps).ceil() as i64 + 2;
    let grid = reference_grid(geo.patches.len());
    let mut views = Vec::new();
    for (k, cam) in cameras.iter().enumerate() {
        let scale = cam.far as f32;
        let mut view = View {
            distance_scale: scale,
            ..View::new(cam, size, eps, lambda, SHADE_KEY)
        };
        view.params.flags |= split.flag();
        if let Some((levels, l)) = level {
            // The reference's shots may load other geometry, which drops
            // the levels: given again only then.
            if renderer.levels().is_none() {
                renderer.set_levels(Some(levels.clone()))?;
            }
            renderer.force_level(Some(l));
        }
        let with = shots(renderer, &view, KEY_BACKGROUND)?;
        let without = if with_wedges_too {
            view.params.flags &= !FLAG_WEDGES;
            let s = shots(renderer, &view, KEY_BACKGROUND)?;
            view.params.flags |= FLAG_WEDGES;
            Some(s)
        } else {
            None
        };
        let shown = front_capable(geo, &view, grid);
        let ref_geo = shown.as_ref().unwrap_or(geo);
        let reference = if ref_geo.patches.is_empty() {
            // Every patch faces away (a flat floor seen from below): the
            // reference is empty background.
            let rgba = REFERENCE_BACKGROUND.map(|c| (c * 255.0) as u8);
            Shots {
                key: rgba.repeat((w * h) as usize),
                distance: vec![f32::INFINITY; (w * h) as usize],
            }
        } else {
            reference_shots(renderer, &view, grid, tested, (ref_geo, geo))?
        };

        let edges = depth_edges(&reference.distance, w as usize, h as usize);
        let folds = hidden_contours(&ref_geo.patches, grid, cam, size, &reference.distance);
        let good: Vec<bool> = pixels(&reference.key)
            .zip(edges.iter().zip(&folds))
            .map(|(p, (&e, &f))| p == WHITE && !e && !f)
            .collect();
        let inside = erode(&good, w as usize, h as usize, radius);
        let holes_in = |shot: &Shots| -> Vec<bool> {
            pixels(&shot.key)
                .enumerate()
                .map(|(i, p)| {
                    inside[i]
                        && p == KEY
                        && shot.distance[i] > reference.distance[i] * (1.0 + SEE_THROUGH)
                })
                .collect()
        };
        let mask_with = holes_in(&with);
        let count = |m: &[bool]| m.iter().filter(|&&x| x).count() as u64;
        let holes = count(&mask_with);
        let holes_without = without.as_ref().map(|s| count(&holes_in(s)));
        let checked_pixels = count(&inside);
        if let (Some(dir), true) = (debug_dir, holes > 0 || checked_pixels == 0) {
            let images = DebugImages {
                with: &with,
                without: without.as_ref(),
                reference: &reference,
                holes: &mask_with,
                excluded: (&edges, &folds),
            };
            images.write(dir, name, k, size);
        }
        views.push(HoleView {
            camera: k,
            holes,
            holes_without_wedges: holes_without,
            checked_pixels,
        });
    }
    Ok(views)
}

/// The images of a view with holes, for `--debug-dir`.
struct DebugImages<'a> {
    with: &'a Shots,
    without: Option<&'a Shots>,
    reference: &'a Shots,
    holes: &'a [bool],
    /// The reference's depth edges and hidden contours (left out).
    excluded: (&'a [bool], &'a [bool]),
}

impl DebugImages<'_> {
    fn write(&self, dir: &std::path::Path, name: &str, k: usize, (w, h): (u32, u32)) {
        let mut marked = self.with.key.clone();
        for (i, &m) in self.holes.iter().enumerate() {
            if m {
                marked[4 * i..4 * i + 4].copy_from_slice(&[255, 0, 0, 255]);
            }
        }
        // The reference with what the mask leaves out: depth edges red,
        // hidden contours (folds) magenta.
        let mut masked = self.reference.key.clone();
        for (i, (&e, &f)) in self.excluded.0.iter().zip(self.excluded.1).enumerate() {
            let c = match (e, f) {
                (true, _) => [255, 0, 0, 255],
                (false, true) => [255, 0, 255, 255],
                _ => continue,
            };
            masked[4 * i..4 * i + 4].copy_from_slice(&c);
        }
        let _ = std::fs::create_dir_all(dir);
        let mut images = vec![
            ("actual", &self.with.key),
            ("reference", &self.reference.key),
            ("holes", &marked),
            ("excluded", &masked),
        ];
        if let Some(s) = self.without {
            images.push(("nowedges", &s.key));
        }
        for (tag, img) in images {
            let file = dir.join(format!("{name}-cam{k}-{tag}.png"));
            if let Err(e) = crate::gpu::write_png(&file, w, h, img) {
                log::warn!("{e}");
            }
        }
    }
}

/// The image of `view` in key colours and coded distances, drawn by the
/// renderer's active method over `background`.
fn shots(renderer: &mut Renderer, view: &View, background: [f32; 4]) -> Result<Shots, RenderError> {
    renderer.set_background(background);
    renderer.render(view)?;
    let key = renderer.read_image()?;
    renderer.set_background([1.0; 4]);
    let coded = View {
        shade: SHADE_DISTANCE,
        ..*view
    };
    renderer.render(&coded)?;
    let distance = decode_distances(&renderer.read_image()?, view.distance_scale);
    Ok(Shots { key, distance })
}

/// The patches of `geo` the reference draws in `view`: all but those of
/// one-sided models that face away from the eye at every point of the
/// reference's `grid` (by the patch's own normal, as SHADE_KEY tells the
/// sides apart), when `view` culls back faces; `None` when that is every
/// patch. Such a patch shows the eye nothing but its back, which a
/// one-sided model never shows, and `ground-truth` (which culls nothing)
/// would draw it at the very depth of a front sheet lying on it: two
/// coincident sheets wound against each other (`catmark_val2_back2back`)
/// tie in the depth test, and the back sheet's pixels hide the front one
/// from the test. Elsewhere a left-out patch lies behind front surface and
/// changes no pixel, or uncovers what lies behind it, as the methods that
/// cull it show too. (The interval test the subdividing methods cull a
/// base patch by is too cautious for this: it keeps the folded patches of
/// those sheets.)
///
/// A displaced model keeps every patch (`None`): its bumps can turn the
/// surface of a patch whose base faces away towards the eye, which is why
/// no method back-face culls a displaced patch; and a subset made here
/// would draw the reference undisplaced.
fn front_capable(geo: &SceneGeometry, view: &View, grid: u32) -> Option<SceneGeometry> {
    if view.params.flags & FLAG_BACKFACE_CULL == 0 || geo.displacement.in_use() {
        return None;
    }
    let eye = view.params.eye.truncate();
    let t = |k: u32| k as f32 / grid as f32;
    let keep: Vec<usize> = (0..geo.patches.len())
        .filter(|&k| {
            if geo.flags[k] & PATCH_TWO_SIDED != 0 {
                return true;
            }
            let p = RationalPatch::new(geo.patches[k], geo.weights_of(k));
            let polynomial = p.is_polynomial();
            (0..=grid).any(|j| {
                (0..=grid).any(|i| {
                    let (u, v) = (t(i), t(j));
                    let (q, n) = if polynomial {
                        (p.patch.eval(u, v), p.patch.normal(u, v))
                    } else {
                        (p.eval(u, v), p.normal(u, v))
                    };
                    n.dot(eye - q) >= 0.0
                })
            })
        })
        .collect();
    if keep.len() == geo.patches.len() {
        return None;
    }
    let weights = if geo.weights.is_empty() {
        Vec::new()
    } else {
        keep.iter().map(|&k| geo.weights[k]).collect()
    };
    Some(SceneGeometry {
        patches: keep.iter().map(|&k| geo.patches[k]).collect(),
        flags: keep.iter().map(|&k| geo.flags[k]).collect(),
        models: geo.models.clone(),
        weights,
        ..SceneGeometry::default()
    })
}

/// The reference shots: `ground-truth` at `grid` on `reference`, then back
/// to `tested` on `geo`.
fn reference_shots(
    renderer: &mut Renderer,
    view: &View,
    grid: u32,
    tested: &str,
    (reference, geo): (&SceneGeometry, &SceneGeometry),
) -> Result<Shots, RenderError> {
    let swap = !std::ptr::eq(reference, geo);
    if swap {
        renderer.set_geometry(reference, &SceneShading::own_derivatives(reference))?;
    }
    let options = renderer.options().clone();
    let mut reference_options = options.clone();
    reference_options.per_method.set_reference_grid(grid);
    renderer.set_options(reference_options)?;
    renderer.set_method(methods::reference().name)?;
    let shot = shots(renderer, view, REFERENCE_BACKGROUND);
    renderer.set_options(options)?;
    renderer.set_method(tested)?;
    if swap {
        renderer.set_geometry(geo, &SceneShading::own_derivatives(geo))?;
    }
    shot
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn erosion_shrinks_by_the_radius() {
        let (w, h) = (21, 21);
        let mask: Vec<bool> = (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as i64, (i / w) as i64);
                (5..16).contains(&x) && (5..16).contains(&y)
            })
            .collect();
        let e = erode(&mask, w, h, 2);
        let n = e.iter().filter(|&&m| m).count();
        assert_eq!(n, 7 * 7);
        assert!(e[10 * w + 10] && !e[10 * w + 6] && e[10 * w + 7]);
    }

    /// The hole test's reference for a displaced model is the displaced
    /// surface in every view: the torus of tests/data/displaced_seams.toml,
    /// cut out as `validate` cuts it, keeps all its patches in views
    /// where some of them face away, while the same torus undisplaced
    /// leaves those out. (The displaced model's reference was once this
    /// function's subset, which drops the displacement: undisplaced in
    /// every view where a patch faced away.)
    #[test]
    fn a_displaced_model_keeps_its_displaced_reference_in_every_view() {
        use crate::constants::SHADE_KEY;
        use crate::scene::desc::Scene;
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/displaced_seams.toml");
        let geo = Scene::load(&path).unwrap().geometry().unwrap();
        let torus = geo.models[0].clone();
        let one = geo.subset(0..torus.patches_per_instance, (0, torus));
        assert!(one.displacement.in_use());
        let mut plain = one.clone();
        plain.displacement = Default::default();
        let grid = reference_grid(one.patches.len());
        let mut faced_away = 0;
        for cam in hole_cameras(&one.patches) {
            let view = View::new(&cam, (256, 144), 1.0, 0.5, SHADE_KEY);
            assert_ne!(view.params.flags & FLAG_BACKFACE_CULL, 0);
            assert!(front_capable(&one, &view, grid).is_none());
            faced_away += usize::from(front_capable(&plain, &view, grid).is_some());
        }
        assert!(faced_away > 0, "some view sees the back of a patch");
    }

    /// A sheet that folds back on itself (x runs out and back along u) seen
    /// from above has a contour the key image cannot show; a sheet without
    /// the fold has none. The reference distance is the nearest layer's.
    #[test]
    fn folds_are_found_and_flat_sheets_are_not() {
        let sheet = |xs: [f32; 4]| BezierPatch {
            pts: std::array::from_fn(|k| {
                let (i, j) = (k % 4, k / 4);
                Vec3::new(xs[i], j as f32 / 3.0, 0.05 * i as f32)
            }),
        };
        let cam = Camera {
            position: [0.5, 0.5, 3.0],
            target: [0.5, 0.5, 0.0],
            up: [0.0, 1.0, 0.0],
            fov_y_deg: 40.0,
            near: 0.01,
            far: 100.0,
        };
        let (w, h) = (64u32, 64u32);
        let eye = glam::DVec3::from_array(cam.position);
        let count = |p: BezierPatch| {
            let mut dist = vec![f32::INFINITY; (w * h) as usize];
            let grid = 16;
            let t = |k: u32| k as f32 / grid as f32;
            let vp = cam.view_proj(w, h);
            for j in 0..grid {
                for i in 0..grid {
                    let v = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
                        .map(|(a, b)| p.eval(t(a), t(b)).as_dvec3());
                    for tri in [[v[0], v[1], v[2]], [v[0], v[2], v[3]]] {
                        crate::validate::raster::cover_triangle(tri, &vp, w, h, |x, y, q| {
                            let k = (y * w + x) as usize;
                            dist[k] = dist[k].min(q.distance(eye) as f32);
                        });
                    }
                }
            }
            let mask = hidden_contours(&[p], 8, &cam, (w, h), &dist);
            mask.iter().filter(|&&m| m).count()
        };
        assert_eq!(count(sheet([0.0, 0.33, 0.67, 1.0])), 0);
        assert!(count(sheet([0.0, 1.6, -0.6, 1.0])) > 10);
    }
}
