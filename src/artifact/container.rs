//! The artifact file: a fixed header followed by an rkyv archive of the payload.
//!
//! # Layout (all integers little-endian)
//!
//! | offset | size | field                                                     |
//! |-------:|-----:|-----------------------------------------------------------|
//! |      0 |    8 | magic `b"FLEXFLT\0"`                                      |
//! |      8 |    4 | container format version, [`FORMAT_VERSION`]              |
//! |     12 |    4 | reserved, zero                                            |
//! |     16 |   32 | schema hash, see [`schema_hash`]                          |
//! |     48 |   32 | cache key                                                 |
//! |     80 |    8 | payload length in bytes                                   |
//! |     88 |    8 | reserved, zero                                            |
//! |     96 |   32 | checksum: blake3 of bytes `0..96` followed by the payload |
//! |    128 |    n | payload: `rkyv::to_bytes` of the value                    |
//!
//! The header is 128 bytes, a multiple of rkyv's 16-byte buffer alignment, and a mapping
//! starts on a page boundary, so the payload is correctly aligned for zero-copy access.
//! The checksum covers the header too, so a flipped bit anywhere in the file is detected.
//!
//! # Checks on load, in order
//!
//! length >= header, magic, format version, schema hash, key, exact payload length
//! (truncated / trailing bytes), checksum, then rkyv/bytecheck validation of the archive.
//! Only a file that passes all of them is handed out.

