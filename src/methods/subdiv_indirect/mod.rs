//! Method `subdiv-indirect`: the paper's execute-indirect variant (§4.1,
//! §4.3), the baseline the persistent kernel is measured against and the
//! path `subdiv` falls back to where persistent threads misbehave.
//!
//! The level schedule of [`super::levels`], one `vkCmdDispatchIndirect` per
//! round (`glsl/levels/round.comp`), after a first one-invocation step
//! (`glsl/levels/init.comp`). Each round processes a chunk of one depth with
//! the same `process()` as the persistent kernel and the oracle (rational
//! patches included), and its last workgroup writes the next round's
//! arguments, so a round past the end of the schedule is an empty
//! dispatch. The node memory is bounded by its budget at any depth (to
//! `l_max` = 10): a depth too large for one chunk is taken in several
//! rounds, depth first, never dropped. Each pass records the rounds the
//! last frame's needed and a margin ([`RoundBudget`]); a frame that needs
//! more is drawn again with twice as many.

use serde_json::json;

use super::levels::{self, finish_rounds, level_memory, level_parts, must_remake, recorded};
use super::levels::{Levels, RoundBudget};
use super::{Finished, Method, MethodInfo, MethodSetup, Reads, RenderError, Role};
use crate::constants::*;
use crate::draw::hiz::Hiz;
use crate::draw::ReadyStage;
use crate::frame::{CopyRange, FrameOut, FrameRec, Retired};
use crate::gpu::blocks::block;
use crate::patch::view::ViewParams;

/// The registry entry.
pub const INFO: MethodInfo = MethodInfo {
    name: "subdiv-indirect",
    about: "recursive subdivision, one indirect dispatch per depth (the paper's \
            execute-indirect variant), in bounded node memory",
    rational: true,
    pn: false,
    reads: Reads::SUBDIVIDES,
    role: Role::Compared,
    targets: &[super::levels::NODE_MEMORY_TARGET],
    heat_map: "subdivision depth",
    seams: "wedges (crack-closing triangles)",
    checks: None,
    blocks: &[block::<crate::methods::levels::push::LevelPush>],
    build: |setup| Ok(Box::new(SubdivIndirect::new(setup)?)),
};

/// The depth limit unless asked otherwise: the node's own, l_max = 10.
pub const DEFAULT_MAX_DEPTH: u32 = L_MAX;

/// `subdiv-indirect`'s knobs ([`super::PerMethod::subdiv_indirect`]) and
/// its flag, under its own heading in `--help`.
#[derive(Clone, Debug, PartialEq, Eq, clap::Args)]
#[command(next_help_heading = "subdiv-indirect")]
pub struct Options {
    /// subdiv-indirect: the deepest level, at most 10 (the default; the
    /// paper's variant stops at 6).
    #[arg(long, value_name = "D", default_value_t = DEFAULT_MAX_DEPTH)]
    pub max_depth: u32,
}

impl Default for Options {
    fn default() -> Self {
        super::cli_defaults()
    }
}

impl Options {
    /// Refuses a depth limit beyond the nodes' own.
    pub fn check(&self) -> Result<(), String> {
        if self.max_depth > L_MAX {
            return Err(format!(
                "--max-depth {} is beyond l_max = {L_MAX}",
                self.max_depth
            ));
        }
        Ok(())
    }
}

/// The per-depth method.
pub struct SubdivIndirect {
    stage: ReadyStage,
    levels: Levels,
    /// The depth pyramid, when occlusion culling is on.
    occlusion: Option<Hiz>,
    max_depth: u32,
    node_memory: u64,
    budget: RoundBudget,
    counters: Option<CopyRange>,
    state: Option<CopyRange>,
}

impl SubdivIndirect {
    /// Creates the ready stage, the node memory and the pipelines.
    pub fn new(setup: &mut MethodSetup<'_>) -> Result<Self, RenderError> {
        let o = setup.options;
        let max_depth = o.per_method.subdiv_indirect.max_depth;
        let (stage, levels, occlusion) = level_parts(setup, false, false, o.occlusion)?;
        Ok(Self {
            stage,
            levels,
            occlusion,
            max_depth,
            node_memory: o.per_method.levels.node_memory,
            budget: RoundBudget::new(max_depth),
            counters: None,
            state: None,
        })
    }
}

impl Method for SubdivIndirect {
    fn name(&self) -> &'static str {
        INFO.name
    }

    fn adjust_view(&self, params: &mut ViewParams) {
        params.l_max = params.l_max.min(self.max_depth);
    }

    fn record(&mut self, f: &mut FrameRec<'_>) -> Result<(), RenderError> {
        self.stage.ensure_capture(f.ctx, f.capture, f.retired)?;
        // The list is in its canonical order already: no sort.
        let budget = self.budget;
        levels::record_phases(
            f,
            &self.stage,
            &mut self.levels,
            self.occlusion.as_mut(),
            |f, levels, phase| levels.record_rounds(f, &self.stage, budget.for_phase(phase), phase),
        )?;
        self.counters = Some(f.copy_out(&self.stage.list().counters, COUNTER_WORDS)?);
        self.state = Some(self.levels.copy_out_state(f)?);
        Ok(())
    }

    fn finish(&mut self, out: &mut FrameOut<'_>) -> Result<Finished, RenderError> {
        let mut m = finish_rounds(
            &mut self.stage,
            &self.levels,
            &mut self.budget,
            self.occlusion.is_some(),
            out,
            recorded(self.counters, self.state)?,
            INFO.name,
        )?;
        if let Finished::Done(m) = &mut m {
            m.own.push(("max_depth_limit", json!(self.max_depth)));
            m.own.push(("occlusion", json!(self.occlusion.is_some())));
        }
        Ok(m)
    }

    fn reconfigure(
        &mut self,
        setup: &mut MethodSetup<'_>,
        _retired: &mut Retired,
    ) -> Result<bool, RenderError> {
        let o = setup.options;
        let culls = (o.occlusion, self.occlusion.is_some());
        Ok(!must_remake(o, &self.stage, self.node_memory, culls)
            && o.per_method.subdiv_indirect.max_depth == self.max_depth)
    }

    fn memory(&self) -> Vec<(&'static str, u64)> {
        level_memory(&self.levels, self.occlusion.as_ref(), None, &self.stage)
    }

    fn ready(&self) -> Option<&ReadyStage> {
        Some(&self.stage)
    }

    fn culls_occluded(&self) -> bool {
        true
    }
}
