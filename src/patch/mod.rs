//! The CPU reference ("oracle") of the subdivision algorithm, in the exact
//! floating-point operation order of the GLSL in `glsl/common/`.

pub mod bezier;
pub mod blossom;
pub mod criterion;
pub mod cull;
pub mod displace;
#[cfg(test)]
pub(crate) mod fixtures;
pub mod homogeneous;
pub mod ops;
pub mod oracle;
pub mod quadnode;
pub mod rational;
pub mod shading;
pub mod view;
pub mod wedge;
