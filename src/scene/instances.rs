//! Instances: each model's patches stored once, in model space, and placed
//! in the world by an affine transform per instance (set 0's
//! `BIND_PATCHES` and `BIND_INSTANCES`, `glsl/common/scene.glsl`).
//!
//! Every shader reads a base patch through `load_patch`, which finds the
//! patch's instance (a binary search over the instances' first ids) and
//! transforms the model's control points in one fixed f32 operation order,
//! row by row `((r.x·x + r.y·y) + r.z·z) + r.w` with `precise`.
//! [`Instance::point`] is its twin, operation for operation, and the host's
//! world-space patches (`SceneGeometry::patches`, what the oracle, the edge
//! table and every check read) are made by it: the GPU's points equal them
//! bit for bit. Neighbours within an instance share their boundary points
//! bit for bit in model space, and the same arithmetic on the same bits
//! gives the same world bits, so an instance is as watertight as its model.
//!
//! An instance costs [`GPU_BYTES_PER_INSTANCE`] on the GPU whatever its
//! model's size, where baking it cost 484 bytes per patch (control points,
//! flags and shading patches).

use std::borrow::Cow;

use bytemuck::{Pod, Zeroable};
use glam::{DMat4, DVec3, Vec3};

use crate::constants::{
    INSTANCE_IDENTITY, INSTANCE_MIRRORED, INSTANCE_WORDS, LEVEL_GROUP_SIZE, PATCH_RATIONAL,
    VISIBILITY_CLUSTER,
};
use crate::patch::bezier::BezierPatch;
use crate::patch::rational::{reoriented_weights, Weights, UNIT_WEIGHTS};

/// Bytes of one instance record on the GPU.
pub const INSTANCE_BYTES: u64 = INSTANCE_WORDS as u64 * 4;

/// Bytes the GPU holds per instance beyond its model's patches: its record,
/// its entry in the level kernels' roots (set 0's BIND_ROOTS) and its
/// visibility word (BIND_VISIBILITY).
pub const GPU_BYTES_PER_INSTANCE: u64 = INSTANCE_BYTES + 8 + 4;

/// Words of one of the two sets of occlusion culling's cluster bits for
/// `instances` instances of `base_patches` base patches in all: a bit per
/// run of up to VISIBILITY_CLUSTER patches of one instance, numbered as
/// `root_cluster` in `glsl/levels/level.glsl` does (at most
/// base_patches / VISIBILITY_CLUSTER + instances + 1). Beside the
/// instances' words and one parity word, the visibility buffer holds two
/// such sets: 2 bits per instance and 1/128 byte per base patch more.
pub fn cluster_set_words(instances: usize, base_patches: usize) -> usize {
    let clusters = base_patches / VISIBILITY_CLUSTER as usize + instances + 1;
    clusters.div_ceil(32)
}

/// The flag bits that belong to an instance alone; the others (two-sided,
/// the model index) are the flags of each of its patches.
pub const INSTANCE_ONLY_FLAGS: u32 = INSTANCE_MIRRORED | INSTANCE_IDENTITY;

/// One instance, laid out as the shaders read it (`Instance` in
/// `glsl/common/scene.glsl`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Instance {
    /// The affine transform's rows: world coordinate i of a model point p is
    /// `((rows[i][0]·p.x + rows[i][1]·p.y) + rows[i][2]·p.z) + rows[i][3]`.
    pub rows: [[f32; 4]; 3],
    /// Global id of its first base patch (the ids of one instance are
    /// consecutive; instances are ordered by it).
    pub first: u32,
    /// Its first model patch (index into the model patches).
    pub source: u32,
    /// Its number of patches.
    pub count: u32,
    /// `PATCH_TWO_SIDED`, the model index `<< PATCH_MODEL_SHIFT`,
    /// `INSTANCE_MIRRORED`, `INSTANCE_IDENTITY`.
    pub flags: u32,
    /// Lower corner of the box of its world control points, a little
    /// enlarged (w unused): culling the instance by it culls only patches
    /// whose own boxes the kernels would cull (see [`Instance::bounded`]).
    pub lo: [f32; 4],
    /// Upper corner of that box.
    pub hi: [f32; 4],
}

