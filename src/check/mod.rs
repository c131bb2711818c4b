//! Stage 2, check: resolve imports and names, check units, ranges and references, and
//! produce the typed IR ([`ir::Program`]) in SI units with spans.
//!
//! Architecture invariants: the checker collects every error it can find in one pass and
//! never stops at the first; it never panics on any input; all file access goes through the
//! [`Loader`] trait (the real disk, or memory in tests and the fuzzer).

pub mod cli_values;
mod datcom_source;
mod dispersion;
pub mod fields;
pub mod fin_outline;
mod fin_sets;
pub mod finish;
mod fixture;
pub mod ir;
mod launch_guide;
mod motor;
pub mod nose;
pub mod overrides;
pub mod plausible;
mod scenario;
pub use dispersion::cholesky as dispersion_cholesky;
mod sweep;
pub mod transition;
mod transition_check;
mod vehicle;

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

use crate::diagnostics::{Diagnostic, did_you_mean};
use crate::syntax::ast::{Block, EntryKind, Ident, SourceTree, Value, ValueKind};
use crate::syntax::{FileId, SourceMap, Span, parse_file};

/// The standard library, embedded so `import "std/..."` works from any directory.
pub const STDLIB: &[(&str, &str)] = &[(
    "std/materials.vdl",
    include_str!("../../stdlib/materials.vdl"),
)];

/// File access for the checker.
pub trait Loader {
    fn read(&self, path: &Path) -> std::io::Result<String>;
    fn exists(&self, path: &Path) -> bool;
}

/// The real file system.
pub struct DiskLoader;

impl Loader for DiskLoader {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        std::fs::read_to_string(path)
    }
    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }
}

/// In-memory files (tests, fuzzing).
#[derive(Default)]
pub struct MemoryLoader {
    pub files: HashMap<PathBuf, String>,
}

impl Loader for MemoryLoader {
    fn read(&self, path: &Path) -> std::io::Result<String> {
        self.files
            .get(path)
            .cloned()
            .ok_or_else(|| std::io::Error::new(std::io::ErrorKind::NotFound, "not found"))
    }
    fn exists(&self, path: &Path) -> bool {
        self.files.contains_key(path)
    }
}

/// Checking context: sources, diagnostics and file access.
pub struct Cx<'a> {
    pub sources: SourceMap,
    pub diags: Vec<Diagnostic>,
    pub loader: &'a dyn Loader,
}

impl Cx<'_> {
    pub fn push(&mut self, d: Diagnostic) {
        // The name may well be declared in a file that could not be imported: an unknown
        // reference after a failed import is a follow-on error, not news.
        if d.code == "vdl::reference::unknown" && self.imports_failed() {
            return;
        }
        self.diags.push(d);
    }

    /// Did an import fail (missing file or cycle)? Then some declarations are absent.
    fn imports_failed(&self) -> bool {
        self.diags
            .iter()
            .any(|d| matches!(d.code, "vdl::import::missing" | "vdl::import::cycle"))
    }

    /// Has any file (or `--set`) a syntax error? Then the trees are partial: an entry the
    /// parser skipped would be reported again as missing, and a block whose brace is
    /// missing shifts every later block to the wrong level. Such files are checked for
    /// syntax only.
    fn has_syntax_errors(&self) -> bool {
        self.diags.iter().any(|d| d.code == "vdl::syntax")
    }

    /// Directory of the file a span is in (to resolve relative paths).
    pub fn dir_of(&self, span: Span) -> PathBuf {
        self.sources
            .get(span.file)
            .and_then(|f| f.path.parent().map(Path::to_path_buf))
            .unwrap_or_default()
    }

    /// Resolve a file path written at `span`, relative to the declaring file; report a
    /// missing file at the span.
    pub fn resolve_file(&mut self, written: &str, span: Span, what: &str) -> Option<PathBuf> {
        let path = lexical_join(&self.dir_of(span), Path::new(written));
        if self.loader.exists(&path) {
            Some(path)
        } else {
            self.push(
                Diagnostic::error(
                    "vdl::file::missing",
                    format!("{what} `{written}` does not exist"),
                )
                .label(span, format!("looked for {}", path.display()))
                .with_help("paths are relative to the file that names them"),
            );
            None
        }
    }
}

