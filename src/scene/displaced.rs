//! The displacement context of a scene's geometry: what the oracle
//! (`patch::oracle::process_displaced`, through [`Displacer`]) and the
//! checks evaluate displaced positions and bounds with; the twin of
//! `glsl/common/displace.glsl`'s owner lookups (the records themselves are
//! `scene::displacement`'s).

use glam::Vec3;

use crate::patch::bezier::{BezierPatch, EDGE_BOTTOM, EDGE_LEFT, EDGE_RIGHT, EDGE_TOP};
use crate::patch::displace::{unit_normal, uv_at, uv_box, Displacer, ModelDisplacement};
use crate::patch::oracle::{Surfaces, WeightedPatches};
use crate::patch::quadnode::QuadNode;
use crate::patch::rational::Weights;
use crate::patch::wedge::NodeMesh;
use crate::scene::displacement::{
    edge_param, edge_point, owner_of, SceneDisplacement, OWNER_COLLAPSED, OWNER_INDEX_MASK,
    OWNER_PATCH_SHIFT, OWNER_REVERSED,
};
use crate::scene::geometry::SceneGeometry;

/// The displacement context of one geometry: what the oracle and the
/// checks evaluate displaced positions and bounds with.
#[derive(Clone, Copy)]
pub struct Displaced<'a> {
    /// The scene's geometry (world patches, instances, UV patches).
    pub geo: &'a SceneGeometry,
    /// Its displacement.
    pub disp: &'a SceneDisplacement,
}

impl<'a> Displaced<'a> {
    /// The context of `geo`, if some model of it is displaced.
    pub fn of(geo: &'a SceneGeometry) -> Option<Self> {
        geo.displacement.in_use().then_some(Self {
            geo,
            disp: &geo.displacement,
        })
    }

    /// Base patch `g`'s displacement settings, if its model is displaced.
    pub fn model_of(&self, g: usize) -> Option<&'a ModelDisplacement> {
        let model = (self.geo.flags[g] >> crate::constants::PATCH_MODEL_SHIFT) as usize;
        self.disp.models.get(model)?.as_ref()
    }

    /// The offset `n̂·d` of base patch `g`'s point (u, v), evaluated by its
    /// owner (twin of `displacement_offset` in displace.glsl).
    pub fn offset(&self, g: usize, m: &ModelDisplacement, u: f32, v: f32) -> Vec3 {
        let (t, k) = self.geo.instances.locate(g);
        let mirrored = t.mirrored();
        let (um, vm) = if mirrored { (v, u) } else { (u, v) };
        let (o, uo, vo) = owner_of(&self.disp.owners, k, um, vm);
        let og = t.first as usize + (o - t.source as usize);
        let (ub, vb) = if mirrored { (vo, uo) } else { (uo, vo) };
        let n = unit_normal(&self.geo.patches[og], ub, vb);
        let st = uv_at(&self.geo.materials.uv_patches[o], uo, vo);
        let h = self.disp.maps[m.map].1.sample(st[0], st[1]);
        n * m.at(h)
    }

    /// Base patch `g`'s drawn point at (u, v): the surface point, displaced
    /// when its model is.
    pub fn point(&self, g: usize, u: f32, v: f32) -> Vec3 {
        let p = self.geo.patches[g].eval(u, v);
        match self.model_of(g) {
            Some(m) => p + self.offset(g, m, u, v),
            None => p,
        }
    }

    /// How far the displacement over the domain `dom` of model patch `k`
    /// may stray from the blend of its corners' (world units; see
    /// [`HeightMap::variation`]).
    fn reach_of_box(&self, m: &ModelDisplacement, k: usize, dom: [f32; 4]) -> f32 {
        let uvp = &self.geo.materials.uv_patches[k];
        let (lo, hi, grow) = uv_box(uvp, self.disp.uv_curvature[k], dom);
        m.reach(self.disp.maps[m.map].1.variation(lo, hi, grow))
    }

    /// How far the displacement can vary along edge `e` of `node` (world
    /// units): from the edge owner's texture coordinates where the edge lies
    /// on the base patch's boundary, so both sides compute the same bits;
    /// 0 on a collapsed edge (one point, displaced once).
    pub fn edge_reach(&self, g: usize, m: &ModelDisplacement, node: QuadNode, e: usize) -> f32 {
        let (inst, k) = self.geo.instances.locate(g);
        let (a, b, c, d) = node.domain();
        // The edge as a line of the base domain: (along u?, fixed, t0, t1).
        let (along_u, fixed, t0, t1) = match e {
            EDGE_BOTTOM => (true, c, a, b),
            EDGE_TOP => (true, d, a, b),
            EDGE_LEFT => (false, a, c, d),
            _ => (false, b, c, d),
        };
        // A mirrored instance's base patch is the model patch with u and
        // v swapped.
        let along_u = along_u != inst.mirrored();
        let (o, along_u, fixed, t0, t1) = self.owned_line(k, along_u, fixed, t0, t1);
        if o == usize::MAX {
            return 0.0;
        }
        let dom = if along_u {
            [t0, t1, fixed, fixed]
        } else {
            [fixed, fixed, t0, t1]
        };
        self.reach_of_box(m, o, dom)
    }

    /// A line of model patch `k`'s domain (along u or v at `fixed`, from
    /// `t0` to `t1`) in its owner's terms: the owner, the line there and
    /// its ends in increasing order; `usize::MAX` for a collapsed edge.
    fn owned_line(
        &self,
        k: usize,
        along_u: bool,
        fixed: f32,
        t0: f32,
        t1: f32,
    ) -> (usize, bool, f32, f32, f32) {
        let e = match (along_u, fixed) {
            (true, 0.0) => EDGE_BOTTOM,
            (true, 1.0) => EDGE_TOP,
            (false, 0.0) => EDGE_LEFT,
            (false, 1.0) => EDGE_RIGHT,
            _ => return (k, along_u, fixed, t0, t1),
        };
        let w = self.disp.owners[k][e];
        if w & OWNER_COLLAPSED != 0 {
            return (usize::MAX, along_u, fixed, t0, t1);
        }
        let map = |t: f32| {
            let (u, v) = if along_u { (t, fixed) } else { (fixed, t) };
            let s = edge_param(e, u, v);
            let s = if w & OWNER_REVERSED != 0 { 1.0 - s } else { s };
            edge_point((w & OWNER_INDEX_MASK) as usize, s)
        };
        let (p0, p1) = (map(t0), map(t1));
        let oe = (w & OWNER_INDEX_MASK) as usize;
        let o_along_u = oe == EDGE_BOTTOM || oe == EDGE_TOP;
        let (o_fixed, s0, s1) = if o_along_u {
            (p0.1, p0.0, p1.0)
        } else {
            (p0.0, p0.1, p1.1)
        };
        let (lo, hi) = if s1 < s0 { (s1, s0) } else { (s0, s1) };
        (
            (w >> OWNER_PATCH_SHIFT) as usize,
            o_along_u,
            o_fixed,
            lo,
            hi,
        )
    }

    /// How far the displacement can vary over `node` (world units): from
    /// its own texture coordinates (the inner tier is the node's alone).
    pub fn inner_reach(&self, g: usize, m: &ModelDisplacement, node: QuadNode) -> f32 {
        let (t, k) = self.geo.instances.locate(g);
        let (a, b, c, d) = node.domain();
        let dom = if t.mirrored() {
            [c, d, a, b]
        } else {
            [a, b, c, d]
        };
        self.reach_of_box(m, k, dom)
    }
}

