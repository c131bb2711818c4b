//! The untyped syntax tree of a vehicle description file.
//!
//! The language is deliberately uniform: a file is a body of entries; an entry is an
//! `import "path"`, an assignment `path = value`, or a block `kind [name] { body }`. What
//! kinds, fields and values mean is the checker's business (`crate::check`), so the parser,
//! the formatter and the grammar stay small. Comments and blank lines are kept as trivia so
//! `flexflight fmt` never loses what the user wrote.

use super::span::{FileId, Span};

/// An identifier with its span.
#[derive(Clone, Debug, PartialEq)]
pub struct Ident {
    pub name: String,
    pub span: Span,
}

/// A `#` comment, without the `#` and without the line end.
#[derive(Clone, Debug, PartialEq)]
pub struct Comment {
    pub text: String,
    pub span: Span,
    /// A blank line separates this comment from the comment before it in its group.
    pub blank_before: bool,
}

/// Comments and blank lines that belong to an entry.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Trivia {
    /// A blank line separated this entry from the one before.
    pub blank_before: bool,
    /// Own-line comments just above the entry.
    pub leading: Vec<Comment>,
    /// A blank line separates `leading` from the entry (a file's header comment).
    pub blank_after_leading: bool,
    /// A comment after the entry on its last line.
    pub trailing: Option<Comment>,
}

/// A parsed file.
#[derive(Clone, Debug, PartialEq)]
pub struct SourceTree {
    pub file: FileId,
    pub body: Body,
}

/// The entries of a file or of a block.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Body {
    pub entries: Vec<Entry>,
    /// Comments after the last entry (before `}` or the end of file).
    pub trailing_comments: Vec<Comment>,
    /// A blank line came before `trailing_comments`.
    pub blank_before_trailing: bool,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Entry {
    pub trivia: Trivia,
    pub kind: EntryKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum EntryKind {
    /// `import "path"`.
    Import { path: String, path_span: Span },
    /// `a.b.c = value`.
    Assign(Assign),
    /// `kind [name] { ... }`.
    Block(Block),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Assign {
    /// Dotted path; a plain field has one element.
    pub path: Vec<Ident>,
    pub value: Value,
}

impl Assign {
    pub fn path_span(&self) -> Span {
        match (self.path.first(), self.path.last()) {
            (Some(a), Some(b)) => a.span.to(b.span),
            _ => self.value.span,
        }
    }

    pub fn path_string(&self) -> String {
        path_string(&self.path)
    }
}

/// Join a dotted path for messages.
pub fn path_string(path: &[Ident]) -> String {
    path.iter()
        .map(|i| i.name.as_str())
        .collect::<Vec<_>>()
        .join(".")
}

#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    pub kind: Ident,
    pub name: Option<Ident>,
    pub body: Body,
    /// The span of `kind [name] {` (the block's header).
    pub header: Span,
}

/// A number as written: its value and its exact lexeme (kept so `fmt` changes no digit).
#[derive(Clone, Debug, PartialEq)]
pub struct Number {
    pub value: f64,
    pub text: String,
    pub span: Span,
}

/// A unit expression such as `kg/m^3` or `N*s`: factors with signed exponents.
#[derive(Clone, Debug, PartialEq)]
pub struct UnitExpr {
    pub factors: Vec<UnitFactor>,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub struct UnitFactor {
    pub name: Ident,
    /// Exponent including the sign from `/`: `kg/m^3` is kg^1, m^-3.
    pub exponent: i8,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Value {
    pub kind: ValueKind,
    pub span: Span,
}

#[derive(Clone, Debug, PartialEq)]
pub enum ValueKind {
    /// `12`, `0.6 mm`, `-3e2 N`.
    Quantity {
        number: Number,
        unit: Option<UnitExpr>,
    },
    /// `(x, y, z) unit`: components share the unit.
    Vector {
        components: Vec<Number>,
        unit: Option<UnitExpr>,
    },
    /// `"path/to/file"`.
    Str(String),
    /// `true` / `false`.
    Bool(bool),
    /// A name: a reference to a declaration or a keyword value (`dopri5`, `per_fin`).
    Name(Ident),
    /// `name(arg, key = arg, ...)`.
    Call { name: Ident, args: Vec<Arg> },
    /// `[a, b, c]`.
    List(Vec<Value>),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    pub name: Option<Ident>,
    pub value: Value,
}

impl Value {
    /// A short description of the value's shape, for "expected X, found Y" messages.
    pub fn describe(&self) -> &'static str {
        match &self.kind {
            ValueKind::Quantity { unit: Some(_), .. } => "a quantity",
            ValueKind::Quantity { unit: None, .. } => "a number",
            ValueKind::Vector { .. } => "a vector",
            ValueKind::Str(_) => "a string",
            ValueKind::Bool(_) => "a boolean",
            ValueKind::Name(_) => "a name",
            ValueKind::Call { .. } => "a call",
            ValueKind::List(_) => "a list",
        }
    }
}
