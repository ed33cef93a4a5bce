//! The drawing under `bench`'s plots (plotters on a bitmap): a figure of
//! panels in a grid with one legend, each panel's axes (linear, or log-log
//! with labels that show the values), its series as lines and markers.

use std::ops::Range;
use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::gpu::write_png;

/// Plot size in pixels.
pub(super) const SIZE: (u32, u32) = (1600, 900);
/// Width of the legend column.
pub(super) const LEGEND_WIDTH: u32 = 260;

/// Method colours, by the method's place in the run (the same in every plot).
pub(super) const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(23, 190, 207),
];

/// Marker shapes, by λ's place in the run; `SQUARE` for methods that
/// ignore λ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Marker {
    Dot,
    Ring,
    Cross,
    Triangle,
    Square,
}

pub(super) const LAMBDA_MARKERS: [Marker; 4] =
    [Marker::Dot, Marker::Ring, Marker::Cross, Marker::Triangle];

/// How one series looks, the same in every panel of a figure.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Style {
    pub(super) label: String,
    pub(super) colour: usize,
    pub(super) marker: Marker,
    pub(super) dashed: bool,
    /// 0 for the last series drawn; earlier ones are wider and larger so
    /// identical series stay visible.
    pub(super) rank: u32,
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
pub(super) struct Series {
    pub(super) style: usize,
    pub(super) points: Vec<(f64, f64)>,
}

/// One chart.
pub(super) struct Panel {
    pub(super) title: String,
    pub(super) series: Vec<Series>,
}

/// A figure: panels in a grid, one legend.
pub(super) struct Figure<'a> {
    pub(super) title: &'a str,
    pub(super) axes: (&'a str, &'a str),
    pub(super) styles: Vec<Style>,
    pub(super) panels: Vec<Panel>,
    pub(super) cols: usize,
    pub(super) lines: bool,
    pub(super) log: bool,
}

/// Axis labels for an axis reaching `span`: integers (with thousands
/// separators from 100 up), one decimal below 10, three below 1 (FLIP
/// means are around 0.01).
pub(super) fn label(v: &f64, span: f64) -> String {
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
pub(super) fn log_label(v: &f64) -> String {
    if *v >= 100.0 {
        crate::figures::thousands(v.round() as u64)
    } else if *v >= 1.0 {
        format!("{v:.1}")
    } else {
        let digits = (-v.log10()).ceil().max(0.0) as usize + 1;
        format!("{v:.digits$}")
    }
}

pub(super) type PlotResult = Result<(), String>;
pub(super) type Area<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

pub(super) fn err<E: std::fmt::Display>(e: E) -> String {
    format!("drawing a plot: {e}")
}

/// Draws `fig` into a PNG at `path`.
pub(super) fn draw(path: &Path, fig: &Figure<'_>) -> PlotResult {
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
pub(super) fn draw_legend(area: &Area<'_>, fig: &Figure<'_>) -> PlotResult {
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

pub(super) fn draw_marker<DB: DrawingBackend>(
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
pub(super) type Chart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Where point `(x, y)` is plotted. A log-log panel plots log10 of both
/// coordinates on linear axes whose labels show the values again: ticks
/// then fall evenly in ratio, also when the data spans less than a decade.
/// Points off a log scale are left out.
pub(super) fn plotted(log: bool, (x, y): (f64, f64)) -> Option<(f64, f64)> {
    if log {
        (x > 0.0 && y > 0.0).then(|| (x.log10(), y.log10()))
    } else {
        Some((x, y))
    }
}

/// The least and greatest coordinate `k` of `points`.
pub(super) fn extent(points: &[(f64, f64)], k: fn(&(f64, f64)) -> f64) -> (f64, f64) {
    points
        .iter()
        .map(k)
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)))
}

/// The axes' ranges for data spanning `(x_lo, x_hi)` and `(y_lo, y_hi)`:
/// from zero on linear axes, a margin either side on log ones.
pub(super) fn axis_ranges(
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
pub(super) fn draw_mesh(
    chart: &mut Chart<'_, '_>,
    fig: &Figure<'_>,
    x_hi: f64,
    y_hi: f64,
) -> PlotResult {
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
pub(super) fn draw_series(
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
pub(super) fn draw_panel(area: &Area<'_>, panel: &Panel, fig: &Figure<'_>) -> PlotResult {
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
