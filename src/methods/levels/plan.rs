//! How a node-memory budget becomes the level schedule's plan: rounds of
//! at most `chunk` nodes, a region of child slots per depth the split can
//! reach; and the budget's flag.

use crate::constants::*;
use crate::methods::targets::{Figure, Target};

/// Node memory of the level kernels unless asked otherwise: under the
/// 26.39 MiB of backing memory the paper's work graph needs at depth 10,
/// and enough that no kitchen keyframe at ε = 1 needs a depth in parts.
pub const DEFAULT_NODE_MEMORY: u64 = 24 << 20;

/// Node memory within 32 MiB on the whole path (the paper's work graph
/// needs 26.39 MiB at depth 10): a target of both level methods.
pub const NODE_MEMORY_TARGET: Target = Target::Worst {
    figure: Figure::NodeMemory,
    limit: 32.0 * 1024.0 * 1024.0,
};

/// The level schedule's knob, which `subdiv` and `subdiv-indirect` share
/// ([`super::PerMethod::levels`]), and its flag, under their heading in
/// `--help`.
#[derive(Clone, Debug, PartialEq, Eq, clap::Args)]
#[command(next_help_heading = "subdiv and subdiv-indirect")]
pub struct Options {
    /// subdiv and subdiv-indirect: node memory of the level schedule in MiB
    /// (default 24); a depth that does not fit is taken in parts.
    // In bytes once parsed; "24" is DEFAULT_NODE_MEMORY in MiB (a test
    // holds them together).
    #[arg(long, value_name = "MIB", value_parser = parse_mib,
          default_value = "24", hide_default_value = true)]
    pub node_memory: u64,
    /// Test-only, a planted fault: regions for this many depths whatever
    /// the split (fewer than aniso reaches must be caught by the kernels'
    /// ERR_LEVEL_REGION, not written past the regions).
    #[arg(skip)]
    pub planted_levels: Option<u32>,
}

impl Default for Options {
    fn default() -> Self {
        crate::methods::cli_defaults()
    }
}

impl Options {
    /// Refuses a budget with no room for a node.
    pub fn check(&self) -> Result<(), String> {
        if self.node_memory == 0 {
            return Err("--node-memory must be positive".into());
        }
        Ok(())
    }
}

/// A number of MiB (fractions too) as bytes; a negative one is 0, which
/// [`Options::check`] refuses in its own words.
fn parse_mib(s: &str) -> Result<u64, String> {
    let mib: f64 = s
        .parse()
        .map_err(|e: std::num::ParseFloatError| e.to_string())?;
    Ok((mib * f64::from(1u32 << 20)) as u64)
}

/// Depths with a region under split mode `aniso`: every depth of the
/// schedule a node can reach. A 1:4 split deepens both directions in one
/// round, so iso nodes are done after `L_MAX` rounds; a 1:2 split deepens
/// one, so under aniso a node can take `L_MAX` rounds per direction,
/// `LEVEL_DEPTHS_MAX` = 2 `L_MAX` in all.
pub const fn levels_for(aniso: bool) -> u32 {
    if aniso {
        LEVEL_DEPTHS_MAX
    } else {
        L_MAX
    }
}

// The state's per-depth arrays hold a word for every depth the schedule
// reaches and one past it (a depth's children are booked at d + 1).
const _: () = {
    assert!(levels_for(true) <= LEVEL_DEPTHS_MAX);
    assert!(S_LEVEL_NEXT - S_LEVEL_COUNT >= LEVEL_DEPTHS_MAX + 2);
    assert!(S_LEVEL_BLOCKS - S_LEVEL_NEXT >= LEVEL_DEPTHS_MAX + 2);
    assert!(S_DEPTH_NODES - S_LEVEL_BLOCKS >= LEVEL_DEPTHS_MAX + 2);
    assert!(S_READY - S_DEPTH_NODES > LEVEL_DEPTHS_MAX);
    assert!(S_VISIBILITY_ATOMICS < LEVEL_STATE_WORDS);
    // S_PENDING holds a bit per depth.
    assert!(LEVEL_DEPTHS_MAX < 32);
};

/// How a node-memory budget is spent: rounds of at most `chunk` nodes,
/// regions for depths 1..=`levels`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LevelPlan {
    /// Nodes per round at most (a multiple of `LEVEL_GROUP_SIZE`).
    pub chunk: u32,
    /// Depths with a region of child slots.
    pub levels: u32,
}

impl LevelPlan {
    /// Entries (8 bytes) of the node buffer: a region of `chunk ×
    /// SPLIT_MAX_CHILDREN` child slots per depth, two ready scratches.
    pub fn node_entries(self) -> u64 {
        let chunk = u64::from(self.chunk);
        u64::from(self.levels) * chunk * u64::from(SPLIT_MAX_CHILDREN) + 2 * chunk
    }

