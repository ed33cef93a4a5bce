//! The rendering methods, each a set of passes recorded into a frame.
//!
//! Names on the command line: `subdiv` (this crate's persistent-threads
//! version of the paper), and, arriving later, `subdiv-indirect`, `tess`,
//! `tess-reparam`, `cudatess`, `ground-truth`.

pub mod sort;
pub mod subdiv;

/// A method the user can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Recursive subdivision, persistent threads (the paper's method).
    Subdiv,
}

/// Every method name the command line knows, built or not.
pub const METHOD_NAMES: &[&str] = &[
    "subdiv",
    "subdiv-indirect",
    "tess",
    "tess-reparam",
    "cudatess",
    "ground-truth",
];

impl Method {
    /// Parses a method name; known but unbuilt methods get their own message.
    pub fn parse(name: &str) -> Result<Method, String> {
        match name {
            "subdiv" => Ok(Method::Subdiv),
            n if METHOD_NAMES.contains(&n) => {
                Err(format!("method '{n}' is not built yet; available: subdiv"))
            }
            n => Err(format!(
                "unknown method '{n}'; methods: {}",
                METHOD_NAMES.join(", ")
            )),
        }
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Method::Subdiv => "subdiv",
        }
    }
}
