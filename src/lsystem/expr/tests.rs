use super::*;

fn eval_with(text: &str, params: &[(&str, f64)]) -> Result<f64, String> {
    let names: Vec<(String, u16)> = params
        .iter()
        .enumerate()
        .map(|(i, (n, _))| (n.to_string(), i as u16))
        .collect();
    let args: Vec<f64> = params.iter().map(|&(_, v)| v).collect();
    let mut defines = HashMap::new();
    defines.insert("q".to_string(), 0.5);
    let globals = RefCell::new(Globals::default());
    let scope = Scope {
        params: &names,
        defines: &defines,
        globals: Some(&globals),
    };
    let mut cur = Cursor::new(text);
    let e = compile(&mut cur, &scope).map_err(|e| e.expected)?;
    cur.skip_ws();
    if !cur.at_end() {
        return Err(format!("stopped at {}", cur.pos()));
    }
    Ok(e.eval(
        &args,
        &mut Env::new(
            super::super::random::Random::Arbor(crate::rng::Rng::new(1)),
            &globals.borrow(),
            Vec::new().into(),
        ),
    ))
}

fn eval(text: &str) -> f64 {
    eval_with(text, &[("x", 3.0), ("y", 4.0)]).unwrap()
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(eval("1 + 2 * 3"), 7.0);
    assert_eq!(eval("(1 + 2) * 3"), 9.0);
    // cpfg's `^`: left-associative, looser than unary minus.
    assert_eq!(eval("2 ^ 3 ^ 2"), 64.0);
    assert_eq!(eval("-2 ^ 2"), 4.0);
    assert_eq!(eval("2 * 3 ^ 2"), 18.0);
    assert_eq!(eval("1 <> 2"), 1.0);
    assert_eq!(eval("7.5 % 4.9"), 3.0);
    assert_eq!(eval("2 ^ -1"), 0.5);
    assert_eq!(eval("10 - 4 - 3"), 3.0);
    assert_eq!(eval("x * q ^ 2"), 0.75);
    assert_eq!(eval("x < y && y <= 4 || 0"), 1.0);
    assert_eq!(eval("!(x == 3)"), 0.0);
    assert_eq!(eval("x != 3 ? 10 : y > 3 ? 20 : 30"), 20.0);
    assert_eq!(eval("7 % 4"), 3.0);
}

#[test]
fn functions_work_in_degrees() {
    assert!((eval("sin(30)") - 0.5).abs() < 1e-12);
    assert!((eval("cos(60)") - 0.5).abs() < 1e-12);
    assert!((eval("atan(1)") - 45.0).abs() < 1e-12);
    assert!((eval("atan(1, 0)") - 90.0).abs() < 1e-12);
    assert_eq!(eval("min(x, y) + max(x, y)"), 7.0);
    assert_eq!(
        eval("sign(-x) + fabs(-2) + floor(1.5) + ceil(1.5) + trunc(-1.5)"),
        3.0
    );
    assert_eq!(eval("sqrt(y) + exp(0) + log(1)"), 3.0);
    let r = eval("ran(x)");
    assert!((0.0..3.0).contains(&r));
}

#[test]
fn constants_fold_and_parameters_stay() {
    let scope_names = vec![("s".to_string(), 0u16)];
    let defines = HashMap::from([("r".to_string(), 0.5)]);
    let scope = Scope {
        params: &scope_names,
        defines: &defines,
        globals: None,
    };
    let e = compile(&mut Cursor::new("2 * r ^ 2 + sin(90)"), &scope).unwrap();
    assert_eq!(e, Expr::Const(1.5));
    let e = compile(&mut Cursor::new("s"), &scope).unwrap();
    assert_eq!(e, Expr::Param(0));
    let e = compile(&mut Cursor::new("s * (1 - r)"), &scope).unwrap();
    assert_eq!(
        e,
        Expr::Binary(Op::Mul, Operand::Param(0), Operand::Const(0.5))
    );
    let e = compile(&mut Cursor::new("s * s + 1"), &scope).unwrap();
    assert_eq!(
        e,
        Expr::Code(
            vec![Op::Param(0), Op::Param(0), Op::Mul, Op::Const(1.0), Op::Add].into(),
            2,
            5
        )
    );
}

#[test]
fn errors_say_what_was_expected() {
    assert!(eval_with("1 +", &[]).unwrap_err().contains("an expression"));
    // An unknown name is a global variable, 0 until assigned.
    assert_eq!(eval_with("zz + 1", &[]).unwrap(), 1.0);
    assert!(
        eval_with("zz[1]", &[])
            .unwrap_err()
            .contains("never declared as an array")
    );
    assert!(eval_with("foo(1)", &[]).unwrap_err().contains("a function"));
    assert!(eval_with("min(1)", &[]).unwrap_err().contains("2 argument"));
    assert!(eval_with("(1", &[]).unwrap_err().contains("`)`"));
    let deep = format!("{}1{}", "(".repeat(100_000), ")".repeat(100_000));
    assert!(eval_with(&deep, &[]).unwrap_err().contains("nested levels"));
    let long = vec!["1"; 100_000].join("+");
    assert_eq!(eval_with(&long, &[]).unwrap(), 100_000.0);
    let minus = format!("{}1", "-".repeat(100_001));
    assert_eq!(eval_with(&minus, &[]).unwrap(), -1.0);
}

#[test]
fn the_arrow_ends_an_expression() {
    let scope = Scope {
        params: &[],
        defines: &HashMap::new(),
        globals: None,
    };
    let mut cur = Cursor::new("1 > 0 --> F");
    assert_eq!(compile(&mut cur, &scope).unwrap(), Expr::Const(1.0));
    assert!(cur.peek_str("-->"));
    let mut cur = Cursor::new("2->F");
    assert_eq!(compile(&mut cur, &scope).unwrap(), Expr::Const(2.0));
}
