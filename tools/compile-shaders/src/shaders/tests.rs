//! Compiling, comparing and writing, driven directly (no process).

use super::*;
use crate::temp_dir::TempDir;

/// The first word of every SPIR-V module.
const SPIRV_MAGIC: u32 = 0x0723_0203;

const COMMON: &str = "float twice(float x) { return 2.0 * x; }\n";
const COMP: &str = "#version 460\n\
    #include \"common/math.glsl\"\n\
    layout(local_size_x = 8) in;\n\
    layout(std430, binding = 0) buffer Data { float v[]; };\n\
    void main() { v[gl_GlobalInvocationID.x] = twice(v[gl_GlobalInvocationID.x]); }\n";

fn first_word(bytes: &[u8]) -> u32 {
    u32::from_le_bytes(bytes[..4].try_into().unwrap())
}

fn compile_one(glsl: &Path, name: &str) -> Result<Compiled, Error> {
    let source = find_sources(glsl)?
        .into_iter()
        .find(|s| s.name == name)
        .expect("source exists");
    ShaderCompiler::new(glsl, &[])?.compile(&source)
}

#[test]
fn compiles_a_shader_with_an_include() {
    let dir = TempDir::new("include");
    dir.put("glsl/common/math.glsl", COMMON);
    dir.put("glsl/double.comp", COMP);
    let glsl = dir.0.join("glsl");
    let spirv = dir.0.join("spirv");

    let batch = compile_all(&glsl, &[]).unwrap();
    assert!(batch.failures.is_empty(), "{:?}", batch.failures);
    assert_eq!(
        batch.modules.len(),
        1,
        "common/ holds includes, not shaders"
    );
    let written = write_all(&spirv, &batch.modules).unwrap();
    assert_eq!(written.created, ["double.comp.spv"]);

    let bytes = fs::read(spirv.join("double.comp.spv")).unwrap();
    assert_eq!(bytes.len() % 4, 0);
    assert_eq!(first_word(&bytes), SPIRV_MAGIC);
    // Word 1 is the SPIR-V version: 1.6 for the Vulkan 1.3 environment.
    assert_eq!(
        u32::from_le_bytes(bytes[4..8].try_into().unwrap()),
        0x0001_0600
    );
}

#[test]
fn output_does_not_depend_on_where_the_source_lives() {
    let a = TempDir::new("where-a");
    let b = TempDir::new("where-b");
    for dir in [&a, &b] {
        dir.put("glsl/common/math.glsl", COMMON);
        dir.put("glsl/double.comp", COMP);
    }
    b.put("glsl/deeper/unused.txt", "");
    let first = compile_one(&a.0.join("glsl"), "double.comp").unwrap();
    let again = compile_one(&a.0.join("glsl"), "double.comp").unwrap();
    let elsewhere = compile_one(&b.0.join("glsl"), "double.comp").unwrap();
    assert_eq!(first.bytes, again.bytes);
    assert_eq!(first.bytes, elsewhere.bytes);
}

/// How many `OpDecorate %x NoContraction` the module holds.
fn no_contraction_count(bytes: &[u8]) -> usize {
    const OP_DECORATE: u32 = 71;
    const NO_CONTRACTION: u32 = 42;
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    let (mut at, mut count) = (5, 0);
    while at < words.len() {
        let (len, op) = ((words[at] >> 16) as usize, words[at] & 0xffff);
        assert!(len > 0, "malformed instruction at word {at}");
        if op == OP_DECORATE && words.get(at + 2) == Some(&NO_CONTRACTION) {
            count += 1;
        }
        at += len;
    }
    count
}

