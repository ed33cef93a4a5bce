//! Method `ground-truth`: every patch drawn as a dense uniform grid, the
//! reference other methods' images are compared with (the paper's ground
//! truth is hardware tessellation with factor 64 everywhere; this is the
//! same 64×64 grid of quads per patch by default, without tessellation
//! hardware, so it runs on every device).
//!
//! One compute pass (`glsl/ground_truth/cull.comp`) drops patches whose control
//! points lie wholly outside the view frustum (they could not draw a pixel)
//! and lists the others in patch order (one workgroup per part of the
//! frame, so the image does not depend on which invocation ran first where
//! surfaces tie in depth), their count the instance count of an indexed
//! indirect draw. The draw instances one
//! index buffer of the `grid`×`grid` topology over the visible patches; the
//! vertex shader (`glsl/ground_truth/grid.vert`) evaluates the base patch at
//! `(i / grid, j / grid)` with the shared precise evaluation. Grids are
//! powers of two, so those parameters are exact and shared patch edges meet
//! bit for bit: the reference is watertight too. Rational patches are
//! evaluated in homogeneous coordinates and projected (`glsl/ground_truth/grid.vert`),
//! and shaded with their own normal (`glsl/ground_truth/grid.frag`); the frustum test
//! on the control points' box holds for them too (positive weights keep a
//! rational patch inside its control points' hull).
//!
//! Cost: 2·grid² triangles per visible patch (8,192 at 64). On lavapipe a
//! 1920×1080 kitchen frame (~32,000 visible patches, 2.6·10⁸ triangles)
//! takes a while; `--grid 16` gives a coarser reference quickly.
//!
//! In parts: the draws of a frame are split ([`plan_parts`],
//! `FrameRec::split`) into submissions of at most [`PART_TRIANGLES`]
//! triangles each, so no single fence wait comes near the timeout on a
//! slow device (the kitchen at grid 64 is 18 parts of 2,048 patches), and a
//! terminal shows the parts finish. The culling pass runs once, in the
//! first part, and sorts each visible patch into its part's list and
//! draw arguments (part k draws the visible patches among base patches
//! k·P .. (k+1)·P).
//!
//! PN triangles ([`pn`]) are drawn in the same pass as uniform triangular
//! grids of the same size (grid² triangles each), not culled.

pub mod constants;
pub mod pn;
pub mod push;

use ash::vk;
use serde_json::json;

use self::constants::*;
use self::push::GridPush;
use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, Reads, RenderError, Role};
use crate::constants::*;
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::blocks::block;
use crate::gpu::DrawPush;
use crate::vk::{
    Access, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline, PipelineLayout,
    Recorder, Res, SetLayout, VkError, VkResult,
};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "ground-truth",
    about: "every patch as a uniform grid (64x64 quads by default, the paper's reference)",
    rational: true,
    pn: true,
    // A fixed grid per patch, nothing back-face culled.
    reads: Reads {
        eps: false,
        backface: false,
        grid: true,
        ..Reads::TESSELLATES
    },
    role: Role::Reference,
    targets: &[],
    heat_map: "log2 of the grid",
    seams: "wedges (none for this method)",
    checks: None,
    blocks: &[block::<push::GridPush>],
    build: |setup| Ok(Box::new(GroundTruth::new(setup)?)),
};

/// Grid cells per patch side unless told otherwise: the paper's
/// tessellation factor 64.
pub const DEFAULT_GRID: u32 = 64;
/// Largest grid accepted (6·grid² indices per patch).
pub const MAX_GRID: u32 = 256;

/// Triangles one part of a frame draws at most (unless the scene needs
/// more than [`G_MAX_PARTS`] such parts): 2^24, about 2 s on this
/// project's 2-core lavapipe when idle and 8 s when busy, far inside the
/// default 60 s fence timeout.
pub const PART_TRIANGLES: u64 = 1 << 24;

const _: () = assert!(G_MAX_PARTS == crate::vk::MAX_FRAME_PARTS);
const _: () = assert!(GRID_WORDS >= G_DRAW_ARGS + G_ARGS_WORDS * G_MAX_PARTS);

