//! Where an image's error comes from, and the geometric error FLIP cannot
//! see.
//!
//! Every pixel is lit with the exact shading normal at its (u, v), so FLIP
//! scores interior geometric error (a surface drawn a little in front of or
//! behind the true one) close to nothing; only silhouettes and occlusion
//! show it. So beside FLIP a configuration's image is compared with the
//! ground truth's by the distance between the two surfaces, in pixels, from
//! the eye distance each image codes per pixel (`SHADE_DISTANCE`):
//!
//! - along the pixel's ray the surfaces are Δ = |d − d_ref| apart; a surface
//!   seen at angle θ to its normal is Δ·cos θ away along its normal, and
//!   cos θ follows from how fast the reference's distance changes across
//!   pixels (one pixel sideways, k·d world units at distance d, moves the
//!   hit point by k·d·tan θ, k = 2 tan(fov/2) / height);
//! - that distance over the pixel's footprint k·d is the error in pixels:
//!   what ε promises to bound;
//! - silhouettes (either image's coverage or depth jumps, one pixel wide
//!   each side) are left out of that measure and counted instead: pixels
//!   whose coverage differs, or that see a different surface.
//!
//! The same masks split the FLIP map: its share in the silhouette band, in
//! the method's wedge triangles, and per model (by the reference's patch id
//! under each pixel).

use crate::validate::holes::{depth_edges, CONTOUR_JUMP};

/// Coded background of `SHADE_PATCH_ID` images (drawn over white).
const WHITE: [u8; 4] = [255, 255, 255, 255];

/// A `SHADE_PATCH_ID` image as patch ids (background: `None`).
pub fn decode_patch_ids(rgba: &[u8]) -> Vec<Option<u32>> {
    rgba.chunks_exact(4)
        .map(|p| (p != WHITE).then(|| (p[0] as u32) << 16 | (p[1] as u32) << 8 | p[2] as u32))
        .collect()
}

/// The pixels of a `SHADE_WEDGES` image that show a wedge: wedges are
/// magenta at 75–100 % brightness, everything else a darkened depth colour.
pub fn wedge_pixels(rgba: &[u8]) -> Vec<bool> {
    rgba.chunks_exact(4)
        .map(|p| p[1] == 0 && p[0] >= 185 && p[2] >= 185)
        .collect()
}

/// The reference's per-pixel facts for one view.
pub struct Reference {
    /// Image size.
    pub size: (u32, u32),
    /// Eye distance per pixel (infinity: background).
    pub distance: Vec<f32>,
    /// Model index per pixel.
    pub model: Vec<Option<usize>>,
    /// Pixel footprint per unit distance: 2 tan(fov/2) / height.
    pub k: f32,
}

/// One model's share of an image's error.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelError {
    /// Reference pixels showing the model.
    pub pixels: u64,
    /// Sum of FLIP over them.
    pub flip_sum: f64,
    /// Sum of the geometric error (pixels) over those of them measured.
    pub geo_sum_px: f64,
    /// How many were measured (covered by both, off the silhouettes).
    pub geo_pixels: u64,
}

/// Where one image's error lies.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Breakdown {
    /// Mean geometric error (pixels) over the pixels both images cover,
    /// off the silhouettes.
    pub geo_mean_px: f64,
    /// Its 99th percentile.
    pub geo_p99_px: f64,
    /// Pixels it was measured over.
    pub geo_pixels: u64,
    /// Pixels whose coverage differs or that see a different surface.
    pub silhouette_diff_px: u64,
    /// Share of the FLIP sum in the silhouette band.
    pub flip_silhouette_share: f64,
    /// Share of the FLIP sum on wedge pixels (methods that draw wedges).
    pub flip_wedge_share: Option<f64>,
    /// Share of the image's pixels that show a wedge.
    pub wedge_pixel_share: Option<f64>,
    /// Per model index.
    pub models: Vec<ModelError>,
}

