//! What the two methods of the level schedule share around a frame: the
//! rounds the per-depth variant records ([`RoundBudget`]), the frame's
//! figures or why it must be drawn again ([`finish_rounds`]), the parts a
//! method of the schedule is made of, its memory, and when it must be made
//! again.

use serde_json::json;

use super::{GpuSubdivStats, LevelState, Levels};
use crate::constants::*;
use crate::draw::hiz::Hiz;
use crate::draw::{ReadyCaps, ReadyStage};
use crate::frame::{CopyRange, FrameOut};
use crate::methods::{Finished, MethodOptions, MethodSetup, RenderError};

/// Most rounds one frame may be given (a frame needing more is refused:
/// raise the node memory or ε).
pub const MAX_ROUNDS: u32 = 1 << 14;

/// Rounds a frame with depth limit `max_depth` takes when no depth needs
/// more than one chunk: one per depth and the final copy.
pub fn base_rounds(max_depth: u32) -> u32 {
    max_depth + 2
}

/// The most rounds a pass records beyond what the last frame's needed.
const MAX_MARGIN: u32 = 8;

/// How many rounds each pass of a frame of per-depth rounds records: what
/// the last frame's pass needed plus a margin for a view that changes. The
/// margin starts at one round, doubles (to [`MAX_MARGIN`]) for a frame that
/// runs short, and halves with every frame that does not, so a still or
/// slowly moving view records one empty round per pass; a frame that runs
/// short is drawn again with twice the rounds of the pass that ran out
/// (as often as it takes). Before any frame, every depth once and the
/// final copy.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RoundBudget {
    /// Rounds of a frame's one pass (or its early phase), and of its late
    /// phase.
    rounds: [u32; 2],
    margin: u32,
    /// Whether the frame being drawn ran short already (its margin grew).
    grown: bool,
}

impl RoundBudget {
    /// The budget before any frame with depth limit `max_depth`.
    pub fn new(max_depth: u32) -> Self {
        RoundBudget {
            rounds: [base_rounds(max_depth); 2],
            margin: 1,
            grown: false,
        }
    }

    /// Rounds to record for pass `phase` (`PHASE_*`).
    pub fn for_phase(&self, phase: u32) -> u32 {
        self.rounds[usize::from(phase == PHASE_LATE)]
    }

    /// After a frame that finished: each pass records what it needed
    /// (`needed`: the one pass or the early phase, the late phase) and
    /// the margin, which then shrinks.
    pub fn fit(&mut self, needed: (u32, u32)) {
        self.rounds = [needed.0 + self.margin, needed.1 + self.margin];
        self.margin = (self.margin / 2).max(1);
        self.grown = false;
    }

    /// After a frame whose pass `pass` (0: the one pass or the early
    /// phase, 1: the late phase) ran out of rounds: twice as many for it
    /// (false when that would pass [`MAX_ROUNDS`]), and once per frame a
    /// larger margin.
    pub fn grow(&mut self, pass: usize) -> bool {
        if self.rounds[pass] >= MAX_ROUNDS {
            return false;
        }
        self.rounds[pass] = (self.rounds[pass] * 2).min(MAX_ROUNDS);
        if !self.grown {
            self.margin = (self.margin * 2).min(MAX_MARGIN);
            self.grown = true;
        }
        true
    }

    /// Dispatches a frame records: each pass's first steps and its rounds.
    pub fn dispatches(&self, phases: bool) -> u32 {
        if phases {
            2 * Levels::first_dispatches(PHASE_EARLY) + self.rounds[0] + self.rounds[1]
        } else {
            Levels::first_dispatches(PHASE_ALL) + self.rounds[0]
        }
    }
}

/// The frame's figures of a level schedule run as per-depth rounds, or why
/// it must be drawn again; shared with `subdiv`'s fallback. `phases`:
/// whether the frame culled by occlusion (two passes).
pub fn finish_rounds(
    stage: &mut ReadyStage,
    levels: &Levels,
    budget: &mut RoundBudget,
    phases: bool,
    out: &mut FrameOut<'_>,
    (counters, state): (CopyRange, CopyRange),
    method: &'static str,
) -> Result<Finished, RenderError> {
    let words = out.words(counters);
    let st = LevelState::from_words(out.words(state));
    let stats = GpuSubdivStats::from_counters(words);
    if let Some(reason) =
        stage.grow_if_full(out.ctx, words, crate::draw::MAX_READY_CAPACITY, out.retired)?
    {
        return Ok(Finished::Redo { reason });
    }
    if let Some(message) = stats.error_message() {
        return Err(RenderError::Method { method, message });
    }
    let recorded = *budget;
    if !st.done {
        let pass = usize::from(phases && !st.early_unfinished);
        let short = recorded.rounds[pass];
        if !budget.grow(pass) {
            return Err(RenderError::Method {
                method,
                message: format!(
                    "the frame needs more than {MAX_ROUNDS} rounds of at most {} nodes; \
                     raise the node memory or ε",
                    levels.plan().chunk
                ),
            });
        }
        let reason = format!(
            "{short} rounds were not enough (depths in parts of {} nodes): drawing with {}",
            levels.plan().chunk,
            budget.rounds[pass]
        );
        return Ok(Finished::Redo { reason });
    }
    budget.fit(st.phase_rounds(phases));
    let mut m = stats.method_stats(stage);
    // The queue kernel's figures mean nothing here.
    m.own
        .retain(|(k, _)| !k.starts_with("queue") && !["iterations_max", "idle_polls"].contains(k));
    m.own.extend(st.stats(levels.plan()));
    let rounds_recorded = recorded.rounds[0] + if phases { recorded.rounds[1] } else { 0 };
    m.own.push(("rounds_recorded", json!(rounds_recorded)));
    // Each pass's first steps and one indirect dispatch per recorded round.
    m.own
        .push(("dispatches", json!(recorded.dispatches(phases))));
    Ok(Finished::Done(m))
}

