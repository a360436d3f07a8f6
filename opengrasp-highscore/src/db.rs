//! A database shared by the web service: one writer connection, a pool of read connections
//! (WAL mode: reads never wait for the writer) and a cache of computed rankings.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError, RwLock};

use super::error::Result;
use super::{Ranking, Store};

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
