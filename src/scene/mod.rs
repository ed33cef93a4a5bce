//! Scene input: Bézier patch files, Catmull–Clark cages, scene files, cameras.

pub mod acc;
pub mod bpt;
pub mod cage;
pub mod camera;
pub mod error;
pub mod file;
pub mod obj;

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

/// Reads a text file. A file that is not UTF-8 text is refused at the line
/// of its first invalid byte (a binary file named `.bpt` or `.obj`).
pub fn read_text(path: &std::path::Path) -> Result<String, SceneError> {
    let bytes = std::fs::read(path).map_err(|e| SceneError::io(path, e))?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..at].iter().filter(|&&b| b == b'\n').count() + 1;
        SceneError::at(
            path,
            line,
            format!("not a text file: byte {at} is not UTF-8 (model files are plain text)"),
        )
    })
}
