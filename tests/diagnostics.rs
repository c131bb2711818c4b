//! Snapshot tests of rendered diagnostics, in the style of gleam's `assert_error!`: every
//! case is a small bad VDL source; the snapshot holds the source, the list of diagnostic
//! codes and the rendering (fixed theme, width 80), so a reviewer sees at once whether the
//! message, the location and the help are right. Each case also asserts the code it is
//! about, so a case cannot silently drift to a different error.

use std::path::PathBuf;

use flexflight::check::{Checked, DiskLoader, MemoryLoader, check_files, check_source};
use flexflight::diagnostics::{RenderOptions, render};

/// A small valid vehicle; cases edit it with [`edit`].
const VEHICLE: &str = r#"import "std/materials.vdl"

vehicle v {
  material = aluminium_thesis
  origin = node(1)
  structure {
    generate {
      body {
        length = 2 m
        diameter = 100 mm
        wall = 2 mm
        elements = 10
      }
    }
  }
  key_nodes {
    body = nearest((-1, 0, 0) m)
  }
  modes {
    body_bending = 2
  }
  aero {
    source = builtin
    reference_point = (-1, 0, 0) m
  }
  forces {
    gravity {}
  }
}
"#;

/// The same vehicle with four fins (and their key nodes and modes).
const FINNED: &str = r#"import "std/materials.vdl"

vehicle v {
  material = aluminium_thesis
  origin = node(1)
  structure {
    generate {
      body {
        length = 2 m
        diameter = 100 mm
        wall = 2 mm
        elements = 10
      }
    }
  }
  fins {
    count = 4
    span = 100 mm
    root_chord = 200 mm
    tip_chord = 100 mm
    trailing_edge_sweep = 0 deg
    thickness = 1 mm
  }
  key_nodes {
    body = nearest((-1, 0, 0) m)
    fins = fin_point(span = 0.5, chord = 0.5)
  }
  modes {
    body_bending = 2
    fin_flap = per_fin
  }
  aero {
    source = builtin
    reference_point = (-1, 0, 0) m
  }
  forces {
    gravity {}
    fin_aero {}
  }
}
"#;

/// A valid scenario for the vehicle `v`; appended to [`VEHICLE`] or [`FINNED`].
const SCENARIO: &str = r#"
scenario s {
  vehicle = v
  initial {
    velocity = (200, 0, 0) m/s
    altitude = 5 km
  }
  run {
    stop_time = 10 s
  }
}
"#;

/// Replace the one occurrence of `from` in `base` by `to` (a test fails if the template
/// no longer contains `from`).
fn edit(base: &str, from: &str, to: &str) -> String {
    assert_eq!(
        base.matches(from).count(),
        1,
        "the template must contain `{from}` exactly once"
    );
    base.replacen(from, to, 1)
}

fn finned_scenario() -> String {
    format!("{FINNED}{SCENARIO}")
}

/// Render a checked result for a snapshot: source(s), codes, rendering.
fn report(sources: &[(&str, &str)], checked: &Checked) -> String {
    assert!(
        checked.has_errors(),
        "expected at least one error, got none"
    );
    let codes: Vec<&str> = checked.diagnostics.iter().map(|d| d.code).collect();
    let rendered = render(
        &checked.diagnostics,
        &checked.sources,
        RenderOptions::plain(80),
    );
    let mut out = String::new();
    for (name, text) in sources {
        out.push_str(&format!("----- SOURCE {name}\n{text}\n"));
    }
    out.push_str(&format!(
        "----- CODES\n{codes:?}\n----- RENDERED\n{rendered}"
    ));
    out
}

/// Check `src` (as `case.vdl`, with extra in-memory files), assert that `code` is among the
/// errors, and snapshot the report under the case name.
fn check_case(name: &str, code: &str, src: &str, files: &[(&str, &str)]) {
    let mut loader = MemoryLoader::default();
    for (p, t) in files {
        loader.files.insert(PathBuf::from(p), t.to_string());
    }
    let checked = check_source("case.vdl", src, &loader);
    let mut all = vec![("case.vdl", src)];
    all.extend(files.iter().filter(|(p, _)| p.ends_with(".vdl")).copied());
    let text = report(&all, &checked);
    assert!(
        checked.diagnostics.iter().any(|d| d.code == code),
        "expected a `{code}` diagnostic in case {name}:\n{text}"
    );
    insta::assert_snapshot!(name, text);
}

