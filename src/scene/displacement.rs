//! Displaced models (issue 40): per scene model a height map, a scale and a
//! bias (the scene's `displacement` key), and per model patch where each of
//! its edges and corners takes its displacement from.
//!
//! Why the latter: a displaced vertex is `P + n̂·d`, and two patches sharing
//! an edge share `P` there bit for bit (invariant 4) but not `n̂` or the
//! texture coordinates: the normal comes from each side's own cross-boundary
//! derivative, and at a UV seam the coordinates differ outright. So every
//! point on a shared edge is displaced by one **owner** of that edge, the
//! side with the least (patch, edge), at the owner's own parameters; every
//! shared corner by the owner of the corner point; a collapsed edge (a pole)
//! by its corner's owner, since it is one point. Both sides then evaluate
//! the same function on the same inputs. The edge tier of the criterion
//! bounds an edge's displacement from the owner's texture coordinates too,
//! so both sides still decide a shared edge identically.
//!
//! Records are in model-patch terms (u, v as the model has them) and shared
//! by every instance; a mirrored instance swaps u and v on the way in and
//! out (`glsl/common/displace.glsl` is the shaders' twin).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::constants::{DISPLACEMENT_HEADER_WORDS, DISPLACEMENT_MODEL_WORDS, PYRAMID_CELL_FLOATS};
use crate::input::error::SceneError;
use crate::patch::bezier::{BezierPatch, EDGE_BOTTOM, EDGE_LEFT, EDGE_RIGHT, EDGE_TOP};
pub use crate::patch::displace::ModelDisplacement;
use crate::patch::displace::{uv_curvature, HeightMap};
use crate::scene::instances::InstanceTable;
use crate::scene::texture::{invalid_map, read_png};

/// Owner records per model patch: 4 edges (`EDGE_*`), then 4 corners
/// ((0,0), (1,0), (1,1), (0,1)).
pub const OWNER_WORDS: usize = crate::constants::OWNER_WORDS as usize;
pub use crate::constants::{OWNER_COLLAPSED, OWNER_INDEX_MASK, OWNER_PATCH_SHIFT, OWNER_REVERSED};
/// The largest height map side accepted.
pub const MAX_HEIGHT_MAP_SIDE: u32 = 8192;

/// A model's displacement as the scene file gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplacementDesc {
    /// The height map (PNG, power-of-two sides; grey, or the luma of colour).
    pub map: PathBuf,
    /// World units per unit of height.
    pub scale: f32,
    /// World units added to every height's displacement.
    pub bias: f32,
}

impl DisplacementDesc {
    /// The largest |displacement| (see [`ModelDisplacement::margin`]).
    pub fn margin(&self) -> f32 {
        ModelDisplacement {
            map: 0,
            scale: self.scale,
            bias: self.bias,
        }
        .margin()
    }
}

/// Reads a height map: a PNG whose sides are powers of two, as 16-bit grey
/// (colour is reduced to its luma), heights `grey / 65535`, rows flipped so
/// t = 0 is the image's bottom row (as albedo maps are read).
pub fn load_height_map(path: &Path) -> Result<HeightMap, SceneError> {
    let image = read_png(path, "height map")?.to_luma16();
    let (w, h) = image.dimensions();
    if !w.is_power_of_two() || !h.is_power_of_two() || w.max(h) > MAX_HEIGHT_MAP_SIDE {
        return Err(invalid_map(
            path,
            format!(
                "height map of {w}x{h} texels: its sides must be powers of two, at most \
                 {MAX_HEIGHT_MAP_SIDE} (so its min/max pyramid wraps exactly)"
            ),
        ));
    }
    let mut heights = Vec::with_capacity((w * h) as usize);
    for y in (0..h).rev() {
        for x in 0..w {
            heights.push(image.get_pixel(x, y).0[0] as f32 / 65535.0);
        }
    }
    Ok(HeightMap::new(w, h, heights))
}

