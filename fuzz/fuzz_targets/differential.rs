//! The differential suite (`pipeline_tests::differential`; docs/fuzzing.md, "The
//! differential suite") on the scene of the seed the input's first eight bytes give: every
//! mode that claims another's bytes, run as the real binaries of `$POLYPIPE_BIN` (default
//! the repository's `target/bin`), compared with what it claims. A broken claim panics
//! with its seed and a command that shows it. The binaries are not instrumented, so this
//! target walks seeds rather than following coverage.
#![no_main]
use libfuzzer_sys::fuzz_target;
use pipeline_tests::differential::{check, generate, Plan};
use std::path::PathBuf;

fuzz_target!(|data: &[u8]| {
    let mut seed = [0u8; 8];
    for (i, b) in data.iter().take(8).enumerate() {
        seed[i] = *b;
    }
    let seed = u64::from_le_bytes(seed);
    let bins = std::env::var_os("POLYPIPE_BIN")
        .map(PathBuf::from)
        .unwrap_or_else(|| pipeline_tests::repo_root().join("target/bin"));
    let (failures, _) = check(&generate(seed), &bins, &Plan::quick());
    let shown: Vec<String> = failures.iter().map(|f| f.to_string()).collect();
    assert!(shown.is_empty(), "{}", shown.join("\n"));
});
