//! The schedule's state words read back after a frame: rounds, depths,
//! culled and occluded instances, the cluster filters' figures.

use serde_json::{json, Value};

use super::LevelPlan;
use crate::constants::*;

/// The schedule's state at the end of a frame (the state words).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LevelState {
    /// Rounds run.
    pub rounds: u32,
    /// Whether the schedule ran out of work (else it ran out of rounds).
    pub done: bool,
    /// Occlusion culling: whether the early phase ran out of rounds.
    pub early_unfinished: bool,
    /// Persistent kernel: workgroups that joined (0 for the per-depth rounds).
    pub participants: u32,
    /// Persistent kernel: a watchdog tripped.
    pub aborted: bool,
    /// Rounds that took part of a depth too large for one chunk.
    pub split_rounds: u32,
    /// Most nodes one depth held at once.
    pub peak_nodes: u32,
    /// Nodes processed per depth 0..=LEVEL_DEPTHS_MAX.
    pub nodes_per_depth: Vec<u32>,
    /// Instances whose patches were depth 0.
    pub root_instances: u32,
    /// Instances culled whole by their boxes, and their patches (counted
    /// among the culled patches, never processed).
    pub culled_instances: u32,
    /// See `culled_instances`.
    pub culled_instance_patches: u32,
    /// Occlusion culling: instances drawn in the early phase, and those the
    /// late phase found hidden (and their patches, never processed).
    pub early_instances: u32,
    /// See `early_instances`.
    pub occluded_instances: u32,
    /// See `early_instances`.
    pub occluded_instance_patches: u32,
    /// Instances the last pass listed that the early phase did not (all
    /// of a frame of one pass).
    pub new_instances: u32,
    /// Occlusion culling: rounds of the early phase (the rest of `rounds`
    /// are the late phase's).
    pub early_rounds: u32,
    /// Occlusion culling's cluster filters: clusters the early phase drew,
    /// clusters the late phase took, the early phase's clusters the late
    /// phase left (their boxes tested against the pyramid) and those found
    /// hidden there.
    pub clusters_early: u32,
    /// See `clusters_early`.
    pub clusters_late: u32,
    /// See `clusters_early`.
    pub clusters_tested: u32,
    /// See `clusters_early`.
    pub clusters_hidden: u32,
    /// Read-modify-writes of the visibility bits (among the global atomics).
    pub visibility_atomics: u32,
}

impl LevelState {
    /// Reads the copied-out state words.
    pub fn from_words(w: &[u32]) -> Self {
        let at = |i: u32| w[i as usize];
        let depths = (0..=LEVEL_DEPTHS_MAX)
            .map(|d| at(S_DEPTH_NODES + d))
            .collect();
        LevelState {
            rounds: at(S_ROUND),
            done: at(S_DONE) != 0 && at(S_EARLY_UNFINISHED) == 0,
            early_unfinished: at(S_EARLY_UNFINISHED) != 0,
            participants: at(S_PARTICIPANTS),
            aborted: at(S_SYNC) & SYNC_ABORT != 0,
            split_rounds: at(S_SPLIT_ROUNDS),
            peak_nodes: at(S_PEAK_NODES),
            nodes_per_depth: depths,
            root_instances: at(S_ROOT_INSTANCES),
            culled_instances: at(S_CULLED_INSTANCES),
            culled_instance_patches: at(S_CULLED_INSTANCE_PATCHES),
            early_instances: at(S_EARLY_INSTANCES),
            occluded_instances: at(S_OCCLUDED_INSTANCES),
            occluded_instance_patches: at(S_OCCLUDED_INSTANCE_PATCHES),
            new_instances: at(S_NEW_INSTANCES),
            early_rounds: at(S_EARLY_ROUNDS),
            clusters_early: at(S_CLUSTERS_EARLY),
            clusters_late: at(S_CLUSTERS_LATE),
            clusters_tested: at(S_CLUSTERS_TESTED),
            clusters_hidden: at(S_CLUSTERS_HIDDEN),
            visibility_atomics: at(S_VISIBILITY_ATOMICS),
        }
    }

    /// The schedule's figures for `method_stats`.
    pub fn stats(&self, plan: LevelPlan) -> Vec<(&'static str, Value)> {
        vec![
            ("rounds", json!(self.rounds)),
            ("rounds_split", json!(self.split_rounds)),
            ("chunk_nodes", json!(plan.chunk)),
            ("peak_depth_nodes", json!(self.peak_nodes)),
            (
                "nodes_per_depth",
                json!(self.nodes_per_depth[..=plan.levels as usize]),
            ),
            ("node_memory_bytes", json!(plan.bytes())),
            (
                "instances_drawn",
                json!(self.early_instances + self.new_instances),
            ),
            ("instances_culled", json!(self.culled_instances)),
            (
                "instance_culled_patches",
                json!(self.culled_instance_patches),
            ),
            ("instances_early", json!(self.early_instances)),
            ("instances_occluded", json!(self.occluded_instances)),
            (
                "instance_occluded_patches",
                json!(self.occluded_instance_patches),
            ),
            ("rounds_early", json!(self.early_rounds)),
            ("clusters_early", json!(self.clusters_early)),
            ("clusters_late", json!(self.clusters_late)),
            ("clusters_retested", json!(self.clusters_tested)),
            ("clusters_found_hidden", json!(self.clusters_hidden)),
            ("visibility_atomics", json!(self.visibility_atomics)),
        ]
    }

    /// Rounds of the early and the late phase (of a frame of one pass: the
    /// pass, and 0).
    pub fn phase_rounds(&self, phases: bool) -> (u32, u32) {
        if phases {
            (self.early_rounds, self.rounds - self.early_rounds)
        } else {
            (self.rounds, 0)
        }
    }
}