impl Instance {
    /// The instance of `count` model patches from `source` placed by `m`
    /// as global patches from `first`, with the patch flags `flags`
    /// (two-sided, model index). The transform is rounded to f32 once; its
    /// translation never holds -0, so no world coordinate is -0 (the
    /// canonical zeros every baked patch had).
    pub fn new(m: &DMat4, first: u32, source: u32, count: u32, flags: u32) -> Self {
        let mut rows = [[0.0f32; 4]; 3];
        for (i, row) in rows.iter_mut().enumerate() {
            for (j, r) in row.iter_mut().enumerate() {
                *r = m.col(j)[i] as f32 + 0.0;
            }
        }
        let mut flags = flags & !INSTANCE_ONLY_FLAGS;
        if *m == DMat4::IDENTITY {
            flags |= INSTANCE_IDENTITY;
        }
        if m.determinant() < 0.0 {
            flags |= INSTANCE_MIRRORED;
        }
        Instance {
            rows,
            first,
            source,
            count,
            flags,
            lo: [0.0; 4],
            hi: [0.0; 4],
        }
        .unbounded()
    }

    /// The instance with the box that holds everything: never culled whole
    /// (the kernels still cull its patches one by one, and no corner
    /// product can make the frustum test's sum NaN: each term of a plane's
    /// positive corner is ≥ 0). For an instance whose world patches change
    /// every frame (a deforming model's, a keyed one), where the box made
    /// at load would go stale (`anim::Animation::unbound`).
    pub fn unbounded(mut self) -> Self {
        self.lo = [-f32::MAX, -f32::MAX, -f32::MAX, 0.0];
        self.hi = [f32::MAX, f32::MAX, f32::MAX, 0.0];
        self
    }

    /// The instance with its box: that of `world`'s control points (its
    /// patches in the world), enlarged by a relative 1e-5. A box test is
    /// monotone in the box's corners, so a patch box inside this one is
    /// culled by the frustum whenever this one is; the margin covers the
    /// few ulps by which a rational patch's divided control points may
    /// stray from the stored ones.
    pub fn bounded(mut self, world: &[BezierPatch]) -> Self {
        let (lo, hi) = padded_box(world);
        self.lo = [lo.x, lo.y, lo.z, 0.0];
        self.hi = [hi.x, hi.y, hi.z, 0.0];
        self
    }

    /// The instance with the box of the model-space box `lo..hi` (its
    /// patches' control points) placed by `m`, the transform this record
    /// was made from: the box of the 8 placed corners, which holds every
    /// placed point in exact arithmetic (an affine map keeps a point of the
    /// box inside the hull of the corners' images), enlarged by a relative
    /// 1e-5 of the largest magnitude the placement sums (`|m| |p| + |t|` per
    /// axis), far more than the few f32 roundings of the record's rows and
    /// of `point` move a point. For an instance whose transform changes
    /// every frame (`anim::Animation::frame`) without walking its patches.
    pub fn placed_box(mut self, m: &DMat4, lo: DVec3, hi: DVec3) -> Self {
        let mut wlo = DVec3::splat(f64::MAX);
        let mut whi = DVec3::splat(-f64::MAX);
        for c in 0..8 {
            let pick = |bit: usize, a: f64, b: f64| if c & bit != 0 { b } else { a };
            let corner = DVec3::new(
                pick(1, lo.x, hi.x),
                pick(2, lo.y, hi.y),
                pick(4, lo.z, hi.z),
            );
            let q = m.transform_point3(corner);
            wlo = wlo.min(q);
            whi = whi.max(q);
        }
        let reach = lo.abs().max(hi.abs());
        let mut pad = DVec3::ZERO;
        for i in 0..3 {
            let row = DVec3::new(m.col(0)[i], m.col(1)[i], m.col(2)[i]);
            pad[i] = (row.abs().dot(reach) + m.col(3)[i].abs()) * 1e-5 + 1e-30;
        }
        let (wlo, whi) = ((wlo - pad).as_vec3(), (whi + pad).as_vec3());
        self.lo = [wlo.x, wlo.y, wlo.z, 0.0];
        self.hi = [whi.x, whi.y, whi.z, 0.0];
        self
    }

    /// The box (lower and upper corner).
    pub fn bounds(&self) -> (Vec3, Vec3) {
        (
            Vec3::from_slice(&self.lo[..3]),
            Vec3::from_slice(&self.hi[..3]),
        )
    }

    /// One instance over `count` patches taken as they are (the layout of a
    /// geometry without instances: model patches = world patches).
    pub fn identity(count: u32) -> Self {
        Self::new(&DMat4::IDENTITY, 0, 0, count, 0)
    }