/// Marks each pixel within one pixel of a marked one.
fn dilate(mask: &[bool], w: usize, h: usize) -> Vec<bool> {
    let mut out = mask.to_vec();
    for y in 0..h {
        for x in 0..w {
            if !mask[y * w + x] {
                continue;
            }
            for (dx, dy) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h {
                    out[ny as usize * w + nx as usize] = true;
                }
            }
        }
    }
    out
}

/// cos θ at pixel `i` of the reference: from the distance's central
/// differences (one-sided at a border); `None` where a neighbour is
/// missing.
fn cos_to_normal(d: &[f32], w: usize, h: usize, i: usize, k: f32) -> Option<f32> {
    let (x, y) = (i % w, i / w);
    let at = |x: usize, y: usize| d.get(y * w + x).copied().filter(|v| v.is_finite());
    let diff = |a: Option<f32>, b: Option<f32>, span: f32| Some((a? - b?) / span);
    let gx = match (x > 0, x + 1 < w) {
        (true, true) => diff(at(x + 1, y), at(x - 1, y), 2.0),
        (false, true) => diff(at(x + 1, y), at(x, y), 1.0),
        (true, false) => diff(at(x, y), at(x - 1, y), 1.0),
        _ => Some(0.0),
    }?;
    let gy = match (y > 0, y + 1 < h) {
        (true, true) => diff(at(x, y + 1), at(x, y - 1), 2.0),
        (false, true) => diff(at(x, y + 1), at(x, y), 1.0),
        (true, false) => diff(at(x, y), at(x, y - 1), 1.0),
        _ => Some(0.0),
    }?;
    let tan = (gx * gx + gy * gy).sqrt() / (k * d[i]);
    Some(1.0 / (1.0 + tan * tan).sqrt())
}

