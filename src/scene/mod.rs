//! Scene input: Bézier patch files, Catmull–Clark cages, scene files, cameras.

pub mod acc;
pub mod adjacency;
pub mod bpt;
pub mod cage;
pub mod camera;
pub mod desc;
pub mod error;
pub mod file;
pub mod fit;
pub mod geometry;
pub mod hash;
pub mod instances;
pub mod isolate;
pub mod limit;
pub mod limits;
pub mod linear;
pub mod model;
pub mod obj;
pub mod orbit;
pub mod orient;
pub mod path;
pub mod pn;
pub mod refine;
pub mod shading;
pub mod sharpness;
pub mod stencil;
pub mod tags;
pub mod tangent;
pub mod text;

pub use error::SceneError;
// The import's results keep their old path for the command layer and the
// tests, which name them often; modules inside `scene` import them from
// `model` and `error`, so nothing here imports from this file.
pub use model::{CageInfo, ImportedModel, PatchOrigin, RuleSource};
