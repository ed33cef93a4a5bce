//! What importing one model file produces: its patches and where they
//! came from, and what a cage import found.

use crate::patch::bezier::BezierPatch;

use super::isolate::LevelCount;
use super::origin::PatchOrigin;
use super::sharpness::BoundaryRule;
use super::uv::{FaceUvs, UvInfo, UvPatches};
use super::{mesh, stencil};
use crate::patch::shading::ShadingPatch;

/// How a cage's boundary rule was chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RuleSource {
    /// The file's `t interpolateboundary` tag, at this line.
    Tag(usize),
    /// The scene file's or command line's option.
    Option,
    /// Neither: [`super::sharpness::DEFAULT_BOUNDARY`].
    Default,
}

/// What a cage import found, for the summary and the sidecar.
#[derive(Clone, Debug, PartialEq)]
pub struct CageInfo {
    /// The boundary rule used.
    pub boundary: BoundaryRule,
    /// Where it came from.
    pub boundary_from: RuleSource,
    /// Boundary edges of the cage.
    pub boundary_edges: usize,
    /// Edges tagged infinitely sharp (sharpness ≥ 10).
    pub sharp_edges: usize,
    /// Edges tagged semi-sharp (0 < sharpness < 10).
    pub semi_sharp_edges: usize,
    /// Vertices tagged as corners (sharpness > 0).
    pub corners: usize,
    /// Edges with three or more faces.
    pub non_manifold_edges: usize,
    /// Vertices where more than one fan of faces meets.
    pub non_manifold_vertices: usize,
    /// Faces without a patch under the `none` rule.
    pub holes: usize,
    /// Faces `t hole` leaves out (after the `none` rule's, if any).
    pub tagged_holes: usize,
    /// Non-manifold edges that are degenerate (a face repeats a vertex).
    pub degenerate_edges: usize,
    /// Non-manifold edges whose two faces run them the same way.
    pub misoriented_edges: usize,
    /// Closed parts wound inside out, turned the right way out.
    pub inside_out: usize,
    /// Closed parts (every edge manifold).
    pub closed_parts: usize,
    /// Creasing method and triangle rule.
    pub scheme: mesh::Scheme,
    /// The isolation asked for.
    pub isolate: u32,
    /// Patches per refinement level.
    pub levels: Vec<LevelCount>,
    /// With `isolate` > 0: the parts refined, and patches and GPU memory
    /// per level, as one line for the import report.
    pub isolation: Option<String>,
    /// The texture coordinates found, for a cage with them.
    pub uv: Option<UvInfo>,
}

/// The result of importing one model file.
#[derive(Clone, Debug, Default)]
pub struct ImportedModel {
    /// Patches in file order.
    pub patches: Vec<BezierPatch>,
    /// The patches' weights, one set per patch, for `.rbpt` files; empty for
    /// polynomial models (every weight 1).
    pub weights: Vec<crate::patch::rational::Weights>,
    /// One entry per patch for cage imports; empty for `.bpt` files.
    pub origins: Vec<PatchOrigin>,
    /// Tangent patches for shading, one per patch; empty when the model has
    /// none of its own (then the patches' own derivatives are used).
    pub shading: Vec<ShadingPatch>,
    /// For cages: the rules applied and what the cage holds.
    pub cage: Option<CageInfo>,
    /// For cages: the patches and shading patches as functions of the
    /// cage's vertices, for animation (`stencil.rs`).
    pub stencils: Option<std::sync::Arc<stencil::CageModel>>,
    /// For cages with texture coordinates: each face corner's, by the
    /// cage's face order (`PatchOrigin::face`).
    pub uvs: Option<std::sync::Arc<FaceUvs>>,
    /// For cages with texture coordinates: each patch's, by the rule the
    /// import was asked for.
    pub uv_patches: Option<UvPatches>,
    /// For cages whose material names one: the albedo map (`mtl.rs`).
    pub albedo: Option<super::mtl::AlbedoMap>,
    /// Things the user should know that did not stop the import.
    pub warnings: Vec<String>,
}

impl ImportedModel {
    /// The shading patches, one per patch: the model's tangent patches, or
    /// the patches' own derivative nets where it has none.
    pub fn shading_patches(&self) -> Vec<ShadingPatch> {
        if self.shading.len() == self.patches.len() {
            self.shading.clone()
        } else {
            self.patches
                .iter()
                .map(ShadingPatch::from_geometry)
                .collect()
        }
    }
}
