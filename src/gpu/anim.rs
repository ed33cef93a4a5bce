//! The animation update pass: before any method records, the moving
//! models' cages are deformed and converted by their stencil tables, their
//! model patches and shading patches (model space, each model's own copy)
//! are written over set 0's, and the keyed instances' records over theirs
//! (`glsl/anim_update.comp`, one pipeline, three dispatches: deform the
//! vertices, the point rows, then the shading rows written straight into
//! the shading patches beside the patches' points gathered and the
//! records; the CPU twin is `anim::Animation::pose`). A static scene has
//! no [`AnimGpu`] and records nothing.
//!
//! Buffers: the tables, the rest vertices and the targets are uploaded
//! once; the deformed vertices and point rows are scratch (a vec4 each:
//! one load per term);
//! each frame slot has its own host-visible deformers, instance records and
//! sequence vertices, written when the slot's frame is recorded (its
//! previous frame has finished by then).

use ash::vk;

use crate::anim::deform::GpuDeformer;
use crate::anim::{Animation, Frame};
use crate::cage::stencil::Table;
use crate::constants::*;
use crate::gpu::{AnimPush, SceneGpu, Shaders};
use crate::scene::instances::{Instance, INSTANCE_BYTES};
use crate::vk::{
    Access, Buffer, BufferBinding, Context, DescriptorSet, MemoryLocation, Pass, Pipeline,
    PipelineLayout, Recorder, Res, SetLayout, VkError, VkResult,
};

/// One frame slot's inputs.
struct SlotBuffers {
    deformers: Buffer,
    records: Buffer,
    inputs: Buffer,
    set: DescriptorSet,
}

/// The update pass of one animation on one uploaded scene.
pub struct AnimGpu {
    layout: PipelineLayout<AnimPush>,
    pipeline: Pipeline,
    statics: Vec<Buffer>,
    scratch: Vec<Buffer>,
    slots: Vec<SlotBuffers>,
    vertices: u32,
    point_rows: u32,
    shading_rows: u32,
    patches: u32,
    targets: u32,
    keyed: u32,
    /// Per model: its deformers' first index (the slot's deformer array).
    deformer_first: Vec<usize>,
    /// Per model with a sequence: its first vertex in the slot's inputs.
    input_first: Vec<Option<usize>>,
    deformer_count: usize,
    input_floats: usize,
    /// The scene's serial the set was made for.
    pub scene_serial: u64,
}

/// The whole animation's tables, inputs renamed to global indices.
struct Layout {
    rest: Vec<f32>,
    vertex_model: Vec<u32>,
    models: Vec<[u32; 4]>,
    point_rows: Vec<[u32; 4]>,
    point_terms: Vec<[u32; 2]>,
    shading_rows: Vec<[u32; 4]>,
    shading_terms: Vec<[u32; 2]>,
    patch_rows: Vec<u32>,
    targets: Vec<[u32; 4]>,
    keyed: Vec<u32>,
    deformer_first: Vec<usize>,
    input_first: Vec<Option<usize>>,
    deformer_count: usize,
    input_floats: usize,
}

/// Appends `table`'s rows as (first term, terms, reference, its own index)
/// and its terms, inputs offset by `input_base`, rows by `row_base`.
fn append(
    table: &Table,
    input_base: u32,
    row_base: u32,
    rows: &mut Vec<[u32; 4]>,
    terms: &mut Vec<[u32; 2]>,
) {
    for r in 0..table.rows() {
        let (reference, t) = table.row(r);
        let start = terms.len() as u32;
        terms.extend(t.map(|(i, w)| [i + input_base, w.to_bits()]));
        let count = terms.len() as u32 - start;
        rows.push([start, count, reference + input_base, row_base + r as u32]);
    }
}

/// Rows reordered by their number of terms within windows of
/// [`SORT_WINDOW`] rows: the invocations a device runs in lockstep (a warp,
/// llvmpipe's 8 SIMD lanes) then loop over as many terms each instead of
/// all waiting for the longest row among them, while a window's rows still
/// read neighbouring terms and points (sorting the whole table scattered
/// them: 16 cars took 5× one car's time per vertex). A row keeps its own
/// index (its `.w`, until a shading row's becomes its destination), so
/// only the order of work changes, no value.
fn by_terms(rows: &mut [[u32; 4]]) {
    rows.sort_by_key(|r| (r[3] / SORT_WINDOW, r[1], r[3]));
}

/// Rows per window of [`by_terms`].
const SORT_WINDOW: u32 = 1024;

