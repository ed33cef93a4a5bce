//! The host's constant blocks against the shaders' own, by reflection of
//! the compiled SPIR-V: every push-constant block a renderer shader
//! declares has a Rust twin in `gpu::blocks` with the same members at the
//! same offsets and sizes (padding members aside), and so do the
//! criterion's `ViewParams` uniform struct and set 0's `Instance` record.
//! A member added, moved or retyped on one side only fails here instead of
//! corrupting a frame.

mod common;

use std::collections::HashMap;

use bezier_subdiv::gpu::blocks::BlockField;
use bezier_subdiv::methods::all_blocks;
use bezier_subdiv::vk::{embedded_shaders, load_spirv};
use common::spirv::{id, lit};
use rspirv::dr::{Instruction, Operand};
use rspirv::spirv::{Decoration, Op, StorageClass};

/// The Vulkan core's own self-test shader has its own block, checked by
/// the test that uses it.
const NOT_RENDERER: &[&str] = &["selftest.comp"];

/// What reflection needs of one module.
struct Reflected {
    names: HashMap<u32, String>,
    member_names: HashMap<(u32, u32), String>,
    offsets: HashMap<(u32, u32), u32>,
    array_strides: HashMap<u32, u32>,
    types: HashMap<u32, Instruction>,
    constants: HashMap<u32, u32>,
}

fn reflect(shader: &str) -> Reflected {
    let words = load_spirv(shader).unwrap();
    Reflected::new(&common::spirv::instructions(shader, &words))
}

impl Reflected {
    fn new(all: &[Instruction]) -> Self {
        let mut r = Reflected {
            names: HashMap::new(),
            member_names: HashMap::new(),
            offsets: HashMap::new(),
            array_strides: HashMap::new(),
            types: HashMap::new(),
            constants: HashMap::new(),
        };
        for i in all {
            match (i.class.opcode, i.operands.as_slice()) {
                (Op::Name, [target, Operand::LiteralString(s)]) => {
                    r.names.insert(id(target), s.clone());
                }
                (Op::MemberName, [target, member, Operand::LiteralString(s)]) => {
                    r.member_names.insert((id(target), lit(member)), s.clone());
                }
                _ => {}
            }
        }
        for i in all {
            match (i.class.opcode, i.operands.as_slice()) {
                (
                    Op::MemberDecorate,
                    [target, member, Operand::Decoration(Decoration::Offset), offset],
                ) => {
                    r.offsets.insert((id(target), lit(member)), lit(offset));
                }
                (Op::Decorate, [target, Operand::Decoration(Decoration::ArrayStride), stride]) => {
                    r.array_strides.insert(id(target), lit(stride));
                }
                _ => {}
            }
        }
        for i in all {
            let Some(result) = i.result_id else { continue };
            if i.class.opcode == Op::Constant {
                if let Some(Operand::LiteralBit32(v)) = i.operands.first() {
                    r.constants.insert(result, *v);
                }
            }
            r.types.insert(result, i.clone());
        }
        r
    }

    /// Bytes a value of type `t` occupies (std140/std430 as decorated).
    fn size(&self, t: u32) -> u32 {
        let i = &self.types[&t];
        let ops = &i.operands;
        match i.class.opcode {
            Op::TypeInt | Op::TypeFloat => lit(&ops[0]) / 8,
            Op::TypeVector => self.size(id(&ops[0])) * lit(&ops[1]),
            // Column-major with 16-byte columns (mat4 of vec4 here).
            Op::TypeMatrix => self.size(id(&ops[0])).max(16) * lit(&ops[1]),
            Op::TypeArray => {
                let len = self.constants[&id(&ops[1])];
                self.array_strides
                    .get(&t)
                    .copied()
                    .unwrap_or(self.size(id(&ops[0])))
                    * len
            }
            Op::TypeStruct => {
                let n = ops.len() as u32;
                self.offsets[&(t, n - 1)] + self.size(id(&ops[n as usize - 1]))
            }
            other => panic!("no size for {other:?}"),
        }
    }

    /// A struct's members as the shader lays them out, and its size.
    fn fields(&self, t: u32) -> (Vec<BlockField>, u32) {
        let i = &self.types[&t];
        let fields = i
            .operands
            .iter()
            .enumerate()
            .map(|(k, member)| {
                let name = self.member_names[&(t, k as u32)].clone();
                BlockField {
                    name: Box::leak(name.into_boxed_str()),
                    offset: self.offsets[&(t, k as u32)],
                    size: self.size(id(member)),
                }
            })
            .collect();
        (fields, self.size(t))
    }

    /// The struct types of push-constant variables.
    fn push_blocks(&self) -> Vec<u32> {
        self.types
            .values()
            .filter(|i| {
                i.class.opcode == Op::Variable
                    && i.operands.first()
                        == Some(&Operand::StorageClass(StorageClass::PushConstant))
            })
            .map(|var| {
                let ptr = &self.types[&var.result_type.unwrap()];
                id(&ptr.operands[1])
            })
            .collect()
    }

    /// The laid-out struct type of that name (glslang also emits an
    /// undecorated copy for function parameters, which has no offsets).
    fn struct_named(&self, name: &str) -> Option<u32> {
        self.types
            .iter()
            .find(|(t, i)| {
                i.class.opcode == Op::TypeStruct
                    && self.names.get(t).map(String::as_str) == Some(name)
                    && self.offsets.contains_key(&(**t, 0))
            })
            .map(|(t, _)| *t)
    }
}

fn without_padding(fields: &[BlockField]) -> Vec<BlockField> {
    fields
        .iter()
        .filter(|f| !f.name.starts_with("pad"))
        .copied()
        .collect()
}

/// Compares one reflected struct with the Rust block of the same name.
fn compare(shader: &str, r: &Reflected, t: u32) -> Result<&'static str, String> {
    let name = r.names.get(&t).cloned().unwrap_or_default();
    let blocks = all_blocks();
    let Some((rust_name, rust_size, rust_fields)) = blocks.iter().find(|(n, _, _)| *n == name)
    else {
        return Err(format!(
            "{shader}: block `{name}` has no Rust twin in methods::all_blocks (a method's own goes in its registry entry's `blocks`)"
        ));
    };
    let (fields, size) = r.fields(t);
    let (glsl, host) = (without_padding(&fields), without_padding(rust_fields));
    if glsl != host || size != *rust_size {
        return Err(format!(
            "{shader}: `{name}` differs\n  GLSL ({size} bytes): {glsl:?}\n  Rust ({rust_size} bytes): {host:?}"
        ));
    }
    Ok(rust_name)
}

#[test]
fn every_block_matches_its_rust_twin() {
    let mut checked: HashMap<&str, usize> = HashMap::new();
    let mut problems = Vec::new();
    for shader in embedded_shaders().filter(|s| !NOT_RENDERER.contains(s)) {
        let r = reflect(shader);
        let mut structs = r.push_blocks();
        structs.extend(r.struct_named("ViewParams"));
        structs.extend(r.struct_named("AnimDeformer"));
        structs.extend(r.struct_named("Instance"));
        for t in structs {
            match compare(shader, &r, t) {
                Ok(name) => *checked.entry(name).or_default() += 1,
                Err(e) => problems.push(e),
            }
        }
    }
    println!("blocks checked (shaders each): {checked:?}");
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    // Every Rust block is used by some shader: a stale twin is a defect too.
    for (name, _, _) in all_blocks() {
        assert!(checked.contains_key(name), "no shader declares `{name}`");
    }
}
