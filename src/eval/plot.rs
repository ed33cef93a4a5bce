//! The plots of a `bench` run (plotters, drawn into a pixel buffer and
//! written with the renderer's own PNG writer): frame time and triangles
//! along the path, one panel per ε and λ with a line per method, and FLIP
//! against triangles per method and λ.
//!
//! Text needs a TrueType font. Plotters' own font lookup goes through the
//! system's font configuration; ab_glyph takes the bytes of a file, so
//! the file is found here: `$BEZIER_SUBDIV_FONT`, else Debian's
//! `fonts-dejavu-core` (installed by `tools/install-deps.sh`).

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::prelude::*;

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

/// One line or point set of a panel.
struct Series {
    label: String,
    colour: usize,
    /// 0: filled dot, 1: ring, 2: cross (λ in the FLIP plot).
    marker: usize,
    points: Vec<(f64, f64)>,
}

/// Axis labels for an axis reaching `span`: integers (with thousands
/// separators from 100 up), one decimal below 10, three below 1 (FLIP
/// means are around 0.01).
fn label(v: &f64, span: f64) -> String {
    if span >= 100.0 {
        crate::commands::thousands(v.round().max(0.0) as u64)
    } else if span >= 10.0 {
        format!("{v:.0}")
    } else if span >= 1.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.3}")
    }
}

/// One chart.
struct Panel {
    title: String,
    series: Vec<Series>,
}

type PlotResult = Result<(), String>;

fn err<E: std::fmt::Display>(e: E) -> String {
    format!("drawing a plot: {e}")
}

/// Draws `panels` in a grid of `cols` columns into a PNG at `path`.
fn draw(
    path: &Path,
    title: &str,
    axes: (&str, &str),
    panels: &[Panel],
    cols: usize,
    lines: bool,
) -> PlotResult {
    let (w, h) = SIZE;
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let root = root.titled(title, ("sans-serif", 28)).map_err(err)?;
        let rows = panels.len().div_ceil(cols.max(1)).max(1);
        let areas = root.split_evenly((rows, cols.max(1)));
        for (panel, area) in panels.iter().zip(areas.iter()) {
            draw_panel(area, panel, axes, lines)?;
        }
        root.present().map_err(err)?;
    }
    let rgba: Vec<u8> = rgb
        .chunks_exact(3)
        .flat_map(|p| [p[0], p[1], p[2], 255])
        .collect();
    write_png(path, w, h, &rgba).map_err(|e| e.to_string())
}