/// Join and normalise `a/b/../c` without touching the disk.
pub fn lexical_join(dir: &Path, rel: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    let joined = if rel.is_absolute() {
        rel.to_path_buf()
    } else {
        dir.join(rel)
    };
    for c in joined.components() {
        match c {
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            Component::CurDir => {}
            other => out.push(other.as_os_str()),
        }
    }
    out
}

/// A `--set PATH=VALUE` override, parsed into its own source file.
#[derive(Clone, Debug)]
pub struct SetOverride {
    pub path: Vec<Ident>,
    pub value: Value,
}

/// Everything a check produced.
pub struct Checked {
    pub program: ir::Program,
    pub sources: SourceMap,
    pub diagnostics: Vec<Diagnostic>,
}

impl Checked {
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }
}

/// Declarations found at the top level of all files.
#[derive(Default)]
pub(crate) struct Decls<'t> {
    pub materials: Vec<&'t Block>,
    pub vehicles: Vec<&'t Block>,
    pub scenarios: Vec<&'t Block>,
    pub sweeps: Vec<&'t Block>,
    pub fixtures: Vec<&'t Block>,
    pub dispersions: Vec<&'t Block>,
}

/// A block of another kind that a reference may name by mistake: its kind, its blocks, the
/// label and help of the `vdl::reference::kind` diagnostic (`None`: "this names a KIND", no
/// help).
pub(crate) struct OtherKind<'a, 't> {
    pub kind: &'static str,
    pub blocks: &'a [&'t Block],
    pub label: Option<&'static str>,
    pub help: Option<&'static str>,
}

/// A reference by name (`vehicle = NAME`, `scenario = NAME`, `fixture = NAME`): the index in
/// `blocks` (the declarations of `kind`) of the block `v` names, or a diagnostic at `v`: not
/// a name (`vdl::type::mismatch`), the name of a block of one of the `others` kinds
/// (`vdl::reference::kind`), or unknown (`vdl::reference::unknown`, with a "did you mean").
pub(crate) fn reference(
    cx: &mut Cx,
    v: &Value,
    kind: &str,
    blocks: &[&Block],
    others: &[OtherKind],
) -> Option<usize> {
    let ValueKind::Name(id) = &v.kind else {
        cx.push(
            Diagnostic::error(
                "vdl::type::mismatch",
                format!("expected a {kind} name, found {}", v.describe()),
            )
            .label(v.span, format!("should name a `{kind}`")),
        );
        return None;
    };
    let named = |b: &&Block| b.name.as_ref().is_some_and(|n| n.name == id.name);
    if let Some(i) = blocks.iter().position(named) {
        return Some(i);
    }
    let d = match others.iter().find(|o| o.blocks.iter().any(named)) {
        Some(o) => {
            let d = Diagnostic::error(
                "vdl::reference::kind",
                format!("`{}` is a {}, not a {kind}", id.name, o.kind),
            )
            .label(
                id.span,
                o.label
                    .map_or_else(|| format!("this names a {}", o.kind), str::to_string),
            );
            match o.help {
                Some(h) => d.with_help(h),
                None => d,
            }
        }
        None => {
            let d = Diagnostic::error(
                "vdl::reference::unknown",
                format!("no {kind} named `{}`", id.name),
            )
            .label(id.span, format!("unknown {kind}"));
            match did_you_mean(
                &id.name,
                blocks
                    .iter()
                    .filter_map(|b| b.name.as_ref().map(|n| n.name.as_str())),
            ) {
                Some(s) => d.with_help(format!("did you mean `{s}`?")),
                None => d,
            }
        }
    };
    cx.push(d);
    None
}

pub const TOP_LEVEL_KINDS: &[&str] = &[
    "material",
    "vehicle",
    "scenario",
    "sweep",
    "fixture",
    "dispersion",
];

/// Check the given root files with `--set` overrides (each `PATH=VALUE`).
pub fn check_files(roots: &[PathBuf], sets: &[String], loader: &dyn Loader) -> Checked {
    check_files_only(roots, sets, None, loader)
}

/// Check only what one scenario needs: the materials and that scenario (with its vehicle),
/// with `--set` overrides; other vehicles, scenarios and the sweeps are not checked, so an
/// override that only fits this scenario's vehicle is no error elsewhere. A sweep checks
/// each of its cases this way.
pub fn check_scenario_files(
    roots: &[PathBuf],
    sets: &[String],
    scenario: &str,
    loader: &dyn Loader,
) -> Checked {
    check_files_only(roots, sets, Some(scenario), loader)
}

