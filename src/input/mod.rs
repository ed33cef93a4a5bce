//! Reading input files, below everything that reads one (scene files, patch
//! files, cages): the error that names the file and line
//! ([`SceneError`]), text reading that refuses binary files at their first
//! bad byte, and the bounds f32 arithmetic sets on what a scene may hold.

pub mod error;
pub mod limits;
pub mod text;

pub use error::SceneError;
