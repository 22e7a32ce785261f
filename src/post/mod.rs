//! Stage 9: outputs — CSV tables, a VTU file for ParaView, plots and `summary.json`.

/// Failures while writing outputs.
#[derive(Debug, thiserror::Error)]
pub enum OutputError {
    /// File-system error.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The path.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
    /// Plotting failed.
    #[error("cannot draw plot {path}: {reason}")]
    Plot {
        /// The path.
        path: String,
        /// The cause.
        reason: String,
    },
}
