//! The constant blocks the host hands to shaders: one push-constant block
//! per pass family, each the twin of a GLSL block of the same name, plus the
//! criterion's [`ViewParams`] uniform block. [`GpuBlock`] lists each Rust
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
        impl GpuBlock for $ty {
            const GLSL_NAME: &'static str = $glsl;
            fn fields() -> Vec<BlockField> {
                vec![$(BlockField {
                    name: stringify!($field),
                    offset: std::mem::offset_of!($ty, $field) as u32,
                    size: field_size(|b: &$ty| &b.$field),
                }),*]
            }
        }
    };
}

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

/// Push constants of the queue kernel (`SubdivPush` in
/// `glsl/subdiv/queue.glsl`, `subdiv --kernel queue`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct SubdivPush {
    /// Entries in the ready list.
    pub ready_capacity: u32,
    /// Entries in the work queue.
    pub queue_capacity: u32,
    /// Base patches.
    pub patch_count: u32,
    /// Polls without any progress anywhere before the kernel gives up with
    /// `ERR_ITERATION_CAP`.
    pub idle_poll_cap: u32,
    /// Deque entries a workgroup uses (at most `SUBDIV_LOCAL_CAP`).
    pub local_cap: u32,
    /// Base patches per claim (0: spread over the workgroups).
    pub base_batch: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 2],
}
gpu_block!(
    SubdivPush,
    "SubdivPush",
    [
        ready_capacity,
        queue_capacity,
        patch_count,
        idle_poll_cap,
        local_cap,
        base_batch,
        pad
    ]
);

/// Push constants of the level kernels: the persistent one, the per-depth
/// rounds and their first step (`LevelPush` in `glsl/levels/level.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LevelPush {
    /// Base patches (the nodes of depth 0).
    pub patch_count: u32,
    /// Nodes per round at most (a multiple of `LEVEL_GROUP_SIZE`).
    pub chunk: u32,
    /// Entries in the ready list.
    pub ready_capacity: u32,
    /// Depths with a region in the node memory.
    pub levels: u32,
    /// Persistent kernel: polls without progress before its watchdog trips.
    pub watchdog_polls: u32,
    /// Persistent kernel: polls of an unchanged join count before the
    /// occupancy window closes.
    pub join_polls: u32,
    /// Persistent kernel: workgroups launched.
    pub launched: u32,
    /// `FAULT_*` bits (tests).
    pub faults: u32,
    /// Per-depth rounds: blocks per workgroup.
    pub group_blocks: u32,
    /// `PHASE_*`: one pass, or a phase of occlusion culling.
    pub phase: u32,
    /// Blocks of 64 cluster slots the roots buffer holds after its
    /// instance entries (occlusion culling's cluster filter).
    pub cluster_blocks: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}
gpu_block!(
    LevelPush,
    "LevelPush",
    [
        patch_count,
        chunk,
        ready_capacity,
        levels,
        watchdog_polls,
        join_polls,
        launched,
        faults,
        group_blocks,
        phase,
        cluster_blocks,
        pad
    ]
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

/// Push constants of the ground truth's culling pass (`GridPush` in
/// `glsl/ground_truth/cull.comp`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct GridPush {
    /// Base patches.
    pub patch_count: u32,
    /// Indices per patch (6 per grid cell).
    pub indices_per_patch: u32,
    /// Base patches one part of the frame draws.
    pub patches_per_part: u32,
    /// Padding to 16 bytes.
    pub pad: u32,
}
gpu_block!(
    GridPush,
    "GridPush",
    [patch_count, indices_per_patch, patches_per_part, pad]
);

/// Push constants of cudatess's compute passes (`CtPush` in
/// `glsl/cudatess/push.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct CtPush {
    /// Base patches.
    pub patch_count: u32,
    /// Vertices the vertex buffer holds.
    pub vertex_capacity: u32,
    /// Indices the index buffer holds.
    pub index_capacity: u32,
    /// `CT_OPT_*`.
    pub options: u32,
    /// Scan: the level's first entry.
    pub scan_offset: u32,
    /// Scan: entries in the level.
    pub scan_count: u32,
    /// Scan: the first entry of the level its block sums go to (`u32::MAX`:
    /// none, the level fits one block).
    pub scan_sums: u32,
    /// Scan: `CT_SCAN_PASS_*`.
    pub pass: u32,
    /// PN triangles (their records and scan entries follow the patches').
    pub tri_count: u32,
    /// Padding to 16 bytes.
    pub pad: [u32; 3],
}
gpu_block!(
    CtPush,
    "CtPush",
    [
        patch_count,
        vertex_capacity,
        index_capacity,
        options,
        scan_offset,
        scan_count,
        scan_sums,
        pass,
        tri_count,
        pad
    ]
);

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

/// Every host block with its GLSL name and fields, for the reflection test.
pub fn all_blocks() -> Vec<(&'static str, u32, Vec<BlockField>)> {
    fn entry<T: GpuBlock>() -> (&'static str, u32, Vec<BlockField>) {
        (T::GLSL_NAME, std::mem::size_of::<T>() as u32, T::fields())
    }
    vec![
        entry::<DrawPush>(),
        entry::<SubdivPush>(),
        entry::<LevelPush>(),
        entry::<ListPush>(),
        entry::<GridPush>(),
        entry::<CtPush>(),
        entry::<AnimPush>(),
        entry::<crate::anim::deform::GpuDeformer>(),
        entry::<HizPush>(),
        entry::<ViewParams>(),
        entry::<crate::scene::instances::Instance>(),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_cover_each_block_without_gaps() {
        for (name, size, fields) in all_blocks() {
            let mut end = 0;
            for f in &fields {
                assert_eq!(f.offset, end, "{name}.{} starts after a gap", f.name);
                end = f.offset + f.size;
            }
            assert_eq!(end, size, "{name}: fields do not fill the struct");
            assert_eq!(size % 16, 0, "{name}: not a 16-byte multiple");
        }
    }
}