/// The update's shader, whose set 0 is the animation set.
pub const ANIM_SHADER: &str = "anim_update.comp";

impl Layout {
    fn new(anim: &Animation) -> Self {
        let mut l = Layout {
            rest: Vec::new(),
            vertex_model: Vec::new(),
            models: Vec::new(),
            point_rows: Vec::new(),
            point_terms: Vec::new(),
            shading_rows: Vec::new(),
            shading_terms: Vec::new(),
            patch_rows: Vec::new(),
            targets: Vec::new(),
            keyed: anim.keyed.iter().map(|k| k.index as u32).collect(),
            deformer_first: Vec::new(),
            input_first: Vec::new(),
            deformer_count: 0,
            input_floats: 0,
        };
        for (m, model) in anim.models.iter().enumerate() {
            let s = &model.cage.stencils;
            let vertex_first = l.vertex_model.len() as u32;
            let row_first = l.point_rows.len() as u32;
            l.targets.push([
                l.patch_rows.len() as u32 / 16,
                model.source,
                l.patch_rows.len() as u32 / 16,
                0,
            ]);
            l.rest
                .extend(model.cage.rest.iter().flat_map(|p| p.to_array()));
            l.vertex_model
                .extend(std::iter::repeat_n(m as u32, model.cage.rest.len()));
            append(
                &s.points,
                vertex_first,
                row_first,
                &mut l.point_rows,
                &mut l.point_terms,
            );
            let shading_first = l.shading_rows.len() as u32;
            append(
                &s.shading,
                row_first,
                shading_first,
                &mut l.shading_rows,
                &mut l.shading_terms,
            );
            l.patch_rows
                .extend(s.patch_rows.iter().flat_map(|r| r.map(|x| x + row_first)));
            let input = (!model.sequence.is_empty()).then_some(l.input_floats / 3);
            if input.is_some() {
                l.input_floats += 3 * model.cage.rest.len();
            }
            l.models.push([
                l.deformer_count as u32,
                model.deform.len() as u32,
                input.map_or(ANIM_NO_SEQUENCE, |i| i as u32),
                vertex_first,
            ]);
            l.deformer_first.push(l.deformer_count);
            l.input_first.push(input);
            l.deformer_count += model.deform.len();
        }
        by_terms(&mut l.point_rows);
        by_terms(&mut l.shading_rows);
        // The write step stores a shading row at its float in set 0's
        // shading patches: found here once (its model by its own index),
        // not by a search per row in every frame.
        for row in &mut l.shading_rows {
            row[3] = shading_float(&l.targets, row[3]);
        }
        l.targets.push([l.patch_rows.len() as u32 / 16, 0, 0, 0]);
        l
    }
}

/// Where shading row `r` (vector `r % 24` of own patch `r / 24`) goes in
/// set 0's shading patches: its model's patch there (`targets`: per model,
/// its first own patch in `.z` and its first model patch in set 0 in
/// `.y`), then the vector's three floats.
fn shading_float(targets: &[[u32; 4]], r: u32) -> u32 {
    let own = r / 24;
    let model = targets.partition_point(|t| t[2] <= own) - 1;
    let dst = targets[model][1] + (own - targets[model][2]);
    SHADING_FLOATS * dst + 3 * (r % 24)
}

