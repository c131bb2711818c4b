//! The cache key: a blake3 hash of everything a compiled artifact depends on.
//!
//! Every input is fed to the hasher as a self-delimiting record
//!
//! ```text
//! tag: u8 | label length: u64 LE | label bytes | value length: u64 LE | value bytes
//! ```
//!
//! so that two different input sequences can never produce the same byte stream
//! (`("ab", "c")` and `("a", "bc")` differ in their length prefixes), and a value can never
//! be mistaken for a value of another kind (the tag). The hasher itself is created in
//! blake3's key-derivation mode with a context string private to flexflight, which
//! separates these hashes from any other use of blake3.

use std::fmt;
use std::fs;
use std::io;
use std::path::Path;

use super::FORMAT_VERSION;

/// Context string of blake3's key-derivation mode: domain separation of cache keys.
const KEY_CONTEXT: &str = "flexflight 2025 artifact cache key";

/// Record tags, one per kind of input.
mod tag {
    pub const HEADER: u8 = 0;
    pub const TEXT: u8 = 1;
    pub const BYTES: u8 = 2;
    pub const F64: u8 = 3;
    pub const U64: u8 = 4;
    pub const FILE: u8 = 5;
    pub const CANONICAL: u8 = 6;
}

/// A 32-byte blake3 hash identifying one compiled artifact; displayed as 64 hex digits.
#[derive(Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct CacheKey(pub [u8; 32]);

impl CacheKey {
    /// The raw hash bytes.
    pub fn as_bytes(&self) -> &[u8; 32] {
        &self.0
    }

    /// The key as 64 lowercase hex digits (the artifact's file stem).
    pub fn to_hex(&self) -> String {
        self.to_string()
    }
}

impl fmt::Display for CacheKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for byte in self.0 {
            write!(f, "{byte:02x}")?;
        }
        Ok(())
    }
}

impl fmt::Debug for CacheKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CacheKey({self})")
    }
}

/// Builds a [`CacheKey`] from labelled inputs.
///
/// [`CacheKeyBuilder::new`] already mixes in the artifact kind, the compiler version
/// (`CARGO_PKG_VERSION`) and the container [`FORMAT_VERSION`], so a new compiler release
/// never reuses an old artifact. The caller then adds the canonical structural inputs and
/// every referenced file, in a fixed order: the order is part of the key.
#[derive(Clone)]
pub struct CacheKeyBuilder {
    hasher: blake3::Hasher,
}

impl CacheKeyBuilder {
    /// Starts a key for an artifact of the given kind (e.g. `"structural-model"`).
    pub fn new(kind: &str) -> Self {
        let mut builder = CacheKeyBuilder {
            hasher: blake3::Hasher::new_derive_key(KEY_CONTEXT),
        };
        builder.record(tag::HEADER, "kind", kind.as_bytes());
        builder.record(
            tag::HEADER,
            "compiler version",
            env!("CARGO_PKG_VERSION").as_bytes(),
        );
        builder.record(tag::HEADER, "format version", &FORMAT_VERSION.to_le_bytes());
        builder
    }

    /// Adds a text input (e.g. a canonical rendering of a structural description).
    pub fn text(&mut self, label: &str, value: &str) -> &mut Self {
        self.record(tag::TEXT, label, value.as_bytes());
        self
    }

    /// Adds a value by its canonical serialisation ([`super::canonical`]): everything it
    /// serialises except source positions, which are left out by their type.
    pub fn canonical<T: serde::Serialize + ?Sized>(
        &mut self,
        label: &str,
        value: &T,
    ) -> Result<&mut Self, super::canonical::Error> {
        let bytes = super::canonical::to_bytes(value)?;
        self.record(tag::CANONICAL, label, &bytes);
        Ok(self)
    }

    /// Adds raw bytes.
    pub fn bytes(&mut self, label: &str, value: &[u8]) -> &mut Self {
        self.record(tag::BYTES, label, value);
        self
    }

    /// Adds a float by its exact bit pattern (so `0.0` and `-0.0` give different keys, and
    /// no formatting or rounding is involved).
    pub fn f64(&mut self, label: &str, value: f64) -> &mut Self {
        self.record(tag::F64, label, &value.to_bits().to_le_bytes());
        self
    }

    /// Adds an unsigned integer (counts, option flags).
    pub fn u64(&mut self, label: &str, value: u64) -> &mut Self {
        self.record(tag::U64, label, &value.to_le_bytes());
        self
    }

    /// Adds a referenced file: its path as given and its full contents.
    ///
    /// The file is read completely; an unreadable file is an error (an artifact whose
    /// inputs cannot be read must not be looked up).
    pub fn file(&mut self, label: &str, path: &Path) -> io::Result<&mut Self> {
        let contents = fs::read(path)?;
        self.record(tag::FILE, label, path.as_os_str().as_encoded_bytes());
        self.record(tag::FILE, label, &contents);
        Ok(self)
    }

    /// The key of everything added so far (the builder may continue to be used).
    pub fn finish(&self) -> CacheKey {
        CacheKey(*self.hasher.finalize().as_bytes())
    }

    fn record(&mut self, tag: u8, label: &str, value: &[u8]) {
        self.hasher.update(&[tag]);
        self.hasher.update(&(label.len() as u64).to_le_bytes());
        self.hasher.update(label.as_bytes());
        self.hasher.update(&(value.len() as u64).to_le_bytes());
        self.hasher.update(value);
    }
}

impl fmt::Debug for CacheKeyBuilder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("CacheKeyBuilder")
            .field("so_far", &self.finish())
            .finish()
    }
}
