//! Finding, compiling, comparing and writing shaders. Everything here is
//! independent of the command line so the tests can drive it directly.

use std::fmt;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use shaderc::{
    CompileOptions, Compiler, EnvVersion, GlslProfile, OptimizationLevel, ResolvedInclude,
    ShaderKind, SourceLanguage, SpirvVersion, TargetEnv,
};

/// File extensions compiled as shaders, with their stage.
pub const STAGES: &[(&str, ShaderKind)] = &[
    ("comp", ShaderKind::Compute),
    ("task", ShaderKind::Task),
    ("mesh", ShaderKind::Mesh),
    ("vert", ShaderKind::Vertex),
    ("tesc", ShaderKind::TessControl),
    ("tese", ShaderKind::TessEvaluation),
    ("geom", ShaderKind::Geometry),
    ("frag", ShaderKind::Fragment),
];

/// Extension of compiled files: `glsl/x.comp` becomes `spirv/x.comp.spv`.
pub const SPV_EXT: &str = "spv";

/// Nested includes deeper than this are taken for an include cycle.
const MAX_INCLUDE_DEPTH: usize = 32;

/// An error with a message ready to print.
#[derive(Debug)]
pub struct Error(pub String);

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

fn io_error(what: &str, path: &Path, e: io::Error) -> Error {
    Error(format!("{what} {}: {e}", show(path)))
}

/// A path as the user should see it: relative to the current directory when
/// it lies below it, so messages read `glsl/a.comp:3: error: ...`.
pub fn show(path: &Path) -> String {
    let rel = std::env::current_dir()
        .ok()
        .and_then(|cwd| path.strip_prefix(cwd).ok().map(Path::to_path_buf));
    match rel {
        Some(r) if !r.as_os_str().is_empty() => r.display().to_string(),
        _ => path.display().to_string(),
    }
}

/// One shader source file: directly in the GLSL directory (the shared
/// passes), or in a method's folder of it (`glsl/cudatess/`, …).
#[derive(Debug, Clone)]
pub struct Source {
    /// Its path below the GLSL directory, with `/`, e.g. `levels/persistent.comp`
    /// or `cudatess/args.comp`: the name the renderer loads it by.
    pub name: String,
    pub path: PathBuf,
    pub kind: ShaderKind,
}

impl Source {
    /// Path of the compiled module below the SPIR-V directory, e.g.
    /// `cudatess/args.comp.spv`.
    pub fn spv_name(&self) -> String {
        format!("{}.{SPV_EXT}", self.name)
    }
}

fn stage_of(path: &Path) -> Option<ShaderKind> {
    let ext = path.extension()?.to_str()?;
    STAGES.iter().find(|(e, _)| *e == ext).map(|&(_, k)| k)
}

/// The folder of include files only: nothing in it is compiled on its own.
pub const INCLUDE_DIR: &str = "common";

/// The entries of `dir` as (file name, path), sorted; `None` when the
/// directory does not exist and `missing_ok`.
fn entries(dir: &Path, missing_ok: bool) -> Result<Vec<(String, PathBuf)>, Error> {
    let read = match fs::read_dir(dir) {
        Ok(r) => r,
        Err(e) if missing_ok && e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io_error("cannot read", dir, e)),
    };
    let mut out = Vec::new();
    for entry in read {
        let entry = entry.map_err(|e| io_error("cannot read", dir, e))?;
        if let Some(name) = entry.file_name().to_str() {
            out.push((name.to_owned(), entry.path()));
        }
    }
    out.sort();
    Ok(out)
}

/// Shader sources in `glsl_dir` and in its folders one level down (but
/// `common/`, which holds include files), sorted by name. Files with other
/// extensions are skipped.
pub fn find_sources(glsl_dir: &Path) -> Result<Vec<Source>, Error> {
    let mut sources = Vec::new();
    for (name, path) in entries(glsl_dir, false)? {
        if path.is_dir() {
            if name == INCLUDE_DIR {
                continue;
            }
            for (file, path) in entries(&path, false)? {
                if let (true, Some(kind)) = (path.is_file(), stage_of(&path)) {
                    sources.push(Source {
                        name: format!("{name}/{file}"),
                        path,
                        kind,
                    });
                }
            }
        } else if let Some(kind) = stage_of(&path) {
            sources.push(Source { name, path, kind });
        }
    }
    sources.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(sources)
}