macro_rules! assert_error {
    ($name:ident, $code:literal, $src:expr) => {
        #[test]
        fn $name() {
            check_case(stringify!($name), $code, &$src, &[]);
        }
    };
    ($name:ident, $code:literal, $src:expr, files = [$(($p:literal, $t:expr)),* $(,)?]) => {
        #[test]
        fn $name() {
            check_case(stringify!($name), $code, &$src, &[$(($p, &$t)),*]);
        }
    };
}

#[test]
fn templates_are_valid() {
    for src in [
        VEHICLE.to_string(),
        FINNED.to_string(),
        format!("{VEHICLE}{SCENARIO}"),
        finned_scenario(),
    ] {
        let checked = check_source("case.vdl", &src, &MemoryLoader::default());
        assert!(
            checked.diagnostics.is_empty(),
            "template has diagnostics:\n{}",
            render(
                &checked.diagnostics,
                &checked.sources,
                RenderOptions::plain(80)
            )
        );
    }
}

// ---------------------------------------------------------------- syntax

const MATERIAL: &str = "material m {\n  E = 70 GPa\n  nu = 0.3\n  rho = 2700 kg/m^3\n}\n";

assert_error!(
    syntax_unclosed_block,
    "vdl::syntax",
    "material m {\n  E = 70 GPa\n  nu = 0.3\n  rho = 2700 kg/m^3\n"
);
assert_error!(
    syntax_missing_equals,
    "vdl::syntax",
    edit(MATERIAL, "E = 70 GPa", "E 70 GPa")
);
assert_error!(
    syntax_bad_number,
    "vdl::syntax",
    edit(MATERIAL, "nu = 0.3", "nu = 1.2.3")
);
assert_error!(
    syntax_unterminated_string,
    "vdl::syntax",
    format!("import \"std/materials.vdl\n\n{MATERIAL}")
);
assert_error!(
    syntax_stray_close_brace,
    "vdl::syntax",
    format!("{MATERIAL}}}\n")
);
assert_error!(
    syntax_bad_exponent,
    "vdl::syntax",
    edit(MATERIAL, "E = 70 GPa", "E = 7e GPa")
);
assert_error!(
    syntax_bad_exponent_sign,
    "vdl::syntax",
    edit(MATERIAL, "E = 70 GPa", "E = 7e+ GPa")
);
assert_error!(
    syntax_missing_value,
    "vdl::syntax",
    edit(MATERIAL, "nu = 0.3", "nu =")
);
assert_error!(
    syntax_two_entries_on_one_line,
    "vdl::syntax",
    edit(MATERIAL, "nu = 0.3\n  rho", "nu = 0.3 rho")
);
assert_error!(
    syntax_unclosed_list,
    "vdl::syntax",
    edit(
        FINNED,
        "    thickness = 1 mm\n",
        "    thickness = 1 mm\n    angles = [0 deg, 90 deg, 180 deg, 270 deg\n"
    )
);
assert_error!(
    syntax_unclosed_vector,
    "vdl::syntax",
    edit(
        VEHICLE,
        "reference_point = (-1, 0, 0) m",
        "reference_point = (-1, 0, 0 m"
    )
);
assert_error!(
    syntax_unclosed_call,
    "vdl::syntax",
    edit(VEHICLE, "origin = node(1)", "origin = node(1")
);
assert_error!(
    syntax_block_without_brace,
    "vdl::syntax",
    edit(VEHICLE, "  modes {\n", "  modes\n")
);

// ---------------------------------------------------------------- units

assert_error!(
    unit_mismatch,
    "vdl::unit::mismatch",
    edit(MATERIAL, "E = 70 GPa", "E = 70 kg")
);
assert_error!(
    unit_unknown_with_suggestion,
    "vdl::unit::unknown",
    edit(MATERIAL, "E = 70 GPa", "E = 70 Gpa")
);
assert_error!(
    unit_missing,
    "vdl::unit::missing",
    edit(MATERIAL, "rho = 2700 kg/m^3", "rho = 2700")
);
assert_error!(
    unit_mismatch_in_vector,
    "vdl::unit::mismatch",
    edit(
        VEHICLE,
        "reference_point = (-1, 0, 0) m",
        "reference_point = (-1, 0, 0) m/s"
    )
);

// ---------------------------------------------------------------- fields and blocks