/// A storage buffer of `data`, or of one zero where it is empty (a binding
/// needs a buffer).
fn storage<T: bytemuck::Pod + bytemuck::Zeroable>(
    ctx: &Context,
    name: &str,
    data: &[T],
) -> VkResult<Buffer> {
    let zero = [T::zeroed()];
    let data = if data.is_empty() { &zero[..] } else { data };
    Buffer::with_data(
        ctx,
        name,
        data,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
}

/// Refuses an animation that writes beyond `scene`: a moving model's
/// patches past its model patches, or a keyed instance past its instances.
fn check_fits(anim: &Animation, scene: &SceneGpu) -> VkResult<()> {
    for m in &anim.models {
        let n = m.cage.stencils.patches() as u32;
        if m.source + n > scene.model_patches {
            return Err(VkError::Usage(format!(
                "a moving model's patches {}..{} lie beyond the scene's {} model patches",
                m.source,
                m.source + n,
                scene.model_patches
            )));
        }
    }
    if let Some(k) = anim
        .keyed
        .iter()
        .find(|k| k.index as u32 >= scene.instance_count)
    {
        return Err(VkError::Usage(format!(
            "a keyed instance ({}) beyond the scene's {} instances",
            k.index, scene.instance_count
        )));
    }
    Ok(())
}

/// Uploads the tables of `l`, in the order the set binds them from
/// `BIND_ANIM_REST` on (the first nine), then the keyed instances.
fn upload_tables(ctx: &Context, l: &Layout) -> VkResult<Vec<Buffer>> {
    Ok(vec![
        storage(ctx, "animation rest vertices", &l.rest)?,
        storage(ctx, "animation vertex models", &l.vertex_model)?,
        storage(ctx, "animation models", &l.models)?,
        storage(ctx, "animation point rows", &l.point_rows)?,
        storage(ctx, "animation point terms", &l.point_terms)?,
        storage(ctx, "animation shading rows", &l.shading_rows)?,
        storage(ctx, "animation shading terms", &l.shading_terms)?,
        storage(ctx, "animation patch rows", &l.patch_rows)?,
        storage(ctx, "animation targets", &l.targets)?,
        storage(ctx, "animation keyed instances", &l.keyed)?,
    ])
}

/// A device-local scratch buffer of `n` vec4s (at least one).
fn scratch_buffer(ctx: &Context, name: &str, n: u32) -> VkResult<Buffer> {
    Buffer::new(
        ctx,
        name,
        u64::from(n.max(1)) * 16,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::GpuOnly,
    )
}

/// A host-visible storage buffer of `bytes` bytes (at least 16), written
/// per frame.
fn host_buffer(ctx: &Context, name: String, bytes: usize) -> VkResult<Buffer> {
    Buffer::new(
        ctx,
        &name,
        bytes.max(16) as u64,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryLocation::CpuToGpu,
    )
}

/// What every slot's set binds beside the slot's own buffers: the tables,
/// the scratch and the scene's instances, patches and shading patches.
struct SharedBindings<'a> {
    set_layout: &'a SetLayout,
    statics: &'a [Buffer],
    scratch: &'a [Buffer],
    scene: &'a SceneGpu,
}

impl SharedBindings<'_> {
    /// Slot `s`'s buffers (deformers, records of `keyed` instances, inputs,
    /// sized by `l`) and its set over them and the shared buffers.
    fn slot(&self, ctx: &Context, s: usize, l: &Layout, keyed: usize) -> VkResult<SlotBuffers> {
        let deformers = host_buffer(
            ctx,
            format!("animation deformers (slot {s})"),
            l.deformer_count.max(1) * std::mem::size_of::<GpuDeformer>(),
        )?;
        let records = host_buffer(
            ctx,
            format!("animation instance records (slot {s})"),
            keyed * INSTANCE_BYTES as usize,
        )?;
        let inputs = host_buffer(
            ctx,
            format!("animation inputs (slot {s})"),
            l.input_floats * 4,
        )?;
        let (statics, scratch, scene) = (self.statics, self.scratch, self.scene);
        let mut bound = [BufferBinding::from(&statics[0]); ANIM_BINDINGS as usize];
        for (k, b) in statics[..9].iter().enumerate() {
            bound[BIND_ANIM_REST as usize + k] = b.into();
        }
        bound[BIND_ANIM_KEYED as usize] = (&statics[9]).into();
        bound[BIND_ANIM_INSTANCES as usize] = (&scene.instances).into();
        bound[BIND_ANIM_VERTS as usize] = (&scratch[0]).into();
        bound[BIND_ANIM_POINTS as usize] = (&scratch[1]).into();
        bound[BIND_ANIM_DEFORMERS as usize] = (&deformers).into();
        bound[BIND_ANIM_RECORDS as usize] = (&records).into();
        bound[BIND_ANIM_INPUTS as usize] = (&inputs).into();
        bound[BIND_ANIM_PATCHES as usize] = (&scene.patches).into();
        bound[BIND_ANIM_SHADING as usize] = (&scene.shading).into();
        let set = DescriptorSet::new(
            ctx,
            &format!("animation set (slot {s})"),
            self.set_layout,
            &bound,
        )?;
        Ok(SlotBuffers {
            deformers,
            records,
            inputs,
            set,
        })
    }
}

