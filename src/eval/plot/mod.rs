//! The plots of a `bench` run (plotters, drawn into a pixel buffer and
//! written with the renderer's own PNG writer): frame time and triangles
//! along the path, one panel per ε and λ with a line per method; the
//! curves over ε of FLIP against triangles and against frame time (log-log,
//! the comparison at equal error); and, when a run sweeps λ, the paper's
//! Fig. 6 (triangles and FLIP against λ).
//!
//! Every series stays visible: a method has its colour, a λ its marker
//! (methods that ignore λ a square and a dashed line), and series that
//! coincide (the two subdivision methods draw the same triangles) are drawn
//! earlier ones wider and larger, so the later one lies inside the earlier.
//! The legend has a column of its own beside the panels, never over data.
//!
//! Text needs a TrueType font. Plotters' own font lookup goes through the
//! system's font configuration; ab_glyph takes the bytes of a file, so
//! the file is found here: `$BEZIER_SUBDIV_FONT`, else Debian's
//! `fonts-dejavu-core` (installed by `tools/install-deps.sh`).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::prelude::*;

mod draw;

use super::pareto::{self, Curve};
use super::record::{Config, ConfigSummary, FrameRow};
use draw::*;

/// The environment variable naming a TTF file for plot text.
pub const FONT_ENV: &str = "BEZIER_SUBDIV_FONT";

/// Where the font is looked for when the variable is not set.
pub const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// The font file: `$BEZIER_SUBDIV_FONT` when set, else the first of
/// `candidates` that exists; the error says how to get one.
pub fn font_file(env: Option<PathBuf>, candidates: &[&str]) -> Result<PathBuf, String> {
    if let Some(p) = env {
        return if p.is_file() {
            Ok(p)
        } else {
            Err(format!(
                "plots need a TrueType font: ${FONT_ENV} names {}, which is not a file",
                p.display()
            ))
        };
    }
    candidates
        .iter()
        .map(PathBuf::from)
        .find(|p| p.is_file())
        .ok_or_else(|| {
            format!(
                "plots need a TrueType font and none was found ({}): install Debian's \
                 fonts-dejavu-core (tools/install-deps.sh does) or set ${FONT_ENV}=FILE.ttf",
                candidates.join(", ")
            )
        })
}

/// Finds, reads and registers the plot font (once per process; later
/// calls answer the first call's result).
pub fn load_font() -> Result<(), String> {
    static LOADED: OnceLock<Result<(), String>> = OnceLock::new();
    LOADED
        .get_or_init(|| {
            let path = font_file(std::env::var_os(FONT_ENV).map(PathBuf::from), FONT_PATHS)?;
            let bytes = std::fs::read(&path)
                .map_err(|e| format!("reading the plot font {}: {e}", path.display()))?;
            // Plotters keeps the font for the life of the process.
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            plotters::style::register_font("sans-serif", FontStyle::Normal, bytes)
                .map_err(|_| format!("{} is not a font plotters can read", path.display()))
        })
        .clone()
}

/// The distinct values of `f` over `configs`, sorted (descending with `desc`).
fn distinct(configs: &[Config], f: impl Fn(&Config) -> Option<f64>, desc: bool) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::new();
    for x in configs.iter().filter_map(f) {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    v.sort_by(|a, b| if desc { b.total_cmp(a) } else { a.total_cmp(b) });
    v
}

/// The methods in run order.
fn methods_of(configs: &[Config]) -> Vec<String> {
    let mut methods: Vec<String> = Vec::new();
    for c in configs {
        if !methods.contains(&c.method) {
            methods.push(c.method.clone());
        }
    }
    methods
}

