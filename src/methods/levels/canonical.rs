//! The level schedule on the CPU (the oracle's `process` run in the
//! kernels' order): the ready list the level kernels must write, entry for
//! entry.

use super::LevelPlan;
use crate::constants::*;
use crate::patch::bezier::BezierPatch;
use crate::patch::cull::outside_frustum;
use crate::patch::oracle::{process_any, Outcome};
use crate::patch::quadnode::QuadNode;
use crate::patch::rational::Weights;
use crate::patch::view::ViewParams;
use crate::scene::instances::Instance;

/// The level schedule on the CPU: the ready list the level kernels write,
/// in their order, and the rounds it takes.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CanonicalRun {
    /// Ready nodes in list order.
    pub ready: Vec<QuadNode>,
    /// Rounds (processing and the final copy).
    pub rounds: u32,
    /// Rounds that took part of a depth too large for one chunk.
    pub split_rounds: u32,
    /// Nodes processed per depth 0..=`plan.levels`.
    pub nodes_per_depth: Vec<u32>,
    /// Most nodes one depth held at once.
    pub peak_nodes: u32,
    /// Children of nodes at the deepest depth with a region, dropped as
    /// the kernels drop them (`ERR_LEVEL_REGION`): 0 for a plan made for
    /// the view's split.
    pub dropped: u32,
}

/// Runs the schedule of `glsl/levels/level.glsl` (`schedule`,
/// `finish_round`) with the oracle's `process` on the CPU: what the GPU's
/// ready list must equal, entry for entry. `weights` is parallel to
/// `patches` or empty; `instances` are the records the scene was uploaded
/// with (`SceneGpu::instance_records`), whose boxes decide depth 0 as
/// `levels/init.comp` does.
pub fn canonical_ready(
    patches: &[BezierPatch],
    weights: &[Weights],
    flags: &[u32],
    instances: &[Instance],
    vp: &ViewParams,
    plan: LevelPlan,
) -> CanonicalRun {
    let depths = plan.levels as usize + 1;
    let mut held: Vec<Vec<QuadNode>> = vec![Vec::new(); depths];
    held[0] = root_patches(instances, vp)
        .into_iter()
        .map(QuadNode::root)
        .collect();
    let mut next = vec![0usize; depths];
    let mut out = CanonicalRun {
        nodes_per_depth: vec![0; depths],
        ..CanonicalRun::default()
    };
    let chunk = plan.chunk as usize;
    let mut copy_blocks = 0;
    loop {
        // `schedule`: the deepest depth with nodes left.
        let pick = (0..=plan.levels as usize)
            .rev()
            .find(|&d| next[d] < held[d].len());
        let Some(d) = pick else {
            if copy_blocks > 0 {
                out.rounds += 1; // the final copy
            }
            return out;
        };
        let (first, n) = (next[d], chunk.min(held[d].len() - next[d]));
        next[d] += n;
        out.split_rounds += (held[d].len() > chunk) as u32;
        out.rounds += 1;
        out.nodes_per_depth[d] += n as u32;
        let mut children = Vec::new();
        let mut readies = 0;
        for &q in &held[d][first..first + n] {
            let id = q.patch() as usize;
            match process_any(&patches[id], weights.get(id), flags[id], q, vp) {
                Outcome::Ready => {
                    out.ready.push(q);
                    readies += 1;
                }
                Outcome::Split(kids) => children.extend(kids),
                Outcome::Culled | Outcome::BackFacing => {}
            }
        }
        if d + 1 == depths {
            out.dropped += children.len() as u32;
        } else if !children.is_empty() {
            out.peak_nodes = out.peak_nodes.max(children.len() as u32);
            held[d + 1] = children;
            next[d + 1] = 0;
        }
        copy_blocks = if readies > 0 {
            n.div_ceil(LEVEL_GROUP_SIZE as usize)
        } else {
            0
        };
    }
}

/// Depth 0 of the level schedule, as `levels/init.comp` lists it: the
/// patches of every instance whose box is not outside the frustum (when
/// the view culls by it), in instance order.
pub fn root_patches(instances: &[Instance], vp: &ViewParams) -> Vec<u32> {
    let frustum = vp.flags & FLAG_FRUSTUM_CULL != 0;
    instances
        .iter()
        .filter(|t| {
            let (lo, hi) = t.bounds();
            !(frustum && outside_frustum(lo, hi, vp))
        })
        .flat_map(|t| t.first..t.first + t.count)
        .collect()
}
