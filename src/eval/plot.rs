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

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::pareto::{self, Curve};
use super::record::{Config, ConfigSummary, FrameRow};
use crate::gpu::write_png;

/// The environment variable naming a TTF file for plot text.
pub const FONT_ENV: &str = "BEZIER_SUBDIV_FONT";

/// Where the font is looked for when the variable is not set.
pub const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
];

/// Plot size in pixels.
const SIZE: (u32, u32) = (1600, 900);
/// Width of the legend column.
const LEGEND_WIDTH: u32 = 260;

/// Method colours, by the method's place in the run (the same in every plot).
const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
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

/// Marker shapes, by λ's place in the run; `SQUARE` for methods that
/// ignore λ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Marker {
    Dot,
    Ring,
    Cross,
    Triangle,
    Square,
}

const LAMBDA_MARKERS: [Marker; 4] = [Marker::Dot, Marker::Ring, Marker::Cross, Marker::Triangle];

/// How one series looks, the same in every panel of a figure.
#[derive(Clone, Debug, PartialEq)]
struct Style {
    label: String,
    colour: usize,
    marker: Marker,
    dashed: bool,
    /// 0 for the last series drawn; earlier ones are wider and larger so
    /// identical series stay visible.
    rank: u32,
}

impl Style {
    /// Line width: 3 px wider per rank (at most 4), so a series drawn
    /// exactly under a later one shows beside it.
    fn width(&self) -> u32 {
        2 + 3 * self.rank.min(4)
    }

    /// Marker radius, growing with the rank; small where points are
    /// dense (a path of many frames).
    fn radius(&self, dense: bool) -> i32 {
        if dense {
            2 + self.rank.min(4) as i32
        } else {
            5 + 2 * self.rank.min(4) as i32
        }
    }
}

/// One line or point set of a panel, drawn with `styles[style]`.
struct Series {
    style: usize,
    points: Vec<(f64, f64)>,
}

/// One chart.
struct Panel {
    title: String,
    series: Vec<Series>,
}

/// A figure: panels in a grid, one legend.
struct Figure<'a> {
    title: &'a str,
    axes: (&'a str, &'a str),
    styles: Vec<Style>,
    panels: Vec<Panel>,
    cols: usize,
    lines: bool,
    log: bool,
}

/// Axis labels for an axis reaching `span`: integers (with thousands
/// separators from 100 up), one decimal below 10, three below 1 (FLIP
/// means are around 0.01).
fn label(v: &f64, span: f64) -> String {
    if span >= 100.0 {
        crate::figures::thousands(v.round().max(0.0) as u64)
    } else if span >= 10.0 {
        format!("{v:.0}")
    } else if span >= 1.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.3}")
    }
}

/// Labels on a logarithmic axis: enough digits to tell neighbours apart.
fn log_label(v: &f64) -> String {
    if *v >= 100.0 {
        crate::figures::thousands(v.round() as u64)
    } else if *v >= 1.0 {
        format!("{v:.1}")
    } else {
        let digits = (-v.log10()).ceil().max(0.0) as usize + 1;
        format!("{v:.digits$}")
    }
}

type PlotResult = Result<(), String>;
type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

fn err<E: std::fmt::Display>(e: E) -> String {
    format!("drawing a plot: {e}")
}

/// Draws `fig` into a PNG at `path`.
fn draw(path: &Path, fig: &Figure<'_>) -> PlotResult {
    let (w, h) = SIZE;
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(fig.title, ("sans-serif", 28)).map_err(err)?;
        let (plots, legend) = root.split_horizontally(w - LEGEND_WIDTH);
        let rows = fig.panels.len().div_ceil(fig.cols.max(1)).max(1);
        let areas = plots.split_evenly((rows, fig.cols.max(1)));
        for (panel, area) in fig.panels.iter().zip(areas.iter()) {
            draw_panel(area, panel, fig)?;
        }
        draw_legend(&legend, fig)?;
        root.present().map_err(err)?;
    }
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    write_png(path, w, h, &rgba).map_err(|e| e.to_string())
}

/// The legend column: a line and marker sample and the label per style
/// that some panel uses.
fn draw_legend(area: &Area<'_>, fig: &Figure<'_>) -> PlotResult {
    let used = |i: usize| {
        fig.panels
            .iter()
            .any(|p| p.series.iter().any(|s| s.style == i))
    };
    let mut y = 60;
    for (_, st) in fig.styles.iter().enumerate().filter(|(i, _)| used(*i)) {
        let colour = COLOURS[st.colour % COLOURS.len()];
        let stroke = colour.stroke_width(st.width());
        if fig.lines {
            if st.dashed {
                for x in (10..50).step_by(12) {
                    area.draw(&PathElement::new(vec![(x, y), (x + 7, y)], stroke))
                        .map_err(err)?;
                }
            } else {
                area.draw(&PathElement::new(vec![(10, y), (50, y)], stroke))
                    .map_err(err)?;
            }
        }
        draw_marker(area, st, (30, y), st.radius(false)).map_err(err)?;
        area.draw(&Text::new(
            st.label.clone(),
            (60, y - 8),
            ("sans-serif", 16),
        ))
        .map_err(err)?;
        y += 28;
    }
    Ok(())
}

fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    st: &Style,
    at: (i32, i32),
    r: i32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let colour = COLOURS[st.colour % COLOURS.len()];
    let (dot, ring) = (colour.filled(), colour.stroke_width(2));
    match st.marker {
        Marker::Dot => area.draw(&Circle::new(at, r, dot)),
        Marker::Ring => area.draw(&Circle::new(at, r, ring)),
        Marker::Cross => area.draw(&Cross::new(at, r, ring)),
        Marker::Triangle => area.draw(&TriangleMarker::new(at, r, ring)),
        Marker::Square => area.draw(&Rectangle::new(
            [(at.0 - r, at.1 - r), (at.0 + r, at.1 + r)],
            ring,
        )),
    }
}

/// A panel's chart: linear axes (a log-log panel plots log10 of both
/// coordinates on them).
type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Where point `(x, y)` is plotted. A log-log panel plots log10 of both
/// coordinates on linear axes whose labels show the values again: ticks
/// then fall evenly in ratio, also when the data spans less than a decade.
/// Points off a log scale are left out.
fn plotted(log: bool, (x, y): (f64, f64)) -> Option<(f64, f64)> {
    if log {
        (x > 0.0 && y > 0.0).then(|| (x.log10(), y.log10()))
    } else {
        Some((x, y))
    }
}

/// The least and greatest coordinate `k` of `points`.
fn extent(points: &[(f64, f64)], k: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    points
        .iter()
        .map(k)
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
}

/// The axes' ranges for data spanning `(x_lo, x_hi)` and `(y_lo, y_hi)`:
/// from zero on linear axes, a margin either side on log ones.
fn axis_ranges(
    log: bool,
    (x_lo, x_hi): (f64, f64),
    (y_lo, y_hi): (f64, f64),
) -> (Range<f64>, Range<f64>) {
    if log {
        // A twentieth of the span (at least 0.02 decades) beyond the data.
        let pad = |lo: f64, hi: f64| {
            let d = ((hi - lo) / 20.0).max(0.02);
            (lo - d)..(hi + d)
        };
        (pad(x_lo, x_hi), pad(y_lo, y_hi))
    } else {
        (0f64..(x_hi * 1.02).max(1.0), 0f64..(y_hi * 1.05).max(1e-9))
    }
}

/// Draws a panel's axes, grid and labels; `x_hi` and `y_hi` are the data's
/// greatest coordinates (they choose the labels' precision).
fn draw_mesh(chart: &mut Chart<'_, '_>, fig: &Figure<'_>, x_hi: f64, y_hi: f64) -> PlotResult {
    let xf = |v: &f64| {
        if fig.log {
            log_label(&10f64.powf(*v))
        } else {
            label(v, x_hi)
        }
    };
    let yf = |v: &f64| {
        if fig.log {
            log_label(&10f64.powf(*v))
        } else {
            label(v, y_hi)
        }
    };
    chart
        .configure_mesh()
        .x_desc(fig.axes.0)
        .y_desc(fig.axes.1)
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        // Along the path x counts frames: no more labels than frames.
        .x_labels(if fig.log {
            12
        } else {
            (x_hi as usize + 1).clamp(2, 12)
        })
        .y_labels(12)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)
}

/// Draws one series' (already plotted) points in style `st`: its line,
/// dashed for a method that ignores λ, when the figure has lines, and its
/// markers.
fn draw_series(
    chart: &mut Chart<'_, '_>,
    st: &Style,
    pts: &[(f64, f64)],
    lines: bool,
) -> PlotResult {
    let colour = COLOURS[st.colour % COLOURS.len()];
    let style = colour.stroke_width(st.width());
    if lines {
        if st.dashed {
            chart
                .draw_series(DashedLineSeries::new(pts.iter().copied(), 10, 6, style))
                .map_err(err)?;
        } else {
            chart
                .draw_series(LineSeries::new(pts.iter().copied(), style))
                .map_err(err)?;
        }
    }
    let r = st.radius(pts.len() > 30);
    let (dot, ring) = (colour.filled(), colour.stroke_width(2));
    let it = pts.iter().copied();
    match st.marker {
        Marker::Dot => chart.draw_series(it.map(|p| Circle::new(p, r, dot))),
        Marker::Ring => chart.draw_series(it.map(|p| Circle::new(p, r, ring))),
        Marker::Cross => chart.draw_series(it.map(|p| Cross::new(p, r, ring))),
        Marker::Triangle => chart.draw_series(it.map(|p| TriangleMarker::new(p, r, ring))),
        Marker::Square => chart.draw_series(
            it.map(|p| EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], ring)),
        ),
    }
    .map_err(err)?;
    Ok(())
}

/// Draws one panel: axes fitted to its data, then its series (or a note
/// that it has none).
fn draw_panel(area: &Area<'_>, panel: &Panel, fig: &Figure<'_>) -> PlotResult {
    let tf = |p: (f64, f64)| plotted(fig.log, p);
    let all: Vec<(f64, f64)> = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().copied())
        .filter_map(tf)
        .collect();
    if all.is_empty() {
        area.draw(&Text::new(
            format!("{}: no data", panel.title),
            (20, 20),
            ("sans-serif", 20),
        ))
        .map_err(err)?;
        return Ok(());
    }
    let (xs, ys) = (extent(&all, |p| p.0), extent(&all, |p| p.1));
    let (x, y) = axis_ranges(fig.log, xs, ys);
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(x, y)
        .map_err(err)?;
    draw_mesh(&mut chart, fig, xs.1, ys.1)?;
    // Earlier styles first: the later (narrower) ones land on top.
    let mut order: Vec<&Series> = panel.series.iter().collect();
    order.sort_by_key(|s| s.style);
    for s in order {
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter_map(tf).collect();
        draw_series(&mut chart, &fig.styles[s.style], &pts, fig.lines)?;
    }
    Ok(())
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
