//! Where each imported patch came from in its cage: the face, the
//! sub-face, the region of it, the conversion rule and whether it was
//! turned. The sidecar reports it; the UV patches are built from it.

use super::acc::PatchRule;

/// Where one imported patch came from, for the `.bpt.json` sidecar.
#[derive(Clone, Debug, PartialEq)]
pub struct PatchOrigin {
    /// Index of the cage face (0-based, file order) the patch came from.
    pub face: usize,
    /// For a refined cage, which sub-quad of the face (its corner k) the
    /// first step made; 0 otherwise. For a face that is not a quad this is
    /// OpenSubdiv's ptex sub-face.
    pub sub: usize,
    /// Face-parameter coordinates of the patch's parameter corners (0,0),
    /// (1,0), (1,1), (0,1) in OpenSubdiv's quad-face convention: in the
    /// quad face, or, for a face that is not a quad, in its sub-face `sub`;
    /// `None` for a patch that is a whole sub-face.
    pub corners_uv: Option<[[f32; 2]; 4]>,
    /// The conversion rules at its corners and its feature edges.
    pub rule: PatchRule,
    /// Catmull–Clark steps before conversion: 1 for a cage with non-quads,
    /// the model's `isolate` where it refines, else 0.
    pub level: u32,
    /// The patch was turned (u and v swapped, its part being inside out):
    /// `corners_uv` are swapped with it, but a whole sub-face has none, so
    /// this says it.
    pub turned: bool,
}

impl PatchOrigin {
    /// The origin of the patch with u and v swapped (`orient::flip_patch`):
    /// corners 1 and 3 trade places, and so do the rules.
    pub fn flip(&mut self) {
        if let Some(c) = &mut self.corners_uv {
            c.swap(1, 3);
        }
        self.rule = self.rule.flipped();
        self.turned = !self.turned;
    }
}