/// The `.spv` files in `spirv_dir` and its folders one level down, as
/// names below it (`x.comp.spv`, `cudatess/args.comp.spv`); none if it does
/// not exist.
pub fn find_spv_files(spirv_dir: &Path) -> Result<Vec<String>, Error> {
    let is_spv = |p: &Path| p.is_file() && p.extension().is_some_and(|e| e == SPV_EXT);
    let mut names = Vec::new();
    for (name, path) in entries(spirv_dir, true)? {
        if path.is_dir() {
            for (file, path) in entries(&path, false)? {
                if is_spv(&path) {
                    names.push(format!("{name}/{file}"));
                }
            }
        } else if is_spv(&path) {
            names.push(name);
        }
    }
    names.sort();
    Ok(names)
}

/// Where an include can come from: the including file's directory, then the
/// GLSL root. `#include <name>` searches the same places as `#include "name"`:
/// shaderc retries a failed `"name"` as `<name>` and shows only the second
/// message, which must therefore name every place looked at.
fn include_candidates(glsl_dir: &Path, requested: &str, includer: &str) -> Vec<PathBuf> {
    let mut dirs = Vec::new();
    if let Some(parent) = Path::new(includer).parent() {
        dirs.push(parent.to_path_buf());
    }
    dirs.push(glsl_dir.to_path_buf());
    // The two are often one directory, spelled relative and absolute.
    if dirs.len() == 2 && same_dir(&dirs[0], &dirs[1]) {
        dirs.pop();
    }
    dirs.iter().map(|d| d.join(requested)).collect()
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// Whether two paths name the same file, which need not exist.
fn same_file(a: &Path, b: &Path) -> bool {
    match (a.parent(), b.parent()) {
        (Some(da), Some(db)) => a.file_name() == b.file_name() && same_dir(da, db),
        _ => a == b,
    }
}

/// An include file this tool writes itself (the constants header). Includes
/// of its path read `text`, whatever the file on disk holds, so that `--check`
/// compiles exactly what a run would.
#[derive(Debug, Clone)]
pub struct Generated {
    pub path: PathBuf,
    pub text: String,
}

fn resolve_include(
    glsl_dir: &Path,
    generated: &[Generated],
    requested: &str,
    includer: &str,
    depth: usize,
) -> Result<ResolvedInclude, String> {
    if depth > MAX_INCLUDE_DEPTH {
        return Err(format!(
            "includes nested deeper than {MAX_INCLUDE_DEPTH} (an include cycle without a guard?)"
        ));
    }
    let candidates = include_candidates(glsl_dir, requested, includer);
    for path in &candidates {
        if let Some(file) = generated.iter().find(|g| same_file(path, &g.path)) {
            return Ok(ResolvedInclude {
                resolved_name: show(path),
                content: file.text.clone(),
            });
        }
        if path.is_file() {
            let content = fs::read_to_string(path)
                .map_err(|e| format!("cannot read include file {}: {e}", show(path)))?;
            if content.contains('\0') {
                return Err(format!("include file {} contains a NUL byte", show(path)));
            }
            return Ok(ResolvedInclude {
                resolved_name: show(path),
                content,
            });
        }
    }
    let tried: Vec<String> = candidates.iter().map(|p| show(p)).collect();
    Err(format!(
        "include file \"{requested}\" not found (looked for {})",
        tried.join(", ")
    ))
}

/// A compiled module: its SPIR-V bytes (little-endian words) and any warnings.
#[derive(Debug)]
pub struct Compiled {
    pub bytes: Vec<u8>,
    pub warnings: String,
}

/// glslang through shaderc, set up the one way this project compiles shaders.
pub struct ShaderCompiler<'a> {
    compiler: Compiler,
    options: CompileOptions<'a>,
}

