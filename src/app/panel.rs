//! The overlay's content: the live controls (method, draw path, ε, λ,
//! l_max, culling, view, anti-aliasing, the ground truth's grid) and the
//! live statistics of the frames the GPU finished.

use crate::commands::render::Shade;
use crate::draw::DrawPath;
use crate::methods::{self, METHODS};
use crate::palette;
use crate::renderer::FrameReport;

/// What the user asked for with a button or key this frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Action {
    /// Save the image and its stats (F12).
    Screenshot,
    /// Compute FLIP of this view against the ground truth.
    Flip,
    /// Back to the scene camera (R).
    ResetCamera,
    /// Play or pause the camera path (P).
    TogglePath,
    /// Play or pause the scene's animation (Space).
    ToggleAnimation,
    /// Close the FLIP window.
    CloseFlip,
}

/// The settings the user changes live.
#[derive(Clone, Debug, PartialEq)]
pub struct Controls {
    /// Registry name of the method.
    pub method: String,
    /// Draw path of the ready-list methods.
    pub draw: DrawPath,
    /// Pixel tolerance ε.
    pub eps: f64,
    /// Blend λ.
    pub lambda: f64,
    /// Deepest subdivision level.
    pub l_max: u32,
    /// How a node splits.
    pub split: crate::patch::view::Split,
    /// Frustum culling on.
    pub frustum: bool,
    /// Back-face culling on.
    pub backface: bool,
    /// Crack-closing wedges on.
    pub wedges: bool,
    /// Occlusion culling on (the level kernels' two phases).
    pub occlusion: bool,
    /// Displaced models drawn displaced; `None` when no model is.
    pub displacement: Option<bool>,
    /// Far instances drawn from levels of detail; `None` when the session
    /// was started without them (`--lod off`).
    pub levels: Option<bool>,
    /// How to shade.
    pub shade: Shade,
    /// Samples per pixel.
    pub msaa: u32,
    /// The ground truth's grid cells per side.
    pub grid: u32,
    /// The scene's animation, where it moves.
    pub anim: Option<AnimControls>,
}

/// Playing the scene's animation.
#[derive(Clone, Debug, PartialEq)]
pub struct AnimControls {
    /// Time runs.
    pub playing: bool,
    /// The time drawn, seconds.
    pub time: f64,
    /// Seconds of animation per second.
    pub speed: f64,
    /// Seconds of one pass.
    pub duration: f64,
    /// Frames per second (the frame number shown).
    pub fps: f64,
    /// Time wraps at the end.
    pub looping: bool,
}

impl AnimControls {
    /// Moves time on by `dt` seconds of wall clock where it plays.
    pub fn advance(&mut self, dt: f64) {
        if !self.playing {
            return;
        }
        let t = self.time + dt * self.speed;
        self.time = if self.looping {
            t.rem_euclid(self.duration)
        } else {
            t.clamp(0.0, self.duration)
        };
    }

    fn ui(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let label = if self.playing {
                "Pause (Space)"
            } else {
                "Play (Space)"
            };
            if ui.button(label).clicked() {
                self.playing = !self.playing;
            }
            ui.label(format!("frame {}", (self.time * self.fps).floor() as u64));
        });
        ui.add(
            egui::Slider::new(&mut self.time, 0.0..=self.duration)
                .text("time (s)")
                .max_decimals(3),
        );
        ui.add(
            egui::Slider::new(&mut self.speed, 0.0..=4.0)
                .text("speed")
                .max_decimals(2),
        );
    }
}

/// Figures of the finished frames, smoothed where they jitter.
#[derive(Clone, Debug, Default)]
pub struct LiveStats {
    /// GPU milliseconds per scope, exponentially smoothed, in the order
    /// the method timed them ("frame" first).
    pub gpu_ms: Vec<(String, f64)>,
    /// Host frame time, smoothed, in milliseconds.
    pub frame_ms: f64,
    /// The last finished frame's report.
    pub last: Option<FrameReport>,
    /// GPU memory in bytes, by purpose.
    pub memory: Vec<(&'static str, u64)>,
    /// Device name.
    pub device: String,
    /// The last thing worth telling the user (a refused setting, a saved
    /// file).
    pub notice: Option<String>,
    /// Host frame times still to leave out: the ones that waited for a
    /// frame whose times include a shader compile.
    pub(crate) skip_frame_times: u32,
}

impl LiveStats {
    /// Folds in a finished frame.
    pub fn add(&mut self, report: FrameReport) {
        if report.compiled {
            // Its times include the driver's compile (a CPU device compiles
            // in the frame): folded in, they took minutes to decay. The
            // smoothing starts again from the next frames.
            self.skip_frame_times = 2;
            self.frame_ms = 0.0;
            self.last = Some(report);
            return;
        }
        for (name, ms) in &report.gpu_ms {
            match self.gpu_ms.iter_mut().find(|(n, _)| n == name) {
                Some((_, e)) => *e += 0.1 * (ms - *e),
                None => self.gpu_ms.push((name.clone(), *ms)),
            }
        }
        self.last = Some(report);
    }

