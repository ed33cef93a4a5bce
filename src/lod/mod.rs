//! Levels of detail below one patch (issue 41): far instances drawn from a
//! simplified triangle mesh of their model's limit surface instead of from
//! patches, so a frame of many small, distant models costs about what its
//! pixels need rather than two triangles per patch.
//!
//! Why triangle meshes and not coarser patches: a patch set fitted over
//! groups of patches must share edge curves across groups to stay
//! watertight, which means refitting the cage; the limit surface on a
//! uniform grid, welded where patches meet ([`mesh::limit_mesh`]) and
//! simplified with meshoptimizer (edge collapses under a quadric error,
//! which never open the mesh), is closed wherever the model is and keeps
//! that through every collapse. Each level's error against the limit
//! surface is *measured* ([`error`]), both ways, not taken from the
//! simplifier; its vertex normals are fitted to the surface its triangles
//! stand for and their error measured too, at every point and seen through
//! footprints of growing size ([`shading`]): an instance takes a level only
//! where its shading at the instance's distance is within a bound
//! ([`MOST_NORMAL_ERROR`]).
//!
//! An instance is drawn whole from one level or whole from patches
//! ([`select`]), so no crack can open inside it: the levels are separate
//! objects as the instances already are.

pub mod cache;
pub mod constants;
pub mod error;
pub mod gpu;
pub mod mesh;
pub mod select;
pub mod shading;

use std::collections::HashMap;

use glam::Vec3;

use crate::constants::{LOD_VERTEX_WORDS, PATCH_MODEL_SHIFT, PATCH_RATIONAL, PATCH_TWO_SIDED};
use crate::patch::bezier::BezierPatch;
use crate::scene::geometry::SceneGeometry;
use crate::scene::material::eval_uv_patch;
use mesh::TriMesh;

/// Cells per patch side of the welded mesh the levels are simplified from.
pub const SOURCE_GRID: usize = 8;
/// Cells per patch side of the dense mesh that stands for the limit surface
/// when the levels' own points are measured against it.
pub const PROXY_GRID: usize = 16;
/// Bytes a level vertex takes on the GPU (`LOD_VERTEX_WORDS` words:
/// position, octahedral normal, texture coordinates).
pub const VERTEX_BYTES: u64 = LOD_VERTEX_WORDS as u64 * 4;
/// Bytes a level triangle takes on the GPU (three u32 indices).
pub const TRIANGLE_BYTES: u64 = 12;
/// Bytes a base patch takes on the GPU (16 points of 3 floats).
pub const PATCH_BYTES: u64 = 192;
/// The simplifier's targets, as fractions of the model's box diagonal,
/// finest first: from 2⁻¹⁰ to 2⁻⁴ in steps of √2 (a coarser level is
/// chosen at √2 times less distance than the one before it).
pub fn targets() -> impl Iterator<Item = f32> {
    (0..=12).map(|k| (2.0f32).powf(-10.0 + 0.5 * k as f32))
}

/// A level is kept only if it has at most this share of the triangles of
/// the finer one kept before it (else it is nearly the same cost).
pub const KEEP_RATIO: f32 = 0.8;

/// A level is kept only if it has fewer triangles than this many per base
/// patch: the patches draw at least two each (one quad), so a level with
/// more never draws an instance cheaper than its patches do where both
/// are within ε.
pub const MOST_TRIANGLES_PER_PATCH: usize = 2;

/// The most shading error a level may show at an instance's distance
/// (radians, 7°; [`Level::shading_error`]) unless told otherwise
/// (`--lod-shading`): ε bounds a level's geometry, not its lighting, and a
/// coarse level of a model with narrow rounded edges (the kitchen's
/// sideboard, its books) loses their highlights up close. 7° keeps the
/// car's levels the herd needs (0.29× its triangles) and the kitchen's
/// FLIP within 7 % of its patches'; 5° costs the herd 0.33×, 10° the
/// kitchen +18 % (docs/BENCHMARKS.md). A level over it even through the
/// largest footprint measured is not kept.
pub const MOST_NORMAL_ERROR: f32 = MOST_NORMAL_ERROR_DEG * std::f32::consts::PI / 180.0;

/// [`MOST_NORMAL_ERROR`] in degrees, as `--lod-shading` takes it.
pub const MOST_NORMAL_ERROR_DEG: f32 = 7.0;

/// One level of a model.
#[derive(Clone, Debug)]
pub struct Level {
    /// The simplified mesh, its vertices compacted to those it uses.
    pub mesh: TriMesh,
    /// Its distance from the limit surface, in model units, measured both
    /// ways ([`measured_error`]).
    pub error: f32,
    /// How far its shading normals lie from the surface's: the
    /// area-weighted mean angle, in radians ([`error::normal_error`]).
    pub normal_error: f32,
    /// The same seen through footprints of growing side: (side in model
    /// units, error in radians), finest first ([`shading::measure`]).
    pub shading: Vec<(f32, f32)>,
    /// What the simplifier was asked for, in model units.
    pub target: f32,
    /// What the simplifier says it reached, in model units.
    pub simplifier_error: f32,
}

