//! `summary.json` and `report.md` of a `bench` run: the paper's Table 1
//! (FLIP per perspective), Table 2 (time and triangles per ε, method and
//! λ), GPU time per pass, the subdivision figures, memory by purpose (its
//! §4.3), and the issue's targets, each figure computed from the frames
//! measured (nothing here is typed in by hand).

mod targets;

use serde_json::{json, Value};

use super::pareto::{self, against, median, Curve};
use super::record::{Config, ConfigSummary};
use crate::figures::thousands;

/// What the run was: everything a reader needs to reproduce it.
#[derive(Clone, Debug)]
pub struct Setup {
    /// The command line that makes the same run.
    pub command: String,
    /// Scene file as given.
    pub scene: String,
    /// Scene name.
    pub scene_name: String,
    /// Base patches.
    pub patches: usize,
    /// Device name.
    pub device: String,
    /// A CPU (software) device.
    pub device_is_cpu: bool,
    /// Driver name and version.
    pub driver: String,
    /// Image size.
    pub size: (u32, u32),
    /// The camera path, in words.
    pub path: String,
    /// Frames timed per configuration.
    pub frames: u32,
    /// Warm-up frames per configuration.
    pub warmup: u32,
    /// Where the FLIP perspectives are on the path.
    pub flip_t: Vec<f64>,
    /// The ground truth's grid.
    pub grid: u32,
    /// The commit the binary was built from.
    pub commit: String,
    /// The scene's model names, by model index.
    pub models: Vec<String>,
    /// How `subdiv` and `subdiv-indirect` split: `iso` or `aniso`.
    pub split: &'static str,
    /// `None` when the run completed, else why it stopped early.
    pub stopped: Option<String>,
}

/// `summary.json`: the setup, then one entry per configuration.
pub fn summary_json(setup: &Setup, configs: &[Config], summaries: &[ConfigSummary]) -> Value {
    let entries: Vec<Value> = summaries
        .iter()
        .map(|s| s.to_json(&configs[s.config]))
        .collect();
    json!({
        "command": setup.command,
        "scene": setup.scene,
        "scene_name": setup.scene_name,
        "patches": setup.patches,
        "device": setup.device,
        "device_is_cpu": setup.device_is_cpu,
        "driver": setup.driver,
        "width": setup.size.0,
        "height": setup.size.1,
        "path": setup.path,
        "frames": setup.frames,
        "warmup": setup.warmup,
        "flip_t": setup.flip_t,
        "grid": setup.grid,
        "split": setup.split,
        "l_max": crate::constants::L_MAX,
        "commit": setup.commit,
        "complete": setup.stopped.is_none(),
        "stopped": setup.stopped,
        "configs": entries,
    })
}

/// Numbers as the paper prints them.
pub(super) fn ms(x: f64) -> String {
    format!("{x:.3} ms")
}

pub(super) fn mib(bytes: f64) -> String {
    if bytes < 1024.0 * 1024.0 {
        format!("{:.2} KiB", bytes / 1024.0)
    } else {
        format!("{:.2} MiB", bytes / (1024.0 * 1024.0))
    }
}

/// λ as a table cell: "–" for a method that ignores it.
fn lambda_text(c: &Config) -> String {
    c.lambda.map_or_else(|| "–".to_string(), |l| l.to_string())
}

/// Table rows group configurations by ε, then the methods that ignore λ,
/// then by λ (the paper's order: λ descending), then by method in run
/// order.
pub(super) struct Index<'a> {
    pub(super) configs: &'a [Config],
    pub(super) summaries: &'a [ConfigSummary],
    eps: Vec<f64>,
    pub(super) lambdas: Vec<f64>,
    methods: Vec<String>,
}

impl<'a> Index<'a> {
    fn new(configs: &'a [Config], summaries: &'a [ConfigSummary]) -> Self {
        let mut eps: Vec<f64> = Vec::new();
        let mut lambdas: Vec<f64> = Vec::new();
        let mut methods: Vec<String> = Vec::new();
        for c in configs {
            if !eps.contains(&c.eps) {
                eps.push(c.eps);
            }
            if let Some(l) = c.lambda.filter(|l| !lambdas.contains(l)) {
                lambdas.push(l);
            }
            if !methods.contains(&c.method) {
                methods.push(c.method.clone());
            }
        }
        eps.sort_by(f64::total_cmp);
        lambdas.sort_by(|a, b| b.total_cmp(a));
        Index {
            configs,
            summaries,
            eps,
            lambdas,
            methods,
        }
    }