impl ShaderCompiler<'_> {
    /// Vulkan 1.3 / SPIR-V 1.6 (mesh and task shaders need 1.4 or later),
    /// GLSL 460, no optimisation and no debug info. Optimising here could
    /// only lose `precise`/NoContraction intent; the driver optimises anyway.
    /// Without debug info no file name or path enters the module, so the
    /// output depends on the source text alone. Includes of a `generated`
    /// file read its text instead of the disk.
    pub fn new(glsl_dir: &Path, generated: &[Generated]) -> Result<Self, Error> {
        let init = |e: shaderc::Error| Error(format!("cannot initialise shaderc: {e}"));
        let compiler = Compiler::new().map_err(init)?;
        let mut options = CompileOptions::new().map_err(init)?;
        options.set_source_language(SourceLanguage::GLSL);
        options.set_target_env(TargetEnv::Vulkan, EnvVersion::Vulkan1_3 as u32);
        options.set_target_spirv(SpirvVersion::V1_6);
        options.set_forced_version_profile(460, GlslProfile::None);
        options.set_optimization_level(OptimizationLevel::Zero);
        let root = glsl_dir.to_path_buf();
        let generated = generated.to_vec();
        options.set_include_callback(move |requested, _kind, includer, depth| {
            resolve_include(&root, &generated, requested, includer, depth)
        });
        Ok(Self { compiler, options })
    }

    /// Compiles one source file. The error carries the file name and
    /// glslang's messages (`file:line: error: ...`).
    pub fn compile(&self, source: &Source) -> Result<Compiled, Error> {
        let name = show(&source.path);
        let text = fs::read_to_string(&source.path)
            .map_err(|e| io_error("cannot read", &source.path, e))?;
        if text.contains('\0') {
            return Err(Error(format!("{name}: contains a NUL byte")));
        }
        let artifact = self
            .compiler
            .compile_into_spirv(&text, source.kind, &name, "main", Some(&self.options))
            .map_err(|e| compile_error(&name, e))?;
        let bytes = artifact
            .as_binary()
            .iter()
            .flat_map(|w| w.to_le_bytes())
            .collect();
        Ok(Compiled {
            bytes,
            warnings: artifact.get_warning_messages(),
        })
    }
}

fn compile_error(name: &str, e: shaderc::Error) -> Error {
    match e {
        // glslang's text already starts each line with `file:line:`.
        shaderc::Error::CompilationError(_, msg) => {
            Error(format!("{name}: compilation failed\n{}", msg.trim_end()))
        }
        other => Error(format!("{name}: {other}")),
    }
}

/// Every source compiled, or every failure.
pub struct Batch {
    pub modules: Vec<(Source, Compiled)>,
    pub failures: Vec<Error>,
}

/// An error unless `glsl_dir` is a directory.
pub fn require_glsl_dir(glsl_dir: &Path) -> Result<(), Error> {
    if glsl_dir.is_dir() {
        Ok(())
    } else {
        Err(Error(format!(
            "GLSL directory {} does not exist",
            show(glsl_dir)
        )))
    }
}

/// Compiles every shader in `glsl_dir`, continuing past failures so that one
/// run reports all of them. Includes of a `generated` file read its text.
pub fn compile_all(glsl_dir: &Path, generated: &[Generated]) -> Result<Batch, Error> {
    require_glsl_dir(glsl_dir)?;
    let sources = find_sources(glsl_dir)?;
    let compiler = ShaderCompiler::new(glsl_dir, generated)?;
    let mut batch = Batch {
        modules: Vec::new(),
        failures: Vec::new(),
    };
    for source in sources {
        match compiler.compile(&source) {
            Ok(compiled) => batch.modules.push((source, compiled)),
            Err(e) => batch.failures.push(e),
        }
    }
    Ok(batch)
}