/// How a frame's draws are split into parts: base patches in runs of
/// `patches_per_part` (`patch_parts` parts), then PN triangles in runs of
/// `pn_per_part` (`pn_parts` parts).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PartPlan {
    /// Base patches per part.
    pub patches_per_part: u32,
    /// Parts drawing base patches.
    pub patch_parts: u32,
    /// PN triangles per part.
    pub pn_per_part: u32,
    /// Parts drawing PN triangles.
    pub pn_parts: u32,
}

impl PartPlan {
    /// Parts in all (at least 1: the first clears the target).
    pub fn parts(&self) -> u32 {
        (self.patch_parts + self.pn_parts).max(1)
    }
}

/// Splits `patches` base patches (2·grid² triangles each) and
/// `pn_triangles` PN triangles (grid² each) into parts of at most
/// `part_triangles` triangles ([`PART_TRIANGLES`] by default), or into
/// `max_parts` parts of more where that would take more.
pub fn plan_parts(
    patches: u32,
    pn_triangles: u32,
    grid: u32,
    part_triangles: u64,
    max_parts: u32,
) -> PartPlan {
    let cells = u64::from(grid) * u64::from(grid);
    let total = u64::from(patches) * 2 * cells + u64::from(pn_triangles) * cells;
    // Room for one more part per kind than an even split needs (the runs
    // are whole).
    let least = total.div_ceil(u64::from(max_parts.saturating_sub(2).max(1)));
    let budget = part_triangles.max(least).max(1);
    let run = |count: u32, per: u64| -> (u32, u32) {
        if count == 0 {
            return (1, 0);
        }
        let n = (budget / per).clamp(1, u64::from(count)) as u32;
        (n, count.div_ceil(n))
    };
    let (patches_per_part, patch_parts) = run(patches, 2 * cells);
    let (pn_per_part, pn_parts) = run(pn_triangles, cells);
    PartPlan {
        patches_per_part,
        patch_parts,
        pn_per_part,
        pn_parts,
    }
}

/// Checks a grid size: a power of two in 1..=[`MAX_GRID`].
pub fn check_grid(grid: u32) -> Result<(), String> {
    if grid.is_power_of_two() && grid <= MAX_GRID {
        Ok(())
    } else {
        Err(format!(
            "the ground-truth grid must be a power of two from 1 to {MAX_GRID} (got {grid}): \
             only then are the sample parameters exact and shared edges meet"
        ))
    }
}

/// `ground-truth`'s knobs ([`super::PerMethod::ground_truth`]) and its
/// flags, under their own heading in `--help`.
#[derive(Clone, Debug, PartialEq, Eq, clap::Args)]
#[command(next_help_heading = "ground-truth")]
pub struct Options {
    /// ground-truth: grid cells per patch side, a power of two up to 256
    /// (64, the paper's tessellation factor, costs 8,192 triangles per
    /// patch; lower it for quick references on a CPU device).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_GRID)]
    pub grid: u32,
    /// The most triangles one part of a frame (one submission, one bounded
    /// fence wait) draws; see [`plan_parts`]. Tests lower it; no flag.
    #[arg(skip = PART_TRIANGLES)]
    pub part_triangles: u64,
}

impl Default for Options {
    fn default() -> Self {
        super::cli_defaults()
    }
}

impl Options {
    /// Refuses a grid [`check_grid`] refuses, naming the flag.
    pub fn check(&self) -> Result<(), String> {
        check_grid(self.grid).map_err(|e| format!("--grid: {e}"))
    }
}

/// The indices of a `grid`×`grid` lattice of quads over (grid+1)² vertices
/// (vertex `j·(grid+1) + i` at (i, j)), two triangles per cell wound like
/// the subdivision's quads: (00, 10, 11), (00, 11, 01).
pub fn grid_indices(grid: u32) -> Vec<u32> {
    let row = grid + 1;
    let mut out = Vec::with_capacity((6 * grid * grid) as usize);
    for j in 0..grid {
        for i in 0..grid {
            let v = |di: u32, dj: u32| (j + dj) * row + i + di;
            out.extend([v(0, 0), v(1, 0), v(1, 1), v(0, 0), v(1, 1), v(0, 1)]);
        }
    }
    out
}

/// The index buffer of [`grid_indices`].
fn grid_index_buffer(ctx: &Context, grid: u32) -> VkResult<Buffer> {
    Buffer::with_data(
        ctx,
        &format!("grid indices ({grid}x{grid})"),
        &grid_indices(grid),
        vk::BufferUsageFlags::INDEX_BUFFER,
        MemoryLocation::GpuOnly,
    )
}

