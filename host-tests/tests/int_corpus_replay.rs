//! Replays every checked-in fuzz corpus file (`fuzz/corpus/<target>/`) through the same check
//! the fuzz target runs (`volsample_host::checks::run`), on stable, in every `cargo test`.

use std::path::PathBuf;
use volsample_host::checks;

#[test]
fn every_corpus_file_passes_its_check() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz/corpus");
    for target in checks::TARGETS {
        let dir = root.join(target);
        let mut files: Vec<_> = std::fs::read_dir(&dir)
            .unwrap_or_else(|e| panic!("corpus {}: {e}", dir.display()))
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .collect();
        files.sort();
        assert!(!files.is_empty(), "no corpus for {target}");
        for f in &files {
            let data = std::fs::read(f).unwrap();
            checks::run(target, &data).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
        }
        println!("{target}: {} corpus files pass", files.len());
    }
}

#[test]
fn unknown_target_is_an_error() {
    assert!(checks::run("no_such_target", &[]).is_err());
}