    /// Whether the model's u and v are swapped in the world.
    pub fn mirrored(&self) -> bool {
        self.flags & INSTANCE_MIRRORED != 0
    }

    /// The model point `p` in the world: the twin of `instance_point` in
    /// `glsl/common/scene.glsl`, operation for operation.
    pub fn point(&self, p: Vec3) -> Vec3 {
        if self.flags & INSTANCE_IDENTITY != 0 {
            return p;
        }
        let row = |r: &[f32; 4]| ((r[0] * p.x + r[1] * p.y) + r[2] * p.z) + r[3];
        Vec3::new(row(&self.rows[0]), row(&self.rows[1]), row(&self.rows[2]))
    }

    /// The model patch `p` in the world.
    pub fn patch(&self, p: &BezierPatch) -> BezierPatch {
        let moved = BezierPatch {
            pts: p.pts.map(|q| self.point(q)),
        };
        if self.mirrored() {
            moved.reoriented(true, false, false)
        } else {
            moved
        }
    }

    /// The model patch's weights `w` in the world (reordered as the points).
    pub fn weights(&self, w: &Weights) -> Weights {
        if self.mirrored() {
            reoriented_weights(w, true, false, false)
        } else {
            *w
        }
    }

    /// The flags of its patch whose model patch has flags `model_flags`.
    pub fn patch_flags(&self, model_flags: u32) -> u32 {
        (self.flags & !INSTANCE_ONLY_FLAGS) | model_flags
    }

    /// Global ids of its patches.
    pub fn ids(&self) -> std::ops::Range<usize> {
        self.first as usize..(self.first + self.count) as usize
    }
}

/// What the GPU holds of a scene's base patches: the model patches once
/// each, their flags and weights, and the instances that place them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InstanceTable {
    /// Model patches, in model space (each distinct model once).
    pub patches: Vec<BezierPatch>,
    /// Per model patch: `PATCH_RATIONAL` (for a geometry without
    /// instances, the whole flags word of each patch).
    pub flags: Vec<u32>,
    /// Per model patch, when some patch is rational; else empty.
    pub weights: Vec<Weights>,
    /// The instances, by first global id, covering 0..N without gaps.
    pub instances: Vec<Instance>,
}

impl InstanceTable {
    /// Base patches (global ids) the table places.
    pub fn base_patches(&self) -> usize {
        self.instances.iter().map(|i| i.count as usize).sum()
    }

    /// The table of a geometry without instances: one identity instance
    /// over the world patches as they are.
    pub fn identity(patches: &[BezierPatch], flags: &[u32], weights: &[Weights]) -> Self {
        InstanceTable {
            patches: patches.to_vec(),
            flags: flags.to_vec(),
            weights: weights.to_vec(),
            instances: vec![Instance::identity(patches.len() as u32).bounded(patches)],
        }
    }

    /// The instance that holds global patch `g`, and `g`'s model patch:
    /// the twin of `instance_of` in `glsl/common/scene.glsl`.
    pub fn locate(&self, g: usize) -> (&Instance, usize) {
        let i = self.instances.partition_point(|t| t.first as usize <= g) - 1;
        let t = &self.instances[i];
        (t, t.source as usize + (g - t.first as usize))
    }

    /// Global patch `g` in the world.
    pub fn world_patch(&self, g: usize) -> BezierPatch {
        let (t, k) = self.locate(g);
        t.patch(&self.patches[k])
    }

    /// The weights of model patch `k` (all 1 for a polynomial table).
    fn model_weights(&self, k: usize) -> Weights {
        self.weights.get(k).copied().unwrap_or(UNIT_WEIGHTS)
    }

    /// Whether the table places exactly `patches` with `flags` and
    /// `weights` (empty: all 1), bit for bit: what the GPU reads through it
    /// is then what the host's checks read.
    pub fn places(&self, patches: &[BezierPatch], flags: &[u32], weights: &[Weights]) -> bool {
        let mut next = 0u32;
        for t in &self.instances {
            if t.first != next || (t.source + t.count) as usize > self.patches.len() {
                return false;
            }
            next += t.count;
        }
        if next as usize != patches.len() || flags.len() != patches.len() {
            return false;
        }
        self.instances.iter().all(|t| {
            t.ids().all(|g| {
                let k = t.source as usize + (g - t.first as usize);
                let w = weights.get(g).copied().unwrap_or(UNIT_WEIGHTS);
                let rational = flags[g] & PATCH_RATIONAL != 0;
                bits(&t.patch(&self.patches[k])) == bits(&patches[g])
                    && t.patch_flags(self.flags[k]) == flags[g]
                    && (!rational || t.weights(&self.model_weights(k)) == w)
            })
        })
    }