fn check_files_only(
    roots: &[PathBuf],
    sets: &[String],
    only_scenario: Option<&str>,
    loader: &dyn Loader,
) -> Checked {
    let mut cx = Cx {
        sources: SourceMap::new(),
        diags: Vec::new(),
        loader,
    };
    let mut trees: Vec<SourceTree> = Vec::new();
    for root in roots {
        load_recursive(&mut cx, &mut trees, root.clone(), None, &mut Vec::new());
    }
    let overrides = parse_sets(&mut cx, sets);
    let program = if cx.has_syntax_errors() {
        ir::Program::default()
    } else {
        check_trees(&mut cx, &trees, &overrides, only_scenario)
    };
    let mut diagnostics = std::mem::take(&mut cx.diags);
    dedup(&mut diagnostics);
    Checked {
        program,
        sources: cx.sources,
        diagnostics,
    }
}

/// Check one in-memory source (for tests and the fuzzer); imports go through `loader`.
pub fn check_source(name: &str, text: &str, loader: &dyn Loader) -> Checked {
    let mut cx = Cx {
        sources: SourceMap::new(),
        diags: Vec::new(),
        loader,
    };
    let id = cx.sources.add(PathBuf::from(name), name.to_string(), text);
    let (tree, errors) = parse_file(id, text);
    push_parse_errors(&mut cx, errors);
    let mut trees = Vec::new();
    let imports = imports_of(&tree);
    let mut stack = vec![PathBuf::from(name)];
    for (path, span) in imports {
        resolve_import(&mut cx, &mut trees, &path, span, &mut stack);
    }
    trees.push(tree);
    let program = if cx.has_syntax_errors() {
        ir::Program::default()
    } else {
        check_trees(&mut cx, &trees, &[], None)
    };
    let mut diagnostics = std::mem::take(&mut cx.diags);
    dedup(&mut diagnostics);
    Checked {
        program,
        sources: cx.sources,
        diagnostics,
    }
}

fn dedup(diags: &mut Vec<Diagnostic>) {
    let mut seen = std::collections::HashSet::new();
    diags.retain(|d| seen.insert(d.clone()));
}

/// Turn syntax errors into diagnostics (also used by `fmt`).
pub fn push_parse_errors_pub(cx: &mut Cx, errors: Vec<crate::syntax::ParseError>) {
    push_parse_errors(cx, errors);
}

fn push_parse_errors(cx: &mut Cx, errors: Vec<crate::syntax::ParseError>) {
    for e in errors {
        let mut d = Diagnostic::error(
            "vdl::syntax",
            format!("expected {}, found {}", e.expected, e.found),
        )
        .label(e.span, format!("expected {}", e.expected));
        if let Some((span, msg)) = e.context {
            d = d.label(span, msg);
        }
        cx.push(d);
    }
}

fn imports_of(tree: &SourceTree) -> Vec<(String, Span)> {
    tree.body
        .entries
        .iter()
        .filter_map(|e| match &e.kind {
            EntryKind::Import { path, path_span } => Some((path.clone(), *path_span)),
            _ => None,
        })
        .collect()
}

/// Load a file and, depth first, its imports (each once). `stack` holds the chain of files
/// being loaded, for cycle detection.
fn load_recursive(
    cx: &mut Cx,
    trees: &mut Vec<SourceTree>,
    path: PathBuf,
    from: Option<Span>,
    stack: &mut Vec<PathBuf>,
) {
    if cx.sources.find(&path).is_some() {
        return;
    }
    let text = match stdlib_text(&path) {
        Some(t) => t.to_string(),
        None => match cx.loader.read(&path) {
            Ok(t) => t,
            Err(e) => {
                let d = Diagnostic::error(
                    if from.is_some() {
                        "vdl::import::missing"
                    } else {
                        "vdl::file::unreadable"
                    },
                    format!("cannot read `{}`: {e}", path.display()),
                );
                cx.push(match from {
                    Some(span) => d.label(span, "imported here"),
                    None => d,
                });
                return;
            }
        },
    };
    let name = path.display().to_string();
    let id = cx.sources.add(path.clone(), name, text.as_str());
    let (tree, errors) = parse_file(id, &text);
    push_parse_errors(cx, errors);
    stack.push(path);
    for (p, span) in imports_of(&tree) {
        resolve_import(cx, trees, &p, span, stack);
    }
    stack.pop();
    trees.push(tree);
}

