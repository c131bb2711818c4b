//! The parser: text to [`SourceTree`], with error recovery at entry level.
//!
//! Token-level recognisers (numbers, names, strings, units, whitespace) are nom 8 parsers
//! over a `nom_locate` span; the block structure is a small recursive descent on top of them,
//! so each error names what was expected at the offending token.
//!
//! Naming convention (after gleam's parser): `parse_x` parses an x or fails with a
//! [`ParseError`]; `maybe_x` returns `None` without consuming when no x starts here;
//! `skip_x` consumes trivia; `lex_x` are the nom token recognisers.
//!
//! Grammar: `grammar/vdl.ebnf`. Newlines end entries (outside brackets); `;` may also end one.

use nom::branch::alt;
use nom::bytes::complete::{take_while, take_while1};
use nom::character::complete::{char, digit0, digit1, one_of};
use nom::combinator::{opt, recognize};
use nom::{IResult, Parser};
use nom_locate::LocatedSpan;

use super::ast::*;
use super::span::{FileId, Span};

type In<'a> = LocatedSpan<&'a str, FileId>;
type Lex<'a, T> = IResult<In<'a>, T, nom::error::Error<In<'a>>>;

/// Nesting deeper than this is refused (protects the stack against hostile input).
const MAX_DEPTH: usize = 64;

/// A syntax error: what was expected, what was found, where.
#[derive(Clone, Debug, PartialEq)]
pub struct ParseError {
    pub span: Span,
    pub expected: String,
    pub found: String,
    /// Where the construct that is not finished started (for example the open brace).
    pub context: Option<(Span, String)>,
}

/// Parse a whole file. Always returns a tree (possibly partial) and every syntax error found.
pub fn parse_file(file: FileId, text: &str) -> (SourceTree, Vec<ParseError>) {
    let mut p = Parser_ {
        errors: Vec::new(),
        depth: 0,
    };
    let input = In::new_extra(text, file);
    let (rest, body) = p.parse_body(input, None);
    if !rest.fragment().is_empty() {
        // A stray `}` at top level: report and stop (the body parser stops at it).
        p.errors.push(error_at(
            rest,
            "an entry (`name = value`, `kind name { ... }` or `import`)",
        ));
    }
    (SourceTree { file, body }, p.errors)
}

/// Parse a single value written outside a file (used by `--set PATH=VALUE`).
pub fn parse_standalone_value(file: FileId, text: &str) -> Result<Value, ParseError> {
    let mut p = Parser_ {
        errors: Vec::new(),
        depth: 0,
    };
    let input = In::new_extra(text, file);
    let (rest, _) = skip_ws_nl(input);
    let (rest, value) = p.parse_value(rest)?;
    let (rest, _) = skip_ws_nl(rest);
    if rest.fragment().is_empty() {
        Ok(value)
    } else {
        Err(error_at(rest, "the end of the value"))
    }
}

/// Parse a dotted path written outside a file (`fins.thickness`).
pub fn parse_standalone_path(file: FileId, text: &str) -> Result<Vec<Ident>, ParseError> {
    let input = In::new_extra(text, file);
    let (rest, _) = skip_inline(input);
    let (rest, path) = parse_path(rest)?;
    let (rest, _) = skip_inline(rest);
    if rest.fragment().is_empty() {
        Ok(path)
    } else {
        Err(error_at(rest, "`.` or the end of the path"))
    }
}

struct Parser_ {
    errors: Vec<ParseError>,
    depth: usize,
}

fn span_of(start: In, end: In) -> Span {
    Span::new(start.extra, start.location_offset(), end.location_offset())
}

fn point(i: In) -> Span {
    Span::new(i.extra, i.location_offset(), i.location_offset())
}

/// Describe the token at `i` for messages.
fn found_at(i: In) -> String {
    let s = i.fragment();
    match s.chars().next() {
        None => "end of file".to_string(),
        Some('\n') | Some('\r') => "end of line".to_string(),
        Some(c) if c.is_alphanumeric() || c == '_' || c == '-' || c == '.' => {
            let tok: String = s
                .chars()
                .take_while(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '+'))
                .take(40)
                .collect();
            format!("`{tok}`")
        }
        Some(c) => format!("`{c}`"),
    }
}