    /// The summary of `method` at `eps` and `lambda` (a method that ignores
    /// λ answers for any), if it was measured.
    pub(super) fn get(&self, method: &str, eps: f64, lambda: f64) -> Option<&'a ConfigSummary> {
        self.summaries.iter().find(|s| {
            let c = &self.configs[s.config];
            c.method == method && c.eps == eps && c.lambda.is_none_or(|l| l == lambda)
        })
    }

    /// Whether `method` reads λ (was measured per λ).
    fn reads_lambda(&self, method: &str) -> bool {
        self.configs
            .iter()
            .any(|c| c.method == method && c.lambda.is_some())
    }

    /// The table columns: each method that ignores λ once, then per λ the
    /// methods that read it.
    fn columns(&self) -> Vec<(&str, Option<f64>)> {
        let mut cols: Vec<(&str, Option<f64>)> = self
            .methods
            .iter()
            .filter(|m| !self.reads_lambda(m))
            .map(|m| (m.as_str(), None))
            .collect();
        for &l in &self.lambdas {
            for m in self.methods.iter().filter(|m| self.reads_lambda(m)) {
                cols.push((m.as_str(), Some(l)));
            }
        }
        cols
    }

    /// Every measured summary in table order, with its configuration.
    fn rows(&self) -> Vec<(&'a Config, &'a ConfigSummary)> {
        let mut out = Vec::new();
        for &e in &self.eps {
            for (m, l) in self.columns() {
                if let Some(s) = self.get(m, e, l.unwrap_or(f64::NAN)) {
                    out.push((&self.configs[s.config], s));
                }
            }
        }
        out
    }
}

/// `report.md`: setup, tables, targets and the plots beside it.
pub fn markdown(
    setup: &Setup,
    configs: &[Config],
    summaries: &[ConfigSummary],
    plots: &[(&str, &str)],
) -> String {
    let ix = Index::new(configs, summaries);
    let mut md = format!("# bench: {}\n\n", setup.scene_name);
    md += &format!("```sh\n{}\n```\n\n", setup.command);
    md += &setup_table(setup);
    md += &table1(&ix, setup);
    md += &table2(&ix);
    md += &passes_table(&ix);
    md += &figures_table(&ix);
    md += &memory_table(&ix);
    let curves = pareto::curves(configs, summaries);
    md += &equal_error(&curves, ErrorMeasure::Flip);
    md += &equal_error(
        &pareto::geometric_curves(configs, summaries),
        ErrorMeasure::Geometric,
    );
    md += &equal_error(
        &pareto::geometric_p99_curves(configs, summaries),
        ErrorMeasure::GeometricP99,
    );
    md += &geometric_error(&ix);
    md += &error_sources(&ix, setup);
    md += &targets::section(&ix, setup, &curves);
    md += "## Plots\n\n";
    for (file, what) in plots {
        md += &format!("![{what}]({file})\n\n");
    }
    md
}

fn setup_table(s: &Setup) -> String {
    let (w, h) = s.size;
    let device = if s.device_is_cpu {
        format!(
            "{} (CPU device: its times say nothing about a GPU)",
            s.device
        )
    } else {
        s.device.clone()
    };
    let flip_t: Vec<String> = s.flip_t.iter().map(|t| format!("{t:.3}")).collect();
    let status = match &s.stopped {
        None => "complete".to_string(),
        Some(why) => format!("**stopped early** ({why}): the tables cover the frames measured"),
    };
    let rows = [
        ("device", device),
        ("driver", s.driver.clone()),
        ("resolution", format!("{w}×{h}")),
        (
            "scene",
            format!(
                "{} (`{}`), {} base patches",
                s.scene_name,
                s.scene,
                thousands(s.patches as u64)
            ),
        ),
        ("camera path", s.path.clone()),
        (
            "split",
            format!(
                "`{}` (how {} split a node)",
                s.split,
                crate::methods::names_that_read(|r| r.split)
            ),
        ),
        (
            "frames",
            format!(
                "{} per configuration after {} warm-up frames",
                s.frames, s.warmup
            ),
        ),
        (
            "FLIP",
            format!(
                "{} perspectives at t = {} against `ground-truth` at grid {}",
                s.flip_t.len(),
                flip_t.join(", "),
                s.grid
            ),
        ),
        ("l_max", crate::constants::L_MAX.to_string()),
        ("commit", format!("`{}`", s.commit)),
        ("run", status),
    ];
    let mut md = "| | |\n|---|---|\n".to_string();
    for (k, v) in rows {
        md += &format!("| {k} | {v} |\n");
    }
    md + "\nTimes are medians over the frames of the path of the GPU timestamps \
           around the whole frame (`gpu_ms.frame`); min–max beside them.\n\n"
}