impl Level {
    /// Its shading error seen through a footprint `side` model units
    /// across ([`shading::error_at`]).
    pub fn shading_error(&self, side: f32) -> f32 {
        shading::error_at(&self.shading, self.normal_error, side)
    }

    /// GPU bytes of its vertices and indices.
    pub fn bytes(&self) -> u64 {
        self.mesh.positions.len() as u64 * VERTEX_BYTES
            + self.mesh.triangles() as u64 * TRIANGLE_BYTES
    }
}

/// The levels of one model (a range of model patches), finest first.
#[derive(Clone, Debug)]
pub struct ModelLevels {
    /// The model's first model patch.
    pub source: u32,
    /// Its number of patches.
    pub count: u32,
    /// The levels, finest first; empty where the model gets none.
    pub levels: Vec<Level>,
    /// Why it has none, if so.
    pub none_because: Option<&'static str>,
}

impl ModelLevels {
    /// GPU bytes of its base patches.
    pub fn patch_bytes(&self) -> u64 {
        u64::from(self.count) * PATCH_BYTES
    }

    /// GPU bytes of all its levels.
    pub fn level_bytes(&self) -> u64 {
        self.levels.iter().map(Level::bytes).sum()
    }
}

/// Every model's levels.
#[derive(Clone, Debug)]
pub struct SceneLevels {
    /// By first model patch, in the order the instances first name them.
    pub models: Vec<ModelLevels>,
    /// The most shading error (radians) a level may show at an instance's
    /// distance ([`Level::shading_error`]).
    pub most_normal_error: f32,
    by_source: HashMap<u32, usize>,
}

impl Default for SceneLevels {
    fn default() -> Self {
        Self {
            models: Vec::new(),
            most_normal_error: MOST_NORMAL_ERROR,
            by_source: HashMap::new(),
        }
    }
}

impl SceneLevels {
    /// The levels of every model `geo`'s instances place. Rational and
    /// displaced models get none (the welded mesh would be of the wrong
    /// surface), nor does a scene's PN-triangle model (not patches).
    pub fn build(geo: &SceneGeometry) -> Self {
        Self::build_with(geo, MOST_NORMAL_ERROR)
    }

    /// [`SceneLevels::build`] under the shading bound `most_normal_error`
    /// (radians): levels over it even through the largest footprint are
    /// not kept, and [`select::choose`] holds the others to it at each
    /// instance's distance.
    pub fn build_with(geo: &SceneGeometry, most_normal_error: f32) -> Self {
        Self::build_cached(geo, most_normal_error, None)
    }

    /// [`SceneLevels::build_with`], each model's levels read from `cache`
    /// where it has them, else made and stored there.
    pub fn build_cached(
        geo: &SceneGeometry,
        most_normal_error: f32,
        cache: Option<&cache::LevelCache>,
    ) -> Self {
        // The table the GPU is given (a geometry cut or edited after
        // loading is uploaded as one identity instance).
        let table = geo
            .instances
            .or_identity(&geo.patches, &geo.flags, &geo.weights);
        let mut out = SceneLevels {
            most_normal_error,
            ..Default::default()
        };
        for t in &table.instances {
            if out.by_source.contains_key(&t.source) {
                continue;
            }
            let range = t.source as usize..(t.source + t.count) as usize;
            let model = (t.flags >> PATCH_MODEL_SHIFT) as usize;
            let rational = table.flags[range.clone()]
                .iter()
                .any(|f| f & PATCH_RATIONAL != 0);
            let two_sided = (t.flags | table.flags[range.start]) & PATCH_TWO_SIDED != 0;
            let displaced = geo
                .displacement
                .models
                .get(model)
                .is_some_and(Option::is_some);
            let none_because = if rational {
                Some("rational patches")
            } else if displaced {
                Some("displaced")
            } else {
                None
            };
            let levels = match none_because {
                Some(_) => Vec::new(),
                None => {
                    let uv = &geo.materials.uv_patches;
                    let first = t.source as usize;
                    let st = |k: usize, u: f32, v: f32| match uv.get(first + k) {
                        Some(p) => eval_uv_patch(p, u, v),
                        None => [u, v],
                    };
                    let patches = &table.patches[range];
                    let make = || model_levels(patches, &st, two_sided, most_normal_error);
                    match cache {
                        Some(c) => c.levels(patches, &st, two_sided, most_normal_error, make),
                        None => make(),
                    }
                }
            };
            out.by_source.insert(t.source, out.models.len());
            out.models.push(ModelLevels {
                source: t.source,
                count: t.count,
                levels,
                none_because,
            });
        }
        out
    }

