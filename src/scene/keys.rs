//! What changes with time in a scene file: numbers given as constants or
//! keys ([`Curve`]), deformers ([`DeformToml`] → [`Deformer`]), keyed
//! instance transforms ([`KeyToml`] → [`InstanceKeys`]) and the
//! `[animation]` table. Times are seconds; between keys values are
//! interpolated linearly (rotations per Euler angle), before the first key
//! and after the last they hold.

use glam::{DMat4, DVec3, EulerRot};
use serde::Deserialize;

/// A number that is constant or follows keys `[[time, value], …]`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Curve {
    /// The same at every time.
    Constant(f64),
    /// (time, value) pairs, times increasing.
    Keys(Vec<[f64; 2]>),
}

impl Curve {
    /// The value at `t`.
    pub fn at(&self, t: f64) -> f64 {
        match self {
            Curve::Constant(v) => *v,
            Curve::Keys(k) => {
                let i = k.partition_point(|p| p[0] <= t);
                match i {
                    0 => k[0][1],
                    i if i == k.len() => k[i - 1][1],
                    i => {
                        let ([t0, v0], [t1, v1]) = (k[i - 1], k[i]);
                        v0 + (v1 - v0) * ((t - t0) / (t1 - t0))
                    }
                }
            }
        }
    }

    /// The time of the last key (0 for a constant).
    pub fn end(&self) -> f64 {
        match self {
            Curve::Constant(_) => 0.0,
            Curve::Keys(k) => k.last().map_or(0.0, |p| p[0]),
        }
    }

    fn check(&self, what: &str) -> Result<(), String> {
        match self {
            Curve::Constant(v) if v.is_finite() => Ok(()),
            Curve::Constant(v) => Err(format!("{what} must be finite (got {v})")),
            Curve::Keys(k) => {
                if k.is_empty() {
                    return Err(format!("{what}: an empty list of keys"));
                }
                if k.iter().flatten().any(|x| !x.is_finite()) {
                    return Err(format!("{what}: keys must be finite"));
                }
                if k.windows(2).any(|w| w[1][0] <= w[0][0]) {
                    return Err(format!(
                        "{what}: key times must increase ([[time, value], …])"
                    ));
                }
                Ok(())
            }
        }
    }
}

/// A coordinate axis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Axis {
    /// x.
    X,
    /// y.
    Y,
    /// z (the default).
    #[default]
    Z,
}

impl Axis {
    /// The axis as the shaders number it (x 0, y 1, z 2).
    pub(crate) fn index(self) -> u32 {
        self as u32
    }
}

/// What kind of deformer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Turns about `axis`, `angle_deg` per `length` along it.
    Twist,
    /// Bends the part from `center` along `axis` over `length` by
    /// `angle_deg`, towards `toward`.
    Bend,
    /// Displaces along `axis` by a sine travelling along `along`.
    Wave,
}

/// One `[[model.deform]]` table.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DeformToml {
    kind: Kind,
    #[serde(default)]
    axis: Axis,
    #[serde(default)]
    center: [f64; 3],
    angle_deg: Option<Curve>,
    length: Option<f64>,
    toward: Option<Axis>,
    along: Option<Axis>,
    amplitude: Option<Curve>,
    wavelength: Option<f64>,
    speed: Option<f64>,
    grow: Option<f64>,
}

/// A checked deformer (model space).
#[derive(Clone, Debug, PartialEq)]
pub struct Deformer {
    pub(crate) kind: Kind,
    pub(crate) axis: Axis,
    pub(crate) other: Axis,
    pub(crate) center: DVec3,
    /// Twist and bend: the angle in degrees; wave: the amplitude.
    pub(crate) amount: Curve,
    /// Twist and bend: the length; wave: the wavelength.
    pub(crate) length: f64,
    /// Wave: cycles per second.
    pub(crate) speed: f64,
    /// Wave: the length over which the amplitude grows from 0.
    pub(crate) grow: f64,
}

