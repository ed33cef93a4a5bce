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

use std::collections::HashMap;

use glam::{DVec3, I64Vec3, Vec3};

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

/// The finest footprint a level's shading is measured at, as a fraction
/// of its model's box diagonal (2⁻¹⁰), and how many are measured, each
/// twice the one before (up to 2⁻²).
pub const FINEST: f32 = 1.0 / 1024.0;
/// See [`FINEST`].
pub const SCALES: usize = 9;

/// A level's shading error: at each point, and over footprints of growing
/// side.
#[derive(Clone, Debug, Default)]
pub struct Shading {
    /// The surface-area-weighted mean angle, in radians, between the
    /// surface's normal at each sample and the level's shaded normal at
    /// its nearest point (as [`super::error::normal_error`] measures it).
    pub unfiltered: f32,
    /// (side in model units, error in radians), finest first: per cubic
    /// cell of that side, the angle whose chord is the cell's area-weighted
    /// mean of (level normal − surface normal), 2·asin(|mean Δn| / 2) (for
    /// one sample, the angle between the two), averaged over the cells by
    /// area.
    pub by_scale: Vec<(f32, f32)>,
}

/// [`Shading`] of `mesh` against the surface `samples`, at [`SCALES`]
/// footprints from `finest` (model units) up, each twice the one before.
/// `two_sided`: the level's normal is taken on the sample's side first, as
/// such a model is lit. One nearest-point query per sample; the cells of a
/// footprint are those of the one before merged in eights, their sums made
/// in sample order and in the order cells were first met, so the result
/// does not depend on the machine.
pub fn measure(samples: &[NormalSample], mesh: &TriMesh, two_sided: bool, finest: f32) -> Shading {
    let near = NearestTriangle::new(mesh);
    // Per chunk: each sample's normal difference, and the chunk's sums of
    // angle × area and area (merged in chunk order, as `normal_error`).
    let (deltas, angle_sum, area_sum) = fold_chunks(
        samples,
        |part| {
            let mut out = (Vec::with_capacity(part.len()), 0.0f64, 0.0f64);
            for s in part {
                let n = shaded_normal(mesh, &near, s.point);
                let n = if two_sided && n.dot(s.normal) < 0.0 {
                    -n
                } else {
                    n
                };
                let a = f64::from(s.area);
                out.0.push(n - s.normal);
                out.1 += f64::from(n.dot(s.normal).clamp(-1.0, 1.0).acos()) * a;
                out.2 += a;
            }
            out
        },
        |mut a, b| {
            a.0.extend(b.0);
            (a.0, a.1 + b.1, a.2 + b.2)
        },
        (Vec::new(), 0.0, 0.0),
    );
    let lo = samples
        .iter()
        .fold(Vec3::splat(f32::MAX), |lo, s| lo.min(s.point));
    let mut cells = finest_cells(samples, &deltas, lo, finest);
    let mut by_scale = Vec::with_capacity(SCALES);
    for k in 0..SCALES {
        if k > 0 {
            cells = merged(&cells);
        }
        by_scale.push((finest * (1u32 << k) as f32, mean_over(&cells)));
    }
    Shading {
        unfiltered: (angle_sum / area_sum.max(f64::MIN_POSITIVE)) as f32,
        by_scale,
    }
}

/// A cell: its integer coordinates at its side, its sum of Δn × area, its
/// area.
type Cell = (I64Vec3, DVec3, f64);

/// The samples' sums per cell of side `side` from `lo`, in the order the
/// cells are first met.
fn finest_cells(samples: &[NormalSample], deltas: &[Vec3], lo: Vec3, side: f32) -> Vec<Cell> {
    let mut cells = Vec::new();
    let mut index = HashMap::new();
    for (s, d) in samples.iter().zip(deltas) {
        let key = ((s.point - lo) / side).floor().as_i64vec3();
        add(
            &mut cells,
            &mut index,
            key,
            d.as_dvec3() * f64::from(s.area),
            f64::from(s.area),
        );
    }
    cells
}

/// The cells of twice the side: each eight of `cells` merged.
fn merged(cells: &[Cell]) -> Vec<Cell> {
    let mut out = Vec::new();
    let mut index = HashMap::new();
    for &(key, sum, area) in cells {
        // Coordinates are never negative (measured from the samples' lower
        // corner): a shift halves them rounding down, as floor would.
        add(&mut out, &mut index, key >> 1, sum, area);
    }
    out
}

fn add(
    cells: &mut Vec<Cell>,
    index: &mut HashMap<I64Vec3, usize>,
    key: I64Vec3,
    sum: DVec3,
    area: f64,
) {
    let k = *index.entry(key).or_insert_with(|| {
        cells.push((key, DVec3::ZERO, 0.0));
        cells.len() - 1
    });
    cells[k].1 += sum;
    cells[k].2 += area;
}

/// The area-weighted mean over `cells` of the angle whose chord is the
/// cell's mean normal difference.
fn mean_over(cells: &[Cell]) -> f32 {
    let (sum, area) =
        cells
            .iter()
            .filter(|c| c.2 > 0.0)
            .fold((0.0, 0.0), |(sum, area), (_, d, a)| {
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
        // Footprints 0.002 to 0.512 (the ball's radius is 1).
        let m = measure(&samples, &coarse, false, 0.002);
        assert_eq!(m.unfiltered, unfiltered);
        let e: Vec<f32> = m.by_scale.iter().map(|s| s.1).collect();
        assert_eq!(m.by_scale[8].0, 0.512);
        // At cells much finer than the samples' spacing each cell holds
        // one sample (two or four where patches meet, at an angle on the
        // ball): about the unfiltered error.
        assert!(
            (e[0] - unfiltered).abs() < 0.1 * unfiltered,
            "{e:?} {unfiltered}"
        );
        // Cells as large as a coarse triangle (about 0.5) average half of
        // its error away (measured: 0.121 at 0.002, 0.104 at 0.256, 0.053
        // at 0.512).
        assert!(e[7] < 0.9 * unfiltered, "{e:?}");
        assert!(e[8] < 0.5 * unfiltered, "{e:?}");
        assert!(e.windows(2).all(|w| w[1] <= w[0] + 1e-4), "{e:?}");
        assert_eq!(error_at(&m.by_scale, unfiltered, 0.001), unfiltered);
        assert_eq!(error_at(&m.by_scale, unfiltered, 0.3), e[7]);
        assert_eq!(error_at(&m.by_scale, unfiltered, 5.0), e[8]);
    }
}
