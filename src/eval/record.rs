//! What a `bench` run measures, and the files that keep it as it is
//! measured: `frames.csv` and `flip.csv` (a row per frame, each flushed
//! when it is complete, so a run stopped at any point leaves valid files),
//! and the medians per configuration that `summary.json` and `report.md`
//! are made from.
//!
//! Every figure keeps the key name of `render`'s stats file; nested keys
//! are flattened with a dot (`gpu_ms.subdivide`, `method_stats.queue_spills`)
//! in the CSV and nested again in the JSON.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use serde_json::{json, Map, Value};

use crate::figures::Timing;
use crate::renderer::FrameReport;

/// One configuration: a method at one ε and λ.
#[derive(Clone, Debug, PartialEq)]
pub struct Config {
    /// Method name.
    pub method: String,
    /// Pixel tolerance.
    pub eps: f64,
    /// Distance blend; `None` for a method that ignores λ (measured once
    /// per ε).
    pub lambda: Option<f64>,
    /// The method's draw path, once a frame has told it.
    pub draw_path: String,
}

impl Config {
    /// `subdiv ε=1 λ=0.5` (`tess ε=1`), for progress and legends.
    pub fn label(&self) -> String {
        match self.lambda {
            Some(l) => format!("{} ε={} λ={l}", self.method, self.eps),
            None => format!("{} ε={}", self.method, self.eps),
        }
    }

    /// `subdiv-e1-l0.5` (`tess-e1`), for file names.
    pub fn stem(&self) -> String {
        match self.lambda {
            Some(l) => format!("{}-e{}-l{l}", self.method, self.eps),
            None => format!("{}-e{}", self.method, self.eps),
        }
    }

    /// The method and λ, the name of one curve over ε (`subdiv λ=0.5`, `tess`).
    pub fn series(&self) -> String {
        match self.lambda {
            Some(l) => format!("{} λ={l}", self.method),
            None => self.method.clone(),
        }
    }

    /// λ as a CSV cell (empty when the method ignores it).
    pub fn lambda_cell(&self) -> String {
        self.lambda.map_or_else(String::new, |l| l.to_string())
    }
}

/// One timed frame along the path.
#[derive(Clone, Debug)]
pub struct FrameRow {
    /// Index into the run's configurations.
    pub config: usize,
    /// Frame index along the path.
    pub frame: u32,
    /// Its position on the path, in [0, 1].
    pub t: f64,
    /// The figures under `render`'s stats key names, flattened.
    pub values: Vec<(String, Value)>,
}

/// The image error of one configuration at one perspective.
#[derive(Clone, Debug)]
pub struct FlipRow {
    /// Index into the run's configurations.
    pub config: usize,
    /// Perspective number (1-based, as in the image file names).
    pub perspective: usize,
    /// Its position on the path.
    pub t: f64,
    /// FLIP mean against the ground truth.
    pub mean: f64,
    /// Triangles of that render.
    pub triangles: u64,
    /// The render, relative to the output directory.
    pub image: String,
    /// The FLIP heat map, relative to the output directory.
    pub heat_map: String,
    /// Where the error lies, and the geometric error beside FLIP.
    pub breakdown: crate::eval::geometry::Breakdown,
}

