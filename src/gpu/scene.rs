//! The scene on the GPU, shared by every method and pass: the model
//! patches, their flags, their shading (tangent) patches and their weights,
//! each model once, and the instances that place them
//! (`scene::instances`), uploaded once, and one `ViewParams` per frame
//! slot, all behind descriptor set 0
//! (`glsl/common/scene.glsl`; the shading normal is evaluated by
//! `glsl/common/shading.glsl`, rational patches by
//! `glsl/common/rational.glsl`). Beside it, on the host, the scene's edge
//! table (which patch sides are one curve), for the methods that need it.

use std::sync::atomic::{AtomicU64, Ordering};

use ash::vk;

use crate::constants::{
    BIND_DISPLACEMENT, BIND_INSTANCES, BIND_MATERIALS, BIND_PATCHES, BIND_PATCH_BOXES,
    BIND_PATCH_FLAGS, BIND_ROOTS, BIND_SHADING, BIND_TEXELS, BIND_UV_PATCHES, BIND_VIEW,
    BIND_VISIBILITY, BIND_WEIGHTS, PATCH_RATIONAL, SCENE_BINDINGS, SET_SCENE, SHADING_FLOATS,
};
use crate::patch::bezier::BezierPatch;
use crate::patch::rational::{is_polynomial, Weights, UNIT_WEIGHTS};
use crate::patch::shading::ShadingPatch;
use crate::patch::view::ViewParams;
use crate::scene::adjacency::{edge_table, EdgeTable};
use crate::scene::displacement::SceneDisplacement;
use crate::scene::geometry::{SceneGeometry, SceneShading};
use crate::scene::instances::{
    cluster_blocks, cluster_set_words, root_entries, Instance, InstanceTable, INSTANCE_BYTES,
};
use crate::scene::material::SceneMaterials;
use crate::scene::pn::PnScene;
use crate::vk::{
    all_stages, Buffer, BufferBinding, Context, DescriptorSet, MemoryLocation, Pass,
    PipelineLayout, SetLayout, VkError, VkResult,
};

/// The layout of set 0: the view (a uniform buffer with a dynamic offset
/// per frame slot), the patches, their flags, their shading patches. Made
/// once per renderer;
/// every pipeline layout starts with it.
pub struct SceneLayout {
    set: SetLayout,
    stages: vk::ShaderStageFlags,
}

/// Set 0's descriptor types, binding by binding. Declared rather than
/// reflected: the view is a dynamic uniform buffer (one offset per frame
/// slot), which SPIR-V cannot say; `tests/reflect.rs` checks every
/// shader's set 0 against it.
pub fn scene_set_types() -> [vk::DescriptorType; SCENE_BINDINGS as usize] {
    let mut types = [vk::DescriptorType::STORAGE_BUFFER; SCENE_BINDINGS as usize];
    types[BIND_VIEW as usize] = vk::DescriptorType::UNIFORM_BUFFER_DYNAMIC;
    types
}

impl SceneLayout {
    /// Creates the set layout.
    pub fn new(ctx: &Context) -> VkResult<Self> {
        let stages = all_stages(ctx);
        Ok(Self {
            set: SetLayout::new(ctx, "scene set", &scene_set_types(), stages)?,
            stages,
        })
    }

    /// The set layout (set 0 of every pipeline layout).
    pub fn set_layout(&self) -> &SetLayout {
        &self.set
    }

    /// The stages that see it.
    pub fn stages(&self) -> vk::ShaderStageFlags {
        self.stages
    }

    /// A pipeline layout of set 0, then `sets` (sets 1, 2, …), then a push
    /// block of type `P` visible to `push_stages`.
    pub fn pipeline_layout<P: bytemuck::Pod>(
        &self,
        ctx: &Context,
        name: &str,
        sets: &[&SetLayout],
        push_stages: vk::ShaderStageFlags,
    ) -> VkResult<PipelineLayout<P>> {
        let mut all = vec![&self.set];
        all.extend_from_slice(sets);
        PipelineLayout::new(ctx, name, &all, push_stages)
    }
}

/// Numbers every uploaded scene, so a method that keeps data derived from
/// one (its copy of the edge table) sees when the scene was replaced.
static SCENE_SERIAL: AtomicU64 = AtomicU64::new(1);

