//! Descriptor set layouts, pipeline layouts and descriptor sets.
//!
//! Every pass binds a few small sets (the scene set every pass shares, then
//! the buffers of its own pass family) and pushes its own constant block, so
//! a new pass adds a set or a push block instead of growing one union of
//! everything.

use super::context::{Context, Core};
use super::error::{VkError, VkResult, VkResultExt};
use super::memory::Buffer;
use super::reflect::{reflect, Reflection};
use super::shader::load_spirv;
use ash::vk;
use std::marker::PhantomData;
use std::sync::Arc;

/// Every shader stage the device has: a layout's stage flags never name
/// one it lacks (the validation layer refuses mesh stages on a device
/// without mesh shaders).
pub fn all_stages(ctx: &Context) -> vk::ShaderStageFlags {
    let info = ctx.info();
    let mut s = vk::ShaderStageFlags::COMPUTE
        | vk::ShaderStageFlags::VERTEX
        | vk::ShaderStageFlags::FRAGMENT;
    if info.has_mesh_shader() {
        s |= vk::ShaderStageFlags::TASK_EXT | vk::ShaderStageFlags::MESH_EXT;
    }
    if info.features.tessellation_shader {
        s |= vk::ShaderStageFlags::TESSELLATION_CONTROL
            | vk::ShaderStageFlags::TESSELLATION_EVALUATION;
    }
    s
}

/// One binding of a set layout.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LayoutBinding {
    /// Its descriptor type.
    pub ty: vk::DescriptorType,
    /// The stages that may read it.
    pub stages: vk::ShaderStageFlags,
}

/// A descriptor set layout whose binding `i` is `bindings[i]` (one
/// descriptor each).
pub struct SetLayout {
    core: Arc<Core>,
    handle: vk::DescriptorSetLayout,
    types: Vec<vk::DescriptorType>,
    bindings: Vec<LayoutBinding>,
    name: String,
}

impl SetLayout {
    /// Creates the layout, every binding visible to `stages`.
    pub fn new(
        ctx: &Context,
        name: &str,
        types: &[vk::DescriptorType],
        stages: vk::ShaderStageFlags,
    ) -> VkResult<Self> {
        let bindings: Vec<_> = types
            .iter()
            .map(|&ty| LayoutBinding { ty, stages })
            .collect();
        Self::with_bindings(ctx, name, &bindings)
    }

    /// Set `set` of the shaders `shaders` (GLSL file names, loaded with
    /// [`load_spirv`]): each binding any of them declares, visible to the
    /// stages that declare it (those the device has). Every pipeline that
    /// uses the layout must be made from shaders in the list. Refuses
    /// shaders that disagree on a binding's type, arrays of descriptors and
    /// gaps (binding `i` of a set is element `i` of what
    /// [`DescriptorSet::new`] is given).
    pub fn reflect(ctx: &Context, name: &str, set: u32, shaders: &[&str]) -> VkResult<Self> {
        let reflected = shaders
            .iter()
            .map(|s| Ok((*s, reflect_shader(s)?)))
            .collect::<VkResult<Vec<_>>>()?;
        let refs: Vec<_> = reflected.iter().map(|(s, r)| (*s, r)).collect();
        let mut bindings = set_bindings(name, set, &refs)?;
        for b in &mut bindings {
            b.stages &= all_stages(ctx);
        }
        Self::with_bindings(ctx, name, &bindings)
    }

