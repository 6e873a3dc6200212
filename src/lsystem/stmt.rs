//! Statements: cpfg's C-like blocks (`Start:`, `End:`, `StartEach:`, `EndEach:`, and the
//! `{ }` of a production before and after its condition).
//!
//! `name = e;` (also `+= -= *= /=`) for a parameter of the production, a global variable
//! or an array element; `if (c) s [else s]`, `while (c) s`, `do s while (c);`, `{ ... }`,
//! `printf("format", e, ...);` to the grammar's log, `stop();` (the derivation ends after
//! the current step), and any expression as a statement (`srand(7);`).

use super::expr::{self, Env, Expr, Scope};
use super::syntax::{Cursor, PResult};

/// Most bytes `printf` writes to a derivation's log; the rest is dropped.
pub(crate) const MAX_LOG_BYTES: usize = 64 << 10;
/// Deepest nesting of blocks and control statements.
const MAX_BLOCK_NESTING: usize = 64;

/// Where an assignment stores.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Target {
    Param(u16),
    Var(u32),
    /// Array and one index per dimension.
    Elem(u16, Vec<Expr>),
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Stmt {
    /// Target, operator (`None` for `=`, else the binary op of `+=` ...), value.
    Set(Target, Option<expr::Op>, Expr),
    If(Expr, Vec<Stmt>, Vec<Stmt>),
    While(Expr, Vec<Stmt>),
    DoWhile(Vec<Stmt>, Expr),
    Eval(Expr),
    Printf(Box<str>, Vec<Expr>),
    Stop,
}

/// The run-time state statements change besides the variables, and the work budget
/// every part of a derivation spends from.
#[derive(Debug, Default)]
pub(crate) struct Effects<'a> {
    /// Work units left before the budget (`max_work`) is spent: rewriting, decomposition,
    /// interpretation rules, statements and queries all spend from it (see
    /// docs/c-api.md, "Robustness").
    pub(crate) budget: u64,
    pub(crate) log: String,
    pub(crate) stop: bool,
    /// The caller's progress callback: it hears the work every [`REPORT_UNITS`] units.
    pub(crate) progress: crate::progress::Run<'a>,
    /// What it hears: the stage and the fraction done when the units were spent.
    pub(crate) stage: crate::progress::Stage,
    pub(crate) fraction: f64,
    /// The budget left at which the next report is due.
    report_at: u64,
}

/// Work units between two reports to the progress callback: at most 7.5 ms of the
/// slowest work measured on the machine the default limits were set on (see
/// docs/c-api.md, "Robustness"), so that a callback that asks to stop is heard well within
/// 100 ms.
pub(crate) const REPORT_UNITS: u64 = 1 << 20;

/// Parses `{ statements }` at the cursor (which must be at `{`).
pub(crate) fn block(cur: &mut Cursor<'_>, scope: &Scope<'_>) -> PResult<Vec<Stmt>> {
    block_at(cur, scope, 0)
}

fn block_at(cur: &mut Cursor<'_>, scope: &Scope<'_>, depth: usize) -> PResult<Vec<Stmt>> {
    cur.skip_ws();
    if !cur.eat("{") {
        return Err(cur.error("`{` opening a block of statements"));
    }
    if depth > MAX_BLOCK_NESTING {
        return Err(cur.error(&format!("blocks nested at most {MAX_BLOCK_NESTING} deep")));
    }
    let mut out = Vec::new();
    loop {
        cur.skip_ws();
        if cur.eat("}") {
            return Ok(out);
        }
        if cur.at_end() {
            return Err(cur.error("`}` closing the block of statements"));
        }
        if cur.eat(";") {
            continue;
        }
        statement(cur, scope, depth, &mut out)?;
    }
}

