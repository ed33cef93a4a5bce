//! `vk::reflect` against rspirv: for every embedded shader, the bindings
//! (set, binding, descriptor type, count), the stage and the push-block size
//! our small SPIR-V reader finds are what a full SPIR-V parser says. Then
//! the layouts the renderer reflects from lists of shaders: each list
//! agrees on its set (no type clash, no gap) and has the binding count the
//! host/shader contract declares, and set 0, which is declared (its view is
//! a dynamic uniform buffer), matches every shader that reads it.

mod common;

use std::collections::{BTreeMap, HashMap};

use ash::vk;
use bezier_subdiv::constants::*;
use bezier_subdiv::methods::{
    cudatess::constants::*, ground_truth::constants::*, subdiv::constants::*, tess::constants::*,
};
use bezier_subdiv::vk::{
    embedded_shaders, load_spirv, reflect, reflect_shader, set_bindings, undynamic,
};
use common::spirv::{id, lit};
use rspirv::dr::{Instruction, Operand};
use rspirv::spirv::{Decoration, ExecutionModel, Op, StorageClass};

/// What rspirv's parse says a layout needs of one module.
struct Truth {
    stages: vk::ShaderStageFlags,
    bindings: BTreeMap<(u32, u32), (vk::DescriptorType, u32)>,
    push_size: u32,
}

fn truth(shader: &str) -> Truth {
    let all = common::spirv::instructions(shader, &load_spirv(shader).unwrap());
    let by_id: HashMap<u32, &Instruction> = all
        .iter()
        .filter_map(|i| i.result_id.map(|r| (r, i)))
        .collect();
    let decorated = |target: u32, d: Decoration| -> Option<u32> {
        all.iter()
            .find_map(|i| match (i.class.opcode, i.operands.as_slice()) {
                (Op::Decorate, [t, Operand::Decoration(x), rest @ ..])
                    if id(t) == target && *x == d =>
                {
                    Some(rest.first().map_or(0, lit))
                }
                _ => None,
            })
    };
    let mut t = Truth {
        stages: vk::ShaderStageFlags::empty(),
        bindings: BTreeMap::new(),
        push_size: 0,
    };
    for i in &all {
        match (i.class.opcode, i.operands.as_slice()) {
            (Op::EntryPoint, [Operand::ExecutionModel(m), ..]) => {
                t.stages |= match m {
                    ExecutionModel::Vertex => vk::ShaderStageFlags::VERTEX,
                    ExecutionModel::TessellationControl => {
                        vk::ShaderStageFlags::TESSELLATION_CONTROL
                    }
                    ExecutionModel::TessellationEvaluation => {
                        vk::ShaderStageFlags::TESSELLATION_EVALUATION
                    }
                    ExecutionModel::Fragment => vk::ShaderStageFlags::FRAGMENT,
                    ExecutionModel::GLCompute => vk::ShaderStageFlags::COMPUTE,
                    ExecutionModel::TaskEXT => vk::ShaderStageFlags::TASK_EXT,
                    ExecutionModel::MeshEXT => vk::ShaderStageFlags::MESH_EXT,
                    other => panic!("{shader}: unexpected stage {other:?}"),
                }
            }
            (Op::Variable, [Operand::StorageClass(class), ..]) => {
                let var = i.result_id.unwrap();
                let ptr = by_id[&i.result_type.unwrap()];
                let mut ty = by_id[&id(&ptr.operands[1])];
                if *class == StorageClass::PushConstant {
                    t.push_size = struct_size(&all, &by_id, ty);
                    continue;
                }
                let (Some(set), Some(binding)) = (
                    decorated(var, Decoration::DescriptorSet),
                    decorated(var, Decoration::Binding),
                ) else {
                    continue;
                };
                let mut count = 1;
                if ty.class.opcode == Op::TypeArray {
                    count = lit(&by_id[&id(&ty.operands[1])].operands[0]);
                    ty = by_id[&id(&ty.operands[0])];
                }
                let block = ty.result_id.unwrap();
                let d = match (class, ty.class.opcode) {
                    (StorageClass::StorageBuffer, _) => vk::DescriptorType::STORAGE_BUFFER,
                    (StorageClass::Uniform, _)
                        if decorated(block, Decoration::BufferBlock).is_some() =>
                    {
                        vk::DescriptorType::STORAGE_BUFFER
                    }
                    (StorageClass::Uniform, _) => vk::DescriptorType::UNIFORM_BUFFER,
                    (StorageClass::UniformConstant, Op::TypeSampledImage) => {
                        vk::DescriptorType::COMBINED_IMAGE_SAMPLER
                    }
                    (StorageClass::UniformConstant, Op::TypeSampler) => vk::DescriptorType::SAMPLER,
                    (StorageClass::UniformConstant, Op::TypeImage) => {
                        if lit(&ty.operands[5]) == 2 {
                            vk::DescriptorType::STORAGE_IMAGE
                        } else {
                            vk::DescriptorType::SAMPLED_IMAGE
                        }
                    }
                    other => panic!("{shader}: unexpected resource {other:?}"),
                };
                t.bindings.insert((set, binding), (d, count));
            }
            _ => {}
        }
    }
    t
}

/// Bytes of a push block: the end of its last member (glslang lays
/// members out in order), members sized as std430 scalars, vectors and
/// decorated arrays.
fn struct_size(all: &[Instruction], by_id: &HashMap<u32, &Instruction>, ty: &Instruction) -> u32 {
    let s = ty.result_id.unwrap();
    let last = ty.operands.len() as u32 - 1;
    let offset = all
        .iter()
        .find_map(|i| match (i.class.opcode, i.operands.as_slice()) {
            (Op::MemberDecorate, [t, m, Operand::Decoration(Decoration::Offset), o])
                if id(t) == s && lit(m) == last =>
            {
                Some(lit(o))
            }
            _ => None,
        })
        .unwrap();
    offset + size(all, by_id, by_id[&id(&ty.operands[last as usize])])
}

