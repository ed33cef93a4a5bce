//! `bench`'s measuring loop: the probes, the warm-ups, the frames along the
//! path, and at each FLIP perspective the ground truth and every
//! configuration's error against it.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::anyhow;

use super::{BenchArgs, Plan, Step};
use crate::constants::{PATCH_MODEL_SHIFT, SHADE_NORMAL};
use crate::eval::geometry::Reference;
use crate::eval::record::{
    breakdown_rows, figure_keys, flatten, flip_cells, flip_columns, frame_cells, Config, CsvLog,
    FlipRow, FrameRow, BREAKDOWN_COLUMNS, FRAME_COLUMNS,
};
use crate::eval::report::Setup;
use crate::eval::{
    distance_image, flip::flip, geometry, ground_truth_image, ground_truth_reference, wedge_image,
};
use crate::frame::View;
use crate::gpu::write_png;
use crate::patch::view::Split;
use crate::renderer::Renderer;
use crate::scene::geometry::SceneGeometry;
use crate::scene::path::ScenePath;

/// What has been measured so far.
pub(super) struct Measured {
    pub(super) configs: Vec<Config>,
    pub(super) rows: Vec<FrameRow>,
    pub(super) flips: Vec<FlipRow>,
    pub(super) steps: u64,
}

/// The measuring loop: a probe frame per method (for the CSV's columns),
/// every configuration's warm-up, then frame by frame along the path every
/// configuration in turn, then per FLIP perspective the ground truth and
/// every configuration. Returns early, with what it has, on `cancel`.
#[allow(clippy::too_many_arguments)]
pub(super) fn measure(
    renderer: &mut Renderer,
    geo: &SceneGeometry,
    args: &BenchArgs,
    plan: &Plan,
    path: &ScenePath,
    setup: &Setup,
    cancel: &AtomicBool,
    watch: &mut dyn FnMut(&Step<'_>),
    m: &mut Measured,
) -> anyhow::Result<()> {
    let mut run = Measuring {
        total: plan.total_steps(),
        split: plan.split,
        // Animation time of path position t (frame i of the path at i / fps).
        fps: renderer.animation().map(|a| a.fps),
        renderer,
        args,
        plan,
        path,
        cancel,
        watch,
        m,
    };
    let ControlFlow::Continue(keys) = run.probe_methods()? else {
        return Ok(());
    };
    // Created once the columns are known, before any timed frame: a run
    // stopped from here on leaves them with every column.
    let mut columns: Vec<String> = FRAME_COLUMNS.iter().map(|s| s.to_string()).collect();
    columns.extend(keys.iter().cloned());
    let mut frames_csv = CsvLog::create(&args.out.join("frames.csv"), &columns)?;
    let flip_columns: Vec<String> = flip_columns().iter().map(|s| s.to_string()).collect();
    let flip_csv = CsvLog::create(&args.out.join("flip.csv"), &flip_columns)?;
    if run.warm_up()?.is_break() || run.time_frames(&keys, &mut frames_csv)?.is_break() {
        return Ok(());
    }
    run.compare_perspectives(geo, setup, flip_csv)
}

/// The measuring loop's state: the renderer, what the run was asked for,
/// what has been measured and who hears of every frame.
struct Measuring<'a> {
    renderer: &'a mut Renderer,
    args: &'a BenchArgs,
    plan: &'a Plan,
    path: &'a ScenePath,
    cancel: &'a AtomicBool,
    watch: &'a mut dyn FnMut(&Step<'_>),
    m: &'a mut Measured,
    /// Frames the run renders, for the progress reports.
    total: u64,
    /// How `subdiv` and `subdiv-indirect` split.
    split: Split,
    /// The animation's frame rate (`None`: a still scene).
    fps: Option<f64>,
}

/// The CSV files of the FLIP perspectives, and the model names the
/// breakdown's rows carry.
struct FlipLogs {
    flip: CsvLog,
    breakdown: CsvLog,
    model_names: Vec<String>,
}

/// One FLIP perspective's ground truth: what every configuration is
/// compared with there.
struct Perspective {
    /// 1-based, as the files and rows name it.
    number: usize,
    t: f64,
    far: f32,
    truth: Vec<u8>,
    reference: Reference,
}