/// One statement, or a block spliced in place.
fn statement(
    cur: &mut Cursor<'_>,
    scope: &Scope<'_>,
    depth: usize,
    out: &mut Vec<Stmt>,
) -> PResult<()> {
    cur.skip_ws();
    if cur.peek_str("{") {
        out.extend(block_at(cur, scope, depth + 1)?);
        return Ok(());
    }
    let save = cur.clone();
    let word = cur.identifier();
    let body = |cur: &mut Cursor<'_>| -> PResult<Vec<Stmt>> {
        let mut v = Vec::new();
        cur.skip_ws();
        if cur.eat(";") {
            return Ok(v);
        }
        statement(cur, scope, depth + 1, &mut v)?;
        Ok(v)
    };
    let paren = |cur: &mut Cursor<'_>, what: &str| condition(cur, scope, what);
    if depth > MAX_BLOCK_NESTING {
        return Err(cur.error(&format!(
            "statements nested at most {MAX_BLOCK_NESTING} deep"
        )));
    }
    match word {
        Some("if") => {
            let c = paren(cur, "if")?;
            let then = body(cur)?;
            let after = cur.clone();
            cur.skip_ws();
            let otherwise = if cur.identifier() == Some("else") {
                body(cur)?
            } else {
                *cur = after;
                Vec::new()
            };
            out.push(Stmt::If(c, then, otherwise));
            return Ok(());
        }
        Some("while") => {
            let c = paren(cur, "while")?;
            let b = body(cur)?;
            out.push(Stmt::While(c, b));
            return Ok(());
        }
        Some("do") => {
            let b = body(cur)?;
            cur.skip_ws();
            if cur.identifier() != Some("while") {
                return Err(cur.error("`while (condition);` after the body of `do`"));
            }
            let c = paren(cur, "do ... while")?;
            end_of_statement(cur)?;
            out.push(Stmt::DoWhile(b, c));
            return Ok(());
        }
        Some(f @ ("printf" | "fprintf")) => {
            out.push(printf_call(cur, scope, f)?);
            return Ok(());
        }
        Some("fscanf") => {
            fscanf_call(cur, scope)?;
            return Ok(());
        }
        Some("fclose") | Some("fflush") => {
            file_call(cur, scope)?;
            return Ok(());
        }
        Some("stop") | Some("Stop") => {
            out.push(stop_call(cur, scope)?);
            return Ok(());
        }
        Some(name) => {
            // An assignment? `name [= += ...]` or `name[i]... =`.
            if let Some(stmt) = assignment(cur, scope, name)? {
                end_of_statement(cur)?;
                out.push(stmt);
                return Ok(());
            }
            *cur = save;
        }
        None => {}
    }
    let e = expr::compile(cur, scope)?;
    end_of_statement(cur)?;
    out.push(Stmt::Eval(e));
    Ok(())
}

/// `(condition)` after `what` (`if`, `while`, `do ... while`).
fn condition(cur: &mut Cursor<'_>, scope: &Scope<'_>, what: &str) -> PResult<Expr> {
    cur.skip_ws();
    if !cur.eat("(") {
        return Err(cur.error(&format!("`(` after `{what}`")));
    }
    let e = expr::compile(cur, scope)?;
    cur.skip_ws();
    if !cur.eat(")") {
        return Err(cur.error(&format!("`)` closing the condition of `{what}`")));
    }
    Ok(e)
}

/// `printf("format", ...)` or `fprintf(fp, "format", ...)` after its name `f`: files
/// opened for writing go to the log too.
fn printf_call(cur: &mut Cursor<'_>, scope: &Scope<'_>, f: &str) -> PResult<Stmt> {
    cur.skip_ws();
    if !cur.eat("(") {
        return Err(cur.error(&format!("`(` after `{f}`")));
    }
    if f == "fprintf" {
        let _handle = expr::compile(cur, scope)?;
        cur.skip_ws();
        if !cur.eat(",") {
            return Err(cur.error("`,` after the file of fprintf"));
        }
    }
    cur.skip_ws();
    let fmt = string_literal(cur)?;
    let mut args = Vec::new();
    loop {
        cur.skip_ws();
        if cur.eat(")") {
            break;
        }
        if !cur.eat(",") {
            return Err(cur.error(&format!("`,` or `)` in {f}")));
        }
        args.push(expr::compile(cur, scope)?);
    }
    end_of_statement(cur)?;
    Ok(Stmt::Printf(fmt.into(), args))
}

