//! The subdivision kernels against the Vulkan memory model, read off their
//! compiled SPIR-V. Lavapipe (and, it seems, NVIDIA's L2) forgives a flag
//! read with a plain load or an acquire left out; other GPUs need not, so no
//! frame on this machine can show such a race. What can be checked is the
//! code: every word workgroups synchronise on is touched only by atomics of
//! device (queue-family) scope, each publication is a release and each
//! observation that data depends on is an acquire, the module uses the
//! Vulkan memory model, and the data published through those words is read
//! and written with device-scope visibility and availability (`coherent`).

mod common;

use std::collections::HashMap;

use bezier_subdiv::constants::*;
use bezier_subdiv::vk::load_spirv;
use rspirv::dr::{Instruction, Operand};
use rspirv::spirv::{MemoryAccess, MemoryModel, Op, Scope};

fn id(op: &Operand) -> u32 {
    match op {
        Operand::IdRef(i) | Operand::IdScope(i) | Operand::IdMemorySemantics(i) => *i,
        other => panic!("expected an id, got {other:?}"),
    }
}

/// SPIR-V memory-semantics bits.
const ACQUIRE: u32 = 0x2;
const RELEASE: u32 = 0x4;
const ACQUIRE_RELEASE: u32 = 0x8;
const SEQ_CST: u32 = 0x10;

/// What an access needs: `Acquire` for loads that data depends on,
/// `Release` for stores and read-modify-writes that publish, both for
/// counters that do both, nothing beyond atomicity otherwise.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Need {
    Atomic,
    Acquire,
    Release,
    AcqRel,
}

/// A synchronisation word: a block (by GLSL name) and a word of it, or
/// every word.
struct Sync {
    block: &'static str,
    word: Option<u32>,
    load: Need,
    store: Need,
    rmw: Need,
}

const fn sync(block: &'static str, word: Option<u32>, load: Need, store: Need, rmw: Need) -> Sync {
    Sync {
        block,
        word,
        load,
        store,
        rmw,
    }
}

/// The level kernels' words (glsl/levels/level.glsl, glsl/levels/persistent.comp):
/// the round barrier's one word (arrivals, generation, abort) and the
/// occupancy discovery's two.
const LEVEL_SYNC: &[Sync] = &[
    sync(
        "LevelState",
        Some(S_SYNC),
        Need::Acquire,
        Need::Release,
        Need::AcqRel,
    ),
    sync(
        "LevelState",
        Some(S_JOIN),
        Need::Atomic,
        Need::Atomic,
        Need::AcqRel,
    ),
    sync(
        "LevelState",
        Some(S_PARTICIPANTS),
        Need::Acquire,
        Need::Release,
        Need::AcqRel,
    ),
];

/// The queue kernel's (glsl/subdiv/queue.comp).
const QUEUE_SYNC: &[Sync] = &[
    sync(
        "QueueSeqs",
        None,
        Need::Acquire,
        Need::Release,
        Need::AcqRel,
    ),
    sync("QueueState", None, Need::Atomic, Need::Atomic, Need::Atomic),
    sync(
        "Counters",
        Some(C_IN_FLIGHT),
        Need::Acquire,
        Need::Release,
        Need::Release,
    ),
    sync(
        "Counters",
        Some(C_IDLE),
        Need::Atomic,
        Need::Atomic,
        Need::Atomic,
    ),
    sync(
        "Counters",
        Some(C_NEXT_BASE),
        Need::Atomic,
        Need::Atomic,
        Need::Atomic,
    ),
];

/// Blocks whose data is published through those words: every plain access
/// must be device-coherent.
const LEVEL_DATA: &[&str] = &["LevelNodes", "LevelScans", "LevelState", "Roots"];
const QUEUE_DATA: &[&str] = &["QueueItems"];

struct Module {
    all: Vec<Instruction>,
    constants: HashMap<u32, u32>,
    /// Result id of a pointer into a block: (block name, constant word index
    /// or None).
    pointers: HashMap<u32, (String, Option<u32>)>,
}

impl Module {
    fn load(shader: &str) -> Self {
        Self::parse(shader, &load_spirv(shader).unwrap())
    }

    fn parse(shader: &str, words: &[u32]) -> Self {
        let all = common::spirv::instructions(shader, words);
        let mut names = HashMap::new();
        let mut constants = HashMap::new();
        let mut types: HashMap<u32, Instruction> = HashMap::new();
        for i in &all {
            if let (Op::Name, [t, Operand::LiteralString(s)]) =
                (i.class.opcode, i.operands.as_slice())
            {
                names.insert(id(t), s.clone());
            }
            if let Some(r) = i.result_id {
                if i.class.opcode == Op::Constant {
                    if let Some(Operand::LiteralBit32(v)) = i.operands.first() {
                        constants.insert(r, *v);
                    }
                }
                types.insert(r, i.clone());
            }
        }
        let mut pointers = HashMap::new();
        // Variables of block type, then access chains into them.
        for i in &all {
            if i.class.opcode != Op::Variable {
                continue;
            }
            let ptr = &types[&i.result_type.unwrap()];
            let pointee = id(&ptr.operands[1]);
            if let Some(name) = names.get(&pointee) {
                pointers.insert(i.result_id.unwrap(), (name.clone(), None));
            }
        }
        for i in &all {
            if i.class.opcode != Op::AccessChain {
                continue;
            }
            let base = id(&i.operands[0]);
            let Some((block, _)) = pointers.get(&base).cloned() else {
                continue;
            };
            // block.member[index]: the runtime array is member 0.
            let word = i
                .operands
                .get(2)
                .and_then(|o| constants.get(&id(o)).copied());
            pointers.insert(i.result_id.unwrap(), (block, word));
        }
        Module {
            all,
            constants,
            pointers,
        }
    }

