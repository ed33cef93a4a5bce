//! The camera path `bench` samples ([`ScenePath`]): the scene's orbit,
//! else its keyframes, else an orbit of its bounding box. It reads both the
//! scene and its loaded geometry, so it sits above `desc.rs`, `geometry.rs`
//! and `orbit.rs`.

use glam::DVec3;

use super::camera::Camera;
use super::desc::Scene;
use super::geometry::SceneGeometry;
use super::orbit::Orbit;

/// The camera path `bench` samples: the scene's orbit, else its keyframes,
/// else an orbit of its bounding box.
#[derive(Clone, Debug)]
pub enum ScenePath {
    /// The scene's `[camera_orbit]`, or an orbit of its bounding box.
    Orbit {
        /// The orbit.
        orbit: Orbit,
        /// Made from the bounding box (the scene has no path).
        from_bounds: bool,
    },
    /// Piecewise linear through the scene's keyframes.
    Keys(Box<Scene>),
}

impl ScenePath {
    /// The scene's orbit, else its keyframes, else an orbit of `geo`'s
    /// bounding box.
    pub fn of(scene: &Scene, geo: &SceneGeometry) -> Self {
        if let Some(orbit) = scene.orbit {
            return ScenePath::Orbit {
                orbit,
                from_bounds: false,
            };
        }
        if !scene.keys.is_empty() {
            return ScenePath::Keys(Box::new(scene.clone()));
        }
        let (mut lo, mut hi) = (DVec3::splat(f64::MAX), DVec3::splat(f64::MIN));
        // PN triangles' vertices count too (their nets bulge a little past
        // them, well within the orbit's margin).
        let pn = geo.pn.positions.iter();
        for q in geo.patches.iter().flat_map(|p| p.pts.iter()).chain(pn) {
            lo = lo.min(q.as_dvec3());
            hi = hi.max(q.as_dvec3());
        }
        if geo.patches.is_empty() && geo.pn.positions.is_empty() {
            (lo, hi) = (DVec3::ZERO, DVec3::ZERO);
        }
        ScenePath::Orbit {
            orbit: Orbit::around(lo, hi),
            from_bounds: true,
        }
    }

    /// Frames the path asks for by default.
    pub fn default_frames(&self) -> u32 {
        match self {
            ScenePath::Orbit { orbit, .. } => orbit.frames,
            ScenePath::Keys(s) => s.path_frames,
        }
    }

    /// Where sample `i` of `n` is: an orbit is closed (its end is its
    /// start), so it is cut in `n` equal steps; the key path is open and
    /// includes both ends.
    pub fn t(&self, i: u32, n: u32) -> f64 {
        match self {
            ScenePath::Orbit { .. } => f64::from(i) / f64::from(n.max(1)),
            ScenePath::Keys(_) if n > 1 => f64::from(i) / f64::from(n - 1),
            ScenePath::Keys(_) => 0.0,
        }
    }

    /// The camera at `t`.
    pub fn camera(&self, t: f64) -> Camera {
        match self {
            ScenePath::Orbit { orbit, .. } => orbit.camera(t),
            ScenePath::Keys(s) => s.path_camera(t),
        }
    }

    /// The path in words, for the report.
    pub fn describe(&self) -> String {
        match self {
            ScenePath::Orbit {
                orbit: o,
                from_bounds,
            } => format!(
                "{} about {:?}: distance {}–{}, height {}–{}, {} turn(s), {} wave(s), fov {}°",
                if *from_bounds {
                    "orbit of the bounding box (the scene has no path)"
                } else {
                    "`[camera_orbit]`"
                },
                o.center,
                o.distance[0],
                o.distance[1],
                o.height[0],
                o.height[1],
                o.turns,
                o.waves,
                o.fov_y_deg
            ),
            ScenePath::Keys(s) => format!(
                "`[camera_path]`: piecewise linear through {} keyframes",
                s.frame_count()
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_path_is_the_orbit_else_the_keys_else_the_bounding_box() {
        let base = "[camera]\nposition = [5.0, -5.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\n[[model]]\nfile = \"m.bpt\"\n";
        let keys = "[camera_path]\nframes = 9\n[[camera_path.key]]\nposition = [7.0, -5.0, 3.0]\ntarget = [0.0, 0.0, 1.0]\n";
        let orbit = "[camera_orbit]\ncenter = [0.0, 0.0, 1.0]\ndistance = [2.0, 6.0]\nheight = [0.5, 3.0]\nframes = 12\n";
        let scene = |text: &str| Scene::parse(std::path::Path::new("/tmp/s.toml"), text).unwrap();
        let mut pts = [glam::Vec3::ZERO; 16];
        for (i, p) in pts.iter_mut().enumerate() {
            *p = glam::Vec3::new((i % 4) as f32, (i / 4) as f32, 2.0);
        }
        let geo = SceneGeometry {
            patches: vec![crate::patch::bezier::BezierPatch { pts }],
            ..Default::default()
        };
        let p = ScenePath::of(&scene(&format!("{base}{keys}{orbit}")), &geo);
        assert!(matches!(
            p,
            ScenePath::Orbit {
                from_bounds: false,
                ..
            }
        ));
        assert_eq!(p.default_frames(), 12);
        // Closed: 4 samples of an orbit never repeat the start.
        assert_eq!(p.t(3, 4), 0.75);
        let p = ScenePath::of(&scene(&format!("{base}{keys}")), &geo);
        assert!(matches!(p, ScenePath::Keys(_)));
        assert_eq!(p.default_frames(), 9);
        // Open: the last sample is the last key.
        assert_eq!(p.t(3, 4), 1.0);
        assert_eq!(p.camera(1.0).position, [7.0, -5.0, 3.0]);
        let p = ScenePath::of(&scene(base), &geo);
        assert!(matches!(
            p,
            ScenePath::Orbit {
                from_bounds: true,
                ..
            }
        ));
        assert_eq!(p.camera(0.0).target, [1.5, 1.5, 2.0]);
    }
}