/// A scene's displacement: the maps, each model's settings and the owner
/// records (empty when no model is displaced).
#[derive(Clone, Debug, Default)]
pub struct SceneDisplacement {
    /// Each height map once, with the file it came from.
    pub maps: Vec<(PathBuf, HeightMap)>,
    /// Per scene model, in scene order.
    pub models: Vec<Option<ModelDisplacement>>,
    /// Per model patch (`InstanceTable::patches`): [`OWNER_WORDS`] words.
    pub owners: Vec<[u32; OWNER_WORDS]>,
    /// Per model patch: its UV patch's second-derivative bounds
    /// ([`uv_curvature`]).
    pub uv_curvature: Vec<[f32; 2]>,
    /// The most texels a displaced model patch spans along u or v (its UV
    /// net's polygon, which bounds the curve's length): what a uniform grid
    /// per patch must resolve to sample the maps ([`Self::resolving_grid`]).
    pub texel_span: f32,
}

impl SceneDisplacement {
    /// Whether some model is displaced.
    pub fn in_use(&self) -> bool {
        self.models.iter().any(Option::is_some)
    }

    /// The index of the map read from `path`, loading it on first use.
    pub fn map_index(&mut self, path: &Path) -> Result<usize, SceneError> {
        if let Some(k) = self.maps.iter().position(|(p, _)| p == path) {
            return Ok(k);
        }
        self.maps.push((path.to_path_buf(), load_height_map(path)?));
        Ok(self.maps.len() - 1)
    }

    /// Fills the owner records and UV bounds for the table's model patches
    /// (after every model is placed).
    pub fn finish(&mut self, table: &InstanceTable, uv_patches: &[[[f32; 2]; 16]]) {
        if !self.in_use() {
            return;
        }
        self.owners = owners(table);
        self.uv_curvature = uv_patches.iter().map(uv_curvature).collect();
        self.texel_span = 0.0;
        for t in &table.instances {
            let model = (t.flags >> crate::constants::PATCH_MODEL_SHIFT) as usize;
            let Some(Some(d)) = self.models.get(model) else {
                continue;
            };
            let map = &self.maps[d.map].1;
            let texels = [map.width as f32, map.height as f32];
            for uv in &uv_patches[t.source as usize..(t.source + t.count) as usize] {
                self.texel_span = self.texel_span.max(net_span(uv, texels));
            }
        }
    }

    /// The power-of-two grid per patch side that puts at least two samples
    /// in every texel a displaced patch spans (1 when nothing is displaced).
    pub fn resolving_grid(&self) -> u32 {
        ((2.0 * self.texel_span).ceil() as u32)
            .max(1)
            .next_power_of_two()
    }
}

/// The longest row or column of a UV net's control polygon, in texels.
fn net_span(uv: &[[f32; 2]; 16], texels: [f32; 2]) -> f32 {
    let length =
        |a: [f32; 2], b: [f32; 2]| ((a[0] - b[0]) * texels[0]).hypot((a[1] - b[1]) * texels[1]);
    let mut span = 0.0f32;
    for j in 0..4 {
        let row: f32 = (0..3)
            .map(|i| length(uv[4 * j + i], uv[4 * j + i + 1]))
            .sum();
        let column: f32 = (0..3)
            .map(|i| length(uv[j + 4 * i], uv[j + 4 * i + 4]))
            .sum();
        span = span.max(row).max(column);
    }
    span
}

impl SceneDisplacement {
    /// How many words [`SceneDisplacement::gpu_words`] makes.
    pub fn gpu_words_len(&self) -> u64 {
        if !self.in_use() {
            return 1;
        }
        let maps: usize = self
            .maps
            .iter()
            .map(|(_, m)| {
                m.heights.len()
                    + PYRAMID_CELL_FLOATS as usize * m.pyramid.iter().map(Vec::len).sum::<usize>()
            })
            .sum();
        (DISPLACEMENT_HEADER_WORDS as usize
            + self.models.len() * DISPLACEMENT_MODEL_WORDS as usize
            + self.owners.len() * OWNER_WORDS
            + 2 * self.uv_curvature.len()
            + maps) as u64
    }