impl Displacer for Displaced<'_> {
    fn patches(&self) -> (&[BezierPatch], &[Weights], &[u32]) {
        (&self.geo.patches, &self.geo.weights, &self.geo.flags)
    }

    fn model_of(&self, g: usize) -> Option<&ModelDisplacement> {
        Displaced::model_of(self, g)
    }

    fn edge_reach(&self, g: usize, m: &ModelDisplacement, node: QuadNode, e: usize) -> f32 {
        Displaced::edge_reach(self, g, m, node, e)
    }

    fn inner_reach(&self, g: usize, m: &ModelDisplacement, node: QuadNode) -> f32 {
        Displaced::inner_reach(self, g, m, node)
    }

    fn offset(&self, g: usize, m: &ModelDisplacement, u: f32, v: f32) -> Vec3 {
        Displaced::offset(self, g, m, u, v)
    }
}

/// The drawn positions of a displaced geometry's nodes: the surface points
/// plus their owners' offsets for displaced models, as the geometry has
/// them otherwise (twin of `patch_node_positions` in
/// glsl/common/draw_rational.glsl).
impl Surfaces for Displaced<'_> {
    fn node_positions(&self, node: QuadNode, mesh: &NodeMesh) -> [Vec3; 8] {
        let g = node.patch() as usize;
        let Some(m) = self.model_of(g) else {
            let geo = self.geo;
            let w = WeightedPatches {
                patches: &geo.patches,
                weights: &geo.weights,
                flags: &geo.flags,
            };
            return w.node_positions(node, mesh);
        };
        let base = &self.geo.patches[g];
        let mut p = [Vec3::ZERO; 8];
        for (i, &(u, v)) in mesh.uv.iter().enumerate().take(mesh.vertex_count) {
            p[i] = base.eval(u, v) + self.offset(g, m, u, v);
        }
        p
    }
}
