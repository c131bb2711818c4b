//! Stage 1, syntax: source text to an untyped tree with spans, and back (`print`).
//!
//! Architecture invariant: this stage knows nothing about vehicles; it accepts any
//! well-formed file, never panics and always returns every syntax error it can find.

pub mod ast;
pub mod parser;
pub mod print;
pub mod span;

pub use parser::{ParseError, parse_file};
pub use span::{FileId, SourceMap, Span, Spanned};