    /// Set 0's BIND_DISPLACEMENT words (see the constant's comment): one
    /// placeholder word for a scene without displacement.
    pub fn gpu_words(&self) -> Vec<u32> {
        if !self.in_use() {
            return vec![0];
        }
        let header = DISPLACEMENT_HEADER_WORDS as usize;
        let records = self.models.len() * DISPLACEMENT_MODEL_WORDS as usize;
        let owners_at = header + records;
        let curvature_at = owners_at + self.owners.len() * OWNER_WORDS;
        let mut maps_at = curvature_at + 2 * self.uv_curvature.len();
        let mut map_words = Vec::new();
        let mut placed = Vec::new();
        for (_, map) in &self.maps {
            let heights = maps_at;
            let pyramid = heights + map.heights.len();
            let cells: usize = map.pyramid.iter().map(Vec::len).sum();
            maps_at = pyramid + PYRAMID_CELL_FLOATS as usize * cells;
            placed.push((heights, pyramid, map.pyramid.len()));
            map_words.extend(map.heights.iter().map(|h| h.to_bits()));
            for level in &map.pyramid {
                map_words.extend(level.iter().flatten().map(|x| x.to_bits()));
            }
        }
        let mut w = vec![
            owners_at as u32,
            curvature_at as u32,
            self.models.len() as u32,
            0,
        ];
        for m in &self.models {
            match m {
                Some(m) => {
                    let (heights, pyramid, levels) = placed[m.map];
                    let map = &self.maps[m.map].1;
                    w.extend([
                        heights as u32,
                        map.width,
                        map.height,
                        pyramid as u32,
                        levels as u32,
                        m.scale.to_bits(),
                        m.bias.to_bits(),
                        m.margin().to_bits(),
                    ]);
                }
                None => w.extend([0; DISPLACEMENT_MODEL_WORDS as usize]),
            }
        }
        w.extend(self.owners.iter().flatten());
        w.extend(self.uv_curvature.iter().flatten().map(|x| x.to_bits()));
        w.extend(map_words);
        w
    }
}

/// The ranges of model patches that belong to one import (owners are never
/// looked for across them).
fn model_ranges(table: &InstanceTable) -> Vec<std::ops::Range<usize>> {
    let mut ranges: Vec<_> = table
        .instances
        .iter()
        .map(|t| t.source as usize..(t.source + t.count) as usize)
        .collect();
    ranges.sort_by_key(|r| (r.start, r.end));
    ranges.dedup();
    ranges
}

