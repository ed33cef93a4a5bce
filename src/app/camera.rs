//! The window's camera: orbit around a target (left drag), fly (W A S D,
//! Q E, right drag to look), zoom (wheel), reset (R), and the scene's camera
//! path played back (P). Pure logic on doubles, so it is tested without a
//! window.

use glam::DVec3;

use crate::scene::camera::Camera;
use crate::scene::desc::Scene;

/// Seconds the camera path takes from its first key to its last.
pub const PATH_SECONDS: f64 = 20.0;

/// Pitch limit, short of the poles, so `up` never lines up with the view.
const MAX_PITCH: f64 = 1.5;

/// Keys held for flying.
#[derive(Clone, Copy, Debug, Default)]
pub struct FlyKeys {
    /// W / S.
    pub forward: f64,
    /// D / A.
    pub right: f64,
    /// E / Q.
    pub up: f64,
}

/// Orbit and fly state; the lens (fov, near, far, up) comes from the
/// scene camera it started from.
#[derive(Clone, Debug)]
pub struct CameraRig {
    home: Camera,
    target: DVec3,
    distance: f64,
    yaw: f64,
    pitch: f64,
    /// Playing the scene's camera path, at this parameter in [0, 1].
    pub path: Option<f64>,
    /// Camera-path parameter kept while paused.
    path_t: f64,
    /// The path's camera last drawn, where a pause holds the view.
    shown: Option<Camera>,
    /// Not moved since the start or the last reset: [`CameraRig::camera`]
    /// is the starting camera exactly (no round trip through angles), so
    /// a screenshot equals `render` of the same keyframe.
    at_home: bool,
}

impl CameraRig {
    /// Starts at `camera`, looking at its target.
    pub fn new(camera: Camera) -> Self {
        let mut rig = Self {
            home: camera,
            target: DVec3::ZERO,
            distance: 1.0,
            yaw: 0.0,
            pitch: 0.0,
            path: None,
            path_t: 0.0,
            shown: None,
            at_home: true,
        };
        rig.reset();
        rig
    }

    /// Back to the starting camera (and the path stopped).
    pub fn reset(&mut self) {
        self.look_from(self.home);
        self.path = None;
        self.at_home = true;
    }

    /// Orbit and fly on from `camera` (its eye and target; the lens stays
    /// the home camera's).
    fn look_from(&mut self, camera: Camera) {
        let eye = DVec3::from_array(camera.position);
        self.target = DVec3::from_array(camera.target);
        let d = eye - self.target;
        self.distance = d.length().max(1e-6);
        let (x, y, z) = self.local(d / self.distance);
        self.yaw = y.atan2(x);
        self.pitch = z.clamp(-1.0, 1.0).asin().clamp(-MAX_PITCH, MAX_PITCH);
        self.at_home = false;
    }

    /// The home camera's up direction, and two directions completing a
    /// right-handed frame with it.
    fn frame(&self) -> (DVec3, DVec3, DVec3) {
        let up = DVec3::from_array(self.home.up).normalize_or(DVec3::Z);
        let helper = if up.z.abs() < 0.9 { DVec3::Z } else { DVec3::X };
        let e1 = helper.cross(up).normalize();
        let e2 = up.cross(e1);
        (e1, e2, up)
    }

    fn local(&self, v: DVec3) -> (f64, f64, f64) {
        let (e1, e2, up) = self.frame();
        (v.dot(e1), v.dot(e2), v.dot(up))
    }

    /// Unit vector from the target to the eye.
    fn offset_dir(&self) -> DVec3 {
        let (e1, e2, up) = self.frame();
        let (c, s) = (self.pitch.cos(), self.pitch.sin());
        e1 * (c * self.yaw.cos()) + e2 * (c * self.yaw.sin()) + up * s
    }

    /// The camera to draw with.
    pub fn camera(&self) -> Camera {
        if self.at_home {
            return self.home;
        }
        let eye = self.target + self.offset_dir() * self.distance;
        Camera {
            position: eye.to_array(),
            target: self.target.to_array(),
            ..self.home
        }
    }

    /// Orbits by a drag of (dx, dy) pixels.
    pub fn orbit(&mut self, dx: f64, dy: f64) {
        self.stop_path();
        self.yaw -= dx * 0.008;
        self.pitch = (self.pitch + dy * 0.008).clamp(-MAX_PITCH, MAX_PITCH);
        self.at_home = false;
    }

    /// Turns the view about the eye by a drag of (dx, dy) pixels (the
    /// target moves, the eye stays).
    pub fn look(&mut self, dx: f64, dy: f64) {
        self.stop_path();
        let eye = self.target + self.offset_dir() * self.distance;
        self.yaw -= dx * 0.004;
        self.pitch = (self.pitch - dy * 0.004).clamp(-MAX_PITCH, MAX_PITCH);
        self.target = eye - self.offset_dir() * self.distance;
        self.at_home = false;
    }

