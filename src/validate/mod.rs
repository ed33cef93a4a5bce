//! The checks behind `validate`: the GPU against the CPU oracle (ready set,
//! vertex positions bit for bit), the paper's §4.4 reordering test on the
//! GPU, and the hole test (`holes`). A method's own checks live in its
//! folder under `src/methods/` and are declared by its registry entry
//! (`MethodInfo::checks`, the traits of `methods::checks`; the shared-edge
//! comparisons the tessellating methods build theirs on are
//! `methods::edges`), so nothing here names a method.

pub mod coverage;
pub mod holes;
pub mod raster;

use glam::Vec3;

use crate::constants::*;
use crate::draw::{DrawPath, ReadyStage};
use crate::gpu::{ListPush, SceneSpec};
pub use crate::methods::checks::{Check, CheckFrame, CheckResult, MakeCheck};
use crate::patch::oracle::Surfaces;
use crate::patch::quadnode::QuadNode;
use crate::patch::wedge::node_mesh;
use crate::renderer::Renderer;
use crate::vk::{Context, Pipeline, ShaderModule, VkError, VkResult};

/// Compares the GPU's ready list (any order) with the oracle's.
pub fn compare_ready(gpu: &[QuadNode], oracle: &[QuadNode]) -> (bool, String) {
    let mut a = gpu.to_vec();
    let mut b = oracle.to_vec();
    a.sort_unstable();
    b.sort_unstable();
    if a == b {
        return (true, format!("{} nodes equal the oracle's", a.len()));
    }
    let only_gpu = a.iter().filter(|q| b.binary_search(q).is_err()).count();
    let only_cpu = b.iter().filter(|q| a.binary_search(q).is_err()).count();
    (
        false,
        format!(
            "GPU {} nodes, oracle {}: {only_gpu} only on the GPU, {only_cpu} only in the oracle",
            a.len(),
            b.len()
        ),
    )
}

fn bits(p: Vec3) -> [u32; 3] {
    p.to_array().map(f32::to_bits)
}

/// The vertex slots a node's mesh uses (corners, plus present pivots).
fn used_slots(node: QuadNode, with_wedges: bool) -> (crate::patch::wedge::NodeMesh, Vec<usize>) {
    let mesh = node_mesh(node, with_wedges);
    let mut slots = vec![0, 1, 2, 3];
    for t in &mesh.tris[2..mesh.tri_count] {
        slots.push(t[2] as usize);
    }
    (mesh, slots)
}

/// Compares the captured world positions (`capture[NODE_MESH_SLOTS i + slot]`, one vec4
/// per slot, in the GPU's ready order) with the oracle's evaluation.
/// Returns (vertices compared, mismatches).
pub fn compare_capture<S: Surfaces + ?Sized>(
    patches: &S,
    ready: &[QuadNode],
    capture: &[[f32; 4]],
    with_wedges: bool,
) -> (u64, u64) {
    let mut compared = 0;
    let mut bad = 0;
    for (i, &node) in ready.iter().enumerate() {
        let (mesh, slots) = used_slots(node, with_wedges);
        let want = patches.node_positions(node, &mesh);
        for s in slots {
            let c = capture[NODE_MESH_SLOTS as usize * i + s];
            compared += 1;
            bad += (bits(Vec3::new(c[0], c[1], c[2])) != bits(want[s])) as u64;
        }
    }
    (compared, bad)
}

/// Compares the fallback vertex buffer (`VERTICES_PER_NODE` vertices of
/// `VERTEX_WORDS` words per node, in the GPU's ready order) with the
/// oracle's triangles; a missing wedge must be a degenerate triangle (three
/// copies of corner 0). Returns (vertices compared, mismatches).
pub fn compare_vertices<S: Surfaces + ?Sized>(
    patches: &S,
    ready: &[QuadNode],
    words: &[u32],
    with_wedges: bool,
) -> (u64, u64) {
    let per_node = (VERTICES_PER_NODE * VERTEX_WORDS) as usize;
    let mut compared = 0;
    let mut bad = 0;
    for (i, &node) in ready.iter().enumerate() {
        let mesh = node_mesh(node, with_wedges);
        let pos = patches.node_positions(node, &mesh);
        // Triangle slots: 0, 1 the quad; 2 + e the wedge on edge e (pivot
        // slot 4 + e).
        let mut slot_tris = [[0usize; 3]; NODE_MESH_TRIS as usize];
        slot_tris[0] = [0, 1, 2];
        slot_tris[1] = [0, 2, 3];
        for t in &mesh.tris[2..mesh.tri_count] {
            slot_tris[t[2] as usize - 2] = t.map(|x| x as usize);
        }
        for (t, tri) in slot_tris.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                let o = i * per_node + (3 * t + k) * VERTEX_WORDS as usize;
                let got = [words[o], words[o + 1], words[o + 2]];
                compared += 1;
                bad += (got != bits(pos[v])) as u64;
            }
        }
    }
    (compared, bad)
}

/// The §4.4 reordering test over every node of a frame's ready list.
pub struct ReorderCheck {
    pipeline: Pipeline,
}

impl ReorderCheck {
    /// Creates the pipeline for `stage`'s ready-list pass layout,
    /// specialized for a scene that holds what `scene` says.
    pub fn new(ctx: &Context, stage: &ReadyStage, scene: SceneSpec) -> VkResult<Self> {
        let shader = ShaderModule::load(ctx, "reorder_check.comp")?;
        let spec = scene.constants(&[]);
        Ok(Self {
            pipeline: Pipeline::compute(ctx, "reorder check", stage.list_layout(), &shader, &spec)?,
        })
    }

    /// Runs over the `ready` nodes of the renderer's ready list (after a
    /// frame was rendered) and returns (nodes checked, nodes failing).
    pub fn run(&self, renderer: &Renderer, ready: u32) -> VkResult<(u32, u32)> {
        let ctx = renderer.context();
        let Some(stage) = renderer.method().ready() else {
            return Err(VkError::Usage(
                "the reordering test needs a method with a ready list".into(),
            ));
        };
        let list = stage.list();
        let layout = stage.list_layout();
        let pc = ListPush {
            ready_capacity: list.caps.ready,
            ..bytemuck::Zeroable::zeroed()
        };
        let groups = ready
            .min(list.caps.ready)
            .div_ceil(EXPAND_GROUP_SIZE)
            .max(1);
        ctx.one_shot(|cmd| {
            use crate::vk::{Access, Pass, Recorder, Res};
            // After everything the renderer recorded, before anything later.
            let mut rec = Recorder::new(ctx, cmd);
            rec.after(Res::Memory, Access::ALL);
            layout.push(cmd, &pc);
            let pass = Pass::new("expand for validation")
                .pipeline(&self.pipeline)
                .bind(SET_PASS, list.set());
            let pass = renderer.scene().bind_to(pass, 0);
            rec.dispatch(&pass, [groups, 1, 1]);
            Ok(())
        })?;
        let c = list.read_counters(ctx)?;
        Ok((c[C_CHECK_NODES as usize], c[C_CHECK_FAILS as usize]))
    }
}

/// Where the draw path keeps positions the validator can read.
pub fn positions_source(path: DrawPath) -> &'static str {
    match path {
        DrawPath::Mesh => "mesh-shader capture",
        DrawPath::Fallback => "fallback vertex buffer",
    }
}