fn token_len(i: In) -> usize {
    let s = i.fragment();
    match s.chars().next() {
        None | Some('\n') | Some('\r') => 0,
        Some(c) if c.is_alphanumeric() || c == '_' => s
            .char_indices()
            .find(|(_, c)| !(c.is_alphanumeric() || *c == '_'))
            .map_or(s.len(), |(k, _)| k),
        Some(c) => c.len_utf8(),
    }
}

fn error_at(i: In, expected: &str) -> ParseError {
    let start = i.location_offset();
    ParseError {
        span: Span::new(i.extra, start, start + token_len(i)),
        expected: expected.to_string(),
        found: found_at(i),
        context: None,
    }
}

// ---------------------------------------------------------------------------------------
// Trivia

/// Spaces and tabs (and `\r`), not newlines, not comments.
fn skip_inline(i: In) -> (In, ()) {
    let r: Lex<In> = take_while(|c| c == ' ' || c == '\t' || c == '\r').parse(i);
    match r {
        Ok((rest, _)) => (rest, ()),
        Err(_) => (i, ()),
    }
}

/// Whitespace, newlines and comments (inside brackets, where newlines do not end entries).
fn skip_ws_nl(mut i: In) -> (In, ()) {
    loop {
        let (rest, _) = skip_inline(i);
        i = rest;
        if let Some((rest, _)) = maybe_comment(i) {
            i = rest;
            continue;
        }
        if i.fragment().starts_with('\n') {
            i = advance(i, 1);
            continue;
        }
        return (i, ());
    }
}

fn advance(i: In, n: usize) -> In {
    // `n` is a byte count (`recover` passes a byte offset from `char_indices`). nom's
    // `take` counts characters on `str`: with multi-byte characters it overshot, or failed
    // near the end of the input and left `i` unchanged, so error recovery looped forever.
    if i.fragment().is_char_boundary(n) {
        nom::Input::take_from(&i, n)
    } else {
        i
    }
}

/// `# ...` up to (not including) the line end.
fn maybe_comment(i: In) -> Option<(In, Comment)> {
    let r: Lex<In> = recognize((char('#'), take_while(|c| c != '\n'))).parse(i);
    let (rest, c) = r.ok()?;
    let text = c.fragment()[1..].trim_end_matches('\r').to_string();
    Some((
        rest,
        Comment {
            text,
            span: span_of(i, rest),
            blank_before: false,
        },
    ))
}

// ---------------------------------------------------------------------------------------
// Tokens

fn lex_ident(i: In) -> Lex<In> {
    recognize((
        take_while1(|c: char| c.is_ascii_alphabetic() || c == '_'),
        take_while(|c: char| c.is_ascii_alphanumeric() || c == '_'),
    ))
    .parse(i)
}

fn maybe_ident(i: In) -> Option<(In, Ident)> {
    let (rest, s) = lex_ident(i).ok()?;
    Some((
        rest,
        Ident {
            name: s.fragment().to_string(),
            span: span_of(i, rest),
        },
    ))
}

fn parse_ident<'a>(i: In<'a>, what: &str) -> Result<(In<'a>, Ident), ParseError> {
    maybe_ident(i).ok_or_else(|| error_at(i, what))
}

fn lex_number(i: In) -> Lex<In> {
    recognize((
        opt(one_of("+-")),
        digit1,
        opt((char('.'), digit0)),
        opt((one_of("eE"), opt(one_of("+-")), digit1)),
    ))
    .parse(i)
}