/// `fscanf(fp, "format", &a, &b[i], ...)` after its name: read. Its file is one cpfg
/// could not open (a data file the model reads must be missing, see
/// `parse::data_files`), so, as in cpfg, it assigns nothing.
fn fscanf_call(cur: &mut Cursor<'_>, scope: &Scope<'_>) -> PResult<()> {
    cur.skip_ws();
    if !cur.eat("(") {
        return Err(cur.error("`(` after `fscanf`"));
    }
    let _handle = expr::compile(cur, scope)?;
    cur.skip_ws();
    if !cur.eat(",") {
        return Err(cur.error("`,` after the file of fscanf"));
    }
    cur.skip_ws();
    let _format = string_literal(cur)?;
    loop {
        cur.skip_ws();
        if cur.eat(")") {
            break;
        }
        if !cur.eat(",") {
            return Err(cur.error("`,` or `)` in fscanf"));
        }
        cur.skip_ws();
        cur.eat("&");
        let _target = expr::compile(cur, scope)?;
    }
    end_of_statement(cur)
}

/// `fclose(fp)` or `fflush(fp)` after its name: read, and nothing to do.
fn file_call(cur: &mut Cursor<'_>, scope: &Scope<'_>) -> PResult<()> {
    cur.skip_ws();
    if !cur.eat("(") {
        return Err(cur.error("`(` and the file"));
    }
    let _handle = expr::compile(cur, scope)?;
    cur.skip_ws();
    if !cur.eat(")") {
        return Err(cur.error("`)` after the file"));
    }
    end_of_statement(cur)
}

/// `stop`, `stop()` or `stop(e)` after its name (cpfg stops when e is not 0).
fn stop_call(cur: &mut Cursor<'_>, scope: &Scope<'_>) -> PResult<Stmt> {
    cur.skip_ws();
    if cur.eat("(") {
        cur.skip_ws();
        if !cur.peek_str(")") {
            let e = expr::compile(cur, scope)?;
            cur.skip_ws();
            if !cur.eat(")") {
                return Err(cur.error("`)` closing stop("));
            }
            end_of_statement(cur)?;
            return Ok(Stmt::If(e, vec![Stmt::Stop], Vec::new()));
        }
        cur.eat(")");
    }
    end_of_statement(cur)?;
    Ok(Stmt::Stop)
}

fn end_of_statement(cur: &mut Cursor<'_>) -> PResult<()> {
    cur.skip_ws();
    if cur.eat(";") || cur.peek_str("}") {
        return Ok(());
    }
    Err(cur.error("`;` after the statement"))
}

/// `name = e` and friends with the cursor after `name`; `None` (cursor anywhere) when
/// what follows is not an assignment.
fn assignment(cur: &mut Cursor<'_>, scope: &Scope<'_>, name: &str) -> PResult<Option<Stmt>> {
    let at = cur.pos();
    cur.skip_ws();
    let is_elem = cur.peek_str("[");
    let target = if let Some(slot) = scope.params.iter().find(|(n, _)| n == name) {
        Target::Param(slot.1)
    } else {
        let Some(globals) = scope.globals else {
            return Ok(None);
        };
        if is_elem {
            let Some(a) = globals.borrow().array(name) else {
                return Err(cur.message_at(
                    at - name.len(),
                    &format!("`{name}` is subscripted but never declared as an array"),
                ));
            };
            let dims = globals.borrow().arrays[a as usize].dims.len();
            let mut idx = Vec::new();
            for _ in 0..dims {
                cur.skip_ws();
                if !cur.eat("[") {
                    return Ok(None);
                }
                idx.push(expr::compile(cur, scope)?);
                cur.skip_ws();
                if !cur.eat("]") {
                    return Err(cur.error("`]` closing an array index"));
                }
            }
            Target::Elem(a, idx)
        } else {
            match globals.borrow().array(name) {
                Some(_) => return Ok(None),
                None => Target::Var(0),
            }
        }
    };
    cur.skip_ws();
    let op = if cur.peek_str("==") {
        return Ok(None);
    } else if cur.eat("=") {
        None
    } else {
        let mut found = None;
        for (tok, op) in [
            ("+=", expr::Op::Add),
            ("-=", expr::Op::Sub),
            ("*=", expr::Op::Mul),
            ("/=", expr::Op::Div),
        ] {
            if cur.eat(tok) {
                found = Some(op);
                break;
            }
        }
        match found {
            Some(op) => Some(op),
            None => return Ok(None),
        }
    };
    let target = match target {
        Target::Var(_) => {
            let globals = scope.globals.expect("checked above");
            let Some(slot) = globals.borrow_mut().intern(name) else {
                return Err(cur.message_at(at, "too many global variables"));
            };
            Target::Var(slot)
        }
        t => t,
    };
    let value = expr::compile(cur, scope)?;
    Ok(Some(Stmt::Set(target, op, value)))
}

