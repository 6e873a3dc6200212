//! cpfg's own answers for every corpus model it runs, recorded by `tools/cpfg-compare
//! --record` from the real cpfg (built headless from the vlab sources,
//! `../shared/cpfg-oracle`) into `tests/cpfg/reference.tsv`: per model the number of
//! modules of its string (one a character, as cpfg keeps them), hashes of their names in
//! blocks of 4,096, and its F/G segments outside polygons (count and length sum). arbor
//! must give the same for every model but the few named below with their reasons; a
//! difference names the model and the first block of modules (or the segments) that
//! differ. The corpus is read in place (`ARBOR_CPFG_CORPUS` or `../shared/cpfg-corpus`).

use arbor::lsystem::{LSystem, LsystemOptions};
use std::path::{Path, PathBuf};

/// Models whose difference from cpfg is known, with the reason (see docs/grammars.md).
const DIFFERS: &[(&str, &str)] = &[];

const BLOCK: usize = 4096;

fn corpus() -> PathBuf {
    let dir = std::env::var_os("ARBOR_CPFG_CORPUS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/cpfg-corpus"));
    assert!(
        dir.join("MANIFEST.tsv").is_file(),
        "the cpfg corpus is not at {} (set ARBOR_CPFG_CORPUS)",
        dir.display()
    );
    dir
}

/// The view file the manifest names for each grammar.
fn views(dir: &Path) -> std::collections::HashMap<String, String> {
    let manifest = std::fs::read_to_string(dir.join("MANIFEST.tsv")).unwrap();
    manifest
        .lines()
        .skip(1)
        .filter_map(|l| {
            let w: Vec<&str> = l.split('\t').collect();
            let notes = w.get(6)?;
            let view = notes
                .split(';')
                .find_map(|p| p.trim().strip_prefix("view file="))?;
            Some((w[0].to_string(), view.trim().to_string()))
        })
        .collect()
}

fn fnv(bytes: &[u8]) -> String {
    let mut h = 0xcbf2_9ce4_8422_2325u64;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100_0000_01b3);
    }
    format!("{h:016x}")
}

/// What arbor answers in the reference's terms.
struct Answer {
    /// Modules, one a character.
    modules: usize,
    /// Hashes of their names in blocks of [`BLOCK`].
    blocks: Vec<String>,
    /// Segments longer than 1e-6 of the model's size, and their length sum.
    segments: usize,
    length: f64,
    /// The sum of |parameter| over the string.
    params: f64,
    /// The sum of |coordinate| of the segments' ends.
    ends: f64,
}

fn answer(path: &Path, view: Option<&Path>, size: f64) -> Result<Answer, String> {
    let ls = LSystem::from_file(path, view).map_err(|e| e.to_string())?;
    let options = LsystemOptions::default();
    let s = ls.derive(&options).map_err(|e| e.to_string())?;
    let mut chars: Vec<char> = Vec::new();
    for i in 0..s.len() {
        chars.extend(ls.symbol_name(s.symbol(i)).chars());
    }
    let blocks = chars
        .chunks(BLOCK)
        .map(|b| {
            let text: Vec<String> = b.iter().map(|c| c.to_string()).collect();
            fnv(text.join("\0").as_bytes())
        })
        .collect();
    let params = (0..s.len())
        .flat_map(|i| s.params(i).iter().map(|&v| (v as f64).abs()))
        .sum();
    let sk = ls.interpret(&s, &options).map_err(|e| e.to_string())?;
    let kept: Vec<(f64, [f32; 3])> = sk
        .branches()
        .iter()
        .map(|b| {
            let l = b
                .start
                .iter()
                .zip(b.end)
                .map(|(a, e)| (e as f64 - *a as f64).powi(2))
                .sum::<f64>()
                .sqrt();
            (l, b.end)
        })
        .filter(|&(l, _)| l > 1e-6 * size)
        .collect();
    Ok(Answer {
        modules: chars.len(),
        blocks,
        segments: kept.len(),
        length: kept.iter().map(|k| k.0).sum(),
        params,
        ends: kept
            .iter()
            .flat_map(|k| k.1)
            .map(|v| (v as f64).abs())
            .sum(),
    })
}

/// Whether `a` and `b` agree within `rel` of `scale`.
fn near(a: f64, b: f64, rel: f64, scale: f64) -> bool {
    (a - b).abs() <= rel * scale.max(a.abs()).max(b.abs()).max(1.0)
}

#[test]
fn every_model_gives_cpfgs_answer() {
    let dir = corpus();
    let views = views(&dir);
    let reference = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cpfg/reference.tsv"),
    )
    .unwrap();
    let (mut matched, mut runs, mut failures) = (0, 0, Vec::new());
    for line in reference.lines().filter(|l| !l.starts_with('#')) {
        let w: Vec<&str> = line.split('\t').collect();
        let rel = w[0];
        let num = |k: usize| w[k].parse::<f64>().unwrap();
        let want = Answer {
            modules: w[1].parse().unwrap(),
            blocks: w[2].split(',').map(str::to_string).collect(),
            segments: w[3].parse().unwrap(),
            length: num(4),
            params: num(6),
            ends: num(7),
        };
        let size = num(5);
        runs += 1;
        let path = dir.join(rel);
        let view = views.get(rel).map(|v| path.parent().unwrap().join(v));
        let difference = match answer(&path, view.as_deref(), size) {
            Err(e) => Some(format!("arbor: {e}")),
            Ok(got) => {
                let block = got
                    .blocks
                    .iter()
                    .zip(&want.blocks)
                    .position(|(x, y)| x != y);
                if got.modules != want.modules || block.is_some() {
                    let k = block.unwrap_or(got.blocks.len().min(want.blocks.len()));
                    Some(format!(
                        "modules: cpfg {}, arbor {}; first differing block: modules {}..{}",
                        want.modules,
                        got.modules,
                        k * BLOCK,
                        (k + 1) * BLOCK
                    ))
                } else if !near(got.params, want.params, 1e-6, 0.0) {
                    Some(format!(
                        "parameters: the sum of their magnitudes is {} in cpfg, {} in arbor",
                        want.params, got.params
                    ))
                } else if got.segments != want.segments
                    || !near(got.length, want.length, 1e-4, size)
                    || (got.ends - want.ends).abs() > 1e-4 * size + 1e-6 * want.ends
                {
                    Some(format!(
                        "segments: cpfg {} of length {} (ends {}), arbor {} of length {} (ends {})",
                        want.segments, want.length, want.ends, got.segments, got.length, got.ends
                    ))
                } else {
                    None
                }
            }
        };
        let known = DIFFERS.iter().find(|(name, _)| rel.ends_with(name));
        match (difference, known) {
            (None, _) => matched += 1,
            (Some(_), Some(_)) => {}
            (Some(d), None) => failures.push(format!("{rel}: {d}")),
        }
    }
    println!("{matched} of the {runs} models cpfg runs give cpfg's answer");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(runs >= 68, "{runs} models recorded");
    // At most the known differences: all 68 today.
    assert!(matched + DIFFERS.len() >= runs, "{matched} of {runs}");
}