    /// Folds in the host's time for one frame.
    pub fn add_frame_time(&mut self, ms: f64) {
        if self.skip_frame_times > 0 {
            self.skip_frame_times -= 1;
            return;
        }
        if self.frame_ms == 0.0 {
            self.frame_ms = ms;
        }
        self.frame_ms += 0.1 * (ms - self.frame_ms);
    }
}

/// What the device offers the controls.
#[derive(Clone, Debug)]
pub struct DeviceOffer {
    /// Mesh shaders (the mesh draw path).
    pub mesh: bool,
    /// Sample counts of 1, 2, 4, 8 the device can render with.
    pub samples: Vec<u32>,
}

/// The result of the last FLIP request, shown in its own window.
pub struct FlipView {
    /// Mean FLIP against the ground truth.
    pub mean: f64,
    /// The heat map, uploaded.
    pub texture: egui::TextureHandle,
    /// Where the heat map was written.
    pub file: String,
    /// Its colour scale, error 0 to 1.
    pub legend: egui::TextureHandle,
}

const SHADES: [(Shade, &str); 8] = [
    (Shade::Normal, "shaded"),
    (Shade::Wireframe, "wireframe"),
    (Shade::Depth, "depth heat map"),
    (Shade::Wedges, "wedges"),
    (Shade::Normals, "normals"),
    (Shade::Uv, "texture coordinates"),
    (Shade::Texture, "albedo (texture)"),
    (Shade::Displacement, "displacement height"),
];

impl Controls {
    /// Lays out the panel; returns the buttons pressed.
    pub fn ui(
        &mut self,
        ctx: &egui::Context,
        stats: &LiveStats,
        flip: Option<&FlipView>,
        device: &DeviceOffer,
    ) -> Vec<Action> {
        let mut actions = Vec::new();
        // Scrolls rather than running off a small window.
        let height = ctx.content_rect().height() - 24.0;
        egui::Window::new("bezier-subdiv")
            .default_pos([12.0, 12.0])
            .auto_sized()
            .show(ctx, |ui| {
                egui::ScrollArea::vertical()
                    .max_height((height - 40.0).max(80.0))
                    .show(ui, |ui| {
                        actions.extend(self.panel_ui(ui, stats, device));
                    });
            });
        if let Some(f) = flip {
            let mut open = true;
            egui::Window::new("FLIP against the ground truth")
                .default_pos([372.0, 12.0])
                .open(&mut open)
                .show(ctx, |ui| {
                    ui.label(format!("mean {:.5}  ({})", f.mean, f.file));
                    let size = f.texture.size_vec2();
                    let scale = (480.0 / size.x).min(1.0);
                    ui.image((f.texture.id(), size * scale));
                    ui.horizontal(|ui| {
                        ui.label("FLIP error 0");
                        ui.image((f.legend.id(), egui::vec2(256.0, 12.0)));
                        ui.label("1");
                    });
                });
            if !open {
                actions.push(Action::CloseFlip);
            }
        }
        actions
    }

    /// The panel's content; returns the buttons pressed.
    fn panel_ui(
        &mut self,
        ui: &mut egui::Ui,
        stats: &LiveStats,
        device: &DeviceOffer,
    ) -> Vec<Action> {
        let mut actions = Vec::new();
        // Auto-sized: the wrapped rows would otherwise take the screen.
        ui.set_max_width(330.0);
        self.method_ui(ui, device.mesh);
        ui.separator();
        self.criterion_ui(ui);
        ui.separator();
        self.view_ui(ui, &device.samples);
        legend_ui(ui, self.shade, &self.method);
        ui.separator();
        if let Some(a) = &mut self.anim {
            a.ui(ui);
            ui.separator();
        }
        ui.horizontal(|ui| {
            if ui.button("Screenshot (F12)").clicked() {
                actions.push(Action::Screenshot);
            }
            if ui.button("FLIP vs ground truth").clicked() {
                actions.push(Action::Flip);
            }
        });
        ui.horizontal(|ui| {
            if ui.button("Reset camera (R)").clicked() {
                actions.push(Action::ResetCamera);
            }
            if ui.button("Play/pause path (P)").clicked() {
                actions.push(Action::TogglePath);
            }
        });
        ui.separator();
        egui::CollapsingHeader::new("statistics")
            .default_open(true)
            .show(ui, |ui| stats_ui(ui, stats));
        actions
    }

