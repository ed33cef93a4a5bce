//! Compiled SPIR-V as a list of instructions.

use rspirv::binary::{Consumer, ParseAction};
use rspirv::dr::{Instruction, ModuleHeader, Operand};

/// Every instruction of a module, in order (the plain parser: rspirv's
/// module builder rejects the SPIR-V 1.6 `OpExecutionModeId` glslang emits
/// for `local_size_x` from a constant).
#[derive(Default)]
struct Collect(Vec<Instruction>);

impl Consumer for Collect {
    fn initialize(&mut self) -> ParseAction {
        ParseAction::Continue
    }
    fn finalize(&mut self) -> ParseAction {
        ParseAction::Continue
    }
    fn consume_header(&mut self, _: ModuleHeader) -> ParseAction {
        ParseAction::Continue
    }
    fn consume_instruction(&mut self, inst: Instruction) -> ParseAction {
        self.0.push(inst);
        ParseAction::Continue
    }
}

/// The instructions of `words`, the module of `shader` (named in a
/// failure to parse).
pub fn instructions(shader: &str, words: &[u32]) -> Vec<Instruction> {
    let mut all = Collect::default();
    rspirv::binary::parse_words(words, &mut all).unwrap_or_else(|e| panic!("{shader}: {e:?}"));
    all.0
}

/// The id an operand names (panics on another kind of operand).
pub fn id(op: &Operand) -> u32 {
    match op {
        Operand::IdRef(i) => *i,
        other => panic!("expected an id, got {other:?}"),
    }
}

/// The 32-bit literal of an operand (panics on another kind of operand).
pub fn lit(op: &Operand) -> u32 {
    match op {
        Operand::LiteralBit32(v) => *v,
        other => panic!("expected a literal, got {other:?}"),
    }
}