/// The uploaded scene: the model patches, their flags, shading patches and
/// weights, the instances that place them, the per-slot views and set 0.
pub struct SceneGpu {
    /// 48 floats per model patch.
    pub patches: Buffer,
    /// One flags word per model patch.
    pub flags: Buffer,
    /// `SHADING_FLOATS` per model patch: the tangent patches of the shading
    /// normals, in model space.
    pub shading: Buffer,
    /// 16 weights per model patch for a scene with rational patches, else 16 ones.
    pub weights: Buffer,
    /// `INSTANCE_WORDS` per instance.
    pub instances: Buffer,
    /// The level kernels' depth 0 of a frame: 2 words per instance, then
    /// occlusion culling's cluster slots and their scan
    /// (`instances::root_entries`).
    pub roots: Buffer,
    /// The model-space box of each model patch, 6 floats
    /// (`InstanceTable::patch_boxes`): occlusion culling's late phase tests
    /// the clusters the early phase drew by them.
    pub patch_boxes: Buffer,
    /// Blocks of cluster slots in `roots` (`instances::cluster_blocks`).
    pub cluster_blocks: u32,
    /// Occlusion culling's verdict of the last frame: 1 word per instance.
    pub visibility: Buffer,
    /// The UV patches (per model patch), the models' material records and
    /// the albedo maps' texels (placeholders where `materials` is false).
    pub uv_patches: Buffer,
    pub material_records: Buffer,
    pub texels: Buffer,
    /// The scene has albedo maps or UVs from a cage (`SceneMaterials::in_use`).
    pub materials: bool,
    /// The displaced models' records, owners, UV bounds and height maps
    /// (`SceneDisplacement::gpu_words`; one placeholder word without).
    pub displacement: Buffer,
    /// Some model is displaced (`SceneDisplacement::in_use`).
    pub displaced: bool,
    /// The instance records as uploaded (the level schedule's CPU twin
    /// culls by their boxes).
    pub instance_records: Vec<Instance>,
    /// Patches with a weight other than 1.
    pub rational_patches: u32,
    /// Number of base patches (global ids 0..count, instance by instance).
    pub count: u32,
    /// Number of model patches (each distinct model once).
    pub model_patches: u32,
    /// Number of instances.
    pub instance_count: u32,
    /// Which patch sides are one curve (computed on the host at upload).
    pub edges: EdgeTable,
    /// This upload's number (a new scene gets a new one).
    pub serial: u64,
    /// The PN-triangle models (host copy: `cudatess` uploads what it needs).
    pub pn: PnScene,
    /// `ViewParams` per frame slot, `view_stride` bytes apart.
    views: Buffer,
    view_stride: u64,
    slots: usize,
    set: DescriptorSet,
}

impl SceneGpu {
    /// Uploads `patches`, `flags` and `shading` (one tangent-patch pair per
    /// patch, in the same order) as they are and makes room for `slots`
    /// views.
    pub fn new(
        ctx: &Context,
        layout: &SceneLayout,
        patches: &[BezierPatch],
        flags: &[u32],
        shading: &[ShadingPatch],
        slots: usize,
    ) -> VkResult<Self> {
        Self::with_weights(ctx, layout, patches, flags, shading, &[], slots)
    }

    /// [`SceneGpu::new`] with the patches' weights (`weights` empty: a
    /// polynomial scene; else one set per patch).
    pub fn with_weights(
        ctx: &Context,
        layout: &SceneLayout,
        patches: &[BezierPatch],
        flags: &[u32],
        shading: &[ShadingPatch],
        weights: &[Weights],
        slots: usize,
    ) -> VkResult<Self> {
        if !weights.is_empty() && weights.len() != patches.len() {
            return Err(VkError::Usage(format!(
                "{} patches with {} weight sets",
                patches.len(),
                weights.len()
            )));
        }
        if patches.is_empty() || patches.len() != flags.len() {
            return Err(VkError::Usage(format!(
                "{} patches with {} flag words",
                patches.len(),
                flags.len()
            )));
        }
        let table = InstanceTable::identity(patches, flags, weights);
        let materials = SceneMaterials::default();
        let displacement = SceneDisplacement::default();
        Self::upload(
            ctx,
            layout,
            &table,
            shading,
            (&materials, &displacement),
            patches,
            weights,
            slots,
        )
    }

