//! Points as values or as linear combinations of named points.
//!
//! The shading construction (`tangent.rs`) is written once over
//! [`Vector`]: run on [`DVec3`] it computes tangent vectors, run on
//! [`Comb`] it computes *which* combination of the patches' control points
//! each tangent vector is, the recipe the animation applies every frame
//! (`stencil.rs`). Both follow the same operations, so the recipe is the
//! construction and not a second copy of its formulas.

use std::ops::{Add, Mul, Neg, Sub};

use glam::DVec3;

/// What the construction needs of a point or vector type.
pub trait Vector:
    Clone
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<f64, Output = Self>
    + Neg<Output = Self>
    + Sized
{
    /// The zero vector.
    fn zero() -> Self;
}

impl Vector for DVec3 {
    fn zero() -> Self {
        DVec3::ZERO
    }
}

/// A linear combination Σ cₖ·xₖ of named inputs xₖ (ids), terms sorted by
/// id, none with a zero coefficient.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Comb(pub Vec<(u32, f64)>);

impl Comb {
    /// The input `id` itself.
    pub fn of(id: u32) -> Self {
        Comb(vec![(id, 1.0)])
    }

    /// Its value for inputs `x`.
    pub fn eval(&self, x: &dyn Fn(u32) -> DVec3) -> DVec3 {
        self.0.iter().fold(DVec3::ZERO, |s, &(i, c)| s + x(i) * c)
    }

    /// The sum of the coefficients (1 for a point of an affine
    /// construction, 0 for a vector).
    pub fn sum(&self) -> f64 {
        self.0.iter().map(|t| t.1).sum()
    }

    /// The same combination of other names.
    pub fn renamed(&self, name: &dyn Fn(u32) -> u32) -> Self {
        let mut terms: Vec<(u32, f64)> = self.0.iter().map(|&(i, c)| (name(i), c)).collect();
        terms.sort_by_key(|t| t.0);
        let mut out: Vec<(u32, f64)> = Vec::with_capacity(terms.len());
        for (i, c) in terms {
            match out.last_mut() {
                Some(last) if last.0 == i => last.1 += c,
                _ => out.push((i, c)),
            }
        }
        out.retain(|t| t.1 != 0.0);
        Comb(out)
    }
}

impl Add for Comb {
    type Output = Comb;
    fn add(self, o: Comb) -> Comb {
        let (a, b) = (self.0, o.0);
        let mut out = Vec::with_capacity(a.len() + b.len());
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let take_a = j == b.len() || (i < a.len() && a[i].0 < b[j].0);
            let take_b = i == a.len() || (j < b.len() && b[j].0 < a[i].0);
            if take_a {
                out.push(a[i]);
                i += 1;
            } else if take_b {
                out.push(b[j]);
                j += 1;
            } else {
                let c = a[i].1 + b[j].1;
                if c != 0.0 {
                    out.push((a[i].0, c));
                }
                i += 1;
                j += 1;
            }
        }
        Comb(out)
    }
}

impl Neg for Comb {
    type Output = Comb;
    fn neg(self) -> Comb {
        Comb(self.0.into_iter().map(|(i, c)| (i, -c)).collect())
    }
}

impl Sub for Comb {
    type Output = Comb;
    fn sub(self, o: Comb) -> Comb {
        self + (-o)
    }
}

impl Mul<f64> for Comb {
    type Output = Comb;
    fn mul(self, f: f64) -> Comb {
        if f == 0.0 {
            return Comb::default();
        }
        Comb(
            self.0
                .into_iter()
                .map(|(i, c)| (i, c * f))
                .filter(|t| t.1 != 0.0)
                .collect(),
        )
    }
}

impl Vector for Comb {
    fn zero() -> Self {
        Comb::default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn combinations_follow_the_values() {
        let x = |i: u32| DVec3::new(i as f64, 1.0 + i as f64 * 0.5, -(i as f64));
        let a = Comb::of(3) * 2.0 - Comb::of(1);
        let b = (Comb::of(1) + Comb::of(7) * 0.25) * -3.0;
        let c = a.clone() + b.clone() - Comb::of(3) * 2.0;
        let want = (x(3) * 2.0 - x(1)) + (x(1) + x(7) * 0.25) * -3.0 - x(3) * 2.0;
        assert!((c.eval(&x) - want).length() < 1e-12);
        // x3 cancels and is dropped.
        assert_eq!(c.0.iter().map(|t| t.0).collect::<Vec<_>>(), vec![1, 7]);
        assert_eq!((a.sum(), Comb::zero().sum()), (1.0, 0.0));
        let r = (Comb::of(1) + Comb::of(2)).renamed(&|_| 5);
        assert_eq!(r, Comb(vec![(5, 2.0)]));
    }
}