use std::fs::{self, File};
use std::io::{self, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use memmap2::Mmap;
use rkyv::rancor;
use rkyv::util::AlignedVec;

use super::error::ArtifactError;
use super::key::CacheKey;
use super::{ArtifactPayload, FORMAT_VERSION};

/// First eight bytes of every artifact file.
pub const MAGIC: [u8; 8] = *b"FLEXFLT\0";
/// Size of the header in bytes; the payload starts here.
pub const HEADER_LEN: usize = 128;
/// Extension of artifact files.
pub const EXTENSION: &str = "ffa";

/// Byte offset of the format version field.
pub const OFFSET_VERSION: usize = 8;
/// Byte offset of the schema hash field.
pub const OFFSET_SCHEMA: usize = 16;
/// Byte offset of the cache key field.
pub const OFFSET_KEY: usize = 48;
/// Byte offset of the payload length field.
pub const OFFSET_PAYLOAD_LEN: usize = 80;
/// Byte offset of the checksum field.
pub const OFFSET_CHECKSUM: usize = 96;

/// Describes the archive encoding; part of every schema hash so that a change of rkyv's
/// format (major version or feature flags) is detected like a change of the payload type.
const ARCHIVE_ENCODING: &str = "rkyv 0.8; little-endian; 32-bit relative pointers; aligned";

/// The schema hash of payload type `T`: blake3 of the archive encoding and `T::SCHEMA`.
pub fn schema_hash<T: ArtifactPayload>() -> [u8; 32] {
    let mut hasher = blake3::Hasher::new();
    hasher.update(ARCHIVE_ENCODING.as_bytes());
    hasher.update(&[0]);
    hasher.update(T::SCHEMA.as_bytes());
    *hasher.finalize().as_bytes()
}

/// File name of the artifact with the given key: `<64 hex digits>.ffa`.
pub fn artifact_file_name(key: &CacheKey) -> String {
    format!("{key}.{EXTENSION}")
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn encode_header(schema: &[u8; 32], key: &CacheKey, payload: &[u8]) -> [u8; HEADER_LEN] {
    let mut header = [0u8; HEADER_LEN];
    header[0..8].copy_from_slice(&MAGIC);
    header[OFFSET_VERSION..OFFSET_VERSION + 4].copy_from_slice(&FORMAT_VERSION.to_le_bytes());
    header[OFFSET_SCHEMA..OFFSET_SCHEMA + 32].copy_from_slice(schema);
    header[OFFSET_KEY..OFFSET_KEY + 32].copy_from_slice(key.as_bytes());
    header[OFFSET_PAYLOAD_LEN..OFFSET_PAYLOAD_LEN + 8]
        .copy_from_slice(&(payload.len() as u64).to_le_bytes());
    let checksum = checksum(&header, payload);
    header[OFFSET_CHECKSUM..OFFSET_CHECKSUM + 32].copy_from_slice(&checksum);
    header
}

/// blake3 of the header fields before the checksum, then the payload.
fn checksum(header: &[u8; HEADER_LEN], payload: &[u8]) -> [u8; 32] {
    let mut hasher = blake3::Hasher::new();
    hasher.update(&header[..OFFSET_CHECKSUM]);
    hasher.update(payload);
    *hasher.finalize().as_bytes()
}

fn field<const N: usize>(bytes: &[u8], offset: usize) -> [u8; N] {
    let mut out = [0u8; N];
    out.copy_from_slice(&bytes[offset..offset + N]);
    out
}

/// Distinguishes temporary files of concurrent writers inside one process (the pid alone
/// is shared by all threads).
static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Serialises `value` and writes it as the artifact for `key` in `dir`, atomically.
///
/// The file is first written to `<dir>/<key>.ffa.tmp.<pid>.<n>`, flushed to disk
/// (`fsync`), then renamed to `<dir>/<key>.ffa`; the rename replaces any previous file
/// in one step, so readers see either the old or the new artifact, never a partial one.
/// Concurrent writers of the same key each write their own temporary file; the last
/// rename wins and both leave a complete artifact. `dir` is created if missing.
/// Returns the path of the artifact.
pub fn write_atomic<T: ArtifactPayload>(
    dir: &Path,
    key: &CacheKey,
    value: &T,
) -> Result<PathBuf, ArtifactError> {
    let final_path = dir.join(artifact_file_name(key));
    let payload =
        rkyv::to_bytes::<rancor::Error>(value).map_err(|error| ArtifactError::Serialize {
            path: final_path.clone(),
            message: error.to_string(),
        })?;
    let header = encode_header(&schema_hash::<T>(), key, &payload);

    fs::create_dir_all(dir).map_err(|e| ArtifactError::io(dir, "create cache directory", e))?;
    let temp_path = dir.join(format!(
        "{}.tmp.{}.{}",
        artifact_file_name(key),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let written = write_new_file(&temp_path, &header, &payload)
        .map_err(|e| ArtifactError::io(&temp_path, "write temporary artifact", e))
        .and_then(|()| {
            fs::rename(&temp_path, &final_path)
                .map_err(|e| ArtifactError::io(&final_path, "rename temporary artifact", e))
        });
    if let Err(error) = written {
        // Best-effort cleanup: the original error is the one worth reporting.
        let _ = fs::remove_file(&temp_path);
        return Err(error);
    }
    sync_directory(dir).map_err(|e| ArtifactError::io(dir, "sync cache directory", e))?;
    Ok(final_path)
}

fn write_new_file(path: &Path, header: &[u8], payload: &[u8]) -> io::Result<()> {
    let mut file = File::options().write(true).create_new(true).open(path)?;
    file.write_all(header)?;
    file.write_all(payload)?;
    file.sync_all()
}

/// Makes the rename durable (the directory entry is flushed too).
#[cfg(unix)]
fn sync_directory(dir: &Path) -> io::Result<()> {
    File::open(dir)?.sync_all()
}

#[cfg(not(unix))]
fn sync_directory(_dir: &Path) -> io::Result<()> {
    Ok(())
}

/// Maps `file` read-only into memory.
///
/// The mapping has the length of the file at the time of the call; the caller has checked
/// that this length is non-zero.
#[allow(unsafe_code)]
fn map_read_only(file: &File) -> io::Result<Mmap> {
    // SAFETY: memmap2 requires that the mapped file is not modified or truncated while the
    // mapping lives (that would change bytes behind a `&[u8]`, or fault on access). The
    // cache never modifies an artifact file in place: `write_atomic` writes a fresh
    // temporary file and renames it over the old name, which leaves the inode mapped here
    // untouched. Only an outside process writing into the cache directory could break this,
    // and every byte is validated (checksum, then bytecheck) right after mapping.
    unsafe { Mmap::map(file) }
}

/// Where the bytes of an [`Artifact`] live.
enum Backing {
    /// A memory-mapped artifact file (header + payload).
    Mapped(Mmap),
    /// A payload serialised in memory (no header), see [`Artifact::from_value`].
    InMemory(AlignedVec),
}

/// A validated artifact: the archived payload, accessed in place without copying.
///
/// The bytes are validated once, when the artifact is loaded; [`Artifact::get`] then
/// hands out the archived root without re-validating (see its documentation).
pub struct Artifact<T: ArtifactPayload> {
    backing: Backing,
    payload_start: usize,
    source: Option<PathBuf>,
    payload: PhantomData<fn() -> T>,
}

impl<T: ArtifactPayload> std::fmt::Debug for Artifact<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Artifact")
            .field("source", &self.source)
            .field("mapped", &self.is_mapped())
            .field("payload_len", &self.payload_bytes().len())
            .finish()
    }
}

impl<T: ArtifactPayload> Artifact<T> {
    /// Serialises `value` into memory and validates it, with no file involved (for runs
    /// without a cache). Copies the arrays once, during serialisation.
    pub fn from_value(value: &T) -> Result<Self, ArtifactError> {
        let path = PathBuf::from("<in memory>");
        let bytes =
            rkyv::to_bytes::<rancor::Error>(value).map_err(|error| ArtifactError::Serialize {
                path: path.clone(),
                message: error.to_string(),
            })?;
        validate::<T>(&bytes, &path)?;
        Ok(Artifact {
            backing: Backing::InMemory(bytes),
            payload_start: 0,
            source: None,
            payload: PhantomData,
        })
    }

    /// The archived payload, borrowed from the mapping.
    ///
    /// Validation (checksum and bytecheck) ran once in [`load`] or
    /// [`Artifact::from_value`]; this access does not repeat it, so it costs a few
    /// nanoseconds whatever the payload size, and it cannot fail. Re-validating on every
    /// call ([`Artifact::get_checked`]) was measured on a 10 MB artifact of `f64`s: 120 ns
    /// with optimisation (bytecheck's per-element loop folds away), but 5.8 ms in an
    /// unoptimised build, and it would force a `Result` on every access of a file that has
    /// already been checked. Hence validate once, then access unchecked.
    #[allow(unsafe_code)]
    pub fn get(&self) -> &T::Archived {
        // SAFETY: `self` can only be built by `load` or `from_value`, which both ran
        // `rkyv::access::<T::Archived, _>` (bytecheck validation) on exactly
        // `self.payload_bytes()` with success. Those bytes are immutable for the lifetime
        // of `self`: an `AlignedVec` we own and never hand out mutably, or a read-only
        // mapping of a file that the cache never modifies in place (see
        // `map_read_only`). Hence a valid `T::Archived` is at the root position.
        unsafe { rkyv::access_unchecked::<T::Archived>(self.payload_bytes()) }
    }

    /// The archived payload after validating the bytes again (a full bytecheck pass);
    /// for callers that want to guard against the file being changed behind the mapping.
    pub fn get_checked(&self) -> Result<&T::Archived, ArtifactError> {
        let path = self
            .source
            .clone()
            .unwrap_or_else(|| PathBuf::from("<in memory>"));
        validate::<T>(self.payload_bytes(), &path)
    }

    /// The serialised payload (without the header).
    pub fn payload_bytes(&self) -> &[u8] {
        &self.all_bytes()[self.payload_start..]
    }

    /// Every byte of the artifact: the whole mapped file, or the in-memory payload.
    pub fn all_bytes(&self) -> &[u8] {
        match &self.backing {
            Backing::Mapped(map) => map,
            Backing::InMemory(bytes) => bytes,
        }
    }

    /// True when the payload is read from a memory-mapped file.
    pub fn is_mapped(&self) -> bool {
        matches!(self.backing, Backing::Mapped(_))
    }

    /// The artifact file, if the artifact was loaded from one.
    pub fn path(&self) -> Option<&Path> {
        self.source.as_deref()
    }
}

fn validate<'a, T: ArtifactPayload>(
    payload: &'a [u8],
    path: &Path,
) -> Result<&'a T::Archived, ArtifactError> {
    rkyv::access::<T::Archived, rancor::Error>(payload).map_err(|error| {
        ArtifactError::InvalidPayload {
            path: path.to_path_buf(),
            message: error.to_string(),
        }
    })
}