fn maybe_number(i: In) -> Option<Result<(In, Number), ParseError>> {
    let (rest, s) = lex_number(i).ok()?;
    // A number glued to a name (`3x`) is not a number followed by a unit written `x`
    // only when the name starts right after a digit: `5mm` is allowed, `1.2.3` is not.
    if rest.fragment().starts_with('.') {
        return Some(Err(error_at(
            rest,
            "a digit, a unit or the end of the number",
        )));
    }
    // `7e GPa`, `7e+ GPa`: an exponent marker without digits. Without this check the `e`
    // would be read as a unit and the error would land on the next token.
    let frag = *rest.fragment();
    if !s.fragment().contains(['e', 'E']) && frag.starts_with(['e', 'E']) {
        let after_marker = &frag[1..];
        let signed = after_marker.starts_with(['+', '-']);
        let next = after_marker[usize::from(signed)..].chars().next();
        if signed || !next.is_some_and(|c| c.is_alphanumeric() || c == '_') {
            let marker_len = 1 + usize::from(signed);
            let start = rest.location_offset();
            return Some(Err(ParseError {
                span: Span::new(rest.extra, start, start + marker_len),
                expected: "digits in the exponent".into(),
                found: format!("`{}` with no digits after it", &frag[..marker_len]),
                context: None,
            }));
        }
    }
    let text = s.fragment().to_string();
    let value = match text.parse::<f64>() {
        Ok(v) if v.is_finite() => v,
        _ => {
            return Some(Err(ParseError {
                span: span_of(i, rest),
                expected: "a finite number".into(),
                found: format!("`{text}`"),
                context: None,
            }));
        }
    };
    Some(Ok((
        rest,
        Number {
            value,
            text,
            span: span_of(i, rest),
        },
    )))
}

fn lex_string(i: In) -> Lex<In> {
    recognize((
        char('"'),
        nom::multi::many0_count(alt((
            recognize((char('\\'), one_of("\"\\nt"))),
            take_while1(|c| c != '"' && c != '\\' && c != '\n'),
        ))),
        char('"'),
    ))
    .parse(i)
}

fn maybe_string(i: In) -> Option<Result<(In, String), ParseError>> {
    if !i.fragment().starts_with('"') {
        return None;
    }
    match lex_string(i) {
        Ok((rest, s)) => {
            let raw = &s.fragment()[1..s.fragment().len() - 1];
            let mut out = String::with_capacity(raw.len());
            let mut chars = raw.chars();
            while let Some(c) = chars.next() {
                if c == '\\' {
                    match chars.next() {
                        Some('n') => out.push('\n'),
                        Some('t') => out.push('\t'),
                        Some(o) => out.push(o),
                        None => {}
                    }
                } else {
                    out.push(c);
                }
            }
            Some(Ok((rest, out)))
        }
        Err(_) => {
            let line_end = i.fragment().find('\n').unwrap_or(i.fragment().len());
            let start = i.location_offset();
            Some(Err(ParseError {
                span: Span::new(i.extra, start, start + line_end),
                expected: "a closing `\"` on the same line".into(),
                found: "an unterminated string".into(),
                context: None,
            }))
        }
    }
}

/// `kg/m^3`, `N*s`, `m/s^2`, `deg`: factors joined by `*` or `/`, each with an optional
/// integer exponent `^n` (`^-n` allowed).
fn maybe_unit(i: In) -> Option<Result<(In, UnitExpr), ParseError>> {
    let (mut rest, first) = maybe_ident(i)?;
    let mut factors = Vec::new();
    let mut sign: i8 = 1;
    let mut name = first;
    loop {
        let mut exponent: i8 = 1;
        if rest.fragment().starts_with('^') {
            let after = advance(rest, 1);
            let r: Lex<In> = recognize((opt(char('-')), digit1)).parse(after);
            match r {
                Ok((r2, e)) => match e.fragment().parse::<i8>() {
                    Ok(v) if (-9..=9).contains(&v) && v != 0 => {
                        exponent = v;
                        rest = r2;
                    }
                    _ => {
                        return Some(Err(ParseError {
                            span: span_of(after, r2),
                            expected: "a small non-zero integer exponent".into(),
                            found: format!("`{}`", e.fragment()),
                            context: None,
                        }));
                    }
                },
                Err(_) => return Some(Err(error_at(after, "an integer exponent after `^`"))),
            }
        }
        factors.push(UnitFactor {
            name,
            exponent: exponent.saturating_mul(sign),
        });
        let op = rest.fragment().chars().next();
        match op {
            Some('*') | Some('/') => {
                sign = if op == Some('/') { -1 } else { 1 };
                let after = advance(rest, 1);
                match maybe_ident(after) {
                    Some((r2, n)) => {
                        name = n;
                        rest = r2;
                    }
                    None => return Some(Err(error_at(after, "a unit name"))),
                }
            }
            _ => break,
        }
    }
    Some(Ok((
        rest,
        UnitExpr {
            factors,
            span: span_of(i, rest),
        },
    )))
}