assert_error!(
    field_unknown_with_suggestion,
    "vdl::field::unknown",
    edit(FINNED, "thickness = 1 mm", "thicknes = 1 mm")
);
assert_error!(
    block_unknown_in_vehicle,
    "vdl::block::unknown",
    edit(
        VEHICLE,
        "  forces {",
        "  force {\n    gravity {}\n  }\n  forces {"
    )
);
assert_error!(
    block_unknown_top_level,
    "vdl::block::unknown",
    edit(MATERIAL, "material m", "materal m")
);
assert_error!(
    field_duplicate,
    "vdl::duplicate",
    edit(MATERIAL, "nu = 0.3\n", "nu = 0.3\n  nu = 0.33\n")
);
assert_error!(
    declaration_duplicate,
    "vdl::duplicate",
    format!("{MATERIAL}\n{MATERIAL}")
);
assert_error!(
    field_missing_required,
    "vdl::field::missing",
    edit(MATERIAL, "  rho = 2700 kg/m^3\n", "")
);
assert_error!(
    block_missing_required,
    "vdl::block::missing",
    edit(
        VEHICLE,
        "  aero {\n    source = builtin\n    reference_point = (-1, 0, 0) m\n  }\n",
        ""
    )
);
assert_error!(
    name_missing,
    "vdl::name::missing",
    edit(MATERIAL, "material m {", "material {")
);

// ---------------------------------------------------------------- imports and files

assert_error!(
    import_cycle,
    "vdl::import::cycle",
    format!("import \"b.vdl\"\n\n{MATERIAL}"),
    files = [("b.vdl", "import \"case.vdl\"\n")]
);
assert_error!(
    import_missing,
    "vdl::import::missing",
    format!("import \"shared/materials.vdl\"\n\n{MATERIAL}")
);
assert_error!(
    import_missing_stdlib_with_suggestion,
    "vdl::import::missing",
    edit(VEHICLE, "std/materials.vdl", "std/material.vdl")
);
assert_error!(
    import_inside_block,
    "vdl::import::placement",
    edit(
        MATERIAL,
        "  nu = 0.3\n",
        "  nu = 0.3\n  import \"std/materials.vdl\"\n"
    )
);
assert_error!(
    thrust_curve_missing,
    "vdl::file::missing",
    edit(
        &edit(
            VEHICLE,
            "    gravity {}\n",
            "    gravity {}\n    thrust {\n      curve = \"motors/c6.eng\"\n    }\n"
        ),
        "    body = nearest((-1, 0, 0) m)\n",
        "    body = nearest((-1, 0, 0) m)\n    nozzle = nearest((-2, 0, 0) m)\n"
    )
);
assert_error!(
    fe_files_missing,
    "vdl::file::missing",
    edit(
        VEHICLE,
        "    generate {\n      body {\n        length = 2 m\n        diameter = 100 mm\n        wall = 2 mm\n        elements = 10\n      }\n    }\n",
        "    files {\n      format = matrix_market\n      mass = \"fe/m.mtx\"\n      stiffness = \"fe/k.mtx\"\n      nodes = \"fe/nodes.csv\"\n    }\n"
    ),
    files = [(
        "fe/m.mtx",
        "%%MatrixMarket matrix coordinate real symmetric\n"
    )]
);

// ---------------------------------------------------------------- values out of range

