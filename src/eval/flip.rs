//! Image error with NVIDIA's FLIP (LDR-FLIP, through the `nv-flip` crate):
//! the metric the paper's Table 1 reports against the ground truth. Images
//! are the renderer's RGBA8 readbacks (sRGB display values); alpha is
//! dropped.

use std::path::Path;

use crate::gpu::{write_png, ImageError};

/// Pixels per degree of visual angle FLIP assumes: its default (a 0.7 m
/// viewing distance from a 0.7 m wide 4K monitor), as the paper's tool used.
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// FLIP of one test image against its reference.
pub struct FlipResult {
    /// Per-pixel error in [0, 1], row-major from the top left.
    pub errors: Vec<f32>,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The mean error: FLIP's authors' single number for an image.
    pub mean: f64,
}

fn rgb(rgba: &[u8]) -> Vec<u8> {
    rgba.chunks_exact(4)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect()
}

/// FLIP between two RGBA8 images of `width`×`height`; `None` when the sizes
/// do not match the data.
pub fn flip(reference: &[u8], test: &[u8], width: u32, height: u32) -> Option<FlipResult> {
    let n = width as usize * height as usize * 4;
    if width == 0 || height == 0 || reference.len() != n || test.len() != n {
        return None;
    }
    let r = nv_flip::FlipImageRgb8::with_data(width, height, &rgb(reference));
    let t = nv_flip::FlipImageRgb8::with_data(width, height, &rgb(test));
    let map = nv_flip::flip(r, t, PIXELS_PER_DEGREE);
    let pool = nv_flip::FlipPool::from_image(&map);
    Some(FlipResult {
        mean: f64::from(pool.mean()),
        errors: map.to_vec(),
        width,
        height,
    })
}

impl FlipResult {
    /// The error map as RGBA8 rows in FLIP's magma colour map (black is no
    /// difference).
    pub fn heat_map_rgba(&self) -> Vec<u8> {
        let map = nv_flip::FlipImageFloat::with_data(self.width, self.height, &self.errors);
        let rgb = map.apply_color_lut(&nv_flip::magma_lut()).to_vec();
        rgb.chunks_exact(3)
            .flat_map(|p| [p[0], p[1], p[2], 255])
            .collect()
    }

    /// The heat map's colour scale: `width` RGBA8 pixels from error 0
    /// (left) to 1 (right), for a legend beside it.
    pub fn legend_rgba(width: u32) -> Vec<u8> {
        let ramp = FlipResult {
            errors: (0..width)
                .map(|i| i as f32 / (width.max(2) - 1) as f32)
                .collect(),
            width,
            height: 1,
            mean: 0.0,
        };
        ramp.heat_map_rgba()
    }

    /// The heat map ([`FlipResult::heat_map_rgba`]) as a PNG, written
    /// atomically to `path`.
    pub fn save_heat_map(&self, path: &Path) -> Result<(), ImageError> {
        write_png(path, self.width, self.height, &self.heat_map_rgba())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(w: u32, h: u32, f: impl Fn(u32, u32) -> [u8; 4]) -> Vec<u8> {
        let mut out = Vec::with_capacity((w * h * 4) as usize);
        for y in 0..h {
            for x in 0..w {
                out.extend(f(x, y));
            }
        }
        out
    }

    #[test]
    fn an_image_against_itself_is_zero_and_worse_images_score_worse() {
        let (w, h) = (64, 48);
        let reference = image(w, h, |x, y| [(x * 4) as u8, (y * 5) as u8, 128, 255]);
        assert_eq!(flip(&reference, &reference, w, h).unwrap().mean, 0.0);
        // A small blemish scores below a large one.
        let blemish = |r: u32| {
            image(w, h, |x, y| {
                let d = (x as i32 - 32).pow(2) + (y as i32 - 24).pow(2);
                if d < (r * r) as i32 {
                    [255, 255, 255, 255]
                } else {
                    [(x * 4) as u8, (y * 5) as u8, 128, 255]
                }
            })
        };
        let small = flip(&reference, &blemish(3), w, h).unwrap().mean;
        let large = flip(&reference, &blemish(12), w, h).unwrap().mean;
        assert!(0.0 < small && small < large, "{small} {large}");
        assert!(flip(&reference, &reference[4..], w, h).is_none());
    }
}
