//! What a pipeline's layout must hold, read from the shaders' SPIR-V.
//!
//! Set layouts and push ranges were declared by hand next to each pass, so
//! a shader that gained a binding or a push field could drift from its
//! layout until the validation layer (or a wrong image) said so. This reads
//! the few facts a layout needs straight from the module words, the way
//! niagara's `parseShader` does: the entry point's stage, each resource
//! variable's (set, binding) with its descriptor type and count, and the
//! push-constant block's size. It is a single pass over the instructions
//! and knows only the opcodes our shaders use for those facts.

use ash::vk;
use std::collections::{BTreeMap, HashMap};

/// The facts a layout needs from one shader module.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Reflection {
    /// The stages of the module's entry points.
    pub stages: vk::ShaderStageFlags,
    /// Descriptor type and count per (set, binding).
    pub bindings: BTreeMap<(u32, u32), (vk::DescriptorType, u32)>,
    /// Bytes of the push-constant block (0 when there is none).
    pub push_size: u32,
    /// The (set, binding)s the module may write: storage buffers and images
    /// not declared `readonly` (a block counts as read-only when every
    /// member is). A pass running the module declares these as writes and
    /// its other bindings as reads ([`crate::vk::Pass::bind`]).
    pub written: std::collections::BTreeSet<(u32, u32)>,
}

// Opcodes, decorations, storage classes and execution models of the
// SPIR-V specification (section 3), only the ones read here.
const OP_ENTRY_POINT: u32 = 15;
const OP_TYPE_BOOL: u32 = 20;
const OP_TYPE_INT: u32 = 21;
const OP_TYPE_FLOAT: u32 = 22;
const OP_TYPE_VECTOR: u32 = 23;
const OP_TYPE_MATRIX: u32 = 24;
const OP_TYPE_IMAGE: u32 = 25;
const OP_TYPE_SAMPLER: u32 = 26;
const OP_TYPE_SAMPLED_IMAGE: u32 = 27;
const OP_TYPE_ARRAY: u32 = 28;
const OP_TYPE_RUNTIME_ARRAY: u32 = 29;
const OP_TYPE_STRUCT: u32 = 30;
const OP_TYPE_POINTER: u32 = 32;
const OP_CONSTANT: u32 = 43;
const OP_VARIABLE: u32 = 59;
const OP_DECORATE: u32 = 71;
const OP_MEMBER_DECORATE: u32 = 72;

const DEC_BUFFER_BLOCK: u32 = 3;
const DEC_NON_WRITABLE: u32 = 24;
const DEC_ARRAY_STRIDE: u32 = 6;
const DEC_MATRIX_STRIDE: u32 = 7;
const DEC_BINDING: u32 = 33;
const DEC_DESCRIPTOR_SET: u32 = 34;
const DEC_OFFSET: u32 = 35;

const SC_UNIFORM_CONSTANT: u32 = 0;
const SC_UNIFORM: u32 = 2;
const SC_PUSH_CONSTANT: u32 = 9;
const SC_STORAGE_BUFFER: u32 = 12;

/// `Dim` of a texel buffer image (a texel-buffer descriptor, not an image).
const DIM_BUFFER: u32 = 5;

/// The Vulkan stage of a SPIR-V execution model.
fn stage(model: u32) -> Result<vk::ShaderStageFlags, String> {
    Ok(match model {
        0 => vk::ShaderStageFlags::VERTEX,
        1 => vk::ShaderStageFlags::TESSELLATION_CONTROL,
        2 => vk::ShaderStageFlags::TESSELLATION_EVALUATION,
        3 => vk::ShaderStageFlags::GEOMETRY,
        4 => vk::ShaderStageFlags::FRAGMENT,
        5 => vk::ShaderStageFlags::COMPUTE,
        5364 => vk::ShaderStageFlags::TASK_EXT,
        5365 => vk::ShaderStageFlags::MESH_EXT,
        m => return Err(format!("execution model {m} is not one a layout knows")),
    })
}

