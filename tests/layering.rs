//! The layering of ARCHITECTURE.md, checked on the source (issue 36): a stage imports only
//! the stages below it (with the few exceptions listed here, each with its reason), no two
//! files of different stages import each other through a cycle, `ops` (the library API)
//! never reaches the command line, and the command line stays a thin shell.
//!
//! An import is any path `crate::a::b::...` (a `use` or a path in code; `super::` and
//! `self::` resolved against the file's module) outside comments and test modules, resolved
//! to the file that defines the longest prefix of it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The stages, bottom to top.
const ORDER: &[&str] = &[
    "units",
    "syntax",
    "diagnostics",
    "check",
    "artifact",
    "structure",
    "aero",
    "runtime",
    "import",
    "plan",
    "run",
    "analysis",
    "report",
    "ops",
    "cli",
    "main",
];

/// Upward imports that are allowed, with the reason: the checker reads the files a model
/// references (coefficient tables, thrust curves) with the parsers of the stages that use
/// them, and sizes outputs with the plan's channel counts, so that a bad file or an
/// impossible request is a diagnostic at `check` time (the brief's "found as early as
/// possible").
const EXCEPTIONS: &[(&str, &str)] = &[
    ("check/vehicle.rs", "aero/tables.rs"),
    ("check/vehicle.rs", "aero/fin_loads.rs"),
    ("check/datcom_source.rs", "aero/datcom.rs"),
    ("check/motor.rs", "runtime/thrust.rs"),
    ("check/motor.rs", "runtime/catalogue.rs"),
    ("check/scenario.rs", "runtime/stimuli.rs"),
    ("check/scenario.rs", "plan/mod.rs"),
];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// `src`-relative path with `/` separators.
fn rel(p: &Path) -> String {
    p.strip_prefix(src())
        .unwrap()
        .components()
        .map(|c| c.as_os_str().to_string_lossy().to_string())
        .collect::<Vec<_>>()
        .join("/")
}

fn stage(rel: &str) -> &str {
    let first = rel.split('/').next().unwrap_or(rel);
    first.strip_suffix(".rs").unwrap_or(first)
}

/// The module path of a file (`aero/panel/mod.rs` -> `[aero, panel]`).
fn module_of(rel: &str) -> Vec<String> {
    let mut segs: Vec<String> = rel
        .strip_suffix(".rs")
        .unwrap()
        .split('/')
        .map(str::to_string)
        .collect();
    if matches!(segs.last().map(String::as_str), Some("mod" | "lib")) {
        segs.pop();
    }
    segs
}

/// The text without comments, and without everything from a `#[cfg(test)]` on (test
/// modules sit at the end of a file).
fn code_of(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        if line.trim_start().starts_with("#[cfg(test)]") {
            break;
        }
        let code = match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        };
        out.push_str(code);
        out.push('\n');
    }
    out
}

/// Files declared as test-only modules (`#[cfg(test)] mod x;`).
fn test_modules(files: &BTreeMap<String, String>) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (rel, text) in files {
        let lines: Vec<&str> = text.lines().collect();
        for w in lines.windows(2) {
            if w[0].trim() == "#[cfg(test)]" {
                if let Some(name) = w[1]
                    .trim()
                    .strip_prefix("mod ")
                    .and_then(|r| r.strip_suffix(';'))
                {
                    let mut m = module_of(rel);
                    if !rel.ends_with("mod.rs") && !rel.ends_with("lib.rs") {
                        m.pop();
                    }
                    let base = m.join("/");
                    let prefix = if base.is_empty() {
                        String::new()
                    } else {
                        base + "/"
                    };
                    out.insert(format!("{prefix}{name}.rs"));
                    out.insert(format!("{prefix}{name}/mod.rs"));
                }
            }
        }
    }
    out
}

/// The file that defines the longest prefix of `segs`.
fn resolve(files: &BTreeMap<String, String>, segs: &[String]) -> Option<String> {
    (1..=segs.len()).rev().find_map(|k| {
        let base = segs[..k].join("/");
        [format!("{base}.rs"), format!("{base}/mod.rs")]
            .into_iter()
            .find(|c| files.contains_key(c))
    })
}

fn ident_chars(s: &str) -> impl Iterator<Item = &str> {
    s.split("::")
}

