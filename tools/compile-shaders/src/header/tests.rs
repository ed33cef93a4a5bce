//! The generated constants header: its text, its values as glslang reads
//! them, and how a stale or hand-edited copy is found and replaced.

use super::*;
use crate::constants::ALL;
use crate::shaders::{compile_all, Batch};
use crate::temp_dir::TempDir;

fn generated() -> String {
    generate(ALL).unwrap()
}

/// One `const uint` line of a header and the comment lines right above it.
#[derive(Debug, PartialEq)]
struct Decl {
    /// First after a blank line, i.e. the start of a group.
    opens_group: bool,
    comment: Vec<String>,
    name: String,
    value: u32,
    hex: bool,
}

/// Reads the declarations back out of a generated header; anything between
/// the guard lines that is not a comment, a blank line or a declaration fails.
fn parse(text: &str) -> Vec<Decl> {
    let body = text
        .split_once("#define CONSTANTS_GLSL\n")
        .and_then(|(_, rest)| rest.strip_suffix("\n#endif\n"))
        .expect("the include guard wraps the body");
    let (mut decls, mut comment, mut opens_group) = (Vec::new(), Vec::new(), false);
    for line in body.lines() {
        if line.is_empty() {
            assert!(comment.is_empty(), "a comment above a blank line");
            opens_group = true;
        } else if let Some(text) = line.strip_prefix("//") {
            comment.push(text.strip_prefix(' ').unwrap_or(text).to_owned());
        } else {
            let (name, literal) = line
                .strip_prefix("const uint ")
                .and_then(|rest| rest.strip_suffix(';'))
                .and_then(|rest| rest.split_once(" = "))
                .unwrap_or_else(|| panic!("not a declaration: {line:?}"));
            let literal = literal.strip_suffix('u').unwrap_or(literal);
            let (value, hex) = match literal.strip_prefix("0x") {
                Some(digits) => (u32::from_str_radix(digits, 16), true),
                None => (literal.parse(), false),
            };
            decls.push(Decl {
                opens_group: std::mem::take(&mut opens_group),
                comment: std::mem::take(&mut comment),
                name: name.to_owned(),
                value: value.unwrap_or_else(|e| panic!("{line:?}: {e}")),
                hex,
            });
        }
    }
    decls
}

/// What [`parse`] should find for a table: a group's comment and its first
/// constant's own comment read as one.
fn expected(table: &[SharedConst]) -> Vec<Decl> {
    let lines = |doc: &[&str]| -> Vec<String> {
        doc.iter()
            .flat_map(|d| d.split('\n'))
            .map(|l| l.strip_prefix(' ').unwrap_or(l).trim_end().to_owned())
            .collect()
    };
    table
        .iter()
        .map(|c| Decl {
            opens_group: c.group.is_some(),
            comment: [lines(c.group.unwrap_or(&[])), lines(c.doc)].concat(),
            name: c.name.to_owned(),
            value: c.value,
            hex: c.hex,
        })
        .collect()
}

#[test]
fn the_committed_header_is_what_src_constants_rs_generates() {
    let committed = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../glsl")
        .join(HEADER);
    let text = fs::read_to_string(&committed).unwrap();
    assert!(
        text == generated(),
        "{} differs from what src/constants.rs generates: edit src/constants.rs, not the \
         header, and run `cargo run --release -p compile-shaders`",
        show(&committed)
    );
}

/// Every method's header, as the tool writes them.
fn method_headers() -> Vec<Header<'static>> {
    crate::method_constants::METHODS
        .iter()
        .map(|(m, source, table)| Header::folder(m, source, table))
        .collect()
}

