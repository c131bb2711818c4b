//! Errors of the artifact container, each with a stable diagnostic code.

use std::io;
use std::path::PathBuf;

use thiserror::Error;

/// Why an artifact could not be written or could not be trusted.
///
/// Every variant carries the path of the artifact file. [`ArtifactError::code`] gives a
/// stable machine-readable code; [`ArtifactError::is_invalid_artifact`] tells a damaged or
/// stale file (which the cache replaces) from an I/O failure (which it reports).
#[derive(Debug, Error)]
pub enum ArtifactError {
    /// The file does not start with the flexflight artifact magic.
    #[error("{path}: not a flexflight artifact (bad magic bytes {found:02x?})")]
    BadMagic {
        /// Artifact file.
        path: PathBuf,
        /// The first eight bytes found.
        found: [u8; 8],
    },
    /// The container format version differs from the one this compiler writes.
    #[error("{path}: artifact format version {found}, this compiler uses {expected}")]
    Version {
        /// Artifact file.
        path: PathBuf,
        /// Version this compiler writes and reads.
        expected: u32,
        /// Version recorded in the file.
        found: u32,
    },
    /// The payload was written for another payload schema (another layout of the data).
    #[error("{path}: artifact payload schema {found} differs from the expected {expected}")]
    Schema {
        /// Artifact file.
        path: PathBuf,
        /// Hex of the expected schema hash.
        expected: String,
        /// Hex of the schema hash in the file.
        found: String,
    },
    /// The artifact records another cache key than the one looked up (renamed or stale).
    #[error("{path}: artifact was built for key {found}, expected {expected}")]
    KeyMismatch {
        /// Artifact file.
        path: PathBuf,
        /// Hex of the key looked up.
        expected: String,
        /// Hex of the key in the file.
        found: String,
    },
    /// The file is shorter than its header says (or shorter than the header itself).
    #[error("{path}: artifact truncated: {actual_len} bytes, expected {expected_len}")]
    Truncated {
        /// Artifact file.
        path: PathBuf,
        /// Length implied by the header (or the header length).
        expected_len: u64,
        /// Length of the file.
        actual_len: u64,
    },
    /// The file is longer than its header says.
    #[error("{path}: artifact has {extra} bytes after the payload")]
    TrailingBytes {
        /// Artifact file.
        path: PathBuf,
        /// Number of unexpected bytes.
        extra: u64,
    },
    /// The blake3 checksum over header and payload does not match (bit rot, partial write).
    #[error("{path}: artifact checksum mismatch (stored {stored}, computed {computed})")]
    Checksum {
        /// Artifact file.
        path: PathBuf,
        /// Hex of the checksum in the header.
        stored: String,
        /// Hex of the checksum of the bytes read.
        computed: String,
    },
    /// The checksum matched but the payload is not a valid archive of the expected type
    /// (rkyv/bytecheck validation failed).
    #[error("{path}: artifact payload is invalid: {message}")]
    InvalidPayload {
        /// Artifact file.
        path: PathBuf,
        /// Validation message from rkyv.
        message: String,
    },
    /// The payload could not be serialised.
    #[error("{path}: cannot serialise artifact payload: {message}")]
    Serialize {
        /// Artifact file that was to be written.
        path: PathBuf,
        /// Message from rkyv.
        message: String,
    },
    /// Reading, writing, mapping or renaming the file failed.
    #[error("{path}: {action}: {source}")]
    Io {
        /// File or directory concerned.
        path: PathBuf,
        /// What was being done ("open", "map", "rename", ...).
        action: &'static str,
        /// Underlying error.
        #[source]
        source: io::Error,
    },
}

impl ArtifactError {
    /// Stable diagnostic code of this error, e.g. `artifact::checksum`.
    pub fn code(&self) -> &'static str {
        match self {
            ArtifactError::BadMagic { .. } => "artifact::bad_magic",
            ArtifactError::Version { .. } => "artifact::version",
            ArtifactError::Schema { .. } => "artifact::schema",
            ArtifactError::KeyMismatch { .. } => "artifact::key_mismatch",
            ArtifactError::Truncated { .. } => "artifact::truncated",
            ArtifactError::TrailingBytes { .. } => "artifact::trailing_bytes",
            ArtifactError::Checksum { .. } => "artifact::checksum",
            ArtifactError::InvalidPayload { .. } => "artifact::invalid_payload",
            ArtifactError::Serialize { .. } => "artifact::serialize",
            ArtifactError::Io { .. } => "artifact::io",
        }
    }

    /// The artifact file (or directory) the error is about.
    pub fn path(&self) -> &std::path::Path {
        match self {
            ArtifactError::BadMagic { path, .. }
            | ArtifactError::Version { path, .. }
            | ArtifactError::Schema { path, .. }
            | ArtifactError::KeyMismatch { path, .. }
            | ArtifactError::Truncated { path, .. }
            | ArtifactError::TrailingBytes { path, .. }
            | ArtifactError::Checksum { path, .. }
            | ArtifactError::InvalidPayload { path, .. }
            | ArtifactError::Serialize { path, .. }
            | ArtifactError::Io { path, .. } => path,
        }
    }

    /// True when the file exists but is corrupt, truncated or stale, i.e. it must be
    /// rebuilt; false for I/O and serialisation failures.
    pub fn is_invalid_artifact(&self) -> bool {
        !matches!(
            self,
            ArtifactError::Io { .. } | ArtifactError::Serialize { .. }
        )
    }

    pub(crate) fn io(path: impl Into<PathBuf>, action: &'static str, source: io::Error) -> Self {
        ArtifactError::Io {
            path: path.into(),
            action,
            source,
        }
    }
}
