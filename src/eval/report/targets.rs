//! `bench`'s "Targets" section: every target a registry entry declares
//! (`methods::targets`), each with what the run measured and its verdict.
//! Nothing here names a method.

use super::{mib, ms, Index, Setup};
use crate::eval::pareto::{against, median, Curve};
use crate::figures::thousands;
use crate::methods::targets::{Against, Figure, Target};
use crate::methods::{self, METHODS};

/// "met", or by how much `ratio` misses `limit`.
pub(super) fn verdict(ratio: f64, limit: f64) -> String {
    if ratio <= limit {
        "met".to_string()
    } else {
        format!("missed by {:.0} %", 100.0 * (ratio / limit - 1.0))
    }
}

/// The section: a line per target (per λ of the run where a target says
/// every λ), in the registry's order.
pub(super) fn section(ix: &Index<'_>, setup: &Setup, curves: &[Curve]) -> String {
    let mut md = "## Targets\n\n| target | measured | verdict |\n|---|---|---|\n".to_string();
    for info in METHODS {
        for target in info.targets {
            md += &lines(info.name, target, ix, setup, curves);
        }
    }
    md + "\n"
}

/// Target `t` of method `me`, as report lines.
fn lines(me: &str, t: &Target, ix: &Index<'_>, setup: &Setup, curves: &[Curve]) -> String {
    match *t {
        Target::Ratio {
            eps,
            figure,
            lambda,
            against,
            limit,
        } => {
            let lambdas = lambda.map_or_else(|| ix.lambdas.clone(), |l| vec![l]);
            lambdas
                .into_iter()
                .map(|l| ratio(me, eps, figure, l, against, limit, ix))
                .collect()
        }
        Target::EqualFlip { lambda, limits } => equal_flip(me, lambda, limits, setup, curves),
        Target::Worst { figure, limit } => worst(me, figure, limit, ix),
    }
}

/// A figure of method `m` at ε `eps` and λ `l`, if measured.
fn value(ix: &Index<'_>, m: &str, eps: f64, l: f64, figure: Figure) -> Option<f64> {
    let s = ix.get(m, eps, l)?;
    match figure {
        Figure::Triangles => s.get("triangles").map(|x| x.0),
        Figure::Flip => s.flip_median(),
        Figure::SubdividePass => s.get("gpu_ms.subdivide").map(|x| x.0),
        Figure::NodeMemory => s.get("method_stats.node_memory_bytes").map(|x| x.2),
    }
}

/// A figure as a cell.
fn cell(figure: Figure, x: f64) -> String {
    match figure {
        Figure::Triangles => thousands(x as u64),
        Figure::Flip => format!("{x:.5}"),
        Figure::SubdividePass => ms(x),
        Figure::NodeMemory => mib(x),
    }
}

fn ratio(
    me: &str,
    eps: f64,
    figure: Figure,
    l: f64,
    against: Against,
    limit: f64,
    ix: &Index<'_>,
) -> String {
    let fig = figure.words();
    let (what, other, needs) = match against {
        Against::Method(o) => (
            format!("ε = {eps}: `{me}` λ = {l} {fig} ≤ {limit}× `{o}`'s"),
            value(ix, o, eps, l, figure),
            format!("`{me}` and `{o}` at ε = {eps}"),
        ),
        Against::Lambda(l2) => (
            format!("ε = {eps}: `{me}` λ = {l} {fig} ≤ {limit}× its λ = {l2}'s"),
            value(ix, me, eps, l2, figure),
            format!("`{me}` at λ = {l} and {l2}, ε = {eps}"),
        ),
    };
    match (value(ix, me, eps, l, figure), other) {
        (Some(a), Some(b)) if b > 0.0 => format!(
            "| {what} | {} / {} = {:.3}× | {} |\n",
            cell(figure, a),
            cell(figure, b),
            a / b,
            verdict(a / b, limit)
        ),
        _ => format!("| {what} | – | not measured (needs {needs} in one run) |\n"),
    }
}

fn equal_flip(
    me: &str,
    lambda: f64,
    limits: &[(&str, f64)],
    setup: &Setup,
    curves: &[Curve],
) -> String {
    let base = methods::baseline().name;
    let limit = limits
        .iter()
        .find(|(scene, _)| *scene == setup.scene_name)
        .map(|&(_, l)| l);
    let all: Vec<String> = limits.iter().map(|(s, l)| format!("{l} ({s})")).collect();
    let what = format!(
        "equal FLIP: `{me}` λ = {lambda} ≤ {}× the triangles of `{base}`",
        limit.map_or(all.join(" / "), |l| l.to_string())
    );
    let reference = curves.iter().find(|c| c.method == base);
    let mine = curves
        .iter()
        .find(|c| c.method == me && c.lambda == Some(lambda));
    let (Some(c), Some(r)) = (mine, reference) else {
        return format!(
            "| {what} | – | not measured (needs FLIP of `{me}` λ = {lambda} and `{base}`) |\n"
        );
    };
    let ratios: Vec<f64> = against(c, r).iter().map(|a| a.triangle_ratio()).collect();
    match (median(ratios.clone()), limit) {
        (Some(m), Some(limit)) => format!(
            "| {what} | median {m:.3}× over {} ε | {} |\n",
            ratios.len(),
            verdict(m, limit)
        ),
        (Some(m), None) => format!(
            "| {what} | median {m:.3}× over {} ε | no limit for this scene |\n",
            ratios.len()
        ),
        (None, _) => {
            format!("| {what} | – | no ε of `{me}` reaches an error within `{base}`'s range |\n")
        }
    }
}

/// The worst frame of the path (node memory: and the rounds that took a
/// depth in parts there, not a failure but a cost the report shows).
fn worst(me: &str, figure: Figure, limit: f64, ix: &Index<'_>) -> String {
    let most = |key: &str| {
        ix.summaries
            .iter()
            .filter(|s| ix.configs[s.config].method == me)
            .filter_map(|s| s.get(key).map(|x| x.2))
            .max_by(f64::total_cmp)
    };
    let what = format!(
        "`{me}` {} ≤ {} on the path",
        figure.words(),
        cell(figure, limit)
    );
    let key = match figure {
        Figure::NodeMemory => "method_stats.node_memory_bytes",
        Figure::Triangles => "triangles",
        Figure::SubdividePass => "gpu_ms.subdivide",
        Figure::Flip => "flip_mean",
    };
    match most(key) {
        Some(x) => {
            let parts = if figure == Figure::NodeMemory {
                let rounds = most("method_stats.rounds_split").unwrap_or(0.0);
                format!(", worst frame {} rounds in parts", thousands(rounds as u64))
            } else {
                String::new()
            };
            format!(
                "| {what} | {}{parts} | {} |\n",
                cell(figure, x),
                verdict(x / limit, 1.0)
            )
        }
        None => format!("| {what} | – | not measured (`{me}` not in this run) |\n"),
    }
}
