//! Replays every checked-in corpus file of the parser fuzz targets (`fuzz/corpus/load_*/`)
//! through the same check the fuzz target runs (`volsample_host::parser_checks::run`), on
//! stable, in every `cargo test`; and checks that every fuzz target has a corpus replayed
//! here or by `int_corpus_replay.rs`.

use std::path::{Path, PathBuf};
use volsample_host::{checks, parser_checks};

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../fuzz")
}

fn corpus(target: &str) -> Vec<PathBuf> {
    let dir = root().join("corpus").join(target);
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("corpus {}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    files
}

#[test]
fn every_parser_corpus_file_passes_its_check() {
    for target in parser_checks::TARGETS {
        let files = corpus(target);
        assert!(!files.is_empty(), "no corpus for {target}");
        let mut loaded = 0;
        for f in &files {
            let data = std::fs::read(f).unwrap();
            loaded += usize::from(
                parser_checks::run_loaded(target, &data)
                    .unwrap_or_else(|e| panic!("{}: {e}", f.display())),
            );
        }
        println!(
            "{target}: {} corpus files pass, {loaded} of them loaded (the rest refused)",
            files.len()
        );
        // The oracle's comparisons ran: some of the corpus loads, some is refused.
        assert!(loaded > 0, "{target}: no corpus file loads");
        assert!(loaded < files.len(), "{target}: no corpus file is refused");
    }
}

/// Every `fuzz/fuzz_targets/*.rs` is one of the replayed targets, with a non-empty corpus.
#[test]
fn every_fuzz_target_has_a_replayed_corpus() {
    let mut targets: Vec<String> = std::fs::read_dir(root().join("fuzz_targets"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "rs"))
        .map(|p| {
            Path::new(&p)
                .file_stem()
                .unwrap()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    targets.sort();
    assert!(targets.len() >= 9, "fuzz targets found: {targets:?}");
    for t in &targets {
        assert!(
            checks::TARGETS.contains(&t.as_str()) || parser_checks::TARGETS.contains(&t.as_str()),
            "fuzz target {t} is replayed by no test"
        );
        assert!(!corpus(t).is_empty(), "no corpus for {t}");
    }
    println!(
        "{} fuzz targets, each with a corpus: {targets:?}",
        targets.len()
    );
}

/// The raw oracle tells a file the loader must load from one it must refuse (a byte short).
#[test]
fn the_raw_oracle_tells_sizes_apart() {
    // dims 2×1×1, u8, little-endian, no spacing, then the file's bytes.
    let ok = [2, 0, 1, 0, 1, 0, 0, 0, 0, 7, 9];
    let short = [2, 0, 1, 0, 1, 0, 0, 0, 0, 7];
    assert_eq!(parser_checks::run_loaded("load_raw", &ok), Ok(true));
    assert_eq!(parser_checks::run_loaded("load_raw", &short), Ok(false));
    assert!(parser_checks::run("no_such_target", &[]).is_err());
}
