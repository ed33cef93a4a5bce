//! Errors for everything read from disk. Each names the file, and the line
//! where there is one, so a user can go straight to the problem.

use std::path::PathBuf;

/// An input file that could not be read or was refused.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be opened or read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the OS said.
        source: std::io::Error,
    },
    /// A syntax or value error at a known line (1-based).
    #[error("{}:{line}: {msg}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong there.
        msg: String,
    },
    /// The file parsed but cannot be used (no line to point at).
    #[error("{}: {msg}", path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        msg: String,
    },
}
