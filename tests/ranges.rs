//! The ranges the documentation gives are the ranges `validate()` enforces: for every
//! field of `GrowthParams`, `WorldOptions`, `MeshOptions` and `LeafOptions` whose doc
//! comment states a range (`[a, b]`,
//! `(a, b]`, `a..=b`, `> a`, `≥ a`), the bounds are accepted or refused as written, just
//! inside and just outside; and the C header documents the same range for the field of the
//! same name.

use arbor::mesh::{LeafOptions, MeshOptions};
use arbor::models::growth::{GrowthParams, WorldOptions};
use std::path::Path;

/// One end of a range: the bound and whether it is included.
type End = Option<(f64, bool)>;

#[derive(Debug, PartialEq)]
struct Range {
    lo: End,
    hi: End,
}

/// The fields of `struct NAME {` in `text` with their doc comments (Rust `///` or the C
/// header's `/** … */`).
fn field_docs(text: &str, name: &str) -> Vec<(String, String)> {
    let start = text
        .find(&format!("struct {name} {{"))
        .unwrap_or_else(|| panic!("no struct {name}"));
    let mut out = Vec::new();
    let mut doc = String::new();
    for line in text[start..].lines().skip(1) {
        let t = line.trim();
        if t == "}" || t.starts_with("} ") {
            break;
        }
        if let Some(d) = t.strip_prefix("///").or_else(|| t.strip_prefix("* ")) {
            doc.push_str(d);
            doc.push(' ');
        } else if t.ends_with(';') || t.ends_with(',') {
            // `pub name: T,` (Rust) or `T name;` (C), possibly an array.
            let decl = t.trim_end_matches([',', ';']);
            let field = if let Some(rust) = decl.strip_prefix("pub ") {
                rust.split(':').next().unwrap().trim()
            } else {
                decl.split_whitespace()
                    .last()
                    .unwrap()
                    .split('[')
                    .next()
                    .unwrap()
            };
            out.push((field.to_string(), std::mem::take(&mut doc)));
        }
    }
    out
}

fn number(s: &str) -> Option<(f64, usize)> {
    let end = s
        .char_indices()
        .find(|&(i, c)| !(c.is_ascii_digit() || c == '.' || (i == 0 && c == '-')))
        .map_or(s.len(), |(i, _)| i);
    let text = s[..end].trim_end_matches('.');
    text.parse().ok().map(|v| (v, text.len()))
}

/// The first range the doc states, if any.
fn range(doc: &str) -> Option<Range> {
    let doc = doc
        .replace('−', "-")
        .replace('≥', ">=")
        .replace(",000", "000");
    let b = doc.as_bytes();
    for i in 0..doc.len() {
        if !doc.is_char_boundary(i) {
            continue;
        }
        let rest = &doc[i..];
        // [a, b] (a, b] [a, b) (a, b)
        if b[i] == b'[' || b[i] == b'(' {
            if let Some((lo, n)) = number(&rest[1..]) {
                let after = &rest[1 + n..];
                if let Some(after) = after.strip_prefix(", ") {
                    if let Some((hi, m)) = number(after) {
                        let close = after[m..].chars().next();
                        if matches!(close, Some(']') | Some(')')) {
                            return Some(Range {
                                lo: Some((lo, b[i] == b'[')),
                                hi: Some((hi, close == Some(']'))),
                            });
                        }
                    }
                }
            }
        }
        // a..=b
        if i == 0 || !(b[i - 1].is_ascii_digit() || b[i - 1] == b'.') {
            if let Some((lo, n)) = number(rest) {
                if let Some(after) = rest[n..].strip_prefix("..=") {
                    if let Some((hi, _)) = number(after) {
                        return Some(Range {
                            lo: Some((lo, true)),
                            hi: Some((hi, true)),
                        });
                    }
                }
            }
        }
        // > a, >= a
        for (op, inclusive) in [(">= ", true), ("> ", false)] {
            if let Some(after) = rest.strip_prefix(op) {
                if let Some((lo, _)) = number(after) {
                    return Some(Range {
                        lo: Some((lo, inclusive)),
                        hi: None,
                    });
                }
            }
        }
    }
    None
}