/// The copies of the counters and the level state that `record` made; an
/// error where `finish` comes first. Shared with `subdiv`.
pub fn recorded(
    counters: Option<CopyRange>,
    state: Option<CopyRange>,
) -> Result<(CopyRange, CopyRange), RenderError> {
    let (Some(c), Some(s)) = (counters, state) else {
        return Err(RenderError::Request(
            "finish() before any frame was recorded".into(),
        ));
    };
    Ok((c, s))
}

/// The memory of a level-schedule method by purpose: the node memory, the
/// depth pyramid where it culls by occlusion, a buffer of its own
/// (`subdiv`'s queue) and the ready stage's. Shared with `subdiv`.
pub fn level_memory(
    levels: &Levels,
    occlusion: Option<&Hiz>,
    own: Option<(&'static str, u64)>,
    stage: &ReadyStage,
) -> Vec<(&'static str, u64)> {
    let mut v = vec![("node_memory", levels.bytes())];
    v.extend(occlusion.map(|h| ("depth_pyramid", h.bytes())));
    v.extend(own);
    v.extend(stage.memory_bytes());
    v
}

/// Whether knobs `o` need a method of the level schedule made again rather
/// than reconfigured (shared with `subdiv`): another draw path or node
/// memory than its ready `stage` and `node_memory` were made with, a larger
/// ready list, or occlusion culling turned on or off (`culls`: whether it
/// would cull with `o`, whether it does now).
pub fn must_remake(
    o: &MethodOptions,
    stage: &ReadyStage,
    node_memory: u64,
    culls: (bool, bool),
) -> bool {
    o.draw != stage.path()
        || o.per_method.levels.node_memory != node_memory
        || o.ready_capacity > stage.list().caps.ready
        || culls.0 != culls.1
}

/// The ready stage, the level schedule and the occlusion culling's depth
/// pyramid a method of the level schedule is made of (shared with
/// `subdiv`): the ready list sorted before drawing or not (`sort`), the
/// persistent level kernel's pipelines or only the per-depth rounds'
/// (`persistent`), a pyramid or none (`occlusion`).
pub fn level_parts(
    setup: &mut MethodSetup<'_>,
    sort: bool,
    persistent: bool,
    occlusion: bool,
) -> Result<(ReadyStage, Levels, Option<Hiz>), RenderError> {
    let (ctx, o) = (setup.ctx, setup.options);
    let caps = ReadyCaps {
        ready: o.ready_capacity,
        vertices: false,
        capture: false,
        sort,
    };
    let stage = ReadyStage::new(ctx, setup.shaders, setup.scene_layout, o.draw, caps)?;
    let levels = Levels::new(
        ctx,
        setup.shaders,
        setup.scene_layout,
        &stage,
        &o.per_method.levels,
        persistent,
    )?;
    let hiz = if occlusion {
        Some(Hiz::new(ctx, setup.shaders, setup.scene_layout)?)
    } else {
        None
    };
    Ok((stage, levels, hiz))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_budget_records_what_the_last_frame_needed_and_a_margin_that_shrinks() {
        let mut b = RoundBudget::new(L_MAX);
        assert_eq!(b.for_phase(PHASE_ALL), L_MAX + 2);
        assert_eq!(b.dispatches(false), 1 + L_MAX + 2);
        b.fit((6, 0));
        assert_eq!(b.for_phase(PHASE_ALL), 7);
        assert_eq!(b.dispatches(false), 8);
        // One frame runs short twice: twice the rounds each time, the
        // margin doubled once.
        assert!(b.grow(0) && b.grow(0));
        assert_eq!(b.for_phase(PHASE_ALL), 28);
        b.fit((20, 0));
        assert_eq!(b.for_phase(PHASE_ALL), 22);
        b.fit((20, 0));
        assert_eq!(b.for_phase(PHASE_ALL), 21);
        // The late phase on its own; a frame's two passes and their first
        // steps (the first step and the cluster filter each).
        b.fit((5, 3));
        assert_eq!((b.for_phase(PHASE_EARLY), b.for_phase(PHASE_LATE)), (6, 4));
        assert!(b.grow(1));
        assert_eq!((b.for_phase(PHASE_EARLY), b.for_phase(PHASE_LATE)), (6, 8));
        assert_eq!(b.dispatches(true), 2 * 2 + 6 + 8);
        // Never beyond MAX_ROUNDS.
        let mut b = RoundBudget::new(L_MAX);
        while b.grow(0) {}
        assert_eq!(b.for_phase(PHASE_ALL), MAX_ROUNDS);
    }
}