fn string_literal(cur: &mut Cursor<'_>) -> PResult<String> {
    if !cur.eat("\"") {
        return Err(cur.error("a string in double quotes"));
    }
    let mut s = String::new();
    loop {
        match cur.bump() {
            None | Some('\n') => return Err(cur.error("`\"` closing the string")),
            Some('"') => return Ok(s),
            Some('\\') => match cur.bump() {
                Some('n') => s.push('\n'),
                Some('t') => s.push('\t'),
                Some(c) => s.push(c),
                None => return Err(cur.error("`\"` closing the string")),
            },
            Some(c) => s.push(c),
        }
    }
}

/// Runs `stmts`; `false` when a fault stopped them (see `env.fault`).
pub(crate) fn exec(stmts: &[Stmt], args: &mut [f64], env: &mut Env, fx: &mut Effects<'_>) -> bool {
    for s in stmts {
        if !fx.spend(env, 1 + s.cost()) {
            return false;
        }
        match s {
            Stmt::Set(target, op, e) => {
                let v = e.eval(args, env);
                let slot: &mut f64 = match target {
                    Target::Param(i) => &mut args[*i as usize],
                    Target::Var(i) => &mut env.vars[*i as usize],
                    Target::Elem(a, idx) => {
                        let mut values = [0.0f64; 8];
                        let n = idx.len().min(8);
                        for (k, e) in idx.iter().take(8).enumerate() {
                            values[k] = e.eval(args, env);
                        }
                        match env.element(*a, &values[..n]) {
                            Some(slot) => &mut env.vars[slot],
                            None => return false,
                        }
                    }
                };
                *slot = match op {
                    None => v,
                    Some(expr::Op::Add) => *slot + v,
                    Some(expr::Op::Sub) => *slot - v,
                    Some(expr::Op::Mul) => *slot * v,
                    Some(_) => *slot / v,
                };
            }
            Stmt::If(c, a, b) => {
                let branch = if c.eval(args, env) != 0.0 { a } else { b };
                if !exec(branch, args, env, fx) {
                    return false;
                }
            }
            Stmt::While(c, body) => {
                while c.eval(args, env) != 0.0 {
                    if !exec(body, args, env, fx) {
                        return false;
                    }
                    if !fx.spend(env, 1 + c.cost()) {
                        return false;
                    }
                }
            }
            Stmt::DoWhile(body, c) => loop {
                if !exec(body, args, env, fx) {
                    return false;
                }
                if c.eval(args, env) == 0.0 {
                    break;
                }
                if !fx.spend(env, 1 + c.cost()) {
                    return false;
                }
            },
            Stmt::Eval(e) => {
                e.eval(args, env);
            }
            Stmt::Printf(fmt, values) => {
                let values: Vec<f64> = values.iter().map(|e| e.eval(args, env)).collect();
                if fx.log.len() < MAX_LOG_BYTES {
                    let text = printf(fmt, &values);
                    let room = MAX_LOG_BYTES - fx.log.len();
                    let mut cut = text.len().min(room);
                    while !text.is_char_boundary(cut) {
                        cut -= 1;
                    }
                    fx.log.push_str(&text[..cut]);
                }
            }
            Stmt::Stop => fx.stop = true,
        }
        if env.fault.is_some() {
            return false;
        }
    }
    true
}

