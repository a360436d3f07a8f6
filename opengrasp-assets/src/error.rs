//! The crate's error type.

use std::path::PathBuf;

use opengrasp_core::CoreError;

/// Errors of the asset library.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AssetError {
    /// No asset of this kind has this name.
    #[error("unknown {kind} `{name}`")]
    UnknownAsset {
        /// What was looked up (`object`, `preshape`, `location`).
        kind: &'static str,
        /// The name asked for.
        name: String,
    },
    /// A user-supplied parameter is out of range.
    #[error("invalid parameter `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter.
        name: String,
        /// Why it is invalid.
        reason: String,
    },
    /// A model, mesh or scene was rejected by opengrasp-core.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// An I/O error while exporting.
    #[error("i/o error on {}: {source}", path.display())]
    Io {
        /// The file involved.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// Result alias of this crate.
pub type Result<T> = std::result::Result<T, AssetError>;
