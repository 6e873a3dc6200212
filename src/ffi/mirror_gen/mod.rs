//! The generator of `src/ffi/mirrors.rs`, the C mirrors of the option structs (test-only).
//!
//! cbindgen reads plain Rust, not the `options!` declarations, so each growing C struct is
//! written out in `mirrors.rs`, generated from the Rust declaration ([`FieldInfo`]) and a
//! [`Spec`] of what only C has (`struct_size`, callbacks, paths, flags, renamed fields).
//! A field added to an option struct needs no edit here: run
//! `ARBOR_BLESS_MIRRORS=1 cargo test --lib --features regen-mirrors c_mirrors`, then
//! `ARBOR_BLESS_HEADER=1 cargo test --test header`, and add the field to the bindings.
//!
//! The layout is append-only: the committed `mirrors.rs` is the record of every published
//! layout, so the generator keeps its fields in their order and appends new ones (Rust
//! fields in declaration order, then new C-only fields); a published field that no longer
//! exists is refused.

mod specs;

use crate::options::FieldInfo;
use std::fmt::Write as _;

/// What a C mirror has beyond its Rust struct's fields.
pub(super) struct Spec {
    /// The C struct's name.
    pub c: &'static str,
    /// The Rust struct's path.
    pub rust: &'static str,
    /// The Rust struct's fields ([`options!`](crate::options::options)'s `FIELDS`).
    pub fields: &'static [FieldInfo],
    /// The C struct's documentation.
    pub doc: &'static str,
    /// Its derives.
    pub derive: &'static str,
    /// Fields only C has.
    pub c_only: &'static [COnly],
    /// Rust fields a C field of another name carries: (C name, Rust name).
    pub renamed: &'static [(&'static str, &'static str)],
    /// Rust fields no C field carries, with their value in `to_rust`; `computed` ones read
    /// the whole C struct (bound as `c`).
    pub rust_only: &'static [RustOnly],
    /// C types other than [`c_type`]'s rule: (field, Rust spelling of the C type).
    pub c_types: &'static [(&'static str, &'static str)],
    /// The C documentation of fields where the Rust documentation, translated, is not
    /// what a C user should read: (field, text).
    pub c_docs: &'static [(&'static str, &'static str)],
}

/// A field only the C struct has.
pub(super) struct COnly {
    pub name: &'static str,
    /// Its Rust spelling of the C type.
    pub ty: &'static str,
    pub doc: &'static str,
    /// Its value in `from_rust`: a constant, or (with `computed`) an expression of the Rust
    /// struct, bound as `r`.
    pub value: &'static str,
    pub computed: bool,
}

/// A Rust field no C field carries.
pub(super) struct RustOnly {
    pub name: &'static str,
    pub value: &'static str,
    pub computed: bool,
}

/// One field of the generated C struct.
struct CField {
    name: String,
    ty: String,
    doc: String,
}

/// The C type of a carried Rust field: the same, or how [`CField`](super::options::CField)
/// carries it (an enum or a flag as `u32`, an optional count as `i32`, a size as `u64`).
fn c_type(rust: &str) -> &str {
    match rust {
        "f32" | "u32" | "u64" | "i32" | "[f32; 3]" => rust,
        "bool" => "u32",
        "usize" => "u64",
        "f64" => "f32",
        "Option<u32>" => "i32",
        // Every other type is a `Numbered` enum (the mirror's conversion does not compile
        // otherwise).
        _ => "u32",
    }
}

/// `Enum::Variant` as its C constant, `ARBOR_ENUM_VARIANT` (`Error::X` as the status
/// `ARBOR_STATUS_X`); other code spans as they are.
fn c_name_of(span: &str) -> String {
    let parts: Vec<&str> = span.rsplit("::").take(2).collect();
    match parts.as_slice() {
        [variant, ty]
            if ty.starts_with(|c: char| c.is_ascii_uppercase())
                && variant.starts_with(|c: char| c.is_ascii_uppercase()) =>
        {
            let ty = if *ty == "Error" { "Status" } else { ty };
            format!(
                "ARBOR_{}_{}",
                heck::ToShoutySnakeCase::to_shouty_snake_case(ty),
                heck::ToShoutySnakeCase::to_shouty_snake_case(*variant)
            )
        }
        _ => span.to_string(),
    }
}

