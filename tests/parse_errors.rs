//! Malformed grammars: each gives a parse error with the line and column it must report
//! and says what was expected (or names the unsupported construct).

use arbor::Error;
use arbor::lsystem::LSystem;

#[rustfmt::skip]
const CASES: &[(&str, u32, u32, &str)] = &[
        ("Axiom: F(", 1, 10, "an expression (a number, a name or `(`)"),
        ("Axiom: F(1", 1, 11, "`,` or `)` after a module parameter"),
        ("Axiom: F(1,)", 1, 12, "an expression (a number, a name or `(`)"),
        ("Axiom: F)", 1, 9, "a module (a letter or a turtle symbol)"),
        ("Axiom: F(1 2)", 1, 12, "`,` or `)` after a module parameter"),
        ("Axiom: [F", 1, 8, "unbalanced brackets: this `[` is never c"),
        ("Axiom: F]", 1, 9, "unbalanced brackets: this `]` closes no "),
        ("Axiom: F(zz[1])", 1, 10, "`zz` is subscripted but never declared "),
        ("Axiom: F(foo(1))", 1, 10, "a function: sin cos tan asin acos atan a"),
        ("Axiom: F(min(1))", 1, 10, "2 argument(s) to `min`, not 1"),
        ("Axiom: @", 1, 9, "a letter after `@` (such as @M, @R or @v"),
        ("Axiom: @1", 1, 9, "a letter after `@` (such as @M, @R or @v"),
        ("Axiom: F\nAxiom: F", 2, 1, "one `Axiom:` line only"),
        ("F --> F", 1, 8, "an `Axiom:` line"),
        ("Axiom: F\nF -> [F", 2, 6, "unbalanced brackets: this `[` is never c"),
        ("Axiom: F\nF --> F]", 2, 8, "unbalanced brackets: this `]` closes no "),
        ("Axiom: F\n --> F", 2, 2, "a predecessor module before `-->`"),
        ("Axiom: F\n[ --> F", 2, 1, "a bracket alone as a predecessor is rewr"),
        ("Axiom: F\nF(x, x) --> F", 2, 6, "a parameter name not used before in this"),
        ("Axiom: F\nF(1) --> F", 2, 3, "a parameter name"),
        ("Axiom: F\nF(x) --> F(x[0])", 2, 12, "`x[` subscripts a name that is not an ar"),
        ("Axiom: F\nF(x) : x > --> F", 2, 12, "an expression (a number, a name or `(`)"),
        ("Axiom: F\nF(x) : { y = ; } --> F", 2, 14, "an expression (a number, a name or `(`)"),
        ("Axiom: F\nF(x) : x > 0 { } z --> F", 2, 18, "`-->` after the condition"),
        ("Axiom: F\nF --> F :", 2, 10, "an expression (a number, a name or `(`)"),
        ("Axiom: F\nF --> F : -1", 2, 11, "a finite probability >= 0"),
        ("Axiom: F\nF --> F : 1 2", 2, 13, "the end of the production after its prob"),
        ("Axiom: F\n[A < B --> F", 2, 1, "brackets are supported in a right contex"),
        ("Axiom: F\nF", 2, 1, "a production with `-->` or a directive s"),
        ("Axiom: F\nhello world", 2, 1, "a production with `-->` or a directive s"),
        ("/* open comment\nAxiom: F", 1, 1, "unterminated comment: `/*` has no closin"),
        ("Axiom: F /* x", 1, 10, "unterminated comment: `/*` has no closin"),
        ("#include \"foo.h\"\nAxiom: F", 1, 1, "#include \"foo.h\" needs the grammar's fo"),
        ("#define\nAxiom: F", 1, 1, "a macro name after `#define`"),
        ("#define 3x 1\nAxiom: F", 1, 1, "a macro name after `#define`"),
        ("#define M(a\nAxiom: F", 1, 1, "`)` closing the parameters of a function"),
        ("#define A B\n#define B A\nAxiom: A", 3, 1, "the macro `A` expands to itself (recursi"),
        ("derivation length: -1\nAxiom: F", 1, 20, "a whole number of steps from 0 to 4294967295"),
        ("derivation length: 2.5\nAxiom: F", 1, 20, "a whole number of steps from 0 to 4294967295"),
        ("derivation length: x\nAxiom: F", 1, 20, "a number or a #define name (this name is"),
        ("seed: -3\nAxiom: F", 1, 7, "a whole, non-negative seed"),
        ("Start: { x = ; }\nAxiom: F", 1, 14, "an expression (a number, a name or `(`)"),
        ("End: { while (1 }\nAxiom: F", 1, 17, "`)` closing the condition of `while`"),
        ("define: { array a[0]; }\nAxiom: F", 1, 19, "a constant array size from 1 to 4194304"),
        ("Axiom: F\nF --> F(vvXmin(1))", 2, 9, "`vvXmin()` needs cpfg's viewer, which ar"),
        ("Lsystem: 1\nAxiom: F\nendlsystem\nLsystem: 2", 4, 1, "sub-L-systems (a second `Lsystem:`) are "),
        ("Lsystem: 1\nAxiom: F\nendlsystem\nF --> G", 4, 1, "nothing after `endlsystem`"),
        ("ignore: +\nconsider: F\nAxiom: F", 2, 1, "one `ignore:` or `consider:` line, not b"),
        ("maximum depth: 3\nAxiom: F", 1, 1, "`maximum depth:` after `homomorphism` or"),
        ("homomorphism\nmaximum depth: -2\nAxiom: F", 2, 16, "a whole maximum depth from 0 to 1000"),
        ("decomposition\nA < B --> F\nAxiom: F", 2, 1, "context in decomposition rules"),
        ("angle increment: abc\nAxiom: F", 1, 18, "a number or a #define name (this name is"),
        ("tropism: 0 -1 0\nAxiom: F", 1, 10, "`T:` and the tropism vector (tropism: T:"),
        ("tropism: T: 0 -1\nAxiom: F", 1, 17, "a number or a #define name"),
        ("tropism: T: 0 -1 0 E:\nAxiom: F", 1, 22, "a number or a #define name"),
        ("Axiom: F(1 +* 2)", 1, 13, "an expression (a number, a name or `(`)"),
        ("Axiom: F(sin(1,2,3))", 1, 10, "1 argument(s) to `sin`, not 3"),
        ("Axiom: F(1 ? 2)", 1, 15, "`:` of a `?:` expression"),
        ("Lsystem: 1", 1, 11, "an `Axiom:` line"),
];