/// `a.b.c`
fn parse_path(i: In) -> Result<(In, Vec<Ident>), ParseError> {
    let (mut rest, first) = parse_ident(i, "a name")?;
    let mut path = vec![first];
    while rest.fragment().starts_with('.') {
        let after = advance(rest, 1);
        let (r2, next) = parse_ident(after, "a field name after `.`")?;
        path.push(next);
        rest = r2;
    }
    Ok((rest, path))
}

// ---------------------------------------------------------------------------------------
// Structure

/// What may end an entry: a newline, `;`, `}` or the end of the file.
fn at_entry_end(i: In) -> bool {
    let s = i.fragment();
    s.is_empty() || s.starts_with('\n') || s.starts_with(';') || s.starts_with('}')
}

impl Parser_ {
    /// Entries until `}` (not consumed) or the end of input. `open` is the span of the
    /// opening brace when inside a block.
    fn parse_body<'a>(&mut self, mut i: In<'a>, open: Option<Span>) -> (In<'a>, Body) {
        let mut body = Body::default();
        let mut pending: Vec<Comment> = Vec::new();
        // A blank line before the pending comment group (or before the next entry if there
        // are no pending comments).
        let mut blank = false;
        // A blank line after the last pending comment.
        let mut gap = false;
        let mut newlines_in_a_row = 0usize;
        loop {
            let (rest, _) = skip_inline(i);
            i = rest;
            let s = *i.fragment();
            if s.starts_with('\n') {
                newlines_in_a_row += 1;
                if newlines_in_a_row >= 2 {
                    if !pending.is_empty() {
                        gap = true;
                    } else if !body.entries.is_empty() {
                        blank = true;
                    }
                }
                i = advance(i, 1);
                continue;
            }
            if s.starts_with(';') {
                i = advance(i, 1);
                continue;
            }
            if let Some((rest, mut c)) = maybe_comment(i) {
                if newlines_in_a_row == 0 && !body.entries.is_empty() && pending.is_empty() {
                    // A comment on the same line after an entry that ended with `;`.
                    if let Some(last) = body.entries.last_mut() {
                        if last.trivia.trailing.is_none() {
                            last.trivia.trailing = Some(c);
                            i = rest;
                            continue;
                        }
                    }
                }
                // A blank line inside a comment group stays with the comment after it.
                c.blank_before = std::mem::take(&mut gap);
                pending.push(c);
                newlines_in_a_row = 0;
                i = rest;
                continue;
            }
            if s.is_empty() || s.starts_with('}') {
                if s.is_empty() {
                    if let Some(open) = open {
                        let mut e = error_at(i, "`}` to close the block");
                        e.context = Some((open, "the block opened here".into()));
                        self.errors.push(e);
                    }
                }
                body.blank_before_trailing = blank && !pending.is_empty();
                body.trailing_comments = pending;
                return (i, body);
            }
            newlines_in_a_row = 0;
            let start = i;
            match self.parse_entry(i) {
                Ok((rest, kind)) => {
                    let (rest, _) = skip_inline(rest);
                    let (rest, trailing) = match maybe_comment(rest) {
                        Some((r, c)) => (r, Some(c)),
                        None => (rest, None),
                    };
                    let span = span_of(start, rest);
                    let trivia = Trivia {
                        blank_after_leading: !pending.is_empty() && std::mem::take(&mut gap),
                        blank_before: blank,
                        leading: std::mem::take(&mut pending),
                        trailing,
                    };
                    blank = false;
                    body.entries.push(Entry { trivia, kind, span });
                    if at_entry_end(rest) {
                        i = rest;
                    } else {
                        self.errors
                            .push(error_at(rest, "the end of the line (one entry per line)"));
                        i = recover(rest);
                    }
                }
                Err(e) => {
                    self.errors.push(e);
                    pending.clear();
                    blank = false;
                    gap = false;
                    i = recover(start);
                }
            }
        }
    }

    fn parse_entry<'a>(&mut self, i: In<'a>) -> Result<(In<'a>, EntryKind), ParseError> {
        let Some((after_kw, first)) = maybe_ident(i) else {
            return Err(error_at(
                i,
                "an entry (`name = value`, `kind name { ... }` or `import \"file\"`)",
            ));
        };
        let (after_ws, _) = skip_inline(after_kw);
        if first.name == "import" && after_ws.fragment().starts_with('"') {
            let Some(r) = maybe_string(after_ws) else {
                return Err(error_at(after_ws, "a quoted file path"));
            };
            let (rest, path) = r?;
            return Ok((
                rest,
                EntryKind::Import {
                    path,
                    path_span: span_of(after_ws, rest),
                },
            ));
        }
        // Assignment: path `=` value.
        let (after_path, path) = parse_path(i)?;
        let (after_path_ws, _) = skip_inline(after_path);
        if after_path_ws.fragment().starts_with('=') {
            let (after_eq, _) = skip_inline(advance(after_path_ws, 1));
            let (rest, value) = self.parse_value(after_eq)?;
            return Ok((rest, EntryKind::Assign(Assign { path, value })));
        }
        if path.len() > 1 {
            return Err(error_at(after_path_ws, "`=` after the field path"));
        }
        // Block: kind [name] `{` body `}`.
        let mut rest = after_path_ws;
        let mut name = None;
        if let Some((r, n)) = maybe_ident(rest) {
            name = Some(n);
            rest = skip_inline(r).0;
        }
        if !rest.fragment().starts_with('{') {
            let expected = if name.is_some() {
                "`{` to open the block"
            } else {
                "`=` or `{`"
            };
            return Err(error_at(rest, expected));
        }
        let open_span = span_of(rest, advance(rest, 1));
        let header = first.span.to(open_span);
        if self.depth >= MAX_DEPTH {
            return Err(ParseError {
                span: open_span,
                expected: format!("at most {MAX_DEPTH} nested blocks"),
                found: "deeper nesting".into(),
                context: None,
            });
        }
        self.depth += 1;
        let (after_body, body) = self.parse_body(advance(rest, 1), Some(open_span));
        self.depth -= 1;
        let rest = if after_body.fragment().starts_with('}') {
            advance(after_body, 1)
        } else {
            after_body
        };
        Ok((
            rest,
            EntryKind::Block(Block {
                kind: first,
                name,
                body,
                header,
            }),
        ))
    }

    fn parse_value<'a>(&mut self, i: In<'a>) -> Result<(In<'a>, Value), ParseError> {
        if self.depth >= MAX_DEPTH {
            return Err(ParseError {
                span: point(i),
                expected: format!("at most {MAX_DEPTH} nested values"),
                found: "deeper nesting".into(),
                context: None,
            });
        }
        self.depth += 1;
        let r = self.parse_value_inner(i);
        self.depth -= 1;
        r
    }

    fn parse_value_inner<'a>(&mut self, i: In<'a>) -> Result<(In<'a>, Value), ParseError> {
        let s = *i.fragment();
        if let Some(r) = maybe_string(i) {
            let (rest, text) = r?;
            return Ok((
                rest,
                Value {
                    kind: ValueKind::Str(text),
                    span: span_of(i, rest),
                },
            ));
        }
        if let Some(r) = maybe_number(i) {
            let (rest, number) = r?;
            let (rest, unit) = self.maybe_trailing_unit(rest)?;
            return Ok((
                rest,
                Value {
                    kind: ValueKind::Quantity { number, unit },
                    span: span_of(i, rest),
                },
            ));
        }
        if s.starts_with('(') {
            let mut rest = skip_ws_nl(advance(i, 1)).0;
            let mut components = Vec::new();
            loop {
                match maybe_number(rest) {
                    Some(r) => {
                        let (r2, n) = r?;
                        components.push(n);
                        rest = skip_ws_nl(r2).0;
                    }
                    None => return Err(error_at(rest, "a number (vector component)")),
                }
                if rest.fragment().starts_with(',') {
                    rest = skip_ws_nl(advance(rest, 1)).0;
                    continue;
                }
                if rest.fragment().starts_with(')') {
                    rest = advance(rest, 1);
                    break;
                }
                return Err(error_at(rest, "`,` or `)` in a vector"));
            }
            let (rest, unit) = self.maybe_trailing_unit(rest)?;
            return Ok((
                rest,
                Value {
                    kind: ValueKind::Vector { components, unit },
                    span: span_of(i, rest),
                },
            ));
        }
        if s.starts_with('[') {
            let mut rest = skip_ws_nl(advance(i, 1)).0;
            let mut items = Vec::new();
            loop {
                if rest.fragment().starts_with(']') {
                    rest = advance(rest, 1);
                    break;
                }
                let (r2, v) = self.parse_value(rest)?;
                items.push(v);
                rest = skip_ws_nl(r2).0;
                if rest.fragment().starts_with(',') {
                    rest = skip_ws_nl(advance(rest, 1)).0;
                } else if !rest.fragment().starts_with(']') {
                    return Err(error_at(rest, "`,` or `]` in a list"));
                }
            }
            return Ok((
                rest,
                Value {
                    kind: ValueKind::List(items),
                    span: span_of(i, rest),
                },
            ));
        }
        if let Some((rest, name)) = maybe_ident(i) {
            if rest.fragment().starts_with('(') {
                let (rest, args) = self.parse_args(advance(rest, 1))?;
                return Ok((
                    rest,
                    Value {
                        kind: ValueKind::Call { name, args },
                        span: span_of(i, rest),
                    },
                ));
            }
            let kind = match name.name.as_str() {
                "true" => ValueKind::Bool(true),
                "false" => ValueKind::Bool(false),
                _ => ValueKind::Name(name),
            };
            return Ok((
                rest,
                Value {
                    kind,
                    span: span_of(i, rest),
                },
            ));
        }
        Err(error_at(
            i,
            "a value (number with unit, `(x, y, z) unit`, \"string\", name, call or list)",
        ))
    }

    /// Arguments after `(`, up to and including `)`.
    fn parse_args<'a>(&mut self, i: In<'a>) -> Result<(In<'a>, Vec<Arg>), ParseError> {
        let mut rest = skip_ws_nl(i).0;
        let mut args = Vec::new();
        loop {
            if rest.fragment().starts_with(')') {
                return Ok((advance(rest, 1), args));
            }
            // `name = value` or a positional value.
            let mut name = None;
            if let Some((r, n)) = maybe_ident(rest) {
                let (r_ws, _) = skip_inline(r);
                if r_ws.fragment().starts_with('=') {
                    name = Some(n);
                    rest = skip_ws_nl(advance(r_ws, 1)).0;
                }
            }
            let (r2, value) = self.parse_value(rest)?;
            args.push(Arg { name, value });
            rest = skip_ws_nl(r2).0;
            if rest.fragment().starts_with(',') {
                rest = skip_ws_nl(advance(rest, 1)).0;
            } else if !rest.fragment().starts_with(')') {
                return Err(error_at(rest, "`,` or `)` in the argument list"));
            }
        }
    }

    /// An optional unit after a number or vector, on the same line.
    fn maybe_trailing_unit<'a>(
        &mut self,
        i: In<'a>,
    ) -> Result<(In<'a>, Option<UnitExpr>), ParseError> {
        let (after_ws, _) = skip_inline(i);
        match maybe_unit(after_ws) {
            // `nu = 0.3 rho = 2700 kg/m^3`: `rho` starts a second entry, not a unit.
            Some(Ok((rest, _))) if skip_inline(rest).0.fragment().starts_with('=') => Err(
                error_at(after_ws, "the end of the line (one entry per line)"),
            ),
            Some(Ok((rest, u))) => Ok((rest, Some(u))),
            Some(Err(e)) => Err(e),
            None => Ok((i, None)),
        }
    }
}

