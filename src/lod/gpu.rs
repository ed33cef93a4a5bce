//! The levels on the GPU and their draw: one vertex and one index buffer
//! for every level of every model, a vertex + fragment pipeline that places
//! a level by its instance's record and shades it as the patches are
//! shaded, and the per-frame work the renderer asks of it
//! ([`Lod::prepare`] before the method, [`Lod::draw`] after it).

use ash::vk;
use glam::Vec3;

use super::select::{self, Draw};
use super::SceneLevels;
use crate::constants::{INSTANCE_LOD, LOD_VERTEX_WORDS, SET_PASS};
use crate::frame::{Retired, View};
use crate::gpu::blocks::DrawPush;
use crate::gpu::{SceneGpu, SceneLayout, SceneSpec, Shaders};
use crate::patch::view::ViewParams;
use crate::scene::instances::{Instance, INSTANCE_BYTES};
use crate::vk::{
    Access, Buffer, Context, DescriptorSet, MemoryLocation, Pass, Pipeline, PipelineLayout,
    Recorder, Res, SetLayout, VkResult,
};

/// The level draw's shaders (its set layout is reflected from them).
const SHADERS: &[&str] = &["lod/draw.vert", "lod/draw.frag"];

/// Byte offset of the flags word in an instance record.
const FLAGS_OFFSET: u64 = 60;