/// Table 1: FLIP per perspective, per ε, per method and λ; the best of
/// each ε and perspective in bold (the paper underlines it).
fn table1(ix: &Index<'_>, setup: &Setup) -> String {
    let n = setup.flip_t.len();
    let mut md = "## Table 1: image error (FLIP against the ground truth)\n\n".to_string();
    if n == 0 || ix.summaries.iter().all(|s| s.flips.is_empty()) {
        return md + "No FLIP perspectives were measured.\n\n";
    }
    md += "| ε | method | λ |";
    for k in 0..n {
        md += &format!(" {} |", k + 1);
    }
    md += " median |\n|---|---|---|";
    md += &"---:|".repeat(n + 1);
    md += "\n";
    for &e in &ix.eps {
        let group: Vec<_> = ix.rows().into_iter().filter(|(c, _)| c.eps == e).collect();
        let best: Vec<Option<f64>> = (1..=n)
            .map(|k| {
                group
                    .iter()
                    .filter_map(|(_, s)| s.flips.iter().find(|f| f.perspective == k))
                    .map(|f| f.mean)
                    .min_by(f64::total_cmp)
            })
            .collect();
        for (c, s) in &group {
            md += &format!("| {} | {} | {} |", c.eps, c.method, lambda_text(c));
            for (k, b) in best.iter().enumerate() {
                match s.flips.iter().find(|f| f.perspective == k + 1) {
                    Some(f) if group.len() > 1 && Some(f.mean) == *b => {
                        md += &format!(" **{:.5}** |", f.mean)
                    }
                    Some(f) => md += &format!(" {:.5} |", f.mean),
                    None => md += " – |",
                }
            }
            md += &match s.flip_median() {
                Some(m) => format!(" {m:.5} |\n"),
                None => " – |\n".into(),
            };
        }
    }
    md + "\n"
}

/// Table 2: per ε, render time and triangles (wedge share) per λ and
/// method.
fn table2(ix: &Index<'_>) -> String {
    let mut md = "## Table 2: render time and triangles (% wedges)\n\n| ε | |".to_string();
    let cols = ix.columns();
    for &(m, l) in &cols {
        md += &match l {
            Some(l) => format!(" {m}, λ = {l} |"),
            None => format!(" {m} |"),
        };
    }
    md += "\n|---|---|";
    md += &"---:|".repeat(cols.len());
    md += "\n";
    for &e in &ix.eps {
        let mut time = format!("| {e} | render time |");
        let mut tris = format!("| {e} | triangles (% wedges) |");
        for &(m, l) in &cols {
            let s = ix.get(m, e, l.unwrap_or(f64::NAN));
            match s.and_then(|s| s.get("gpu_ms.frame")) {
                Some((med, lo, hi)) => time += &format!(" {} ({:.3}–{:.3}) |", ms(med), lo, hi),
                None => time += " – |",
            }
            match s.and_then(|s| s.get("triangles")) {
                Some((med, lo, hi)) => {
                    let share = s
                        .and_then(|s| s.get("wedge_share"))
                        .map_or(String::new(), |w| format!(" ({:.1} %)", 100.0 * w.0));
                    tris += &format!(
                        " {}{share} ({}–{}) |",
                        thousands(med.round() as u64),
                        thousands(lo as u64),
                        thousands(hi as u64)
                    );
                }
                None => tris += " – |",
            }
        }
        md += &format!("{time}\n{tris}\n");
    }
    md + "\n"
}