/// Maps the artifact at `path` and checks it against `expected_key` and the schema of `T`.
///
/// Nothing is copied: the returned [`Artifact`] reads the arrays straight from the
/// mapping. A missing file gives [`ArtifactError::Io`] whose source has kind
/// [`io::ErrorKind::NotFound`]; every corrupt, truncated or stale file gives the
/// corresponding variant (see the module documentation for the order of checks).
pub fn load<T: ArtifactPayload>(
    path: &Path,
    expected_key: &CacheKey,
) -> Result<Artifact<T>, ArtifactError> {
    let file = File::open(path).map_err(|e| ArtifactError::io(path, "open artifact", e))?;
    let file_len = file
        .metadata()
        .map_err(|e| ArtifactError::io(path, "read artifact metadata", e))?
        .len();
    if file_len < HEADER_LEN as u64 {
        return Err(ArtifactError::Truncated {
            path: path.to_path_buf(),
            expected_len: HEADER_LEN as u64,
            actual_len: file_len,
        });
    }
    let map = map_read_only(&file).map_err(|e| ArtifactError::io(path, "map artifact", e))?;
    check_container::<T>(&map, path, expected_key)?;
    validate::<T>(&map[HEADER_LEN..], path)?;
    Ok(Artifact {
        backing: Backing::Mapped(map),
        payload_start: HEADER_LEN,
        source: Some(path.to_path_buf()),
        payload: PhantomData,
    })
}