assert_error!(
    range_poisson_ratio,
    "vdl::value::range",
    edit(MATERIAL, "nu = 0.3", "nu = 0.6")
);
assert_error!(
    range_negative_mass,
    "vdl::value::range",
    edit(
        VEHICLE,
        "        elements = 10\n      }\n",
        "        elements = 10\n      }\n      point_mass payload {\n        position = (-0.5, 0, 0) m\n        mass = -1 kg\n      }\n"
    )
);
assert_error!(
    range_tip_chord_longer_than_root,
    "vdl::value::range",
    edit(FINNED, "tip_chord = 100 mm", "tip_chord = 250 mm")
);
// Issue 9 audit: `body_aero { rate_terms = true }` with a body table that has no rate
// columns passed `check` and was refused only when the plan built the block.
assert_error!(
    rate_terms_with_a_table_without_rate_columns_is_refused_at_check,
    "vdl::aero::rate_columns",
    edit(
        &edit(
            FINNED,
            "source = builtin\n",
            "source = tables\n    body_table = \"body.csv\"\n    fin_table = \"fin.csv\"\n"
        ),
        "gravity {}\n",
        "gravity {}\n    body_aero { rate_terms = true }\n"
    ),
    files = [
        (
            "body.csv",
            "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,0,0.3,0\n2,0,0,0,0.3,0\n0,10,0,1,0.3,-1\n2,10,0,1,0.3,-1\n0,0,10000,0,0.3,0\n2,0,10000,0,0.3,0\n0,10,10000,1,0.3,-1\n2,10,10000,1,0.3,-1\n"
        ),
        (
            "fin.csv",
            "mach,alpha_deg,altitude_m,cn,ca,cm\n0,0,0,0,0.01,0\n2,0,0,0,0.01,0\n"
        )
    ]
);
// Issue 9 audit: `check` accepted a pointed fin (tip chord 0) that the fin generator then
// refused at compile time.
assert_error!(
    generated_pointed_fin_is_refused_at_check,
    "vdl::fins::tip_chord",
    edit(FINNED, "tip_chord = 100 mm", "tip_chord = 0 mm")
);
assert_error!(
    fins_forward_swept_leading_edge_with_theory_loads,
    "vdl::fins::forward_sweep",
    edit(
        FINNED,
        "trailing_edge_sweep = 0 deg",
        "trailing_edge_sweep = -60 deg"
    )
);
// Issue 34: a freeform fin's outline that crosses itself, that turns back in span, or whose
// root is off the body is refused at `check`, at the offending point.
assert_error!(
    fins_freeform_outline_crosses_itself,
    "vdl::fins::outline",
    edit(
        FINNED,
        "span = 100 mm\n    root_chord = 200 mm\n    tip_chord = 100 mm\n    trailing_edge_sweep = 0 deg",
        "planform = freeform\n    points = [(0, 0) mm, (250, 100) mm, (150, 100) mm, (200, 0) mm]"
    )
);
assert_error!(
    fins_freeform_outline_not_single_valued,
    "vdl::fins::outline",
    edit(
        FINNED,
        "span = 100 mm\n    root_chord = 200 mm\n    tip_chord = 100 mm\n    trailing_edge_sweep = 0 deg",
        "planform = freeform\n    points = [(0, 0) mm, (50, 80) mm, (60, 40) mm, (100, 100) mm, (200, 0) mm]"
    )
);
assert_error!(
    fins_freeform_root_off_the_body,
    "vdl::fins::outline",
    edit(
        FINNED,
        "span = 100 mm\n    root_chord = 200 mm\n    tip_chord = 100 mm\n    trailing_edge_sweep = 0 deg",
        "planform = freeform\n    points = [(0, 0) mm, (100, 100) mm, (150, 100) mm, (200, 5) mm]"
    )
);
assert_error!(
    fins_elliptical_with_a_tip_chord,
    "vdl::fins::planform",
    edit(
        FINNED,
        "trailing_edge_sweep = 0 deg",
        "planform = elliptical"
    )
);
assert_error!(
    range_wall_too_thick,
    "vdl::value::range",
    edit(VEHICLE, "wall = 2 mm", "wall = 50 mm")
);
assert_error!(
    range_fin_count_zero,
    "vdl::value::range",
    edit(FINNED, "count = 4", "count = 0")
);
assert_error!(
    range_station_outside_body,
    "vdl::value::range",
    edit(
        VEHICLE,
        "        elements = 10\n      }\n",
        "        elements = 10\n      }\n      distributed_mass motor {\n        from = -1.5 m\n        to = -2.5 m\n        mass = 2 kg\n      }\n"
    )
);
assert_error!(
    range_quaternion_not_normalised,
    "vdl::value::range",
    edit(
        &finned_scenario(),
        "    altitude = 5 km\n",
        "    altitude = 5 km\n    attitude = quaternion(1, 0.1, 0, 0)\n"
    )
);
assert_error!(
    range_altitude_above_atmosphere,
    "vdl::value::range",
    edit(&finned_scenario(), "altitude = 5 km", "altitude = 90 km")
);

// ---------------------------------------------------------------- references

