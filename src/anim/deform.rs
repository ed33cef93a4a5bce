//! Procedural deformers (bend, twist, wave) of a cage's vertices, in f32
//! arithmetic written out in a fixed order: the twin of
//! `glsl/common/anim.glsl`, which the GPU's update pass runs on the same
//! inputs to the same bits. Sine and cosine are not the platform's (GLSL's
//! are not correctly rounded, and differ between devices) but a
//! Cody–Waite range reduction and Taylor polynomials, [`sin_cos`].
//!
//! Everything that depends only on time (angles, curvature and its
//! inverse, the wave's phase) is computed once per frame on the CPU in f64
//! and rounded to f32 ([`Deformer::at`]); the shaders receive those numbers.

use bytemuck::{Pod, Zeroable};

use crate::constants::*;
use crate::scene::keys::{Deformer, Kind};

fn f(bits: u32) -> f32 {
    f32::from_bits(bits)
}

/// The largest |x| [`sin_cos`] reduces exactly (4,096 quarter turns);
/// beyond it the argument is clamped.
pub const SIN_COS_LIMIT: f32 = 6433.0;

/// (sin x, cos x) in f32, the twin of `anim_sin_cos`: x·(2/π) rounded
/// down from +½ to a quarter turn q, r = (x − q·HI) − q·LO, Taylor
/// polynomials in Horner form on r, then the quadrant. Within 4e-7 of the
/// true values for |x| ≤ [`SIN_COS_LIMIT`].
pub fn sin_cos(x: f32) -> (f32, f32) {
    let x = x.clamp(-SIN_COS_LIMIT, SIN_COS_LIMIT);
    let q = (x * f(ANIM_TWO_OVER_PI_BITS) + 0.5).floor();
    let r = (x - q * f(ANIM_PIO2_HI_BITS)) - q * f(ANIM_PIO2_LO_BITS);
    let r2 = r * r;
    let ps = f(ANIM_SIN_2_BITS) + r2 * f(ANIM_SIN_3_BITS);
    let ps = f(ANIM_SIN_1_BITS) + r2 * ps;
    let s = r + r * (r2 * ps);
    let pc = f(ANIM_COS_3_BITS) + r2 * f(ANIM_COS_4_BITS);
    let pc = f(ANIM_COS_2_BITS) + r2 * pc;
    let pc = f(ANIM_COS_1_BITS) + r2 * pc;
    let c = 1.0 + r2 * pc;
    match (q as i32) & 3 {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// A deformer as the update pass reads it (`AnimDeformer` in
/// `glsl/common/anim.glsl`), for one frame.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuDeformer {
    /// `DEFORM_*`.
    pub kind: u32,
    /// Twist: the axis turned about; bend: the axis bent along; wave: the
    /// axis displaced (0, 1, 2: x, y, z).
    pub axis: u32,
    /// Bend: the axis it bends towards; wave: the axis it travels along.
    pub other: u32,
    /// Padding.
    pub pad: u32,
    /// The centre (xyz; w unused).
    pub center: [f32; 4],
    /// Twist: radians per unit along the axis. Bend: curvature k, 1/k (0
    /// for k = 0: no bend), the length bent. Wave: amplitude, radians per
    /// unit along `other`, phase, 1/(length it grows over) or 0.
    pub p: [f32; 4],
}

/// The points `ps` moved by each of `deformers` in turn (a model's cage
/// vertices in a frame: the CPU twin of the deform pass).
pub fn apply_all(deformers: &[GpuDeformer], ps: &[glam::Vec3]) -> Vec<glam::Vec3> {
    ps.iter()
        .map(|p| {
            let q = deformers.iter().fold(p.to_array(), |q, d| apply(d, q));
            glam::Vec3::from_array(q)
        })
        .collect()
}

/// Applies `d` to the point `p` (the twin of `anim_deform`).
pub fn apply(d: &GpuDeformer, p: [f32; 3]) -> [f32; 3] {
    let c = d.center;
    let mut p = p;
    let a = d.axis as usize % 3;
    match d.kind {
        DEFORM_TWIST => {
            let (b1, b2) = ((a + 1) % 3, (a + 2) % 3);
            let h = p[a] - c[a];
            let theta = h * d.p[0];
            let (s, co) = sin_cos(theta);
            let u = p[b1] - c[b1];
            let v = p[b2] - c[b2];
            let u2 = u * co - v * s;
            let v2 = u * s + v * co;
            p[b1] = c[b1] + u2;
            p[b2] = c[b2] + v2;
        }
        DEFORM_BEND => {
            let (k, inv_k, length) = (d.p[0], d.p[1], d.p[2]);
            if k == 0.0 || inv_k == 0.0 {
                return p;
            }
            let t = d.other as usize % 3;
            let h = p[a] - c[a];
            let dist = p[t] - c[t];
            let hc = h.clamp(0.0, length);
            let theta = hc * k;
            let (s, co) = sin_cos(theta);
            let (s2, _) = sin_cos(theta * 0.5);
            let extra = h - hc;
            // (R − d)·sin θ and R·(1 − cos θ) + d·cos θ with R = 1/k and
            // 1 − cos θ = 2 sin²(θ/2), then straight on beyond the length.
            let along = (s * inv_k - dist * s) + extra * co;
            let across = ((s2 * s2) * (2.0 * inv_k) + dist * co) + extra * s;
            p[a] = c[a] + along;
            p[t] = c[t] + across;
        }
        DEFORM_WAVE => {
            let t = d.other as usize % 3;
            let (amplitude, freq, phase, inv_grow) = (d.p[0], d.p[1], d.p[2], d.p[3]);
            let x = p[t];
            let (s, _) = sin_cos(x * freq + phase);
            let ramp = if inv_grow > 0.0 {
                ((x - c[t]) * inv_grow).clamp(0.0, 1.0)
            } else {
                1.0
            };
            p[a] += (amplitude * ramp) * s;
        }
        _ => {}
    }
    p
}

/// Rounds to f32, -0 to +0.
fn f32_of(x: f64) -> f32 {
    x as f32 + 0.0
}

// The deformer's GPU form is the update pass's, so it is made here (the
// scene file's description, `scene::keys`, knows nothing of the GPU).
impl Deformer {
    /// The deformer at time `t` as the update pass reads it: every number
    /// that depends on time alone computed here, in f64, rounded once.
    pub fn at(&self, t: f64) -> GpuDeformer {
        let c = self.center;
        let center = [f32_of(c.x), f32_of(c.y), f32_of(c.z), 0.0];
        let (kind, p) = match self.kind {
            Kind::Twist => {
                let rate = self.amount.at(t).to_radians() / self.length;
                (DEFORM_TWIST, [f32_of(rate), 0.0, 0.0, 0.0])
            }
            Kind::Bend => {
                let k = self.amount.at(t).to_radians() / self.length;
                let k32 = f32_of(k);
                let inv = if k32 == 0.0 { 0.0 } else { f32_of(1.0 / k) };
                (DEFORM_BEND, [k32, inv, f32_of(self.length), 0.0])
            }
            Kind::Wave => {
                let tau = std::f64::consts::TAU;
                // Wrapped to one turn so the f32 phase stays exact enough
                // however long the animation runs.
                let phase = (-tau * self.speed * t).rem_euclid(tau);
                let inv_grow = if self.grow > 0.0 {
                    1.0 / self.grow
                } else {
                    0.0
                };
                (
                    DEFORM_WAVE,
                    [
                        f32_of(self.amount.at(t)),
                        f32_of(tau / self.length),
                        f32_of(phase),
                        f32_of(inv_grow),
                    ],
                )
            }
        };
        GpuDeformer {
            kind,
            axis: self.axis.index(),
            other: self.other.index(),
            pad: 0,
            center,
            p,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_and_cosine_are_close_to_the_true_ones() {
        let mut worst = 0.0f64;
        for k in -200_000..=200_000 {
            let x = k as f32 * 0.0005;
            let (s, c) = sin_cos(x);
            let x64 = f64::from(x);
            worst = worst
                .max((f64::from(s) - x64.sin()).abs())
                .max((f64::from(c) - x64.cos()).abs());
        }
        assert!(worst < 4e-7, "{worst}");
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        // Far out the reduction still holds.
        let (s, c) = sin_cos(6000.0);
        assert!((f64::from(s) - 6000f64.sin()).abs() < 2e-6);
        assert!((f64::from(c) - 6000f64.cos()).abs() < 2e-6);
    }

    #[test]
    fn twist_turns_and_bend_keeps_lengths() {
        let twist = GpuDeformer {
            kind: DEFORM_TWIST,
            axis: 2,
            p: [std::f32::consts::PI, 0.0, 0.0, 0.0],
            ..Default::default()
        };
        // Half a unit up: a quarter turn.
        let q = apply(&twist, [1.0, 0.0, 0.5]);
        assert!(q[0].abs() < 1e-6 && (q[1] - 1.0).abs() < 1e-6 && q[2] == 0.5);
        // A quarter circle of length 2 along z, bending towards +x.
        let k = std::f32::consts::FRAC_PI_2 / 2.0;
        let bend = GpuDeformer {
            kind: DEFORM_BEND,
            axis: 2,
            other: 0,
            p: [k, 1.0 / k, 2.0, 0.0],
            ..Default::default()
        };
        let end = apply(&bend, [0.0, 0.0, 2.0]);
        let r = 1.0 / k;
        assert!(
            (end[0] - r).abs() < 1e-5 && (end[2] - r).abs() < 1e-5,
            "{end:?}"
        );
        // Beyond the length: straight on along +x.
        let past = apply(&bend, [0.0, 0.0, 3.0]);
        assert!((past[0] - (r + 1.0)).abs() < 1e-5 && (past[2] - r).abs() < 1e-5);
        // Below the centre: untouched.
        assert_eq!(apply(&bend, [0.25, 0.5, -1.0]), [0.25, 0.5, -1.0]);
    }
}