fn bits(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

/// The corner points of a patch, in owner-record order.
fn corners(p: &BezierPatch) -> [Vec3; 4] {
    [p.at(0, 0), p.at(3, 0), p.at(3, 3), p.at(0, 3)]
}

/// Every model patch's owner records: per import, the least (patch, edge)
/// holding an edge's control points (either way round) owns it, the least
/// (patch, corner) holding a corner point owns it.
pub fn owners(table: &InstanceTable) -> Vec<[u32; OWNER_WORDS]> {
    let mut out = vec![[0u32; OWNER_WORDS]; table.patches.len()];
    for range in model_ranges(table) {
        let mut edge_owner: HashMap<[u32; 12], (usize, usize, bool)> = HashMap::new();
        let mut corner_owner: HashMap<[u32; 3], (usize, usize)> = HashMap::new();
        for k in range.clone() {
            let p = &table.patches[k];
            for e in 0..4 {
                let (key, reversed) = edge_key(&p.edge(e));
                edge_owner.entry(key).or_insert((k, e, reversed));
            }
            for (c, q) in corners(p).into_iter().enumerate() {
                corner_owner.entry(bits(q)).or_insert((k, c));
            }
        }
        for k in range {
            let p = &table.patches[k];
            for (e, word) in out[k][..4].iter_mut().enumerate() {
                let c = p.edge(e);
                let (key, reversed) = edge_key(&c);
                let (o, oe, orev) = edge_owner[&key];
                let collapsed = c.iter().all(|q| bits(*q) == bits(c[0]));
                *word = (o as u32) << OWNER_PATCH_SHIFT
                    | oe as u32
                    | if reversed != orev { OWNER_REVERSED } else { 0 }
                    | if collapsed { OWNER_COLLAPSED } else { 0 };
            }
            for (c, q) in corners(p).into_iter().enumerate() {
                let (o, oc) = corner_owner[&bits(q)];
                out[k][4 + c] = (o as u32) << OWNER_PATCH_SHIFT | oc as u32;
            }
        }
    }
    out
}

/// The key of a boundary curve (its control points' bits, in the lesser of
/// its two directions) and whether that is the curve reversed.
fn edge_key(c: &[Vec3; 4]) -> ([u32; 12], bool) {
    let key = |pts: [Vec3; 4]| -> [u32; 12] {
        let mut k = [0u32; 12];
        for (i, p) in pts.iter().enumerate() {
            k[3 * i..3 * i + 3].copy_from_slice(&bits(*p));
        }
        k
    };
    let fwd = key(*c);
    let rev = key([c[3], c[2], c[1], c[0]]);
    if rev < fwd {
        (rev, true)
    } else {
        (fwd, false)
    }
}

/// The parameter along edge `e`'s counter-clockwise direction of its point
/// (u, v) (exact for the dyadic parameters nodes have).
#[inline]
pub fn edge_param(e: usize, u: f32, v: f32) -> f32 {
    match e {
        EDGE_BOTTOM => u,
        EDGE_RIGHT => v,
        EDGE_TOP => 1.0 - u,
        _ => 1.0 - v,
    }
}

/// The point of edge `e` at counter-clockwise parameter `s`.
#[inline]
pub fn edge_point(e: usize, s: f32) -> (f32, f32) {
    match e {
        EDGE_BOTTOM => (s, 0.0),
        EDGE_RIGHT => (1.0, s),
        EDGE_TOP => (1.0 - s, 1.0),
        _ => (0.0, 1.0 - s),
    }
}

/// Corner `c`'s parameters.
#[inline]
pub fn corner_point(c: usize) -> (f32, f32) {
    [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)][c]
}

/// The corner at (u, v), if it is one.
#[inline]
fn corner_at(u: f32, v: f32) -> Option<usize> {
    match (u, v) {
        (0.0, 0.0) => Some(0),
        (1.0, 0.0) => Some(1),
        (1.0, 1.0) => Some(2),
        (0.0, 1.0) => Some(3),
        _ => None,
    }
}

/// The edge (u, v) lies on (not at a corner), if any.
#[inline]
fn edge_at(u: f32, v: f32) -> Option<usize> {
    if v == 0.0 {
        Some(EDGE_BOTTOM)
    } else if u == 1.0 {
        Some(EDGE_RIGHT)
    } else if v == 1.0 {
        Some(EDGE_TOP)
    } else if u == 0.0 {
        Some(EDGE_LEFT)
    } else {
        None
    }
}

/// Where model patch `k`'s point (u, v) takes its displacement from: the
/// owning model patch and the point's parameters there.
pub fn owner_of(owners: &[[u32; OWNER_WORDS]], k: usize, u: f32, v: f32) -> (usize, f32, f32) {
    let rec = &owners[k];
    let corner = |c: usize| {
        let w = rec[4 + c];
        let (u, v) = corner_point((w & OWNER_INDEX_MASK) as usize);
        ((w >> OWNER_PATCH_SHIFT) as usize, u, v)
    };
    if let Some(c) = corner_at(u, v) {
        return corner(c);
    }
    let Some(e) = edge_at(u, v) else {
        return (k, u, v);
    };
    let w = rec[e];
    if w & OWNER_COLLAPSED != 0 {
        return corner(e);
    }
    let s = edge_param(e, u, v);
    let s = if w & OWNER_REVERSED != 0 { 1.0 - s } else { s };
    let (u, v) = edge_point((w & OWNER_INDEX_MASK) as usize, s);
    ((w >> OWNER_PATCH_SHIFT) as usize, u, v)
}