    fn method_ui(&mut self, ui: &mut egui::Ui, has_mesh: bool) {
        egui::ComboBox::from_label("method")
            .selected_text(self.method.clone())
            .show_ui(ui, |ui| {
                for m in METHODS {
                    ui.selectable_value(&mut self.method, m.name.to_string(), m.name)
                        .on_hover_text(m.about);
                }
            });
        let reads = methods::reads(&self.method);
        ui.add_enabled_ui(reads.draw_path, |ui| {
            ui.horizontal(|ui| {
                ui.label("draw path");
                ui.add_enabled_ui(has_mesh, |ui| {
                    ui.radio_value(&mut self.draw, DrawPath::Mesh, "mesh");
                });
                ui.radio_value(&mut self.draw, DrawPath::Fallback, "fallback");
            })
        })
        .response
        .on_disabled_hover_text(format!("{} draws itself", self.method));
        if reads.grid {
            let mut exp = self.grid.max(1).ilog2();
            ui.add(egui::Slider::new(&mut exp, 0..=6).text("grid (log2)"));
            self.grid = 1 << exp;
        }
    }

    /// The criterion and culling; a control the method does not read is
    /// greyed out (`methods::reads`).
    fn criterion_ui(&mut self, ui: &mut egui::Ui) {
        let reads = methods::reads(&self.method);
        let ignored = format!("{} does not read this", self.method);
        ui.add_enabled(
            reads.eps,
            egui::Slider::new(&mut self.eps, 0.1..=16.0)
                .logarithmic(true)
                .text("ε (pixels)"),
        )
        .on_disabled_hover_text(&ignored);
        ui.add_enabled(
            reads.lambda,
            egui::Slider::new(&mut self.lambda, 0.0..=1.0).text("λ"),
        )
        .on_disabled_hover_text(&ignored);
        ui.add_enabled(
            reads.l_max,
            egui::Slider::new(&mut self.l_max, 1..=crate::constants::L_MAX).text("l_max"),
        )
        .on_disabled_hover_text(&ignored);
        let mut aniso = self.split == crate::patch::view::Split::Aniso;
        ui.add_enabled(
            reads.split,
            egui::Checkbox::new(&mut aniso, "aniso: 1:2 splits where one direction suffices"),
        )
        .on_disabled_hover_text(&ignored);
        self.split = if aniso {
            crate::patch::view::Split::Aniso
        } else {
            crate::patch::view::Split::Iso
        };
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.frustum, "frustum cull");
            ui.add_enabled(
                reads.backface,
                egui::Checkbox::new(&mut self.backface, "back-face cull"),
            )
            .on_disabled_hover_text(&ignored);
            ui.add_enabled(
                reads.wedges,
                egui::Checkbox::new(&mut self.wedges, "wedges"),
            )
            .on_disabled_hover_text(&ignored);
            ui.add_enabled(
                reads.occlusion,
                egui::Checkbox::new(&mut self.occlusion, "occlusion cull"),
            )
            .on_hover_text(
                "draw what the last frame saw, build a depth pyramid, skip what it hides \
                 (the same image)",
            )
            .on_disabled_hover_text(&ignored);
        });
        if let Some(on) = self.levels.as_mut() {
            ui.checkbox(on, "levels of detail: far instances from simplified meshes")
                .on_hover_text(
                    "the coarsest level within ε (and the shading bound) at each instance's \
                     distance; off: every instance from its patches",
                );
        }
        if let Some(on) = self.displacement.as_mut() {
            ui.add_enabled(
                reads.displacement,
                egui::Checkbox::new(on, "displacement: height maps move the surfaces"),
            )
            .on_hover_text("off: the displaced models as their base surfaces")
            .on_disabled_hover_text(&ignored);
        }
    }

    /// The view and the sample counts the device offers.
    fn view_ui(&mut self, ui: &mut egui::Ui, samples: &[u32]) {
        ui.horizontal_wrapped(|ui| {
            for (shade, name) in SHADES {
                ui.radio_value(&mut self.shade, shade, name);
            }
        });
        ui.horizontal(|ui| {
            ui.label("MSAA");
            for &n in samples {
                ui.radio_value(&mut self.msaa, n, format!("{n}x"));
            }
        })
        .response
        .on_hover_text("the sample counts this device renders with (`info` lists them)");
    }
}