/// How one file in the SPIR-V directory compares with its source.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    Current,
    /// Exists but differs from what the source compiles to.
    Stale,
    /// The source has no compiled file.
    Missing,
    /// A `.spv` file whose source is gone.
    Orphaned,
}

impl State {
    pub fn label(self) -> &'static str {
        match self {
            State::Current => "current",
            State::Stale => "stale",
            State::Missing => "missing",
            State::Orphaned => "orphaned",
        }
    }
}

/// The state of every compiled module and every orphan, sorted by file name.
pub fn compare(
    spirv_dir: &Path,
    modules: &[(Source, Compiled)],
) -> Result<Vec<(String, State)>, Error> {
    let mut states = Vec::new();
    for (source, compiled) in modules {
        let name = source.spv_name();
        let path = spirv_dir.join(&name);
        let state = match fs::read(&path) {
            Ok(bytes) if bytes == compiled.bytes => State::Current,
            Ok(_) => State::Stale,
            Err(e) if e.kind() == io::ErrorKind::NotFound => State::Missing,
            Err(e) => return Err(io_error("cannot read", &path, e)),
        };
        states.push((name, state));
    }
    for name in orphans(spirv_dir, modules)? {
        states.push((name, State::Orphaned));
    }
    states.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(states)
}

fn orphans(spirv_dir: &Path, modules: &[(Source, Compiled)]) -> Result<Vec<String>, Error> {
    let wanted: Vec<String> = modules.iter().map(|(s, _)| s.spv_name()).collect();
    Ok(find_spv_files(spirv_dir)?
        .into_iter()
        .filter(|n| !wanted.contains(n))
        .collect())
}

/// What [`write_all`] did, file names per kind of change.
#[derive(Debug, Default)]
pub struct Written {
    pub created: Vec<String>,
    pub updated: Vec<String>,
    pub unchanged: Vec<String>,
    pub removed: Vec<String>,
}

/// Writes every module whose bytes changed (through a temporary file and a
/// rename, so a reader never sees half a module) and removes orphaned `.spv`
/// files. `modules` must hold every source of the GLSL directory: any `.spv`
/// file not among them is deleted.
pub fn write_all(spirv_dir: &Path, modules: &[(Source, Compiled)]) -> Result<Written, Error> {
    fs::create_dir_all(spirv_dir).map_err(|e| io_error("cannot create", spirv_dir, e))?;
    let mut written = Written::default();
    for (name, state) in compare(spirv_dir, modules)? {
        let path = spirv_dir.join(&name);
        match state {
            State::Current => written.unchanged.push(name),
            State::Orphaned => {
                fs::remove_file(&path).map_err(|e| io_error("cannot remove", &path, e))?;
                written.removed.push(name);
            }
            State::Stale | State::Missing => {
                let (_, compiled) = modules
                    .iter()
                    .find(|(s, _)| s.spv_name() == name)
                    .expect("compare() reports only names of modules or orphans");
                if let Some(dir) = path.parent() {
                    fs::create_dir_all(dir).map_err(|e| io_error("cannot create", dir, e))?;
                }
                write_atomically(&path, &compiled.bytes)?;
                if state == State::Stale {
                    written.updated.push(name);
                } else {
                    written.created.push(name);
                }
            }
        }
    }
    Ok(written)
}

/// Writes `bytes` to a temporary file beside `path` and renames it into
/// place, so a reader sees the old file or the new one, never half of one.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    let file_name = path.file_name().and_then(|n| n.to_str()).ok_or_else(|| {
        Error(format!(
            "cannot write {}: not a UTF-8 file name",
            show(path)
        ))
    })?;
    let tmp = path.with_file_name(format!(".{file_name}.tmp{}", std::process::id()));
    let result = fs::write(&tmp, bytes)
        .map_err(|e| io_error("cannot write", &tmp, e))
        .and_then(|()| fs::rename(&tmp, path).map_err(|e| io_error("cannot replace", path, e)));
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

#[cfg(test)]
mod tests;