impl Measuring<'_> {
    /// Whether the run was asked to stop.
    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }

    /// Sets the animation clock to path position `t`.
    fn clock(&mut self, t: f64) {
        if let Some(fps) = self.fps {
            self.renderer
                .set_time(t * f64::from(self.plan.frames) / fps);
        }
    }

    /// The view of `c` at path position `t`. A method that ignores λ draws
    /// the same at any: it gets the first.
    fn view(&self, t: f64, c: &Config) -> View {
        let lambda = c.lambda.unwrap_or(self.args.lambda[0]);
        let mut v = View::new(
            &self.path.camera(t),
            self.args.size,
            c.eps,
            lambda,
            SHADE_NORMAL,
        );
        v.params.flags |= self.split.flag();
        v
    }

    /// Counts a rendered frame and tells the watcher.
    fn step(&mut self, what: &str) {
        self.m.steps += 1;
        (self.watch)(&Step {
            done: self.m.steps,
            total: self.total,
            what,
            rows: self.m.rows.len(),
        });
    }

    /// Probes every method once: its scopes, memory and figures name the
    /// CSV's columns, which must be known before the first row. Returns
    /// the figures' keys.
    fn probe_methods(&mut self) -> anyhow::Result<ControlFlow<(), Vec<String>>> {
        let mut probes = Vec::new();
        for name in self.plan.methods() {
            if self.cancelled() {
                return Ok(ControlFlow::Break(()));
            }
            let c = self
                .m
                .configs
                .iter()
                .find(|c| c.method == name)
                .expect("a method has configurations")
                .clone();
            self.renderer.set_method(&name)?;
            self.clock(0.0);
            let report = self.renderer.render(&self.view(0.0, &c))?;
            probes.push(flatten(&report, &self.renderer.memory()));
            self.step(&format!("{name}: first frame"));
        }
        Ok(ControlFlow::Continue(figure_keys(
            probes.iter().map(Vec::as_slice),
        )))
    }

    /// Every configuration's untimed warm-up frames.
    fn warm_up(&mut self) -> anyhow::Result<ControlFlow<()>> {
        for ci in 0..self.m.configs.len() {
            let c = self.m.configs[ci].clone();
            self.renderer.set_method(&c.method)?;
            for _ in 0..self.plan.warmup {
                if self.cancelled() {
                    return Ok(ControlFlow::Break(()));
                }
                self.clock(0.0);
                self.renderer.render(&self.view(0.0, &c))?;
                self.step(&label(&c, "warm-up"));
            }
        }
        Ok(ControlFlow::Continue(()))
    }

    /// The timed frames, a row of `frames.csv` each. Frame by frame, every
    /// configuration in turn: whatever else slows the device down (other
    /// processes on a CPU device, clocks on a GPU) then falls on every
    /// configuration alike.
    fn time_frames(
        &mut self,
        keys: &[String],
        frames_csv: &mut CsvLog,
    ) -> anyhow::Result<ControlFlow<()>> {
        let frames = self.plan.frames;
        for i in 0..frames {
            let t = self.path.t(i, frames);
            for ci in 0..self.m.configs.len() {
                if self.cancelled() {
                    return Ok(ControlFlow::Break(()));
                }
                let c = self.m.configs[ci].clone();
                self.renderer.set_method(&c.method)?;
                self.clock(t);
                let report = self.renderer.render(&self.view(t, &c))?;
                self.m.configs[ci].draw_path = report.draw_path.to_string();
                let row = FrameRow {
                    config: ci,
                    frame: i,
                    t,
                    values: flatten(&report, &self.renderer.memory()),
                };
                frames_csv.append(&frame_cells(&self.m.configs[ci], &row, keys))?;
                self.m.rows.push(row);
                self.step(&label(&c, &format!("frame {}/{}", i + 1, frames)));
            }
        }
        Ok(ControlFlow::Continue(()))
    }

    /// Per FLIP perspective, the ground truth and then every configuration
    /// compared with it: `flip.csv`, `breakdown.csv` and the images.
    fn compare_perspectives(
        &mut self,
        geo: &SceneGeometry,
        setup: &Setup,
        flip_csv: CsvLog,
    ) -> anyhow::Result<()> {
        let mut logs = FlipLogs {
            flip: flip_csv,
            breakdown: CsvLog::create(
                &self.args.out.join("breakdown.csv"),
                &BREAKDOWN_COLUMNS.map(String::from),
            )?,
            model_names: geo.models.iter().map(|m| m.name.clone()).collect(),
        };
        for (k, &t) in setup.flip_t.iter().enumerate() {
            if self.cancelled() {
                return Ok(());
            }
            let p = self.ground_truth(geo, k + 1, t)?;
            for ci in 0..self.m.configs.len() {
                if self.cancelled() {
                    return Ok(());
                }
                self.compare(&p, ci, &mut logs)?;
            }
        }
        Ok(())
    }

    /// The ground truth at perspective `number` (path position `t`), its
    /// image written. The reference does not depend on ε or λ: one per
    /// perspective.
    fn ground_truth(
        &mut self,
        geo: &SceneGeometry,
        number: usize,
        t: f64,
    ) -> anyhow::Result<Perspective> {
        let model_of = |patch: u32| {
            geo.flags
                .get(patch as usize)
                .map(|f| (f >> PATCH_MODEL_SHIFT) as usize)
        };
        self.clock(t);
        let cam = self.path.camera(t);
        let far = cam.far as f32;
        let view = self.view(t, &self.m.configs[0]);
        let truth = ground_truth_image(self.renderer, &view)?;
        let view = self.view(t, &self.m.configs[0]);
        let reference = ground_truth_reference(self.renderer, &view, far, cam.fov_y_deg, model_of)?;
        let (w, h) = self.args.size;
        write_png(
            &self
                .args
                .out
                .join(format!("flip/ground-truth-p{number}.png")),
            w,
            h,
            &truth,
        )?;
        self.step(&format!("ground truth, perspective {number}"));
        Ok(Perspective {
            number,
            t,
            far,
            truth,
            reference,
        })
    }

    /// Configuration `ci` at perspective `p`: its image, FLIP heat map and
    /// per-model breakdown, written and logged.
    fn compare(&mut self, p: &Perspective, ci: usize, logs: &mut FlipLogs) -> anyhow::Result<()> {
        let (w, h) = self.args.size;
        let (t, k1) = (p.t, p.number);
        let c = self.m.configs[ci].clone();
        self.renderer.set_method(&c.method)?;
        let report = self.renderer.render(&self.view(t, &c))?;
        let img = self.renderer.read_image()?;
        let f =
            flip(&p.truth, &img, w, h).ok_or_else(|| anyhow!("FLIP: images of different sizes"))?;
        let distance = distance_image(self.renderer, &self.view(t, &c), p.far)?;
        let wedges = if report.stats.get_u64("wedge_triangles").is_some() {
            Some(wedge_image(self.renderer, &self.view(t, &c))?)
        } else {
            None
        };
        let breakdown = geometry::breakdown(&p.reference, &distance, wedges.as_deref(), &f.errors);
        let image = format!("flip/{}-p{k1}.png", c.stem());
        let heat_map = format!("flip/{}-p{k1}-flip.png", c.stem());
        write_png(&self.args.out.join(&image), w, h, &img)?;
        f.save_heat_map(&self.args.out.join(&heat_map))?;
        let row = FlipRow {
            config: ci,
            perspective: k1,
            t,
            mean: f.mean,
            triangles: report.triangles(),
            image,
            heat_map,
            breakdown,
        };
        logs.flip.append(&flip_cells(&self.m.configs[ci], &row))?;
        for cells in breakdown_rows(&self.m.configs[ci], &row, &logs.model_names) {
            logs.breakdown.append(&cells)?;
        }
        self.m.flips.push(row);
        self.step(&label(&c, &format!("FLIP perspective {k1}")));
        Ok(())
    }
}

/// A progress message about configuration `c`.
fn label(c: &Config, what: &str) -> String {
    format!("{} ({what})", c.label())
}
