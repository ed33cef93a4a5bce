//! Cameras for views of a model.

use bezier_subdiv::patch::bezier::BezierPatch;
use bezier_subdiv::scene::camera::Camera;
use glam::DVec3;

/// Three cameras around `patches`' bounding box at distances in
/// proportion to its size, looking at its centre.
pub fn around(patches: &[BezierPatch]) -> Vec<Camera> {
    let (lo, hi) = BezierPatch::bounds(patches).unwrap();
    let c = ((lo + hi) * 0.5).as_dvec3();
    let r = ((hi - lo).length() as f64).max(1e-3);
    [
        DVec3::new(1.5, -2.0, 1.0),
        DVec3::new(-0.4, 0.3, 0.6),
        DVec3::new(0.2, 0.9, -1.4),
    ]
    .iter()
    .map(|d| Camera {
        position: (c + *d * r).to_array(),
        target: c.to_array(),
        up: [0.0, 0.0, 1.0],
        fov_y_deg: 45.0,
        near: 0.01 * r,
        far: 100.0 * r,
    })
    .collect()
}
