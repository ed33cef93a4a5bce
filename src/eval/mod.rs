//! Judging images and runs: FLIP against a reference ([`flip`]), the
//! reference itself (the `ground-truth` method's image of the same view),
//! and what `bench` makes of its measurements: the per-frame records and
//! their medians ([`record`]), the Markdown and JSON reports ([`report`]),
//! the plots ([`plot`]).

pub mod flip;
pub mod geometry;
pub mod pareto;
pub mod plot;
pub mod record;
pub mod report;

use crate::constants::{SHADE_DISTANCE, SHADE_PATCH_ID, SHADE_WEDGES};
use crate::frame::View;
use crate::methods::{self, RenderError};
use crate::renderer::Renderer;

/// The `ground-truth` image of `view` (at the renderer's grid), as RGBA8
/// rows; the renderer is left with the method it had.
pub fn ground_truth_image(renderer: &mut Renderer, view: &View) -> Result<Vec<u8>, RenderError> {
    let method = renderer.method().name();
    renderer.set_method(methods::reference().name)?;
    let image = renderer
        .render(view)
        .and_then(|_| Ok(renderer.read_image()?));
    renderer.set_method(method)?;
    image
}

/// `view` drawn by the renderer's active method with shading `shade` over
/// a white background (the coded images' "nothing here"), as RGBA8 rows;
/// the background is put back.
fn coded_image(renderer: &mut Renderer, view: &View, shade: u32) -> Result<Vec<u8>, RenderError> {
    let background = renderer.target().clear;
    renderer.set_background([1.0; 4]);
    let coded = View { shade, ..*view };
    let image = renderer
        .render(&coded)
        .and_then(|_| Ok(renderer.read_image()?));
    renderer.set_background(background);
    image
}

/// The eye distance per pixel of `view` as the active method draws it
/// (infinity where nothing is drawn); `far` is the camera's far plane.
pub fn distance_image(
    renderer: &mut Renderer,
    view: &View,
    far: f32,
) -> Result<Vec<f32>, RenderError> {
    let v = View {
        distance_scale: far,
        ..*view
    };
    Ok(crate::validate::holes::decode_distances(
        &coded_image(renderer, &v, SHADE_DISTANCE)?,
        far,
    ))
}

/// The base patch drawn at each pixel of `view` by the active method.
pub fn patch_id_image(
    renderer: &mut Renderer,
    view: &View,
) -> Result<Vec<Option<u32>>, RenderError> {
    Ok(geometry::decode_patch_ids(&coded_image(
        renderer,
        view,
        SHADE_PATCH_ID,
    )?))
}

/// The pixels of `view` on which the active method draws a wedge.
pub fn wedge_image(renderer: &mut Renderer, view: &View) -> Result<Vec<bool>, RenderError> {
    Ok(geometry::wedge_pixels(&coded_image(
        renderer,
        view,
        SHADE_WEDGES,
    )?))
}

/// The ground truth's facts for `view` (distances and the model under each
/// pixel; `model_of` maps a patch id to its model), at the renderer's
/// grid; the renderer is left with the method it had.
pub fn ground_truth_reference(
    renderer: &mut Renderer,
    view: &View,
    far: f32,
    fov_y_deg: f64,
    model_of: impl Fn(u32) -> Option<usize>,
) -> Result<geometry::Reference, RenderError> {
    let method = renderer.method().name();
    renderer.set_method(methods::reference().name)?;
    let images =
        distance_image(renderer, view, far).and_then(|d| Ok((d, patch_id_image(renderer, view)?)));
    renderer.set_method(method)?;
    let (distance, ids) = images?;
    let size = renderer.target().size();
    Ok(geometry::Reference {
        size,
        distance,
        model: ids.into_iter().map(|p| p.and_then(&model_of)).collect(),
        k: (2.0 * (fov_y_deg.to_radians() * 0.5).tan() / f64::from(size.1)) as f32,
    })
}

/// The distance in pixels between the active method's surface and the
/// ground truth's in `view` (`geometry`), and where the FLIP map
/// `flip_errors` (of the same view) has its error. The reference is the
/// ground truth's distance image only: one ground-truth frame, no patch
/// ids (no per-model shares). The renderer is left with its method.
pub fn geometric_error(
    renderer: &mut Renderer,
    view: &View,
    camera: &crate::scene::camera::Camera,
    flip_errors: &[f32],
) -> Result<geometry::Breakdown, RenderError> {
    let far = camera.far as f32;
    let method = renderer.method().name();
    renderer.set_method(methods::reference().name)?;
    let truth = distance_image(renderer, view, far);
    renderer.set_method(method)?;
    let distance = truth?;
    let size = renderer.target().size();
    let reference = geometry::Reference {
        size,
        model: vec![None; distance.len()],
        distance,
        k: (2.0 * (camera.fov_y_deg.to_radians() * 0.5).tan() / f64::from(size.1)) as f32,
    };
    let distance = distance_image(renderer, view, far)?;
    let wedges = if renderer.method().has_wedges() {
        Some(wedge_image(renderer, view)?)
    } else {
        None
    };
    Ok(geometry::breakdown(
        &reference,
        &distance,
        wedges.as_deref(),
        flip_errors,
    ))
}
