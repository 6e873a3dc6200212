use super::*;

fn pp(text: &str) -> String {
    preprocess(text, "", Includes::None).unwrap().text
}

fn pp_err(text: &str) -> String {
    match preprocess(text, "", Includes::None) {
        Err(Error::Parse { line, message, .. }) => format!("{line}: {message}"),
        other => panic!("expected an error, got {other:?}"),
    }
}

#[test]
fn object_and_function_like_macros() {
    let out = pp("#define N 3\n#define SQ(x) ((x)*(x))\nA(N) SQ(N+1)\n");
    assert_eq!(out.lines().nth(2).unwrap(), "A(3) ((3+1)*(3+1))");
    // Macros that expand to parameter lists and to several statements.
    let out = pp("#define P 1,2\n#define S a=1; b=2;\nF(P) { S }\n");
    assert_eq!(out.lines().nth(2).unwrap(), "F(1,2) { a=1; b=2; }");
    // A function-like name without `(` is left alone; `#` and `##`.
    let out =
        pp("#define f(x) g(x)\n#define STR(x) #x\n#define CAT(a,b) a##b\nf + STR(a b) CAT(x,1)\n");
    assert_eq!(out.lines().nth(3).unwrap(), "f + \"a b\" x1");
    // Rescanning: a macro's result is expanded again.
    let out = pp("#define A B\n#define B 7\nA\n");
    assert_eq!(out.lines().nth(2).unwrap(), "7");
}

#[test]
fn undef_conditionals_continuations_and_comments() {
    let src = "#define X 1\n#ifdef X\nyes\n#else\nno\n#endif\n#undef X\n#ifndef X\nundone\n#endif\n\
               #if defined(X) || 2 > 1 && !0\nif\n#elif 1\nelif\n#endif\n\
               F(1,\\\n2) // two rolls? no: a comment\nG /* inline */ H\n";
    let out = pp(src);
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines.contains(&"yes"));
    assert!(!lines.contains(&"no"));
    assert!(lines.contains(&"undone"));
    assert!(lines.contains(&"if"));
    assert!(!lines.contains(&"elif"));
    assert!(lines.iter().any(|l| l.trim_end() == "F(1,2)"));
    assert!(lines.iter().any(|l| l.trim_end() == "G   H"));
    // `//` in a string is not a comment.
    assert!(pp("printf(\"a//b\");").contains("a//b"));
}

#[test]
fn lines_map_back_to_the_file() {
    let p = preprocess(
        "#define A 1\n/* a\n comment */\nB\n#if 0\nx\n#endif\nC\n",
        "",
        Includes::None,
    )
    .unwrap();
    let lines: Vec<&str> = p.text.lines().collect();
    let b = lines.iter().position(|l| l.trim() == "B").unwrap();
    let c = lines.iter().position(|l| l.trim() == "C").unwrap();
    assert_eq!(p.origin(b as u32 + 1), (None, 4));
    assert_eq!(p.origin(c as u32 + 1), (None, 8));
}

#[test]
fn a_call_may_span_lines() {
    let p = preprocess("#define M(a,b) a+b\nX M(1,\n2) Y\nZ\n", "", Includes::None).unwrap();
    let lines: Vec<&str> = p.text.lines().collect();
    assert_eq!(lines[1], "X 1+2 Y");
    assert_eq!(lines[3], "Z");
    assert_eq!(p.origin(4), (None, 4));
}

#[test]
fn malformed_input_gets_clear_errors() {
    assert!(pp_err("#define M(a) a\nM(1\n").contains("unterminated macro call"));
    assert!(pp_err("#define M(a, b\n").contains("unterminated #define"));
    assert!(pp_err("#define A B\n#define B A\nA\n").contains("recursive"));
    assert!(pp_err("#define A A\nA\n").contains("recursive"));
    assert!(pp_err("#if 1\nx\n").starts_with("1: "));
    assert!(pp_err("#endif\n").contains("without an `#if`"));
    assert!(pp_err("#include \"x.h\"\n").contains("needs the grammar's folder"));
    assert!(pp_err("/* open\n").contains("unterminated comment"));
    assert!(pp_err("#define M(a) a\nM(1,2)\n").contains("1 argument"));
    assert!(pp_err("#if 1 +\n#endif\n").contains("#if"));
    // Exponential macros stop at the token bound.
    let mut src = String::from("#define A0 x\n");
    for i in 1..40 {
        src.push_str(&format!("#define A{i} A{} A{}\n", i - 1, i - 1));
    }
    src.push_str("A39\n");
    assert!(pp_err(&src).contains("more than"));
    // Deep conditionals: bounded, with an error past the limit.
    let deep = "#if 1\n".repeat(100_000);
    assert!(pp_err(&deep).contains("nested deeper"));
    let fine = format!("{}x\n{}", "#if 1\n".repeat(4000), "#endif\n".repeat(4000));
    assert!(pp(&fine).lines().any(|l| l == "x"));
}
