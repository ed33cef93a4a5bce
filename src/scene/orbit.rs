//! A camera orbit: the path `bench` samples, circling a centre while the
//! eye moves in and out, so near and far views of the same objects follow
//! each other (the paper's Fig. 7 animation). A scene's `[camera_path]`
//! keys are validation views far apart; linear blends between them pass
//! through walls of geometry and say little about a smooth animation.
//! `path.rs` makes the choice `bench` samples.

use std::f64::consts::TAU;

use glam::DVec3;
use serde::Deserialize;

use super::camera::{default_far, default_fov, default_near, default_up, Camera};

/// `[camera_orbit]` of a scene file (see `scene::file` for the format).
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Orbit {
    /// The point looked at, and the orbit's centre.
    pub center: [f64; 3],
    /// Eye distance from the axis through `center` along `up`: nearest,
    /// farthest.
    pub distance: [f64; 2],
    /// Eye height above `center` along `up` at the nearest and at the
    /// farthest distance (in between it follows the distance).
    pub height: [f64; 2],
    /// Revolutions over the whole path.
    #[serde(default = "one")]
    pub turns: f64,
    /// Far → near → far cycles over the whole path.
    #[serde(default = "two")]
    pub waves: f64,
    /// Azimuth of the first frame, degrees, counter-clockwise about `up`.
    #[serde(default)]
    pub start_deg: f64,
    /// The orbit's axis and the camera's up direction.
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
    /// Frames `bench` samples along the orbit by default.
    #[serde(default = "default_frames")]
    pub frames: u32,
}

fn one() -> f64 {
    1.0
}
fn two() -> f64 {
    2.0
}
fn default_frames() -> u32 {
    240
}

impl Orbit {
    /// An orbit that shows a bounding box `lo`..`hi` (z up) from just
    /// outside it to well away, for scenes that bring no path of their own.
    pub fn around(lo: DVec3, hi: DVec3) -> Orbit {
        let c = (lo + hi) * 0.5;
        // At least a unit radius: a flat or empty box still gets a camera.
        let r = ((hi - lo).length() * 0.5).max(1.0);
        Orbit {
            center: c.to_array(),
            distance: [1.2 * r, 2.8 * r],
            height: [0.25 * r, 0.9 * r],
            turns: 1.0,
            waves: 2.0,
            start_deg: -60.0,
            up: default_up(),
            fov_y_deg: default_fov(),
            near: 0.01 * r,
            far: 10.0 * r,
            frames: default_frames(),
        }
    }

    /// The camera at `t` ∈ [0, 1]: azimuth `start_deg + 360° · turns · t`,
    /// distance and height at their far ends at t = 0, nearest halfway
    /// through each wave.
    pub fn camera(&self, t: f64) -> Camera {
        let up = DVec3::from_array(self.up).normalize();
        // Any vector not parallel to up gives the azimuth's zero direction.
        let seed = if up.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let e1 = (seed - up * seed.dot(up)).normalize();
        let e2 = up.cross(e1);
        let a = self.start_deg.to_radians() + TAU * self.turns * t;
        let s = 0.5 * (1.0 + (TAU * self.waves * t).cos());
        let d = self.distance[0] + (self.distance[1] - self.distance[0]) * s;
        let h = self.height[0] + (self.height[1] - self.height[0]) * s;
        let c = DVec3::from_array(self.center);
        Camera {
            position: (c + (e1 * a.cos() + e2 * a.sin()) * d + up * h).to_array(),
            target: self.center,
            up: self.up,
            fov_y_deg: self.fov_y_deg,
            near: self.near,
            far: self.far,
        }
    }

