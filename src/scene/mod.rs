//! The scene description: scene files (TOML) and what they hold (models
//! and their instances, cameras, keyframe paths and orbits, time-varying
//! keys and deformers), Bézier patch files (`.bpt`, `.rbpt`), PN-triangle
//! meshes, and the geometry a scene becomes (its patches placed, its
//! instance table, the patch sides that are one curve). Catmull–Clark
//! cages are converted by `crate::cage`.

pub mod adjacency;
pub mod bpt;
pub mod camera;
pub mod desc;
pub mod displaced;
pub mod displacement;
pub mod file;
pub mod geometry;
pub mod instances;
pub mod keys;
pub mod material;
pub mod orbit;
pub mod path;
pub mod pn;
pub mod sequence;
pub mod texture;

// Every reader of the scene reports this error; it lives below the scene
// (`crate::input`), where the cage converter reports it too.
pub use crate::input::SceneError;
