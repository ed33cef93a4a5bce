//! Judging images and runs: FLIP against a reference ([`flip`]), the
//! reference itself (the `ground-truth` method's image of the same view),
//! and what `bench` makes of its measurements: the per-frame records and
//! their medians ([`record`]), the Markdown and JSON reports ([`report`]),
//! the plots ([`plot`]).

pub mod flip;
pub mod pareto;
pub mod plot;
pub mod record;
pub mod report;

use crate::frame::View;
use crate::methods::{ground_truth, RenderError};
use crate::renderer::Renderer;

/// The `ground-truth` image of `view` (at the renderer's grid), as RGBA8
/// rows; the renderer is left with the method it had.
pub fn ground_truth_image(renderer: &mut Renderer, view: &View) -> Result<Vec<u8>, RenderError> {
    let method = renderer.method().name();
    renderer.set_method(ground_truth::INFO.name)?;
    let image = renderer
        .render(view)
        .and_then(|_| Ok(renderer.read_image()?));
    renderer.set_method(method)?;
    image
}
