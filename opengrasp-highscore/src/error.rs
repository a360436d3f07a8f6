//! Errors of the high-score board.

use std::path::PathBuf;

/// Result alias of the high-score board.
pub type Result<T, E = HighscoreError> = std::result::Result<T, E>;

/// What can go wrong when submitting, ranking or serving results.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum HighscoreError {
    /// A file could not be read.
    #[error("cannot read `{path}`: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The upload or results file is larger than the limit.
    #[error("upload of {size} bytes exceeds the limit of {limit} bytes")]
    TooLarge {
        /// Size of the upload (bytes; for HTTP uploads the size read before giving up).
        size: u64,
        /// Limit (bytes).
        limit: u64,
    },
    /// The upload is not valid JSON or does not follow the results-file schema.
    #[error("invalid results json: {message}")]
    InvalidJson {
        /// The parser's message (with line and column).
        message: String,
    },
    /// A field of a well-formed upload has an invalid value.
    #[error("invalid field `{field}`: {reason}")]
    InvalidField {
        /// Path of the field (e.g. `grasp.cells[3].mean_epsilon`).
        field: String,
        /// Why it is rejected.
        reason: String,
    },
    /// The benchmark is not administered by this board.
    #[error("unknown benchmark `{id}`")]
    UnknownBenchmark {
        /// The benchmark id asked for.
        id: String,
    },
    /// The submission does not exist.
    #[error("unknown submission {id}")]
    UnknownSubmission {
        /// The submission id asked for.
        id: i64,
    },
    /// The database was written by a newer (or foreign) schema.
    #[error("database schema version {found} is not supported (this build reads version {supported})")]
    SchemaVersion {
        /// `PRAGMA user_version` of the file.
        found: i64,
        /// The version this build writes.
        supported: i64,
    },
    /// SQLite failed.
    #[error("database error: {0}")]
    Database(rusqlite::Error),
    /// The database is locked by another writer for longer than the busy timeout; retry.
    #[error("database busy: {0}")]
    Busy(rusqlite::Error),
    /// The database file does not exist (reads never create it).
    #[error("no high-score database at `{path}`")]
    NoDatabase {
        /// The path asked for.
        path: PathBuf,
    },
    /// An upload without a valid API token.
    #[error("unauthorized: {reason}")]
    Unauthorized {
        /// Why the token was refused.
        reason: String,
    },
    /// The request body was not received within the body timeout.
    #[error("the request body was not received in time")]
    BodyTimeout,
    /// The same results were already submitted by someone else.
    #[error("these results were already submitted as submission {id}")]
    Duplicate {
        /// The existing submission.
        id: i64,
    },
    /// A remote high-score server answered with an error (the `submit --server` client).
    #[error("server answered {status}: {message}")]
    Remote {
        /// HTTP status code.
        status: u16,
        /// The server's message.
        message: String,
    },
    /// The server could not bind or run.
    #[error("server error on {addr}: {source}")]
    Server {
        /// The address served.
        addr: String,
        /// The cause.
        source: std::io::Error,
    },
}

impl HighscoreError {
    /// Shorthand for [`HighscoreError::InvalidField`].
    pub(crate) fn field(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Self::InvalidField { field: field.into(), reason: reason.into() }
    }

    /// A stable machine-readable code, used in the HTTP API's error bodies.
    pub fn code(&self) -> &'static str {
        match self {
            Self::Io { .. } => "io",
            Self::TooLarge { .. } => "too_large",
            Self::InvalidJson { .. } => "invalid_json",
            Self::InvalidField { .. } => "invalid_field",
            Self::UnknownBenchmark { .. } => "unknown_benchmark",
            Self::UnknownSubmission { .. } => "unknown_submission",
            Self::SchemaVersion { .. } => "schema_version",
            Self::Database(_) => "database",
            Self::Busy(_) => "busy",
            Self::NoDatabase { .. } => "no_database",
            Self::Unauthorized { .. } => "unauthorized",
            Self::Duplicate { .. } => "duplicate",
            Self::BodyTimeout => "body_timeout",
            Self::Remote { .. } => "remote",
            Self::Server { .. } => "server",
        }
    }
}

impl From<rusqlite::Error> for HighscoreError {
    fn from(e: rusqlite::Error) -> Self {
        match e.sqlite_error_code() {
            Some(rusqlite::ErrorCode::DatabaseBusy | rusqlite::ErrorCode::DatabaseLocked) => Self::Busy(e),
            _ => Self::Database(e),
        }
    }
}