/// The error of an image against `reference`: its coded distances, its
/// wedge pixels (if it draws wedges), and its FLIP map against the
/// reference's shaded image.
pub fn breakdown(
    reference: &Reference,
    distance: &[f32],
    wedges: Option<&[bool]>,
    flip: &[f32],
) -> Breakdown {
    let (w, h) = (reference.size.0 as usize, reference.size.1 as usize);
    let r = &reference.distance;
    let mut edges = depth_edges(r, w, h);
    for (e, t) in edges.iter_mut().zip(depth_edges(distance, w, h)) {
        *e |= t;
    }
    let band = dilate(&edges, w, h);
    let models = reference.model.iter().flatten().max().map_or(0, |m| m + 1);
    let mut out = Breakdown {
        models: vec![ModelError::default(); models],
        ..Breakdown::default()
    };
    let (mut geo, mut flip_total, mut flip_band, mut flip_wedge) = (Vec::new(), 0.0, 0.0, 0.0);
    let mut wedge_px = 0u64;
    for i in 0..w * h {
        let (a, b) = (r[i], distance[i]);
        let f = f64::from(flip[i]);
        flip_total += f;
        if band[i] {
            flip_band += f;
        }
        if wedges.is_some_and(|m| m[i]) {
            flip_wedge += f;
            wedge_px += 1;
        }
        let differs = match (a.is_finite(), b.is_finite()) {
            (true, true) => (a - b).abs() > CONTOUR_JUMP * a.min(b),
            (false, false) => false,
            _ => true,
        };
        out.silhouette_diff_px += differs as u64;
        let model = reference.model[i].map(|m| &mut out.models[m]);
        let measured = !band[i] && !differs && a.is_finite() && b.is_finite();
        let e = if measured {
            cos_to_normal(r, w, h, i, reference.k).map(|c| (a - b).abs() * c / (reference.k * a))
        } else {
            None
        };
        if let Some(e) = e {
            geo.push(e);
        }
        if let Some(m) = model {
            m.pixels += 1;
            m.flip_sum += f;
            if let Some(e) = e {
                m.geo_sum_px += f64::from(e);
                m.geo_pixels += 1;
            }
        }
    }
    geo.sort_by(f32::total_cmp);
    out.geo_pixels = geo.len() as u64;
    if !geo.is_empty() {
        out.geo_mean_px = geo.iter().map(|&e| f64::from(e)).sum::<f64>() / geo.len() as f64;
        let k = ((geo.len() as f64 * 0.99).ceil() as usize).clamp(1, geo.len()) - 1;
        out.geo_p99_px = f64::from(geo[k]);
    }
    let share = |x: f64| {
        if flip_total > 0.0 {
            x / flip_total
        } else {
            0.0
        }
    };
    out.flip_silhouette_share = share(flip_band);
    out.flip_wedge_share = wedges.map(|_| share(flip_wedge));
    out.wedge_pixel_share = wedges.map(|_| wedge_px as f64 / (w * h) as f64);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A plane seen head-on at distance 10 and one tilted 60°: a surface
    /// 0.01 in front of each is 0.01 / (k·10) pixels away, whatever the
    /// tilt (the ray distance grows as 1 / cos θ, the measure divides it
    /// out); the silhouette band is left out and counted.
    #[test]
    fn geometric_error_is_the_normal_distance_in_pixels() {
        let (w, h) = (40usize, 30usize);
        let k = 0.01f32;
        for tilt_deg in [0.0f32, 60.0] {
            let tan = tilt_deg.to_radians().tan();
            // Distance along the rays of a plane tilted about the vertical
            // axis: d grows by k·d·tan θ per pixel (small-angle rays).
            let mut reference = vec![0f32; w * h];
            for y in 0..h {
                let mut d = 10.0f32;
                for x in 0..w {
                    reference[y * w + x] = d;
                    d *= 1.0 + k * tan;
                }
            }
            let offset = 0.01f32;
            let cos = tilt_deg.to_radians().cos();
            let test: Vec<f32> = reference.iter().map(|d| d - offset / cos).collect();
            let r = Reference {
                size: (w as u32, h as u32),
                distance: reference.clone(),
                model: vec![Some(0); w * h],
                k,
            };
            let b = breakdown(&r, &test, None, &vec![0.0; w * h]);
            let want = offset / (k * 10.0);
            // The pixels near x = 0 are at d ≈ 10; the mean over the image
            // is smaller (farther pixels are smaller in world units).
            assert!(
                b.geo_p99_px as f32 <= want * 1.01,
                "{tilt_deg}°: {} > {want}",
                b.geo_p99_px
            );
            assert!(
                b.geo_p99_px as f32 >= want * 0.3,
                "{tilt_deg}°: {}",
                b.geo_p99_px
            );
            assert_eq!(b.silhouette_diff_px, 0);
        }
    }

    #[test]
    fn silhouettes_wedges_and_models_split_the_flip_sum() {
        let (w, h) = (10usize, 10usize);
        // Reference: model 0 on the left half, background on the right.
        let reference: Vec<f32> = (0..w * h)
            .map(|i| if i % w < 5 { 10.0 } else { f32::INFINITY })
            .collect();
        // The test covers one column more: silhouette pixels that differ.
        let test: Vec<f32> = (0..w * h)
            .map(|i| if i % w < 6 { 10.0 } else { f32::INFINITY })
            .collect();
        let model = (0..w * h).map(|i| (i % w < 5).then_some(0)).collect();
        let r = Reference {
            size: (w as u32, h as u32),
            distance: reference,
            model,
            k: 0.01,
        };
        let flip: Vec<f32> = (0..w * h)
            .map(|i| if i % w == 5 { 1.0 } else { 0.0 })
            .collect();
        let wedges: Vec<bool> = (0..w * h).map(|i| i / w == 0).collect();
        let b = breakdown(&r, &test, Some(&wedges), &flip);
        assert_eq!(b.silhouette_diff_px, 10);
        assert_eq!(b.flip_silhouette_share, 1.0);
        assert_eq!(b.flip_wedge_share, Some(0.1));
        assert_eq!(b.wedge_pixel_share, Some(0.1));
        assert_eq!(b.models[0].pixels, 50);
        assert_eq!(b.models[0].flip_sum, 0.0);
        // Columns 0..=2 are off the band and measured, at zero error.
        assert_eq!(b.geo_pixels, 30);
        assert_eq!(b.geo_mean_px, 0.0);
    }
}