impl DeformToml {
    /// Checks the table; `Err` says what is wrong: a key of another kind
    /// first, then the kind's own keys, then its amount and its length.
    pub fn check(&self) -> Result<Deformer, String> {
        if self.center.iter().any(|c| !c.is_finite()) {
            return Err("`center` must be finite".into());
        }
        self.only_its_keys()?;
        let (other, speed, grow) = match self.kind {
            Kind::Twist => (self.axis, 0.0, 0.0),
            Kind::Bend => (self.toward()?, 0.0, 0.0),
            Kind::Wave => self.travel()?,
        };
        // A twist turns `angle_deg` per `length` (default 1), a bend by
        // `angle_deg` over `length`, a wave by `amplitude` per `wavelength`.
        let (amount, length) = match self.kind {
            Kind::Twist => (
                self.amount("angle_deg", &self.angle_deg)?,
                self.positive("length", self.length, Some(1.0))?,
            ),
            Kind::Bend => (
                self.amount("angle_deg", &self.angle_deg)?,
                self.positive("length", self.length, None)?,
            ),
            Kind::Wave => (
                self.amount("amplitude", &self.amplitude)?,
                self.positive("wavelength", self.wavelength, None)?,
            ),
        };
        Ok(Deformer {
            kind: self.kind,
            axis: self.axis,
            other,
            center: DVec3::from_array(self.center),
            amount,
            length,
            speed,
            grow,
        })
    }

    /// Refuses the first optional key (in the table's order) that is given
    /// but does not apply to this kind.
    fn only_its_keys(&self) -> Result<(), String> {
        let own: &[&str] = match self.kind {
            Kind::Twist => &["angle_deg", "length"],
            Kind::Bend => &["angle_deg", "length", "toward"],
            Kind::Wave => &["along", "amplitude", "wavelength", "speed", "grow"],
        };
        let given = [
            ("angle_deg", self.angle_deg.is_some()),
            ("length", self.length.is_some()),
            ("toward", self.toward.is_some()),
            ("along", self.along.is_some()),
            ("amplitude", self.amplitude.is_some()),
            ("wavelength", self.wavelength.is_some()),
            ("speed", self.speed.is_some()),
            ("grow", self.grow.is_some()),
        ];
        match given.iter().find(|(name, g)| *g && !own.contains(name)) {
            Some((name, _)) => Err(format!(
                "`{name}` does not apply to a {:?} deformer",
                self.kind
            )),
            None => Ok(()),
        }
    }

    /// A bend's second axis: the one it bends towards.
    fn toward(&self) -> Result<Axis, String> {
        let toward = self
            .toward
            .ok_or("a Bend deformer needs `toward`: the axis it bends towards")?;
        if toward == self.axis {
            return Err("`toward` must differ from `axis`".into());
        }
        Ok(toward)
    }

    /// A wave's second axis (the one it travels along), its speed and the
    /// length over which it grows.
    fn travel(&self) -> Result<(Axis, f64, f64), String> {
        let along = self
            .along
            .ok_or("a Wave deformer needs `along`: the axis it travels along")?;
        let speed = self.speed.unwrap_or(0.0);
        if !speed.is_finite() {
            return Err("`speed` must be finite".into());
        }
        let grow = self.grow.unwrap_or(0.0);
        if !(grow.is_finite() && grow >= 0.0) {
            return Err(format!("`grow` must be ≥ 0 (got {grow})"));
        }
        Ok((along, speed, grow))
    }

    /// The length `name`: `v`, else `default`; it must be given and > 0.
    fn positive(&self, name: &str, v: Option<f64>, default: Option<f64>) -> Result<f64, String> {
        match v.or(default) {
            Some(x) if x.is_finite() && x > 0.0 => Ok(x),
            Some(x) => Err(format!("`{name}` must be a positive length (got {x})")),
            None => Err(format!("a {:?} deformer needs `{name}`", self.kind)),
        }
    }

    /// The curve `name`, which must be given and valid.
    fn amount(&self, name: &str, c: &Option<Curve>) -> Result<Curve, String> {
        let c = c
            .clone()
            .ok_or_else(|| format!("a {:?} deformer needs `{name}`", self.kind))?;
        c.check(name)?;
        Ok(c)
    }
}

impl Deformer {
    /// The last key time of its curves.
    pub fn end(&self) -> f64 {
        self.amount.end()
    }

    /// Whether it changes with time.
    pub fn moves(&self) -> bool {
        matches!(self.amount, Curve::Keys(_)) || self.speed != 0.0
    }
}

#[derive(Deserialize)]
#[serde(untagged)]
enum ScaleToml {
    Uniform(f64),
    PerAxis([f64; 3]),
}

impl Default for ScaleToml {
    fn default() -> Self {
        ScaleToml::Uniform(1.0)
    }
}