fn stdlib_text(path: &Path) -> Option<&'static str> {
    STDLIB
        .iter()
        .find(|(p, _)| Path::new(p) == path)
        .map(|(_, t)| *t)
}

fn resolve_import(
    cx: &mut Cx,
    trees: &mut Vec<SourceTree>,
    written: &str,
    span: Span,
    stack: &mut Vec<PathBuf>,
) {
    let path = if written.starts_with("std/") {
        if stdlib_text(Path::new(written)).is_none() {
            let names = STDLIB.iter().map(|(p, _)| *p);
            let mut d = Diagnostic::error(
                "vdl::import::missing",
                format!("no standard library file `{written}`"),
            )
            .label(span, "not in the standard library");
            if let Some(s) = did_you_mean(written, names) {
                d = d.with_help(format!("did you mean `{s}`?"));
            }
            cx.push(d);
            return;
        }
        PathBuf::from(written)
    } else {
        lexical_join(&cx.dir_of(span), Path::new(written))
    };
    if let Some(pos) = stack.iter().position(|p| *p == path) {
        let chain: Vec<String> = stack[pos..]
            .iter()
            .chain(std::iter::once(&path))
            .map(|p| p.display().to_string())
            .collect();
        cx.push(
            Diagnostic::error(
                "vdl::import::cycle",
                format!("import cycle: {}", chain.join(" -> ")),
            )
            .label(span, "this import closes the cycle")
            .with_help("remove one of the imports; shared declarations can live in a third file"),
        );
        return;
    }
    if stdlib_text(&path).is_none() && !cx.loader.exists(&path) {
        cx.push(
            Diagnostic::error("vdl::import::missing", format!("imported file `{written}` does not exist"))
                .label(span, format!("looked for {}", path.display()))
                .with_help("import paths are relative to the importing file; `std/...` names the standard library"),
        );
        return;
    }
    load_recursive(cx, trees, path, Some(span), stack);
}

fn parse_sets(cx: &mut Cx, sets: &[String]) -> Vec<SetOverride> {
    let mut out = Vec::new();
    for (k, s) in sets.iter().enumerate() {
        let name = format!("<--set {}>", k + 1);
        let id: FileId = cx.sources.add(PathBuf::from(&name), name, s.as_str());
        let (tree, errors) = parse_file(id, s);
        let had_errors = !errors.is_empty();
        push_parse_errors(cx, errors);
        if had_errors {
            continue;
        }
        match tree.body.entries.as_slice() {
            [e] => match &e.kind {
                EntryKind::Assign(a) => out.push(SetOverride {
                    path: a.path.clone(),
                    value: a.value.clone(),
                }),
                _ => cx.push(set_shape_error(e.span)),
            },
            _ => cx.push(set_shape_error(Span::new(id, 0, s.len()))),
        }
    }
    out
}

fn set_shape_error(span: Span) -> Diagnostic {
    Diagnostic::error("vdl::override::syntax", "`--set` takes one `PATH=VALUE`")
        .label(span, "not of the form PATH=VALUE")
        .with_help("for example --set 'fins.thickness=0.6 mm'")
}

