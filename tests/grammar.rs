//! grammar/vdl.ebnf agrees with the parser: every `@example` parses without error, every
//! `@reject` fails, and every nonterminal used on a right-hand side is defined.

use flexflight::syntax::{FileId, parse_file};

const GRAMMAR: &str = include_str!("../grammar/vdl.ebnf");

fn blocks(tag: &str) -> Vec<String> {
    let open = format!("(* {tag}");
    let mut out = Vec::new();
    let mut rest = GRAMMAR;
    while let Some(i) = rest.find(&open) {
        let after = &rest[i + open.len()..];
        let end = after.find("*)").expect("unterminated example");
        out.push(after[..end].trim_start_matches('\n').to_string());
        rest = &after[end..];
    }
    out
}

#[test]
fn every_example_parses() {
    let examples = blocks("@example");
    assert!(examples.len() >= 5);
    for ex in examples {
        let (_, errors) = parse_file(FileId(0), &ex);
        assert!(
            errors.is_empty(),
            "example does not parse:\n{ex}\n{errors:?}"
        );
    }
}

#[test]
fn every_reject_fails() {
    let rejects = blocks("@reject");
    assert!(rejects.len() >= 5);
    for ex in rejects {
        let (_, errors) = parse_file(FileId(0), &ex);
        assert!(!errors.is_empty(), "rejected example parses:\n{ex}");
    }
}

#[test]
fn every_nonterminal_is_defined() {
    // Strip comments, then collect `name =` definitions and identifiers used on the right.
    let mut text = String::new();
    let mut rest = GRAMMAR;
    while let Some(i) = rest.find("(*") {
        text.push_str(&rest[..i]);
        let j = rest[i..].find("*)").expect("unterminated comment");
        rest = &rest[i + j + 2..];
    }
    text.push_str(rest);
    let mut defined = Vec::new();
    let mut used = Vec::new();
    for rule in text.split(';') {
        let Some((lhs, rhs)) = rule.split_once('=') else {
            continue;
        };
        defined.push(lhs.trim().to_string());
        // Drop quoted terminals, then take identifiers.
        let mut unquoted = String::new();
        let mut quote: Option<char> = None;
        for c in rhs.chars() {
            match quote {
                Some(q) if c == q => quote = None,
                Some(_) => {}
                None if c == '"' || c == '\'' => quote = Some(c),
                None => unquoted.push(c),
            }
        }
        for word in unquoted.split(|c: char| !(c.is_alphanumeric() || c == '_')) {
            if !word.is_empty() && word.chars().next().is_some_and(|c| c.is_alphabetic()) {
                used.push(word.to_string());
            }
        }
    }
    let informal = [
        "letter",
        "digit",
        "string_char",
        "any_char_but_newline",
        "newline",
        "end_of_file",
    ];
    for u in used {
        assert!(
            defined.contains(&u) || informal.contains(&u.as_str()),
            "nonterminal `{u}` is used but not defined"
        );
    }
}