    /// This table when it places `patches`, `flags` and `weights` exactly,
    /// else the identity table over them (a geometry edited after it was
    /// loaded draws what it now holds).
    pub fn or_identity<'a>(
        &'a self,
        patches: &[BezierPatch],
        flags: &[u32],
        weights: &[Weights],
    ) -> Cow<'a, InstanceTable> {
        if !self.instances.is_empty() && self.places(patches, flags, weights) {
            Cow::Borrowed(self)
        } else {
            Cow::Owned(Self::identity(patches, flags, weights))
        }
    }

    /// The instances as the GPU reads them.
    pub fn records(&self) -> &[Instance] {
        &self.instances
    }

    /// The model-space box of each model patch's control points, enlarged
    /// as [`Instance::bounded`] enlarges, 6 floats (lo, hi) per model patch:
    /// set 0's `BIND_PATCH_BOXES`, by which the late phase of occlusion
    /// culling tests the clusters the early phase drew
    /// (`glsl/levels/clusters.comp`).
    pub fn patch_boxes(&self) -> Vec<f32> {
        self.patches
            .iter()
            .flat_map(|p| {
                let (lo, hi) = padded_box(std::slice::from_ref(p));
                [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z]
            })
            .collect()
    }
}

/// Occlusion culling's clusters of `instances`: VISIBILITY_CLUSTER
/// consecutive patches of one instance from its first (the last one of an
/// instance may hold fewer).
pub fn clusters(instances: &[Instance]) -> u64 {
    instances
        .iter()
        .map(|t| u64::from(t.count.div_ceil(VISIBILITY_CLUSTER)))
        .sum()
}

/// Blocks of LEVEL_GROUP_SIZE cluster slots the level kernels' roots (set
/// 0's `BIND_ROOTS`) hold after their instance entries, for the cluster
/// filter of `instances`' clusters.
pub fn cluster_blocks(instances: &[Instance]) -> u32 {
    clusters(instances).div_ceil(u64::from(LEVEL_GROUP_SIZE)) as u32
}

/// Entries (8 bytes) of the roots for `instances`: one per instance, then
/// the cluster filter's slots (a block of LEVEL_GROUP_SIZE per
/// [`cluster_blocks`]) and its block scan (one per block and the total).
pub fn root_entries(instances: &[Instance]) -> u64 {
    let blocks = u64::from(cluster_blocks(instances));
    instances.len().max(1) as u64 + blocks * u64::from(LEVEL_GROUP_SIZE) + blocks + 1
}