#[test]
fn precise_survives_as_no_contraction() {
    let dir = TempDir::new("precise");
    let body = "layout(local_size_x = 8) in;\n\
        layout(std430, binding = 0) buffer D { vec4 v[]; };\n\
        float f(vec4 a, vec4 b) { return (a.x * b.x + a.y * b.y) + (a.z * b.z + a.w * b.w); }\n\
        void main() { v[gl_GlobalInvocationID.x].x = f(v[0], v[1]); }\n";
    dir.put("glsl/plain.comp", &format!("#version 460\n{body}"));
    dir.put(
        "glsl/precise.comp",
        &format!(
            "#version 460\n{}",
            body.replacen("float f", "precise float f", 1)
        ),
    );
    let glsl = dir.0.join("glsl");
    let plain = compile_one(&glsl, "plain.comp").unwrap();
    let precise = compile_one(&glsl, "precise.comp").unwrap();
    assert_eq!(no_contraction_count(&plain.bytes), 0);
    // Four products and three sums, each decorated: nothing folded away.
    assert_eq!(no_contraction_count(&precise.bytes), 7);
}

#[test]
fn includes_resolve_from_the_includer_and_from_the_root() {
    let dir = TempDir::new("nested");
    // common/b.glsl includes a sibling by a relative name, and the shader
    // names it from the root.
    dir.put("glsl/common/a.glsl", "float one() { return 1.0; }\n");
    dir.put(
        "glsl/common/b.glsl",
        "#include \"a.glsl\"\n#include <common/a_guarded.glsl>\nfloat two() { return one() + one(); }\n",
    );
    dir.put(
        "glsl/common/a_guarded.glsl",
        "#ifndef A_GUARDED\n#define A_GUARDED\n#endif\n",
    );
    dir.put(
        "glsl/n.frag",
        "#version 460\n#include \"common/b.glsl\"\nlayout(location = 0) out vec4 c;\nvoid main() { c = vec4(two()); }\n",
    );
    let compiled = compile_one(&dir.0.join("glsl"), "n.frag").unwrap();
    assert_eq!(first_word(&compiled.bytes), SPIRV_MAGIC);
}

#[test]
fn a_missing_include_names_the_file_and_the_places_looked() {
    let dir = TempDir::new("noinclude");
    dir.put(
        "glsl/x.comp",
        "#version 460\n#include \"common/nope.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
    );
    dir.put("glsl/common/inner.glsl", "\n#include \"gone.glsl\"\n");
    dir.put(
        "glsl/y.comp",
        "#version 460\n#include \"common/inner.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
    );
    let glsl = dir.0.join("glsl");
    let err = compile_one(&glsl, "x.comp").unwrap_err().0;
    assert!(err.contains("x.comp:2:"), "{err}");
    assert!(err.contains("\"common/nope.glsl\" not found"), "{err}");

    // Nested: the line is the include file's, and both places are named.
    let err = compile_one(&glsl, "y.comp").unwrap_err().0;
    assert!(err.contains("inner.glsl:2:"), "{err}");
    let common = show(&glsl.join("common/gone.glsl"));
    let root = show(&glsl.join("gone.glsl"));
    assert!(
        err.contains(&format!("looked for {common}, {root})")),
        "{err}"
    );
}

#[test]
fn an_include_cycle_is_an_error_not_a_hang() {
    let dir = TempDir::new("cycle");
    dir.put("glsl/common/loop.glsl", "#include \"loop.glsl\"\n");
    dir.put(
        "glsl/x.comp",
        "#version 460\n#include \"common/loop.glsl\"\nlayout(local_size_x = 1) in;\nvoid main() {}\n",
    );
    let err = compile_one(&dir.0.join("glsl"), "x.comp").unwrap_err().0;
    assert!(err.contains("nested deeper"), "{err}");
}

#[test]
fn a_syntax_error_names_the_file_and_line() {
    let dir = TempDir::new("syntax");
    dir.put(
        "glsl/broken.vert",
        "#version 460\nvoid main() {\n  gl_Position = vec4(1.0)\n}\n",
    );
    let batch = compile_all(&dir.0.join("glsl"), &[]).unwrap();
    assert!(batch.modules.is_empty());
    let err = &batch.failures[0].0;
    assert!(err.contains("broken.vert:"), "{err}");
    // glslang reports the missing `;` where the next token starts, line 4.
    assert!(err.contains("broken.vert:4:"), "{err}");
}