/// A unit vector as two snorm16 of its octahedral projection (decoded by
/// `oct_decode` in `glsl/lod/draw.vert`).
pub fn oct_encode(n: Vec3) -> u32 {
    let n = n / (n.x.abs() + n.y.abs() + n.z.abs()).max(1e-30);
    let (mut x, mut y) = (n.x, n.y);
    if n.z < 0.0 {
        let sx = if n.x >= 0.0 { 1.0 } else { -1.0 };
        let sy = if n.y >= 0.0 { 1.0 } else { -1.0 };
        (x, y) = ((1.0 - n.y.abs()) * sx, (1.0 - n.x.abs()) * sy);
    }
    let q = |v: f32| ((v.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    q(x) | (q(y) << 16)
}

/// Where one level lies in the shared buffers.
#[derive(Clone, Copy, Debug)]
struct Range {
    first_index: u32,
    index_count: u32,
    vertex_offset: i32,
}

/// What the levels drew in a frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LodFrame {
    /// Instances drawn from a level (inside the view).
    pub instances: u64,
    /// Their triangles.
    pub triangles: u64,
    /// Per level index (0 the finest of each model): instances, triangles.
    pub by_level: Vec<(u64, u64)>,
    /// Bytes of every level on the GPU.
    pub bytes: u64,
}

/// The levels of a scene on the GPU and what draws each instance.
pub struct Lod {
    levels: SceneLevels,
    ranges: Vec<Vec<Range>>,
    vertices: Buffer,
    indices: Buffer,
    /// Kept for as long as the set made from it.
    _set_layout: SetLayout,
    layout: PipelineLayout<DrawPush>,
    set: DescriptorSet,
    /// The draw pipeline and what it was made for (sample count, scene).
    pipeline: Option<(Pipeline, vk::SampleCountFlags, SceneSpec)>,
    /// Per instance: what drew it last frame (`None`: nothing yet, or ε
    /// changed since).
    choice: Vec<Option<Draw>>,
    /// The ε × pixel size of the last frame's view (`ViewParams::eps_k`).
    eps_k: f32,
    /// Per instance: whether its record on the GPU has `INSTANCE_LOD` set.
    flagged: Vec<bool>,
    /// The instances this frame draws from a level: (instance, model, level).
    draws: Vec<(u32, usize, usize)>,
    /// Every instance with levels drawn from this one (the model's
    /// coarsest where it has fewer), whatever its distance: the hole test
    /// of a level.
    force: Option<usize>,
}

impl Lod {
    /// Uploads `levels` for the scene `scene` holds.
    pub fn new(
        ctx: &Context,
        scene: &SceneGpu,
        scene_layout: &SceneLayout,
        levels: SceneLevels,
    ) -> VkResult<Self> {
        let mut words: Vec<u32> = Vec::new();
        let mut indices: Vec<u32> = Vec::new();
        let mut ranges = Vec::new();
        for m in &levels.models {
            let mut model = Vec::new();
            for l in &m.levels {
                let base = (words.len() / LOD_VERTEX_WORDS as usize) as i32;
                for (k, p) in l.mesh.positions.iter().enumerate() {
                    let st = l.mesh.st[k];
                    words.extend([
                        p.x.to_bits(),
                        p.y.to_bits(),
                        p.z.to_bits(),
                        oct_encode(l.mesh.normals[k][0]),
                        st[0].to_bits(),
                        st[1].to_bits(),
                    ]);
                }
                model.push(Range {
                    first_index: indices.len() as u32,
                    index_count: l.mesh.indices.len() as u32,
                    vertex_offset: base,
                });
                indices.extend_from_slice(&l.mesh.indices);
            }
            ranges.push(model);
        }
        // Never empty: a scene whose models all lack levels binds one word.
        words.resize(words.len().max(LOD_VERTEX_WORDS as usize), 0);
        indices.resize(indices.len().max(3), 0);
        let gpu = MemoryLocation::GpuOnly;
        let vertices = Buffer::with_data(
            ctx,
            "level-of-detail vertices",
            &words,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            gpu,
        )?;
        let index_buffer = Buffer::with_data(
            ctx,
            "level-of-detail indices",
            &indices,
            vk::BufferUsageFlags::INDEX_BUFFER,
            gpu,
        )?;
        let set_layout = SetLayout::reflect(ctx, "level-of-detail set", SET_PASS, SHADERS)?;
        let layout = scene_layout.pipeline_layout::<DrawPush>(
            ctx,
            "level-of-detail draw layout",
            &[&set_layout],
            scene_layout.stages(),
        )?;
        let set = DescriptorSet::new(
            ctx,
            "level-of-detail set",
            &set_layout,
            &[(&vertices).into()],
        )?;
        let n = scene.instance_records.len();
        Ok(Self {
            levels,
            ranges,
            vertices,
            indices: index_buffer,
            _set_layout: set_layout,
            layout,
            set,
            pipeline: None,
            choice: vec![None; n],
            eps_k: 0.0,
            force: None,
            flagged: vec![false; n],
            draws: Vec::new(),
        })
    }

    /// Draws every instance with levels from level `level` (see
    /// [`Lod::force`]'s field), or, with `None`, as its distance says.
    pub fn set_force(&mut self, level: Option<usize>) {
        self.force = level;
    }

    /// The levels.
    pub fn levels(&self) -> &SceneLevels {
        &self.levels
    }

    /// Bytes the levels take on the GPU.
    pub fn bytes(&self) -> u64 {
        self.vertices.size() + self.indices.size()
    }

    /// Chooses what draws each instance in `params` (`enabled` false: the
    /// patches, everywhere) and records the flag changes into the
    /// instance records, so the method leaves the level-drawn instances
    /// alone. Call before the method records.
    pub fn prepare(
        &mut self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        scene: &SceneGpu,
        params: &ViewParams,
        enabled: bool,
    ) {
        self.draws.clear();
        if params.eps_k != self.eps_k {
            // A new tolerance (or image height, or field of view): the
            // hysteresis band was the old one's.
            self.choice.fill(None);
            self.eps_k = params.eps_k;
        }
        let records = &scene.instance_records;
        let mut changed = Vec::new();
        for (i, inst) in records.iter().enumerate() {
            let forced = self.levels.model_of(inst.source).and_then(|m| {
                let n = self.levels.models[m].levels.len();
                let l = self.force?;
                (n > 0).then(|| Draw::Level(m, l.min(n - 1)))
            });
            let draw = match (enabled, forced) {
                (false, _) => Draw::Patches,
                (true, Some(d)) => d,
                (true, None) => select::choose(&self.levels, params, inst, self.choice[i]),
            };
            self.choice[i] = Some(draw);
            let lod = matches!(draw, Draw::Level(..));
            if lod != self.flagged[i] {
                self.flagged[i] = lod;
                changed.push(i);
            }
            if let Draw::Level(m, l) = draw {
                if !outside(params, inst) {
                    self.draws.push((i as u32, m, l));
                }
            }
        }
        if changed.is_empty() {
            return;
        }
        let mut rec = Recorder::new(ctx, cmd);
        // The frames before may still read the records.
        rec.after(Res::Memory, Access::ALL);
        let pass = Pass::new("level-of-detail flags")
            .write(Res::Buffer(&scene.instances), Access::TRANSFER_WRITE);
        rec.run(&pass, |cmd| {
            for &i in &changed {
                let flags = records[i].flags | if self.flagged[i] { INSTANCE_LOD } else { 0 };
                let offset = i as u64 * INSTANCE_BYTES + FLAGS_OFFSET;
                unsafe {
                    ctx.device().cmd_update_buffer(
                        cmd,
                        scene.instances.handle(),
                        offset,
                        &flags.to_ne_bytes(),
                    )
                };
            }
        });
        rec.hand_off(Res::Memory, Access::ALL);
    }

    /// Whether this frame draws anything from a level.
    pub fn draws_any(&self) -> bool {
        !self.draws.is_empty()
    }

    /// What this frame draws from levels.
    pub fn frame(&self) -> LodFrame {
        let mut out = LodFrame {
            bytes: self.bytes(),
            ..LodFrame::default()
        };
        for &(_, m, l) in &self.draws {
            let t = u64::from(self.ranges[m][l].index_count / 3);
            out.instances += 1;
            out.triangles += t;
            if out.by_level.len() <= l {
                out.by_level.resize(l + 1, (0, 0));
            }
            out.by_level[l].0 += 1;
            out.by_level[l].1 += t;
        }
        out
    }

    /// Records the level draws into the target's render pass, begun by the
    /// caller (loading what the method drew).
    #[allow(clippy::too_many_arguments)]
    pub fn draw(
        &mut self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        shaders: &mut Shaders,
        scene: &SceneGpu,
        slot: usize,
        view: &View,
        retired: &mut Retired,
    ) -> VkResult<()> {
        let key = (shaders.samples, shaders.scene);
        let stale = self
            .pipeline
            .as_ref()
            .is_none_or(|(_, s, spec)| (*s, *spec) != key);
        if stale {
            let stages = [
                (vk::ShaderStageFlags::VERTEX, SHADERS[0]),
                (vk::ShaderStageFlags::FRAGMENT, SHADERS[1]),
            ];
            let p = shaders.draw_pipeline(ctx, &self.layout, "draw (levels of detail)", &stages)?;
            // Frames in flight may still draw with the old one.
            if let Some(old) = self.pipeline.replace((p, key.0, key.1)) {
                retired.push(old);
            }
        }
        let Some((pipeline, ..)) = &self.pipeline else {
            return Ok(());
        };
        let bind = vk::PipelineBindPoint::GRAPHICS;
        pipeline.bind(cmd);
        scene.bind(ctx, cmd, bind, &self.layout, slot);
        self.set.bind(ctx, cmd, bind, &self.layout, SET_PASS, &[]);
        self.layout.push(cmd, &view.draw_push(0, false, 0));
        let dev = ctx.device();
        unsafe {
            dev.cmd_bind_index_buffer(cmd, self.indices.handle(), 0, vk::IndexType::UINT32);
            for &(i, m, l) in &self.draws {
                let r = self.ranges[m][l];
                dev.cmd_draw_indexed(cmd, r.index_count, 1, r.first_index, r.vertex_offset, i);
            }
        }
        Ok(())
    }
}

/// Whether `inst`'s box lies wholly outside one of the view's planes.
fn outside(params: &ViewParams, inst: &Instance) -> bool {
    let (lo, hi) = (Vec3::from_slice(&inst.lo), Vec3::from_slice(&inst.hi));
    params.planes.iter().any(|p| {
        let far = |a: f32, l: f32, h: f32| (a * l).max(a * h);
        far(p.x, lo.x, hi.x) + far(p.y, lo.y, hi.y) + far(p.z, lo.z, hi.z) + p.w < 0.0
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedral_codes_keep_unit_vectors_within_a_thousandth() {
        for k in 0..500 {
            let s = k as f32 * 0.61;
            let n = Vec3::new(
                s.sin() * (s * 0.3).cos(),
                (s * 1.7).cos(),
                (s * 0.9).sin() - 0.2,
            )
            .normalize();
            let w = oct_encode(n);
            let e = glam::Vec2::new(
                (w as u16 as i16) as f32 / 32767.0,
                ((w >> 16) as u16 as i16) as f32 / 32767.0,
            );
            let mut d = Vec3::new(e.x, e.y, 1.0 - e.x.abs() - e.y.abs());
            if d.z < 0.0 {
                let sx = if e.x >= 0.0 { 1.0 } else { -1.0 };
                let sy = if e.y >= 0.0 { 1.0 } else { -1.0 };
                d = Vec3::new((1.0 - e.y.abs()) * sx, (1.0 - e.x.abs()) * sy, d.z);
            }
            assert!(d.normalize().distance(n) < 1e-3, "{n} -> {d}");
        }
    }
}
