//! Scene input: Bézier patch files, Catmull–Clark cages, scene files, cameras.

pub mod acc;
pub mod bpt;
pub mod cage;
pub mod camera;
pub mod error;
pub mod file;
pub mod obj;
pub mod orbit;

pub use error::SceneError;

use crate::patch::bezier::BezierPatch;

/// Where one imported patch came from, for the `.bpt.json` sidecar.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchOrigin {
    /// Index of the cage face (0-based, file order) the patch came from.
    pub face: usize,
    /// Face-parameter coordinates of the patch's parameter corners (0,0),
    /// (1,0), (1,1), (0,1) in OpenSubdiv's quad-face convention; `None` for
    /// patches of non-quad faces.
    pub corners_uv: Option<[[f32; 2]; 4]>,
}

/// The result of importing one model file.
#[derive(Clone, Debug, Default)]
pub struct ImportedModel {
    /// Patches in file order.
    pub patches: Vec<BezierPatch>,
    /// One entry per patch for cage imports; empty for `.bpt` files.
    pub origins: Vec<PatchOrigin>,
    /// Things the user should know that did not stop the import.
    pub warnings: Vec<String>,
}
