//! Method `cudatess`: Schwarz and Stamminger, *Fast GPU-based Adaptive
//! Tessellation with CUDA* (2009), their Fig. 1 in Vulkan compute, for
//! bicubic patches, rational ones included (their §3):
//!
//! 1. **factors** (`glsl/cudatess/factors.comp`, one invocation per patch):
//!    frustum culling and, for one-sided polynomial patches, back-patch
//!    culling (factor 0), then factors m along u and n along v from
//!    the Zheng–Sederberg bound for ε pixels at the patch's nearest control
//!    point; each edge's factor becomes the largest of its patches'
//!    (atomicMax into the scene's edge table: sides with bit-identical
//!    control points and weights are one edge).
//! 2. **scan**: each patch reads its edges' final factors and counts the
//!    vertices and indices of its pattern (`cudatess/counts.comp`); an exclusive
//!    multi-level scan turns the counts into buffer offsets (`cudatess/scan.comp`,
//!    planned in [`scan`]); one invocation writes the draw's arguments, or an
//!    overflow bit (`cudatess/args.comp`).
//! 3. **vertices** (`cudatess/vertices.comp`, [`CT_VERTEX_THREADS`] invocations per
//!    patch): corners, edge vertices from the edge's own control points in a
//!    reversal-symmetric order (both patches of an edge write the same bits),
//!    interior vertices by evaluation or, with
//!    [`Options::forward_differencing`], by
//!    forward differences along rows.
//! 4. **indices** (`cudatess/indices.comp`, one invocation per patch): the uniform
//!    core and Bresenham-like transition strips ([`pattern`]).
//! 5. **draw**: one `vkCmdDrawIndexedIndirect` through `cudatess/draw.vert` and the
//!    shared fragment shading (`cudatess/draw.frag`: rational patches lit with their
//!    own normal).
//!
//! PN triangles (their §4; the scene's `surface = "pn-triangles"` models)
//! run through the same stages with their own passes after the patches'
//! (`cudatess/pn_factors.comp`: conversion to the cubic net and normal field,
//! culling, Filip-bound factors per edge; `cudatess/pn_counts.comp`,
//! `cudatess/pn_vertices.comp`, `cudatess/pn_indices.comp`; see `glsl/common/pn.glsl`):
//! their records and scan entries follow the patches', the one scan and the
//! one draw cover both, and the fragment stage lights them with their
//! quadratic normal.
//!
//! The vertex and index buffers start small and are grown when a frame's
//! totals do not fit ([`Finished::Redo`]). After a frame the per-patch
//! records, offsets and the buffers stay readable for validation
//! ([`CudaTess::read_frame`]).

pub mod checks;
pub mod constants;
mod passes;
pub mod pattern;
pub mod push;
mod records;
pub mod scan;

use ash::vk;
use serde_json::json;

use self::constants::*;
use self::push::CtPush;
use super::{Finished, Method, MethodInfo, MethodSetup, MethodStats, Reads, RenderError, Role};
use crate::constants::*;
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::blocks::block;
use crate::gpu::DrawPush;
use crate::scene::pn::PnScene;
use crate::vk::{
    Access, Buffer, BufferBinding, Context, DescriptorSet, MemoryLocation, Pipeline,
    PipelineLayout, Recorder, Res, SetLayout, VkError, VkResult,
};
use scan::ScanPlan;

use passes::ComputePasses;
pub use records::{CtVertex, FrameData, PatchRecord};

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "cudatess",
    about: "Schwarz-Stamminger compute tessellation: Zheng-Sederberg factors, scan, \
            vertex and index buffers, one indexed indirect draw (rational patches too)",
    rational: true,
    pn: true,
    reads: Reads::TESSELLATES,
    role: Role::Compared,
    targets: &[],
    heat_map: "log2 of the patch's larger factor",
    seams: "transition strips",
    checks: Some(checks::make),
    blocks: &[block::<push::CtPush>],
    build: |setup| Ok(Box::new(CudaTess::new(setup)?)),
};