    /// Uploads `table` (model patches, flags, weights and instances) with
    /// `shading` and `materials`' UV patches parallel to its model patches;
    /// `world` and `world_weights` are the base patches it places (the
    /// host's edge table is theirs).
    #[allow(clippy::too_many_arguments)]
    fn upload(
        ctx: &Context,
        layout: &SceneLayout,
        table: &InstanceTable,
        shading: &[ShadingPatch],
        (materials, displacement): (&SceneMaterials, &SceneDisplacement),
        world: &[BezierPatch],
        world_weights: &[Weights],
        slots: usize,
    ) -> VkResult<Self> {
        check_upload(ctx, table, shading, materials, displacement)?;
        let rational_patches = world_weights.iter().filter(|w| !is_polynomial(w)).count() as u32;
        let edges = edge_table(
            world,
            if rational_patches > 0 {
                world_weights
            } else {
                &[]
            },
        );
        let b = SceneBuffers::new(
            ctx,
            table,
            shading,
            (materials, displacement),
            rational_patches,
            slots,
        )?;
        let set = b.bind(ctx, layout, table.instances.len())?;
        Ok(Self {
            count: table.base_patches() as u32,
            model_patches: table.patches.len() as u32,
            instance_count: table.instances.len() as u32,
            patches: b.patches,
            flags: b.flags,
            shading: b.shading,
            weights: b.weights,
            instances: b.instances,
            roots: b.roots,
            patch_boxes: b.patch_boxes,
            cluster_blocks: cluster_blocks(&table.instances),
            visibility: b.visibility,
            uv_patches: b.uv_patches,
            material_records: b.material_records,
            texels: b.texels,
            materials: materials.in_use(),
            displacement: b.displacement,
            displaced: displacement.in_use(),
            instance_records: table.instances.clone(),
            rational_patches,
            edges,
            serial: SCENE_SERIAL.fetch_add(1, Ordering::Relaxed),
            pn: PnScene::default(),
            views: b.views,
            view_stride: b.view_stride,
            slots: slots.max(1),
            set,
        })
    }

    /// The scene of `geo` with `shading`: its instance table where it
    /// places exactly the geometry's patches and `shading` has the model
    /// patches' tangent patches, else the patches as they are; and the PN
    /// triangles beside the patches. A scene of PN triangles alone binds
    /// one placeholder patch (buffers cannot be empty) and counts none.
    pub fn for_geometry(
        ctx: &Context,
        layout: &SceneLayout,
        geo: &SceneGeometry,
        shading: &SceneShading,
        slots: usize,
    ) -> VkResult<Self> {
        let mut scene = if geo.patches.is_empty() && geo.pn.count() > 0 {
            let placeholder = [BezierPatch {
                pts: [glam::Vec3::ZERO; 16],
            }];
            let shading = SceneShading::from_geometry(&placeholder);
            let mut s = Self::new(ctx, layout, &placeholder, &[0], &shading.patches, slots)?;
            s.count = 0;
            s.edges = EdgeTable::default();
            s
        } else {
            if geo.patches.len() != geo.flags.len() {
                return Err(VkError::Usage(format!(
                    "{} patches with {} flag words",
                    geo.patches.len(),
                    geo.flags.len()
                )));
            }
            let instanced = shading.model.len() == geo.instances.patches.len()
                && geo.instances.places(&geo.patches, &geo.flags, &geo.weights);
            if instanced {
                Self::upload(
                    ctx,
                    layout,
                    &geo.instances,
                    &shading.model,
                    (&geo.materials, &geo.displacement),
                    &geo.patches,
                    &geo.weights,
                    slots,
                )?
            } else {
                if shading.patches.len() != geo.patches.len() {
                    return Err(VkError::Usage(format!(
                        "{} patches with {} shading patches",
                        geo.patches.len(),
                        shading.patches.len()
                    )));
                }
                Self::with_weights(
                    ctx,
                    layout,
                    &geo.patches,
                    &geo.flags,
                    &shading.patches,
                    &geo.weights,
                    slots,
                )?
            }
        };
        scene.pn = geo.pn.clone();
        Ok(scene)
    }

