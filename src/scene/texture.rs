//! Albedo maps: a PNG read through the `image` crate, its mip chain made
//! on the host in linear light, and every level packed as sRGB-encoded
//! RGBA8 words for set 0's texel buffer (`glsl/common/texture.glsl`
//! samples it).
//!
//! Why a storage buffer and fetches rather than a sampled image: every
//! method's fragment shading reads set 0, which is all buffers, so the
//! passes' reflection-derived barriers cover the map with nothing new; and
//! the filtering is the shaders' own arithmetic, the same on every device,
//! so FLIP compares the methods on a textured scene without a driver's
//! filtering between them (issue 40 needs fetches for displacement anyway).

use std::path::{Path, PathBuf};

use crate::input::error::SceneError;

/// The largest side accepted: 8192 texels (a mip chain of 8192² is 341 MiB
/// of words, more than any scene here needs and than some devices bind).
pub const MAX_TEXTURE_SIDE: u32 = 8192;

/// A mip-mapped albedo map: level 0 is the file's pixels, each next level
/// half the size (rounded down, at least 1), down to 1×1.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// The file it was read from.
    pub path: PathBuf,
    /// Level 0's width in texels.
    pub width: u32,
    /// Level 0's height in texels.
    pub height: u32,
    /// The levels, largest first: sRGB-encoded RGBA8 words (red in the low
    /// byte), rows top to bottom as in the file.
    pub levels: Vec<Vec<u32>>,
}

impl Texture {
    /// Reads `path` (PNG) and makes its mip chain. A missing, unreadable or
    /// undecodable file, or one beyond [`MAX_TEXTURE_SIDE`], is an error
    /// naming the file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let image = read_png(path, "texture")?.to_rgba8();
        let (width, height) = image.dimensions();
        if width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(invalid_map(
                path,
                format!("texture of {width}x{height} texels: at most {MAX_TEXTURE_SIDE} on a side"),
            ));
        }
        let words = image.pixels().map(|p| u32::from_le_bytes(p.0)).collect();
        Ok(Self::from_rgba(path.to_path_buf(), width, height, words))
    }

    /// The texture of `words` (level 0, sRGB-encoded RGBA8, `width` ×
    /// `height`, both ≥ 1) with its mip chain.
    pub fn from_rgba(path: PathBuf, width: u32, height: u32, words: Vec<u32>) -> Self {
        assert_eq!(words.len(), (width * height) as usize, "texel count");
        let mut levels = vec![words];
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let next = half_level(levels.last().expect("level 0"), w, h);
            w = (w / 2).max(1);
            h = (h / 2).max(1);
            levels.push(next);
        }
        Self {
            path,
            width,
            height,
            levels,
        }
    }

    /// Words in all levels.
    pub fn words(&self) -> usize {
        self.levels.iter().map(Vec::len).sum()
    }
}

/// Decodes the PNG at `path` (a `what`: texture, height map); a missing,
/// unreadable or undecodable file is an error naming it.
pub fn read_png(path: &Path, what: &str) -> Result<image::DynamicImage, SceneError> {
    let bytes = std::fs::read(path).map_err(|cause| SceneError::Io {
        path: path.to_path_buf(),
        cause,
    })?;
    image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
        .map_err(|e| invalid_map(path, format!("not a readable PNG {what}: {e}")))
}

/// The error for a map at `path` that cannot be used.
pub fn invalid_map(path: &Path, msg: String) -> SceneError {
    SceneError::Invalid {
        path: path.to_path_buf(),
        msg,
    }
}

/// The level below `texels` (`w` × `h`): each texel the mean, in linear
/// light, of the 2×2 (or, along a side of 1, 1×2) block above it; an odd
/// side's last row or column is dropped, as GPUs' mip chains do.
fn half_level(texels: &[u32], w: u32, h: u32) -> Vec<u32> {
    let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
    let mut out = Vec::with_capacity((nw * nh) as usize);
    for y in 0..nh {
        for x in 0..nw {
            let xs = [(2 * x).min(w - 1), (2 * x + 1).min(w - 1)];
            let ys = [(2 * y).min(h - 1), (2 * y + 1).min(h - 1)];
            let mut sum = [0.0f32; 4];
            for &yy in &ys {
                for &xx in &xs {
                    let t = texels[(yy * w + xx) as usize].to_le_bytes();
                    for c in 0..3 {
                        sum[c] += srgb_to_linear(t[c]);
                    }
                    sum[3] += f32::from(t[3]) / 255.0;
                }
            }
            let mut t = [0u8; 4];
            for c in 0..3 {
                t[c] = linear_to_srgb(sum[c] / 4.0);
            }
            t[3] = (sum[3] / 4.0 * 255.0).round() as u8;
            out.push(u32::from_le_bytes(t));
        }
    }
    out
}

/// An sRGB-encoded byte in linear light (0..1).
pub fn srgb_to_linear(c: u8) -> f32 {
    let s = f32::from(c) / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// A linear value (0..1) as an sRGB-encoded byte.
pub fn linear_to_srgb(l: f32) -> u8 {
    let l = l.clamp(0.0, 1.0);
    let s = if l <= 0.003_130_8 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    (s * 255.0).round() as u8
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgba(r: u8, g: u8, b: u8) -> u32 {
        u32::from_le_bytes([r, g, b, 255])
    }

    #[test]
    fn mip_chain_halves_down_to_one_texel() {
        let t = Texture::from_rgba(PathBuf::new(), 5, 2, vec![rgba(0, 0, 0); 10]);
        let sizes: Vec<usize> = t.levels.iter().map(Vec::len).collect();
        assert_eq!(sizes, [10, 2, 1]);
        assert_eq!(t.words(), 13);
    }

    #[test]
    fn levels_average_in_linear_light() {
        // Black and white average to linear 0.5, sRGB 188, not 128.
        let t = Texture::from_rgba(
            PathBuf::new(),
            2,
            1,
            vec![rgba(0, 0, 0), rgba(255, 255, 255)],
        );
        assert_eq!(t.levels[1], [rgba(188, 188, 188)]);
    }

    #[test]
    fn srgb_round_trips_every_byte() {
        for c in 0..=255u8 {
            assert_eq!(linear_to_srgb(srgb_to_linear(c)), c);
        }
    }

    #[test]
    fn a_missing_or_broken_file_names_itself() {
        let dir = std::env::temp_dir().join(format!("bs-texture-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let missing = dir.join("missing.png");
        let e = Texture::load(&missing).unwrap_err().to_string();
        assert!(e.contains("missing.png"), "{e}");
        let broken = dir.join("broken.png");
        std::fs::write(&broken, b"not a png").unwrap();
        let e = Texture::load(&broken).unwrap_err().to_string();
        assert!(e.contains("broken.png") && e.contains("PNG"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