/// The PN-triangle passes.
struct PnPipelines {
    factors: Pipeline,
    counts: Pipeline,
    vertices: Pipeline,
    indices: Pipeline,
}

/// The scene's PN triangles on the GPU (one-element placeholders where the
/// scene has none: a binding needs a buffer).
struct PnBuffers {
    vertices: Buffer,
    triangles: Buffer,
    edge_ids: Buffer,
    nets: Buffer,
}

impl PnBuffers {
    /// Uploads `pn`, its edge ids offset by `first_edge` (the patches'
    /// edges come first in the edge factors).
    fn new(ctx: &Context, pn: &PnScene, first_edge: u32) -> VkResult<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let mut vertices: Vec<[f32; 8]> = pn
            .positions
            .iter()
            .zip(&pn.normals)
            .map(|(p, n)| [p.x, p.y, p.z, 1.0, n.x, n.y, n.z, 0.0])
            .collect();
        let mut triangles: Vec<[u32; 4]> = pn
            .triangles
            .iter()
            .zip(&pn.flags)
            .map(|(t, &f)| [t[0], t[1], t[2], f])
            .collect();
        let mut edge_ids: Vec<[u32; 4]> = pn
            .edge_ids
            .iter()
            .map(|e| [e[0] + first_edge, e[1] + first_edge, e[2] + first_edge, 0])
            .collect();
        if triangles.is_empty() {
            vertices.push([0.0; 8]);
            triangles.push([0; 4]);
            edge_ids.push([0; 4]);
        }
        let nets = Buffer::new(
            ctx,
            "cudatess PN nets",
            triangles.len() as u64 * u64::from(CT_PN_NET_VEC4) * 16,
            storage,
            gpu,
        )?;
        Ok(Self {
            vertices: Buffer::with_data(ctx, "cudatess PN vertices", &vertices, storage, gpu)?,
            triangles: Buffer::with_data(ctx, "cudatess PN triangles", &triangles, storage, gpu)?,
            edge_ids: Buffer::with_data(ctx, "cudatess PN edge ids", &edge_ids, storage, gpu)?,
            nets,
        })
    }
}

/// Vertices the vertex buffer holds at first (grown on demand).
pub const INITIAL_VERTICES: u32 = 1 << 18;
/// Indices the index buffer holds at first (grown on demand).
pub const INITIAL_INDICES: u32 = 1 << 20;

/// `cudatess`'s knobs ([`super::PerMethod::cudatess`]) and its flag, under
/// its own heading in `--help`.
#[derive(Clone, Debug, Default, PartialEq, Eq, clap::Args)]
#[command(next_help_heading = "cudatess")]
pub struct Options {
    /// cudatess: interior vertices by forward differences along each row
    /// (the paper's option) instead of evaluating every one.
    #[arg(long = "forward-diff")]
    pub forward_differencing: bool,
    /// The vertex and index buffers' first capacities instead of
    /// [`INITIAL_VERTICES`] and [`INITIAL_INDICES`] (small ones make the
    /// first frames grow them; tests set them, no flag).
    #[arg(skip)]
    pub capacity: Option<(u32, u32)>,
}

/// The buffers that follow the scene: its edge table, the edge factors,
/// the per-patch records and the scan.
struct SceneBuffers {
    serial: u64,
    patches: u32,
    /// PN triangles (records and scan entries after the patches').
    tris: u32,
    pn: PnBuffers,
    edges: u32,
    edge_ids: Buffer,
    edge_factors: Buffer,
    records: Buffer,
    scan: Buffer,
    plan: ScanPlan,
}

/// The vertex and index buffers and their capacities.
struct Outputs {
    vertices: Buffer,
    indices: Buffer,
    vertex_capacity: u32,
    index_capacity: u32,
}

