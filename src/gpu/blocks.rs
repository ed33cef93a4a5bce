//! The constant blocks the host hands to shaders that more than one method
//! uses: one push-constant block per pass family, each the twin of a GLSL
//! block of the same name, plus the criterion's [`ViewParams`] uniform
//! block. A method's own blocks live in its folder (`push.rs`), declared
//! with the same macro and listed by its registry entry. [`GpuBlock`] lists each Rust
//! struct's fields with their offsets so a test can hold them against the
//! blocks reflected from the compiled SPIR-V (`tests/blocks.rs`).

use bytemuck::{Pod, Zeroable};

use crate::patch::view::ViewParams;

/// One field of a block as the host lays it out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockField {
    /// Field name (the GLSL member has the same name).
    pub name: &'static str,
    /// Byte offset.
    pub offset: u32,
    /// Byte size.
    pub size: u32,
}

/// A host struct that mirrors a GLSL block member for member.
pub trait GpuBlock: Pod {
    /// The GLSL block (type) name it mirrors.
    const GLSL_NAME: &'static str;
    /// Every field in declaration order.
    fn fields() -> Vec<BlockField>;
}

/// `size_of` the field a projection closure points at.
#[doc(hidden)]
pub fn field_size<T, F>(_: fn(&T) -> &F) -> u32 {
    std::mem::size_of::<F>() as u32
}

/// Implements [`GpuBlock`] for `$ty`, mirroring GLSL block `$glsl`, from
/// its field list.
macro_rules! gpu_block {
    ($ty:ty, $glsl:literal, [$($field:ident),* $(,)?]) => {
        impl $crate::gpu::blocks::GpuBlock for $ty {
            const GLSL_NAME: &'static str = $glsl;
            fn fields() -> Vec<$crate::gpu::blocks::BlockField> {
                vec![$($crate::gpu::blocks::BlockField {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($ty, $field) as u32,
                    size: $crate::gpu::blocks::field_size(|b: &$ty| &b.$field),
                }),*]
            }
        }
    };
}
// For the methods' own blocks, in their folders.
pub(crate) use gpu_block;

/// Push constants of every draw: the ready-list paths (mesh, fallback
/// expansion and vertex stages) and the self-drawing methods' grids; the
/// fragment stage reads the shading fields (`DrawPush` in
/// `glsl/common/draw.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct DrawPush {
    /// World → Vulkan clip space, column-major.
    pub view_proj: [f32; 16],
    /// Direction towards the light (xyz); w: for `SHADE_DISTANCE` the
    /// distance coded as 1.0.
    pub light_dir: [f32; 4],
    /// `SHADE_*`.
    pub shade: u32,
    /// Entries the list being drawn can hold (ready list, visible patches).
    pub capacity: u32,
    /// Write world positions to the capture buffer (validation).
    pub capture_enabled: u32,
    /// Grid cells per patch side (grid draws; 0 otherwise).
    pub grid: u32,
    /// The fallback path: which chunk of `FALLBACK_CHUNK_NODES` ready
    /// entries (from the draw's first) is expanded and drawn (0 otherwise).
    pub chunk: u32,
    /// Unused (the block is a whole number of 16-byte rows).
    pub pad: [u32; 3],
}
gpu_block!(
    DrawPush,
    "DrawPush",
    [
        view_proj,
        light_dir,
        shade,
        capacity,
        capture_enabled,
        grid,
        chunk,
        pad
    ]
);

/// Push constants of the animation update pass (`AnimPush` in
/// `glsl/common/anim.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct AnimPush {
    /// `ANIM_PASS_*`.
    pub pass: u32,
    /// Items of this step (vertices, point rows; the write step: shading
    /// rows, model patches, keyed instance records).
    pub count: u32,
    /// Deforming models (the write step's binary searches).
    pub targets: u32,
    /// The write step: shading rows (its first items).
    pub rows: u32,
    /// The write step: model patches (the items after the rows).
    pub patches: u32,
    /// Padding.
    pub pad: [u32; 3],
}
gpu_block!(
    AnimPush,
    "AnimPush",
    [pass, count, targets, rows, patches, pad]
);
gpu_block!(
    crate::anim::deform::GpuDeformer,
    "AnimDeformer",
    [kind, axis, other, pad, center, p]
);

/// Push constants of the ready-list passes that are not draws: the sort
/// (`glsl/sort.comp`) and the §4.4 check (`glsl/reorder_check.comp`)
/// (`ListPush` in `glsl/common/ready.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct ListPush {
    /// Entries in the ready list.
    pub ready_capacity: u32,
    /// Sort: which pass.
    pub mode: u32,
    /// Sort: bitonic stage.
    pub k: u32,
    /// Sort: compare distance.
    pub j: u32,
}
gpu_block!(ListPush, "ListPush", [ready_capacity, mode, k, j]);

gpu_block!(
    ViewParams,
    "ViewParams",
    [depth_row, planes, eye, eps_k, near, w_orth, w_par, l_max, flags, width, height, clip]
);

/// Push constants of the depth pyramid's passes (`HizPush` in
/// `glsl/common/hiz_pass.glsl`): level `dst` from level `src` (or from the
/// depth image for level 0).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct HizPush {
    /// First float of the level read (unused for level 0).
    pub src_offset: u32,
    /// First float of the level written.
    pub dst_offset: u32,
    /// Size of the level read, in texels.
    pub src_width: u32,
    /// See `src_width`.
    pub src_height: u32,
    /// Size of the level written.
    pub dst_width: u32,
    /// See `dst_width`.
    pub dst_height: u32,
    /// Samples per pixel of the depth image (level 0).
    pub samples: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}
gpu_block!(
    HizPush,
    "HizPush",
    [src_offset, dst_offset, src_width, src_height, dst_width, dst_height, samples, pad]
);

gpu_block!(
    crate::scene::instances::Instance,
    "Instance",
    [rows, first, source, count, flags, lo, hi]
);

/// A block as the reflection test sees it: its GLSL name, its size in
/// bytes and its fields.
pub type BlockEntry = (&'static str, u32, Vec<BlockField>);

/// `T`'s entry; a method's registry entry lists its blocks as these
/// (`MethodInfo::blocks`).
pub fn block<T: GpuBlock>() -> BlockEntry {
    (T::GLSL_NAME, std::mem::size_of::<T>() as u32, T::fields())
}

/// The blocks more than one method's shaders use, with their GLSL names and
/// fields; `methods::all_blocks` adds each method's own.
pub fn shared_blocks() -> Vec<BlockEntry> {
    vec![
        block::<DrawPush>(),
        block::<ListPush>(),
        block::<AnimPush>(),
        block::<crate::anim::deform::GpuDeformer>(),
        block::<HizPush>(),
        block::<ViewParams>(),
        block::<crate::scene::instances::Instance>(),
    ]
}