/// A type instruction, kept for what sizes and descriptor types need.
#[derive(Clone, Debug)]
enum Type {
    /// Bool, int or float of this many bytes.
    Scalar(u32),
    /// `count` components of type `of` (vectors; matrices are columns).
    Vector {
        of: u32,
        count: u32,
    },
    Matrix {
        column: u32,
        count: u32,
    },
    /// `length` is the id of the constant that gives the length.
    Array {
        of: u32,
        length: u32,
    },
    RuntimeArray,
    Struct(Vec<u32>),
    /// `sampled` is 1 for a sampled image, 2 for a storage image.
    Image {
        dim: u32,
        sampled: u32,
    },
    Sampler,
    SampledImage,
    Pointer {
        class: u32,
        to: u32,
    },
}

/// What one pass over a module collected.
#[derive(Default)]
struct Module {
    stages: vk::ShaderStageFlags,
    types: HashMap<u32, Type>,
    constants: HashMap<u32, u32>,
    /// Decorations on ids: (id, decoration) -> first literal.
    decorations: HashMap<(u32, u32), u32>,
    /// Offset decorations on struct members: (struct, member) -> bytes.
    offsets: HashMap<(u32, u32), u32>,
    matrix_strides: HashMap<(u32, u32), u32>,
    /// Struct members decorated `NonWritable` (a `readonly` block's).
    read_only_members: std::collections::HashSet<(u32, u32)>,
    /// (pointer type, variable id) per module-scope variable.
    variables: Vec<(u32, u32)>,
}

/// Reads the layout facts of a module (`words` with the 5-word header).
pub fn reflect(words: &[u32]) -> Result<Reflection, String> {
    let m = scan(words)?;
    let mut out = Reflection {
        stages: m.stages,
        ..Default::default()
    };
    for &(ptr, var) in &m.variables {
        let Some(&Type::Pointer { class, to }) = m.types.get(&ptr) else {
            return Err(format!("variable %{var} has a type that is not a pointer"));
        };
        if class == SC_PUSH_CONSTANT {
            out.push_size = out.push_size.max(m.size(to)?);
            continue;
        }
        let set = m.decorations.get(&(var, DEC_DESCRIPTOR_SET));
        let binding = m.decorations.get(&(var, DEC_BINDING));
        let (Some(&set), Some(&binding)) = (set, binding) else {
            continue; // inputs, outputs, shared and private memory
        };
        let (inner, count) = m.unarray(to)?;
        let ty = m.descriptor_type(class, inner)?;
        out.bindings.insert((set, binding), (ty, count));
        if m.may_write(var, inner, ty) {
            out.written.insert((set, binding));
        }
    }
    Ok(out)
}