#[test]
fn mesh_and_task_shaders_compile() {
    let dir = TempDir::new("mesh");
    dir.put(
        "glsl/quad.task",
        "#version 460\n#extension GL_EXT_mesh_shader : require\n\
         layout(local_size_x = 32) in;\n\
         struct Payload { uint base; };\ntaskPayloadSharedEXT Payload payload;\n\
         void main() { payload.base = gl_WorkGroupID.x; EmitMeshTasksEXT(1, 1, 1); }\n",
    );
    dir.put(
        "glsl/quad.mesh",
        "#version 460\n#extension GL_EXT_mesh_shader : require\n\
         layout(local_size_x = 32) in;\n\
         layout(triangles, max_vertices = 4, max_primitives = 2) out;\n\
         void main() {\n  SetMeshOutputsEXT(4, 2);\n\
           if (gl_LocalInvocationIndex < 4) {\n\
             precise float x = float(gl_LocalInvocationIndex & 1u) * 2.0 - 1.0;\n\
             gl_MeshVerticesEXT[gl_LocalInvocationIndex].gl_Position = vec4(x, 0.0, 0.0, 1.0);\n\
           }\n\
           if (gl_LocalInvocationIndex < 2) {\n\
             gl_PrimitiveTriangleIndicesEXT[gl_LocalInvocationIndex] = uvec3(0, 1, 2) + gl_LocalInvocationIndex;\n\
           }\n}\n",
    );
    let batch = compile_all(&dir.0.join("glsl"), &[]).unwrap();
    assert!(batch.failures.is_empty(), "{:?}", batch.failures);
    let names: Vec<&str> = batch.modules.iter().map(|(s, _)| s.name.as_str()).collect();
    assert_eq!(names, ["quad.mesh", "quad.task"]);
    for (_, compiled) in &batch.modules {
        assert_eq!(first_word(&compiled.bytes), SPIRV_MAGIC);
    }
}

#[test]
fn compare_and_write_track_stale_missing_and_orphaned_files() {
    let dir = TempDir::new("states");
    dir.put("glsl/common/math.glsl", COMMON);
    dir.put("glsl/a.comp", COMP);
    dir.put("glsl/b.comp", COMP);
    dir.put("spirv/a.comp.spv", "not spir-v");
    dir.put("spirv/gone.comp.spv", "old");
    dir.put("spirv/README.md", "not a module, left alone");
    let glsl = dir.0.join("glsl");
    let spirv = dir.0.join("spirv");

    let batch = compile_all(&glsl, &[]).unwrap();
    let states = compare(&spirv, &batch.modules).unwrap();
    assert_eq!(
        states,
        [
            ("a.comp.spv".to_owned(), State::Stale),
            ("b.comp.spv".to_owned(), State::Missing),
            ("gone.comp.spv".to_owned(), State::Orphaned),
        ]
    );

    let written = write_all(&spirv, &batch.modules).unwrap();
    assert_eq!(written.updated, ["a.comp.spv"]);
    assert_eq!(written.created, ["b.comp.spv"]);
    assert_eq!(written.removed, ["gone.comp.spv"]);
    assert!(spirv.join("README.md").exists());

    let states = compare(&spirv, &batch.modules).unwrap();
    assert!(
        states.iter().all(|(_, s)| *s == State::Current),
        "{states:?}"
    );
    let written = write_all(&spirv, &batch.modules).unwrap();
    assert_eq!(written.unchanged.len(), 2);
    // No temporary files are left behind.
    let mut left: Vec<String> = fs::read_dir(&spirv)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    left.sort();
    assert_eq!(left, ["README.md", "a.comp.spv", "b.comp.spv"]);
}