assert_error!(
    reference_scenario_names_material,
    "vdl::reference::kind",
    edit(
        &finned_scenario(),
        "vehicle = v",
        "vehicle = aluminium_thesis"
    )
);
assert_error!(
    reference_sweep_names_vehicle,
    "vdl::reference::kind",
    format!(
        "{}\nsweep sw {{\n  scenario = v\n  grid {{\n    fins.thickness = [1 mm, 2 mm]\n  }}\n}}\n",
        finned_scenario()
    )
);
assert_error!(
    reference_unknown_material_with_suggestion,
    "vdl::reference::unknown",
    edit(
        VEHICLE,
        "material = aluminium_thesis",
        "material = aluminum_thesis"
    )
);
assert_error!(
    reference_unknown_vehicle_with_suggestion,
    "vdl::reference::unknown",
    edit(&finned_scenario(), "vehicle = v\n", "vehicle = vv\n")
);

// ---------------------------------------------------------------- overrides

assert_error!(
    override_bad_path_in_with,
    "vdl::field::unknown",
    edit(
        &finned_scenario(),
        "  vehicle = v\n",
        "  vehicle = v\n  with {\n    fins.thicknes = 0.4 mm\n  }\n"
    )
);
assert_error!(
    override_through_a_field,
    "vdl::override::path",
    edit(
        &finned_scenario(),
        "  vehicle = v\n",
        "  vehicle = v\n  with {\n    fins.count.value = 3\n  }\n"
    )
);
assert_error!(
    override_with_sets_scenario_field,
    "vdl::override::path",
    edit(
        &finned_scenario(),
        "  vehicle = v\n",
        "  vehicle = v\n  with {\n    initial.altitude = 3 km\n  }\n"
    )
);
assert_error!(
    override_with_bad_unit,
    "vdl::unit::mismatch",
    edit(
        &finned_scenario(),
        "  vehicle = v\n",
        "  vehicle = v\n  with {\n    fins.thickness = 0.4 s\n  }\n"
    )
);

/// `--set` overrides go through `check_files`; the file lives in a temporary directory.
fn check_with_sets(name: &str, code: &str, src: &str, sets: &[&str]) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("case.vdl");
    std::fs::write(&path, src).expect("write");
    let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let checked = check_files(std::slice::from_ref(&path), &sets, &DiskLoader);
    let mut text = report(&[("case.vdl", src)], &checked);
    text.push_str(&format!("----- SETS\n{sets:?}\n"));
    // The temporary directory differs per run: keep the snapshot stable.
    let text = text.replace(&dir.path().display().to_string(), "$TMP");
    assert!(
        checked.diagnostics.iter().any(|d| d.code == code),
        "expected a `{code}` diagnostic in case {name}:\n{text}"
    );
    insta::assert_snapshot!(name, text);
}

#[test]
fn override_bad_path_in_set() {
    check_with_sets(
        "override_bad_path_in_set",
        "vdl::field::unknown",
        FINNED,
        &["fins.thicknes=0.4 mm"],
    );
}

#[test]
fn override_set_missing_equals() {
    check_with_sets(
        "override_set_missing_equals",
        "vdl::syntax",
        FINNED,
        &["fins.thickness"],
    );
}

#[test]
fn override_set_not_an_assignment() {
    check_with_sets(
        "override_set_not_an_assignment",
        "vdl::override::syntax",
        FINNED,
        &["forces { gravity {} }"],
    );
}

#[test]
fn override_set_names_a_block() {
    check_with_sets(
        "override_set_names_a_block",
        "vdl::override::path",
        FINNED,
        &["forces.gravity=false"],
    );
}

// ---------------------------------------------------------------- sweeps

fn sweep(axes: &str) -> String {
    format!(
        "{}\nsweep sw {{\n  scenario = s\n{axes}}}\n",
        finned_scenario()
    )
}

assert_error!(
    sweep_empty_list,
    "vdl::sweep::empty",
    sweep("  grid {\n    fins.thickness = []\n  }\n")
);
assert_error!(sweep_no_axes, "vdl::sweep::empty", sweep("  grid {\n  }\n"));
assert_error!(
    sweep_bad_range,
    "vdl::sweep::range",
    sweep("  grid {\n    fins.thickness = range(1 mm, 0.3 mm, step = 0.1 mm)\n  }\n")
);
assert_error!(
    sweep_zero_step,
    "vdl::sweep::range",
    sweep("  grid {\n    fins.thickness = range(0.3 mm, 1 mm, step = 0 mm)\n  }\n")
);
assert_error!(
    sweep_zip_lengths_differ,
    "vdl::sweep::zip",
    sweep(
        "  zip {\n    fins.thickness = [0.5 mm, 1 mm]\n    initial.altitude = [1 km, 2 km, 3 km]\n  }\n"
    )
);
assert_error!(
    sweep_unknown_path,
    "vdl::field::unknown",
    sweep("  grid {\n    fins.thicknes = [0.5 mm, 1 mm]\n  }\n")
);
assert_error!(
    sweep_grid_and_zip,
    "vdl::sweep::combine",
    sweep(
        "  grid {\n    fins.thickness = [0.5 mm, 1 mm]\n  }\n  zip {\n    initial.altitude = [1 km, 2 km]\n  }\n"
    )
);

