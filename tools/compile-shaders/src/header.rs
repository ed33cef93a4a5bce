//! The generated constants headers: `glsl/common/constants.glsl` from the
//! table of shared constants in `src/constants.rs`, and per method with a
//! `src/methods/<method>/constants.rs` its `glsl/<method>/constants.glsl`
//! (all compiled into this tool by path), so the numbers the shaders and the
//! host share are written down once, in Rust.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs;
use std::io;
use std::path::{Path, PathBuf};

use crate::constants::SharedConst;
use crate::shaders::{show, write_atomically, Error, State};

/// Where the shared header lives, relative to the GLSL directory.
pub const HEADER: &str = "common/constants.glsl";

/// The shared header's include guard, as the shaders have always used it.
const GUARD: &str = "CONSTANTS_GLSL";

/// One generated header: where it goes, what it is generated from, and its
/// table.
#[derive(Debug, Clone)]
pub struct Header<'a> {
    /// Its path below the GLSL directory.
    pub glsl: String,
    /// The Rust file its table is declared in, relative to the workspace.
    pub source: String,
    pub guard: String,
    pub table: &'a [SharedConst],
}

impl<'a> Header<'a> {
    /// The shared header, `common/constants.glsl`, for `table`.
    pub fn shared(table: &'a [SharedConst]) -> Self {
        Self {
            glsl: HEADER.to_owned(),
            source: "src/constants.rs".to_owned(),
            guard: GUARD.to_owned(),
            table,
        }
    }

    /// A folder's header, `<folder>/constants.glsl` (a method's, or the
    /// levels of detail's), which its shaders include as `constants.glsl`
    /// from their own folder; `source` is the Rust file declaring `table`.
    pub fn folder(folder: &str, source: &str, table: &'a [SharedConst]) -> Self {
        Self {
            glsl: format!("{folder}/constants.glsl"),
            source: source.to_owned(),
            guard: format!("{}_CONSTANTS_GLSL", folder.to_ascii_uppercase()),
            table,
        }
    }

    /// The header's path for a GLSL directory.
    pub fn path(&self, glsl_dir: &Path) -> PathBuf {
        glsl_dir.join(&self.glsl)
    }

    /// The header's text: the notice, the include guard, and per constant its
    /// group comment (after a blank line, where a group starts), its own
    /// comment and `const uint NAME = value;`. Values are in hex where the
    /// table says so. Values above `i32::MAX` get a `u` suffix: unsuffixed,
    /// the literal would be a negative `int`, converted back only by the
    /// assignment. Smaller values stay unsuffixed, as they were when the
    /// header was written by hand.
    ///
    /// Refuses what would not survive as GLSL: a name that is not a plain
    /// ASCII identifier, is reserved (`gl_…`, `__`) or the include guard, a
    /// name used twice, and comment text with control characters or a
    /// trailing backslash (which GLSL reads as a line continuation,
    /// swallowing the next line into the comment).
    pub fn text(&self) -> Result<String, Error> {
        let mut out = notice(&self.source);
        let guard = &self.guard;
        let _ = writeln!(out, "#ifndef {guard}\n#define {guard}");
        let mut seen = std::collections::BTreeSet::new();
        for c in self.table {
            self.check_name(c.name)?;
            if !seen.insert(c.name) {
                return Err(Error(format!(
                    "shared constant `{}` is declared twice",
                    c.name
                )));
            }
            if let Some(group) = c.group {
                out.push('\n');
                comment(&mut out, c.name, "group comment", group)?;
            }
            comment(&mut out, c.name, "comment", c.doc)?;
            let value = if c.hex {
                format!("{:#x}", c.value)
            } else {
                c.value.to_string()
            };
            let suffix = if c.value > i32::MAX as u32 { "u" } else { "" };
            let _ = writeln!(out, "const uint {} = {value}{suffix};", c.name);
        }
        out.push_str("\n#endif\n");
        Ok(out)
    }

