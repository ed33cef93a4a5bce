//! The comparison at equal error: each method's curve over ε of image
//! error against triangles and against frame time, and what the baseline
//! method (the registry's `Role::Baseline`) needs for the same error,
//! interpolated on its curve.
//!
//! Comparing at one ε compares two different promises (a sample test for
//! subdivision, a bound for tessellation), so the fair question is: for the
//! error a configuration reaches, how many triangles (and how much time)
//! does the other method need? A curve's points are its ε values, each at
//! the medians over the FLIP perspectives (error, triangles of those same
//! images) and the median frame time along the path. Between two points the
//! curve is interpolated log-log (error and triangles both span decades);
//! outside its range nothing is claimed.

use super::record::{Config, ConfigSummary};

/// One configuration on its curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Pixel tolerance.
    pub eps: f64,
    /// The error measure: median over the perspectives (FLIP, or the
    /// geometric error in pixels).
    pub error: f64,
    /// Median triangles of the FLIP images.
    pub triangles: f64,
    /// Median GPU frame time along the path, if frames were timed.
    pub frame_ms: Option<f64>,
}

/// A method at one λ (or a method that ignores λ) over ε.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Method name.
    pub method: String,
    /// λ, `None` for a method that ignores it.
    pub lambda: Option<f64>,
    /// Points in ε order.
    pub points: Vec<Point>,
}

impl Curve {
    /// `subdiv λ=0.5`, `tess`.
    pub fn name(&self) -> String {
        match self.lambda {
            Some(l) => format!("{} λ={l}", self.method),
            None => self.method.clone(),
        }
    }

    /// Triangles and frame time this curve needs for error `error`,
    /// interpolated log-log between the two points whose errors bracket it
    /// (points ordered by error); `None` outside the curve's range.
    pub fn at_error(&self, error: f64) -> Option<(f64, Option<f64>)> {
        let mut pts: Vec<&Point> = self.points.iter().filter(|p| p.error > 0.0).collect();
        pts.sort_by(|a, b| a.error.total_cmp(&b.error));
        let exact = pts.iter().find(|p| p.error == error);
        if let Some(p) = exact {
            return Some((p.triangles, p.frame_ms));
        }
        let (lo, hi) = pts
            .windows(2)
            .map(|w| (w[0], w[1]))
            .find(|(a, b)| a.error < error && error < b.error)?;
        let s = (error.ln() - lo.error.ln()) / (hi.error.ln() - lo.error.ln());
        let lerp = |a: f64, b: f64| (a.ln() + s * (b.ln() - a.ln())).exp();
        let ms = match (lo.frame_ms, hi.frame_ms) {
            (Some(a), Some(b)) if a > 0.0 && b > 0.0 => Some(lerp(a, b)),
            _ => None,
        };
        Some((lerp(lo.triangles, hi.triangles), ms))
    }
}

/// The curves of a run over FLIP, in configuration order (method, then λ).
pub fn curves(configs: &[Config], summaries: &[ConfigSummary]) -> Vec<Curve> {
    curves_by(configs, summaries, |s| s.flip_median())
}

/// The curves of a run over the mean geometric error (pixels).
pub fn geometric_curves(configs: &[Config], summaries: &[ConfigSummary]) -> Vec<Curve> {
    curves_by(configs, summaries, |s| {
        s.flip_figure_median(|b| (b.geo_pixels > 0).then_some(b.geo_mean_px))
    })
}

/// The curves of a run over the geometric error's 99th percentile
/// (pixels): the statistic ε bounds. The mean counts every pixel alike, so
/// a method that refines a whole patch for one detail lowers it where the
/// error was already far below ε; the percentile asks about the worst.
pub fn geometric_p99_curves(configs: &[Config], summaries: &[ConfigSummary]) -> Vec<Curve> {
    curves_by(configs, summaries, |s| {
        s.flip_figure_median(|b| (b.geo_pixels > 0).then_some(b.geo_p99_px))
    })
}