    fn with_bindings(ctx: &Context, name: &str, bindings: &[LayoutBinding]) -> VkResult<Self> {
        let info: Vec<_> = bindings
            .iter()
            .enumerate()
            .map(|(i, b)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(i as u32)
                    .descriptor_type(b.ty)
                    .descriptor_count(1)
                    .stage_flags(b.stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&info);
        let handle = unsafe { ctx.device().create_descriptor_set_layout(&info, None) }
            .ctx(&format!("vkCreateDescriptorSetLayout({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
            types: bindings.iter().map(|b| b.ty).collect(),
            bindings: bindings.to_vec(),
            name: name.to_owned(),
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::DescriptorSetLayout {
        self.handle
    }

    /// Descriptor type per binding.
    pub fn types(&self) -> &[vk::DescriptorType] {
        &self.types
    }
}

impl Drop for SetLayout {
    fn drop(&mut self) {
        unsafe {
            self.core
                .device
                .destroy_descriptor_set_layout(self.handle, None)
        };
    }
}

/// The reflection of shader `name` (a GLSL file name).
pub fn reflect_shader(name: &str) -> VkResult<Reflection> {
    let words = load_spirv(name)?;
    reflect(&words).map_err(|reason| VkError::Spirv {
        path: format!("spirv/{name}.spv").into(),
        reason,
    })
}

/// Set `set`'s bindings as the union over `shaders` (name, reflection):
/// binding `i` of the result is binding `i` of the set, visible to the
/// stages of every shader that declares it. `layout` names the set in
/// errors: two shaders giving one binding different types, an array of
/// descriptors, a binding no shader declares below the highest one.
pub fn set_bindings(
    layout: &str,
    set: u32,
    shaders: &[(&str, &Reflection)],
) -> VkResult<Vec<LayoutBinding>> {
    let mut out: Vec<Option<(LayoutBinding, &str)>> = Vec::new();
    for &(shader, r) in shaders {
        for (&(s, binding), &(ty, count)) in &r.bindings {
            if s != set {
                continue;
            }
            if count != 1 {
                return Err(VkError::Usage(format!(
                    "{shader} declares binding {binding} of set {set} (`{layout}`) as an array \
                     of {count} descriptors; sets here hold one descriptor per binding"
                )));
            }
            let i = binding as usize;
            if out.len() <= i {
                out.resize(i + 1, None);
            }
            match &mut out[i] {
                Some((b, _)) if b.ty == ty => b.stages |= r.stages,
                Some((b, first)) => {
                    return Err(VkError::Usage(format!(
                        "binding {binding} of set {set} (`{layout}`) is {:?} in {first} but \
                         {ty:?} in {shader}",
                        b.ty
                    )))
                }
                slot @ None => {
                    let stages = r.stages;
                    *slot = Some((LayoutBinding { ty, stages }, shader));
                }
            }
        }
    }
    out.into_iter()
        .enumerate()
        .map(|(i, b)| {
            b.map(|(b, _)| b).ok_or_else(|| {
                let names: Vec<_> = shaders.iter().map(|(s, _)| *s).collect();
                VkError::Usage(format!(
                    "no shader of `{layout}` ({}) declares binding {i} of set {set}",
                    names.join(", ")
                ))
            })
        })
        .collect()
}

/// The type a shader declares for a binding of type `ty`: dynamic offsets
/// are the host's choice, invisible in SPIR-V.
pub fn undynamic(ty: vk::DescriptorType) -> vk::DescriptorType {
    match ty {
        vk::DescriptorType::UNIFORM_BUFFER_DYNAMIC => vk::DescriptorType::UNIFORM_BUFFER,
        vk::DescriptorType::STORAGE_BUFFER_DYNAMIC => vk::DescriptorType::STORAGE_BUFFER,
        t => t,
    }
}

/// The push block of a pipeline layout that pushes nothing.
pub type NoPush = ();

/// A pipeline layout: set layouts plus one push-constant range at offset
/// 0 holding a `P` (none for [`NoPush`]). Pushing takes a `P`, so a pass
/// cannot push a block of another type; pipelines check at creation that
/// their shaders declare a push block of `P`'s size.
pub struct PipelineLayout<P: bytemuck::Pod = NoPush> {
    core: Arc<Core>,
    handle: vk::PipelineLayout,
    push_stages: vk::ShaderStageFlags,
    name: String,
    /// The bindings of each set, to check shaders against.
    sets: Vec<Vec<LayoutBinding>>,
    push: PhantomData<fn(&P)>,
}

impl<P: bytemuck::Pod> PipelineLayout<P> {
    /// Creates the layout of `sets`, with `P` visible to `push_stages`.
    pub fn new(
        ctx: &Context,
        name: &str,
        sets: &[&SetLayout],
        push_stages: vk::ShaderStageFlags,
    ) -> VkResult<Self> {
        let push_size = Self::push_size();
        let limit = ctx.info().limits.max_push_constants_size;
        if push_size % 4 != 0 || push_size > limit {
            return Err(VkError::Usage(format!(
                "push constants of `{name}` are {push_size} bytes; they must be a multiple of 4 \
                 and at most {limit} on this device"
            )));
        }
        let set_handles: Vec<_> = sets.iter().map(|s| s.handle).collect();
        let ranges = [vk::PushConstantRange::default()
            .stage_flags(push_stages)
            .offset(0)
            .size(push_size)];
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&set_handles)
            .push_constant_ranges(if push_size > 0 { &ranges } else { &[] });
        let handle = unsafe { ctx.device().create_pipeline_layout(&info, None) }
            .ctx(&format!("vkCreatePipelineLayout({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
            push_stages,
            name: name.to_owned(),
            sets: sets.iter().map(|s| s.bindings.clone()).collect(),
            push: PhantomData,
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::PipelineLayout {
        self.handle
    }

    /// Bytes of the push-constant range: the size of `P`.
    pub fn push_size() -> u32 {
        std::mem::size_of::<P>() as u32
    }

    /// Refuses a shader that does not fit the layout: a push block that is
    /// not a `P` (a shader without one may share the layout), or a
    /// binding the layout lacks, gives another type or hides from the
    /// shader's stage. Pipelines call it at creation, so a shader and its
    /// layout that drift apart fail there, naming both.
    pub fn check_shader(&self, shader: &str, reflected: &Reflection) -> VkResult<()> {
        let want = Self::push_size();
        if reflected.push_size != 0 && reflected.push_size != want {
            return Err(VkError::Usage(format!(
                "{shader} declares a {}-byte push-constant block but the layout `{}` pushes \
                 {want} bytes ({})",
                reflected.push_size,
                self.name,
                std::any::type_name::<P>()
            )));
        }
        for (&(set, binding), &(ty, _)) in &reflected.bindings {
            let have = self
                .sets
                .get(set as usize)
                .and_then(|s| s.get(binding as usize));
            let fits =
                have.is_some_and(|b| undynamic(b.ty) == ty && b.stages.contains(reflected.stages));
            if !fits {
                return Err(VkError::Usage(format!(
                    "{shader} reads binding {binding} of set {set} as {ty:?} from {:?}, but the \
                     layout `{}` has {have:?} there",
                    reflected.stages, self.name
                )));
            }
        }
        Ok(())
    }

    /// Records pushing `block`.
    pub fn push(&self, cmd: vk::CommandBuffer, block: &P) {
        let data = bytemuck::bytes_of(block);
        if !data.is_empty() {
            unsafe {
                self.core
                    .device
                    .cmd_push_constants(cmd, self.handle, self.push_stages, 0, data)
            };
        }
    }
}

impl<P: bytemuck::Pod> Drop for PipelineLayout<P> {
    fn drop(&mut self) {
        unsafe { self.core.device.destroy_pipeline_layout(self.handle, None) };
    }
}

/// A buffer bound to one descriptor: the whole buffer, or for a dynamic
/// uniform buffer the `range` bytes one dynamic offset selects.
#[derive(Clone, Copy)]
pub struct BufferBinding<'a> {
    /// The buffer.
    pub buffer: &'a Buffer,
    /// Bytes visible through the descriptor (`vk::WHOLE_SIZE` for all).
    pub range: u64,
}

impl<'a> From<&'a Buffer> for BufferBinding<'a> {
    fn from(buffer: &'a Buffer) -> Self {
        Self {
            buffer,
            range: vk::WHOLE_SIZE,
        }
    }
}

/// What one descriptor points at: a buffer, or an image read through a
/// sampler (a `COMBINED_IMAGE_SAMPLER` binding, e.g. a depth image).
#[derive(Clone, Copy)]
pub enum Binding<'a> {
    /// A storage or uniform buffer.
    Buffer(BufferBinding<'a>),
    /// An image view in `layout`, read through `sampler`.
    Image {
        /// The view.
        view: vk::ImageView,
        /// Its layout when the set is used.
        layout: vk::ImageLayout,
        /// The sampler.
        sampler: &'a Sampler,
    },
}

impl<'a> From<BufferBinding<'a>> for Binding<'a> {
    fn from(b: BufferBinding<'a>) -> Self {
        Binding::Buffer(b)
    }
}

impl<'a> From<&'a Buffer> for Binding<'a> {
    fn from(b: &'a Buffer) -> Self {
        Binding::Buffer(b.into())
    }
}

/// A nearest-texel, clamp-to-edge sampler (shaders read it with
/// `texelFetch`, so filtering never applies).
pub struct Sampler {
    core: Arc<Core>,
    handle: vk::Sampler,
}

impl Sampler {
    /// Creates the sampler.
    pub fn nearest(ctx: &Context, name: &str) -> VkResult<Self> {
        let clamp = vk::SamplerAddressMode::CLAMP_TO_EDGE;
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(clamp)
            .address_mode_v(clamp)
            .address_mode_w(clamp)
            .max_lod(0.0);
        let handle = unsafe { ctx.device().create_sampler(&info, None) }
            .ctx(&format!("vkCreateSampler({name})"))?;
        ctx.set_name(handle, name);
        Ok(Self {
            core: ctx.core.clone(),
            handle,
        })
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::Sampler {
        self.handle
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_sampler(self.handle, None) };
    }
}

/// One descriptor set with the pool it came from; freed with it. Each set
/// has its own small pool: sets are few and long-lived here.
pub struct DescriptorSet {
    core: Arc<Core>,
    pool: vk::DescriptorPool,
    handle: vk::DescriptorSet,
    /// The buffer each binding points at (`None` for an image), so that a
    /// pass binding the set declares what it binds.
    buffers: Vec<Option<vk::Buffer>>,
}

impl DescriptorSet {
    /// Allocates a set of `layout` and points binding `i` at `buffers[i]`.
    pub fn new(
        ctx: &Context,
        name: &str,
        layout: &SetLayout,
        buffers: &[BufferBinding<'_>],
    ) -> VkResult<Self> {
        let bindings: Vec<Binding<'_>> = buffers.iter().map(|&b| b.into()).collect();
        Self::with_bindings(ctx, name, layout, &bindings)
    }

    /// Allocates a set of `layout` and points binding `i` at
    /// `bindings[i]` (buffers and sampled images).
    pub fn with_bindings(
        ctx: &Context,
        name: &str,
        layout: &SetLayout,
        buffers: &[Binding<'_>],
    ) -> VkResult<Self> {
        if buffers.len() != layout.types.len() {
            return Err(VkError::Usage(format!(
                "the set layout `{}` has {} bindings but {} buffers were given for `{name}`",
                layout.name,
                layout.types.len(),
                buffers.len()
            )));
        }
        let pool = create_pool(ctx, name, &layout.types)?;
        let layouts = [layout.handle()];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool)
            .set_layouts(&layouts);
        let allocated = unsafe { ctx.device().allocate_descriptor_sets(&info) }
            .ctx(&format!("vkAllocateDescriptorSets({name})"));
        let handle = match allocated {
            Ok(sets) => sets[0],
            Err(e) => {
                unsafe { ctx.device().destroy_descriptor_pool(pool, None) };
                return Err(e);
            }
        };
        ctx.set_name(handle, name);
        write(ctx, handle, &layout.types, buffers);
        let buffers = buffers
            .iter()
            .map(|b| match b {
                Binding::Buffer(b) => Some(b.buffer.handle()),
                Binding::Image { .. } => None,
            })
            .collect();
        Ok(Self {
            core: ctx.core.clone(),
            pool,
            handle,
            buffers,
        })
    }

    /// The buffer each binding points at (`None`: an image).
    pub fn buffers(&self) -> &[Option<vk::Buffer>] {
        &self.buffers
    }

    /// The Vulkan handle.
    pub fn handle(&self) -> vk::DescriptorSet {
        self.handle
    }

    /// Records binding this set as set `index` of `layout`, with one dynamic
    /// offset per dynamic descriptor.
    pub fn bind(
        &self,
        ctx: &Context,
        cmd: vk::CommandBuffer,
        bind_point: vk::PipelineBindPoint,
        layout: &PipelineLayout<impl bytemuck::Pod>,
        index: u32,
        dynamic_offsets: &[u32],
    ) {
        unsafe {
            ctx.device().cmd_bind_descriptor_sets(
                cmd,
                bind_point,
                layout.handle(),
                index,
                &[self.handle],
                dynamic_offsets,
            )
        };
    }
}

impl Drop for DescriptorSet {
    fn drop(&mut self) {
        if !self.core.may_free() {
            return;
        }
        unsafe { self.core.device.destroy_descriptor_pool(self.pool, None) };
    }
}

/// A pool with room for exactly one set of these descriptor types.
fn create_pool(
    ctx: &Context,
    name: &str,
    types: &[vk::DescriptorType],
) -> VkResult<vk::DescriptorPool> {
    let mut sizes: Vec<vk::DescriptorPoolSize> = Vec::new();
    for &ty in types {
        match sizes.iter_mut().find(|s| s.ty == ty) {
            Some(s) => s.descriptor_count += 1,
            None => sizes.push(vk::DescriptorPoolSize::default().ty(ty).descriptor_count(1)),
        }
    }
    let info = vk::DescriptorPoolCreateInfo::default()
        .max_sets(1)
        .pool_sizes(&sizes);
    let pool = unsafe { ctx.device().create_descriptor_pool(&info, None) }
        .ctx(&format!("vkCreateDescriptorPool({name})"))?;
    ctx.set_name(pool, name);
    Ok(pool)
}

/// Points binding `i` of `set` at `bindings[i]` with the layout's types.
fn write(
    ctx: &Context,
    set: vk::DescriptorSet,
    types: &[vk::DescriptorType],
    bindings: &[Binding<'_>],
) {
    // One info per write, built first: each write points into these vectors.
    let buffers: Vec<[vk::DescriptorBufferInfo; 1]> = bindings
        .iter()
        .map(|b| match b {
            Binding::Buffer(b) => [vk::DescriptorBufferInfo::default()
                .buffer(b.buffer.handle())
                .offset(0)
                .range(b.range)],
            Binding::Image { .. } => [vk::DescriptorBufferInfo::default()],
        })
        .collect();
    let images: Vec<[vk::DescriptorImageInfo; 1]> = bindings
        .iter()
        .map(|b| match b {
            Binding::Image {
                view,
                layout,
                sampler,
            } => [vk::DescriptorImageInfo::default()
                .image_view(*view)
                .image_layout(*layout)
                .sampler(sampler.handle())],
            Binding::Buffer(_) => [vk::DescriptorImageInfo::default()],
        })
        .collect();
    let writes: Vec<_> = bindings
        .iter()
        .zip(types)
        .enumerate()
        .map(|(i, (b, &ty))| {
            let w = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(i as u32)
                .descriptor_type(ty);
            match b {
                Binding::Buffer(_) => w.buffer_info(&buffers[i]),
                Binding::Image { .. } => w.image_info(&images[i]),
            }
        })
        .collect();
    unsafe { ctx.device().update_descriptor_sets(&writes, &[]) };
}