    /// Words of the scan buffer: a block scan per depth 1..=levels+1, two
    /// ready scans, and the round's block statistics.
    pub fn scan_words(self) -> u64 {
        let blocks = u64::from(self.chunk / LEVEL_GROUP_SIZE);
        u64::from(self.levels + 3) * (blocks + 1) + u64::from(LEVEL_BLOCK_STATS) * blocks
    }

    /// Bytes of the three buffers together.
    pub fn bytes(self) -> u64 {
        8 * self.node_entries() + 4 * self.scan_words() + 4 * u64::from(LEVEL_STATE_WORDS)
    }

    /// The largest plan with regions for depths 1..=`levels` within
    /// `budget` bytes whose buffers each fit `max_buffer` bytes (one
    /// storage-buffer binding), and whose chunk is at most
    /// `LEVEL_MAX_CHUNK` nodes (a round's finish walks at most 64 block
    /// totals per invocation; beyond it a budget buys nothing).
    pub fn for_budget(budget: u64, max_buffer: u64, levels: u32) -> Result<Self, String> {
        let fits = |chunk: u32| {
            let p = LevelPlan { chunk, levels };
            p.bytes() <= budget && 8 * p.node_entries() <= max_buffer
        };
        let smallest = LevelPlan {
            chunk: LEVEL_GROUP_SIZE,
            levels,
        };
        if !fits(LEVEL_GROUP_SIZE) {
            return Err(format!(
                "a node memory of {budget} bytes is below the smallest the level kernels \
                 can work in ({} bytes: one block of {LEVEL_GROUP_SIZE} nodes per round)",
                smallest.bytes()
            ));
        }
        // Blocks per round: the largest count that fits (a binary search;
        // the cost grows with the chunk), at most LEVEL_MAX_CHUNK nodes.
        let (mut lo, mut hi) = (1u32, LEVEL_MAX_CHUNK / LEVEL_GROUP_SIZE + 1);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if fits(mid * LEVEL_GROUP_SIZE) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Ok(LevelPlan {
            chunk: lo * LEVEL_GROUP_SIZE,
            levels,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plans_fill_the_budget_in_whole_blocks() {
        let range = 128 << 20;
        let p = LevelPlan::for_budget(DEFAULT_NODE_MEMORY, range, L_MAX).unwrap();
        assert_eq!(p.chunk % LEVEL_GROUP_SIZE, 0);
        assert!(p.bytes() <= DEFAULT_NODE_MEMORY);
        let bigger = LevelPlan {
            chunk: p.chunk + LEVEL_GROUP_SIZE,
            ..p
        };
        assert!(
            bigger.bytes() > DEFAULT_NODE_MEMORY,
            "{p:?} is not the largest"
        );
        // A budget that is not a multiple of anything still gives whole blocks.
        let odd = LevelPlan::for_budget(1_000_003, range, L_MAX).unwrap();
        assert_eq!(odd.chunk % LEVEL_GROUP_SIZE, 0);
        assert!(odd.bytes() <= 1_000_003);
        // One block is the least; below that, a sentence.
        let least = LevelPlan::for_budget(p.bytes().min(30_000), range, L_MAX).unwrap();
        assert_eq!(least.chunk, LEVEL_GROUP_SIZE);
        let e = LevelPlan::for_budget(1000, range, L_MAX).unwrap_err();
        assert!(e.contains("below the smallest"), "{e}");
        // The buffer range caps the chunk too.
        let capped = LevelPlan::for_budget(1 << 40, 1 << 20, L_MAX).unwrap();
        assert!(8 * capped.node_entries() <= 1 << 20);
        // And LEVEL_MAX_CHUNK: a round's finish walks at most 64 block
        // totals per invocation.
        let huge = LevelPlan::for_budget(1 << 40, 1 << 40, L_MAX).unwrap();
        assert_eq!(huge.chunk, LEVEL_MAX_CHUNK);
        assert_eq!(LEVEL_MAX_CHUNK, LEVEL_GROUP_SIZE.pow(3));
    }

    #[test]
    fn the_state_holds_every_depth_aniso_reaches() {
        // A 1:2 split deepens one direction: L_MAX rounds per direction.
        assert_eq!(levels_for(true), 2 * L_MAX);
        assert_eq!(levels_for(false), L_MAX);
        // Twice the regions at the same budget: half the chunk, or about.
        let range = 128 << 20;
        let iso = LevelPlan::for_budget(DEFAULT_NODE_MEMORY, range, levels_for(false)).unwrap();
        let aniso = LevelPlan::for_budget(DEFAULT_NODE_MEMORY, range, levels_for(true)).unwrap();
        assert!(aniso.bytes() <= DEFAULT_NODE_MEMORY && aniso.chunk < iso.chunk);
    }
}
