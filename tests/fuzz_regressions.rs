//! Inputs found by `cargo fuzz run check_bytes` (fuzz/), kept as regression tests. Each runs
//! the same pipeline as the fuzz target: parse, print, re-parse, check.

use flexflight::check::{MemoryLoader, check_source};
use flexflight::syntax::print::print_tree;
use flexflight::syntax::{FileId, parse_file};

fn run(data: &[u8]) -> usize {
    let text = String::from_utf8_lossy(data);
    let (tree, errors) = parse_file(FileId(0), &text);
    let printed = print_tree(&tree);
    let (tree2, errors2) = parse_file(FileId(0), &printed);
    if errors.is_empty() {
        assert!(
            errors2.is_empty(),
            "printed text does not parse: {errors2:?}"
        );
        assert_eq!(printed, print_tree(&tree2));
    }
    let _ = check_source("fuzz.vdl", &text, &MemoryLoader::default());
    errors.len()
}

/// Error recovery skipped `n` *characters* where `n` was a byte offset: after a run of
/// multi-byte characters near the end of the input the skip failed, left the position
/// unchanged, and the parser pushed the same error forever (out of memory).
#[test]
fn recovery_after_multibyte_characters_terminates() {
    let data = format!(
        "material m {{\n  yield = 410 M{}Pa\n  ultimate = 480 MPa\n}}\n",
        "\u{FFFD}".repeat(50)
    );
    let data = data.as_str();
    let n = run(data.as_bytes());
    assert_eq!(
        n, 1,
        "one error for the bad unit, then recovery at the line end"
    );
    // The next line was not skipped: `ultimate` is parsed.
    let (tree, _) = parse_file(FileId(0), data);
    assert!(format!("{tree:?}").contains("ultimate"));
}

/// The fuzzer's original input (invalid UTF-8 bytes inside the stdlib file).
#[test]
fn fuzz_oom_bc0246385d() {
    let mut data = b"material m {\n  E = 70 GPa\n  yield = 410 M".to_vec();
    data.extend(std::iter::repeat_n(0x99u8, 60));
    data.extend_from_slice(b"Pa\n  ultimate = 480 MPa\n}\n");
    run(&data);
}