/// A method's folder of shaders compiles into a folder of the same name,
/// its files named by their path below `glsl/`; `common/` is include files
/// only; an orphan in a folder goes too.
#[test]
fn method_folders_compile_into_folders_of_their_own() {
    let dir = TempDir::new("folders");
    dir.put("glsl/common/math.glsl", COMMON);
    dir.put("glsl/common/not_compiled.comp", COMP);
    dir.put("glsl/top.comp", COMP);
    dir.put(
        "glsl/mine/own.glsl",
        "float thrice(float x) { return 3.0 * x; }\n",
    );
    dir.put(
        "glsl/mine/pass.comp",
        &COMP.replace(
            "#include \"common/math.glsl\"",
            "#include \"common/math.glsl\"\n#include \"own.glsl\"",
        ),
    );
    dir.put("spirv/mine/gone.comp.spv", "old");
    let glsl = dir.0.join("glsl");
    let spirv = dir.0.join("spirv");
    let batch = compile_all(&glsl, &[]).unwrap();
    let names: Vec<&str> = batch.modules.iter().map(|(s, _)| s.name.as_str()).collect();
    assert_eq!(names, ["mine/pass.comp", "top.comp"]);
    let written = write_all(&spirv, &batch.modules).unwrap();
    assert_eq!(written.created, ["mine/pass.comp.spv", "top.comp.spv"]);
    assert_eq!(written.removed, ["mine/gone.comp.spv"]);
    let bytes = fs::read(spirv.join("mine/pass.comp.spv")).unwrap();
    assert_eq!(first_word(&bytes), SPIRV_MAGIC);
    assert_eq!(
        find_spv_files(&spirv).unwrap(),
        ["mine/pass.comp.spv", "top.comp.spv"]
    );
}

#[test]
fn an_empty_glsl_directory_is_fine() {
    let dir = TempDir::new("empty");
    fs::create_dir_all(dir.0.join("glsl/common")).unwrap();
    let batch = compile_all(&dir.0.join("glsl"), &[]).unwrap();
    assert!(batch.modules.is_empty() && batch.failures.is_empty());
    assert!(compare(&dir.0.join("spirv"), &batch.modules)
        .unwrap()
        .is_empty());
}

#[test]
fn a_generated_include_is_read_from_memory_not_from_disk() {
    let dir = TempDir::new("generated");
    // Stale on disk; reached from the root by one shader and, through
    // common/inner.glsl, from the includer's directory by the other.
    dir.put("glsl/common/k.glsl", "const uint K = 1;\n");
    dir.put("glsl/common/inner.glsl", "#include \"k.glsl\"\n");
    let body = "layout(local_size_x = 1) in;\nuint check[(K == 2u) ? 1 : -1];\nvoid main() {}\n";
    dir.put(
        "glsl/root.comp",
        &format!("#version 460\n#include \"common/k.glsl\"\n{body}"),
    );
    dir.put(
        "glsl/nested.comp",
        &format!("#version 460\n#include \"common/inner.glsl\"\n{body}"),
    );
    let glsl = dir.0.join("glsl");
    // Spelled differently from the include paths on purpose.
    let generated = [Generated {
        path: glsl.join("common/../common/k.glsl"),
        text: "const uint K = 2;\n".to_owned(),
    }];

    let batch = compile_all(&glsl, &generated).unwrap();
    assert!(batch.failures.is_empty(), "{:?}", batch.failures);
    assert_eq!(batch.modules.len(), 2);
    let batch = compile_all(&glsl, &[]).unwrap();
    assert_eq!(batch.failures.len(), 2, "the disk says K = 1");

    fs::remove_file(glsl.join("common/k.glsl")).unwrap();
    let batch = compile_all(&glsl, &generated).unwrap();
    assert!(batch.failures.is_empty(), "{:?}", batch.failures);
}
