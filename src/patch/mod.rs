//! The CPU reference ("oracle") of the subdivision algorithm, in the exact
//! floating-point operation order of the GLSL in `glsl/common/`.

pub mod bezier;
pub mod ops;