#[test]
fn every_method_with_constants_has_its_committed_header() {
    let headers = method_headers();
    let names: Vec<&str> = crate::method_constants::METHODS
        .iter()
        .map(|(m, ..)| *m)
        .collect();
    // build.rs found the methods that declare constants of their own.
    for m in ["cudatess", "ground_truth", "lod", "subdiv", "tess"] {
        assert!(names.contains(&m), "{names:?}");
    }
    let glsl = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../glsl");
    for h in &headers {
        let text = h.text().unwrap();
        assert!(text.starts_with(&format!("// Generated from {}", h.source)));
        assert!(text.contains(&format!("#define {}\n", h.guard)), "{text}");
        let committed = fs::read_to_string(h.path(&glsl)).unwrap();
        assert!(
            committed == text,
            "{} differs from what {} generates",
            h.glsl,
            h.source
        );
    }
    let mut all = vec![Header::shared(ALL)];
    all.extend(headers);
    check_distinct(&all).unwrap();
}

#[test]
fn a_name_in_two_headers_is_refused_naming_both_files() {
    let one = [entry("X", 1, false, Some(&[]), &[])];
    let headers = [
        Header::shared(&one),
        Header::folder("toy", "src/methods/toy/constants.rs", &one),
    ];
    let err = check_distinct(&headers).unwrap_err().0;
    assert!(
        err.contains("`X`")
            && err.contains("src/constants.rs")
            && err.contains("src/methods/toy/constants.rs"),
        "{err}"
    );
    // A method's header refuses its own guard as a name, naming its file.
    let guard = [entry("TOY_CONSTANTS_GLSL", 1, false, None, &[])];
    let err = Header::folder("toy", "src/methods/toy/constants.rs", &guard)
        .text()
        .unwrap_err()
        .0;
    assert!(
        err.contains("include guard") && err.contains("src/methods/toy/constants.rs"),
        "{err}"
    );
}

#[test]
fn the_header_round_trips_every_constant_with_its_comments() {
    let text = generated();
    assert!(
        text.starts_with("// Generated from src/constants.rs"),
        "{text}"
    );
    assert!(text.contains("do not edit"));
    let decls = parse(&text);
    assert!(decls.len() > 40, "{} constants", decls.len());
    assert_eq!(decls, expected(ALL));
    // The bit masks are spelled in hex, as src/constants.rs spells them.
    for name in ["THIRD_BITS", "IN_FLIGHT_MASK", "FLAG_QUEUE_STRESS"] {
        assert!(decls.iter().any(|d| d.name == name && d.hex), "{name}");
    }
    assert!(text.contains("const uint IN_FLIGHT_MASK = 0xffffff;\n"));
}

/// The start of [`value_check_shader`]; its line `CHECKS_FROM + i` checks
/// constant `i`.
const CHECK_PRELUDE: &str = "#version 460
#include \"common/constants.glsl\"
#include \"common/constants.glsl\"
layout(local_size_x = 1) in;
";
const CHECKS_FROM: usize = 5;

/// A compute shader that fails to compile, on the line of the constant,
/// unless glslang reads every constant of the header as `table` declares it.
/// (It includes the header twice: the include guard must hold.)
fn value_check_shader(table: &[SharedConst]) -> String {
    let mut text = String::from(CHECK_PRELUDE);
    for c in table {
        // A negative array size is a compile error.
        let _ = writeln!(
            text,
            "uint check_{0}[({0} == {1}u) ? 1 : -1];",
            c.name, c.value
        );
    }
    text.push_str("void main() {}\n");
    text
}

fn compile_with_header(table: &[SharedConst], expected: &[SharedConst]) -> Batch {
    let dir = TempDir::new("glslang");
    dir.put("glsl/common/constants.glsl", &generate(table).unwrap());
    dir.put("glsl/check.comp", &value_check_shader(expected));
    compile_all(&dir.0.join("glsl"), &[]).unwrap()
}

#[test]
fn glslang_reads_every_value_as_declared() {
    let batch = compile_with_header(ALL, ALL);
    assert!(batch.failures.is_empty(), "{:?}", batch.failures);
    assert_eq!(batch.modules.len(), 1);

    // A wrong value in the header is caught, by name.
    let mut planted = ALL.to_vec();
    let l_max = planted.iter_mut().find(|c| c.name == "L_MAX").unwrap();
    l_max.value += 1;
    let batch = compile_with_header(&planted, ALL);
    let err = &batch.failures[0].0;
    let at = ALL.iter().position(|c| c.name == "L_MAX").unwrap();
    assert!(
        err.contains(&format!("check.comp:{}: ", CHECKS_FROM + at)),
        "{err}"
    );
    assert_eq!(
        err.matches("array size must be a positive").count(),
        1,
        "{err}"
    );
}