/// One pass over the instructions, keeping what [`reflect`] reads.
fn scan(words: &[u32]) -> Result<Module, String> {
    if words.len() < 5 || words[0] != 0x0723_0203 {
        return Err("not a SPIR-V module (header missing or bad magic)".into());
    }
    let mut m = Module::default();
    let mut at = 5;
    while at < words.len() {
        let count = (words[at] >> 16) as usize;
        let op = words[at] & 0xffff;
        if count == 0 || at + count > words.len() {
            return Err(format!("instruction at word {at} runs past the module"));
        }
        let a = &words[at + 1..at + count];
        // Operand `i`, or 0 for a truncated instruction (the spec's minimum
        // word counts make that impossible in a valid module).
        let w = |i: usize| a.get(i).copied().unwrap_or(0);
        match op {
            OP_ENTRY_POINT => m.stages |= stage(w(0))?,
            OP_TYPE_BOOL => {
                m.types.insert(w(0), Type::Scalar(4));
            }
            OP_TYPE_INT | OP_TYPE_FLOAT => {
                m.types.insert(w(0), Type::Scalar(w(1) / 8));
            }
            OP_TYPE_VECTOR => {
                let t = Type::Vector {
                    of: w(1),
                    count: w(2),
                };
                m.types.insert(w(0), t);
            }
            OP_TYPE_MATRIX => {
                let t = Type::Matrix {
                    column: w(1),
                    count: w(2),
                };
                m.types.insert(w(0), t);
            }
            OP_TYPE_IMAGE => {
                let t = Type::Image {
                    dim: w(2),
                    sampled: w(6),
                };
                m.types.insert(w(0), t);
            }
            OP_TYPE_SAMPLER => {
                m.types.insert(w(0), Type::Sampler);
            }
            OP_TYPE_SAMPLED_IMAGE => {
                m.types.insert(w(0), Type::SampledImage);
            }
            OP_TYPE_ARRAY => {
                let t = Type::Array {
                    of: w(1),
                    length: w(2),
                };
                m.types.insert(w(0), t);
            }
            OP_TYPE_RUNTIME_ARRAY => {
                m.types.insert(w(0), Type::RuntimeArray);
            }
            OP_TYPE_STRUCT => {
                m.types
                    .insert(w(0), Type::Struct(a.get(1..).unwrap_or(&[]).to_vec()));
            }
            OP_TYPE_POINTER => {
                let t = Type::Pointer {
                    class: w(1),
                    to: w(2),
                };
                m.types.insert(w(0), t);
            }
            // Only 32-bit constants size arrays here: the low word is enough.
            OP_CONSTANT => {
                m.constants.insert(w(1), w(2));
            }
            OP_VARIABLE if w(2) != 7 => m.variables.push((w(0), w(1))), // 7: Function
            OP_DECORATE => {
                m.decorations.insert((w(0), w(1)), w(2));
            }
            OP_MEMBER_DECORATE if w(2) == DEC_OFFSET => {
                m.offsets.insert((w(0), w(1)), w(3));
            }
            OP_MEMBER_DECORATE if w(2) == DEC_MATRIX_STRIDE => {
                m.matrix_strides.insert((w(0), w(1)), w(3));
            }
            OP_MEMBER_DECORATE if w(2) == DEC_NON_WRITABLE => {
                m.read_only_members.insert((w(0), w(1)));
            }
            _ => {}
        }
        at += count;
    }
    Ok(m)
}

impl Module {
    fn ty(&self, id: u32) -> Result<&Type, String> {
        self.types
            .get(&id)
            .ok_or_else(|| format!("%{id} is not a type this reader knows"))
    }

    /// The element type and descriptor count of a possibly arrayed resource.
    fn unarray(&self, id: u32) -> Result<(u32, u32), String> {
        match *self.ty(id)? {
            Type::Array { of, length } => {
                let n = self.constants.get(&length).copied();
                Ok((
                    of,
                    n.ok_or(format!("array length %{length} is not a constant"))?,
                ))
            }
            _ => Ok((id, 1)),
        }
    }

    /// Whether variable `var` (of type `ty`, descriptor type `kind`) may be
    /// written: a storage buffer or image not decorated `NonWritable`, on
    /// the variable or on every member of its block.
    fn may_write(&self, var: u32, ty: u32, kind: vk::DescriptorType) -> bool {
        use vk::DescriptorType as D;
        if !matches!(
            kind,
            D::STORAGE_BUFFER | D::STORAGE_IMAGE | D::STORAGE_TEXEL_BUFFER
        ) || self.decorations.contains_key(&(var, DEC_NON_WRITABLE))
        {
            return false;
        }
        match self.types.get(&ty) {
            Some(Type::Struct(members)) => {
                (0..members.len() as u32).any(|k| !self.read_only_members.contains(&(ty, k)))
            }
            _ => true,
        }
    }