/// GPU time per named pass (medians), every scope any method reported.
fn passes_table(ix: &Index<'_>) -> String {
    let rows = ix.rows();
    let mut scopes: Vec<&str> = Vec::new();
    for (_, s) in &rows {
        for sc in &s.stats.scopes {
            if let Some(name) = sc.0.strip_prefix("gpu_ms.") {
                if !scopes.contains(&name) {
                    scopes.push(name);
                }
            }
        }
    }
    let mut md = "## GPU time per pass (median ms)\n\n| method | λ | ε |".to_string();
    for sc in &scopes {
        md += &format!(" {sc} |");
    }
    md += "\n|---|---|---|";
    md += &"---:|".repeat(scopes.len());
    md += "\n";
    for (c, s) in rows {
        md += &format!("| {} | {} | {} |", c.method, lambda_text(c), c.eps);
        for sc in &scopes {
            md += &match s.get(&format!("gpu_ms.{sc}")) {
                Some((m, _, _)) => format!(" {m:.3} |"),
                None => " – |".into(),
            };
        }
        md += "\n";
    }
    md + "\n"
}

/// Subdivision figures: medians, and the worst frame for depth, rounds and
/// memory. The level schedule (both methods' default) reports rounds; the
/// `--kernel queue` variant reports its queue instead, so both sets of
/// columns are here and a method leaves the other's empty.
fn figures_table(ix: &Index<'_>) -> String {
    let cols: [(&str, &str, bool); 9] = [
        ("method_stats.ready_quads", "ready quads", false),
        ("culled_patches", "culled patches", false),
        ("method_stats.nodes_processed", "nodes processed", false),
        ("method_stats.max_depth", "max depth (max)", true),
        ("method_stats.rounds", "rounds (max)", true),
        ("method_stats.rounds_split", "rounds in parts (max)", true),
        ("method_stats.queue_peak_items", "queue peak (max)", true),
        ("method_stats.queue_spills", "queue spills (max)", true),
        ("frames_redone", "frames redone (max)", true),
    ];
    let mut md = "## Subdivision figures (median over the path; (max): the worst frame)\n\n\
                  | method | λ | ε |"
        .to_string();
    for (_, name, _) in &cols {
        md += &format!(" {name} |");
    }
    md += "\n|---|---|---|";
    md += &"---:|".repeat(cols.len());
    md += "\n";
    for (c, s) in ix.rows() {
        md += &format!("| {} | {} | {} |", c.method, lambda_text(c), c.eps);
        for (key, _, worst) in &cols {
            md += &match s.get(key) {
                Some((m, _, hi)) => format!(
                    " {} |",
                    thousands(if *worst { hi } else { m }.round() as u64)
                ),
                None => " – |".into(),
            };
        }
        md += "\n";
    }
    md + "\n"
}

/// Memory by purpose per method (the largest seen over the run: buffers
/// only grow), the paper's §4.3 comparison.
fn memory_table(ix: &Index<'_>) -> String {
    let mut purposes: Vec<&str> = Vec::new();
    for s in ix.summaries {
        for sc in &s.stats.scopes {
            if let Some(p) = sc.0.strip_prefix("memory_bytes.") {
                if !purposes.contains(&p) {
                    purposes.push(p);
                }
            }
        }
    }
    let held = |m: &str, p: &str| -> Option<f64> {
        ix.summaries
            .iter()
            .filter(|s| ix.configs[s.config].method == m)
            .filter_map(|s| s.get(&format!("memory_bytes.{p}")).map(|x| x.2))
            .max_by(f64::total_cmp)
    };
    let mut md = "## Memory by purpose (GPU buffers, the largest held during the run)\n\n\
                  | purpose |"
        .to_string();
    for m in &ix.methods {
        md += &format!(" {m} |");
    }
    md += "\n|---|";
    md += &"---:|".repeat(ix.methods.len());
    md += "\n";
    for p in &purposes {
        md += &format!("| {p} |");
        for m in &ix.methods {
            md += &held(m, p).map_or(" – |".into(), |b| format!(" {} |", mib(b)));
        }
        md += "\n";
    }
    md += "| **total** |";
    for m in &ix.methods {
        let total: f64 = purposes.iter().filter_map(|p| held(m, p)).sum();
        md += &format!(" **{}** |", mib(total));
    }
    md += "\n\n";
    md
}