const fn entry(
    name: &'static str,
    value: u32,
    hex: bool,
    group: Option<&'static [&'static str]>,
    doc: &'static [&'static str],
) -> SharedConst {
    SharedConst {
        name,
        value,
        doc,
        hex,
        group,
    }
}

#[test]
fn values_above_i32_max_and_odd_comments_survive_glslang() {
    let table = [
        // A group without a comment; a doc with an empty line and an indent.
        entry("ZERO", 0, false, Some(&[]), &[" a", "", "   indented"]),
        entry("BIG", 3_000_000_000, false, None, &[]),
        entry("ALL_BITS", u32::MAX, true, None, &[" two\n lines"]),
        entry("SIGN", 0x8000_0000, true, Some(&[" Ünïcödé: λ ε"]), &[]),
        entry("NOT_HEX", 0x10, false, None, &["tab\there, no space"]),
    ];
    let text = generate(&table).unwrap();
    assert!(text.contains("const uint BIG = 3000000000u;\n"), "{text}");
    assert!(
        text.contains("const uint ALL_BITS = 0xffffffffu;\n"),
        "{text}"
    );
    assert!(text.contains("const uint NOT_HEX = 16;\n"), "{text}");
    assert!(text.contains("// a\n//\n//   indented\n"), "{text}");
    assert!(
        text.contains("// two\n// lines\nconst uint ALL_BITS"),
        "{text}"
    );
    assert!(
        text.contains("\n\n// Ünïcödé: λ ε\nconst uint SIGN"),
        "{text}"
    );
    assert_eq!(parse(&text).len(), table.len());

    let batch = compile_with_header(&table, &table);
    assert!(batch.failures.is_empty(), "{:?}", batch.failures);
}

#[test]
fn names_and_comments_glsl_cannot_take_are_errors() {
    let cases: [(SharedConst, &str); 7] = [
        (entry("gl_X", 1, false, None, &[]), "reserved"),
        (entry("A__B", 1, false, None, &[]), "reserved"),
        (entry("1X", 1, false, None, &[]), "not an ASCII identifier"),
        (entry("ÄX", 1, false, None, &[]), "not an ASCII identifier"),
        (
            entry("CONSTANTS_GLSL", 1, false, None, &[]),
            "include guard",
        ),
        (entry("X", 1, false, None, &[" a \\"]), "line continuation"),
        (entry("X", 1, false, Some(&[" a\rb"]), &[]), "U+000D"),
    ];
    for (c, problem) in cases {
        let err = generate(&[c]).unwrap_err().0;
        assert!(err.contains(problem) && err.contains(c.name), "{err}");
    }
    let twice = [
        entry("X", 1, false, None, &[]),
        entry("X", 2, false, None, &[]),
    ];
    let err = generate(&twice).unwrap_err().0;
    assert!(err.contains("`X` is declared twice"), "{err}");
}

#[test]
fn a_planted_wrong_value_is_stale_and_write_restores_the_header() {
    let dir = TempDir::new("stale");
    let path = Header::shared(ALL).path(&dir.0.join("glsl"));
    let text = generated();
    assert_eq!(compare(&path, &text).unwrap(), State::Missing);
    assert_eq!(write(&path, &text).unwrap(), State::Missing);
    assert_eq!(compare(&path, &text).unwrap(), State::Current);
    assert_eq!(write(&path, &text).unwrap(), State::Current);

    let line = "const uint L_MAX = 10;\n";
    assert!(text.contains(line));
    fs::write(&path, text.replace(line, "const uint L_MAX = 11;\n")).unwrap();
    assert_eq!(compare(&path, &text).unwrap(), State::Stale);
    assert_eq!(write(&path, &text).unwrap(), State::Stale);
    assert_eq!(fs::read_to_string(&path).unwrap(), text);
    // Only the header is left: no temporary file.
    let names: Vec<_> = fs::read_dir(path.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, ["constants.glsl"]);
}
