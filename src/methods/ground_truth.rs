//! Method `ground-truth`: every patch drawn as a dense uniform grid, the
//! reference other methods' images are compared with (the paper's ground
//! truth is hardware tessellation with factor 64 everywhere; this is the
//! same 64×64 grid of quads per patch by default, without tessellation
//! hardware, so it runs on every device).
//!
//! One compute pass (`glsl/grid_cull.comp`) drops patches whose control
//! points lie wholly outside the view frustum (they could not draw a pixel)
//! and appends the others to a visible list, counting them straight into
//! the instance count of an indexed indirect draw. The draw instances one
//! index buffer of the `grid`×`grid` topology over the visible patches; the
//! vertex shader (`glsl/grid.vert`) evaluates the base patch at
//! `(i / grid, j / grid)` with the shared precise evaluation. Grids are
//! powers of two, so those parameters are exact and shared patch edges meet
//! bit for bit: the reference is watertight too. Rational patches are
//! evaluated in homogeneous coordinates and projected (`glsl/grid.vert`),
//! and shaded with their own normal (`glsl/grid.frag`); the frustum test
//! on the control points' box holds for them too (positive weights keep a
//! rational patch inside its control points' hull).
//!
//! Cost: 2·grid² triangles per visible patch (8,192 at 64). On lavapipe a
//! 1920×1080 kitchen frame (~32,000 visible patches, 2.6·10⁸ triangles)
//! takes a while; `--grid 16` gives a coarser reference quickly.
//!
//! PN triangles ([`pn`]) are drawn in the same pass as uniform triangular
//! grids of the same size (grid² triangles each), not culled.

pub mod pn;

use ash::vk;
use serde_json::json;

use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, RenderError};
use crate::constants::*;
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::{DrawPush, GridPush};
use crate::vk::{
    buffer_barrier, fill_buffer, memory_barrier, Access, Buffer, Context, DescriptorSet,
    MemoryLocation, Pipeline, PipelineLayout, SetLayout, VkError, VkResult,
};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "ground-truth",
    about: "every patch as a uniform grid (64x64 quads by default, the paper's reference)",
    rational: true,
    reads_lambda: false,
    build: |setup| Ok(Box::new(GroundTruth::new(setup)?)),
};

/// Grid cells per patch side unless told otherwise: the paper's
/// tessellation factor 64.
pub const DEFAULT_GRID: u32 = 64;
/// Largest grid accepted (6·grid² indices per patch).
pub const MAX_GRID: u32 = 256;

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

/// The ground-truth method.
pub struct GroundTruth {
    grid: u32,
    indices: Buffer,
    counters: Buffer,
    visible: Option<Visible>,
    set_layout: SetLayout,
    cull_layout: PipelineLayout,
    draw_layout: PipelineLayout,
    cull: Pipeline,
    draw: Pipeline,
    pn: pn::GroundTruthPn,
    copied: Option<CopyRange>,
}

impl GroundTruth {
    /// Creates the pipelines and the index buffer for the options' grid.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        let grid = setup.options.grid;
        check_grid(grid).map_err(RenderError::Request)?;
        let scene = setup.scene_layout;
        let set_layout = SetLayout::storage(
            ctx,
            "grid set",
            GRID_BINDINGS as usize,
            vk::ShaderStageFlags::COMPUTE | vk::ShaderStageFlags::VERTEX,
        )?;
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
        let cull = setup
            .shaders
            .compute(ctx, &cull_layout, "grid cull", "grid_cull.comp")?;
        let draw = setup.shaders.draw_pipeline(
            ctx,
            &draw_layout,
            "draw (grid)",
            &[
                (vk::ShaderStageFlags::VERTEX, "grid.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "grid.frag"),
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

    /// Records the counters' reset (index count of the indirect draw set,
    /// the rest zero) and the culling pass.
    fn record_cull(&self, f: &mut FrameRec<'_>, visible: &Visible) -> VkResult<()> {
        let (ctx, cmd) = (f.ctx, f.cmd);
        let per_patch = 6 * self.grid * self.grid;
        fill_buffer(ctx, cmd, &self.counters, 0);
        unsafe {
            ctx.device().cmd_update_buffer(
                cmd,
                self.counters.handle(),
                u64::from(G_DRAW_ARGS) * 4,
                &per_patch.to_le_bytes(),
            );
        }
        buffer_barrier(
            ctx,
            cmd,
            &self.counters,
            Access::TRANSFER_WRITE,
            Access::ALL,
        );
        let bind = vk::PipelineBindPoint::COMPUTE;
        self.cull.bind(cmd);
        f.bind_scene(bind, &self.cull_layout);
        visible
            .set
            .bind(ctx, cmd, bind, &self.cull_layout, SET_PASS, &[]);
        let pc = GridPush {
            patch_count: f.scene.count,
            indices_per_patch: per_patch,
            pad: [0; 2],
        };
        self.cull_layout.push_block(cmd, &pc)?;
        let groups = f.scene.count.div_ceil(GRID_CULL_GROUP_SIZE);
        f.scoped("cull", |f| {
            unsafe { f.ctx.device().cmd_dispatch(f.cmd, groups, 1, 1) };
            Ok(())
        })?;
        memory_barrier(
            ctx,
            cmd,
            Access::COMPUTE_WRITE,
            Access::new(
                vk::PipelineStageFlags2::DRAW_INDIRECT | vk::PipelineStageFlags2::VERTEX_SHADER,
                vk::AccessFlags2::INDIRECT_COMMAND_READ | vk::AccessFlags2::SHADER_STORAGE_READ,
            ),
        );
        Ok(())
    }

    /// Records the instanced indexed draw of the visible patches.
    fn record_draw(&self, f: &mut FrameRec<'_>, visible: &Visible) -> VkResult<()> {
        let pc = f.view.draw_push(visible.capacity, false, self.grid);
        f.scoped("draw", |f| {
            let (ctx, cmd) = (f.ctx, f.cmd);
            f.target.begin(ctx, cmd);
            let bind = vk::PipelineBindPoint::GRAPHICS;
            self.draw.bind(cmd);
            f.bind_scene(bind, &self.draw_layout);
            visible
                .set
                .bind(ctx, cmd, bind, &self.draw_layout, SET_PASS, &[]);
            let pushed = self.draw_layout.push_block(cmd, &pc);
            if pushed.is_ok() {
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
                        u64::from(G_DRAW_ARGS) * 4,
                        1,
                        20,
                    );
                }
            }
            let pushed = pushed.and_then(|_| self.pn.record(f, &pc));
            f.target.end(ctx, cmd);
            pushed
        })
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
        self.record_cull(f, visible)?;
        self.pn.prepare(f)?;
        self.record_draw(f, visible)?;
        self.copied = Some(f.copy_out(&self.counters, GRID_WORDS)?);
        Ok(())
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let grid = setup.options.grid;
        if grid != self.grid {
            check_grid(grid).map_err(RenderError::Request)?;
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
        let visible = u64::from(words[(G_DRAW_ARGS + 1) as usize]);
        let culled = u64::from(words[G_CULLED as usize]);
        let per_patch = 2 * u64::from(self.grid) * u64::from(self.grid);
        Ok(Finished::Done(MethodStats {
            triangles: visible * per_patch + self.pn.triangles(),
            culled_patches: culled,
            own: vec![
                ("grid", json!(self.grid)),
                ("visible_patches", json!(visible)),
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
}