    fn constant(&self, op: &Operand) -> u32 {
        self.constants[&id(op)]
    }
}

fn semantics_ok(bits: u32, need: Need) -> bool {
    let acq = bits & (ACQUIRE | ACQUIRE_RELEASE | SEQ_CST) != 0;
    let rel = bits & (RELEASE | ACQUIRE_RELEASE | SEQ_CST) != 0;
    match need {
        Need::Atomic => true,
        Need::Acquire => acq,
        Need::Release => rel,
        Need::AcqRel => acq && rel,
    }
}

/// Every breach of the rules in `shader`, as sentences.
fn breaches(shader: &str, rules: &[Sync], data: &[&str]) -> Vec<String> {
    breaches_in(shader, &Module::load(shader), rules, data)
}

fn breaches_in(shader: &str, m: &Module, rules: &[Sync], data: &[&str]) -> Vec<String> {
    let mut out = Vec::new();
    let vulkan = m.all.iter().any(|i| {
        i.class.opcode == Op::MemoryModel
            && i.operands.get(1) == Some(&Operand::MemoryModel(MemoryModel::Vulkan))
    });
    if !vulkan {
        out.push(format!("{shader} does not use the Vulkan memory model"));
    }
    let rule = |p: u32| {
        let (block, word) = m.pointers.get(&p)?;
        rules
            .iter()
            .find(|r| r.block == block && (r.word.is_none() || r.word == *word))
            .map(|r| (r, block.clone(), *word))
    };
    for i in &m.all {
        let op = i.class.opcode;
        let ptr = match op {
            Op::Load
            | Op::Store
            | Op::AtomicLoad
            | Op::AtomicStore
            | Op::AtomicIAdd
            | Op::AtomicOr
            | Op::AtomicUMax
            | Op::AtomicExchange
            | Op::AtomicCompareExchange => id(&i.operands[0]),
            _ => continue,
        };
        let what = |block: &str, word: Option<u32>| match word {
            Some(w) => format!("{block}[{w}]"),
            None => block.to_string(),
        };
        if let Some((r, block, word)) = rule(ptr) {
            let (need, sem, scope) = match op {
                Op::Load | Op::Store => {
                    out.push(format!(
                        "{shader}: a plain {op:?} of {}",
                        what(&block, word)
                    ));
                    continue;
                }
                Op::AtomicLoad => (r.load, &i.operands[2], &i.operands[1]),
                Op::AtomicStore => (r.store, &i.operands[2], &i.operands[1]),
                _ => (r.rmw, &i.operands[2], &i.operands[1]),
            };
            let scope = m.constant(scope);
            if scope != Scope::Device as u32 && scope != Scope::QueueFamily as u32 {
                out.push(format!(
                    "{shader}: {op:?} of {} at scope {scope}",
                    what(&block, word)
                ));
            }
            if !semantics_ok(m.constant(sem), need) {
                out.push(format!(
                    "{shader}: {op:?} of {} with semantics {:#x}, needs {need:?}",
                    what(&block, word),
                    m.constant(sem)
                ));
            }
            continue;
        }
        // Data behind the flags: plain accesses must be device-coherent.
        let Some((block, word)) = m.pointers.get(&ptr) else {
            continue;
        };
        if !data.contains(&block.as_str()) || !matches!(op, Op::Load | Op::Store) {
            continue;
        }
        let access = i.operands.iter().find_map(|o| match o {
            Operand::MemoryAccess(a) => Some(*a),
            _ => None,
        });
        let need = if op == Op::Load {
            MemoryAccess::MAKE_POINTER_VISIBLE
        } else {
            MemoryAccess::MAKE_POINTER_AVAILABLE
        } | MemoryAccess::NON_PRIVATE_POINTER;
        if !access.is_some_and(|a| a.contains(need)) {
            out.push(format!(
                "{shader}: a {op:?} of {} without device-scope {}",
                what(block, *word),
                if op == Op::Load {
                    "visibility"
                } else {
                    "availability"
                }
            ));
        }
    }
    out
}

#[test]
fn level_kernels_synchronise_only_through_acquire_release_atomics() {
    for shader in [
        "levels/persistent.comp",
        "levels/round.comp",
        "levels/clusters.comp",
    ] {
        let b = breaches(shader, LEVEL_SYNC, LEVEL_DATA);
        assert!(b.is_empty(), "{}", b.join("\n"));
    }
}

#[test]
fn queue_kernel_synchronises_only_through_acquire_release_atomics() {
    let b = breaches("subdiv/queue.comp", QUEUE_SYNC, QUEUE_DATA);
    assert!(b.is_empty(), "{}", b.join("\n"));
}

/// The checker itself: the queue kernel as a7d19dc compiled it (sequence
/// numbers and the in-flight count read with plain loads behind fences,
/// the GLSL 450 memory model) must fail it on each of those counts.
#[test]
fn the_check_finds_the_races_of_a7d19dc() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/spirv/subdivide-a7d19dc.comp.spv");
    let words = bezier_subdiv::vk::load_spirv_file(&path).unwrap();
    let m = Module::parse("a7d19dc", &words);
    let b = breaches_in("a7d19dc", &m, QUEUE_SYNC, QUEUE_DATA);
    println!("{}", b.join("\n"));
    let has = |what: &str| b.iter().any(|s| s.contains(what));
    assert!(has("does not use the Vulkan memory model"), "{b:?}");
    assert!(has("plain Load of QueueSeqs"), "{b:?}");
    assert!(has("plain Store of QueueSeqs"), "{b:?}");
    assert!(
        has(&format!("plain Load of Counters[{C_IN_FLIGHT}]")),
        "{b:?}"
    );
    assert!(has("plain Load of QueueState"), "{b:?}");
}
