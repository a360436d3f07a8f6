//! API tokens of the networked submission: issued per team by an administrator, stored as
//! SHA-256 hashes (the token itself is shown once), checked on every upload.

use std::io::Read;

use rusqlite::{params, OptionalExtension};
use sha2::{Digest, Sha256};

use super::error::{HighscoreError, Result};
use super::Store;

/// Lowercase hex SHA-256 of `bytes`.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    let mut out = String::with_capacity(64);
    for b in digest {
        out.push_str(&format!("{b:02x}"));
    }
    out
}

/// A stored token (without the secret).
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct TokenInfo {
    /// Token id (for revoking).
    pub id: i64,
    /// The team it was issued to.
    pub team: String,
    /// When it was issued (UTC, ISO-8601).
    pub created_at: String,
    /// Whether it was revoked.
    pub revoked: bool,
}

impl Store {
    /// Issues a new API token for `team`; returns `(id, token)`. Only the token's hash is
    /// stored: the returned text is the only copy.
    ///
    /// # Errors
    /// [`HighscoreError::InvalidField`] for a bad team name, [`HighscoreError::Io`] if the
    /// system's random source cannot be read, database errors.
    pub fn issue_token(&self, team: &str) -> Result<(i64, String)> {
        super::check_name("team", team)?;
        let mut secret = [0u8; 32];
        let path = std::path::Path::new("/dev/urandom");
        std::fs::File::open(path)
            .and_then(|mut f| f.read_exact(&mut secret))
            .map_err(|source| HighscoreError::Io { path: path.to_path_buf(), source })?;
        let token = format!("ogt_{}", secret.iter().map(|b| format!("{b:02x}")).collect::<String>());
        self.conn()
            .execute("INSERT INTO tokens (team, hash) VALUES (?1, ?2)", params![team, sha256_hex(token.as_bytes())])?;
        Ok((self.conn().last_insert_rowid(), token))
    }

    /// The team of a valid (issued, not revoked) token.
    ///
    /// # Errors
    /// [`HighscoreError::Unauthorized`] for an unknown or revoked token, database errors.
    pub fn check_token(&self, token: &str) -> Result<String> {
        let team: Option<String> = self
            .conn()
            .prepare_cached("SELECT team FROM tokens WHERE hash = ?1 AND revoked = 0")?
            .query_row([sha256_hex(token.as_bytes())], |r| r.get(0))
            .optional()?;
        team.ok_or_else(|| HighscoreError::Unauthorized { reason: "unknown or revoked API token".into() })
    }

    /// Revokes token `id`; returns whether it existed.
    ///
    /// # Errors
    /// Database errors.
    pub fn revoke_token(&self, id: i64) -> Result<bool> {
        Ok(self.conn().execute("UPDATE tokens SET revoked = 1 WHERE id = ?1", [id])? > 0)
    }

    /// Every issued token (without secrets), oldest first.
    ///
    /// # Errors
    /// Database errors.
    pub fn tokens(&self) -> Result<Vec<TokenInfo>> {
        let mut stmt = self.conn().prepare("SELECT id, team, created_at, revoked FROM tokens ORDER BY id")?;
        let rows = stmt.query_map([], |r| {
            Ok(TokenInfo { id: r.get(0)?, team: r.get(1)?, created_at: r.get(2)?, revoked: r.get(3)? })
        })?;
        Ok(rows.collect::<rusqlite::Result<_>>()?)
    }
}
