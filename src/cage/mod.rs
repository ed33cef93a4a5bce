//! The cage converter: a Catmull–Clark control cage (Wavefront OBJ, with
//! OpenSubdiv's `t` tags for creases, corners and boundary rules) in,
//! bicubic Bézier patches out, with their shading (tangent) patches, the
//! stencils that remake them from moved cage vertices, and a record of
//! where each patch came from. A subsystem of its own below the scene
//! description: `scene` asks it for models and knows nothing of how.
//!
//! The public surface: [`obj::read`] / [`obj::read_with`] (a file) and
//! [`obj::parse`] / [`obj::parse_with`] (text) with [`obj::CageOptions`]
//! (isolation levels, limit corners), returning an [`ImportedModel`]
//! (patches, shading patches, [`PatchOrigin`]s, the cage's
//! [`CageInfo`] and, for animation, its [`stencil::CageModel`]).
//!
//! Inside, in the order a cage goes through them:
//! - `obj` reads the file (`tags` its tags) into a polygon [`mesh`] with
//!   OpenSubdiv's adjacency, `orient` orients it consistently;
//! - `sharpness` gives every edge and vertex its rule (smooth, crease,
//!   corner, semi-sharp), `refine` takes Catmull–Clark steps where a face
//!   is not yet a regular quad (`isolate` around extraordinary vertices
//!   and semi-sharp features, to `CageOptions::isolate` levels);
//! - `acc` converts each face to Bézier patches (exact for regular quads,
//!   Loop–Schaefer's ACC-2 approximation at extraordinary vertices), `fit`
//!   fits the semi-sharp ones and the crease ends to the refined limit,
//!   `limit` gives exact limit positions where they are needed;
//! - `tangent` makes the shading patches whose normals are continuous
//!   across patches, `linear` holds the linear combinations (`Comb`) all
//!   of this is written in, so `stencil` can keep them as stencils;
//! - `model` is the output, `hash` the converter's fast index maps.

pub mod acc;
pub mod fit;
pub mod hash;
pub mod isolate;
pub mod limit;
pub mod linear;
pub mod mesh;
pub mod model;
pub mod mtl;
pub mod obj;
pub mod orient;
pub mod origin;
mod probe;
pub mod refine;
pub mod scan;
pub mod sharpness;
pub mod stencil;
pub mod tags;
pub mod tangent;
pub mod uv;

pub use isolate::LevelCount;
pub use model::{CageInfo, ImportedModel, RuleSource};
pub use origin::PatchOrigin;