fn size(all: &[Instruction], by_id: &HashMap<u32, &Instruction>, ty: &Instruction) -> u32 {
    let ops = &ty.operands;
    match ty.class.opcode {
        Op::TypeInt | Op::TypeFloat => lit(&ops[0]) / 8,
        Op::TypeVector | Op::TypeMatrix => size(all, by_id, by_id[&id(&ops[0])]) * lit(&ops[1]),
        Op::TypeArray => {
            let len = lit(&by_id[&id(&ops[1])].operands[0]);
            let stride = all.iter().find_map(|i| match i.operands.as_slice() {
                [t, Operand::Decoration(Decoration::ArrayStride), s]
                    if i.class.opcode == Op::Decorate && Some(id(t)) == ty.result_id =>
                {
                    Some(lit(s))
                }
                _ => None,
            });
            len * stride.unwrap_or_else(|| size(all, by_id, by_id[&id(&ops[0])]))
        }
        Op::TypeStruct => struct_size(all, by_id, ty),
        other => panic!("no size for {other:?}"),
    }
}

#[test]
fn reflection_agrees_with_rspirv_for_every_shader() {
    let mut checked = 0;
    for shader in embedded_shaders() {
        let r = reflect(&load_spirv(shader).unwrap()).unwrap_or_else(|e| panic!("{shader}: {e}"));
        let t = truth(shader);
        assert_eq!(r.stages, t.stages, "{shader}: stages");
        assert_eq!(r.bindings, t.bindings, "{shader}: bindings");
        assert_eq!(r.push_size, t.push_size, "{shader}: push-constant block");
        checked += 1;
    }
    assert!(checked >= 30, "only {checked} embedded shaders");
}

/// Each list of shaders the renderer makes a set layout from, with the set
/// and the binding count of the host/shader contract.
#[test]
fn reflected_set_layouts_are_whole_and_agree() {
    use bezier_subdiv::draw::{hiz::HIZ_SHADERS, ready::READY_SHADERS};
    use bezier_subdiv::gpu::anim::ANIM_SHADER;
    use bezier_subdiv::methods::{
        cudatess::scan::CT_SHADERS, ground_truth::GRID_SHADERS, levels::LEVEL_SHADERS,
        subdiv::QUEUE_SHADERS, tess::TESS_SHADERS,
    };
    let layouts: [(&str, u32, &[&str], u32); 8] = [
        ("ready-list set", SET_PASS, READY_SHADERS, READY_BINDINGS),
        ("depth pyramid set", SET_PASS, HIZ_SHADERS, HIZ_BINDINGS),
        ("cudatess set", SET_PASS, CT_SHADERS, CT_BINDINGS),
        ("grid set", SET_PASS, GRID_SHADERS, GRID_BINDINGS),
        ("tess set", SET_PASS, TESS_SHADERS, TESS_BINDINGS),
        ("level set", SET_PRODUCER, LEVEL_SHADERS, LEVEL_BINDINGS),
        ("queue set", SET_PRODUCER, QUEUE_SHADERS, QUEUE_BINDINGS),
        ("animation set", 0, &[ANIM_SHADER], ANIM_BINDINGS),
    ];
    for (name, set, shaders, count) in layouts {
        let reflected: Vec<_> = shaders
            .iter()
            .map(|s| (*s, reflect_shader(s).unwrap()))
            .collect();
        let refs: Vec<_> = reflected.iter().map(|(s, r)| (*s, r)).collect();
        let bindings = set_bindings(name, set, &refs).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(bindings.len() as u32, count, "{name}");
    }
}

#[test]
fn set_layouts_refuse_disagreeing_shaders() {
    // Set 1 is the ready list in sort.comp but cudatess's set in
    // cudatess/args.comp: binding 4 is a storage buffer in both, so make one
    // disagree by hand.
    let a = reflect_shader("sort.comp").unwrap();
    let mut b = reflect_shader("cudatess/args.comp").unwrap();
    b.bindings
        .insert((SET_PASS, 4), (vk::DescriptorType::UNIFORM_BUFFER, 1));
    let e = set_bindings(
        "test set",
        SET_PASS,
        &[("sort.comp", &a), ("cudatess/args.comp", &b)],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("sort.comp") && e.contains("cudatess/args.comp") && e.contains("binding 4"),
        "{e}"
    );
    // A list that leaves a binding out names the gap.
    let e = set_bindings(
        "gap",
        SET_PASS,
        &[(
            "cudatess/scan.comp",
            &reflect_shader("cudatess/scan.comp").unwrap(),
        )],
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("binding 0") && e.contains("cudatess/scan.comp"),
        "{e}"
    );
}

/// Set 0 is declared by hand; every shader that reads it (all but the
/// animation update, whose set 0 is its own, and the Vulkan core's
/// self-test) must read it as declared.
#[test]
fn the_declared_scene_set_matches_every_shader() {
    let declared = bezier_subdiv::gpu::scene_set_types();
    for shader in embedded_shaders() {
        if ["anim_update.comp", "selftest.comp"].contains(&shader) {
            continue;
        }
        let r = reflect_shader(shader).unwrap();
        for (&(set, binding), &(ty, count)) in &r.bindings {
            if set != SET_SCENE {
                continue;
            }
            let have = declared.get(binding as usize).map(|&t| undynamic(t));
            assert_eq!(
                have,
                Some(ty),
                "{shader}: set 0 binding {binding} is {ty:?}, declared {have:?}"
            );
            assert_eq!(count, 1, "{shader}: set 0 binding {binding}");
        }
    }
}