/// Buffers sized by the scene: the visible list and its set.
struct Visible {
    list: Buffer,
    capacity: u32,
    set: DescriptorSet,
}

/// The grid's shaders, which share set 1.
pub const GRID_SHADERS: &[&str] = &[
    "ground_truth/cull.comp",
    "ground_truth/grid.vert",
    "ground_truth/grid.frag",
];

/// The ground-truth method.
pub struct GroundTruth {
    grid: u32,
    indices: Buffer,
    counters: Buffer,
    visible: Option<Visible>,
    set_layout: SetLayout,
    cull_layout: PipelineLayout<GridPush>,
    draw_layout: PipelineLayout<DrawPush>,
    cull: Pipeline,
    draw: Pipeline,
    pn: pn::GroundTruthPn,
    copied: Option<CopyRange>,
    /// How the last recorded frame was split.
    plan: Option<PartPlan>,
    part_triangles: u64,
}

impl GroundTruth {
    /// Creates the pipelines and the index buffer for the options' grid.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        // Checked with every knob where the renderer takes them.
        let grid = setup.options.per_method.ground_truth.grid;
        let scene = setup.scene_layout;
        let set_layout = SetLayout::reflect(ctx, "grid set", SET_PASS, GRID_SHADERS)?;
        let cull_layout = scene.pipeline_layout::<GridPush>(
            ctx,
            "grid cull layout",
            &[&set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let draw_layout = scene.pipeline_layout::<DrawPush>(
            ctx,
            "grid draw layout",
            &[&set_layout],
            scene.stages(),
        )?;
        let cull =
            setup
                .shaders
                .compute(ctx, &cull_layout, "grid cull", "ground_truth/cull.comp")?;
        let draw = setup.shaders.draw_pipeline(
            ctx,
            &draw_layout,
            "draw (grid)",
            &[
                (vk::ShaderStageFlags::VERTEX, "ground_truth/grid.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "ground_truth/grid.frag"),
            ],
        )?;
        let indices = grid_index_buffer(ctx, grid)?;
        let pn = pn::GroundTruthPn::new(setup, grid)?;
        let counters = Buffer::new(
            ctx,
            "grid counters",
            u64::from(GRID_WORDS) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        Ok(Self {
            grid,
            indices,
            counters,
            visible: None,
            set_layout,
            cull_layout,
            draw_layout,
            cull,
            draw,
            pn,
            copied: None,
            plan: None,
            part_triangles: setup.options.per_method.ground_truth.part_triangles,
        })
    }

    /// The visible list for `patches` patches, made (or remade larger) on
    /// demand; a replaced one is retired.
    fn ensure_visible(&mut self, f: &mut FrameRec<'_>) -> VkResult<()> {
        // A scene of PN triangles alone still binds a (one-entry) list.
        let need = f.scene.count.max(1);
        if self.visible.as_ref().is_some_and(|v| v.capacity >= need) {
            return Ok(());
        }
        let list = Buffer::new(
            f.ctx,
            "grid visible patches",
            u64::from(need) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let mut bound = [(&list).into(); GRID_BINDINGS as usize];
        bound[BIND_GRID_VISIBLE as usize] = (&list).into();
        bound[BIND_GRID_COUNTERS as usize] = (&self.counters).into();
        let set = DescriptorSet::new(f.ctx, "grid set", &self.set_layout, &bound)?;
        let new = Visible {
            list,
            capacity: need,
            set,
        };
        if let Some(old) = self.visible.replace(new) {
            f.retired.push(old);
        }
        Ok(())
    }

    /// Records the counters' reset (each part's draw arguments set, the
    /// instance counts zero) and the culling pass, which sorts the visible
    /// patches into their parts.
    fn record_cull(
        &self,
        f: &mut FrameRec<'_>,
        visible: &Visible,
        plan: &PartPlan,
    ) -> VkResult<()> {
        let (ctx, cmd) = (f.ctx, f.cmd);
        let per_patch = 6 * self.grid * self.grid;
        let args: Vec<u32> = (0..plan.patch_parts.max(1))
            .flat_map(|k| [per_patch, 0, 0, 0, k * plan.patches_per_part])
            .collect();
        let mut rec = Recorder::new(ctx, cmd);
        let counters = Res::Buffer(&self.counters);
        // The reset waits for every earlier use (the last frame's readback).
        rec.after(counters, Access::ALL);
        rec.fill("grid counters reset", &self.counters, 0);
        let update = Pass::new("draw arguments").write(counters, Access::TRANSFER_WRITE);
        rec.run(&update, |cmd| unsafe {
            ctx.device().cmd_update_buffer(
                cmd,
                self.counters.handle(),
                u64::from(G_DRAW_ARGS) * 4,
                bytemuck::cast_slice(&args),
            );
        });
        rec.hand_off(counters, Access::ALL);
        let pc = GridPush {
            patch_count: f.scene.count,
            indices_per_patch: per_patch,
            patches_per_part: plan.patches_per_part,
            pad: 0,
        };
        self.cull_layout.push(cmd, &pc);
        // One workgroup per part: each fills its part's list in patch order.
        let groups = plan.patch_parts.max(1);
        // The cull writes the draw's arguments and the visible list.
        let cull = Pass::new("cull")
            .pipeline(&self.cull)
            .bind(SET_PASS, &visible.set);
        let cull = f.with_scene(cull);
        f.scoped("cull", |_| {
            rec.dispatch(&cull, [groups, 1, 1]);
            Ok(())
        })?;
        let draw = Access::new(
            vk::PipelineStageFlags2::DRAW_INDIRECT | vk::PipelineStageFlags2::VERTEX_SHADER,
            vk::AccessFlags2::INDIRECT_COMMAND_READ | vk::AccessFlags2::SHADER_STORAGE_READ,
        );
        rec.hand_off(counters, draw);
        rec.hand_off(Res::Buffer(&visible.list), draw);
        Ok(())
    }

    /// Records part `k` of the frame's draws (of `plan.parts()`): base
    /// patches through part k's indirect arguments, or a run of PN
    /// triangles.
    fn record_draw(
        &self,
        f: &mut FrameRec<'_>,
        visible: &Visible,
        plan: &PartPlan,
        k: u32,
    ) -> VkResult<()> {
        let pc = f.view.draw_push(visible.capacity, false, self.grid);
        let (first, last) = (k == 0, k + 1 == plan.parts());
        f.scoped("draw", |f| {
            let (ctx, cmd) = (f.ctx, f.cmd);
            f.target.begin_part(ctx, cmd, first, last);
            let drawn = if k < plan.patch_parts {
                self.record_patch_part(f, visible, &pc, k)
            } else {
                let first_pn = (k - plan.patch_parts) * plan.pn_per_part;
                self.pn.record(f, &pc, first_pn, plan.pn_per_part)
            };
            f.target.end(ctx, cmd);
            drawn
        })
    }

    /// The instanced indexed draw of part `k`'s visible patches.
    fn record_patch_part(
        &self,
        f: &FrameRec<'_>,
        visible: &Visible,
        pc: &DrawPush,
        k: u32,
    ) -> VkResult<()> {
        let (ctx, cmd) = (f.ctx, f.cmd);
        let bind = vk::PipelineBindPoint::GRAPHICS;
        self.draw.bind(cmd);
        f.bind_scene(bind, &self.draw_layout);
        visible
            .set
            .bind(ctx, cmd, bind, &self.draw_layout, SET_PASS, &[]);
        self.draw_layout.push(cmd, pc);
        unsafe {
            ctx.device().cmd_bind_index_buffer(
                cmd,
                self.indices.handle(),
                0,
                vk::IndexType::UINT32,
            );
            ctx.device().cmd_draw_indexed_indirect(
                cmd,
                self.counters.handle(),
                u64::from(G_DRAW_ARGS + k * G_ARGS_WORDS) * 4,
                1,
                20,
            );
        }
        Ok(())
    }
}

impl Method for GroundTruth {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn draw_path(&self) -> &'static str {
        "grid"
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.ensure_visible(f)?;
        let visible = self
            .visible
            .as_ref()
            .ok_or_else(|| VkError::Usage("no visible list".into()))?;
        let plan = plan_parts(
            f.scene.count,
            f.scene.pn.count(),
            self.grid,
            self.part_triangles,
            f.max_parts(),
        );
        self.record_cull(f, visible, &plan)?;
        self.pn.prepare(f)?;
        for k in 0..plan.parts() {
            if k > 0 {
                f.split()?;
            }
            self.record_draw(f, visible, &plan, k)?;
        }
        self.plan = Some(plan);
        self.copied = Some(f.copy_out(&self.counters, GRID_WORDS)?);
        Ok(())
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let o = &setup.options.per_method.ground_truth;
        self.part_triangles = o.part_triangles;
        let grid = o.grid;
        if grid != self.grid {
            let indices = grid_index_buffer(setup.ctx, grid)?;
            retired.push(std::mem::replace(&mut self.indices, indices));
            if let Some(old) = self.pn.set_grid(setup.ctx, grid)? {
                retired.push(old);
            }
            self.grid = grid;
        }
        Ok(true)
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let range = self
            .copied
            .ok_or_else(|| RenderError::Request("finish() before any frame was recorded".into()))?;
        let words = out.words(range);
        let parts = self.plan.map_or(1, |p| p.patch_parts.max(1));
        let visible: u64 = (0..parts)
            .map(|k| u64::from(words[(G_DRAW_ARGS + k * G_ARGS_WORDS + 1) as usize]))
            .sum();
        let culled = u64::from(words[G_CULLED as usize]);
        let per_patch = 2 * u64::from(self.grid) * u64::from(self.grid);
        Ok(Finished::Done(MethodStats {
            triangles: visible * per_patch + self.pn.triangles(),
            placeholder_triangles: 0,
            culled_patches: culled,
            own: vec![
                ("grid", json!(self.grid)),
                ("visible_patches", json!(visible)),
                ("parts", json!(self.plan.map_or(1, |p| p.parts()))),
                ("pn_triangles", json!(self.pn.triangles())),
            ],
        }))
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![
            ("grid_indices", self.indices.size()),
            ("counters", self.counters.size()),
        ];
        if self.pn.triangles() > 0 {
            v.push(("pn", self.pn.memory()));
        }
        if let Some(vis) = &self.visible {
            v.push(("visible_list", vis.list.size()));
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_topology_winds_like_quads() {
        let idx = grid_indices(2);
        assert_eq!(idx.len(), 24);
        assert_eq!(&idx[..6], &[0, 1, 4, 0, 4, 3]);
        assert_eq!(*idx.iter().max().unwrap(), 8);
        assert!(check_grid(64).is_ok() && check_grid(1).is_ok());
        assert!(check_grid(48).is_err() && check_grid(0).is_err() && check_grid(512).is_err());
    }

    /// Parts hold at most PART_TRIANGLES each, cover every patch and PN
    /// triangle, and never exceed the ring's limit.
    #[test]
    fn parts_are_bounded_and_cover_everything() {
        let kitchen = plan_parts(35_940, 0, 64, PART_TRIANGLES, G_MAX_PARTS);
        assert_eq!(kitchen.patches_per_part, 2_048);
        assert_eq!((kitchen.patch_parts, kitchen.parts()), (18, 18));
        assert_eq!(
            plan_parts(35_940, 0, 16, PART_TRIANGLES, G_MAX_PARTS).parts(),
            2
        );
        assert_eq!(
            plan_parts(32, 0, 64, PART_TRIANGLES, G_MAX_PARTS).parts(),
            1
        );
        assert_eq!(plan_parts(0, 0, 64, PART_TRIANGLES, G_MAX_PARTS).parts(), 1);
        assert_eq!(
            plan_parts(35_940, 0, 64, PART_TRIANGLES, 1).parts(),
            1,
            "a one-shot recorder"
        );
        for (patches, pn, grid) in [
            (1_000_000, 0, 256),
            (100, 5_000, 64),
            (7, 3, 1),
            (0, 9_000, 128),
        ] {
            let p = plan_parts(patches, pn, grid, PART_TRIANGLES, G_MAX_PARTS);
            assert!(p.parts() <= G_MAX_PARTS, "{p:?}");
            assert!(p.patch_parts * p.patches_per_part >= patches, "{p:?}");
            assert!(p.pn_parts * p.pn_per_part >= pn, "{p:?}");
            let cells = u64::from(grid * grid);
            let biggest =
                (u64::from(p.patches_per_part) * 2 * cells).max(u64::from(p.pn_per_part) * cells);
            let even = (u64::from(patches) * 2 * cells + u64::from(pn) * cells).div_ceil(62);
            assert!(biggest <= PART_TRIANGLES.max(even), "{p:?}");
        }
    }
}