    /// The descriptor type of a variable of class `class` and type `id`.
    fn descriptor_type(&self, class: u32, id: u32) -> Result<vk::DescriptorType, String> {
        use vk::DescriptorType as D;
        Ok(match (class, self.ty(id)?) {
            (SC_STORAGE_BUFFER, _) => D::STORAGE_BUFFER,
            // Before SPIR-V 1.3 storage buffers were Uniform + BufferBlock.
            (SC_UNIFORM, _) if self.decorations.contains_key(&(id, DEC_BUFFER_BLOCK)) => {
                D::STORAGE_BUFFER
            }
            (SC_UNIFORM, _) => D::UNIFORM_BUFFER,
            (SC_UNIFORM_CONSTANT, Type::SampledImage) => D::COMBINED_IMAGE_SAMPLER,
            (SC_UNIFORM_CONSTANT, Type::Sampler) => D::SAMPLER,
            (SC_UNIFORM_CONSTANT, &Type::Image { dim, sampled }) => match (dim, sampled) {
                (DIM_BUFFER, 2) => D::STORAGE_TEXEL_BUFFER,
                (DIM_BUFFER, _) => D::UNIFORM_TEXEL_BUFFER,
                (_, 2) => D::STORAGE_IMAGE,
                _ => D::SAMPLED_IMAGE,
            },
            (c, t) => return Err(format!("no descriptor type for {t:?} in storage class {c}")),
        })
    }

