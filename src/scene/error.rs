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

impl SceneError {
    /// A [`SceneError::Parse`] at `line` (1-based) of `path`.
    pub fn at(path: &std::path::Path, line: usize, msg: impl Into<String>) -> Self {
        SceneError::Parse {
            path: path.to_path_buf(),
            line,
            msg: msg.into(),
        }
    }

    /// A [`SceneError::Invalid`] for `path`.
    pub fn invalid(path: &std::path::Path, msg: impl Into<String>) -> Self {
        SceneError::Invalid {
            path: path.to_path_buf(),
            msg: msg.into(),
        }
    }

    /// A [`SceneError::Io`] for `path`.
    pub fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        SceneError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