/// The run's figures of one frame under `render`'s stats key names: the
/// common keys, the wedge share where the method draws wedges, GPU time
/// per scope, memory per purpose, and the method's own section.
pub fn flatten(report: &FrameReport, memory: &[(&'static str, u64)]) -> Vec<(String, Value)> {
    let s = &report.stats;
    let mut v = vec![
        // The query's count, the same for every method (as in `render`).
        ("triangles".to_string(), json!(report.triangles())),
        ("method_triangles".to_string(), json!(s.triangles)),
        ("culled_patches".to_string(), json!(s.culled_patches)),
        ("frames_redone".to_string(), json!(report.redone)),
    ];
    if let Some(w) = s.get_u64("wedge_triangles") {
        let share = w as f64 / s.triangles.max(1) as f64;
        v.push(("wedge_share".into(), json!(share)));
    }
    let lod = &report.lod;
    if lod.bytes > 0 {
        // Levels of detail were on: what they drew, what occlusion culling
        // kept them from drawing, and per level index
        // (0 the finest of each model) instances and triangles.
        v.push(("lod.instances".into(), json!(lod.instances)));
        v.push(("lod.triangles".into(), json!(lod.triangles)));
        v.push(("lod.occluded".into(), json!(lod.occluded)));
        v.push(("lod.by_level".into(), json!(lod.by_level)));
    }
    v.extend(
        report
            .gpu_ms
            .iter()
            .map(|(k, ms)| (format!("gpu_ms.{k}"), json!(ms))),
    );
    v.extend(
        memory
            .iter()
            .map(|(k, b)| (format!("memory_bytes.{k}"), json!(b))),
    );
    v.extend(
        s.own
            .iter()
            .map(|(k, x)| (format!("method_stats.{k}"), x.clone())),
    );
    v
}

/// The columns every frame row starts with, before the figures.
pub const FRAME_COLUMNS: [&str; 6] = ["method", "draw_path", "eps", "lambda", "frame", "t"];

/// A column of `flip.csv`: its name and how a row's cell is written.
pub type FlipColumn = (&'static str, fn(&Config, &FlipRow) -> String);

/// The columns of `flip.csv`, each declared once with its cell.
pub const FLIP_COLUMNS: &[FlipColumn] = &[
    ("method", |c, _| c.method.clone()),
    ("draw_path", |c, _| c.draw_path.clone()),
    ("eps", |c, _| c.eps.to_string()),
    ("lambda", |c, _| c.lambda_cell()),
    ("perspective", |_, r| r.perspective.to_string()),
    ("t", |_, r| r.t.to_string()),
    ("flip_mean", |_, r| r.mean.to_string()),
    ("triangles", |_, r| r.triangles.to_string()),
    ("geo_mean_px", |_, r| r.breakdown.geo_mean_px.to_string()),
    ("geo_p99_px", |_, r| r.breakdown.geo_p99_px.to_string()),
    ("silhouette_diff_px", |_, r| {
        r.breakdown.silhouette_diff_px.to_string()
    }),
    ("flip_silhouette_share", |_, r| {
        r.breakdown.flip_silhouette_share.to_string()
    }),
    ("flip_wedge_share", |_, r| {
        opt_cell(r.breakdown.flip_wedge_share)
    }),
    ("wedge_pixel_share", |_, r| {
        opt_cell(r.breakdown.wedge_pixel_share)
    }),
    ("image", |_, r| r.image.clone()),
    ("heat_map", |_, r| r.heat_map.clone()),
];

/// The names of [`FLIP_COLUMNS`].
pub fn flip_columns() -> Vec<&'static str> {
    FLIP_COLUMNS.iter().map(|c| c.0).collect()
}

/// The columns of `breakdown.csv`: per configuration, perspective and
/// model, the reference pixels showing the model, FLIP over them and the
/// geometric error.
pub const BREAKDOWN_COLUMNS: [&str; 10] = [
    "method",
    "eps",
    "lambda",
    "perspective",
    "model",
    "pixels",
    "flip_sum",
    "flip_share",
    "geo_mean_px",
    "geo_pixels",
];

/// The figure keys of several frames' flattened values, each once, in the
/// order first seen, grouped as the stats file groups them: common keys,
/// then `gpu_ms`, `memory_bytes`, `method_stats`.
pub fn figure_keys<'a>(frames: impl IntoIterator<Item = &'a [(String, Value)]>) -> Vec<String> {
    let mut keys: Vec<String> = Vec::new();
    for f in frames {
        for (k, _) in f {
            if !keys.contains(k) {
                keys.push(k.clone());
            }
        }
    }
    let group = |k: &String| {
        ["gpu_ms.", "memory_bytes.", "method_stats."]
            .iter()
            .position(|p| k.starts_with(p))
            .map_or(0, |i| i + 1)
    };
    // Stable: first-seen order within each group.
    keys.sort_by_key(group);
    keys
}

/// A CSV file written row by row: each row goes out in one write as soon
/// as it is complete, so whatever stops the run leaves whole rows only.
pub struct CsvLog {
    file: std::fs::File,
    path: PathBuf,
    columns: usize,
}

impl CsvLog {
    /// Creates (truncates) `path` and writes the header.
    pub fn create(path: &Path, columns: &[String]) -> std::io::Result<Self> {
        let file = std::fs::File::create(path)?;
        let mut log = CsvLog {
            file,
            path: path.to_path_buf(),
            columns: columns.len(),
        };
        log.write_line(columns)?;
        Ok(log)
    }

    /// Appends one row of exactly as many cells as there are columns.
    pub fn append(&mut self, cells: &[String]) -> std::io::Result<()> {
        if cells.len() != self.columns {
            return Err(std::io::Error::other(format!(
                "{}: a row of {} cells for {} columns",
                self.path.display(),
                cells.len(),
                self.columns
            )));
        }
        self.write_line(cells)
    }

    fn write_line(&mut self, cells: &[String]) -> std::io::Result<()> {
        let mut line = cells
            .iter()
            .map(|c| csv_cell(c))
            .collect::<Vec<_>>()
            .join(",");
        line.push('\n');
        self.file.write_all(line.as_bytes())?;
        self.file.flush()
    }
}

/// A CSV cell, quoted when it holds a separator, a quote or a line break.
pub fn csv_cell(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// A figure as a CSV cell: numbers and booleans as they are, lists as
/// compact JSON, missing as empty.
pub fn value_cell(v: Option<&Value>) -> String {
    match v {
        None | Some(Value::Null) => String::new(),
        Some(Value::String(s)) => s.clone(),
        Some(x) => x.to_string(),
    }
}

/// The cells of a frame row for `keys`.
pub fn frame_cells(config: &Config, row: &FrameRow, keys: &[String]) -> Vec<String> {
    let mut cells = vec![
        config.method.clone(),
        config.draw_path.clone(),
        config.eps.to_string(),
        config.lambda_cell(),
        row.frame.to_string(),
        row.t.to_string(),
    ];
    cells.extend(
        keys.iter()
            .map(|k| value_cell(row.values.iter().find(|(n, _)| n == k).map(|(_, v)| v))),
    );
    cells
}

/// The cells of a `flip.csv` row.
pub fn flip_cells(config: &Config, row: &FlipRow) -> Vec<String> {
    FLIP_COLUMNS
        .iter()
        .map(|(_, cell)| cell(config, row))
        .collect()
}

fn opt_cell(x: Option<f64>) -> String {
    x.map_or_else(String::new, |v| v.to_string())
}

/// The rows of `breakdown.csv` for one FLIP row (models by name; models
/// the reference does not show are left out).
pub fn breakdown_rows(config: &Config, row: &FlipRow, models: &[String]) -> Vec<Vec<String>> {
    let total: f64 = row.breakdown.models.iter().map(|m| m.flip_sum).sum();
    row.breakdown
        .models
        .iter()
        .enumerate()
        .filter(|(_, m)| m.pixels > 0)
        .map(|(i, m)| {
            vec![
                config.method.clone(),
                config.eps.to_string(),
                config.lambda_cell(),
                row.perspective.to_string(),
                models
                    .get(i)
                    .cloned()
                    .unwrap_or_else(|| format!("model {i}")),
                m.pixels.to_string(),
                m.flip_sum.to_string(),
                if total > 0.0 { m.flip_sum / total } else { 0.0 }.to_string(),
                if m.geo_pixels > 0 {
                    m.geo_sum_px / m.geo_pixels as f64
                } else {
                    0.0
                }
                .to_string(),
                m.geo_pixels.to_string(),
            ]
        })
        .collect()
}

/// One configuration's frames summarised: median, min and max of every
/// numeric figure (`Timing` does for any named figure what it does for
/// GPU scopes), and its FLIP rows.
#[derive(Clone, Debug)]
pub struct ConfigSummary {
    /// Index into the run's configurations.
    pub config: usize,
    /// (key, median, min, max) per numeric figure; `frames` counts them.
    pub stats: Timing,
    /// FLIP per perspective, in perspective order.
    pub flips: Vec<FlipRow>,
    /// The last frame's figures as they were (lists and flags included).
    pub last: Vec<(String, Value)>,
}

impl ConfigSummary {
    /// Summarises the rows of configuration `config`.
    pub fn of(config: usize, frames: &[FrameRow], flips: &[FlipRow]) -> Self {
        let numeric: Vec<Vec<(String, f64)>> = frames
            .iter()
            .filter(|r| r.config == config)
            .map(|r| {
                r.values
                    .iter()
                    .filter_map(|(k, v)| v.as_f64().map(|x| (k.clone(), x)))
                    .collect()
            })
            .collect();
        let mut flips: Vec<FlipRow> = flips
            .iter()
            .filter(|f| f.config == config)
            .cloned()
            .collect();
        flips.sort_by_key(|f| f.perspective);
        let last = frames
            .iter()
            .rev()
            .find(|r| r.config == config)
            .map_or_else(Vec::new, |r| r.values.clone());
        ConfigSummary {
            config,
            stats: Timing::of(&numeric),
            flips,
            last,
        }
    }

    /// Figure `key` of the last frame, as it was.
    pub fn fact(&self, key: &str) -> Option<&Value> {
        self.last.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    /// (median, min, max) of figure `key`, if any frame had it.
    pub fn get(&self, key: &str) -> Option<(f64, f64, f64)> {
        self.stats
            .scopes
            .iter()
            .find(|s| s.0 == key)
            .map(|s| (s.1, s.2, s.3))
    }

    /// The median of the FLIP means over the perspectives measured.
    pub fn flip_median(&self) -> Option<f64> {
        let mut v: Vec<f64> = self.flips.iter().map(|f| f.mean).collect();
        v.sort_by(f64::total_cmp);
        (!v.is_empty()).then(|| crate::figures::median(&v))
    }

    /// The median over the perspectives of a figure of their breakdowns.
    pub fn flip_figure_median(
        &self,
        f: impl Fn(&crate::eval::geometry::Breakdown) -> Option<f64>,
    ) -> Option<f64> {
        let mut v: Vec<f64> = self.flips.iter().filter_map(|r| f(&r.breakdown)).collect();
        v.sort_by(f64::total_cmp);
        (!v.is_empty()).then(|| crate::figures::median(&v))
    }

    /// The median triangle count of the FLIP images.
    pub fn flip_triangles_median(&self) -> Option<f64> {
        let mut v: Vec<f64> = self.flips.iter().map(|f| f.triangles as f64).collect();
        v.sort_by(f64::total_cmp);
        (!v.is_empty()).then(|| crate::figures::median(&v))
    }

    /// The `summary.json` entry: the medians nested as in `render`'s stats
    /// file, with `min` and `max` beside them in the same layout, and FLIP.
    pub fn to_json(&self, config: &Config) -> Value {
        let pick = |i: usize| {
            nest(
                self.stats
                    .scopes
                    .iter()
                    .map(|s| (s.0.as_str(), [s.1, s.2, s.3][i])),
            )
        };
        let mut entry = Map::new();
        entry.insert("method".into(), json!(config.method));
        entry.insert("draw_path".into(), json!(config.draw_path));
        entry.insert("eps".into(), json!(config.eps));
        entry.insert("lambda".into(), json!(config.lambda));
        entry.insert("frames".into(), json!(self.stats.frames));
        if let Value::Object(medians) = pick(0) {
            entry.extend(medians);
        }
        entry.insert("min".into(), pick(1));
        entry.insert("max".into(), pick(2));
        let per: Vec<Value> = self
            .flips
            .iter()
            .map(|f| {
                let b = &f.breakdown;
                json!({"perspective": f.perspective, "t": f.t, "flip_mean": f.mean,
                       "triangles": f.triangles, "geo_mean_px": b.geo_mean_px,
                       "geo_p99_px": b.geo_p99_px, "silhouette_diff_px": b.silhouette_diff_px,
                       "flip_silhouette_share": b.flip_silhouette_share,
                       "flip_wedge_share": b.flip_wedge_share,
                       "image": f.image, "heat_map": f.heat_map})
            })
            .collect();
        entry.insert(
            "flip".into(),
            json!({"median": self.flip_median(),
                   "geo_mean_px": self.flip_figure_median(|b| Some(b.geo_mean_px)),
                   "geo_p99_px": self.flip_figure_median(|b| Some(b.geo_p99_px)),
                   "silhouette_diff_px": self.flip_figure_median(|b| Some(b.silhouette_diff_px as f64)),
                   "flip_silhouette_share": self.flip_figure_median(|b| Some(b.flip_silhouette_share)),
                   "flip_wedge_share": self.flip_figure_median(|b| b.flip_wedge_share),
                   "perspectives": per}),
        );
        Value::Object(entry)
    }
}

/// Nests dotted keys: `gpu_ms.draw` → `{"gpu_ms": {"draw": …}}`.
pub fn nest<'a>(pairs: impl IntoIterator<Item = (&'a str, f64)>) -> Value {
    let mut root = Map::new();
    for (key, x) in pairs {
        match key.split_once('.') {
            Some((group, name)) => {
                let g = root
                    .entry(group.to_string())
                    .or_insert_with(|| Value::Object(Map::new()));
                if let Value::Object(m) = g {
                    m.insert(name.to_string(), json!(x));
                }
            }
            None => {
                root.insert(key.to_string(), json!(x));
            }
        }
    }
    Value::Object(root)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::methods::MethodStats;

    fn report(tris: u64, wedges: u64, frame_ms: f64) -> FrameReport {
        FrameReport {
            method: "m",
            draw_path: "mesh",
            stats: MethodStats {
                triangles: tris,
                placeholder_triangles: 0,
                culled_patches: 7,
                own: vec![
                    ("wedge_triangles", json!(wedges)),
                    ("nodes_per_depth", json!([1, 2])),
                ],
            },
            gpu_ms: vec![("frame".into(), frame_ms), ("draw".into(), 1.0)],
            redone: 0,
            compiled: false,
            primitives: None,
            lod: Default::default(),
        }
    }

    #[test]
    fn figures_keep_the_stats_names_and_summaries_take_medians() {
        let rows: Vec<FrameRow> = [
            (100, 25, 3.0),
            (300, 30, 1.0),
            (200, 50, 2.0),
            (400, 0, 9.0),
        ]
        .iter()
        .enumerate()
        .map(|(i, &(t, w, ms))| FrameRow {
            config: 0,
            frame: i as u32,
            t: 0.0,
            values: flatten(&report(t, w, ms), &[("queue", 64)]),
        })
        .collect();
        let keys = figure_keys(rows.iter().map(|r| r.values.as_slice()));
        assert_eq!(
            keys,
            [
                "triangles",
                "method_triangles",
                "culled_patches",
                "frames_redone",
                "wedge_share",
                "gpu_ms.frame",
                "gpu_ms.draw",
                "memory_bytes.queue",
                "method_stats.wedge_triangles",
                "method_stats.nodes_per_depth"
            ]
        );
        let s = ConfigSummary::of(0, &rows, &[]);
        assert_eq!(s.stats.frames, 4);
        assert_eq!(s.get("triangles"), Some((250.0, 100.0, 400.0)));
        assert_eq!(s.get("gpu_ms.frame"), Some((2.5, 1.0, 9.0)));
        assert_eq!(s.get("wedge_share"), Some((0.175, 0.0, 0.25)));
        // Lists are not summarised.
        assert_eq!(s.get("method_stats.nodes_per_depth"), None);
        let config = Config {
            method: "m".into(),
            eps: 1.0,
            lambda: Some(0.5),
            draw_path: "mesh".into(),
        };
        let j = s.to_json(&config);
        assert_eq!(j["gpu_ms"]["frame"], json!(2.5));
        assert_eq!(j["max"]["gpu_ms"]["frame"], json!(9.0));
        assert_eq!(j["method_stats"]["wedge_triangles"], json!(27.5));
        assert_eq!(j["triangles"], json!(250.0));
        // The CSV row has a cell per column; the list is one quoted cell.
        let cells = frame_cells(&config, &rows[0], &keys);
        assert_eq!(cells.len(), FRAME_COLUMNS.len() + keys.len());
        assert_eq!(csv_cell(cells.last().unwrap()), "\"[1,2]\"");
    }

    #[test]
    fn csv_rows_must_fit_the_header() {
        let dir = std::env::temp_dir().join(format!("bezier-subdiv-csv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("x.csv");
        let mut log = CsvLog::create(&path, &["a".into(), "b".into()]).unwrap();
        log.append(&["1".into(), "say \"hi\", twice".into()])
            .unwrap();
        assert!(log.append(&["1".into()]).is_err());
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "a,b\n1,\"say \"\"hi\"\", twice\"\n");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
