//! Pinhole cameras in Vulkan's conventions (right-handed world, clip-space y
//! down, depth in [0, 1]), and the view constants they give the criterion.

use glam::{DMat4, DVec3};
use serde::Deserialize;

use crate::patch::view::{ViewInputs, ViewParams};

/// A camera: where it is, what it looks at, and its lens.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Eye position (world units).
    pub position: [f64; 3],
    /// Point looked at.
    pub target: [f64; 3],
    /// World up direction.
    #[serde(default = "default_up")]
    pub up: [f64; 3],
    /// Vertical field of view in degrees.
    #[serde(default = "default_fov")]
    pub fov_y_deg: f64,
    /// Near plane distance.
    #[serde(default = "default_near")]
    pub near: f64,
    /// Far plane distance.
    #[serde(default = "default_far")]
    pub far: f64,
}

pub(crate) fn default_up() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}
pub(crate) fn default_fov() -> f64 {
    45.0
}
pub(crate) fn default_near() -> f64 {
    0.05
}
pub(crate) fn default_far() -> f64 {
    1000.0
}

impl Camera {
    /// Eye position.
    pub fn eye(&self) -> DVec3 {
        DVec3::from_array(self.position)
    }

    /// Unit viewing direction.
    pub fn forward(&self) -> DVec3 {
        (DVec3::from_array(self.target) - self.eye()).normalize()
    }

    /// World → view transform.
    pub fn view(&self) -> DMat4 {
        DMat4::look_at_rh(
            self.eye(),
            DVec3::from_array(self.target),
            DVec3::from_array(self.up),
        )
    }

    /// View → Vulkan clip space for the given aspect ratio (width / height).
    /// Depth maps to [0, 1]; y is flipped so +y up in view space is up on
    /// screen. The flip also mirrors the winding: a triangle counter-clockwise
    /// in view space is clockwise in framebuffer coordinates.
    pub fn projection(&self, aspect: f64) -> DMat4 {
        let mut p = DMat4::perspective_rh(self.fov_y_deg.to_radians(), aspect, self.near, self.far);
        p.y_axis.y = -p.y_axis.y;
        p
    }

    /// Projection × view.
    pub fn view_proj(&self, width: u32, height: u32) -> DMat4 {
        self.projection(width as f64 / height as f64) * self.view()
    }

    /// The criterion's constants for a `width`×`height` viewport.
    pub fn view_params(&self, width: u32, height: u32, eps: f64, lambda: f64) -> ViewParams {
        ViewParams::new(&ViewInputs {
            eye: self.eye(),
            forward: self.forward(),
            view_proj: self.view_proj(width, height),
            fov_y: self.fov_y_deg.to_radians(),
            near: self.near,
            width,
            height,
            eps,
            lambda,
        })
    }

    /// Checks the numbers make a camera; the message says which one does not.
    pub fn check(&self) -> Result<(), String> {
        let all = self.position.iter().chain(&self.target).chain(&self.up);
        if !all.clone().all(|x| x.is_finite()) {
            return Err("camera coordinates must be finite".into());
        }
        let dir = DVec3::from_array(self.target) - self.eye();
        if dir.length() == 0.0 {
            return Err("camera position and target coincide".into());
        }
        let up = DVec3::from_array(self.up);
        if up == DVec3::ZERO {
            return Err("camera up is [0, 0, 0]: give it a direction, e.g. [0, 0, 1]".into());
        }
        if dir.cross(up).length() <= 1e-9 * dir.length() * up.length() {
            return Err("camera up is parallel to the viewing direction".into());
        }
        if !(self.fov_y_deg > 0.0 && self.fov_y_deg < 180.0) {
            return Err(format!("fov_y_deg {} is not in (0, 180)", self.fov_y_deg));
        }
        if !(self.near > 0.0 && self.far > self.near) {
            return Err(format!(
                "need 0 < near < far (near {}, far {})",
                self.near, self.far
            ));
        }
        Ok(())
    }

    /// Linear blend of two cameras (positions, targets, up, lens), for paths.
    pub fn lerp(&self, other: &Camera, t: f64) -> Camera {
        let mix3 = |a: [f64; 3], b: [f64; 3]| {
            (DVec3::from_array(a) + (DVec3::from_array(b) - DVec3::from_array(a)) * t).to_array()
        };
        let mix = |a: f64, b: f64| a + (b - a) * t;
        Camera {
            position: mix3(self.position, other.position),
            target: mix3(self.target, other.target),
            up: mix3(self.up, other.up),
            fov_y_deg: mix(self.fov_y_deg, other.fov_y_deg),
            near: mix(self.near, other.near),
            far: mix(self.far, other.far),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec4;

    fn cam() -> Camera {
        Camera {
            position: [4.0, -6.0, 3.0],
            target: [0.0, 0.0, 1.0],
            up: [0.0, 0.0, 1.0],
            fov_y_deg: 40.0,
            near: 0.1,
            far: 50.0,
        }
    }

    #[test]
    fn target_projects_to_screen_centre_and_up_is_up() {
        let c = cam();
        let m = c.view_proj(640, 360);
        let t = m * DVec4::new(0.0, 0.0, 1.0, 1.0);
        assert!((t.x / t.w).abs() < 1e-12 && (t.y / t.w).abs() < 1e-12);
        assert!(t.z / t.w > 0.0 && t.z / t.w < 1.0);
        // A point above the target is above the centre: Vulkan y is down.
        let a = m * DVec4::new(0.0, 0.0, 1.5, 1.0);
        assert!(a.y / a.w < 0.0);
    }

    #[test]
    fn eps_k_is_pixel_size_at_unit_depth() {
        let c = cam();
        let vp = c.view_params(640, 360, 2.0, 0.5);
        let want = 2.0 * 2.0 * (20f64.to_radians()).tan() / 360.0;
        assert!((vp.eps_k as f64 - want).abs() < 1e-9);
        // The same pixel, found from the projection alone.
        assert!((f64::from(vp.pixel_at_unit_depth()) - want / 2.0).abs() < 1e-6);
        assert_eq!(vp.w_orth, 0.5);
        let d = c.eye().distance(DVec3::new(0.0, 0.0, 1.0));
        let z = crate::patch::ops::affine_row(vp.depth_row, glam::Vec3::new(0.0, 0.0, 1.0));
        assert!((z as f64 - d).abs() < 1e-5);
    }

    #[test]
    fn bad_cameras_are_refused() {
        let mut c = cam();
        c.target = c.position;
        assert!(c.check().is_err());
        let mut c = cam();
        c.up = [0.0, 0.0, 0.0];
        assert_eq!(
            c.check().unwrap_err(),
            "camera up is [0, 0, 0]: give it a direction, e.g. [0, 0, 1]"
        );
        // Parallel (and tiny but not zero) up vectors are named as such.
        c.up = [-4e-12, 6e-12, -2e-12];
        assert!(c.check().unwrap_err().contains("parallel"));
        c.up = [0.0, 0.0, 1e-12];
        assert!(c.check().is_ok());
        let mut c = cam();
        c.near = 0.0;
        assert!(c.check().is_err());
        assert!(cam().check().is_ok());
    }
}