    /// Writes slot `slot`'s view constants (host-visible memory; the slot's
    /// previous frame must have finished).
    pub fn set_view(&mut self, ctx: &Context, slot: usize, vp: &ViewParams) -> VkResult<()> {
        if slot >= self.slots {
            return Err(VkError::Usage(format!(
                "view slot {slot} of {}",
                self.slots
            )));
        }
        let offset = slot as u64 * self.view_stride;
        self.views.write(ctx, offset, std::slice::from_ref(vp))
    }

    /// `pass` binding set 0 with slot `slot`'s view (for a compute pass,
    /// which thereby declares the scene buffers its pipeline uses).
    pub fn bind_to<'p>(&'p self, pass: Pass<'p>, slot: usize) -> Pass<'p> {
        pass.bind_dynamic(SET_SCENE, &self.set, &[self.view_offset(slot)])
    }

    /// The dynamic offset of slot `slot`'s view in the view buffer.
    fn view_offset(&self, slot: usize) -> u32 {
        (slot.min(self.slots - 1) as u64 * self.view_stride) as u32
    }

    /// Records binding set 0 for `layout` with slot `slot`'s view.
    pub fn bind(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout<impl bytemuck::Pod>,
        slot: usize,
    ) {
        let offset = self.view_offset(slot);
        self.set
            .bind(ctx, cmd, bind_point, layout, SET_SCENE, &[offset]);
    }

    /// Forgets what earlier frames found visible: the next frame culls by
    /// occlusion as the first one after the upload does (everything counts
    /// as visible). Frames in flight may still use the words; the upload
    /// waits for them on the GPU.
    pub fn reset_visibility(&mut self, ctx: &Context) -> VkResult<()> {
        let words = visibility_words(self.instance_records.len(), self.count as usize);
        self.visibility.write(ctx, 0, &words)
    }

    /// Bytes of the model patches and their flags.
    pub fn bytes(&self) -> u64 {
        self.patches.size() + self.flags.size()
    }

    /// Bytes of the instance records, their entries in the per-frame roots
    /// and the visibility kept from frame to frame.
    pub fn instance_bytes(&self) -> u64 {
        self.instances.size() + 8 * u64::from(self.instance_count) + self.visibility.size()
    }

    /// Bytes of occlusion culling's clusters and patch boxes: the cluster
    /// slots and their scan in the roots, and the model patches' boxes.
    pub fn cluster_bytes(&self) -> u64 {
        self.roots.size() - 8 * u64::from(self.instance_count) + self.patch_boxes.size()
    }

    /// Bytes of the shading patches.
    pub fn shading_bytes(&self) -> u64 {
        self.shading.size()
    }

    /// Bytes of the UV patches, material records and albedo maps, where
    /// the scene has them.
    pub fn material_bytes(&self) -> Option<u64> {
        self.materials
            .then(|| self.uv_patches.size() + self.material_records.size() + self.texels.size())
    }

    /// Bytes of the weights, where the scene has rational patches (a
    /// polynomial scene's 16 ones are not worth a line).
    pub fn weight_bytes(&self) -> Option<u64> {
        (self.rational_patches > 0).then(|| self.weights.size())
    }
}

/// Refuses an upload of `table` with `shading` before anything is
/// allocated: shading patches that are not one per model patch, or a
/// buffer beyond the device's storage-buffer range (a binding beyond the
/// range is invalid usage, not an allocation failure).
fn check_upload(
    ctx: &Context,
    table: &InstanceTable,
    shading: &[ShadingPatch],
    materials: &SceneMaterials,
    displacement: &SceneDisplacement,
) -> VkResult<()> {
    let models = table.patches.len();
    let uvs = materials.in_use() || displacement.in_use();
    if uvs && materials.uv_patches.len() != models {
        return Err(VkError::Usage(format!(
            "{models} model patches with {} UV patches",
            materials.uv_patches.len()
        )));
    }
    if displacement.in_use() && displacement.owners.len() != models {
        return Err(VkError::Usage(format!(
            "{models} model patches with {} displacement owner records",
            displacement.owners.len()
        )));
    }
    if shading.len() != models {
        return Err(VkError::Usage(format!(
            "{models} model patches with {} shading patches",
            shading.len()
        )));
    }
    let limit = u64::from(ctx.info().limits.max_storage_buffer_range);
    let n = models as u64;
    for (what, bytes) in [
        ("model patches", n * 48 * 4),
        ("shading patches", n * u64::from(SHADING_FLOATS) * 4),
        ("instances", table.instances.len() as u64 * INSTANCE_BYTES),
        ("albedo maps", 4 * materials.texel_words_len()),
        ("height maps", 4 * displacement.gpu_words_len()),
    ] {
        if bytes > limit {
            return Err(VkError::OverDeviceLimit {
                what: format!("scene's {what}"),
                bytes,
                limit,
                hint: "draw fewer models or instances",
            });
        }
    }
    Ok(())
}