/// The error a comparison at equal error holds equal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ErrorMeasure {
    Flip,
    Geometric,
    GeometricP99,
}

/// The comparison at equal image error: per curve and ε, the triangles
/// and frame time `tess` needs for the same FLIP (interpolated on its
/// curve), and one verdict per curve.
fn equal_error(curves: &[Curve], what: ErrorMeasure) -> String {
    let (title, name, digits) = match what {
        ErrorMeasure::Flip => ("image error", "FLIP", 5),
        ErrorMeasure::Geometric => ("geometric error", "mean geometric error (px)", 3),
        ErrorMeasure::GeometricP99 => ("geometric error, 99th percentile", "geometric p99 (px)", 3),
    };
    let base = crate::methods::baseline().name;
    let mut md = format!(
        "## At equal {title} (against `{base}`)\n\n\
         Per configuration: its {name} (median over the perspectives), its triangles in those \
         images and its median frame time, and what `{base}` needs for the same error, \
         interpolated log-log between the two ε of `{base}` whose errors bracket it \
         (`–`: outside `{base}`'s range).\n\n"
    );
    let Some(reference) = curves.iter().find(|c| c.method == base) else {
        return md + &format!("Not measured: `{base}` needs FLIP perspectives in the run.\n\n");
    };
    md += &format!(
        "| curve | ε | {name} | triangles | `{base}` triangles | ratio | frame ms | \
         `{base}` ms | ratio |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    let mut verdicts = String::new();
    for c in curves.iter().filter(|c| c.method != base) {
        let at = against(c, reference);
        for p in &c.points {
            let a = at.iter().find(|a| a.point.eps == p.eps);
            let opt = |x: Option<f64>, f: &dyn Fn(f64) -> String| x.map_or("–".to_string(), f);
            md += &format!(
                "| {} | {} | {:.digits$} | {} | {} | {} | {} | {} | {} |\n",
                c.name(),
                p.eps,
                p.error,
                thousands(p.triangles.round() as u64),
                opt(a.map(|a| a.ref_triangles), &|t| thousands(t.round() as u64)),
                opt(a.map(|a| a.triangle_ratio()), &|r| format!("{r:.3}×")),
                opt(p.frame_ms, &|m| format!("{m:.3}")),
                opt(a.and_then(|a| a.ref_frame_ms), &|m| format!("{m:.3}")),
                opt(a.and_then(|a| a.time_ratio()), &|r| format!("{r:.3}×")),
            );
        }
        let tri = median(at.iter().map(|a| a.triangle_ratio()).collect());
        let time = median(at.iter().filter_map(|a| a.time_ratio()).collect());
        verdicts += &match tri {
            None => format!("- **{}**: no ε within `{base}`'s error range.\n", c.name()),
            Some(t) => format!(
                "- **{}**: at equal {name} it draws {t:.2}× `{base}`'s triangles{} \
                 (median of {} ε): {}.\n",
                c.name(),
                time.map_or(String::new(), |x| format!(" in {x:.2}× its frame time")),
                at.len(),
                match (t < 1.0, time.map(|x| x < 1.0)) {
                    (true, Some(true)) => "fewer triangles and faster",
                    (true, Some(false)) => "fewer triangles, but slower",
                    (false, Some(true)) => "more triangles, but faster",
                    (false, Some(false)) => "more triangles and slower",
                    (true, None) => "fewer triangles",
                    (false, None) => "more triangles",
                }
            ),
        };
    }
    md + "\n" + &verdicts + "\n"
}

/// The geometric error beside FLIP, and whether each method keeps the ε it
/// promises (its 99th percentile within ε).
fn geometric_error(ix: &Index<'_>) -> String {
    let mut md = "## Geometric error and each method's ε\n\n\
                  The distance between the drawn surface and the ground truth's, in pixels, \
                  over the pixels both images cover off the silhouettes (median over the \
                  perspectives of each image's mean and 99th percentile); silhouette pixels \
                  that differ (coverage, or a different surface seen) are counted instead. \
                  A method keeps its ε when the 99th percentile is within it.\n\n\
                  | method | λ | ε | mean px | p99 px | silhouette px | ε kept |\n\
                  |---|---|---:|---:|---:|---:|---|\n"
        .to_string();
    let mut any = false;
    for (c, s) in ix.rows() {
        let (Some(mean), Some(p99), Some(sil)) = (
            s.flip_figure_median(|b| Some(b.geo_mean_px)),
            s.flip_figure_median(|b| Some(b.geo_p99_px)),
            s.flip_figure_median(|b| Some(b.silhouette_diff_px as f64)),
        ) else {
            continue;
        };
        any = true;
        md += &format!(
            "| {} | {} | {} | {mean:.3} | {p99:.3} | {} | {} |\n",
            c.method,
            lambda_text(c),
            c.eps,
            thousands(sil.round() as u64),
            if p99 <= c.eps {
                "yes".to_string()
            } else {
                format!("no: p99 {:.0} % over", 100.0 * (p99 / c.eps - 1.0))
            }
        );
    }
    if !any {
        return String::new();
    }
    md + "\n"
}

/// Where the FLIP error lies at ε = 1 (else the middle ε): in the
/// silhouette band, on wedges, and per model (over all perspectives).
fn error_sources(ix: &Index<'_>, setup: &Setup) -> String {
    let Some(&e) = ix
        .eps
        .iter()
        .find(|&&e| e == 1.0)
        .or_else(|| ix.eps.get(ix.eps.len() / 2))
    else {
        return String::new();
    };
    let rows: Vec<_> = ix
        .rows()
        .into_iter()
        .filter(|(c, s)| c.eps == e && !s.flips.is_empty())
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    let mut md = format!(
        "## Where the image error lies (ε = {e})\n\n\
         Share of the FLIP sum (all perspectives) in the silhouette band (a pixel either side of \
         a coverage or depth jump in either image), on wedge triangles (their share of the \
         pixels beside it), and the models with the largest shares (by the ground truth's patch \
         under each pixel; geometric error in pixels beside).\n\n\
         | method | λ | silhouettes | wedges (pixels) | largest shares by model |\n\
         |---|---|---:|---:|---|\n"
    );
    for (c, s) in rows {
        let sil = s.flip_figure_median(|b| Some(b.flip_silhouette_share));
        let wedge = s.flip_figure_median(|b| b.flip_wedge_share);
        let wedge_px = s.flip_figure_median(|b| b.wedge_pixel_share);
        let n = s
            .flips
            .iter()
            .map(|f| f.breakdown.models.len())
            .max()
            .unwrap_or(0);
        let mut per: Vec<(usize, f64, f64, u64)> = (0..n)
            .map(|i| {
                let ms = s.flips.iter().filter_map(|f| f.breakdown.models.get(i));
                let (flip, geo, px) = ms.fold((0.0, 0.0, 0), |(a, b, c), m| {
                    (a + m.flip_sum, b + m.geo_sum_px, c + m.geo_pixels)
                });
                (i, flip, geo, px)
            })
            .collect();
        let total: f64 = per.iter().map(|p| p.1).sum();
        per.sort_by(|a, b| b.1.total_cmp(&a.1));
        let top: Vec<String> = per
            .iter()
            .take(4)
            .filter(|p| p.1 > 0.0 && total > 0.0)
            .map(|&(i, flip, geo, px)| {
                let name = setup.models.get(i).map_or("?", String::as_str);
                let g = if px > 0 { geo / px as f64 } else { 0.0 };
                format!("{name} {:.0} % ({g:.2} px)", 100.0 * flip / total)
            })
            .collect();
        let pct = |x: Option<f64>| x.map_or("–".to_string(), |v| format!("{:.0} %", 100.0 * v));
        md += &format!(
            "| {} | {} | {} | {}{} | {} |\n",
            c.method,
            lambda_text(c),
            pct(sil),
            pct(wedge),
            wedge_px.map_or(String::new(), |p| format!(" ({:.1} %)", 100.0 * p)),
            top.join(", ")
        );
    }
    md + "\n"
}
