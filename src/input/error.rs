//! Errors for everything read from disk. Each names the file, and the line
//! where there is one, so a user can go straight to the problem.

use std::path::PathBuf;

/// An input file that could not be read or was refused.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be opened or read. The OS's words are part of
    /// the message, not a separate error source, so that error chains
    /// (`{:#}`) print them once.
    #[error("{}: {cause}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the OS said.
        cause: std::io::Error,
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
    /// A model of a scene could not be loaded or placed. The message names
    /// the model and its file but not the scene, which every caller names
    /// already (`loading the models of SCENE: …`).
    #[error("model '{model}': {msg}")]
    Model {
        /// The scene file.
        scene: PathBuf,
        /// The model's name in the scene.
        model: String,
        /// What went wrong, naming the model file where it is to blame.
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
    pub fn io(path: &std::path::Path, cause: std::io::Error) -> Self {
        SceneError::Io {
            path: path.to_path_buf(),
            cause,
        }
    }
}