    /// Bytes of type `id` in an explicitly laid-out block: the end of its
    /// last member for a struct, the strides the decorations give for
    /// arrays and matrices.
    fn size(&self, id: u32) -> Result<u32, String> {
        Ok(match self.ty(id)? {
            &Type::Scalar(bytes) => bytes,
            &Type::Vector { of, count } => count * self.size(of)?,
            &Type::Matrix { column, count } => count * self.size(column)?,
            &Type::Array { of, length } => {
                let n = self.constants.get(&length).copied().unwrap_or(0);
                let stride = match self.decorations.get(&(id, DEC_ARRAY_STRIDE)) {
                    Some(&s) => s,
                    None => self.size(of)?,
                };
                n * stride
            }
            Type::Struct(members) => {
                let mut end = 0;
                for (k, &member) in members.iter().enumerate() {
                    let k = k as u32;
                    let offset = self.offsets.get(&(id, k)).copied().unwrap_or(0);
                    let size = match (self.ty(member)?, self.matrix_strides.get(&(id, k))) {
                        (&Type::Matrix { count, .. }, Some(&stride)) => count * stride,
                        _ => self.size(member)?,
                    };
                    end = end.max(offset + size);
                }
                end
            }
            t => return Err(format!("no size for {t:?} in a push-constant block")),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An instruction: opcode and operands, with its word count.
    fn op(code: u32, operands: &[u32]) -> Vec<u32> {
        let mut v = vec![((operands.len() as u32 + 1) << 16) | code];
        v.extend_from_slice(operands);
        v
    }

    fn module(body: &[Vec<u32>]) -> Vec<u32> {
        let mut w = vec![0x0723_0203, 0x0001_0600, 0, 100, 0];
        body.iter().for_each(|i| w.extend_from_slice(i));
        w
    }

    /// A compute shader with a storage buffer at (1, 2), an array of three
    /// combined image samplers at (0, 5), an old-style BufferBlock buffer
    /// at (0, 0), a uniform block at (2, 0) and a push block
    /// `{ uint a; vec3 b @16; mat2 m @32 (stride 16) }` of 64 bytes.
    fn sample() -> Vec<u32> {
        module(&[
            op(OP_ENTRY_POINT, &[5, 1, 0x6e69_616d, 0]),
            op(OP_DECORATE, &[20, DEC_DESCRIPTOR_SET, 1]),
            op(OP_DECORATE, &[20, DEC_BINDING, 2]),
            op(OP_DECORATE, &[21, DEC_DESCRIPTOR_SET, 0]),
            op(OP_DECORATE, &[21, DEC_BINDING, 5]),
            op(OP_DECORATE, &[22, DEC_DESCRIPTOR_SET, 0]),
            op(OP_DECORATE, &[22, DEC_BINDING, 0]),
            op(OP_DECORATE, &[13, DEC_BUFFER_BLOCK]),
            op(OP_DECORATE, &[23, DEC_DESCRIPTOR_SET, 2]),
            op(OP_DECORATE, &[23, DEC_BINDING, 0]),
            op(OP_MEMBER_DECORATE, &[12, 0, DEC_OFFSET, 0]),
            op(OP_MEMBER_DECORATE, &[12, 1, DEC_OFFSET, 16]),
            op(OP_MEMBER_DECORATE, &[12, 2, DEC_OFFSET, 32]),
            op(OP_MEMBER_DECORATE, &[12, 2, DEC_MATRIX_STRIDE, 16]),
            op(OP_TYPE_INT, &[2, 32, 0]),
            op(OP_TYPE_FLOAT, &[3, 32]),
            op(OP_TYPE_VECTOR, &[4, 3, 3]),
            op(OP_TYPE_VECTOR, &[5, 3, 2]),
            op(OP_TYPE_MATRIX, &[6, 5, 2]),
            op(OP_CONSTANT, &[2, 7, 3]),
            op(OP_TYPE_IMAGE, &[8, 3, 1, 0, 0, 0, 1, 0]),
            op(OP_TYPE_SAMPLED_IMAGE, &[9, 8]),
            op(OP_TYPE_ARRAY, &[10, 9, 7]),
            op(OP_TYPE_STRUCT, &[11, 2]),
            op(OP_TYPE_STRUCT, &[12, 2, 4, 6]),
            op(OP_TYPE_STRUCT, &[13, 2]),
            op(OP_TYPE_POINTER, &[30, SC_STORAGE_BUFFER, 11]),
            op(OP_TYPE_POINTER, &[31, SC_UNIFORM_CONSTANT, 10]),
            op(OP_TYPE_POINTER, &[32, SC_UNIFORM, 13]),
            op(OP_TYPE_POINTER, &[33, SC_UNIFORM, 11]),
            op(OP_TYPE_POINTER, &[34, SC_PUSH_CONSTANT, 12]),
            op(OP_VARIABLE, &[30, 20, SC_STORAGE_BUFFER]),
            op(OP_VARIABLE, &[31, 21, SC_UNIFORM_CONSTANT]),
            op(OP_VARIABLE, &[32, 22, SC_UNIFORM]),
            op(OP_VARIABLE, &[33, 23, SC_UNIFORM]),
            op(OP_VARIABLE, &[34, 24, SC_PUSH_CONSTANT]),
        ])
    }

    #[test]
    fn reads_stage_bindings_and_push_size() {
        let r = reflect(&sample()).unwrap();
        assert_eq!(r.stages, vk::ShaderStageFlags::COMPUTE);
        use vk::DescriptorType as D;
        let want: BTreeMap<_, _> = [
            ((0, 0), (D::STORAGE_BUFFER, 1)),
            ((0, 5), (D::COMBINED_IMAGE_SAMPLER, 3)),
            ((1, 2), (D::STORAGE_BUFFER, 1)),
            ((2, 0), (D::UNIFORM_BUFFER, 1)),
        ]
        .into_iter()
        .collect();
        assert_eq!(r.bindings, want);
        assert_eq!(r.push_size, 64);
    }

    #[test]
    fn refuses_what_it_cannot_read() {
        assert!(reflect(&[1, 2, 3]).is_err());
        let mut cut = sample();
        cut.truncate(cut.len() - 2);
        assert!(reflect(&cut).unwrap_err().contains("runs past"));
        let ray = module(&[op(OP_ENTRY_POINT, &[5313, 1, 0])]);
        assert!(reflect(&ray).unwrap_err().contains("5313"));
    }
}