/// The model patches' flags as uploaded. The shaders read a patch's
/// weights where its flags say PATCH_RATIONAL: the flag follows the
/// weights uploaded with it (a scene without rational patches keeps its
/// flags as they are).
fn uploaded_flags(table: &InstanceTable, rational_patches: u32) -> Vec<u32> {
    if rational_patches > 0 {
        table
            .flags
            .iter()
            .enumerate()
            .map(|(k, &f)| {
                let w = table.weights.get(k).unwrap_or(&UNIT_WEIGHTS);
                let bit = if is_polynomial(w) { 0 } else { PATCH_RATIONAL };
                (f & !PATCH_RATIONAL) | bit
            })
            .collect()
    } else {
        table.flags.clone()
    }
}

/// The weights as uploaded: 16 per model patch where the scene has
/// rational patches. A polynomial scene binds 16 ones: no shader reads
/// them (only patches flagged PATCH_RATIONAL have weights to read).
fn uploaded_weights(table: &InstanceTable, rational_patches: u32) -> Vec<f32> {
    if rational_patches > 0 {
        (0..table.patches.len())
            .flat_map(|k| *table.weights.get(k).unwrap_or(&UNIT_WEIGHTS))
            .collect()
    } else {
        UNIT_WEIGHTS.to_vec()
    }
}

/// The buffers of an upload, before set 0 binds them.
struct SceneBuffers {
    patches: Buffer,
    flags: Buffer,
    shading: Buffer,
    weights: Buffer,
    instances: Buffer,
    roots: Buffer,
    patch_boxes: Buffer,
    visibility: Buffer,
    uv_patches: Buffer,
    material_records: Buffer,
    texels: Buffer,
    displacement: Buffer,
    views: Buffer,
    view_stride: u64,
}