impl Stmt {
    /// Work units of the statement's own expressions (not of the statements it holds,
    /// which count as they run), evaluated once.
    fn cost(&self) -> u64 {
        match self {
            Stmt::Set(target, _, e) => {
                e.cost()
                    + match target {
                        Target::Elem(_, idx) => idx.iter().map(Expr::cost).sum(),
                        _ => 0,
                    }
            }
            Stmt::If(c, _, _) | Stmt::While(c, _) | Stmt::DoWhile(_, c) | Stmt::Eval(c) => c.cost(),
            Stmt::Printf(_, values) => 16 + values.iter().map(Expr::cost).sum::<u64>(),
            Stmt::Stop => 0,
        }
    }
}

/// The fault a derivation notes when its work passes `max_work`.
pub(crate) const OVER_BUDGET: &str = "the derivation's work passed `max_work` (a loop that never ends, or a string that \
     stays large for very many steps?)";

/// The fault a derivation notes when the progress callback asks it to stop.
pub(crate) const CANCELLED: &str = "cancelled by the progress callback";

impl Effects<'_> {
    /// A budget of `units`, reporting to nobody.
    pub(crate) fn with_budget(units: u64) -> Self {
        let mut fx = Effects::default();
        fx.reset_budget(units);
        fx
    }

    /// Sets the budget left to `units`; the next report is due [`REPORT_UNITS`] on.
    pub(crate) fn reset_budget(&mut self, units: u64) {
        self.budget = units;
        self.report_at = units.saturating_sub(REPORT_UNITS);
    }

    /// Spends `units` of work against the budget (`max_work`); `false`, with the fault
    /// [`OVER_BUDGET`] noted, when it is spent, or with [`CANCELLED`] when the progress
    /// callback, due to hear the work, asks to stop.
    #[inline]
    pub(crate) fn spend(&mut self, env: &mut Env, units: u64) -> bool {
        let units = units.saturating_add(std::mem::take(&mut env.extra_work));
        match self.budget.checked_sub(units) {
            Some(left) => {
                self.budget = left;
                left >= self.report_at || self.report(env)
            }
            None => {
                self.budget = 0;
                if env.fault.is_none() {
                    env.fault = Some(OVER_BUDGET.into());
                }
                false
            }
        }
    }

    #[cold]
    #[inline(never)]
    fn report(&mut self, env: &mut Env) -> bool {
        self.report_at = self.budget.saturating_sub(REPORT_UNITS);
        if self.progress.report(self.stage, self.fraction).is_err() {
            if env.fault.is_none() {
                env.fault = Some(CANCELLED.into());
            }
            return false;
        }
        true
    }
}