    fn check_name(&self, name: &str) -> Result<(), Error> {
        let plain = name.chars().next().is_some_and(|c| !c.is_ascii_digit())
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        let problem = if !plain {
            "is not an ASCII identifier"
        } else if name.starts_with("gl_") || name.contains("__") {
            "is reserved in GLSL (`gl_` prefix or `__`)"
        } else if name == self.guard {
            "is the header's include guard"
        } else {
            return Ok(());
        };
        Err(Error(format!(
            "shared constant name `{name}` {problem}; rename it in {}",
            self.source
        )))
    }
}

/// The shared header's text for `table` (see [`Header::text`]).
#[cfg(test)]
pub fn generate(table: &[SharedConst]) -> Result<String, Error> {
    Header::shared(table).text()
}

/// The notice at the top of a header generated from `source`.
fn notice(source: &str) -> String {
    format!(
        "\
// Generated from {source} by tools/compile-shaders; do not edit.
// Every number the shaders share with the host is declared there, once: add
// or change a constant in {source}, then run
// `cargo run --release -p compile-shaders`, which rewrites this file and the
// SPIR-V. `--check` (CI) fails while this file differs from what it writes.
"
    )
}

/// Refuses a name declared in two headers: a shader including both would
/// not compile, and the host would have two constants of one name.
pub fn check_distinct(headers: &[Header]) -> Result<(), Error> {
    let mut owner: BTreeMap<&str, &str> = BTreeMap::new();
    for h in headers {
        for c in h.table {
            if let Some(first) = owner.insert(c.name, &h.source) {
                return Err(Error(format!(
                    "shared constant `{}` is declared in {first} and in {}",
                    c.name, h.source
                )));
            }
        }
    }
    Ok(())
}

/// Appends doc lines as `//` comments. The doc strings are as rustc hands
/// them over (`/// text` gives " text"); one may hold several lines.
fn comment(out: &mut String, name: &str, what: &str, doc: &[&str]) -> Result<(), Error> {
    for line in doc.iter().flat_map(|d| d.split('\n')) {
        let bad = |problem: &str| {
            Error(format!(
                "the {what} of shared constant `{name}` {problem}: {line:?}"
            ))
        };
        if let Some(c) = line.chars().find(|&c| c.is_control() && c != '\t') {
            return Err(bad(&format!(
                "has a control character (U+{:04X})",
                c as u32
            )));
        }
        let line = line.trim_end();
        if line.ends_with('\\') {
            return Err(bad(
                "ends in a backslash, which GLSL reads as a line continuation",
            ));
        }
        // `/// text` comes as " text": drop that one space, keep any indent.
        match line.strip_prefix(' ').unwrap_or(line) {
            "" => out.push_str("//\n"),
            text => {
                let _ = writeln!(out, "// {text}");
            }
        }
    }
    Ok(())
}

/// How the header at `path` compares with `text`.
pub fn compare(path: &Path, text: &str) -> Result<State, Error> {
    match fs::read(path) {
        Ok(bytes) if bytes == text.as_bytes() => Ok(State::Current),
        Ok(_) => Ok(State::Stale),
        Err(e) if e.kind() == io::ErrorKind::NotFound => Ok(State::Missing),
        Err(e) => Err(Error(format!("cannot read {}: {e}", show(path)))),
    }
}

/// Writes `text` to `path` unless it holds it already (through a temporary
/// file and a rename, like the SPIR-V); returns the state found before.
pub fn write(path: &Path, text: &str) -> Result<State, Error> {
    let state = compare(path, text)?;
    if state != State::Current {
        if let Some(dir) = path.parent() {
            fs::create_dir_all(dir)
                .map_err(|e| Error(format!("cannot create {}: {e}", show(dir))))?;
        }
        write_atomically(path, text.as_bytes())?;
    }
    Ok(state)
}

#[cfg(test)]
mod tests;