/// The curves of a run over the error measure `error`.
pub fn curves_by(
    configs: &[Config],
    summaries: &[ConfigSummary],
    error: impl Fn(&ConfigSummary) -> Option<f64>,
) -> Vec<Curve> {
    let mut out: Vec<Curve> = Vec::new();
    for s in summaries {
        let c = &configs[s.config];
        let (Some(e), Some(triangles)) = (error(s), s.flip_triangles_median()) else {
            continue;
        };
        let point = Point {
            eps: c.eps,
            error: e,
            triangles,
            frame_ms: s.get("gpu_ms.frame").map(|x| x.0),
        };
        match out
            .iter_mut()
            .find(|k| k.method == c.method && k.lambda == c.lambda)
        {
            Some(k) => k.points.push(point),
            None => out.push(Curve {
                method: c.method.clone(),
                lambda: c.lambda,
                points: vec![point],
            }),
        }
    }
    for k in &mut out {
        k.points.sort_by(|a, b| a.eps.total_cmp(&b.eps));
    }
    out
}

/// One point of a curve against the reference at the same error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtEqualError {
    /// The point compared.
    pub point: Point,
    /// The reference's triangles at that error.
    pub ref_triangles: f64,
    /// The reference's frame time at that error.
    pub ref_frame_ms: Option<f64>,
}

impl AtEqualError {
    /// This point's triangles over the reference's.
    pub fn triangle_ratio(&self) -> f64 {
        self.point.triangles / self.ref_triangles
    }

    /// This point's frame time over the reference's.
    pub fn time_ratio(&self) -> Option<f64> {
        Some(self.point.frame_ms? / self.ref_frame_ms?)
    }
}

/// Every point of `curve` that lies within the reference's error range,
/// with what the reference needs there.
pub fn against(curve: &Curve, reference: &Curve) -> Vec<AtEqualError> {
    curve
        .points
        .iter()
        .filter_map(|p| {
            let (t, ms) = reference.at_error(p.error)?;
            Some(AtEqualError {
                point: *p,
                ref_triangles: t,
                ref_frame_ms: ms,
            })
        })
        .collect()
}

/// The median of `v` (`None` when empty).
pub fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    Some(crate::figures::median(&v))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(pts: &[(f64, f64, f64)]) -> Curve {
        Curve {
            method: "baseline".into(),
            lambda: None,
            points: pts
                .iter()
                .map(|&(eps, error, triangles)| Point {
                    eps,
                    error,
                    triangles,
                    frame_ms: Some(triangles / 1000.0),
                })
                .collect(),
        }
    }

    #[test]
    fn interpolation_is_log_log_and_stays_inside_the_curve() {
        // FLIP halves and triangles quarter per step: a power law, which
        // log-log interpolation reproduces exactly in between.
        let c = curve(&[
            (0.5, 0.01, 40_000.0),
            (1.0, 0.02, 10_000.0),
            (2.0, 0.04, 2_500.0),
        ]);
        let f = 0.01 * 2f64.sqrt();
        let (t, ms) = c.at_error(f).unwrap();
        assert!((t - 20_000.0).abs() < 1e-6, "{t}");
        assert!((ms.unwrap() - 20.0).abs() < 1e-9);
        assert_eq!(c.at_error(0.02).unwrap().0, 10_000.0);
        assert_eq!(c.at_error(0.005), None);
        assert_eq!(c.at_error(0.05), None);
    }

    #[test]
    fn ratios_against_the_reference() {
        let reference = curve(&[(0.5, 0.01, 40_000.0), (2.0, 0.04, 2_500.0)]);
        let mut mine = curve(&[(0.5, 0.02, 5_000.0), (4.0, 0.1, 100.0)]);
        mine.method = "mine".into();
        let a = against(&mine, &reference);
        assert_eq!(
            a.len(),
            1,
            "the second point is beyond the reference's range"
        );
        assert!((a[0].ref_triangles - 10_000.0).abs() < 1e-6);
        assert!((a[0].triangle_ratio() - 0.5).abs() < 1e-9);
        assert!((a[0].time_ratio().unwrap() - 0.5).abs() < 1e-9);
    }
}
