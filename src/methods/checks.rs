//! A method's own `validate` checks ([`MethodInfo::checks`](super::MethodInfo)):
//! the report line they write, the check itself, and the narrow view of
//! the frame just drawn that they read ([`CheckFrame`]), so that checks in
//! a method's folder need neither the renderer nor `validate`.

use super::{Method, RenderError};
use crate::scene::geometry::SceneGeometry;
use crate::vk::Context;

/// One line of the report.
#[derive(Clone, Debug)]
pub struct CheckResult {
    /// What was checked.
    pub check: String,
    /// Keyframe, if the check is per frame.
    pub frame: Option<usize>,
    /// Passed?
    pub ok: bool,
    /// Figures.
    pub detail: String,
}

impl CheckResult {
    /// The line of check `check` on keyframe `frame` (none: the whole scene).
    pub fn new(check: &str, frame: Option<usize>, ok: bool, detail: String) -> Self {
        Self {
            check: check.into(),
            frame,
            ok,
            detail,
        }
    }
}

/// The frame a check reads: the device it was drawn on and the method
/// that drew it (whose buffers a check reads through
/// [`Method::downcast`](super::Method)). The renderer is one.
pub trait CheckFrame {
    /// The device.
    fn context(&self) -> &Context;
    /// The method that drew the frame.
    fn method(&self) -> &dyn Method;
}

/// A method's own checks, which `validate` runs on every keyframe right
/// after the renderer drew it with the method. They reach the method's
/// concrete type through [`Method::downcast`](super::Method).
pub trait Check {
    /// Whether the frames must be drawn with the renderer's capture on.
    fn capture(&self) -> bool {
        false
    }

    /// The report's lines for keyframe `k`, the frame `frame` holds.
    fn keyframe(&self, frame: &dyn CheckFrame, k: usize) -> Result<Vec<CheckResult>, RenderError>;
}

/// Makes a method's [`Check`] for the scene's geometry at the checked time
/// (`MethodInfo::checks`).
pub type MakeCheck = for<'a> fn(&'a SceneGeometry) -> Box<dyn Check + 'a>;
