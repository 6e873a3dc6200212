//! Conformance on real cpfg models: every grammar of `../shared/cpfg-corpus` (the Virtual
//! Laboratory distribution and the ADEL crop models, read in place, never copied) is read
//! as cpfg reads it (preprocessor, view file) and grown. `ARBOR_CPFG_CORPUS` may name
//! another copy; without one the suite fails and says so.

use arbor::lsystem::{LSystem, LsystemOptions};
use std::path::{Path, PathBuf};

/// The corpus: `ARBOR_CPFG_CORPUS`, or `../shared/cpfg-corpus` beside the checkout. It
/// is other people's work and is not part of arbor; without it this suite fails and says
/// where to put it.
fn corpus() -> PathBuf {
    let dir = std::env::var_os("ARBOR_CPFG_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/cpfg-corpus"));
    if dir.join("MANIFEST.tsv").is_file() {
        dir
    } else {
        panic!(
            "the cpfg corpus is not at {} (no MANIFEST.tsv): the conformance suite reads real \
             cpfg models that arbor does not redistribute; set ARBOR_CPFG_CORPUS to a copy",
            dir.display()
        );
    }
}

/// The grammars of the manifest, in its order.
fn grammars(dir: &Path) -> Vec<PathBuf> {
    let manifest = std::fs::read_to_string(dir.join("MANIFEST.tsv")).unwrap();
    manifest
        .lines()
        .skip(1)
        .filter_map(|l| l.split('\t').next())
        .filter(|p| !p.is_empty())
        .map(|p| dir.join(p))
        .collect()
}

/// Files that cannot run as written, with what the error must name: each needs something
/// outside arbor (or outside the corpus), or is not a whole model.
const NEEDS_OUTSIDE: &[(&str, &str)] = &[
    // Includes `leaf.l`, which the corpus does not have.
    ("Sedge/sedge.l", "#include \"leaf.l\": cannot open"),
];

/// Known results (the corpus manifest's D0L counts): modules after the derivation, and
/// modules per symbol.
/// (file, modules, modules per symbol).
type Known = (&'static str, usize, &'static [(&'static str, usize)]);

const KNOWN: &[Known] = &[
    (
        "01-anklets/fractal.l",
        1197,
        &[("X", 512), ("-", 342), ("f", 340), ("+", 1)],
    ),
    (
        "01-tri-bar/molecule.l",
        43,
        &[("C", 13), ("f", 13), ("[", 3), ("]", 3)],
    ),
    ("BackgroundScene/plant.l", 1, &[("F", 1)]),
    (
        "ConcavePolygons/fractal.l",
        1540,
        &[("-", 516), ("+", 508), ("R", 256), ("S", 256)],
    ),
    (
        "GeneralizedCylinder/fractal.l",
        158,
        &[("-", 48), ("+", 40), ("X", 32), ("f", 32)],
    ),
    (
        "03-snowflake/fractal.l",
        597,
        &[("F", 256), ("+", 170), ("-", 171)],
    ),
    (
        "05-compound-homo/leaf.l",
        451,
        &[("I", 130), ("A", 81), ("[", 80), ("]", 80)],
    ),
];

struct Outcome {
    modules: usize,
    branches: usize,
    leaves: usize,
    polygons: usize,
    /// Modules per symbol name.
    symbols: Vec<(String, usize)>,
}

fn grow(path: &Path) -> arbor::Result<Outcome> {
    let ls = LSystem::from_file(path, None)?;
    let options = LsystemOptions::default()
        .max_modules(4_000_000)
        .max_work(40_000_000);
    let string = ls.derive(&options)?;
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for i in 0..string.len() {
        *counts
            .entry(ls.symbol_name(string.symbol(i)).to_string())
            .or_default() += 1;
    }
    let skeleton = ls.interpret(&string, &options)?;
    Ok(Outcome {
        modules: string.len(),
        branches: skeleton.len(),
        leaves: skeleton.leaves().len(),
        polygons: skeleton.polygons().len(),
        symbols: counts.into_iter().collect(),
    })
}

fn short(dir: &Path, p: &Path) -> String {
    p.strip_prefix(dir)
        .unwrap_or(p)
        .to_string_lossy()
        .replace("AlgorithmicBotany+vlab/", "")
        .replace("oofs/ext/", "")
}

#[test]
fn every_corpus_file_runs_as_written() {
    let dir = corpus();
    let files = grammars(&dir);
    assert!(
        files.len() >= 70,
        "{} grammars in the manifest",
        files.len()
    );
    let mut ran = 0;
    let mut checked = 0;
    let mut failures = Vec::new();
    for path in &files {
        let name = short(&dir, path);
        let result = std::panic::catch_unwind(|| grow(path));
        let result = result.unwrap_or_else(|_| panic!("{name}: panicked"));
        match result {
            Ok(o) => {
                ran += 1;
                assert!(o.branches <= 4_000_000 && o.modules <= 4_000_000, "{name}");
                if let Some((_, modules, symbols)) = KNOWN.iter().find(|k| name.ends_with(k.0)) {
                    assert_eq!(o.modules, *modules, "{name}: modules");
                    for (sym, n) in symbols.iter() {
                        let got = o.symbols.iter().find(|(s, _)| s == sym).map_or(0, |x| x.1);
                        assert_eq!(got, *n, "{name}: modules `{sym}`");
                    }
                    checked += 1;
                }
                println!(
                    "ok   {name}: {} modules, {} branches, {} leaves, {} polygons",
                    o.modules, o.branches, o.leaves, o.polygons
                );
            }
            Err(e) => {
                println!("FAIL {name}: {e}");
                failures.push((name, e.to_string()));
            }
        }
    }
    println!(
        "{ran} of {} corpus grammars run; {checked} counts match",
        files.len()
    );
    assert_eq!(checked, KNOWN.len(), "every known count was checked");
    assert!(ran >= 71, "{ran} grammars ran; 71 of the 72 do");
    let unexpected: Vec<_> = failures
        .iter()
        .filter(|(n, e)| {
            !NEEDS_OUTSIDE
                .iter()
                .any(|(file, why)| n.contains(file) && e.contains(why))
        })
        .collect();
    assert!(
        unexpected.is_empty(),
        "{} grammars fail: {unexpected:#?}",
        unexpected.len()
    );
}