/// Every file -> the files it imports.
fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let mut paths = Vec::new();
    rust_files(&src(), &mut paths);
    let files: BTreeMap<String, String> = paths
        .iter()
        .map(|p| (rel(p), std::fs::read_to_string(p).unwrap()))
        .collect();
    let tests = test_modules(&files);
    let mut g = BTreeMap::new();
    for (rel, text) in &files {
        if tests.contains(rel) {
            continue;
        }
        let me = module_of(rel);
        let code = code_of(text);
        let mut out = BTreeSet::new();
        let bytes = code.as_bytes();
        for root in ["crate::", "super::", "self::"] {
            let mut from = 0;
            while let Some(i) = code[from..].find(root) {
                let at = from + i;
                from = at + root.len();
                // A whole word: not the tail of another identifier.
                if at > 0 && (bytes[at - 1].is_ascii_alphanumeric() || bytes[at - 1] == b'_') {
                    continue;
                }
                let tail: String = code[at..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_' || *c == ':')
                    .collect();
                let mut segs: Vec<String> = ident_chars(&tail)
                    .filter(|s| !s.is_empty())
                    .map(str::to_string)
                    .collect();
                let mut base = match segs.first().map(String::as_str) {
                    Some("crate") => Vec::new(),
                    Some("self") => me.clone(),
                    Some("super") => {
                        let mut m = me.clone();
                        m.pop();
                        m
                    }
                    _ => continue,
                };
                segs.remove(0);
                while segs.first().map(String::as_str) == Some("super") {
                    base.pop();
                    segs.remove(0);
                }
                base.extend(segs);
                // `use crate::{a, b}` groups: each item (the group's first level only).
                if code[at + tail.len()..].starts_with('{') {
                    let close = code[at + tail.len()..].find('}').unwrap_or(0);
                    for item in code[at + tail.len() + 1..at + tail.len() + close].split(',') {
                        let first = item.trim().split("::").next().unwrap_or("").trim();
                        if first.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                            && !first.is_empty()
                        {
                            let mut p = base.clone();
                            p.push(first.to_string());
                            if let Some(f) = resolve(&files, &p) {
                                out.insert(f);
                            }
                        }
                    }
                }
                if let Some(f) = resolve(&files, &base) {
                    out.insert(f);
                }
            }
        }
        out.remove(rel);
        g.insert(rel.clone(), out);
    }
    g
}

#[test]
fn stages_import_only_the_stages_below_them() {
    let rank: BTreeMap<&str, usize> = ORDER.iter().enumerate().map(|(i, s)| (*s, i)).collect();
    let mut wrong = Vec::new();
    for (file, deps) in graph() {
        let a = stage(&file);
        let Some(ra) = rank.get(a) else { continue };
        for d in deps {
            let b = stage(&d);
            let Some(rb) = rank.get(b) else { continue };
            if rb > ra && !EXCEPTIONS.contains(&(file.as_str(), d.as_str())) {
                wrong.push(format!("{file} ({a}) imports {d} ({b})"));
            }
        }
    }
    assert!(
        wrong.is_empty(),
        "imports against the layering of ARCHITECTURE.md:\n{}",
        wrong.join("\n")
    );
}

/// Tarjan's strongly connected components of the file graph: no component holds files of
/// two stages.
#[test]
fn no_import_cycle_between_files_of_different_stages() {
    let g = graph();
    let names: Vec<&String> = g.keys().collect();
    let id: BTreeMap<&String, usize> = names.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let adj: Vec<Vec<usize>> = names
        .iter()
        .map(|n| g[*n].iter().filter_map(|d| id.get(d).copied()).collect())
        .collect();
    let n = names.len();
    let (mut index, mut low, mut on) = (vec![usize::MAX; n], vec![0; n], vec![false; n]);
    let (mut stack, mut next, mut comps) = (Vec::new(), 0usize, Vec::new());
    // Iterative Tarjan: (node, next edge).
    for s in 0..n {
        if index[s] != usize::MAX {
            continue;
        }
        let mut work = vec![(s, 0usize)];
        index[s] = next;
        low[s] = next;
        next += 1;
        stack.push(s);
        on[s] = true;
        while let Some(&mut (v, ref mut e)) = work.last_mut() {
            if *e < adj[v].len() {
                let w = adj[v][*e];
                *e += 1;
                if index[w] == usize::MAX {
                    index[w] = next;
                    low[w] = next;
                    next += 1;
                    stack.push(w);
                    on[w] = true;
                    work.push((w, 0));
                } else if on[w] {
                    low[v] = low[v].min(index[w]);
                }
            } else {
                work.pop();
                if let Some(&(u, _)) = work.last() {
                    low[u] = low[u].min(low[v]);
                }
                if low[v] == index[v] {
                    let mut comp = Vec::new();
                    while let Some(w) = stack.pop() {
                        on[w] = false;
                        comp.push(names[w].clone());
                        if w == v {
                            break;
                        }
                    }
                    comps.push(comp);
                }
            }
        }
    }
    let mixed: Vec<Vec<String>> = comps
        .into_iter()
        .filter(|c| c.iter().map(|f| stage(f)).collect::<BTreeSet<_>>().len() > 1)
        .collect();
    assert!(mixed.is_empty(), "import cycles across stages: {mixed:#?}");
}

/// The command line is a shell over `ops` (issue 36: no file over 600 lines, under 3,000
/// lines in all).
#[test]
fn the_command_line_stays_thin() {
    let mut paths = Vec::new();
    rust_files(&src().join("cli"), &mut paths);
    let mut total = 0;
    for p in &paths {
        let lines = std::fs::read_to_string(p).unwrap().lines().count();
        assert!(lines <= 600, "{}: {lines} lines", rel(p));
        total += lines;
    }
    assert!(total < 3000, "src/cli: {total} lines");
}

/// The graph sees real imports (a guard against a parser that finds nothing and passes).
#[test]
fn the_import_graph_is_not_empty() {
    let g = graph();
    assert!(
        g["run/mod.rs"].contains("plan/mod.rs"),
        "{:?}",
        g["run/mod.rs"]
    );
    assert!(
        g["cli/run.rs"].contains("ops/run.rs"),
        "{:?}",
        g["cli/run.rs"]
    );
    assert!(
        g["ops/run.rs"].contains("ops/compile.rs"),
        "{:?}",
        g["ops/run.rs"]
    );
}