/// Check the declarations; with `only_scenario`, just the materials and that scenario.
fn check_trees(
    cx: &mut Cx,
    trees: &[SourceTree],
    sets: &[SetOverride],
    only_scenario: Option<&str>,
) -> ir::Program {
    let mut decls = Decls::default();
    let mut names: HashMap<(String, String), Span> = HashMap::new();
    for tree in trees {
        for e in &tree.body.entries {
            match &e.kind {
                EntryKind::Import { .. } => {}
                EntryKind::Assign(a) => cx.push(
                    Diagnostic::error(
                        "vdl::toplevel",
                        format!(
                            "`{}` cannot be set at the top level of a file",
                            a.path_string()
                        ),
                    )
                    .label(a.path_span(), "outside any block")
                    .with_help(
                        "fields belong inside a `vehicle`, `scenario`, `sweep` or `material` block",
                    ),
                ),
                EntryKind::Block(b) => {
                    let kind = b.kind.name.as_str();
                    let Some(name) = &b.name else {
                        if TOP_LEVEL_KINDS.contains(&kind) {
                            cx.push(
                                Diagnostic::error(
                                    "vdl::name::missing",
                                    format!("a `{kind}` needs a name"),
                                )
                                .label(b.header, format!("write `{kind} NAME {{`")),
                            );
                        } else {
                            cx.push(unknown_top(b));
                        }
                        continue;
                    };
                    if !TOP_LEVEL_KINDS.contains(&kind) {
                        cx.push(unknown_top(b));
                        continue;
                    }
                    let key = (kind.to_string(), name.name.clone());
                    if let Some(first) = names.get(&key) {
                        cx.push(
                            Diagnostic::error(
                                "vdl::duplicate",
                                format!("{kind} `{}` is declared twice", name.name),
                            )
                            .label(name.span, "declared again here")
                            .label(*first, "first declared here"),
                        );
                        continue;
                    }
                    names.insert(key, name.span);
                    match kind {
                        "material" => decls.materials.push(b),
                        "vehicle" => decls.vehicles.push(b),
                        "scenario" => decls.scenarios.push(b),
                        "fixture" => decls.fixtures.push(b),
                        "dispersion" => decls.dispersions.push(b),
                        _ => decls.sweeps.push(b),
                    }
                }
            }
        }
    }
    let mut program = ir::Program::default();
    for b in &decls.materials {
        if let Some(m) = vehicle::check_material(cx, b) {
            program.materials.push(m);
        }
    }
    let vehicle_sets: Vec<&SetOverride> = sets
        .iter()
        .filter(|s| !overrides::is_scenario_path(&s.path))
        .collect();
    let wanted =
        |b: &Block| only_scenario.is_none_or(|n| b.name.as_ref().is_some_and(|x| x.name == n));
    for b in decls.vehicles.iter().filter(|_| only_scenario.is_none()) {
        let patched = patch(cx, b, &vehicle_sets);
        if let Some(v) = vehicle::check_vehicle(cx, &patched, &program.materials) {
            program.vehicles.push(v);
        }
    }
    for b in decls.fixtures.iter().filter(|_| only_scenario.is_none()) {
        if let Some(x) = fixture::check_fixture(cx, b, &program.materials) {
            program.fixtures.push(x);
        }
    }
    for b in decls.scenarios.iter().filter(|b| wanted(b)) {
        if fixture::is_tunnel_scenario(b) {
            if let Some(t) = fixture::check_tunnel_test(cx, b, &decls, &program.materials, sets) {
                program.tunnel_tests.push(t);
            }
        } else if let Some(s) = scenario::check_scenario(cx, b, &decls, &program.materials, sets) {
            program.scenarios.push(s);
        }
    }
    for b in decls.sweeps.iter().filter(|_| only_scenario.is_none()) {
        if let Some(s) = sweep::check_sweep(cx, b, &decls, &program, sets) {
            program.sweeps.push(s);
        }
    }
    for b in decls.dispersions.iter().filter(|_| only_scenario.is_none()) {
        if let Some(d) = dispersion::check_dispersion(cx, b, &decls, &program, sets) {
            program.dispersions.push(d);
        }
    }
    program
}

fn unknown_top(b: &Block) -> Diagnostic {
    let mut d = Diagnostic::error(
        "vdl::block::unknown",
        format!("unknown top-level block `{}`", b.kind.name),
    )
    .label(
        b.kind.span,
        "expected `material`, `vehicle`, `scenario`, `sweep`, `fixture` or `dispersion`",
    );
    if let Some(s) = did_you_mean(&b.kind.name, TOP_LEVEL_KINDS.iter().copied()) {
        d = d.with_help(format!("did you mean `{s}`?"));
    }
    d
}

/// A copy of a block with overrides applied; override errors are reported.
pub(crate) fn patch(cx: &mut Cx, b: &Block, sets: &[&SetOverride]) -> Block {
    let mut out = b.clone();
    for s in sets {
        if let Err(d) = overrides::apply(&mut out.body, &s.path, &s.value) {
            cx.push(d);
        }
    }
    out
}