/// A Rust field's documentation as C reads it: links become their text, variants their
/// C constants, `true`/`false` 1/0, and an enum field says which C enum it takes.
fn translate_doc(doc: &[&str], rust_ty: &str) -> String {
    let text = doc.iter().map(|l| l.trim()).collect::<Vec<_>>().join(" ");
    let mut out = String::new();
    let mut rest = text.as_str();
    while let Some(open) = rest.find("[`") {
        out.push_str(&rest[..open]);
        let after = &rest[open + 2..];
        let Some(close) = after.find("`]") else {
            out.push_str(&rest[open..]);
            rest = "";
            break;
        };
        out.push_str(&c_name_of(&after[..close]));
        rest = &after[close + 2..];
        // A link target `(...)` after the span is dropped.
        if rest.starts_with('(') {
            if let Some(end) = rest.find(')') {
                rest = &rest[end + 1..];
            }
        }
    }
    out.push_str(rest);
    let out = out
        .replace("Default false", "Default 0")
        .replace("Default true", "Default 1");
    match c_type(rust_ty) {
        "u32" if rust_ty == "bool" => format!("1 or 0. {out}"),
        "u32" if rust_ty != "u32" => format!("An Arbor{rust_ty} value. {out}"),
        _ => out,
    }
}

/// The field names, in order, of `pub struct <c>` in a previous `mirrors.rs`.
fn recorded_fields(record: &str, c: &str) -> Vec<String> {
    let Some(start) = record.find(&format!("pub struct {c} {{")) else {
        return Vec::new();
    };
    let body = &record[start..];
    let body = &body[..body.find("\n}").unwrap_or(body.len())];
    body.lines()
        .skip(1)
        .filter_map(|l| l.trim().strip_prefix("pub "))
        .filter_map(|l| l.split(':').next())
        .filter(|&n| n != "struct_size")
        .map(str::to_string)
        .collect()
}