#[test]
fn every_malformed_grammar_reports_its_position() {
    assert!(CASES.len() >= 40);
    for &(source, line, column, expected) in CASES {
        match LSystem::parse(source) {
            Err(Error::Parse {
                line: l,
                column: c,
                message,
            }) => {
                assert_eq!((l, c), (line, column), "{source:?}: {message}");
                assert!(message.contains(expected), "{source:?}: {message}");
            }
            other => panic!("{source:?}: expected a parse error, got {other:?}"),
        }
    }
}

#[test]
fn hostile_text_is_refused_cleanly() {
    let deep = format!("Axiom: F({}1{})", "(".repeat(100_000), ")".repeat(100_000));
    assert!(matches!(LSystem::parse(&deep), Err(Error::Parse { .. })));
    let brackets = format!("Axiom: {}F{}", "[".repeat(100_000), "]".repeat(100_000));
    let ls = LSystem::parse(&brackets).unwrap();
    let s = ls.skeleton(&Default::default()).unwrap();
    assert_eq!(s.len(), 1);
    // A long macro name is C: fine.
    let long_name = format!("#define {} 1\nAxiom: F", "x".repeat(10_000));
    assert!(LSystem::parse(&long_name).is_ok());
    assert!(matches!(LSystem::parse(""), Err(Error::Parse { .. })));
    // Keywords are case-insensitive, as in cpfg.
    assert!(LSystem::parse("LSYSTEM: 1\nAXIOM: F\nDerivation Length: 2\nENDLSYSTEM").is_ok());
}

/// Where the character at byte `at` of `text` stands: its 1-based line and column (in
/// characters).
fn place_of(text: &str, at: usize) -> (u32, u32) {
    let before = &text[..at];
    let line = before.matches('\n').count() as u32 + 1;
    let start = before.rfind('\n').map_or(0, |k| k + 1);
    (line, before[start..].chars().count() as u32 + 1)
}

/// What may stand between two tokens of a production without changing it: a
/// `\`-newline splice (LF or CRLF), a block comment on one line. (A comment over several
/// lines, like a line comment, ends the production's line.)
const JOINS: &[&str] = &[" \\\n", "\\\n", " /* a */ ", " \\\r\n ", "/**/"];

proptest::proptest! {
    /// The position of a parse error is the offending character's line and column in the
    /// file's own text, whatever splices, comments and macros stand before it on its line
    /// or on lines before it.
    #[test]
    fn error_positions_are_in_the_files_own_text(
        joins in proptest::collection::vec((0usize..64, 0usize..JOINS.len()), 0..6),
        macro_before in proptest::bool::ANY,
    ) {
        // Tokens of a production whose last token, `)`, is the error.
        let head = if macro_before {
            "#define W F(1)\n/* a comment\nover lines */ Axiom: A\n"
        } else {
            "Axiom: /* a */ A \\\n\n"
        };
        let tokens: &[&str] = &[
            "A", "-->", if macro_before { "W" } else { "F(1)" }, "[", "+", "A", "]", "G",
        ];
        let mut text = head.to_string();
        let mut seps = vec![" "; tokens.len()];
        for (at, j) in &joins {
            seps[at % tokens.len()] = JOINS[*j];
        }
        for (t, sep) in tokens.iter().zip(&seps) {
            text += t;
            text += sep;
        }
        let at = text.len();
        text += ")\n";
        let want = place_of(&text, at);
        match LSystem::parse(&text) {
            Err(Error::Parse { line, column, message }) => {
                proptest::prop_assert_eq!((line, column), want, "{:?}: {}", text, message);
            }
            other => proptest::prop_assert!(false, "{:?}: {:?}", text, other.map(|_| ())),
        }
    }
}

/// round4/error_column_after_continuation.l, in kind: a line ending in `\` is joined
/// with the next, and the error after the join is told on the next line, at its column
/// there.
#[test]
fn an_error_after_a_continuation_is_told_on_its_own_line() {
    let text = "Lsystem: 1\nignore: C~#\\\nangle increment: -30\nAxiom: F\n";
    match LSystem::parse(text) {
        Err(Error::Parse { line, column, .. }) => assert_eq!((line, column), (3, 16)),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

/// An error inside an included file is told at that file's own name, line and column,
/// after splices and comments there.
#[test]
fn an_error_in_an_included_file_is_told_in_that_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("rules.h"),
        "/* rules */\nA --> F \\\n [+A] /* x */ )\n",
    )
    .unwrap();
    let main = dir.path().join("plant.l");
    std::fs::write(
        &main,
        "Lsystem: 1\nAxiom: A\n#include \"rules.h\"\nendlsystem\n",
    )
    .unwrap();
    match LSystem::from_file(&main, None) {
        Err(Error::Parse {
            line,
            column,
            message,
        }) => {
            assert_eq!((line, column), (3, 15), "{message}");
            assert!(message.contains("rules.h"), "{message}");
        }
        other => panic!("expected a parse error, got {other:?}"),
    }
}
