//! Stage 4, artifact: the compiled structural model cached on disk as a binary artifact.
//!
//! An artifact is identified by a [`CacheKey`], the blake3 hash of the canonical structural
//! inputs, the bytes of every referenced file and the compiler version
//! ([`CacheKeyBuilder`]). It is stored as one file `<key>.ffa` in the cache directory
//! ([`Cache`]): a fixed 128-byte header (magic, format version, schema hash, key, payload
//! length, checksum) followed by an rkyv archive of the payload ([`container`]).
//!
//! Architecture invariants:
//! - An artifact is only handed out after every check passed (header fields, exact length,
//!   blake3 checksum, rkyv/bytecheck validation). A corrupt, truncated or stale file is
//!   reported ([`CacheOutcome::Rebuilt`]) and replaced, never used.
//! - Files are written atomically (temporary file, fsync, rename) and never modified in
//!   place; this is what makes the read-only memory mapping sound.
//! - Loading copies nothing: the archived arrays are read straight from the mapping.
//! - Only a finished payload is ever written: a failed build leaves the cache untouched.
//!
//! bincode is deliberately not used (unmaintained); rkyv 0.8 with memmap2 gives zero-copy
//! loads.

pub mod cache;
pub mod canonical;
pub mod container;
pub mod error;
pub mod key;

pub use cache::{CACHE_DIR_ENV, Cache, CacheOutcome, GetOrBuildError};
pub use container::{Artifact, HEADER_LEN, MAGIC, load, schema_hash, write_atomic};
pub use error::ArtifactError;
pub use key::{CacheKey, CacheKeyBuilder};

use rkyv::api::high::{HighSerializer, HighValidator};
use rkyv::bytecheck::CheckBytes;
use rkyv::rancor;
use rkyv::ser::allocator::ArenaHandle;
use rkyv::util::AlignedVec;

/// Version of the container format (header layout and checksum definition). Bump it when
/// either changes; it is also part of every cache key.
pub const FORMAT_VERSION: u32 = 1;

/// A type that can be stored as an artifact payload.
///
/// `SCHEMA` describes the payload's fields and their versions in words, e.g.
/// `"StructuralModel v3: nodes Vec<[f64;3]>, modes Vec<f64> (column-major, 6 dof/node)"`.
/// Its hash is stored in each artifact header; an artifact written with another schema is
/// rejected as stale. Change the string whenever the payload layout changes.
pub trait ArtifactPayload:
    rkyv::Archive<Archived: for<'a> CheckBytes<HighValidator<'a, rancor::Error>>>
    + for<'a> rkyv::Serialize<HighSerializer<AlignedVec, ArenaHandle<'a>, rancor::Error>>
{
    /// Human-written description of the payload layout and its version.
    const SCHEMA: &'static str;
}