/// `text` wrapped into `///` lines at `indent`, within 100 columns.
fn doc_lines(out: &mut String, text: &str, indent: &str) {
    let width = 100 - indent.len() - 4;
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.len() + 1 + word.len() > width {
            let _ = writeln!(out, "{indent}/// {line}");
            line.clear();
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    let _ = writeln!(out, "{indent}/// {line}");
}

/// The C fields of `spec` in layout order: those of `record` first, then new ones.
fn layout(spec: &Spec, record: &str) -> Result<Vec<CField>, String> {
    let carried = spec
        .fields
        .iter()
        .filter(|f| !spec.rust_only.iter().any(|r| r.name == f.name))
        .map(|f| {
            let name = spec
                .renamed
                .iter()
                .find(|(_, r)| *r == f.name)
                .map_or(f.name, |(c, _)| *c);
            let doc = spec
                .c_docs
                .iter()
                .find(|(n, _)| *n == name)
                .map_or_else(|| translate_doc(f.doc, f.ty), |(_, d)| d.to_string());
            let ty = spec
                .c_types
                .iter()
                .find(|(n, _)| *n == name)
                .map_or(c_type(f.ty), |(_, t)| *t);
            CField {
                name: name.to_string(),
                ty: ty.to_string(),
                doc,
            }
        });
    let only = spec.c_only.iter().map(|o| CField {
        name: o.name.to_string(),
        ty: o.ty.to_string(),
        doc: o.doc.to_string(),
    });
    let mut all: Vec<Option<CField>> = carried.chain(only).map(Some).collect();
    let mut out = Vec::new();
    for name in recorded_fields(record, spec.c) {
        let Some(f) = all
            .iter_mut()
            .find(|f| f.as_ref().is_some_and(|f| f.name == name))
        else {
            return Err(format!(
                "{}.{name} is in the published layout but neither {} nor the spec has it: a \
                 C field is never removed (keep it as a C-only field)",
                spec.c, spec.rust
            ));
        };
        out.push(f.take().expect("found above"));
    }
    out.extend(all.into_iter().flatten());
    Ok(out)
}

/// The source of one C mirror: the struct and its `mirror!`.
fn mirror_source(spec: &Spec, record: &str) -> Result<String, String> {
    let fields = layout(spec, record)?;
    let mut s = String::new();
    doc_lines(&mut s, spec.doc, "");
    let _ = writeln!(
        s,
        "#[repr(C)]\n#[derive({})]\npub struct {} {{",
        spec.derive, spec.c
    );
    let init = heck::ToSnakeCase::to_snake_case(spec.c) + "_init()";
    doc_lines(
        &mut s,
        &format!(
            "sizeof({}) as the host was compiled; set by {init}.",
            spec.c
        ),
        "    ",
    );
    s.push_str("    pub struct_size: u32,\n");
    for f in &fields {
        doc_lines(&mut s, &f.doc, "    ");
        let _ = writeln!(s, "    pub {}: {},", f.name, f.ty);
    }
    s.push_str("}\n\n");

    let is_only = |n: &str| spec.c_only.iter().any(|o| o.name == n);
    let renamed = |n: &str| spec.renamed.iter().any(|(c, _)| *c == n);
    let same: Vec<&str> = fields
        .iter()
        .map(|f| f.name.as_str())
        .filter(|n| !is_only(n) && !renamed(n))
        .collect();
    let rust = spec.rust.rsplit("::").next().unwrap_or(spec.rust);
    let _ = writeln!(s, "mirror!({} => {rust} {{", spec.c);
    list(&mut s, "same", same.iter().map(|n| n.to_string()));
    list(
        &mut s,
        "renamed",
        spec.renamed.iter().map(|(c, r)| format!("{c} = {r}")),
    );
    let ordered_only = fields
        .iter()
        .filter_map(|f| spec.c_only.iter().find(|o| o.name == f.name));
    let (computed, constant): (Vec<&COnly>, Vec<&COnly>) = ordered_only.partition(|o| o.computed);
    list(
        &mut s,
        "c_only",
        constant.iter().map(|o| format!("{}: {}", o.name, o.value)),
    );
    list(
        &mut s,
        "rust_only",
        spec.rust_only
            .iter()
            .filter(|r| !r.computed)
            .map(|r| format!("{}: {}", r.name, r.value)),
    );
    if spec.rust_only.iter().any(|r| r.computed) {
        list(
            &mut s,
            "to_rust(c)",
            spec.rust_only
                .iter()
                .filter(|r| r.computed)
                .map(|r| format!("{}: {}", r.name, r.value)),
        );
    }
    if !computed.is_empty() {
        list(
            &mut s,
            "to_c(r)",
            computed.iter().map(|o| format!("{}: {}", o.name, o.value)),
        );
    }
    s.push_str("});\n");
    Ok(s)
}

/// `    name { a, b, }` with one item per line (an empty list on one line).
fn list(s: &mut String, name: &str, items: impl Iterator<Item = String>) {
    let items: Vec<String> = items.collect();
    if items.is_empty() {
        let _ = writeln!(s, "    {name} {{}}");
        return;
    }
    let _ = writeln!(s, "    {name} {{");
    for item in items {
        let _ = writeln!(s, "        {item},");
    }
    s.push_str("    }\n");
}

const HEADER: &str = "\
// @generated by `ARBOR_BLESS_MIRRORS=1 cargo test --lib --features regen-mirrors c_mirrors`
// from the options! declarations and src/ffi/mirror_gen/specs.rs; do not edit. The C structs
// of the option structs that grow, for cbindgen (see src/ffi/mirror_gen/mod.rs).

use super::*;
";

/// The whole `mirrors.rs` for `specs`, keeping the layouts `record` published.
fn generate(specs: &[Spec], record: &str) -> Result<String, String> {
    let mut s = HEADER.to_string();
    for spec in specs {
        let _ = writeln!(s, "use {};", spec.rust);
    }
    for spec in specs {
        s.push('\n');
        s.push_str(&mirror_source(spec, record)?);
    }
    Ok(s)
}

#[test]
fn c_mirrors_are_generated_from_the_options() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/src/ffi/mirrors.rs");
    let old = std::fs::read_to_string(path).unwrap_or_default();
    let new = generate(specs::SPECS, &old).unwrap();
    if std::env::var_os("ARBOR_BLESS_MIRRORS").is_some() {
        std::fs::write(path, &new).unwrap();
        return;
    }
    if let Some((k, (a, b))) = old
        .lines()
        .zip(new.lines())
        .enumerate()
        .find(|(_, (a, b))| a != b)
    {
        panic!(
            "src/ffi/mirrors.rs is stale at line {}:\n  committed: {a}\n  generated: {b}\nrun \
             `ARBOR_BLESS_MIRRORS=1 cargo test --lib --features regen-mirrors c_mirrors`, then \
             `ARBOR_BLESS_HEADER=1 cargo test --test header`",
            k + 1
        );
    }
    assert_eq!(
        old.lines().count(),
        new.lines().count(),
        "src/ffi/mirrors.rs is stale"
    );
}