/// Checks every documented range of `T` against `valid`, setting fields with `set`.
fn check<T: Default>(
    rust_src: &str,
    rust_name: &str,
    c_name: &str,
    set: &dyn Fn(&mut T, &str, f64) -> bool,
    valid: &dyn Fn(&T) -> bool,
) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let rust = std::fs::read_to_string(root.join(rust_src)).unwrap();
    let header = std::fs::read_to_string(root.join("include/arbor.h")).unwrap();
    let c_docs = field_docs(&header, c_name);
    let mut checked = 0;
    for (field, doc) in field_docs(&rust, rust_name) {
        let Some(r) = range(&doc) else { continue };
        assert!(
            set(&mut T::default(), &field, 0.0),
            "{rust_name}.{field} documents {r:?} but the test cannot set it"
        );
        let integer = doc.contains("cycles")
            || field.starts_with("max_")
            || field.ends_with("depth")
            || field.ends_with("segments")
            || field.ends_with("rings")
            || field.starts_with("atlas_");
        let step = |v: f64| {
            if integer {
                1.0
            } else {
                (v.abs() * 1e-3).max(1e-3)
            }
        };
        let accepts = |v: f64| {
            let mut t = T::default();
            set(&mut t, &field, v);
            valid(&t)
        };
        if let Some((lo, inclusive)) = r.lo {
            assert_eq!(accepts(lo), inclusive, "{rust_name}.{field} = {lo} ({doc})");
            // An unsigned field has nothing below 0.
            if !(integer && lo <= 0.0) {
                assert!(
                    !accepts(lo - step(lo)),
                    "{rust_name}.{field} below {lo} ({doc})"
                );
            }
            assert!(
                accepts(lo + step(lo)),
                "{rust_name}.{field} just above {lo} ({doc})"
            );
        }
        if let Some((hi, inclusive)) = r.hi {
            assert_eq!(accepts(hi), inclusive, "{rust_name}.{field} = {hi} ({doc})");
            assert!(
                !accepts(hi + step(hi)),
                "{rust_name}.{field} above {hi} ({doc})"
            );
            assert!(
                accepts(hi - step(hi)),
                "{rust_name}.{field} just below {hi} ({doc})"
            );
        }
        let (_, c_doc) = c_docs
            .iter()
            .find(|(f, _)| *f == field)
            .unwrap_or_else(|| panic!("{c_name} has no field {field}"));
        assert_eq!(
            range(c_doc).as_ref(),
            Some(&r),
            "{c_name}.{field} documents another range than {rust_name}.{field}: {c_doc} / {doc}"
        );
        checked += 1;
    }
    checked
}

#[test]
fn growth_params_ranges_are_the_documented_ones() {
    // The declaration's own bounded fields: a documented range without a bound fails.
    let set = |p: &mut GrowthParams, field: &str, v: f64| p.set_bounded(field, v);
    let n = check(
        "src/models/growth/params.rs",
        "GrowthParams",
        "ArborGrowthParams",
        &set,
        &|p: &GrowthParams| p.validate().is_ok(),
    );
    assert!(n >= 21, "only {n} documented ranges found");
}

#[test]
fn world_options_ranges_are_the_documented_ones() {
    let set = |o: &mut WorldOptions, field: &str, v: f64| {
        if field == "cell_size" {
            // A small box, so a fine grid stays within max_cells.
            o.max = [0.5, 0.5, 0.5];
            o.min = [0.0, 0.0, 0.0];
            o.max_cells = 1 << 31;
        }
        o.set_bounded(field, v)
    };
    let n = check(
        "src/models/growth/mod.rs",
        "WorldOptions",
        "ArborWorldOptions",
        &set,
        &|o: &WorldOptions| o.validate().is_ok(),
    );
    assert!(n >= 5, "only {n} documented ranges found");
}

#[test]
fn mesh_options_ranges_are_the_documented_ones() {
    let set = |o: &mut MeshOptions, field: &str, v: f64| o.set_bounded(field, v);
    let n = check(
        "src/mesh/options.rs",
        "MeshOptions",
        "ArborMeshOptions",
        &set,
        &|o: &MeshOptions| o.validate().is_ok(),
    );
    assert!(n >= 4, "only {n} documented ranges found");
}

#[test]
fn leaf_options_ranges_are_the_documented_ones() {
    let set = |o: &mut LeafOptions, field: &str, v: f64| o.set_bounded(field, v);
    let n = check(
        "src/mesh/leaves.rs",
        "LeafOptions",
        "ArborLeafOptions",
        &set,
        &|o: &LeafOptions| o.validate().is_ok(),
    );
    assert!(n >= 3, "only {n} documented ranges found");
}

#[test]
fn ranges_are_read_as_written() {
    let r = |lo, li, hi, hi_in| {
        Some(Range {
            lo: Some((lo, li)),
            hi: Some((hi, hi_in)),
        })
    };
    assert_eq!(range("λ in [0, 1]: 0.5 neutral"), r(0.0, true, 1.0, true));
    assert_eq!(
        range("World units, in (0, 10000]."),
        r(0.0, false, 1e4, true)
    );
    assert_eq!(range("η, −1..=1. Default 0.1."), r(-1.0, true, 1.0, true));
    assert_eq!(
        range("ξ ≥ 0: weight"),
        Some(Range {
            lo: Some((0.0, true)),
            hi: None
        })
    );
    assert_eq!(
        range("Finite, > 0. Default 0.25"),
        Some(Range {
            lo: Some((0.0, false)),
            hi: None
        })
    );
    assert_eq!(range("Seeds the markers. Default 0."), None);
}