/// Skip to the end of the current entry after an error: to the next newline or `;` outside
/// braces and strings, or to a `}` that closes the enclosing block (not consumed).
fn recover(i: In) -> In {
    let s = *i.fragment();
    let mut depth: i32 = 0;
    let mut in_string = false;
    let mut cut = s.len();
    let mut iter = s.char_indices().peekable();
    while let Some((k, c)) = iter.next() {
        if in_string {
            match c {
                '\\' => {
                    iter.next();
                }
                '"' => in_string = false,
                '\n' => {
                    in_string = false;
                    if depth <= 0 {
                        cut = k;
                        break;
                    }
                }
                _ => {}
            }
            continue;
        }
        match c {
            '"' => in_string = true,
            '#' => {
                // comment: skip to line end
                while let Some((_, c2)) = iter.peek() {
                    if *c2 == '\n' {
                        break;
                    }
                    iter.next();
                }
            }
            // Only braces hold recovery across lines: an unclosed `(` or `[` is the usual
            // error itself, and the next line is most likely a new entry.
            '{' => depth += 1,
            '}' => {
                if depth <= 0 {
                    cut = k;
                    break;
                }
                depth -= 1;
            }
            '\n' | ';' if depth <= 0 => {
                cut = k;
                break;
            }
            _ => {}
        }
    }
    advance(i, cut)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_ok(src: &str) -> SourceTree {
        let (tree, errors) = parse_file(FileId(0), src);
        assert!(errors.is_empty(), "{errors:?}");
        tree
    }

    #[test]
    fn blocks_assignments_and_values() {
        let tree = parse_ok(
            "import \"stdlib/materials.vdl\"\n\
             vehicle v {\n  fins { count = 4; span = 127.23 mm }\n  x = (0, 0, -1.5) m # c\n}\n",
        );
        assert_eq!(tree.body.entries.len(), 2);
        let EntryKind::Block(b) = &tree.body.entries[1].kind else {
            panic!()
        };
        assert_eq!(b.kind.name, "vehicle");
        assert_eq!(b.body.entries.len(), 2);
        assert_eq!(
            b.body.entries[1].trivia.trailing.as_ref().unwrap().text,
            " c"
        );
    }

    #[test]
    fn units_with_exponents() {
        let tree = parse_ok("rho = 2710 kg/m^3\ng = 9.8 m*s^-2\n");
        let EntryKind::Assign(a) = &tree.body.entries[0].kind else {
            panic!()
        };
        let ValueKind::Quantity { unit: Some(u), .. } = &a.value.kind else {
            panic!()
        };
        assert_eq!(u.factors.len(), 2);
        assert_eq!(u.factors[1].exponent, -3);
    }

    #[test]
    fn errors_are_collected_and_recovered() {
        let (_, errors) = parse_file(FileId(0), "a = \nb = (1, 2\nc = 3 m\nd e f\n");
        assert_eq!(errors.len(), 3, "{errors:?}");
    }

    #[test]
    fn unclosed_block_points_at_end_with_context() {
        let (_, errors) = parse_file(FileId(0), "vehicle v {\n  a = 1\n");
        assert_eq!(errors.len(), 1);
        assert!(errors[0].context.is_some());
    }

    #[test]
    fn deep_nesting_is_refused_not_overflowed() {
        let src = "a = ".to_string() + &"[".repeat(10_000);
        let (_, errors) = parse_file(FileId(0), &src);
        assert!(!errors.is_empty());
        let src = "x {".repeat(10_000);
        let (_, errors) = parse_file(FileId(0), &src);
        assert!(!errors.is_empty());
    }
}