    /// Checks the numbers make an orbit; the message names the key.
    pub fn check(&self) -> Result<(), String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.center) || !finite(&self.up) {
            return Err("center and up must be finite".into());
        }
        if DVec3::from_array(self.up).length() == 0.0 {
            return Err("up must not be zero".into());
        }
        let [d0, d1] = self.distance;
        if !(finite(&self.distance) && d0 > 0.0 && d1 >= d0) {
            return Err(format!(
                "distance = [nearest, farthest] needs 0 < nearest <= farthest (got [{d0}, {d1}])"
            ));
        }
        if !finite(&self.height) {
            return Err("height must be finite".into());
        }
        if !finite(&[self.turns, self.start_deg]) {
            return Err("turns and start_deg must be finite".into());
        }
        if !(self.waves.is_finite() && self.waves >= 0.0) {
            return Err(format!("waves must be >= 0 (got {})", self.waves));
        }
        if self.frames == 0 {
            return Err("frames must be at least 1".into());
        }
        // The eye is never on the axis (distance > 0), so one camera checks
        // the lens for the whole orbit.
        self.camera(0.0).check()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn orbit() -> Orbit {
        Orbit {
            center: [1.0, 2.0, 3.0],
            distance: [4.0, 10.0],
            height: [1.0, 5.0],
            turns: 1.0,
            waves: 2.0,
            start_deg: 0.0,
            up: [0.0, 0.0, 1.0],
            fov_y_deg: 45.0,
            near: 0.05,
            far: 100.0,
            frames: 240,
        }
    }

    fn horizontal(c: &Camera, o: &Orbit) -> (f64, f64) {
        let d = DVec3::from_array(c.position) - DVec3::from_array(o.center);
        (d.truncate().length(), d.z)
    }

    #[test]
    fn moves_in_and_out_while_circling() {
        let o = orbit();
        let (d, h) = horizontal(&o.camera(0.0), &o);
        assert!((d - 10.0).abs() < 1e-12 && (h - 5.0).abs() < 1e-12);
        // Two waves: nearest at a quarter and three quarters of the way.
        let (d, h) = horizontal(&o.camera(0.25), &o);
        assert!((d - 4.0).abs() < 1e-12 && (h - 1.0).abs() < 1e-12);
        let (d, _) = horizontal(&o.camera(0.5), &o);
        assert!((d - 10.0).abs() < 1e-12);
        // A quarter turn at t = 0.25; back where it began at t = 1.
        let p = DVec3::from_array(o.camera(0.25).position) - DVec3::from_array(o.center);
        assert!(p.x.abs() < 1e-9 && p.y > 0.0, "{p}");
        let (a, b) = (o.camera(0.0).position, o.camera(1.0).position);
        assert!((DVec3::from_array(a) - DVec3::from_array(b)).length() < 1e-9);
        assert_eq!(o.camera(0.3).target, o.center);
    }

    #[test]
    fn bad_values_are_named() {
        type Spoil = fn(&mut Orbit);
        let cases: [(Spoil, &str); 6] = [
            (|o| o.distance = [5.0, 4.0], "nearest <= farthest"),
            (|o| o.distance = [0.0, 4.0], "0 < nearest"),
            (|o| o.waves = -1.0, "waves"),
            (|o| o.frames = 0, "frames"),
            (|o| o.up = [0.0; 3], "up"),
            (|o| o.near = 0.0, "near"),
        ];
        for (spoil, want) in cases {
            let mut o = orbit();
            spoil(&mut o);
            let e = o.check().unwrap_err();
            assert!(e.contains(want), "{want}: {e}");
        }
        assert!(orbit().check().is_ok());
    }

    #[test]
    fn a_box_orbit_looks_at_the_box_from_outside() {
        let o = Orbit::around(DVec3::new(-2.0, -2.0, 0.0), DVec3::new(2.0, 2.0, 1.0));
        o.check().unwrap();
        for i in 0..8 {
            let c = o.camera(i as f64 / 8.0);
            let eye = DVec3::from_array(c.position);
            assert!(
                eye.x.abs() > 2.0 || eye.y.abs() > 2.0 || eye.z > 1.0,
                "{eye}"
            );
            assert_eq!(c.target, [0.0, 0.0, 0.5]);
        }
    }
}
