//! The targets a method is judged by in `bench`'s report, declared by its
//! registry entry ([`MethodInfo::targets`](super::MethodInfo)): the paper's
//! claims and the project's own, as data, so the report that checks them
//! names no method.

/// A figure of a measured configuration a target compares.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure {
    /// Triangles drawn (the medians of the FLIP images).
    Triangles,
    /// Mean FLIP against the reference (the median over the perspectives).
    Flip,
    /// GPU time of the subdivision pass (median over the path).
    SubdividePass,
    /// Node memory (the worst frame of the path), with the rounds that took
    /// a depth in parts.
    NodeMemory,
}

impl Figure {
    /// How the report's lines name it.
    pub fn words(self) -> &'static str {
        match self {
            Figure::Triangles => "triangles",
            Figure::Flip => "FLIP",
            Figure::SubdividePass => "subdivide pass",
            Figure::NodeMemory => "node memory",
        }
    }
}

/// What a figure is held against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Against {
    /// Another method's at the same ε (and λ, where it reads λ).
    Method(&'static str),
    /// The same method's at another λ.
    Lambda(f64),
}

/// One target.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Target {
    /// At ε `eps`, the method's `figure` at λ `lambda` (`None`: at every λ
    /// of the run, a line each) is at most `limit` times what `against`
    /// gives.
    Ratio {
        /// The tolerance.
        eps: f64,
        /// The figure.
        figure: Figure,
        /// The method's λ, or every λ of the run.
        lambda: Option<f64>,
        /// What it is held against.
        against: Against,
        /// The largest ratio that meets the target.
        limit: f64,
    },
    /// At equal FLIP against the baseline method (its curve over ε
    /// interpolated log-log), the method at λ `lambda` draws at most the
    /// scene's limit times the baseline's triangles (median over the ε
    /// within the baseline's range); `limits` by scene name.
    EqualFlip {
        /// The method's λ.
        lambda: f64,
        /// (scene name, limit); a scene not listed is measured, not judged.
        limits: &'static [(&'static str, f64)],
    },
    /// The worst frame of the path keeps `figure` within `limit` (bytes
    /// for node memory).
    Worst {
        /// The figure.
        figure: Figure,
        /// The largest value that meets the target.
        limit: f64,
    },
}