impl AnimGpu {
    /// Uploads `anim`'s tables for `scene` (whose patches the animated
    /// instances overwrite) with `slots` frame slots.
    pub fn new(
        ctx: &Context,
        shaders: &mut Shaders,
        anim: &Animation,
        scene: &SceneGpu,
        slots: usize,
    ) -> VkResult<Self> {
        check_fits(anim, scene)?;
        let l = Layout::new(anim);
        let set_layout = SetLayout::reflect(ctx, "animation set", 0, &[ANIM_SHADER])?;
        let layout = PipelineLayout::<AnimPush>::new(
            ctx,
            "animation layout",
            &[&set_layout],
            vk::ShaderStageFlags::COMPUTE,
        )?;
        let pipeline = shaders.compute(ctx, &layout, "animation update", ANIM_SHADER)?;
        let statics = upload_tables(ctx, &l)?;
        let vertices = l.vertex_model.len() as u32;
        let point_rows = l.point_rows.len() as u32;
        let shading_rows = l.shading_rows.len() as u32;
        let scratch = vec![
            scratch_buffer(ctx, "animation deformed vertices", vertices)?,
            scratch_buffer(ctx, "animation points", point_rows)?,
        ];
        let shared = SharedBindings {
            set_layout: &set_layout,
            statics: &statics,
            scratch: &scratch,
            scene,
        };
        let mut slot_buffers = Vec::with_capacity(slots);
        for s in 0..slots.max(1) {
            slot_buffers.push(shared.slot(ctx, s, &l, anim.keyed.len())?);
        }
        let patches = l.targets.last().map_or(0, |t| t[0]);
        Ok(Self {
            layout,
            pipeline,
            statics,
            scratch,
            slots: slot_buffers,
            vertices,
            point_rows,
            shading_rows,
            patches,
            targets: anim.models.len() as u32,
            keyed: anim.keyed.len() as u32,
            deformer_first: l.deformer_first,
            input_first: l.input_first,
            deformer_count: l.deformer_count,
            input_floats: l.input_floats,
            scene_serial: scene.serial,
        })
    }

    /// Bytes of its buffers: the tables and instance list, the scratch, and
    /// every slot's inputs.
    pub fn bytes(&self) -> u64 {
        let slots: u64 = self
            .slots
            .iter()
            .map(|s| s.deformers.size() + s.records.size() + s.inputs.size())
            .sum();
        self.statics.iter().map(Buffer::size).sum::<u64>()
            + self.scratch.iter().map(Buffer::size).sum::<u64>()
            + slots
    }

    /// Model patches written per frame.
    pub fn patches(&self) -> u32 {
        self.patches
    }

    /// Writes `frame`'s inputs into slot `slot` (its previous frame has
    /// finished) and records the three steps into `cmd`, from a barrier
    /// after every earlier command (the frame before may still read the
    /// patches) to one before every later one.
    pub fn record(
        &mut self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        slot: usize,
        frame: &Frame,
    ) -> VkResult<()> {
        let slot = slot.min(self.slots.len() - 1);
        let mut deformers = vec![GpuDeformer::default(); self.deformer_count.max(1)];
        for (m, list) in frame.deformers.iter().enumerate() {
            let first = self.deformer_first[m];
            deformers[first..first + list.len()].copy_from_slice(list);
        }
        let records: &[Instance] = &frame.records;
        let mut inputs = vec![0.0f32; self.input_floats];
        for (m, first) in self.input_first.iter().enumerate() {
            if let Some(first) = first {
                for (k, p) in frame.inputs[m].iter().enumerate() {
                    inputs[3 * (first + k)..3 * (first + k) + 3].copy_from_slice(&p.to_array());
                }
            }
        }
        let s = &mut self.slots[slot];
        s.deformers.write(ctx, 0, &deformers)?;
        s.records.write(ctx, 0, records)?;
        s.inputs.write(ctx, 0, &inputs)?;
        // The frame before may still read the patches; the steps read each
        // other's results in the model buffers their set points at.
        let mut rec = Recorder::new(ctx, cmd);
        rec.after(Res::Memory, Access::ALL);
        let max = ctx.info().limits.max_compute_work_group_count[0].max(1);
        let steps = [
            (ANIM_PASS_DEFORM, self.vertices),
            (ANIM_PASS_POINTS, self.point_rows),
            (
                ANIM_PASS_WRITE,
                self.shading_rows + self.patches + self.keyed,
            ),
        ];
        for (pass, count) in steps {
            let push = AnimPush {
                pass,
                count,
                targets: self.targets,
                rows: self.shading_rows,
                patches: self.patches,
                pad: [0; 3],
            };
            self.layout.push(cmd, &push);
            let groups = count.div_ceil(ANIM_GROUP_SIZE).clamp(1, max);
            let step = Pass::new("anim step")
                .pipeline(&self.pipeline)
                .bind(0, &s.set);
            rec.dispatch(&step, [groups, 1, 1]);
        }
        rec.hand_off(Res::Memory, Access::ALL);
        Ok(())
    }
}
