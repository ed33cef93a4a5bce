//! Per-frame constants of the criterion and culling, in the exact layout the
//! GPU receives (std140/std430 compatible). All camera-only factors are
//! computed here once, in f64, and rounded to f32: the shaders and the oracle
//! then start from the same bits.

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, DVec4, Vec4};

use super::quadnode::L_MAX;

/// `ViewParams::flags` bits: frustum culling, back-face culling of ready
/// one-sided sub-patches, wedge triangles (off only to show the cracks they
/// close).
pub use crate::constants::{FLAG_ANISO, FLAG_BACKFACE_CULL, FLAG_FRUSTUM_CULL, FLAG_WEDGES};
/// The defaults: everything on.
pub const FLAGS_DEFAULT: u32 = FLAG_FRUSTUM_CULL | FLAG_BACKFACE_CULL | FLAG_WEDGES;

/// How subdivision splits a node that is not flat: `Iso` always 1:4 (the
/// paper's method), `Aniso` halves only the direction whose edges are not
/// flat (1:2), 1:4 when both are or the inner tier fails. A criterion
/// setting like ε and λ: it travels in the view's flags (`FLAG_ANISO`), so
/// the GPU and the oracle read it from the same place.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Split {
    /// Always 1:4.
    #[default]
    Iso,
    /// 1:2 where only one direction needs it.
    Aniso,
}

impl Split {
    /// The view flag bits this mode sets.
    pub fn flag(self) -> u32 {
        match self {
            Split::Iso => 0,
            Split::Aniso => FLAG_ANISO,
        }
    }

    /// The mode a view's flags ask for.
    pub fn of_flags(flags: u32) -> Self {
        if flags & FLAG_ANISO != 0 {
            Split::Aniso
        } else {
            Split::Iso
        }
    }

    /// `iso` or `aniso`, as the flag and the scene key spell it.
    pub fn name(self) -> &'static str {
        match self {
            Split::Iso => "iso",
            Split::Aniso => "aniso",
        }
    }
}

/// Constants of one view, uploaded verbatim.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct ViewParams {
    /// View-space depth of a world point p: `((r.x p.x + r.y p.y) + r.z p.z) + r.w`.
    pub depth_row: Vec4,
    /// Frustum planes (left, right, bottom, top, near, far); inside when the
    /// same affine form is ≥ 0.
    pub planes: [Vec4; 6],
    /// Camera position (xyz), w = 1.
    pub eye: Vec4,
    /// World-space size of one pixel at unit depth times ε:
    /// `ε · 2·tan(fov_y/2) / viewport height`.
    pub eps_k: f32,
    /// Depths below this (samples near, at or behind the camera plane) are
    /// clamped to it, so they demand fine subdivision, bounded by `l_max`.
    pub near: f32,
    /// Weight of the orthogonal distance, `1 - λ`.
    pub w_orth: f32,
    /// Weight of the parametric distance, `λ`.
    pub w_par: f32,
    /// Deepest level; nodes at this depth are drawn whatever the criterion says.
    pub l_max: u32,
    /// `FLAG_*` bits.
    pub flags: u32,
    /// Viewport size in pixels (the depth pyramid's level 0).
    pub width: u32,
    /// See `width`.
    pub height: u32,
    /// Rows of the view-projection matrix (world → Vulkan clip space, in
    /// f32): clip coordinate i of p is `affine_row(clip[i], p)`. Only the
    /// occlusion test reads it (no oracle decision depends on it).
    pub clip: [Vec4; 4],
}

/// What a view is made of, in f64.
#[derive(Clone, Copy, Debug)]
pub struct ViewInputs {
    /// Camera position.
    pub eye: DVec3,
    /// Unit viewing direction.
    pub forward: DVec3,
    /// Projection × view (Vulkan clip space: depth in [0, w]).
    pub view_proj: DMat4,
    /// Vertical field of view in radians.
    pub fov_y: f64,
    /// Near-plane distance.
    pub near: f64,
    /// Viewport width in pixels.
    pub width: u32,
    /// Viewport height in pixels.
    pub height: u32,
    /// Pixel tolerance ε.
    pub eps: f64,
    /// Blend λ ∈ [0, 1] between orthogonal (0) and parametric (1) distance.
    pub lambda: f64,
}

impl ViewParams {
    /// Builds the constants for a view.
    pub fn new(v: &ViewInputs) -> Self {
        let f = v.forward.normalize();
        let depth_row = DVec4::new(f.x, f.y, f.z, -f.dot(v.eye));
        let eps_k = v.eps * 2.0 * (v.fov_y * 0.5).tan() / v.height as f64;
        ViewParams {
            depth_row: depth_row.as_vec4(),
            planes: frustum_planes(&v.view_proj),
            eye: v.eye.extend(1.0).as_vec4(),
            eps_k: eps_k as f32,
            near: v.near as f32,
            w_orth: (1.0 - v.lambda) as f32,
            w_par: v.lambda as f32,
            l_max: L_MAX,
            flags: FLAGS_DEFAULT,
            width: v.width,
            height: v.height,
            clip: std::array::from_fn(|i| v.view_proj.row(i).as_vec4()),
        }
    }

    /// The height of one pixel at unit depth (world units): the view's
    /// vertical focal length, from its clip rows, over half the image.
    pub fn pixel_at_unit_depth(&self) -> f32 {
        let (y, w) = (self.clip[1].truncate(), self.clip[3].truncate());
        2.0 * w.length() / (y.length() * self.height as f32)
    }

    /// True when `flag` is set.
    pub fn has(&self, flag: u32) -> bool {
        self.flags & flag != 0
    }
}

/// The six planes of a Vulkan-convention view-projection (clip x, y in
/// [-w, w], z in [0, w]), normalised so the distances have world units.
pub fn frustum_planes(m: &DMat4) -> [Vec4; 6] {
    let r = |i: usize| m.row(i);
    let raw = [
        r(3) + r(0),
        r(3) - r(0),
        r(3) + r(1),
        r(3) - r(1),
        r(2),
        r(3) - r(2),
    ];
    raw.map(|p| {
        let len = p.truncate().length();
        (if len > 0.0 { p / len } else { p }).as_vec4()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_is_gpu_friendly() {
        assert_eq!(std::mem::size_of::<ViewParams>(), 224);
        assert_eq!(std::mem::size_of::<ViewParams>() % 16, 0);
    }

    #[test]
    fn planes_contain_the_view_axis() {
        let eye = DVec3::new(0.0, 1.0, 5.0);
        let view = DMat4::look_at_rh(eye, DVec3::ZERO, DVec3::Y);
        let proj = DMat4::perspective_rh(0.8, 1.5, 0.1, 100.0);
        let planes = frustum_planes(&(proj * view));
        let inside = (DVec3::ZERO - eye).normalize() * 3.0 + eye;
        for p in planes {
            let d = p.as_dvec4().truncate().dot(inside) + p.w as f64;
            assert!(d > 0.0, "{p}");
        }
        let behind = eye + (eye - DVec3::ZERO).normalize();
        assert!(planes
            .iter()
            .any(|p| p.as_dvec4().truncate().dot(behind) + (p.w as f64) < 0.0));
    }
}
