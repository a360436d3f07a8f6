//! A database shared by the web service: one writer connection, a pool of read connections
//! (WAL mode: reads never wait for the writer) and a cache of computed rankings.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{mpsc, Arc, Mutex, PoisonError, RwLock};

use super::error::Result;
use super::{Inserted, Ranking, Store, Submission};

/// An upload waiting for a group commit and where to send its outcome.
#[derive(Debug)]
struct Job {
    submission: Submission,
    reply: mpsc::SyncSender<Result<Stored>>,
}

/// Outcome of [`Db::insert_grouped`]: the stored submission and the benchmarks it is on.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Stored {
    /// The stored submission (the earlier one for a retried upload).
    pub inserted: Inserted,
    /// Ids of the benchmarks it has results on.
    pub benchmarks: Vec<String>,
}

/// Read connections kept open for reuse (more are opened on demand and closed after use).
const POOL: usize = 8;

/// A shared results database: [`Db::write`] serialises writers on one connection,
/// [`Db::read`] runs on a pooled read-only connection, [`Db::ranking`] serves rankings from a
/// cache versioned by [`Store::generation`] (so submissions stored by another process are
/// seen too).
#[derive(Debug)]
pub struct Db {
    path: PathBuf,
    writer: Mutex<Store>,
    readers: Mutex<Vec<Store>>,
    /// Uploads waiting for the next group commit.
    queue: Mutex<Vec<Job>>,
    cache: RwLock<HashMap<String, (i64, Arc<Ranking>)>>,
}

impl Db {
    /// Opens (creating and migrating if needed) the database at `path`.
    ///
    /// # Errors
    /// As [`Store::open`].
    pub fn open(path: &Path) -> Result<Self> {
        let writer = Store::open(path)?;
        Ok(Self {
            path: path.to_path_buf(),
            writer: Mutex::new(writer),
            readers: Mutex::new(Vec::new()),
            queue: Mutex::new(Vec::new()),
            cache: RwLock::new(HashMap::new()),
        })
    }

    /// Runs `f` on the writer connection (one writer at a time).
    ///
    /// # Errors
    /// Whatever `f` returns.
    pub fn write<T>(&self, f: impl FnOnce(&mut Store) -> Result<T>) -> Result<T> {
        let mut store = self.writer.lock().unwrap_or_else(PoisonError::into_inner);
        f(&mut store)
    }

    /// Stores a validated submission with group commit: it joins the queue of waiting
    /// uploads; whichever caller next holds the writer writes every queued submission in one
    /// transaction (one fsync) and hands each its outcome only after the commit returned, so
    /// an `Ok` is durable (`synchronous = FULL`). Blocks: call it off the async workers.
    ///
    /// # Errors
    /// As [`Store::insert_batch`] (for the whole group) and [`Store::insert_submission`]
    /// (for this submission).
    pub fn insert_grouped(&self, submission: Submission) -> Result<Stored> {
        let (reply, outcome) = mpsc::sync_channel(1);
        self.queue.lock().unwrap_or_else(PoisonError::into_inner).push(Job { submission, reply });
        {
            let mut store = self.writer.lock().unwrap_or_else(PoisonError::into_inner);
            // Whatever queued while the previous group was committing (ours included, unless
            // the previous holder already took it).
            let jobs = std::mem::take(&mut *self.queue.lock().unwrap_or_else(PoisonError::into_inner));
            if !jobs.is_empty() {
                commit_group(&mut store, jobs);
            }
        }
        outcome.recv().unwrap_or_else(|_| Err(crate::server::server_error("", "the group commit was abandoned")))
    }

    /// Runs `f` on a read-only connection from the pool.
    ///
    /// # Errors
    /// Opening a connection fails, or whatever `f` returns.
    pub fn read<T>(&self, f: impl FnOnce(&Store) -> Result<T>) -> Result<T> {
        let pooled = self.readers.lock().unwrap_or_else(PoisonError::into_inner).pop();
        let store = match pooled {
            Some(s) => s,
            None => Store::open_read_only(&self.path)?,
        };
        let result = f(&store);
        let mut pool = self.readers.lock().unwrap_or_else(PoisonError::into_inner);
        if pool.len() < POOL {
            pool.push(store);
        }
        result
    }

    /// The full ranking of a benchmark, from the cache when no submission was stored since it
    /// was computed.
    ///
    /// # Errors
    /// As [`Store::ranking`].
    pub fn ranking(&self, benchmark: &str) -> Result<Arc<Ranking>> {
        self.read(|store| {
            let generation = store.generation()?;
            if let Some((g, r)) = self.cache.read().unwrap_or_else(PoisonError::into_inner).get(benchmark) {
                if *g == generation {
                    return Ok(r.clone());
                }
            }
            let ranking = Arc::new(store.ranking(benchmark)?);
            let mut cache = self.cache.write().unwrap_or_else(PoisonError::into_inner);
            if cache.len() > 1024 {
                cache.clear(); // bounded: lookups by arbitrary names must not grow it forever
            }
            cache.insert(benchmark.to_string(), (generation, ranking.clone()));
            Ok(ranking)
        })
    }
}

/// Writes `jobs` in one transaction and answers each (after the commit).
fn commit_group(store: &mut Store, jobs: Vec<Job>) {
    let submissions: Vec<&Submission> = jobs.iter().map(|j| &j.submission).collect();
    match store.insert_batch(&submissions) {
        Ok(outcomes) => {
            for (job, outcome) in jobs.iter().zip(outcomes) {
                let stored = outcome.and_then(|inserted| {
                    Ok(Stored { inserted, benchmarks: store.submission_benchmarks(inserted.id)? })
                });
                let _ = job.reply.send(stored);
            }
        }
        Err(e) => {
            // Nothing of the group was stored: every upload gets the error (503 if busy).
            let message = e.to_string();
            let busy = matches!(e, crate::HighscoreError::Busy(_));
            for job in &jobs {
                let err = if busy {
                    let code = rusqlite::ffi::Error::new(rusqlite::ffi::SQLITE_BUSY);
                    crate::HighscoreError::Busy(rusqlite::Error::SqliteFailure(code, Some(message.clone())))
                } else {
                    crate::server::server_error("", &message)
                };
                let _ = job.reply.send(Err(err));
            }
        }
    }
}