/// The box of `patches`' control points, enlarged by a relative 1e-5 (and
/// 1e-30, so that it never collapses).
fn padded_box(patches: &[BezierPatch]) -> (Vec3, Vec3) {
    let mut lo = Vec3::splat(f32::MAX);
    let mut hi = Vec3::splat(-f32::MAX);
    for q in patches.iter().flat_map(|p| p.pts) {
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let pad = |v: Vec3| v.abs() * 1e-5 + Vec3::splat(1e-30);
    (lo - pad(lo), hi + pad(hi))
}

/// The bits of a patch's points (so -0 and +0 differ, as they do on the GPU).
fn bits(p: &BezierPatch) -> [[u32; 3]; 16] {
    p.pts.map(|q| q.to_array().map(f32::to_bits))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::constants::PATCH_TWO_SIDED;
    use glam::{DQuat, DVec3};

    fn wavy() -> BezierPatch {
        BezierPatch {
            pts: std::array::from_fn(|n| {
                let (i, j) = ((n % 4) as f32, (n / 4) as f32);
                Vec3::new(
                    i * 0.37 - 0.5,
                    j * 0.41 + 0.25,
                    (i * 1.3).sin() * (j * 0.7).cos(),
                )
            }),
        }
    }

    fn placed() -> DMat4 {
        DMat4::from_scale_rotation_translation(
            DVec3::new(1.5, 0.75, 2.0),
            DQuat::from_euler(glam::EulerRot::XYZ, 0.3, -0.8, 1.9),
            DVec3::new(12.0, -3.5, 0.25),
        )
    }

    /// The f32 twin stays within a few ulps of the exact transform (it is
    /// what replaced rounding the f64 transform once).
    #[test]
    fn the_f32_transform_is_close_to_the_exact_one() {
        let m = placed();
        let t = Instance::new(&m, 0, 0, 1, 0);
        let p = wavy();
        for q in p.pts {
            let exact = m.transform_point3(q.as_dvec3());
            let got = t.point(q).as_dvec3();
            let scale = exact.abs().max_element().max(1.0);
            assert!(
                (got - exact).abs().max_element() <= 8.0 * f32::EPSILON as f64 * scale,
                "{got} vs {exact}"
            );
        }
    }

    /// The identity reads points unchanged (no -0 turned +0, nothing
    /// rounded), mirroring swaps u and v, and no world coordinate is -0.
    #[test]
    fn identity_and_mirror() {
        let p = wavy();
        let id = Instance::identity(1);
        assert_eq!(id.flags, INSTANCE_IDENTITY);
        assert_eq!(bits(&id.patch(&p)), bits(&p));
        let m = DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0));
        let t = Instance::new(&m, 0, 0, 1, 0);
        assert!(t.mirrored() && t.flags & INSTANCE_IDENTITY == 0);
        let w = t.patch(&p);
        assert_eq!(w.at(1, 2).x, -p.at(2, 1).x);
        let zero = BezierPatch {
            pts: [Vec3::ZERO; 16],
        };
        let z = Instance::new(&DMat4::from_scale(DVec3::splat(-1.0)), 0, 0, 1, 0).patch(&zero);
        assert!(z
            .pts
            .iter()
            .all(|q| q.to_array().iter().all(|c| c.to_bits() == 0)));
    }

    /// `places` accepts the table's own world patches and refuses one
    /// changed bit, a wrong flag and a wrong count.
    #[test]
    fn places_checks_every_bit() {
        let p = wavy();
        let a = Instance::new(&DMat4::IDENTITY, 0, 0, 1, 1 << 16);
        let b = Instance::new(&placed(), 1, 0, 1, PATCH_TWO_SIDED | 2 << 16);
        let table = InstanceTable {
            patches: vec![p],
            flags: vec![0],
            weights: Vec::new(),
            instances: vec![a, b],
        };
        let world: Vec<BezierPatch> = (0..2).map(|g| table.world_patch(g)).collect();
        let flags = vec![1 << 16, PATCH_TWO_SIDED | 2 << 16];
        assert!(table.places(&world, &flags, &[]));
        let mut moved = world.clone();
        moved[1].pts[5].y = f32::from_bits(moved[1].pts[5].y.to_bits() ^ 1);
        assert!(!table.places(&moved, &flags, &[]));
        assert!(!table.places(&world, &[1 << 16, 2 << 16], &[]));
        assert!(!table.places(&world[..1], &flags[..1], &[]));
        assert_eq!(table.locate(1).1, 0);
        assert!(matches!(
            table.or_identity(&moved, &flags, &[]),
            Cow::Owned(t) if t.instances.len() == 1 && t.patches == moved
        ));
    }

    /// Occlusion culling's clusters and patch boxes: each box holds its
    /// model patch's control points, and the roots hold a slot for every
    /// cluster of every instance (a block per 64).
    #[test]
    fn patch_boxes_hold_their_patches_and_the_roots_every_cluster() {
        let model = vec![wavy(); 70];
        let table = InstanceTable {
            patches: model.clone(),
            flags: vec![0; 70],
            weights: Vec::new(),
            instances: vec![
                Instance::new(&DMat4::IDENTITY, 0, 0, 70, 0),
                Instance::new(&placed(), 70, 3, 33, 0),
            ],
        };
        let boxes = table.patch_boxes();
        assert_eq!(boxes.len(), 6 * 70);
        for (p, b) in model.iter().zip(boxes.chunks_exact(6)) {
            for q in p.pts {
                assert!(q.x > b[0] && q.y > b[1] && q.z > b[2], "{q} below {b:?}");
                assert!(q.x < b[3] && q.y < b[4] && q.z < b[5], "{q} above {b:?}");
            }
        }
        // 70 patches: 3 clusters; 33: 2.
        assert_eq!(clusters(&table.instances), 5);
        assert_eq!(cluster_blocks(&table.instances), 1);
        assert_eq!(root_entries(&table.instances), 2 + 64 + 2);
    }
}
