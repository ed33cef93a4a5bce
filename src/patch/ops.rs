//! Floating-point building blocks in a fixed operation order.
//!
//! Every function here has a twin in `glsl/common/ops.glsl` that performs the
//! same IEEE operations in the same order under `precise`. That is what lets
//! the CPU oracle and the GPU agree bit for bit, and what lets two patches that
//! share an edge take the same decision about it. Never replace these with
//! glam's `dot`/`cross`/matrix products: their internal order is not ours to
//! pin, and a GPU compiler is free to reorder the built-ins.

use glam::{Vec3, Vec4};

use crate::constants::{THIRD_BITS, TWO_THIRDS_BITS};

/// f32(1/3), spelled as bits so GLSL and Rust cannot disagree on the literal.
pub const THIRD: f32 = f32::from_bits(THIRD_BITS);
/// f32(2/3).
pub const TWO_THIRDS: f32 = f32::from_bits(TWO_THIRDS_BITS);

/// `(a.x*b.x + a.y*b.y) + a.z*b.z`.
#[inline]
pub fn dot3(a: Vec3, b: Vec3) -> f32 {
    (a.x * b.x + a.y * b.y) + a.z * b.z
}

/// `a × b`, each component as `p*q - r*s` (no fused multiply-add).
#[inline]
pub fn cross3(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// A plane or affine row `(r.xyz, r.w)` applied to a point:
/// `((r.x*p.x + r.y*p.y) + r.z*p.z) + r.w`.
#[inline]
pub fn affine_row(r: Vec4, p: Vec3) -> f32 {
    ((r.x * p.x + r.y * p.y) + r.z * p.z) + r.w
}

/// `2^-l` built from its bit pattern: exact, where `exp2` and division are
/// not promised to be on a GPU.
#[inline]
pub fn pow2_neg(l: u32) -> f32 {
    debug_assert!(l < 127);
    f32::from_bits((127 - l) << 23)
}

/// Componentwise minimum (plain comparisons, no NaN handling needed: inputs
/// are validated finite on import).
#[inline]
pub fn min3(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        if b.x < a.x { b.x } else { a.x },
        if b.y < a.y { b.y } else { a.y },
        if b.z < a.z { b.z } else { a.z },
    )
}

/// Componentwise maximum.
#[inline]
pub fn max3(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(
        if b.x > a.x { b.x } else { a.x },
        if b.y > a.y { b.y } else { a.y },
        if b.z > a.z { b.z } else { a.z },
    )
}

/// `max(a, b)` for finite inputs, written as the comparison GLSL will use.
#[inline]
pub fn maxf(a: f32, b: f32) -> f32 {
    if b > a {
        b
    } else {
        a
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thirds_are_the_rounded_fractions() {
        assert_eq!(THIRD, 1.0f32 / 3.0);
        assert_eq!(TWO_THIRDS, 2.0f32 / 3.0);
    }

    #[test]
    fn pow2_neg_is_exact() {
        for l in 0..=20u32 {
            assert_eq!(pow2_neg(l), 1.0 / (1u64 << l) as f32);
        }
    }

    #[test]
    fn cross_is_antisymmetric_bitwise() {
        let a = Vec3::new(0.1, -2.7, 3.3);
        let b = Vec3::new(-1.9, 0.4, 8.2);
        assert_eq!(cross3(a, b), -cross3(b, a));
        assert_eq!(dot3(a, b), dot3(b, a));
    }
}