/// Checks header fields, length and checksum of a whole artifact file's bytes.
fn check_container<T: ArtifactPayload>(
    bytes: &[u8],
    path: &Path,
    expected_key: &CacheKey,
) -> Result<(), ArtifactError> {
    let path_buf = || path.to_path_buf();
    if bytes.len() < HEADER_LEN {
        return Err(ArtifactError::Truncated {
            path: path_buf(),
            expected_len: HEADER_LEN as u64,
            actual_len: bytes.len() as u64,
        });
    }
    let magic: [u8; 8] = field(bytes, 0);
    if magic != MAGIC {
        return Err(ArtifactError::BadMagic {
            path: path_buf(),
            found: magic,
        });
    }
    let version = u32::from_le_bytes(field(bytes, OFFSET_VERSION));
    if version != FORMAT_VERSION {
        return Err(ArtifactError::Version {
            path: path_buf(),
            expected: FORMAT_VERSION,
            found: version,
        });
    }
    let schema: [u8; 32] = field(bytes, OFFSET_SCHEMA);
    let expected_schema = schema_hash::<T>();
    if schema != expected_schema {
        return Err(ArtifactError::Schema {
            path: path_buf(),
            expected: hex(&expected_schema),
            found: hex(&schema),
        });
    }
    let key: [u8; 32] = field(bytes, OFFSET_KEY);
    if key != *expected_key.as_bytes() {
        return Err(ArtifactError::KeyMismatch {
            path: path_buf(),
            expected: expected_key.to_hex(),
            found: hex(&key),
        });
    }
    let payload_len = u64::from_le_bytes(field(bytes, OFFSET_PAYLOAD_LEN));
    let expected_len = (HEADER_LEN as u64).saturating_add(payload_len);
    let actual_len = bytes.len() as u64;
    if actual_len < expected_len {
        return Err(ArtifactError::Truncated {
            path: path_buf(),
            expected_len,
            actual_len,
        });
    }
    if actual_len > expected_len {
        return Err(ArtifactError::TrailingBytes {
            path: path_buf(),
            extra: actual_len - expected_len,
        });
    }
    let header: [u8; HEADER_LEN] = field(bytes, 0);
    let stored: [u8; 32] = field(bytes, OFFSET_CHECKSUM);
    let computed = checksum(&header, &bytes[HEADER_LEN..]);
    if stored != computed {
        return Err(ArtifactError::Checksum {
            path: path_buf(),
            stored: hex(&stored),
            computed: hex(&computed),
        });
    }
    Ok(())
}
