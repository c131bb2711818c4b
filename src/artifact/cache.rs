//! The cache directory: find an artifact by key, or build and store it.

use std::ffi::OsString;
use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use thiserror::Error;

use super::ArtifactPayload;
use super::container::{Artifact, artifact_file_name, load, write_atomic};
use super::error::ArtifactError;
use super::key::CacheKey;

/// Environment variable naming the cache directory (overridden by `--cache-dir`).
pub const CACHE_DIR_ENV: &str = "FLEXFLIGHT_CACHE";
/// Name of the cache directory inside the cargo target directory (the default location).
pub const DEFAULT_CACHE_SUBDIR: &str = "flexflight-cache";

/// A directory of artifacts, one file `<key hex>.ffa` per cache key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Cache {
    dir: PathBuf,
}

/// How [`Cache::get_or_build`] obtained its artifact.
#[derive(Debug)]
pub enum CacheOutcome {
    /// A valid artifact was found and mapped; nothing was built.
    Hit,
    /// No artifact existed for the key; it was built and stored.
    Miss,
    /// An artifact existed but was corrupt, truncated or stale; it was not used, and was
    /// rebuilt and replaced. `reason` is what was wrong with it (for a warning).
    Rebuilt {
        /// The problem found in the old file.
        reason: ArtifactError,
    },
}

impl CacheOutcome {
    /// True for [`CacheOutcome::Hit`].
    pub fn is_hit(&self) -> bool {
        matches!(self, CacheOutcome::Hit)
    }
}

impl fmt::Display for CacheOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CacheOutcome::Hit => f.write_str("cache hit"),
            CacheOutcome::Miss => f.write_str("cache miss"),
            CacheOutcome::Rebuilt { reason } => {
                write!(f, "rebuilt invalid artifact [{}]: {reason}", reason.code())
            }
        }
    }
}

/// Failure of [`Cache::get_or_build`]: either the build or the cache itself failed.
#[derive(Debug, Error)]
pub enum GetOrBuildError<E> {
    /// The build function failed; nothing was written to the cache.
    #[error(transparent)]
    Build(E),
    /// Reading, writing or re-reading the artifact failed.
    #[error(transparent)]
    Artifact(#[from] ArtifactError),
}

impl Cache {
    /// A cache in the given directory (created on first write).
    pub fn new(dir: impl Into<PathBuf>) -> Self {
        Cache { dir: dir.into() }
    }

    /// The cache directory chosen by the command line and the environment.
    ///
    /// Precedence: `cli_dir` (the `--cache-dir` option), then the environment variable
    /// `FLEXFLIGHT_CACHE`, then `<target>/flexflight-cache` where `<target>` is
    /// `CARGO_TARGET_DIR` if set, else `target` relative to the current directory. Empty
    /// environment variables count as unset. See [`Cache::resolve_from`].
    pub fn resolve(cli_dir: Option<&Path>) -> Self {
        Self::resolve_from(
            cli_dir,
            std::env::var_os(CACHE_DIR_ENV),
            std::env::var_os("CARGO_TARGET_DIR"),
        )
    }

    /// [`Cache::resolve`] with the environment passed in (pure, for tests).
    pub fn resolve_from(
        cli_dir: Option<&Path>,
        env_cache: Option<OsString>,
        env_target: Option<OsString>,
    ) -> Self {
        let non_empty = |value: Option<OsString>| value.filter(|v| !v.is_empty());
        let dir = match (cli_dir, non_empty(env_cache)) {
            (Some(dir), _) => dir.to_path_buf(),
            (None, Some(dir)) => PathBuf::from(dir),
            (None, None) => non_empty(env_target)
                .map(PathBuf::from)
                .unwrap_or_else(|| PathBuf::from("target"))
                .join(DEFAULT_CACHE_SUBDIR),
        };
        Cache { dir }
    }

    /// The cache directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Where the artifact for `key` lives (whether or not it exists).
    pub fn path_for(&self, key: &CacheKey) -> PathBuf {
        self.dir.join(artifact_file_name(key))
    }

    /// Loads the artifact for `key` if it exists and is valid.
    ///
    /// `Ok(None)` when there is no file; `Err` when the file is invalid or unreadable.
    pub fn lookup<T: ArtifactPayload>(
        &self,
        key: &CacheKey,
    ) -> Result<Option<Artifact<T>>, ArtifactError> {
        match load::<T>(&self.path_for(key), key) {
            Ok(artifact) => Ok(Some(artifact)),
            Err(ArtifactError::Io { source, .. }) if source.kind() == io::ErrorKind::NotFound => {
                Ok(None)
            }
            Err(error) => Err(error),
        }
    }

    /// Returns the artifact for `key`, building and storing it first if needed.
    ///
    /// A valid file is a [`CacheOutcome::Hit`] and `build` is not called. A missing file is
    /// a [`CacheOutcome::Miss`]. A file that exists but is corrupt, truncated, stale or
    /// unreadable is never used: the outcome is [`CacheOutcome::Rebuilt`] with the reason,
    /// and the new artifact atomically replaces it. If `build` fails, its error is returned
    /// and nothing is written. The stored artifact is re-opened through [`load`], so the
    /// returned artifact is always the memory-mapped, validated file.
    pub fn get_or_build<T, E>(
        &self,
        key: &CacheKey,
        build: impl FnOnce() -> Result<T, E>,
    ) -> Result<(Artifact<T>, CacheOutcome), GetOrBuildError<E>>
    where
        T: ArtifactPayload,
    {
        let outcome = match self.lookup::<T>(key) {
            Ok(Some(artifact)) => return Ok((artifact, CacheOutcome::Hit)),
            Ok(None) => CacheOutcome::Miss,
            Err(reason) => CacheOutcome::Rebuilt { reason },
        };
        let value = build().map_err(GetOrBuildError::Build)?;
        let path = write_atomic(&self.dir, key, &value)?;
        drop(value);
        let artifact = load::<T>(&path, key)?;
        Ok((artifact, outcome))
    }
}