/// The method.
pub struct CudaTess {
    set_layout: SetLayout,
    compute_layout: PipelineLayout<CtPush>,
    draw_layout: PipelineLayout<DrawPush>,
    factors: Pipeline,
    counts: Pipeline,
    scan: Pipeline,
    args: Pipeline,
    vertices: Pipeline,
    indices: Pipeline,
    draw: Pipeline,
    pn: PnPipelines,
    counters: Buffer,
    scene: Option<SceneBuffers>,
    outputs: Outputs,
    set: Option<DescriptorSet>,
    forward_differencing: bool,
    /// The first capacities asked for ([`Options::capacity`]).
    first_capacity: Option<(u32, u32)>,
    copied: Option<CopyRange>,
}

impl CudaTess {
    /// Creates the pipelines and the first (small) output buffers.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let ctx = setup.ctx;
        check_device(ctx)?;
        let set_layout = scan::set_layout(ctx)?;
        let scene = setup.scene_layout;
        let compute_layout = scene.pipeline_layout::<CtPush>(
            ctx,
            "cudatess compute layout",
            &[&set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let draw_layout = scene.pipeline_layout::<DrawPush>(
            ctx,
            "cudatess draw layout",
            &[&set_layout],
            scene.stages(),
        )?;
        let sh = &mut *setup.shaders;
        let l = &compute_layout;
        let factors = sh.compute(ctx, l, "cudatess factors", "cudatess/factors.comp")?;
        let counts = sh.compute(ctx, l, "cudatess counts", "cudatess/counts.comp")?;
        let scan = sh.compute(ctx, l, "cudatess scan", "cudatess/scan.comp")?;
        let args = sh.compute(ctx, l, "cudatess args", "cudatess/args.comp")?;
        let vertices = sh.compute(ctx, l, "cudatess vertices", "cudatess/vertices.comp")?;
        let indices = sh.compute(ctx, l, "cudatess indices", "cudatess/indices.comp")?;
        let pn = PnPipelines {
            factors: sh.compute(ctx, l, "cudatess PN factors", "cudatess/pn_factors.comp")?,
            counts: sh.compute(ctx, l, "cudatess PN counts", "cudatess/pn_counts.comp")?,
            vertices: sh.compute(ctx, l, "cudatess PN vertices", "cudatess/pn_vertices.comp")?,
            indices: sh.compute(ctx, l, "cudatess PN indices", "cudatess/pn_indices.comp")?,
        };
        let draw = sh.draw_pipeline(
            ctx,
            &draw_layout,
            "draw (cudatess)",
            &[
                (vk::ShaderStageFlags::VERTEX, "cudatess/draw.vert"),
                (vk::ShaderStageFlags::FRAGMENT, "cudatess/draw.frag"),
            ],
        )?;
        let counters = Buffer::new(
            ctx,
            "cudatess counters",
            u64::from(CT_WORDS) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDIRECT_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let o = &setup.options.per_method.cudatess;
        let (v, i) = o.capacity.unwrap_or((INITIAL_VERTICES, INITIAL_INDICES));
        let outputs = Outputs::new(ctx, v.max(1), i.max(1))?;
        Ok(Self {
            set_layout,
            compute_layout,
            draw_layout,
            factors,
            counts,
            scan,
            args,
            vertices,
            indices,
            draw,
            pn,
            counters,
            scene: None,
            outputs,
            set: None,
            forward_differencing: o.forward_differencing,
            first_capacity: o.capacity,
            copied: None,
        })
    }

    /// The scene's buffers, made (the old ones retired) when the scene is
    /// new: the edge table is uploaded from the host copy the scene keeps.
    fn ensure_scene(&mut self, f: &mut FrameRec<'_>) -> VkResult<()> {
        if self
            .scene
            .as_ref()
            .is_some_and(|s| s.serial == f.scene.serial)
        {
            return Ok(());
        }
        let ctx = f.ctx;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let patches = f.scene.count;
        let table = &f.scene.edges;
        // A scene of PN triangles alone has no patch sides: one placeholder.
        let ids: &[[u32; 4]] = if table.ids.is_empty() {
            &[[0; 4]]
        } else {
            &table.ids
        };
        let edge_ids = Buffer::with_data(ctx, "cudatess edge table", ids, storage, gpu)?;
        let tris = f.scene.pn.count();
        let pn = PnBuffers::new(ctx, &f.scene.pn, table.count)?;
        let edges = (table.count + f.scene.pn.edges).max(1);
        let edge_factors = Buffer::new(
            ctx,
            "cudatess edge factors",
            u64::from(edges) * 4,
            storage,
            gpu,
        )?;
        let records = Buffer::new(
            ctx,
            "cudatess patch records",
            u64::from((patches + tris).max(1)) * u64::from(CT_PATCH_WORDS) * 4,
            storage,
            gpu,
        )?;
        let plan = ScanPlan::new(patches + tris + 1);
        let scan = Buffer::new(
            ctx,
            "cudatess scan",
            u64::from(plan.entries()) * 8,
            storage,
            gpu,
        )?;
        let new = SceneBuffers {
            serial: f.scene.serial,
            patches,
            tris,
            pn,
            edges,
            edge_ids,
            edge_factors,
            records,
            scan,
            plan,
        };
        if let Some(old) = self.scene.replace(new) {
            f.retired.push(old);
        }
        if let Some(old) = self.set.take() {
            f.retired.push(old);
        }
        Ok(())
    }

    /// Set 1 for the current scene and output buffers.
    fn ensure_set(&mut self, ctx: &Context) -> VkResult<()> {
        if self.set.is_some() {
            return Ok(());
        }
        let s = self
            .scene
            .as_ref()
            .ok_or_else(|| VkError::Usage("cudatess: no scene buffers".into()))?;
        let mut bound = [BufferBinding::from(&self.counters); CT_BINDINGS as usize];
        bound[BIND_CT_EDGE_IDS as usize] = (&s.edge_ids).into();
        bound[BIND_CT_EDGE_FACTORS as usize] = (&s.edge_factors).into();
        bound[BIND_CT_PATCHES as usize] = (&s.records).into();
        bound[BIND_CT_SCAN as usize] = (&s.scan).into();
        bound[BIND_CT_VERTICES as usize] = (&self.outputs.vertices).into();
        bound[BIND_CT_INDICES as usize] = (&self.outputs.indices).into();
        bound[BIND_CT_PN_VERTICES as usize] = (&s.pn.vertices).into();
        bound[BIND_CT_PN_TRIANGLES as usize] = (&s.pn.triangles).into();
        bound[BIND_CT_PN_EDGE_IDS as usize] = (&s.pn.edge_ids).into();
        bound[BIND_CT_PN_NETS as usize] = (&s.pn.nets).into();
        self.set = Some(DescriptorSet::new(
            ctx,
            "cudatess set",
            &self.set_layout,
            &bound,
        )?);
        Ok(())
    }

    /// Workgroups for `items` items of `per_group` (capped at the device's
    /// limit; the shaders loop over the rest).
    fn groups(ctx: &Context, items: u32, per_group: u32) -> u32 {
        let max = ctx.info().limits.max_compute_work_group_count[0].max(1);
        items.div_ceil(per_group).clamp(1, max)
    }

    /// Records the compute passes and the draw.
    fn record_frame(&self, f: &mut FrameRec<'_>) -> VkResult<()> {
        let (Some(s), Some(set)) = (self.scene.as_ref(), self.set.as_ref()) else {
            return Err(VkError::Usage("cudatess: nothing to record with".into()));
        };
        let (ctx, cmd) = (f.ctx, f.cmd);
        // Orders the scene uploads (earlier submissions) before the passes,
        // and the last frame's draw and readback before this frame's
        // writes, the counters' and edge factors' resets first.
        let mut rec = Recorder::new(ctx, cmd);
        rec.after(Res::Memory, Access::ALL);
        rec.fill("cudatess counters reset", &self.counters, 0);
        rec.fill("edge factors reset", &s.edge_factors, 0);
        let passes = ComputePasses {
            method: self,
            set,
            push: self.frame_push(s),
            tris: s.tris,
        };
        passes.record(f, &mut rec, s)?;
        // The draw reads set 1 (the counters hold its arguments, the index
        // buffer is bound in it too).
        let draw = Access::new(
            vk::PipelineStageFlags2::DRAW_INDIRECT
                | vk::PipelineStageFlags2::INDEX_INPUT
                | vk::PipelineStageFlags2::VERTEX_SHADER
                | vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::INDIRECT_COMMAND_READ
                | vk::AccessFlags2::INDEX_READ
                | vk::AccessFlags2::SHADER_STORAGE_READ,
        );
        rec.hand_off_set(set, draw);
        self.record_draw(f, set)
    }

    /// The push block every compute pass of a frame over `s` gets.
    fn frame_push(&self, s: &SceneBuffers) -> CtPush {
        CtPush {
            patch_count: s.patches,
            vertex_capacity: self.outputs.vertex_capacity,
            index_capacity: self.outputs.index_capacity,
            options: if self.forward_differencing {
                CT_OPT_FORWARD_DIFF
            } else {
                0
            },
            scan_offset: 0,
            scan_count: 0,
            scan_sums: scan::NO_SUMS,
            pass: 0,
            tri_count: s.tris,
            pad: [0; 3],
        }
    }

    /// Records the draw scope: the one indexed indirect draw of what the
    /// compute passes wrote, between the target's begin and end.
    fn record_draw(&self, f: &mut FrameRec<'_>, set: &DescriptorSet) -> VkResult<()> {
        let pc = f.view.draw_push(0, false, 0);
        f.scoped("draw", |f| {
            let (ctx, cmd) = (f.ctx, f.cmd);
            f.target.begin(ctx, cmd);
            let bind = vk::PipelineBindPoint::GRAPHICS;
            self.draw.bind(cmd);
            f.bind_scene(bind, &self.draw_layout);
            set.bind(ctx, cmd, bind, &self.draw_layout, SET_PASS, &[]);
            self.draw_layout.push(cmd, &pc);
            unsafe {
                ctx.device().cmd_bind_index_buffer(
                    cmd,
                    self.outputs.indices.handle(),
                    0,
                    vk::IndexType::UINT32,
                );
                ctx.device().cmd_draw_indexed_indirect(
                    cmd,
                    self.counters.handle(),
                    u64::from(CT_DRAW_ARGS) * 4,
                    1,
                    std::mem::size_of::<vk::DrawIndexedIndirectCommand>() as u32,
                );
            }
            f.target.end(ctx, cmd);
            Ok(())
        })
    }

    /// What the last finished frame left: every patch's record and offsets,
    /// the vertices and the indices (read after `render`).
    pub fn read_frame(&self, ctx: &Context) -> Result<FrameData, RenderError> {
        let s = self.scene.as_ref().ok_or_else(|| {
            RenderError::Request("cudatess: render a frame before reading it".into())
        })?;
        let counters: Vec<u32> = self.counters.read(ctx)?;
        if counters[CT_ERROR as usize] != 0 {
            return Err(RenderError::Request(
                "cudatess: the last frame overflowed its buffers".into(),
            ));
        }
        let words: Vec<u32> = s.records.read(ctx)?;
        let scan: Vec<[u32; 2]> = s.scan.read(ctx)?;
        let w = CT_PATCH_WORDS as usize;
        let records = words
            .chunks_exact(w)
            .take((s.patches + s.tris) as usize)
            .zip(&scan)
            .map(|(r, o)| PatchRecord {
                own: [r[CT_REC_M as usize], r[CT_REC_N as usize]],
                edges: std::array::from_fn(|k| r[CT_REC_EDGES as usize + k]),
                counts: [r[CT_REC_VERTICES as usize], r[CT_REC_INDICES as usize]],
                offsets: *o,
            })
            .collect();
        let nv = counters[CT_VERTEX_TOTAL as usize] as usize;
        let ni = counters[CT_INDEX_TOTAL as usize] as usize;
        let vw: Vec<u32> = self.outputs.vertices.read(ctx)?;
        let vertices = vw
            .chunks_exact(CT_VERTEX_WORDS as usize)
            .take(nv)
            .map(|v| CtVertex {
                position: [0, 1, 2].map(|k| f32::from_bits(v[k])),
                uv: [f32::from_bits(v[3]), f32::from_bits(v[4])],
                word: v[5],
            })
            .collect();
        let mut indices: Vec<u32> = self.outputs.indices.read(ctx)?;
        indices.truncate(ni);
        let mut pn_nets: Vec<[[f32; 4]; 16]> = s.pn.nets.read(ctx)?;
        pn_nets.truncate(s.tris as usize);
        Ok(FrameData {
            records,
            patches: s.patches as usize,
            vertices,
            indices,
            pn_nets,
        })
    }

    /// The output buffers' capacities (vertices, indices).
    pub fn capacities(&self) -> (u32, u32) {
        (self.outputs.vertex_capacity, self.outputs.index_capacity)
    }
}

impl Outputs {
    fn new(ctx: &Context, vertex_capacity: u32, index_capacity: u32) -> VkResult<Self> {
        Ok(Self {
            vertices: Buffer::new(
                ctx,
                "cudatess vertices",
                u64::from(vertex_capacity) * u64::from(CT_VERTEX_WORDS) * 4,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryLocation::GpuOnly,
            )?,
            indices: Buffer::new(
                ctx,
                "cudatess indices",
                u64::from(index_capacity) * 4,
                vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::INDEX_BUFFER,
                MemoryLocation::GpuOnly,
            )?,
            vertex_capacity,
            index_capacity,
        })
    }
}

/// The capacity for `need` entries of `bytes` each after an overflow: a
/// quarter more than needed, at least double the old, within the device's
/// storage-buffer range; `None` when even `need` does not fit.
fn grown(old: u32, need: u32, bytes: u64, range: u64) -> Option<u32> {
    let most = (range / bytes).min(u64::from(u32::MAX)) as u32;
    if u64::from(need) * bytes > range {
        return None;
    }
    let want = u64::from(need) + u64::from(need) / 4;
    Some(want.max(2 * u64::from(old)).min(u64::from(most)) as u32)
}

/// Refuses a device without what the draw needs.
fn check_device(ctx: &Context) -> Result<(), RenderError> {
    let info = ctx.info();
    if info.limits.max_compute_work_group_invocations < CT_SCAN_GROUP_SIZE {
        return Err(RenderError::Request(format!(
            "method `cudatess` needs {CT_SCAN_GROUP_SIZE} invocations per workgroup; {} allows {}",
            info.name, info.limits.max_compute_work_group_invocations
        )));
    }
    Ok(())
}

impl Method for CudaTess {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn draw_path(&self) -> &'static str {
        "compute + indexed indirect"
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.ensure_scene(f)?;
        self.ensure_set(f.ctx)?;
        self.record_frame(f)?;
        self.copied = Some(f.copy_out(&self.counters, CT_WORDS)?);
        Ok(())
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let range = self
            .copied
            .ok_or_else(|| RenderError::Request("finish() before any frame was recorded".into()))?;
        let words = out.words(range).to_vec();
        let at = |k: u32| words[k as usize];
        let (nv, ni) = (at(CT_VERTEX_TOTAL), at(CT_INDEX_TOTAL));
        if at(CT_ERROR) != 0 {
            let range = u64::from(out.ctx.info().limits.max_storage_buffer_range);
            let o = &self.outputs;
            let vbytes = u64::from(CT_VERTEX_WORDS) * 4;
            let too_big = |what: &str, need: u32, bytes: u64| RenderError::Method {
                method: INFO.name,
                message: format!(
                    "the frame needs {need} {what} ({} bytes), more than one storage buffer \
                     of this device holds ({range} bytes); raise --eps or draw a smaller scene",
                    u64::from(need) * bytes
                ),
            };
            let v = if nv > o.vertex_capacity {
                grown(o.vertex_capacity, nv, vbytes, range)
                    .ok_or_else(|| too_big("vertices", nv, vbytes))?
            } else {
                o.vertex_capacity
            };
            let i = if ni > o.index_capacity {
                grown(o.index_capacity, ni, 4, range).ok_or_else(|| too_big("indices", ni, 4))?
            } else {
                o.index_capacity
            };
            let outputs = Outputs::new(out.ctx, v, i)?;
            out.retired
                .push(std::mem::replace(&mut self.outputs, outputs));
            if let Some(old) = self.set.take() {
                out.retired.push(old);
            }
            return Ok(Finished::Redo {
                reason: format!(
                    "{nv} vertices and {ni} indices did not fit; buffers grown to {v} and {i}"
                ),
            });
        }
        let patches = self.scene.as_ref().map_or(0, |s| s.patches);
        let culled = u64::from(at(CT_CULLED));
        let backface = u64::from(at(CT_BACKFACE));
        Ok(Finished::Done(MethodStats {
            triangles: u64::from(ni / 3),
            placeholder_triangles: 0,
            culled_patches: culled,
            own: vec![
                (
                    "tessellated_patches",
                    json!(
                        u64::from(patches + self.scene.as_ref().map_or(0, |s| s.tris))
                            .saturating_sub(culled + backface)
                    ),
                ),
                ("backface_culled_patches", json!(backface)),
                ("vertices", json!(nv)),
                ("indices", json!(ni)),
                ("largest_factor", json!(at(CT_MAX_FACTOR_SEEN))),
                ("max_factor", json!(CT_MAX_FACTOR)),
                ("edges", json!(self.scene.as_ref().map_or(0, |s| s.edges))),
                (
                    "pn_triangles",
                    json!(self.scene.as_ref().map_or(0, |s| s.tris)),
                ),
                ("forward_differencing", json!(self.forward_differencing)),
                ("vertex_capacity", json!(self.outputs.vertex_capacity)),
                ("index_capacity", json!(self.outputs.index_capacity)),
            ],
        }))
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let o = &setup.options.per_method.cudatess;
        self.forward_differencing = o.forward_differencing;
        // Other first capacities: made again, with the buffers they ask for.
        Ok(o.capacity == self.first_capacity)
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        let mut v = vec![("counters", self.counters.size())];
        if let Some(s) = &self.scene {
            v.push(("edge_table", s.edge_ids.size()));
            v.push(("edge_factors", s.edge_factors.size()));
            v.push(("patch_records", s.records.size()));
            v.push(("scan", s.scan.size()));
            if s.tris > 0 {
                let pn = &s.pn;
                let input = pn.vertices.size() + pn.triangles.size() + pn.edge_ids.size();
                v.push(("pn_input", input));
                v.push(("pn_nets", pn.nets.size()));
            }
        }
        v.push(("vertex_buffer", self.outputs.vertices.size()));
        v.push(("index_buffer", self.outputs.indices.size()));
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_is_bounded_by_the_range() {
        assert_eq!(grown(100, 120, 4, 1 << 20), Some(200));
        assert_eq!(grown(100, 1000, 4, 1 << 20), Some(1250));
        assert_eq!(grown(100, 1000, 4, 4400), Some(1100));
        assert_eq!(grown(100, 2000, 4, 4400), None);
    }
}