// ---------------------------------------------------------------- structure of the file

assert_error!(
    toplevel_assignment,
    "vdl::toplevel",
    format!("nu = 0.3\n\n{MATERIAL}")
);
assert_error!(
    dotted_path_outside_override,
    "vdl::field::dotted",
    edit(
        FINNED,
        "    fin_flap = per_fin\n",
        "    fin_flap = per_fin\n    fins.count = 3\n"
    )
);
assert_error!(
    vector_arity,
    "vdl::vector::arity",
    edit(
        VEHICLE,
        "reference_point = (-1, 0, 0) m",
        "reference_point = (-1, 0) m"
    )
);
assert_error!(
    modes_select_nothing,
    "vdl::modes::empty",
    edit(VEHICLE, "    body_bending = 2\n", "    fixity = origin\n")
);
assert_error!(
    modes_per_fin_without_fins,
    "vdl::modes::no_fins",
    edit(
        VEHICLE,
        "    body_bending = 2\n",
        "    body_bending = 2\n    fin_twist = per_fin\n"
    )
);
assert_error!(
    fin_aero_without_fins,
    "vdl::block::missing",
    edit(
        VEHICLE,
        "    gravity {}\n",
        "    gravity {}\n    fin_aero {}\n"
    )
);
assert_error!(
    fin_key_nodes_without_fins,
    "vdl::reference::kind",
    edit(
        VEHICLE,
        "    body = nearest((-1, 0, 0) m)\n",
        "    body = nearest((-1, 0, 0) m)\n    fins = fin_point(span = 0.5, chord = 0.5)\n"
    )
);
assert_error!(
    thrust_without_nozzle_key_node,
    "vdl::key_node::missing",
    edit(
        VEHICLE,
        "    gravity {}\n",
        "    gravity {}\n    thrust {\n      curve = \"c6.eng\"\n    }\n"
    ),
    files = [("c6.eng", "C6 18 70 0 0.0108 0.0231 Estes\n0.0 0.0\n")]
);
assert_error!(
    structure_generate_and_files,
    "vdl::structure::ambiguous",
    edit(
        VEHICLE,
        "    generate {\n",
        "    files {\n      format = op4\n      matrices = \"fe/model.op4\"\n      nodes = \"fe/grid.bdf\"\n    }\n    generate {\n"
    ),
    files = [("fe/model.op4", ""), ("fe/grid.bdf", "")]
);
// A loaded motor of 2575 kg (the K1000T's 2575 g written in kg) in a 75 mm x 396 mm
// cylinder: mean density 1.47e6 kg/m^3, far above solid steel's 7850.
assert_error!(
    motor_heavier_than_its_size,
    "vdl::motor::heavy",
    edit(
        VEHICLE,
        "  forces {\n    gravity {}\n  }\n",
        "  forces {\n    gravity {}\n  }\n  motor k1000 {\n    curve = \"motors/k1000.eng\"\n    position = (-2, 0, 0) m\n    length = 396 mm\n    diameter = 75 mm\n    total_mass = 2575 kg\n  }\n"
    ),
    files = [(
        "motors/k1000.eng",
        "; AeroTech K1000T\nK1000T-P 75 396 P 1.182 2.575 AT\n0.004 895.1\n1.0 1000.0\n2.5 0.0\n"
    )]
);
assert_error!(
    keyword_unknown_with_suggestion,
    "vdl::value::keyword",
    edit(VEHICLE, "source = builtin", "source = built_in")
);
assert_error!(
    type_mismatch_string_for_number,
    "vdl::type::mismatch",
    edit(VEHICLE, "elements = 10", "elements = \"10\"")
);

// ---------------------------------------------------------------- the registry of codes