fn draw_panel(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    panel: &Panel,
    (x_desc, y_desc): (&str, &str),
    lines: bool,
) -> PlotResult {
    let all = panel.series.iter().flat_map(|s| s.points.iter());
    let (x_max, y_max) = all.fold((0f64, 0f64), |(a, b), &(x, y)| (a.max(x), b.max(y)));
    if x_max <= 0.0 && y_max <= 0.0 {
        area.draw(&Text::new(
            format!("{}: no data", panel.title),
            (20, 20),
            ("sans-serif", 20),
        ))
        .map_err(err)?;
        return Ok(());
    }
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        // Headroom above the data for the legend in the upper right.
        .build_cartesian_2d(0f64..(x_max * 1.02).max(1.0), 0f64..(y_max * 1.3).max(1e-9))
        .map_err(err)?;
    let (xf, yf) = (|v: &f64| label(v, x_max), |v: &f64| label(v, y_max));
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 16))
        .light_line_style(WHITE)
        .draw()
        .map_err(err)?;
    let last = panel.series.iter().map(|s| s.colour).max().unwrap_or(0);
    for s in &panel.series {
        let colour = COLOURS[s.colour % COLOURS.len()];
        // Earlier methods are drawn wider, so identical lines (the two
        // subdivision methods draw the same triangles) stay visible.
        let style = colour.stroke_width(2 + 2 * (last - s.colour).min(2) as u32);
        if lines {
            chart
                .draw_series(LineSeries::new(s.points.iter().copied(), style))
                .map_err(err)?;
        }
        let pts = s.points.iter().copied();
        let (dot, ring) = (colour.filled(), colour.stroke_width(2));
        // Small marks where the points are dense (a path of many frames).
        let r = if s.points.len() > 30 { 2 } else { 5 };
        let anno = match s.marker % 3 {
            0 => chart.draw_series(pts.map(|p| Circle::new(p, r, dot))),
            1 => chart.draw_series(pts.map(|p| Circle::new(p, r, ring))),
            _ => chart.draw_series(pts.map(|p| Cross::new(p, r, ring))),
        }
        .map_err(err)?
        .label(&s.label);
        let line = move |(x, y): (i32, i32)| {
            EmptyElement::at((x, y)) + PathElement::new(vec![(0, 0), (20, 0)], style)
        };
        match s.marker % 3 {
            0 => anno.legend(move |p| line(p) + Circle::new((10, 0), 5, dot)),
            1 => anno.legend(move |p| line(p) + Circle::new((10, 0), 5, ring)),
            _ => anno.legend(move |p| line(p) + Cross::new((10, 0), 5, ring)),
        };
    }
    chart
        .configure_series_labels()
        .label_font(("sans-serif", 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// The distinct values of `f` over `configs`, sorted (descending with `desc`).
fn distinct(configs: &[Config], f: impl Fn(&Config) -> f64, desc: bool) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::new();
    for c in configs {
        if !v.contains(&f(c)) {
            v.push(f(c));
        }
    }
    v.sort_by(|a, b| if desc { b.total_cmp(a) } else { a.total_cmp(b) });
    v
}

/// Panels of figure `key` along the path: rows λ (descending), columns ε.
fn along_path(
    configs: &[Config],
    methods: &[String],
    rows: &[FrameRow],
    key: &str,
) -> (Vec<Panel>, usize) {
    let eps = distinct(configs, |c| c.eps, false);
    let mut panels = Vec::new();
    for l in distinct(configs, |c| c.lambda, true) {
        for &e in &eps {
            let series = configs
                .iter()
                .enumerate()
                .filter(|(_, c)| c.eps == e && c.lambda == l)
                .map(|(i, c)| Series {
                    label: c.method.clone(),
                    colour: methods.iter().position(|m| *m == c.method).unwrap_or(0),
                    marker: 0,
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
                title: format!("ε = {e}, λ = {l}"),
                series,
            });
        }
    }
    (panels, eps.len())
}

/// Writes the run's plots into `dir`; returns (file name, what it shows).
pub fn write_plots(
    dir: &Path,
    configs: &[Config],
    rows: &[FrameRow],
    summaries: &[ConfigSummary],
) -> Result<Vec<(&'static str, &'static str)>, String> {
    load_font()?;
    let mut methods: Vec<String> = Vec::new();
    for c in configs {
        if !methods.contains(&c.method) {
            methods.push(c.method.clone());
        }
    }
    let (panels, cols) = along_path(configs, &methods, rows, "gpu_ms.frame");
    draw(
        &dir.join("frame_time.png"),
        "GPU frame time along the path",
        ("frame", "ms"),
        &panels,
        cols,
        true,
    )?;
    let (panels, cols) = along_path(configs, &methods, rows, "triangles");
    draw(
        &dir.join("triangles.png"),
        "Triangles along the path",
        ("frame", "triangles"),
        &panels,
        cols,
        true,
    )?;
    // FLIP against triangles: per method and λ, one point per ε (medians
    // over the perspectives), joined in ε order.
    let mut series = Vec::new();
    for (mi, m) in methods.iter().enumerate() {
        for (li, l) in distinct(configs, |c| c.lambda, true)
            .into_iter()
            .enumerate()
        {
            let mut points: Vec<(f64, f64)> = summaries
                .iter()
                .filter(|s| configs[s.config].method == *m && configs[s.config].lambda == l)
                .filter_map(|s| {
                    let mut t: Vec<f64> = s.flips.iter().map(|f| f.triangles as f64).collect();
                    t.sort_by(f64::total_cmp);
                    Some((crate::commands::render::median(&t), s.flip_median()?))
                })
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            if !points.is_empty() {
                series.push(Series {
                    label: format!("{m} λ={l}"),
                    colour: mi,
                    marker: li,
                    points,
                });
            }
        }
    }
    let panel = Panel {
        title: "one point per ε: medians over the FLIP perspectives".into(),
        series,
    };
    draw(
        &dir.join("flip_vs_triangles.png"),
        "FLIP against the ground truth vs triangles",
        ("triangles", "FLIP mean"),
        &[panel],
        1,
        true,
    )?;
    Ok(vec![
        ("frame_time.png", "frame time along the path"),
        ("triangles.png", "triangles along the path"),
        ("flip_vs_triangles.png", "FLIP vs triangles"),
    ])
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
