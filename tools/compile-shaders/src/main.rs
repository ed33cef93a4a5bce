//! # compile-shaders
//!
//! Compiles the renderer's GLSL (`glsl/*.{comp,task,mesh,vert,tesc,tese,geom,frag}`)
//! into the SPIR-V that is checked in under `spirv/` (`glsl/x.comp` →
//! `spirv/x.comp.spv`), so the renderer itself builds without a shader
//! compiler. Files in subdirectories such as `glsl/common/` are include files:
//! `#include "common/foo.glsl"` resolves against the including file's
//! directory, then against `glsl/`.
//!
//! It also writes one include file: `glsl/common/constants.glsl`, generated
//! from the table of shared constants in `src/constants.rs` (compiled into
//! this tool by path, so the tool does not build the renderer). That file is
//! written first, since the shaders include it, and never edited by hand;
//! the shaders are compiled with the generated text whatever the file holds.
//!
//! ```text
//! cargo run --release -p compile-shaders            # regenerate the header and spirv/
//! cargo run --release -p compile-shaders -- --check # CI: fail if either is stale
//! ```
//!
//! Every module is built the same way: Vulkan 1.3 environment (SPIR-V 1.6),
//! GLSL 460, no optimisation (the `precise`/NoContraction decorations stay
//! exactly as written; drivers optimise anyway) and no debug info, so the
//! bytes depend only on the source text and the shaderc/glslang version.
//! A run writes the constants header if it changed, then writes no SPIR-V
//! unless every shader compiles; each file is written to a temporary name and
//! renamed into place, and `.spv` files without a source are removed.
//!
//! `--check` writes nothing: it compares the constants header with what it
//! would generate, compiles in memory (with the generated header), compares
//! with `spirv/`, lists every stale, missing or orphaned file (exactly the
//! files a run would change) and exits 1 if there is one. CI runs it so that
//! a GLSL or constants change committed without its generated files, or a
//! hand edit of the header, fails the build. The bytes come from the glslang
//! in Debian 12's packages; another glslang version may produce different
//! (equally valid) modules, so regenerate on that setup.
//!
//! ## Why static linking, configured in `.cargo/config.toml`
//!
//! Debian's `libshaderc.so` leaves glslang and SPIRV-Tools symbols undefined,
//! and its `libshaderc_combined.a` is not combined: it lacks glslang and
//! SPIRV-Tools. When `shaderc-sys`' build script finds no usable library it
//! builds shaderc from source, which takes over 8 minutes on two cores. So the
//! workspace's `.cargo/config.toml` overrides that build script (a cargo
//! `links` override for `shaderc`): it names the system directory and every
//! static archive needed, the build script never runs, and a missing library
//! is a link error in seconds instead of a silent source build. All archives
//! end up in one rlib, so their order does not matter to GNU ld either.

// The renderer's constants module, for its table `ALL`, and every method's
// (found by build.rs); the tool reads nothing else of the renderer and does
// not depend on its crate.
#[path = "../../../src/constants.rs"]
mod constants;
mod header;
mod method_constants {
    include!(concat!(env!("OUT_DIR"), "/method_constants.rs"));
}
mod shaders;
#[cfg(test)]
mod temp_dir;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use shaders::{show, Error, State};