/// The style of every (method, λ) curve: colour by method, marker by λ
/// (a dashed line and a square for methods that ignore λ), rank by order.
fn curve_styles(configs: &[Config]) -> Vec<(String, Option<f64>, Style)> {
    let methods = methods_of(configs);
    let lambdas = distinct(configs, |c| c.lambda, true);
    let mut keys: Vec<(String, Option<f64>)> = Vec::new();
    for c in configs {
        let k = (c.method.clone(), c.lambda);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let n = methods.len() as u32;
    keys.into_iter()
        .map(|(m, l)| {
            let i = methods.iter().position(|x| *x == m).unwrap_or(0);
            let style = Style {
                label: match l {
                    Some(l) => format!("{m} λ={l}"),
                    None => m.clone(),
                },
                colour: i,
                marker: match l {
                    Some(l) => {
                        let k = lambdas.iter().position(|x| *x == l).unwrap_or(0);
                        LAMBDA_MARKERS[k % LAMBDA_MARKERS.len()]
                    }
                    None => Marker::Square,
                },
                dashed: l.is_none(),
                rank: n - 1 - i as u32,
            };
            (m, l, style)
        })
        .collect()
}

/// Panels of figure `key` along the path: rows λ (descending), columns ε,
/// a line per method (methods that ignore λ in every row).
fn along_path(configs: &[Config], rows: &[FrameRow], key: &str) -> (Vec<Style>, Vec<Panel>, usize) {
    let methods = methods_of(configs);
    let n = methods.len() as u32;
    let styles: Vec<Style> = methods
        .iter()
        .enumerate()
        .map(|(i, m)| Style {
            label: m.clone(),
            colour: i,
            marker: Marker::Dot,
            dashed: false,
            rank: n - 1 - i as u32,
        })
        .collect();
    let eps = distinct(configs, |c| Some(c.eps), false);
    let mut lambdas: Vec<Option<f64>> = distinct(configs, |c| c.lambda, true)
        .into_iter()
        .map(Some)
        .collect();
    if lambdas.is_empty() {
        lambdas.push(None);
    }
    let mut panels = Vec::new();
    for &l in &lambdas {
        for &e in &eps {
            let series = configs
                .iter()
                .enumerate()
                .filter(|(_, c)| c.eps == e && (c.lambda.is_none() || c.lambda == l))
                .map(|(i, c)| Series {
                    style: methods.iter().position(|m| *m == c.method).unwrap_or(0),
                    points: rows
                        .iter()
                        .filter(|r| r.config == i)
                        .filter_map(|r| {
                            let v = r.values.iter().find(|(k, _)| k == key)?;
                            Some((f64::from(r.frame), v.1.as_f64()?))
                        })
                        .collect(),
                })
                .collect();
            panels.push(Panel {
                title: match l {
                    Some(l) => format!("ε = {e}, λ = {l}"),
                    None => format!("ε = {e}"),
                },
                series,
            });
        }
    }
    (styles, panels, eps.len())
}

/// The curves over ε as one panel: `y` against `x` of each point.
fn curve_panel(
    title: &str,
    curves: &[Curve],
    styles: &[(String, Option<f64>, Style)],
    xy: impl Fn(&pareto::Point) -> Option<(f64, f64)>,
) -> Panel {
    let series = curves
        .iter()
        .filter_map(|c| {
            let style = styles
                .iter()
                .position(|(m, l, _)| *m == c.method && *l == c.lambda)?;
            let mut points: Vec<(f64, f64)> = c.points.iter().filter_map(&xy).collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Some(Series { style, points })
        })
        .collect();
    Panel {
        title: title.into(),
        series,
    }
}

/// The (method, ε) pairs measured at 3 or more λ, in configuration
/// order: one series each in the λ figure, labelled in the same order.
fn lambda_keys(configs: &[Config]) -> Vec<(String, f64)> {
    let mut keys: Vec<(String, f64)> = Vec::new();
    for c in configs {
        let k = (c.method.clone(), c.eps);
        let swept = configs
            .iter()
            .filter(|d| d.method == c.method && d.eps == c.eps && d.lambda.is_some())
            .count();
        if swept >= 3 && !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys
}

/// Fig. 6: per method that reads λ and ε with three or more λ measured,
/// triangles and FLIP against λ. `None` when the run sweeps no λ.
fn lambda_figure(configs: &[Config], summaries: &[ConfigSummary]) -> Option<Vec<Panel>> {
    let keys = lambda_keys(configs);
    if keys.is_empty() {
        return None;
    }
    let along_lambda = |(m, e): &(String, f64), value: &dyn Fn(&ConfigSummary) -> Option<f64>| {
        let mut pts: Vec<(f64, f64)> = summaries
            .iter()
            .filter(|s| configs[s.config].method == *m && configs[s.config].eps == *e)
            .filter_map(|s| Some((configs[s.config].lambda?, value(s)?)))
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts
    };
    let triangles = |s: &ConfigSummary| {
        s.flip_triangles_median()
            .or(s.get("triangles").map(|x| x.0))
    };
    let flip = |s: &ConfigSummary| s.flip_median();
    let mk = |title: &str, value: &dyn Fn(&ConfigSummary) -> Option<f64>| Panel {
        title: title.into(),
        series: keys
            .iter()
            .enumerate()
            .map(|(i, k)| Series {
                style: i,
                points: along_lambda(k, value),
            })
            .collect(),
    };
    Some(vec![
        mk("triangles", &triangles),
        mk("FLIP against the ground truth", &flip),
    ])
}

/// A plot of the curves over ε: file, title, x axis, what it shows, and
/// each point's (x, y).
type CurvePlot = (
    &'static str,
    &'static str,
    &'static str,
    &'static str,
    fn(&pareto::Point) -> Option<(f64, f64)>,
);

/// Writes the run's plots into `dir`; returns (file name, what it shows).
pub fn write_plots(
    dir: &Path,
    configs: &[Config],
    rows: &[FrameRow],
    summaries: &[ConfigSummary],
) -> Result<Vec<(&'static str, &'static str)>, String> {
    load_font()?;
    let mut written = path_plots(dir, configs, rows)?;
    written.extend(curve_plots(dir, configs, summaries)?);
    if let Some(panels) = lambda_figure(configs, summaries) {
        let styles = lambda_styles(configs, &panels);
        let fig = Figure {
            title: "λ: triangles and FLIP (the paper's Fig. 6)",
            axes: ("λ", ""),
            styles,
            panels,
            cols: 2,
            lines: true,
            log: false,
        };
        draw(&dir.join("lambda.png"), &fig)?;
        written.push(("lambda.png", "triangles and FLIP against λ (Fig. 6)"));
    }
    Ok(written)
}

/// The plots along the path: frame time and triangles per frame.
fn path_plots(
    dir: &Path,
    configs: &[Config],
    rows: &[FrameRow],
) -> Result<Vec<(&'static str, &'static str)>, String> {
    let mut written = Vec::new();
    for (file, title, key, y, what) in [
        (
            "frame_time.png",
            "GPU frame time along the path",
            "gpu_ms.frame",
            "ms",
            "frame time along the path",
        ),
        (
            "triangles.png",
            "Triangles along the path",
            "triangles",
            "triangles",
            "triangles along the path",
        ),
    ] {
        let (styles, panels, cols) = along_path(configs, rows, key);
        let fig = Figure {
            title,
            axes: ("frame", y),
            styles,
            panels,
            cols,
            lines: true,
            log: false,
        };
        draw(&dir.join(file), &fig)?;
        written.push((file, what));
    }
    Ok(written)
}

/// The curves over ε: one point per ε (medians over the perspectives),
/// FLIP against triangles and frame time, geometric error against
/// triangles.
fn curve_plots(
    dir: &Path,
    configs: &[Config],
    summaries: &[ConfigSummary],
) -> Result<Vec<(&'static str, &'static str)>, String> {
    let mut written = Vec::new();
    let curves = pareto::curves(configs, summaries);
    let styles = curve_styles(configs);
    let plain: Vec<Style> = styles.iter().map(|(_, _, s)| s.clone()).collect();
    let pareto_plots: [CurvePlot; 3] = [
        (
            "flip_vs_triangles.png",
            "FLIP against the ground truth vs triangles (one point per ε)",
            "triangles (median of the FLIP images)",
            "FLIP vs triangles",
            |p| Some((p.triangles, p.error)),
        ),
        (
            "flip_vs_time.png",
            "FLIP against the ground truth vs GPU frame time (one point per ε)",
            "frame time, ms (median along the path)",
            "FLIP vs frame time",
            |p| Some((p.frame_ms?, p.error)),
        ),
        (
            "geometric_vs_triangles.png",
            "Geometric error against the ground truth vs triangles (one point per ε)",
            "triangles (median of the FLIP images)",
            "geometric error vs triangles",
            |p| Some((p.triangles, p.error)),
        ),
    ];
    let geometric = pareto::geometric_curves(configs, summaries);
    for (i, (file, title, x, what, xy)) in pareto_plots.into_iter().enumerate() {
        let (curves, y) = if i < 2 {
            (&curves, "FLIP mean (median of the perspectives)")
        } else {
            (
                &geometric,
                "mean geometric error, px (median of the perspectives)",
            )
        };
        let fig = Figure {
            title,
            axes: (x, y),
            styles: plain.clone(),
            panels: vec![curve_panel(
                "log-log: lower left is better",
                curves,
                &styles,
                xy,
            )],
            cols: 1,
            lines: true,
            log: true,
        };
        draw(&dir.join(file), &fig)?;
        written.push((file, what));
    }
    Ok(written)
}

/// The styles of Fig. 6's series, one per (method, ε) that reads λ:
/// colour by method (shifted per series), marker by place.
fn lambda_styles(configs: &[Config], panels: &[Panel]) -> Vec<Style> {
    // The same keys, in the same order, as the panel's series.
    let keys = lambda_keys(configs);
    let methods = methods_of(configs);
    let n = panels[0].series.len() as u32;
    panels[0]
        .series
        .iter()
        .zip(&keys)
        .enumerate()
        .map(|(i, (_, (m, e)))| Style {
            label: format!("{m} ε={e}"),
            colour: methods.iter().position(|x| x == m).unwrap_or(0) + i,
            marker: LAMBDA_MARKERS[i % LAMBDA_MARKERS.len()],
            dashed: false,
            rank: n - 1 - i as u32,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_font_is_a_sentence() {
        let e = font_file(None, &["/nonexistent/font.ttf"]).unwrap_err();
        assert!(
            e.contains("fonts-dejavu-core") && e.contains(FONT_ENV),
            "{e}"
        );
        let e = font_file(Some("/nonexistent/x.ttf".into()), FONT_PATHS).unwrap_err();
        assert!(e.contains("/nonexistent/x.ttf"), "{e}");
    }
}
