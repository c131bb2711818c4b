//! The README's field table against the checker (issue 9, defect 10): every field, required
//! field and sub-block the checker reads for a block is in the table row of that block, and
//! everything the row names is a field, block or keyword the checker reads. The checker's
//! schema is recorded while it checks the repository's files and two fixtures that use
//! every block and variant (`flexflight::check::fields::record_schema`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

use flexflight::check::fields::record_schema;
use flexflight::check::{DiskLoader, MemoryLoader, check_files};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn readme() -> String {
    std::fs::read_to_string(repo("docs/language.md")).unwrap()
}

/// What the README documents for one block kind.
#[derive(Default, Debug)]
struct Documented {
    /// Field names, sub-block kinds and keyword values written for the block.
    names: BTreeSet<String>,
    /// Names in bold (required).
    bold: BTreeSet<String>,
    /// Sub-blocks written as `kind { ... }` or `kind NAME`.
    blocks: BTreeSet<String>,
}

fn is_ident(s: &str) -> bool {
    let mut c = s.chars();
    c.next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// The leading identifier of a backticked token (`x`, `x = ...`), if the token names a
/// field or a keyword (not a call such as `fin_point(...)`, a list, a number or a
/// placeholder in capitals).
fn leading_name(token: &str) -> Option<&str> {
    let end = token
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(token.len());
    let (name, rest) = token.split_at(end);
    let placeholder = name.len() > 1 && name.chars().all(|c| c.is_ascii_uppercase());
    (is_ident(name) && !placeholder && (rest.is_empty() || rest.starts_with(" ="))).then_some(name)
}

/// Parses `kind { a, b, sub {...}, sub2 NAME {...} }`: the kind, its fields (none when the
/// list is elided with `...`) and its sub-blocks.
fn brace_block(token: &str) -> Option<(String, Vec<String>, Vec<String>)> {
    let open = token.find(" {")?;
    let kind = &token[..open];
    if !is_ident(kind) || !token.ends_with('}') {
        return None;
    }
    let inner = &token[open + 2..token.len() - 1];
    // Remove nested `{...}` groups, remembering the words before them as sub-blocks.
    let mut flat = String::new();
    let mut subs = Vec::new();
    let mut depth = 0;
    for ch in inner.chars() {
        match ch {
            '{' => {
                if depth == 0 {
                    let words: Vec<&str> = flat.split_whitespace().collect();
                    let sub = match words.as_slice() {
                        [.., s, "NAME"] => Some(*s),
                        [.., s] => Some(*s),
                        [] => None,
                    };
                    if let Some(s) = sub {
                        subs.push(s.trim_matches(',').to_string());
                        let cut = flat.rfind(s).unwrap_or(flat.len());
                        flat.truncate(cut);
                    }
                }
                depth += 1;
            }
            '}' => depth -= 1,
            c if depth == 0 => flat.push(c),
            _ => {}
        }
    }
    let fields = if flat.contains("...") {
        Vec::new()
    } else {
        flat.split([',', ' '])
            .map(str::trim)
            .filter(|w| is_ident(w))
            .map(str::to_string)
            .collect()
    };
    Some((kind.to_string(), fields, subs))
}

/// The field table of the README (`| block | fields |` rows under "The vehicle description
/// language"), per block kind, with the blocks written inline (`gravity { ... }`,
/// `sine NAME (...)`).
fn readme_fields() -> BTreeMap<String, Documented> {
    let text = readme();
    // The field table: the block of `|` rows after "Reference of blocks and fields".
    let start = text.find("Reference of blocks and fields").unwrap();
    let table = start + text[start..].find("\n|").unwrap() + 1;
    let end = table + text[table..].find("\n\n").unwrap_or(text.len() - table);
    let mut out: BTreeMap<String, Documented> = BTreeMap::new();
    for line in text[start..end].lines() {
        let cells: Vec<&str> = line.split(" | ").collect();
        if !line.starts_with("| `") || cells.len() < 2 {
            continue;
        }
        let head = cells[0].trim_start_matches("| `");
        let kind = head.split(['`', ' ']).next().unwrap().to_string();
        let cell = cells[1..].join(" | ");
        let cell = cell.trim_end_matches(" |");
        // Walk the cell: backticked tokens, bold, and parenthesised groups in the prose.
        let mut pending: Vec<String> = Vec::new(); // `x NAME` tokens waiting for their group
        let mut depth = 0usize;
        let mut group_owner: Option<(usize, Vec<String>)> = None;
        let bytes: Vec<char> = cell.chars().collect();
        let mut i = 0;
        let mut last_was_name_block = false;
        while i < bytes.len() {
            let c = bytes[i];
            if c == '`' {
                let close = bytes[i + 1..].iter().position(|&c| c == '`').unwrap() + i + 1;
                let token: String = bytes[i + 1..close].iter().collect();
                let bold = i >= 2
                    && bytes[i - 1] == '*'
                    && bytes[i - 2] == '*'
                    && bytes.get(close + 1) == Some(&'*');
                i = close + 1;
                let owners: Vec<String> = match &group_owner {
                    Some((_, o)) => o.clone(),
                    None => vec![kind.clone()],
                };
                if let Some((sub, fields, subs)) = brace_block(&token) {
                    out.entry(kind.clone())
                        .or_default()
                        .blocks
                        .insert(sub.clone());
                    let d = out.entry(sub).or_default();
                    d.names.extend(fields);
                    d.blocks.extend(subs);
                    last_was_name_block = false;
                    continue;
                }
                if let Some(sub) = token.strip_suffix(" NAME").filter(|s| is_ident(s)) {
                    out.entry(kind.clone())
                        .or_default()
                        .blocks
                        .insert(sub.into());
                    if !last_was_name_block {
                        pending.clear();
                    }
                    pending.push(sub.to_string());
                    last_was_name_block = true;
                    continue;
                }
                last_was_name_block = false;
                // A token inside parentheses that no `kind NAME` group owns is a default, a
                // value or prose (`(`stop` \| `clamp`)`, `(false: with `true` ...)`), not a field.
                if depth > 0 && group_owner.is_none() {
                    continue;
                }
                if let Some(name) = leading_name(&token) {
                    for o in &owners {
                        let d = out.entry(o.clone()).or_default();
                        d.names.insert(name.to_string());
                        if bold {
                            d.bold.insert(name.to_string());
                        }
                    }
                }
                continue;
            }
            match c {
                '(' => {
                    depth += 1;
                    if depth == 1 && !pending.is_empty() {
                        group_owner = Some((depth, pending.clone()));
                    }
                }
                ')' => {
                    if group_owner.as_ref().is_some_and(|(d, _)| *d == depth) {
                        group_owner = None;
                        pending.clear();
                    }
                    depth = depth.saturating_sub(1);
                }
                ',' | ' ' | '*' => {}
                _ => last_was_name_block = false,
            }
            i += 1;
        }
    }
    out
}

/// What the checker reads, per block kind: the union over several programs that together
/// use every block and every variant of it (all of the repository's `.vdl` files and the
/// fixtures below).
#[derive(Default, Debug)]
struct Read {
    fields: BTreeSet<String>,
    required: BTreeSet<String>,
    blocks: BTreeSet<String>,
}

/// Vehicles and scenarios with every variant the repository's files do not show: FE
/// files in each format, a swept trailing edge, table aerodynamics, thrust, Mach and
/// position initial states, every stimulus and a zipped sweep. Values need not make sense
/// (missing files are diagnostics): only the fields read matter.
const FIXTURE: &str = r#"
material m { E = 70 GPa; nu = 0.3; rho = 2700 kg/m^3; yield = 1 MPa; ultimate = 2 MPa }
vehicle mm {
  material = m
  origin = nearest((0, 0, 0) m)
  structure { files { format = matrix_market; mass = "m.mtx"; stiffness = "k.mtx"; nodes = "n.csv"; elements = "e.csv"; dof_order = [u, v, w, rx, ry, rz]; coordinates_unit = mm } }
  key_nodes { body = node(1); nozzle = node(2) }
  motor mo { curve = "c.eng"; position = (-1, 0, 0) m; length = 0.5 m; diameter = 50 mm; propellant_mass = 1 kg; total_mass = 2 kg }
  modes { indices = [1, 2]; band = [1 Hz, 100 Hz]; fixity = none; damping = 0.01 }
  aero { source = tables; body_table = "b.csv"; fin_table = "f.csv"; out_of_range = clamp; reference_area = 1 m^2; reference_length = 1 m; reference_point = (0, 0, 0) m }
  forces {
    gravity { enabled = true; altitude_correction = false }
    thrust { enabled = true; curve = "c.eng"; offset = (0, 0, 0) m; misalignment = (0, 0, 0) rad }
    body_aero { enabled = false; rate_terms = false }
    fin_aero { enabled = false; distribution = uniform; leeward_reduction = false; stress_limit = 0.5; incidence = load_weighted; model = key_node }
  }
}
vehicle op4 {
  material = m
  origin = node(1)
  structure { files { format = op4; matrices = "a.op4"; nodes = "b.bdf"; mass_matrix = "MAA"; stiffness_matrix = "KAA" } }
  key_nodes { body = node(1) }
  modes { body_bending = 1 }
  aero { source = builtin; reference_point = (0, 0, 0) m }
  forces { gravity {} }
}
vehicle dmig {
  material = m
  origin = node(1)
  structure { files { format = dmig; matrices = "a.bdf"; nodes = "a.bdf" } }
  key_nodes { body = node(1) }
  modes { body_bending = 1 }
  aero { source = builtin; reference_point = (0, 0, 0) m }
  forces { gravity {} }
}
vehicle gen {
  material = m
  origin = node(1)
  structure {
    generate {
      body { length = 1 m; diameter = 0.1 m; wall = 2 mm; nose_length = 0.2 m; nose_shape = ogive; elements = 10; theory = timoshenko }
      fin_mesh { span_elements = 2; chord_elements = 2 }
      point_mass p { position = (-0.5, 0, 0) m; mass = 1 kg; inertia = (0.1, 0.1, 0.1) kg*m^2 }
      distributed_mass d { from = -0.1 m; to = -0.5 m; mass = 1 kg }
    }
  }
  fins { count = 3; span = 0.1 m; root_chord = 0.2 m; tip_chord = 0.1 m; leading_edge_sweep = 30 deg; thickness = 1 mm; cross_section = rounded; cant = 1 deg; angles = [0 deg, 120 deg, 240 deg]; root_trailing_edge = -1 m; material = m }
  key_nodes { body = node(1); fins = [node(1), node(2), node(3)] }
  modes { fin_flap = 1; fin_twist = 1; body_bending = 1 }
  aero { source = builtin; reference_point = (0, 0, 0) m }
  forces { gravity {} }
}
scenario a {
  vehicle = gen
  with { fins.thickness = 2 mm }
  initial { mach = 0.5; angular_velocity = (0, 0, 0) rad/s; attitude = quaternion(1, 0, 0, 0); position = (0, 0, -100) m }
  stimuli {
    gust g { start = 1 s; duration = 0.1 s; velocity = (0, 0, 1) m/s; frame = inertial }
    one_minus_cosine c { start = 1 s; duration = 0.1 s; velocity = (0, 0, 1) m/s; frame = body }
    sine s { start = 1 s; duration = 1 s; amplitude = (0, 0, 1) m/s; frequency = 2 Hz; frame = body }
    turbulence t { model = von_karman; intensity = 1 m/s; scale_length = 100 m; seed = 1; start = 0 s; duration = 1 s }
  }
  run { stop_time = 1 s; integrator = rk4; rtol = 1e-6; atol = 1e-9; step = 1 ms; min_step = 1e-9 s; output_interval = 1 ms; stop_on_ground = false; max_alpha = 10 deg; max_deformation = 1 m }
}
scenario b {
  vehicle = gen
  initial { velocity = (10, 0, 0) m/s; attitude = euler(0 deg, 0 deg, 0 deg); altitude = 1 km }
  run { stop_time = 1 s; integrator = dopri5 }
}
scenario c {
  vehicle = gen
  launch { site_altitude = 100 m; rail_length = 3 m; elevation = 85 deg; heading = 10 deg }
  wind { speed = 5 m/s; direction = 270 deg; reference_height = 10 m; exponent = 0.14 }
  parachute p { cd_area = 1 m^2; trigger = apogee; lag = 1 s }
  run { stop_time = 1 s }
}
sweep z { scenario = a; analysis = planar_unpinned; zip { fins.thickness = [1 mm, 2 mm]; run.stop_time = [1 s, 2 s] } }
sweep y { scenario = a; analysis = linear3d; grid { fins.thickness = range(1 mm, 2 mm, count = 2) } }
"#;

/// A second fixture: the variants that exclude those above (trailing-edge sweep instead of
/// leading-edge, each planar analysis and `run`).
const FIXTURE_2: &str = r#"
material m { E = 70 GPa; nu = 0.3; rho = 2700 kg/m^3 }
vehicle gen {
  material = m
  origin = node(1)
  structure { generate { body { length = 1 m; diameter = 0.1 m; wall = 2 mm; nose_length = 0.2 m; nose_shape = power(0.5); elements = 10; theory = euler_bernoulli } } }
  fins { count = 3; span = 0.1 m; root_chord = 0.2 m; tip_chord = 0.1 m; trailing_edge_sweep = 0 deg; thickness = 1 mm }
  motor mo { designation = "Cesaroni M1670"; position = (-1, 0, 0) m; expect_unusual = true }
  key_nodes { body = node(1); fins = fin_point(span = 0.5, chord = 0.25) }
  modes { fin_flap = per_fin; fin_twist = per_fin; fixity = origin }
  aero { source = builtin; out_of_range = stop; reference_point = (0, 0, 0) m }
  forces { body_aero { rate_terms = true }; fin_aero { distribution = theory; incidence = key_node; model = key_node } }
}
scenario a {
  vehicle = gen
  initial { velocity = (10, 0, 0) m/s; altitude = 1 km }
  run { stop_time = 1 s }
}
scenario w {
  vehicle = gen
  launch { site_altitude = 0 m; rail_length = 1 m; elevation = 90 deg }
  wind { profile = [at(0 m, 2 m/s, 270 deg), at(500 m, 6 m/s, 280 deg)] }
  run { stop_time = 1 s }
}
vehicle ff {
  material = m
  origin = node(1)
  structure { generate { body { length = 1 m; diameter = 0.1 m; wall = 2 mm; elements = 10; transition { fore_station = -0.3 m; length = 0.1 m; fore_diameter = 0.1 m; aft_diameter = 0.08 m; shape = ogive }; launch_lug { station = -0.5 m; length = 30 mm; outer_diameter = 6 mm; inner_diameter = 4 mm; mass = 1 g }; rail_button { station = -0.7 m; outer_diameter = 10 mm; height = 8 mm; inner_diameter = 6 mm; inner_height = 3 mm; mass = 2 g } } } }
  fins { count = 3; planform = freeform; points = [(0, 0) mm, (100, 100) mm, (150, 100) mm, (200, 0) mm]; thickness = 1 mm }
  key_nodes { body = node(1); fins = fin_point(span = 0.5, chord = 0.25) }
  modes { fin_flap = per_fin }
  aero { source = builtin; finish = smooth_paint; reference_point = (0, 0, 0) m }
  forces { gravity {} }
}
sweep p { scenario = a; analysis = planar_pinned; grid { run.stop_time = [1 s] } }
sweep r { scenario = a; analysis = run; grid { run.stop_time = [1 s] } }
"#;

/// A third fixture: wind-tunnel fixtures with the surface variants the AGARD 445.6 example
/// does not show (a flat plate, leading- and trailing-edge sweeps, a swept grain, no mass)
/// and a tunnel scenario with overrides and listed speeds.
const FIXTURE_3: &str = r#"
material o { E = 10 GPa; E2 = 1 GPa; G12 = 0.5 GPa; nu = 0.3; rho = 500 kg/m^3 }
fixture f {
  material = o
  surface { span = 0.5 m; root_chord = 0.3 m; tip_chord = 0.2 m; leading_edge_sweep = 10 deg; thickness = 2 mm; grain = swept(10 deg) }
}
fixture g {
  material = o
  surface { span = 0.5 m; root_chord = 0.3 m; tip_chord = 0.2 m; trailing_edge_sweep = 0 deg; thickness = 2 mm }
  mesh { chord_elements = 4; span_elements = 4 }
  modes = 2
  spanwise_panels = 4
  reference_frequency = 100 rad/s
}
scenario t {
  fixture = g
  with { surface.thickness = 3 mm }
  tunnel { mach = 0.3; density = 1.2 kg/m^3; speeds = [50 m/s, 60 m/s] }
}
"#;

fn checker_fields() -> (BTreeMap<String, Read>, BTreeSet<String>) {
    let mut read: BTreeMap<String, Read> = BTreeMap::new();
    let mut keywords = BTreeSet::new();
    let mut add = |checked: &flexflight::check::Checked,
                   rec: flexflight::check::fields::SchemaRecord| {
        for b in rec.blocks {
            let header = checked.sources.slice(b.header);
            let kind = header.split_whitespace().next().unwrap_or("").to_string();
            let r = read.entry(kind).or_default();
            r.fields.extend(b.fields.iter().map(|s| s.to_string()));
            r.required.extend(b.required.iter().map(|s| s.to_string()));
            r.blocks.extend(b.blocks.iter().map(|s| s.to_string()));
        }
        keywords.extend(rec.keywords.iter().map(|s| s.to_string()));
    };
    for f in [
        "vehicles/sphads1.vdl",
        "vehicles/sphads1a.vdl",
        "examples/thesis/section_6_5.vdl",
        "examples/free_tumble.vdl",
        "examples/tube_from_nastran.vdl",
        "examples/agard445/agard445.vdl",
        "examples/hpr_k1000/hpr_k1000.vdl",
    ] {
        let (checked, rec) = record_schema(|| check_files(&[repo(f)], &[], &DiskLoader));
        add(&checked, rec);
    }
    for (k, text) in [FIXTURE, FIXTURE_2, FIXTURE_3].iter().enumerate() {
        let path = PathBuf::from(format!("/fixture{k}.vdl"));
        let loader = MemoryLoader {
            files: [(path.clone(), text.to_string())].into_iter().collect(),
        };
        let (checked, rec) = record_schema(|| check_files(&[path], &[], &loader));
        // The fixtures are written against the README: an unknown field in them is a
        // README field the checker does not read.
        let unknown: Vec<String> = checked
            .diagnostics
            .iter()
            .filter(|d| matches!(d.code, "vdl::field::unknown" | "vdl::block::unknown"))
            .map(|d| d.message.clone())
            .collect();
        assert!(unknown.is_empty(), "fixture {k}: {unknown:?}");
        add(&checked, rec);
    }
    (read, keywords)
}

#[test]
fn the_readme_field_table_lists_exactly_what_the_checker_reads() {
    let doc = readme_fields();
    let (read, keywords) = checker_fields();
    assert!(
        read.len() > 20,
        "the recording found only {} blocks",
        read.len()
    );
    let mut problems = Vec::new();
    for (kind, r) in &read {
        let Some(d) = doc.get(kind) else {
            problems.push(format!(
                "block `{kind}` is read by the checker but not in the README"
            ));
            continue;
        };
        for f in &r.fields {
            if !d.names.contains(f) {
                problems.push(format!("`{kind}` reads field `{f}`: not in the README"));
            }
        }
        for b in &r.blocks {
            if !(d.blocks.contains(b) || d.names.contains(b)) {
                problems.push(format!("`{kind}` reads block `{b}`: not in the README"));
            }
        }
        for f in &r.required {
            if !d.bold.contains(f) {
                problems.push(format!("`{kind}` requires `{f}`: not bold in the README"));
            }
        }
        for n in &d.names {
            let known = r.fields.contains(n) || r.blocks.contains(n) || keywords.contains(n);
            if !known {
                problems.push(format!(
                    "the README lists `{n}` for `{kind}`: not a field, block or keyword the checker reads there"
                ));
            }
        }
        for n in &d.bold {
            if !(r.fields.contains(n) || r.blocks.contains(n)) {
                problems.push(format!(
                    "the README makes `{n}` of `{kind}` required: not a field"
                ));
            }
        }
    }
    // `with`, `grid` and `zip` hold override paths (`PATH = value`), checked by
    // `check::overrides` and `check::sweep`, not by the field reader this test records.
    const OVERRIDE_BLOCKS: [&str; 3] = ["with", "grid", "zip"];
    for kind in doc.keys() {
        if !read.contains_key(kind) && !OVERRIDE_BLOCKS.contains(&kind.as_str()) {
            problems.push(format!(
                "the README documents block `{kind}`, which the checker never reads"
            ));
        }
    }
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn the_readme_table_parser_reads_inline_blocks_and_groups() {
    // The parser itself, on rows written like the README's.
    let b = brace_block("gravity { enabled, altitude_correction }").unwrap();
    assert_eq!(b.0, "gravity");
    assert_eq!(b.1, ["enabled", "altitude_correction"]);
    let g = brace_block("generate { body {...} point_mass NAME {...} }").unwrap();
    assert_eq!(
        (g.1.len(), g.2.clone()),
        (0, vec!["body".to_string(), "point_mass".into()])
    );
    assert_eq!(leading_name("indices = [..]"), Some("indices"));
    assert_eq!(leading_name("fin_point(span = f, chord = f)"), None);
    assert_eq!(leading_name("E"), Some("E"));
    assert_eq!(leading_name("PATH = [values]"), None);
}