impl SceneBuffers {
    /// Uploads `table`'s model patches, flags and weights (marked and
    /// written as `rational_patches` says), `shading` and the instances,
    /// and makes the per-frame roots, the visibility and room for `slots`
    /// views.
    fn new(
        ctx: &Context,
        table: &InstanceTable,
        shading: &[ShadingPatch],
        (materials, displacement): (&SceneMaterials, &SceneDisplacement),
        rational_patches: u32,
        slots: usize,
    ) -> VkResult<Self> {
        let floats: Vec<f32> = table
            .patches
            .iter()
            .flat_map(|p| p.pts.iter().flat_map(|q| q.to_array()))
            .collect();
        let flags = uploaded_flags(table, rational_patches);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        let patches = Buffer::with_data(ctx, "model patches", &floats, storage, gpu)?;
        let flags = Buffer::with_data(ctx, "model patch flags", &flags, storage, gpu)?;
        let shading_floats: Vec<f32> = shading.iter().flat_map(|s| s.to_floats()).collect();
        let shading = Buffer::with_data(ctx, "shading patches", &shading_floats, storage, gpu)?;
        let weight_floats = uploaded_weights(table, rational_patches);
        let weights = Buffer::with_data(ctx, "patch weights", &weight_floats, storage, gpu)?;
        let instances = Buffer::with_data(ctx, "instances", table.records(), storage, gpu)?;
        let roots = Buffer::new(
            ctx,
            "roots (instances and clusters at depth 0)",
            8 * root_entries(&table.instances),
            storage,
            gpu,
        )?;
        let boxes = table.patch_boxes();
        let patch_boxes = Buffer::with_data(ctx, "model patch boxes", &boxes, storage, gpu)?;
        // Everything counts as visible before the first frame: its early
        // phase draws all that is in view and its late phase finds what
        // that hides, so the second frame culls (with nothing visible, the
        // first frame's pyramid would be empty and only the third would).
        let visibility = Buffer::with_data(
            ctx,
            "instance and cluster visibility",
            &initial_visibility(table),
            storage,
            gpu,
        )?;
        // A scene without maps or cage UVs binds one placeholder each: its
        // pipelines are specialized not to read them (SPEC_SCENE_MATERIALS).
        // A displaced scene needs the UV patches whatever its maps.
        let unused = SceneMaterials::default();
        let m = if materials.in_use() {
            materials
        } else {
            &unused
        };
        let uv_floats = if displacement.in_use() {
            materials.uv_floats()
        } else {
            m.uv_floats()
        };
        let uv_patches = Buffer::with_data(ctx, "UV patches", &uv_floats, storage, gpu)?;
        let displacement =
            Buffer::with_data(ctx, "displacement", &displacement.gpu_words(), storage, gpu)?;
        let material_records =
            Buffer::with_data(ctx, "material records", &m.material_words(), storage, gpu)?;
        let texels = Buffer::with_data(ctx, "albedo texels", &m.texel_words(), storage, gpu)?;
        let align = ctx.info().limits.min_uniform_buffer_offset_alignment.max(1);
        let view_stride = VIEW_BYTES.div_ceil(align) * align;
        let views = Buffer::new(
            ctx,
            "view params (per frame slot)",
            view_stride * slots.max(1) as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        Ok(Self {
            patches,
            flags,
            shading,
            weights,
            instances,
            roots,
            patch_boxes,
            visibility,
            uv_patches,
            material_records,
            texels,
            displacement,
            views,
            view_stride,
        })
    }

    /// Set 0 over these buffers: one view (`ViewParams`, at a dynamic
    /// offset per slot) and the first `instances` instance records.
    fn bind(
        &self,
        ctx: &Context,
        layout: &SceneLayout,
        instances: usize,
    ) -> VkResult<DescriptorSet> {
        let mut bound = [BufferBinding::from(&self.patches); SCENE_BINDINGS as usize];
        bound[BIND_VIEW as usize] = BufferBinding {
            buffer: &self.views,
            range: VIEW_BYTES,
        };
        bound[BIND_PATCHES as usize] = BufferBinding::from(&self.patches);
        bound[BIND_PATCH_FLAGS as usize] = BufferBinding::from(&self.flags);
        bound[BIND_SHADING as usize] = BufferBinding::from(&self.shading);
        bound[BIND_WEIGHTS as usize] = BufferBinding::from(&self.weights);
        bound[BIND_INSTANCES as usize] = BufferBinding {
            buffer: &self.instances,
            range: instances as u64 * INSTANCE_BYTES,
        };
        bound[BIND_ROOTS as usize] = BufferBinding::from(&self.roots);
        bound[BIND_PATCH_BOXES as usize] = BufferBinding::from(&self.patch_boxes);
        bound[BIND_VISIBILITY as usize] = BufferBinding::from(&self.visibility);
        bound[BIND_UV_PATCHES as usize] = BufferBinding::from(&self.uv_patches);
        bound[BIND_MATERIALS as usize] = BufferBinding::from(&self.material_records);
        bound[BIND_TEXELS as usize] = BufferBinding::from(&self.texels);
        bound[BIND_DISPLACEMENT as usize] = BufferBinding::from(&self.displacement);
        DescriptorSet::new(ctx, "scene set", layout.set_layout(), &bound)
    }
}

/// Bytes of one slot's `ViewParams` (the view binding's range; slots lie
/// `view_stride` apart).
const VIEW_BYTES: u64 = std::mem::size_of::<ViewParams>() as u64;

/// The visibility buffer before the first frame (`glsl/levels/level.glsl`):
/// every instance and every cluster of base patches visible, parity 0. A
/// word per instance, the parity, then two sets of a bit per cluster of up
/// to VISIBILITY_CLUSTER base patches of one instance (`cluster_id`).
fn initial_visibility(table: &InstanceTable) -> Vec<u32> {
    visibility_words(table.instances.len(), table.base_patches())
}

/// [`initial_visibility`] for `instances` instances of `base_patches`
/// base patches in all.
fn visibility_words(instances: usize, base_patches: usize) -> Vec<u32> {
    let instances = instances.max(1);
    let set = cluster_set_words(instances, base_patches);
    let mut words = vec![1u32; instances];
    words.push(0);
    words.extend(std::iter::repeat_n(u32::MAX, 2 * set));
    words
}