    /// The index in [`Self::models`] of the model starting at model patch
    /// `source`.
    pub fn model_of(&self, source: u32) -> Option<usize> {
        self.by_source.get(&source).copied()
    }

    /// GPU bytes of the base patches of the models with levels, and of
    /// their levels.
    pub fn bytes(&self) -> (u64, u64) {
        let with = self.models.iter().filter(|m| !m.levels.is_empty());
        with.fold((0, 0), |(p, l), m| {
            (p + m.patch_bytes(), l + m.level_bytes())
        })
    }
}

/// The levels of one model's patches, finest first; `st(k, u, v)` the
/// texture coordinates of its patch k at (u, v); `two_sided`: the model is
/// lit from the side it is seen from (its normal error then ignores
/// orientation); levels whose normal error exceeds `most_normal_error`
/// (radians; [`MOST_NORMAL_ERROR`] for a scene) are not kept.
pub fn model_levels(
    patches: &[BezierPatch],
    st: &dyn Fn(usize, f32, f32) -> [f32; 2],
    two_sided: bool,
    most_normal_error: f32,
) -> Vec<Level> {
    let Some((lo, hi)) = BezierPatch::bounds(patches) else {
        return Vec::new();
    };
    let diagonal = (hi - lo).length();
    let source = mesh::limit_mesh(patches, SOURCE_GRID, st);
    let proxy = mesh::limit_mesh(patches, PROXY_GRID, &mesh::plain_uv);
    // The proxy's own distance from the surface, added to every distance
    // measured against it.
    let proxy_error = error::grid_error(patches, PROXY_GRID);
    let surface = error::surface_samples(patches, 2 * SOURCE_GRID);
    let normals = error::surface_normals(patches, 2 * SOURCE_GRID);
    let mut levels: Vec<Level> = Vec::new();
    let mut finer = MOST_TRIANGLES_PER_PATCH * patches.len();
    for fraction in targets() {
        let target = fraction * diagonal;
        let (mut mesh, simplifier_error) = simplify(&source, target);
        if mesh.triangles() == 0 || mesh.triangles() as f32 >= KEEP_RATIO * finer as f32 {
            continue;
        }
        error::fit_normals(&mut mesh, &normals);
        let shading::Shading {
            unfiltered: normal_error,
            by_scale: shading,
        } = shading::measure(&normals, &mesh, two_sided, shading::FINEST * diagonal);
        let level_shading = |side| shading::error_at(&shading, normal_error, side);
        // Shaded too far from the surface even seen from the farthest
        // scale measured: no distance would take it.
        if level_shading(f32::INFINITY) > most_normal_error {
            continue;
        }
        finer = mesh.triangles();
        let error = measured_error(&surface, &mesh, &proxy, proxy_error);
        levels.push(Level {
            mesh,
            error,
            normal_error,
            shading,
            target,
            simplifier_error,
        });
    }
    levels
}

/// How many of `level`'s open edges lie where its model (`model`, of the
/// scene `geo`) is closed ([`TriMesh::edges_opened_from`] against the
/// welded mesh the level was simplified from): the hole test of a level
/// too small on screen for the pixel test.
pub fn edges_opened(geo: &SceneGeometry, model: &ModelLevels, level: &Level) -> usize {
    let table = geo
        .instances
        .or_identity(&geo.patches, &geo.flags, &geo.weights);
    let range = model.source as usize..(model.source + model.count) as usize;
    let source = mesh::limit_mesh(&table.patches[range], SOURCE_GRID, &mesh::plain_uv);
    level.mesh.edges_opened_from(&source)
}

/// The larger of: the farthest limit-surface sample from the level, and
/// the farthest level sample (vertices, edge midpoints, centroids) from the
/// proxy plus the proxy's own error.
pub fn measured_error(surface: &[Vec3], level: &TriMesh, proxy: &TriMesh, proxy_error: f32) -> f32 {
    let to_level = error::max_distance(surface, level);
    let from_level = error::max_distance(&error::mesh_samples(level), proxy) + proxy_error;
    to_level.max(from_level)
}