/// C's printf for numbers: `%d %i %f %e %g %c %%` with flags, width and precision.
pub(crate) fn printf(fmt: &str, values: &[f64]) -> String {
    let mut out = String::new();
    let mut values = values.iter().copied();
    let mut chars = fmt.chars().peekable();
    while let Some(c) = chars.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let mut flags = String::new();
        while let Some(&f) = chars.peek() {
            if "-+ 0#".contains(f) {
                flags.push(f);
                chars.next();
            } else {
                break;
            }
        }
        let mut width = String::new();
        while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
            width.push(d);
            chars.next();
        }
        let mut precision: Option<usize> = None;
        if chars.peek() == Some(&'.') {
            chars.next();
            let mut p = String::new();
            while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
                p.push(d);
                chars.next();
            }
            precision = Some(p.parse().unwrap_or(0));
        }
        while matches!(chars.peek(), Some('l' | 'h')) {
            chars.next();
        }
        let Some(conv) = chars.next() else {
            out.push('%');
            break;
        };
        let precision = precision.map(|p| p.min(64));
        let text = match conv {
            '%' => "%".to_string(),
            'd' | 'i' => format!("{}", values.next().unwrap_or(0.0) as i64),
            'f' | 'F' => format!(
                "{:.*}",
                precision.unwrap_or(6),
                values.next().unwrap_or(0.0)
            ),
            'e' | 'E' => format!(
                "{:.*e}",
                precision.unwrap_or(6),
                values.next().unwrap_or(0.0)
            ),
            'g' | 'G' => {
                let v = values.next().unwrap_or(0.0);
                let p = precision.unwrap_or(6).max(1);
                let s = format!("{:.*e}", p - 1, v);
                let exp: i32 = s
                    .rsplit('e')
                    .next()
                    .and_then(|e| e.parse().ok())
                    .unwrap_or(0);
                if exp < -4 || exp >= p as i32 {
                    s
                } else {
                    let f = format!("{:.*}", (p as i32 - 1 - exp).max(0) as usize, v);
                    if f.contains('.') && !flags.contains('#') {
                        f.trim_end_matches('0').trim_end_matches('.').to_string()
                    } else {
                        f
                    }
                }
            }
            'c' => char::from_u32(values.next().unwrap_or(0.0) as u32)
                .map(String::from)
                .unwrap_or_default(),
            other => format!("%{other}"),
        };
        let width: usize = width.parse::<usize>().unwrap_or(0).min(256);
        if text.chars().count() < width {
            let pad = width - text.chars().count();
            if flags.contains('-') {
                out.push_str(&text);
                out.extend(std::iter::repeat_n(' ', pad));
            } else {
                let fill = if flags.contains('0') { '0' } else { ' ' };
                out.extend(std::iter::repeat_n(fill, pad));
                out.push_str(&text);
            }
        } else {
            out.push_str(&text);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lsystem::expr::{ArrayDecl, Globals};
    use std::cell::RefCell;
    use std::collections::HashMap;

    fn run(text: &str) -> (Vec<f64>, Globals, Effects<'static>, Option<String>) {
        let mut g = Globals::default();
        g.arrays.push(ArrayDecl {
            name: "a".into(),
            dims: vec![3],
            offset: 0,
        });
        g.init = vec![0.0; 3];
        let globals = RefCell::new(g);
        let names = vec![("x".to_string(), 0u16)];
        let defines = HashMap::new();
        let scope = Scope {
            params: &names,
            defines: &defines,
            globals: Some(&globals),
        };
        let stmts = block(&mut Cursor::new(text), &scope).unwrap();
        let g = globals.into_inner();
        let mut env = Env::new(
            crate::lsystem::random::Random::Arbor(crate::rng::Rng::new(1)),
            &g,
            Vec::new().into(),
        );
        let mut fx = Effects::with_budget(10_000);
        let mut args = vec![2.0];
        exec(&stmts, &mut args, &mut env, &mut fx);
        let mut all = args;
        all.extend(env.vars);
        (all, g, fx, env.fault)
    }

    #[test]
    fn assignments_loops_and_arrays() {
        let (v, g, fx, fault) = run(
            "{ i = 0; while (i < 3) { a[i] = i * x; i += 1; } if (a[2] == 4) y = 1; else y = 2;
               do { x = x + 1; } while (x < 5); printf(\"%d:%.2f|%5.1f|%g\\n\", x, a[1], 2.25, 0.5); }",
        );
        assert_eq!(fault, None);
        let var = |n: &str| v[1 + g.var(n).unwrap() as usize];
        assert_eq!(&v[1..4], &[0.0, 2.0, 4.0]);
        assert_eq!(var("i"), 3.0);
        assert_eq!(var("y"), 1.0);
        assert_eq!(v[0], 5.0);
        assert_eq!(fx.log, "5:2.00|  2.2|0.5\n");
        assert!(!fx.stop);
    }

    #[test]
    fn faults_and_budgets_stop_the_statements() {
        let (_, _, _, fault) = run("{ a[3] = 1; }");
        assert!(fault.unwrap().contains("outside 0..3"));
        let (_, _, _, fault) = run("{ while (1) { x = x + 1; } }");
        assert!(fault.unwrap().contains("max_work"));
        let (_, _, fx, _) = run("{ stop(); }");
        assert!(fx.stop);
    }
}
