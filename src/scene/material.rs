//! What a scene's surfaces are coloured with, beside its geometry: a UV
//! patch per model patch (the cage's texture coordinates through the
//! conversion, `cage::uv`; the patch's own (u, v) for a model without
//! them, which is the teapot's parametric mapping) and per model an albedo
//! map or none. Set 0 holds them as three buffers (`gpu::scene`): the UV
//! patches, a record per model, and every map's mip chain.

use std::path::PathBuf;

use super::texture::Texture;
use crate::cage::uv::UvPatch;
use crate::constants::MATERIAL_WORDS;
use crate::patch::bezier::curve;

/// The UV patch of a model without texture coordinates: the patch's own
/// parameters, (u, v) at every point (control points i/3, j/3).
pub fn parametric_uv_patch() -> UvPatch {
    std::array::from_fn(|k| [(k % 4) as f32 / 3.0, (k / 4) as f32 / 3.0])
}

/// UV patch `p` at (u, v): rows at u, then the column at v, in the
/// patches' own operation order (`patch::bezier::curve`; the shaders'
/// `eval_patch2` is its twin).
pub fn eval_uv_patch(p: &UvPatch, u: f32, v: f32) -> [f32; 2] {
    let point = |k: usize| glam::Vec2::from(p[k]);
    let rows: [glam::Vec2; 4] = std::array::from_fn(|j| {
        curve(
            u,
            &[
                point(4 * j),
                point(4 * j + 1),
                point(4 * j + 2),
                point(4 * j + 3),
            ],
        )
    });
    curve(v, &rows).to_array()
}

/// A scene's UV patches and albedo maps.
#[derive(Clone, Debug, Default)]
pub struct SceneMaterials {
    /// Per scene model, in scene order: the index of its albedo map in
    /// `textures`, if it has one.
    pub model_texture: Vec<Option<usize>>,
    /// Per model patch (the instance table's order): its UV patch.
    pub uv_patches: Vec<UvPatch>,
    /// Model patches whose UV patch comes from the cage's texture
    /// coordinates (the rest are parametric).
    pub cage_uv_patches: usize,
    /// The albedo maps, each file once.
    pub textures: Vec<Texture>,
}

impl SceneMaterials {
    /// Whether anything here changes how the scene is drawn: a map, or
    /// UVs from a cage (the UV view shows them). A scene without either
    /// binds placeholders and its pipelines carry no texturing code.
    pub fn in_use(&self) -> bool {
        !self.textures.is_empty() || self.cage_uv_patches > 0
    }

    /// The index of the map read from `path`, loading it on first use.
    pub fn texture_index(&mut self, path: &PathBuf) -> Result<usize, crate::input::SceneError> {
        if let Some(k) = self.textures.iter().position(|t| t.path == *path) {
            return Ok(k);
        }
        self.textures.push(Texture::load(path)?);
        Ok(self.textures.len() - 1)
    }

    /// Set 0's material records: MATERIAL_WORDS per scene model (the
    /// first word of its map's level 0 in [`SceneMaterials::texel_words`],
    /// width, height, levels; width 0 for a model without a map).
    pub fn material_words(&self) -> Vec<u32> {
        let mut starts = Vec::with_capacity(self.textures.len());
        let mut at = 0u32;
        for t in &self.textures {
            starts.push(at);
            at += t.words() as u32;
        }
        let mut words = Vec::with_capacity(self.model_texture.len() * MATERIAL_WORDS as usize);
        for m in &self.model_texture {
            match m {
                Some(k) => {
                    let t = &self.textures[*k];
                    words.extend([starts[*k], t.width, t.height, t.levels.len() as u32]);
                }
                None => words.extend([0; MATERIAL_WORDS as usize]),
            }
        }
        if words.is_empty() {
            words.extend([0; MATERIAL_WORDS as usize]);
        }
        words
    }

    /// Words [`SceneMaterials::texel_words`] holds.
    pub fn texel_words_len(&self) -> u64 {
        self.textures
            .iter()
            .map(|t| t.words() as u64)
            .sum::<u64>()
            .max(1)
    }

    /// Every map's levels, map after map, largest level first.
    pub fn texel_words(&self) -> Vec<u32> {
        let mut words: Vec<u32> = self
            .textures
            .iter()
            .flat_map(|t| t.levels.iter().flatten().copied())
            .collect();
        if words.is_empty() {
            words.push(0);
        }
        words
    }

    /// The UV patches as floats, (s, t) per control point, u fastest.
    pub fn uv_floats(&self) -> Vec<f32> {
        if self.uv_patches.is_empty() {
            return vec![0.0; 32];
        }
        self.uv_patches
            .iter()
            .flatten()
            .flatten()
            .copied()
            .collect()
    }

    /// Bytes on the GPU: UV patches, records and texels.
    pub fn bytes(&self) -> u64 {
        4 * (self.uv_patches.len() * 32
            + self.model_texture.len() * MATERIAL_WORDS as usize
            + self.textures.iter().map(Texture::words).sum::<usize>()) as u64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_parametric_patch_is_the_identity_map() {
        let p = parametric_uv_patch();
        let s = eval_uv_patch(&p, 0.3, 0.8);
        assert!(
            (s[0] - 0.3).abs() < 1e-6 && (s[1] - 0.8).abs() < 1e-6,
            "{s:?}"
        );
    }

    #[test]
    fn records_point_at_each_maps_levels() {
        let t = |name: &str, w: u32, h: u32| {
            Texture::from_rgba(PathBuf::from(name), w, h, vec![0; (w * h) as usize])
        };
        let m = SceneMaterials {
            model_texture: vec![None, Some(1), Some(0)],
            uv_patches: Vec::new(),
            cage_uv_patches: 0,
            textures: vec![t("a", 2, 2), t("b", 4, 1)],
        };
        // a: 4 + 1 words; b: 4 + 2 + 1.
        assert_eq!(m.material_words(), [0, 0, 0, 0, 5, 4, 1, 3, 0, 2, 2, 2]);
        assert_eq!(m.texel_words().len(), 12);
    }
}
