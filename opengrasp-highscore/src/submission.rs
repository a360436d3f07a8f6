//! Validated uploads: parsing, the board's limits and name rules.

use opengrasp_bench::results::ResultsFile;

use super::error::{HighscoreError, Result};
use super::{Submitter, MAX_NAME, MAX_RECORDS, MAX_TEXT, MAX_UPLOAD_BYTES};

/// A validated upload, ready to be stored.
#[derive(Clone, Debug, PartialEq)]
pub struct Submission {
    /// Who submitted.
    pub submitter: Submitter,
    /// The results.
    pub results: ResultsFile,
    /// The results file as uploaded (stored verbatim).
    pub raw: String,
    /// Lowercase hex SHA-256 of the canonical JSON of `results` (whitespace and key order of
    /// the upload do not matter): a retried or repeated upload has the same hash.
    pub content_hash: String,
}

impl Submission {
    /// Parses and validates a results file: the checks of [`ResultsFile::validate`], the
    /// board's limits (sizes, name lengths, at least one cell or run) and the plausibility
    /// rules of [`check_plausible`](crate::plausible::check_plausible) (known suite sizes,
    /// physical bounds, complete and unique runs, summaries equal to the runs').
    ///
    /// # Errors
    /// [`HighscoreError::TooLarge`], [`HighscoreError::InvalidJson`],
    /// [`HighscoreError::InvalidField`].
    pub fn from_json(text: &str, submitter: Submitter) -> Result<Self> {
        if text.len() > MAX_UPLOAD_BYTES {
            return Err(HighscoreError::TooLarge { size: text.len() as u64, limit: MAX_UPLOAD_BYTES as u64 });
        }
        submitter.validate()?;
        let results = ResultsFile::from_json(text).map_err(from_results_error)?;
        validate_limits(&results)?;
        crate::plausible::check_plausible(&results)?;
        let canonical =
            serde_json::to_string(&results).map_err(|e| HighscoreError::InvalidJson { message: e.to_string() })?;
        let content_hash = crate::tokens::sha256_hex(canonical.as_bytes());
        Ok(Self { submitter, results, raw: text.to_string(), content_hash })
    }
}

fn from_results_error(e: opengrasp_bench::results::Error) -> HighscoreError {
    use opengrasp_bench::results::Error as E;
    match e {
        E::Parse { source, .. } => HighscoreError::InvalidJson { message: source.to_string() },
        E::SchemaVersion { found, expected } => {
            HighscoreError::field("schema_version", format!("version {found} is not supported (expected {expected})"))
        }
        E::Invalid { field, reason } => HighscoreError::InvalidField { field, reason },
        E::Io { path, source } => HighscoreError::Io { path, source },
        other => HighscoreError::field("results", other.to_string()),
    }
}

pub(crate) fn check_text(field: &str, value: &str, max: usize) -> Result<()> {
    let n = value.chars().count();
    if n > max {
        return Err(HighscoreError::field(field, format!("{n} characters exceed the limit of {max}")));
    }
    Ok(())
}

pub(crate) fn check_name(field: &str, value: &str) -> Result<()> {
    if value.trim().is_empty() {
        return Err(HighscoreError::field(field, "is empty"));
    }
    if value.chars().any(char::is_control) {
        return Err(HighscoreError::field(field, "contains control characters"));
    }
    if value.chars().any(is_bidi_or_invisible) {
        return Err(HighscoreError::field(field, "contains bidirectional or invisible formatting characters"));
    }
    check_text(field, value, MAX_NAME)
}

fn validate_limits(r: &ResultsFile) -> Result<()> {
    let p = &r.provenance;
    for (field, v) in [
        ("provenance.suite_version", &p.suite_version),
        ("provenance.suite_size", &p.suite_size),
        ("provenance.opengrasp_version", &p.opengrasp_version),
    ] {
        check_name(field, v)?;
    }
    for (field, v) in [("provenance.started_at", &p.started_at), ("provenance.finished_at", &p.finished_at)] {
        check_text(field, v, MAX_NAME)?;
    }
    for (field, v) in [("provenance.git_commit", &p.git_commit), ("provenance.cpu_model", &p.cpu_model)] {
        if let Some(v) = v {
            check_text(field, v, MAX_NAME)?;
        }
    }
    if p.suite_version != opengrasp_bench::results::SUITE_VERSION {
        return Err(HighscoreError::field(
            "provenance.suite_version",
            format!("the board ranks suite {:?}, not {:?}", opengrasp_bench::results::SUITE_VERSION, p.suite_version),
        ));
    }
    for (k, v) in &p.crate_versions {
        check_name("provenance.crate_versions", k)?;
        check_text("provenance.crate_versions", v, MAX_NAME)?;
    }
    let mut records = 0;
    if let Some(g) = &r.grasp {
        records += g.cells.len();
        for (i, pl) in g.planners.iter().enumerate() {
            check_name(&format!("grasp.planners[{i}].name"), &pl.name)?;
            check_text(&format!("grasp.planners[{i}].parameters"), &pl.parameters, MAX_TEXT)?;
        }
        for (i, c) in g.cells.iter().enumerate() {
            check_name(&format!("grasp.cells[{i}].hand"), &c.cell.hand)?;
            check_name(&format!("grasp.cells[{i}].object"), &c.cell.object)?;
        }
    }
    if let Some(m) = &r.motion {
        records += m.runs.len();
        for (i, pl) in m.planners.iter().enumerate() {
            check_name(&format!("motion.planners[{i}].name"), &pl.name)?;
            check_text(&format!("motion.planners[{i}].parameters"), &pl.parameters, MAX_TEXT)?;
        }
        for (i, run) in m.runs.iter().enumerate() {
            check_name(&format!("motion.runs[{i}].scene"), &run.scene)?;
            if let Some(msg) = &run.message {
                check_text(&format!("motion.runs[{i}].message"), msg, MAX_TEXT)?;
            }
        }
    }
    if records == 0 {
        return Err(HighscoreError::field("results", "no grasp cell and no motion run to rank"));
    }
    if records > MAX_RECORDS {
        return Err(HighscoreError::field("results", format!("{records} records exceed the limit of {MAX_RECORDS}")));
    }
    Ok(())
}

/// Bidirectional overrides, embeddings and isolates, directional marks and zero-width
/// characters: they let a name display as something else (e.g. reversed text).
fn is_bidi_or_invisible(c: char) -> bool {
    matches!(c, '\u{061C}' | '\u{200B}'..='\u{200F}' | '\u{202A}'..='\u{202E}' | '\u{2060}'..='\u{2069}' | '\u{FEFF}')
}
