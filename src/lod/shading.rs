//! How far a level's shading lies from the surface's as a viewer sees it.
//!
//! A level's vertex normals, interpolated, differ from the limit surface's
//! normal inside each of its triangles ([`super::error::normal_error`]).
//! Up close that difference is a visible change of a highlight; far away a
//! triangle covers a pixel or two and the eye (and FLIP, which models it)
//! sees only the mean over a small neighbourhood, where the fitted normals
//! ([`super::error::fit_normals`]), being area-weighted means of the
//! surface's, nearly agree with the surface. So a level's shading error is
//! measured at several scales — the mean normal difference over cubic cells
//! of each side — and an instance takes a level by the error at the scale
//! one filter footprint has at its distance ([`footprint_pixels`]).
//!
//! Lambertian shading is linear in the normal, so the mean difference of
//! the normals bounds the mean difference of the diffuse shade; a
//! highlight is not linear, and for it this is an estimate, not a bound.

use glam::{DVec3, Vec3};

use super::error::{fold_chunks, shaded_normal, NearestTriangle, NormalSample};
use super::mesh::TriMesh;
use crate::eval::flip::PIXELS_PER_DEGREE;

/// FLIP's achromatic contrast-sensitivity filter is a Gaussian of variance
/// b / (2π²) square degrees with this b (Andersson et al. 2020, "FLIP: A
/// Difference Evaluator for Alternating Images", the A channel's b₁).
const FLIP_ACHROMATIC_B: f32 = 0.0047;

/// The side, in pixels, of the square whose mean stands for FLIP's
/// achromatic filter at its viewing distance: the box of the Gaussian's
/// variance (σ√12; σ ≈ 1.03 pixels at 67 pixels per degree, the box
/// 3.6 pixels). Brightness differences finer than this the filter averages.
pub fn footprint_pixels() -> f32 {
    let sigma_deg = (FLIP_ACHROMATIC_B / (2.0 * std::f32::consts::PI.powi(2))).sqrt();
    sigma_deg * PIXELS_PER_DEGREE * 12f32.sqrt()
}

/// The scales a level's shading is measured at, as fractions of its
/// model's box diagonal, finest first: 2⁻¹⁰ to 2⁻² by factors of 2.
pub fn scale_fractions() -> impl Iterator<Item = f32> {
    (0..=8).map(|k| (2.0f32).powi(k - 10))
}

/// For each of `scales` (model units, finest first): the surface-area-
/// weighted mean, over cubic cells of that side, of the angle whose chord
/// is the cell's mean difference between `mesh`'s shaded normal and the
/// surface's at `samples` (2·asin(|mean Δn| / 2); for one sample, the angle
/// between the two). `two_sided`: the level's normal is taken on the
/// sample's side first, as such a model is lit.
pub fn filtered_errors(
    samples: &[NormalSample],
    mesh: &TriMesh,
    two_sided: bool,
    scales: &[f32],
) -> Vec<f32> {
    let near = NearestTriangle::new(mesh);
    let deltas = fold_chunks(
        samples,
        |part| {
            part.iter()
                .map(|s| {
                    let n = shaded_normal(mesh, &near, s.point);
                    let n = if two_sided && n.dot(s.normal) < 0.0 {
                        -n
                    } else {
                        n
                    };
                    n - s.normal
                })
                .collect::<Vec<Vec3>>()
        },
        |mut a, b| {
            a.extend(b);
            a
        },
        Vec::new(),
    );
    let lo = samples
        .iter()
        .fold(Vec3::splat(f32::MAX), |lo, s| lo.min(s.point));
    let deltas = deltas.as_slice();
    std::thread::scope(|s| {
        let workers: Vec<_> = scales
            .iter()
            .map(|&side| s.spawn(move || error_at_scale(samples, deltas, lo, side)))
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("a shading worker does not panic"))
            .collect()
    })
}

/// [`filtered_errors`] at one cell side: the cells' sums are made in
/// sample order and averaged in the order the cells were first met, so the
/// result does not depend on the machine.
fn error_at_scale(samples: &[NormalSample], deltas: &[Vec3], lo: Vec3, side: f32) -> f32 {
    let mut index = std::collections::HashMap::new();
    let mut cells: Vec<(DVec3, f64)> = Vec::new();
    for (s, d) in samples.iter().zip(deltas) {
        let key = ((s.point - lo) / side).floor().as_i64vec3();
        let k = *index.entry(key).or_insert_with(|| {
            cells.push((DVec3::ZERO, 0.0));
            cells.len() - 1
        });
        let a = f64::from(s.area);
        cells[k].0 += d.as_dvec3() * a;
        cells[k].1 += a;
    }
    let (sum, area) =
        cells
            .iter()
            .filter(|(_, a)| *a > 0.0)
            .fold((0.0, 0.0), |(sum, area), (d, a)| {
                let chord = (d.length() / a).min(2.0);
                (sum + 2.0 * (chord / 2.0).asin() * a, area + a)
            });
    (sum / f64::max(area, f64::MIN_POSITIVE)) as f32
}

/// A level's shading error seen through a footprint `side` model units
/// across: the error measured at the largest scale of `by_scale` ((side,
/// error), finest first) not above it, or `unfiltered` (the error at each
/// point) where the footprint is finer than every scale measured. A coarser
/// scale's error is not assumed smaller: the nearest scale below is taken.
pub fn error_at(by_scale: &[(f32, f32)], unfiltered: f32, side: f32) -> f32 {
    by_scale
        .iter()
        .take_while(|(s, _)| *s <= side)
        .last()
        .map_or(unfiltered, |&(_, e)| e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lod::{error, mesh};

    #[test]
    fn flips_filter_is_about_three_and_a_half_pixels() {
        let f = footprint_pixels();
        assert!((3.5..3.7).contains(&f), "{f}");
    }

    #[test]
    fn a_coarse_balls_shading_error_falls_with_the_footprint() {
        let ball = mesh::shapes::ball(2);
        let samples = error::surface_normals(&ball, 16);
        let mut coarse = mesh::limit_mesh(&ball, 1, &mesh::plain_uv);
        error::fit_normals(&mut coarse, &samples);
        let unfiltered = error::normal_error(&samples, &coarse, false);
        let scales: Vec<f32> = [0.001, 0.05, 0.3, 1.0].to_vec();
        let by_scale = filtered_errors(&samples, &coarse, false, &scales);
        // At cells much finer than the samples' spacing each cell holds
        // one sample (two or four where patches meet, at an angle on the
        // ball): about the unfiltered error, as `normal_error` measures it.
        assert!(
            (by_scale[0] - unfiltered).abs() < 0.1 * unfiltered,
            "{by_scale:?} {unfiltered}"
        );
        // Cells as large as a coarse triangle (about 0.5) average much of
        // its error away (measured: 0.13 unfiltered, 0.07 and 0.04 at 0.3
        // and 1).
        assert!(by_scale[2] < 0.7 * unfiltered, "{by_scale:?}");
        assert!(by_scale[3] < 0.4 * unfiltered, "{by_scale:?}");
        assert!(
            by_scale.windows(2).all(|w| w[1] <= w[0] + 1e-4),
            "{by_scale:?}"
        );
        let pairs: Vec<(f32, f32)> = scales.iter().copied().zip(by_scale.clone()).collect();
        assert_eq!(error_at(&pairs, unfiltered, 0.0005), unfiltered);
        assert_eq!(error_at(&pairs, unfiltered, 0.2), by_scale[1]);
        assert_eq!(error_at(&pairs, unfiltered, 5.0), by_scale[3]);
    }
}