const USAGE: &str = "\
Writes glsl/common/constants.glsl from src/constants.rs, and each
glsl/<method>/constants.glsl from src/methods/<method>/constants.rs, then
compiles glsl/*.{comp,task,mesh,vert,tesc,tese,geom,frag} and the same in
glsl/<folder>/ (but common/, which holds include files) to spirv/, each to
its own path with .spv appended.

Usage: compile-shaders [--check] [--glsl DIR] [--spirv DIR]

Options:
  --check       write nothing: compare the constants headers and the SPIR-V
                directory with what would be written; list stale, missing
                and orphaned files and exit 1 if there are any
  --glsl DIR    GLSL sources, with the header in DIR/common/ (default: glsl/
                in the workspace root)
  --spirv DIR   compiled modules (default: spirv/ in the workspace root)
  -h, --help    print this help

Exit status: 0 success, 1 --check found differences, 2 any other error.";

/// Exit status for `--check` finding differences.
const EXIT_STALE: u8 = 1;
/// Exit status for usage, I/O and compile errors.
const EXIT_ERROR: u8 = 2;

#[derive(Debug, PartialEq)]
struct Args {
    check: bool,
    glsl: Option<PathBuf>,
    spirv: Option<PathBuf>,
    help: bool,
}

fn parse_args(args: impl IntoIterator<Item = String>) -> Result<Args, Error> {
    let mut parsed = Args {
        check: false,
        glsl: None,
        spirv: None,
        help: false,
    };
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let (flag, inline) = match arg.split_once('=') {
            Some((f, v)) if f.starts_with("--") => (f.to_owned(), Some(v.to_owned())),
            _ => (arg.clone(), None),
        };
        let mut value = |name: &str| {
            inline
                .clone()
                .or_else(|| args.next())
                .filter(|v| !v.is_empty())
                .map(PathBuf::from)
                .ok_or_else(|| Error(format!("{name} needs a directory")))
        };
        match flag.as_str() {
            "--check" if inline.is_none() => parsed.check = true,
            "-h" | "--help" if inline.is_none() => parsed.help = true,
            "--glsl" => parsed.glsl = Some(value("--glsl")?),
            "--spirv" => parsed.spirv = Some(value("--spirv")?),
            _ => return Err(Error(format!("unknown argument `{arg}`"))),
        }
    }
    Ok(parsed)
}

/// The workspace root: where this tool was built from if that still exists
/// (so `cargo run -p compile-shaders` works from any directory), else the
/// current directory.
fn workspace_root() -> PathBuf {
    let built_in = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    match built_in.canonicalize() {
        Ok(root) if root.join("glsl").is_dir() => root,
        _ => std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
    }
}

fn main() -> ExitCode {
    match run(std::env::args().skip(1)) {
        Ok(code) => ExitCode::from(code),
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(EXIT_ERROR)
        }
    }
}

fn run(args: impl IntoIterator<Item = String>) -> Result<u8, Error> {
    let args = parse_args(args).map_err(|e| Error(format!("{e}\n\n{USAGE}")))?;
    if args.help {
        println!("{USAGE}");
        return Ok(0);
    }
    let root = workspace_root();
    let glsl = args.glsl.unwrap_or_else(|| root.join("glsl"));
    let spirv = args.spirv.unwrap_or_else(|| root.join("spirv"));
    shaders::require_glsl_dir(&glsl)?;

    // The headers first: the shaders include them. A run writes them;
    // either way the shaders are compiled with the generated text, so
    // `--check` compiles what a run would even while a file on disk is stale
    // or missing.
    let mut headers = vec![header::Header::shared(constants::ALL)];
    for (folder, source, table) in method_constants::METHODS {
        headers.push(header::Header::folder(folder, source, table));
    }
    header::check_distinct(&headers)?;
    let mut generated = Vec::new();
    let mut stale_headers = 0;
    for h in &headers {
        let (path, text) = (h.path(&glsl), h.text()?);
        let state = if args.check {
            header::compare(&path, &text)?
        } else {
            header::write(&path, &text)?
        };
        stale_headers += usize::from(state != State::Current);
        let label = match (args.check, state) {
            (_, State::Current) => None,
            (true, state) => Some(state.label()),
            (false, State::Missing) => Some("created"),
            (false, _) => Some("updated"),
        };
        if let Some(label) = label {
            println!(
                "{:<9} {} (generated from {})",
                format!("{label}:"),
                show(&path),
                h.source
            );
        }
        generated.push(shaders::Generated { path, text });
    }

    let batch = shaders::compile_all(&glsl, &generated)?;
    for (_, compiled) in &batch.modules {
        // glslang's warnings already start with `file:line: warning:`.
        if !compiled.warnings.is_empty() {
            eprintln!("{}", compiled.warnings.trim_end());
        }
    }
    if !batch.failures.is_empty() {
        for failure in &batch.failures {
            eprintln!("error: {failure}");
        }
        let n = batch.failures.len();
        let what = if args.check {
            "no SPIR-V compared"
        } else {
            "no SPIR-V written"
        };
        return Err(Error(format!(
            "{n} shader{} failed to compile; {what}",
            if n == 1 { "" } else { "s" }
        )));
    }

    if args.check {
        check(headers.len(), stale_headers, &spirv, &batch.modules)
    } else {
        write(&glsl, &spirv, &batch.modules)
    }
}

/// Reports the SPIR-V's state (the headers' is printed already) and the verdict.
fn check(
    headers: usize,
    stale_headers: usize,
    spirv: &Path,
    modules: &[(shaders::Source, shaders::Compiled)],
) -> Result<u8, Error> {
    let states = shaders::compare(spirv, modules)?;
    let bad: Vec<_> = states
        .iter()
        .filter(|(_, s)| *s != State::Current)
        .collect();
    for (name, state) in &bad {
        println!(
            "{:<9} {}",
            format!("{}:", state.label()),
            show(&spirv.join(name))
        );
    }
    let n_bad = bad.len() + stale_headers;
    if n_bad == 0 {
        println!(
            "the {headers} constants header{} and all {} SPIR-V module{} in {} are current",
            if headers == 1 { "" } else { "s" },
            modules.len(),
            if modules.len() == 1 { "" } else { "s" },
            show(spirv)
        );
        Ok(0)
    } else {
        println!(
            "{n_bad} generated file{} out of date; run `cargo run --release -p compile-shaders` and commit the result",
            if n_bad == 1 { " is" } else { "s are" }
        );
        Ok(EXIT_STALE)
    }
}

fn write(
    glsl: &Path,
    spirv: &Path,
    modules: &[(shaders::Source, shaders::Compiled)],
) -> Result<u8, Error> {
    if modules.is_empty() {
        println!("no shaders in {}", show(glsl));
    }
    let written = shaders::write_all(spirv, modules)?;
    for (label, names) in [
        ("created", &written.created),
        ("updated", &written.updated),
        ("removed", &written.removed),
    ] {
        for name in names {
            println!("{:<8} {}", format!("{label}:"), show(&spirv.join(name)));
        }
    }
    println!(
        "{} shader{} compiled: {} created, {} updated, {} unchanged, {} orphaned .spv removed",
        modules.len(),
        if modules.len() == 1 { "" } else { "s" },
        written.created.len(),
        written.updated.len(),
        written.unchanged.len(),
        written.removed.len()
    );
    Ok(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(args: &[&str]) -> Result<Args, Error> {
        parse_args(args.iter().map(|s| s.to_string()))
    }

    #[test]
    fn parses_flags_and_directories() {
        let a = parse(&["--check", "--glsl", "g", "--spirv=s"]).unwrap();
        assert!(a.check && !a.help);
        assert_eq!(a.glsl.as_deref(), Some(Path::new("g")));
        assert_eq!(a.spirv.as_deref(), Some(Path::new("s")));
        assert!(parse(&["-h"]).unwrap().help);
        assert_eq!(parse(&[]).unwrap().glsl, None);
    }

    #[test]
    fn rejects_unknown_and_incomplete_arguments() {
        assert!(parse(&["--chek"]).unwrap_err().0.contains("--chek"));
        assert!(parse(&["--glsl"])
            .unwrap_err()
            .0
            .contains("needs a directory"));
        assert!(parse(&["--spirv="]).is_err());
        assert!(parse(&["--check=yes"]).is_err());
        assert!(parse(&["extra"]).is_err());
    }
}