/// What the heat map's colours of `method` mean (its registry entry's
/// `heat_map`), what the wedges' colour marks (its `seams`), or the
/// normal's axes.
fn legend_ui(ui: &mut egui::Ui, shade: Shade, method: &str) {
    let info = methods::find(method).ok();
    let what = info.map_or("subdivision depth", |m| m.heat_map);
    match shade {
        Shade::Depth | Shade::Wedges => {
            ui.label(format!("colour: {what}"));
            ramp_ui(ui);
            if shade == Shade::Wedges {
                let label = info.map_or("wedges", |m| m.seams);
                ui.horizontal(|ui| {
                    swatch(ui, palette::wedge_color());
                    ui.label(label);
                });
            }
        }
        Shade::Normals => {
            ui.label("colour: the shading normal, x → red, y → green, z → blue (world axes)");
        }
        Shade::Wireframe => {
            ui.label("lines: the outline of every drawn cell");
        }
        Shade::Uv => {
            ui.label("colour: s → red, t → green (repeating), eighths as a checker in blue; a model without UVs shows each patch's (u, v)");
        }
        Shade::Texture => {
            ui.label("colour: each model's albedo map, unlit (its tint where it has none)");
        }
        Shade::Displacement => {
            ui.label("colour: the displaced models' map height, dark blue 0 → yellow 1 (the surface moves bias + scale·height along its normal); grey: not displaced");
        }
        Shade::Normal => {}
    }
}

/// The depth ramp as swatches 0..10 with their numbers.
fn ramp_ui(ui: &mut egui::Ui) {
    ui.horizontal(|ui| {
        ui.spacing_mut().item_spacing.x = 1.0;
        for d in 0..=crate::constants::L_MAX {
            ui.vertical(|ui| {
                swatch(ui, palette::depth_color(d));
                ui.label(egui::RichText::new(d.to_string()).small());
            });
        }
    });
}

fn swatch(ui: &mut egui::Ui, rgb: [u8; 3]) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(22.0, 14.0), egui::Sense::hover());
    ui.painter()
        .rect_filled(rect, 2.0, egui::Color32::from_rgb(rgb[0], rgb[1], rgb[2]));
}

fn stats_ui(ui: &mut egui::Ui, stats: &LiveStats) {
    ui.label(format!(
        "{}  ·  {:.1} ms/frame ({:.0} fps)",
        stats.device,
        stats.frame_ms,
        1000.0 / stats.frame_ms.max(1e-3)
    ));
    egui::Grid::new("gpu").num_columns(2).show(ui, |ui| {
        for (name, ms) in &stats.gpu_ms {
            ui.label(name);
            ui.label(format!("{ms:.3} ms"));
            ui.end_row();
        }
    });
    if let Some(n) = &stats.notice {
        ui.label(n);
    }
    let Some(r) = &stats.last else {
        return;
    };
    let s = &r.stats;
    ui.label(format!(
        "{} ({} path): {} triangles",
        r.method,
        r.draw_path,
        crate::figures::thousands(r.triangles())
    ));
    if let Some(w) = s.get_u64("wedge_triangles") {
        ui.label(format!(
            "wedges {:.1} %, ready quads {}",
            100.0 * w as f64 / s.triangles.max(1) as f64,
            crate::figures::thousands(s.get_u64("ready_quads").unwrap_or(0))
        ));
    }
    if let Some(peak) = s.get_u64("queue_peak_items") {
        ui.label(format!(
            "queue peak {}, spills {}",
            crate::figures::thousands(peak),
            s.get_u64("queue_spills").unwrap_or(0)
        ));
    }
    let total: u64 = stats.memory.iter().map(|(_, b)| b).sum();
    // In its unit: the teapot with tess holds 15 KiB, which read 0.0 MiB.
    ui.label(format!("GPU memory {}", crate::figures::bytes_text(total)))
        .on_hover_text(
            stats
                .memory
                .iter()
                .map(|(k, b)| format!("{k}: {:.2} MiB", *b as f64 / (1 << 20) as f64))
                .collect::<Vec<_>>()
                .join("\n"),
        );
}
