//! Ground truth for PN triangles: every triangle as a uniform triangular
//! grid of the method's grid size (`grid`² triangles), drawn instanced
//! through `glsl/ground_truth/pn.vert` and cudatess's fragment stage (`cudatess/draw.frag`,
//! which lights PN triangles with their normal field). The nets are
//! converted on the host ([`PnScene::net`], the CPU twin of cudatess's
//! conversion) and bound in cudatess's set layout, so the shaders' view of
//! them (`glsl/common/pn.glsl`) is one for both methods.

use ash::vk;

use crate::constants::*;
use crate::frame::FrameRec;
use crate::gpu::DrawPush;
use crate::methods::cudatess::constants::*;
use crate::methods::cudatess::scan;
use crate::methods::{MethodSetup, RenderError};
use crate::scene::pn::PnScene;
use crate::vk::{
    Buffer, BufferBinding, Context, DescriptorSet, MemoryLocation, Pipeline, PipelineLayout,
    SetLayout, VkResult,
};

/// The indices of the triangular lattice of `grid` steps per side over its
/// (grid + 1)(grid + 2) / 2 vertices (vertex `j (grid + 1) − j (j − 1) / 2
/// + i` at (i, j), i + j ≤ grid), counter-clockwise in (u, v).
pub fn triangle_grid_indices(grid: u32) -> Vec<u32> {
    let at = |i: u32, j: u32| j * (grid + 1) - j * j.saturating_sub(1) / 2 + i;
    let mut out = Vec::with_capacity((3 * grid * grid) as usize);
    for j in 0..grid {
        for i in 0..grid - j {
            out.extend([at(i, j), at(i + 1, j), at(i, j + 1)]);
            if i + j + 2 <= grid {
                out.extend([at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    out
}

/// A scene's PN triangles, uploaded.
struct Uploaded {
    serial: u64,
    count: u32,
    _buffers: [Buffer; 2],
    set: DescriptorSet,
}

/// The PN part of the ground truth.
pub struct GroundTruthPn {
    set_layout: SetLayout,
    layout: PipelineLayout<DrawPush>,
    draw: Pipeline,
    indices: Buffer,
    grid: u32,
    scene: Option<Uploaded>,
}

impl GroundTruthPn {
    /// The pipeline and the lattice for `grid`.
    pub fn new(setup: &mut MethodSetup<'_>, grid: u32) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        let set_layout = scan::set_layout(ctx)?;
        let scene = setup.scene_layout;
        let layout = scene.pipeline_layout::<DrawPush>(
            ctx,
            "grid PN draw layout",
            &[&set_layout],
            scene.stages(),
        )?;
        let draw = setup.shaders.draw_pipeline(
            ctx,
            &layout,
            "draw (grid, PN triangles)",
            &[
                (vk::ShaderStageFlags::VERTEX, "ground_truth/pn.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "cudatess/draw.frag"),
            ],
        )?;
        Ok(Self {
            set_layout,
            layout,
            draw,
            indices: Self::index_buffer(ctx, grid)?,
            grid,
            scene: None,
        })
    }

    fn index_buffer(ctx: &Context, grid: u32) -> VkResult<Buffer> {
        Buffer::with_data(
            ctx,
            &format!("triangle grid indices ({grid})"),
            &triangle_grid_indices(grid),
            vk::BufferUsageFlags::INDEX_BUFFER,
            MemoryLocation::GpuOnly,
        )
    }

    /// A new lattice for `grid` (the old one is returned to be retired).
    pub fn set_grid(&mut self, ctx: &Context, grid: u32) -> VkResult<Option<Buffer>> {
        if grid == self.grid {
            return Ok(None);
        }
        self.grid = grid;
        Ok(Some(std::mem::replace(
            &mut self.indices,
            Self::index_buffer(ctx, grid)?,
        )))
    }

    /// Uploads the frame's scene's triangles when the scene is new; `false`
    /// when it has none.
    pub fn prepare(&mut self, f: &mut FrameRec<'_>) -> VkResult<bool> {
        let pn: &PnScene = &f.scene.pn;
        if pn.count() == 0 {
            return Ok(false);
        }
        if self
            .scene
            .as_ref()
            .is_some_and(|s| s.serial == f.scene.serial)
        {
            return Ok(true);
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let triangles: Vec<[u32; 4]> = pn
            .triangles
            .iter()
            .zip(&pn.flags)
            .map(|(t, &fl)| [t[0], t[1], t[2], fl])
            .collect();
        let nets: Vec<[f32; 4]> = (0..pn.triangles.len())
            .flat_map(|t| {
                let net = pn.net(t);
                let points = net.b.into_iter().map(|p| p.extend(1.0).to_array());
                points.chain(net.n.into_iter().map(|n| n.extend(0.0).to_array()))
            })
            .collect();
        let triangles = Buffer::with_data(f.ctx, "grid PN triangles", &triangles, storage, gpu)?;
        let nets = Buffer::with_data(f.ctx, "grid PN nets", &nets, storage, gpu)?;
        let mut bound = [BufferBinding::from(&nets); CT_BINDINGS as usize];
        bound[BIND_CT_PN_TRIANGLES as usize] = (&triangles).into();
        let set = DescriptorSet::new(f.ctx, "grid PN set", &self.set_layout, &bound)?;
        let new = Uploaded {
            serial: f.scene.serial,
            count: pn.count(),
            _buffers: [triangles, nets],
            set,
        };
        if let Some(old) = self.scene.replace(new) {
            f.retired.push(old);
        }
        Ok(true)
    }

    /// Records the draw of PN triangles `first .. first + count` (inside
    /// the target's rendering; a part of the frame of its own).
    pub fn record(&self, f: &FrameRec<'_>, pc: &DrawPush, first: u32, count: u32) -> VkResult<()> {
        let Some(s) = &self.scene else {
            return Ok(());
        };
        let count = count.min(s.count.saturating_sub(first));
        if count == 0 {
            return Ok(());
        }
        let (ctx, cmd) = (f.ctx, f.cmd);
        let bind = vk::PipelineBindPoint::GRAPHICS;
        self.draw.bind(cmd);
        f.bind_scene(bind, &self.layout);
        s.set.bind(ctx, cmd, bind, &self.layout, SET_PASS, &[]);
        self.layout.push(cmd, pc);
        unsafe {
            ctx.device().cmd_bind_index_buffer(
                cmd,
                self.indices.handle(),
                0,
                vk::IndexType::UINT32,
            );
            ctx.device()
                .cmd_draw_indexed(cmd, 3 * self.grid * self.grid, count, 0, 0, first);
        }
        Ok(())
    }

    /// Triangles drawn per frame.
    pub fn triangles(&self) -> u64 {
        self.scene
            .as_ref()
            .map_or(0, |s| u64::from(s.count) * u64::from(self.grid * self.grid))
    }

    /// Its buffers' bytes.
    pub fn memory(&self) -> u64 {
        self.indices.size()
            + self
                .scene
                .as_ref()
                .map_or(0, |s| s._buffers.iter().map(Buffer::size).sum())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triangle_lattice_covers_the_triangle() {
        let idx = triangle_grid_indices(2);
        assert_eq!(idx.len(), 12);
        assert_eq!(*idx.iter().max().unwrap(), 5);
        assert_eq!(&idx[..6], &[0, 1, 3, 1, 4, 3]);
        assert_eq!(triangle_grid_indices(64).len(), 3 * 64 * 64);
    }
}