/// `source` simplified with error at most `target` (absolute), its
/// vertices split where creases need ([`TriMesh::split`]); and the error the simplifier reports.
fn simplify(source: &TriMesh, target: f32) -> (TriMesh, f32) {
    let positions: &[f32] = bytemuck::cast_slice(&source.positions);
    let adapter = meshopt::VertexDataAdapter::new(bytemuck::cast_slice(positions), 12, 0)
        .expect("a Vec3 slice is 12-byte vertices");
    let mut reached = 0.0f32;
    // Borders not locked: the whole model is simplified at once, so a
    // border is the model's own open edge, which may be simplified like
    // the rest (the simplifier still never opens a new one).
    let options = meshopt::SimplifyOptions::ErrorAbsolute;
    let indices = meshopt::simplify(
        &source.indices,
        &adapter,
        0,
        target,
        options,
        Some(&mut reached),
    );
    (source.split(&indices), reached)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn levels_coarsen_measured_and_stay_closed() {
        let ball = mesh::shapes::ball(4);
        let levels = model_levels(&ball, &mesh::plain_uv, false, MOST_NORMAL_ERROR);
        assert!(levels.len() >= 2, "{} levels", levels.len());
        let mut finer = MOST_TRIANGLES_PER_PATCH * ball.len();
        for l in &levels {
            assert!(l.mesh.triangles() as f32 <= KEEP_RATIO * finer as f32);
            finer = l.mesh.triangles();
            // Closed as the ball is: no collapse opened it.
            assert_eq!(l.mesh.boundary_edges(), vec![]);
            // The measured error is real (a simplified ball is not the
            // ball) and not far from what was asked for.
            assert!(l.error > 0.0 && l.error < 4.0 * l.target, "{l:?}");
        }
        // Coarser levels lie farther from the surface.
        assert!(levels.last().unwrap().error > levels[0].error);
    }

    /// No collapse opens the mesh: a level's border runs only through
    /// vertices on the model's own border (it may be simplified, not cut
    /// anew through the interior).
    #[test]
    fn an_open_model_opens_nowhere_else_on_any_level() {
        let open = &mesh::shapes::ball(4)[..5 * 16];
        let source = mesh::limit_mesh(open, SOURCE_GRID, &mesh::plain_uv);
        let levels = model_levels(open, &mesh::plain_uv, false, MOST_NORMAL_ERROR);
        assert!(!levels.is_empty());
        for l in &levels {
            assert!(!l.mesh.boundary_edges().is_empty(), "the model is open");
            assert_eq!(l.mesh.edges_opened_from(&source), 0);
        }
        // A level with a triangle taken out opens where the model does not.
        let mut cut = levels[0].mesh.clone();
        let middle = 3 * (cut.triangles() / 2);
        cut.indices.drain(middle..middle + 3);
        assert!(cut.edges_opened_from(&source) > 0);
    }

    /// A coarse level of a box with narrow rounded edges: its vertices
    /// lie on the edges, whose normals, taken from the surface there,
    /// tilted the flat faces' lighting; fitted to the surface each
    /// triangle stands for, the shading lies nearer the surface's.
    #[test]
    fn fitted_normals_shade_a_rounded_box_nearer_its_surface() {
        let rounded = mesh::shapes::rounded_box(4);
        let source = mesh::limit_mesh(&rounded, SOURCE_GRID, &mesh::plain_uv);
        let samples = error::surface_normals(&rounded, 2 * SOURCE_GRID);
        let (mut level, _) = simplify(&source, 0.06);
        assert!(level.triangles() < 200, "{}", level.triangles());
        let surface = error::normal_error(&samples, &level, false);
        error::fit_normals(&mut level, &samples);
        let fitted = error::normal_error(&samples, &level, false);
        assert!(
            fitted < 0.8 * surface,
            "{}° fitted against {}° from the surface",
            fitted.to_degrees(),
            surface.to_degrees()
        );
        // A bound of 3°: every level is farther from the surface up close
        // (3.4° to 8.6°); seen through a quarter of the box, all but the
        // coarsest are within it (0.9° to 2.9°; the coarsest 4.0°), so
        // the coarsest is not kept and the others are, for distances.
        let all = model_levels(&rounded, &mesh::plain_uv, false, std::f32::consts::PI);
        let bound = 3f32.to_radians();
        let kept = model_levels(&rounded, &mesh::plain_uv, false, bound);
        assert!(all.iter().all(|l| l.normal_error > bound));
        assert_eq!(kept.len(), all.len() - 1);
        for l in &kept {
            assert!(l.shading_error(f32::INFINITY) <= bound, "{l:?}");
        }
    }

    /// A crease stays sharp: the flat-faced cube's levels light each face
    /// with its own normal, not the corners' average.
    #[test]
    fn creases_keep_their_normals() {
        let cube = mesh::shapes::cube_with(4, |p| p);
        let levels = model_levels(&cube, &mesh::plain_uv, false, MOST_NORMAL_ERROR);
        assert!(!levels.is_empty());
        for l in &levels {
            for n in &l.mesh.normals {
                assert!(n[0].abs().max_element() > 0.999, "{n:?}");
            }
            // Closed, by position, as the cube is.
            assert_eq!(l.mesh.boundary_edges(), vec![]);
        }
    }
}