    /// Zooms by wheel `steps` (positive: closer).
    pub fn zoom(&mut self, steps: f64) {
        self.stop_path();
        self.distance = (self.distance * 0.85f64.powf(steps)).max(1e-4);
        self.at_home = false;
    }

    /// Flies for `dt` seconds with `keys` held, at a speed relative to the
    /// distance to the target.
    pub fn fly(&mut self, keys: FlyKeys, dt: f64) {
        if keys.forward == 0.0 && keys.right == 0.0 && keys.up == 0.0 {
            return;
        }
        self.stop_path();
        let forward = -self.offset_dir();
        let (_, _, up) = self.frame();
        let right = forward.cross(up).normalize_or_zero();
        let step = (forward * keys.forward + right * keys.right + up * keys.up)
            * (self.distance * 0.8 * dt);
        self.target += step;
        self.at_home = false;
    }

    /// Starts or pauses the camera path.
    pub fn toggle_path(&mut self) {
        if self.path.is_some() {
            self.stop_path();
        } else {
            self.path = Some(self.path_t);
        }
    }

    /// Pauses a playing path where it is: the camera holds the path's last
    /// view and orbits and flies on from there (it once jumped back to
    /// where it was before the path played).
    fn stop_path(&mut self) {
        if let Some(t) = self.path.take() {
            self.path_t = t;
            if let Some(shown) = self.shown {
                self.look_from(shown);
            }
        }
    }

    /// Advances a playing path by `dt` seconds and returns its camera.
    pub fn advance_path(&mut self, scene: &Scene, dt: f64) -> Option<Camera> {
        let t = self.path.as_mut()?;
        *t = (*t + dt / PATH_SECONDS).fract();
        let camera = scene.path_camera(*t);
        self.shown = Some(camera);
        Some(camera)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn start() -> Camera {
        Camera {
            position: [4.0, -3.0, 2.0],
            target: [0.0, 0.0, 1.0],
            up: [0.0, 0.0, 1.0],
            fov_y_deg: 45.0,
            near: 0.1,
            far: 100.0,
        }
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (DVec3::from_array(a) - DVec3::from_array(b)).length() < 1e-9
    }

    #[test]
    fn starts_where_the_scene_camera_is_and_resets_there() {
        let mut rig = CameraRig::new(start());
        assert_eq!(rig.camera(), start(), "exactly, not through angles");
        rig.orbit(120.0, -40.0);
        rig.zoom(3.0);
        rig.fly(
            FlyKeys {
                forward: 1.0,
                ..FlyKeys::default()
            },
            0.5,
        );
        assert!(!close(rig.camera().position, start().position));
        rig.reset();
        assert_eq!(rig.camera(), start());
        // The angles it resumes from are the starting camera's too.
        rig.orbit(0.0, 0.0);
        assert!(close(rig.camera().position, start().position));
        assert!(close(rig.camera().target, start().target));
    }

    #[test]
    fn orbit_keeps_the_distance_and_zoom_shrinks_it() {
        let mut rig = CameraRig::new(start());
        let dist =
            |c: &Camera| (DVec3::from_array(c.position) - DVec3::from_array(c.target)).length();
        let d0 = dist(&rig.camera());
        rig.orbit(300.0, 500.0);
        assert!((dist(&rig.camera()) - d0).abs() < 1e-9);
        // Never past the pole: the view never lines up with `up`.
        let c = rig.camera();
        let f = (DVec3::from_array(c.target) - DVec3::from_array(c.position)).normalize();
        assert!(f.z.abs() < 0.999);
        rig.zoom(1.0);
        assert!(dist(&rig.camera()) < d0);
    }

    #[test]
    fn look_turns_about_the_eye() {
        let mut rig = CameraRig::new(start());
        let eye = rig.camera().position;
        rig.look(50.0, 20.0);
        assert!(close(rig.camera().position, eye));
        assert!(!close(rig.camera().target, start().target));
    }

    /// P a second time holds the view where the path is (it once jumped
    /// back to the camera from before the path); a drag also goes on from
    /// there.
    #[test]
    fn pausing_the_path_holds_its_view() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/kitchen.toml");
        let scene = Scene::load(&path).unwrap();
        let mut rig = CameraRig::new(scene.camera);
        rig.toggle_path();
        let shown = rig.advance_path(&scene, 3.7).unwrap();
        assert!(!close(shown.position, scene.camera.position));
        rig.toggle_path();
        assert!(rig.path.is_none());
        assert!(close(rig.camera().position, shown.position));
        assert!(close(rig.camera().target, shown.target));
        rig.toggle_path();
        let shown = rig.advance_path(&scene, 1.0).unwrap();
        rig.zoom(0.0);
        assert!(rig.path.is_none(), "a move pauses the path");
        assert!(close(rig.camera().position, shown.position));
    }
}