/// Every diagnostic code written in a string in `src/**/*.rs`: `"vdl::..."`, `"fe::..."`,
/// `"artifact::..."`, ... as a complete literal, and also inside a message or a format
/// string (`"error[run::cannot_start]: {e}"`, `"plan::invalid: {e}"`), which is how codes
/// of errors printed without a `Diagnostic` are written. A code is `prefix::name(::name)*`
/// right after a `"` or a `[`, followed by `"`, `]` or a single `:`; comment lines are
/// skipped (doc links such as `[run::run]` are not codes).
fn codes_in_source() -> Vec<(String, PathBuf)> {
    fn walk(dir: &std::path::Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).expect("read src") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    walk(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("src"),
        &mut files,
    );
    let mut codes = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read");
        for line in text.lines() {
            if line.trim_start().starts_with("//") {
                continue;
            }
            codes.extend(codes_in_line(line).into_iter().map(|c| (c, f.clone())));
        }
    }
    codes
}

/// The codes of [`codes_in_source`] on one line.
fn codes_in_line(line: &str) -> Vec<String> {
    const PREFIXES: [&str; 11] = [
        "vdl::",
        "import::",
        "fe::",
        "artifact::",
        "generate::",
        "modal::",
        "structure::",
        "analysis::",
        "report::",
        "plan::",
        "run::",
    ];
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let mut out = Vec::new();
    for prefix in PREFIXES {
        for (k, _) in line.match_indices(prefix) {
            if !(line[..k].ends_with('"') || line[..k].ends_with('[')) {
                continue;
            }
            // prefix::name(::name)*
            let rest = &line[k..];
            let mut end = prefix.len();
            loop {
                let seg = rest[end..]
                    .find(|c: char| !ident(c))
                    .unwrap_or(rest.len() - end);
                if seg == 0 {
                    break;
                }
                end += seg;
                if rest[end..].starts_with("::") {
                    end += 2;
                } else {
                    break;
                }
            }
            let code = &rest[..end];
            let after = &rest[end..];
            let complete = !code.ends_with(':')
                && code.len() > prefix.len()
                && (after.starts_with('"')
                    || after.starts_with(']')
                    || (after.starts_with(':') && !after.starts_with("::")));
            if complete {
                out.push(code.to_string());
            }
        }
    }
    out
}

#[test]
fn the_code_scan_finds_codes_in_messages_and_format_strings() {
    assert_eq!(
        codes_in_line(r#"  Diagnostic::error("vdl::syntax", m)"#),
        ["vdl::syntax"]
    );
    assert_eq!(
        codes_in_line(r#"eprintln!("error[run::cannot_start]: {e}");"#),
        ["run::cannot_start"]
    );
    assert_eq!(
        codes_in_line(r#"format!("plan::invalid: {e}")"#),
        ["plan::invalid"]
    );
    // A prefix of a code built at run time, and a path that is not in a string, are not codes.
    assert!(codes_in_line(r#"format!("vdl::{kind}::x")"#).is_empty());
    assert!(codes_in_line("let x = run::run(&p);").is_empty());
}

#[test]
fn every_code_is_documented() {
    let doc_path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/diagnostic-codes.md");
    let doc = std::fs::read_to_string(&doc_path).expect("docs/diagnostic-codes.md");
    let codes = codes_in_source();
    assert!(
        codes.len() > 40,
        "the scan found only {} codes: is it broken?",
        codes.len()
    );
    let missing: Vec<String> = codes
        .iter()
        .filter(|(c, _)| !doc.contains(&format!("`{c}`")))
        .map(|(c, f)| format!("{c} (used in {})", f.display()))
        .collect();
    assert!(
        missing.is_empty(),
        "codes used in src/ but not listed in docs/diagnostic-codes.md:\n{}",
        missing.join("\n")
    );
}

#[test]
fn documented_codes_are_used() {
    // The converse: a code listed in the table but used nowhere is stale.
    let doc = std::fs::read_to_string(
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/diagnostic-codes.md"),
    )
    .expect("docs/diagnostic-codes.md");
    let used: std::collections::HashSet<String> =
        codes_in_source().into_iter().map(|(c, _)| c).collect();
    let stale: Vec<&str> = doc
        .lines()
        .filter_map(|l| l.strip_prefix("| `"))
        .filter_map(|l| l.split('`').next())
        .filter(|c| !used.contains(*c))
        .collect();
    assert!(stale.is_empty(), "documented but unused codes: {stale:?}");
}