#[cfg(test)]
mod generator_tests {
    use super::*;

    static FIELDS: &[FieldInfo] = &[
        FieldInfo {
            name: "a",
            ty: "f32",
            doc: &[" First. Default [`Tip::Open`]."],
        },
        FieldInfo {
            name: "b",
            ty: "bool",
            doc: &[" Second. Default false."],
        },
        FieldInfo {
            name: "c",
            ty: "Tip",
            doc: &[" Third, see [`Error::LimitExceeded`](x)."],
        },
    ];

    fn spec(fields: &'static [FieldInfo]) -> Spec {
        Spec {
            c: "ArborThing",
            rust: "Thing",
            fields,
            doc: "A thing.",
            derive: "Clone, Copy",
            c_only: &[COnly {
                name: "progress",
                ty: "ArborProgressFn",
                doc: "Called.",
                value: "None",
                computed: false,
            }],
            renamed: &[],
            rust_only: &[],
            c_types: &[],
            c_docs: &[],
        }
    }

    #[test]
    fn a_new_field_is_appended_after_the_published_layout() {
        let first = generate(&[spec(&FIELDS[..2])], "").unwrap();
        assert_eq!(
            recorded_fields(&first, "ArborThing"),
            ["a", "b", "progress"]
        );
        let grown = generate(&[spec(FIELDS)], &first).unwrap();
        assert_eq!(
            recorded_fields(&grown, "ArborThing"),
            ["a", "b", "progress", "c"]
        );
        assert!(grown.contains("    pub c: u32,"), "{grown}");
        assert!(grown.contains("/// An ArborTip value. Third, see ARBOR_STATUS_LIMIT_EXCEEDED."));
        assert!(grown.contains("/// 1 or 0. Second. Default 0."));
        assert!(grown.contains("/// First. Default ARBOR_TIP_OPEN."));
        assert!(
            grown.contains("same {\n        a,\n        b,\n        c,\n    }"),
            "{grown}"
        );
    }

    #[test]
    fn a_published_field_is_never_removed() {
        let first = generate(&[spec(FIELDS)], "").unwrap();
        let e = generate(&[spec(&FIELDS[..2])], &first).unwrap_err();
        assert!(e.contains("ArborThing.c is in the published layout"), "{e}");
    }
}