/// One `[[model.instance.key]]` table: the instance's transform at `time`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyToml {
    time: f64,
    #[serde(default)]
    translate: [f64; 3],
    #[serde(default)]
    rotate_deg: [f64; 3],
    #[serde(default)]
    scale: ScaleToml,
}

/// One key of an instance's transform.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    time: f64,
    translate: DVec3,
    rotate_deg: DVec3,
    scale: DVec3,
}

/// An instance's keyed transform, after an offset (its grid cell).
#[derive(Clone, Debug, PartialEq)]
pub struct InstanceKeys {
    keys: Vec<Key>,
    offset: DVec3,
}

impl InstanceKeys {
    /// Checks the keys (at least one, times increasing, scales non-zero
    /// and of one handedness: a patch cannot turn inside out mid-flight).
    pub fn new(list: &[KeyToml]) -> Result<Self, String> {
        let mut keys = Vec::new();
        for (k, key) in list.iter().enumerate() {
            let scale = match key.scale {
                ScaleToml::Uniform(s) => DVec3::splat(s),
                ScaleToml::PerAxis(s) => DVec3::from_array(s),
            };
            let all = [key.time]
                .into_iter()
                .chain(key.translate)
                .chain(key.rotate_deg)
                .chain(scale.to_array());
            if all.into_iter().any(|x| !x.is_finite()) {
                return Err(format!("key {}: every number must be finite", k + 1));
            }
            if scale.x * scale.y * scale.z == 0.0 {
                return Err(format!("key {}: scale must be non-zero", k + 1));
            }
            keys.push(Key {
                time: key.time,
                translate: DVec3::from_array(key.translate),
                rotate_deg: DVec3::from_array(key.rotate_deg),
                scale,
            });
        }
        if keys.windows(2).any(|w| w[1].time <= w[0].time) {
            return Err("key times must increase".into());
        }
        let sign = |k: &Key| (k.scale.x * k.scale.y * k.scale.z).signum();
        if keys.windows(2).any(|w| sign(&w[0]) != sign(&w[1])) {
            return Err(
                "every key's scale must mirror alike (all or none with an odd number of negative axes)"
                    .into(),
            );
        }
        Ok(InstanceKeys {
            keys,
            offset: DVec3::ZERO,
        })
    }

    /// The same keys after a translation by `offset`.
    pub fn offset(&self, offset: DVec3) -> Self {
        InstanceKeys {
            keys: self.keys.clone(),
            offset: self.offset + offset,
        }
    }

    /// The last key's time.
    pub fn end(&self) -> f64 {
        self.keys.last().map_or(0.0, |k| k.time)
    }

    /// The transform at `t`.
    pub fn at(&self, t: f64) -> DMat4 {
        let k = &self.keys;
        let i = k.partition_point(|x| x.time <= t);
        let key = match i {
            0 => k[0],
            i if i == k.len() => k[i - 1],
            i => {
                let (a, b) = (k[i - 1], k[i]);
                let s = (t - a.time) / (b.time - a.time);
                Key {
                    time: t,
                    translate: a.translate.lerp(b.translate, s),
                    rotate_deg: a.rotate_deg.lerp(b.rotate_deg, s),
                    scale: a.scale.lerp(b.scale, s),
                }
            }
        };
        let r = key.rotate_deg.to_array().map(f64::to_radians);
        DMat4::from_translation(self.offset + key.translate)
            * DMat4::from_euler(EulerRot::ZYX, r[2], r[1], r[0])
            * DMat4::from_scale(key.scale)
    }
}

/// The `[animation]` table.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AnimationToml {
    /// Seconds of one pass (default: the last key of anything).
    pub duration: Option<f64>,
    /// Frames per second (`--anim-frame`, the window's steps, `bench`;
    /// default 24).
    pub fps: Option<f64>,
    /// Whether time wraps at the end (default true).
    #[serde(rename = "loop")]
    pub looping: Option<bool>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_interpolate_and_hold() {
        let c = Curve::Keys(vec![[1.0, 0.0], [3.0, 10.0]]);
        assert_eq!(
            (c.at(0.0), c.at(2.0), c.at(9.0), c.end()),
            (0.0, 5.0, 10.0, 3.0)
        );
        assert!(Curve::Keys(vec![[1.0, 0.0], [1.0, 2.0]])
            .check("x")
            .is_err());
        assert_eq!(Curve::Constant(2.5).at(7.0), 2.5);
    }
}
