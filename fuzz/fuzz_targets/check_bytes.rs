//! Arbitrary bytes through the whole front end: parse, print, re-parse, check.
//!
//! Invariants: nothing panics or hangs; the printer's output of a file that parsed without
//! errors parses without errors again, and printing is idempotent on it.
#![no_main]

use flexflight::check::{MemoryLoader, check_source};
use flexflight::syntax::parse_file;
use flexflight::syntax::print::print_tree;
use flexflight::syntax::FileId;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let (tree, errors) = parse_file(FileId(0), &text);
    let printed = print_tree(&tree);
    let (tree2, errors2) = parse_file(FileId(0), &printed);
    if errors.is_empty() {
        assert!(
            errors2.is_empty(),
            "printed text of an error-free file does not parse: {errors2:?}\n--- printed\n{printed}"
        );
        let printed2 = print_tree(&tree2);
        assert_eq!(printed, printed2, "printing is not idempotent");
    }
    let _ = check_source("fuzz.vdl", &text, &MemoryLoader::default());
});
