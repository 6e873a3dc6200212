//! Expressions: parsed once, constant-folded, compiled to a compact stack bytecode.
//!
//! Grammar, lowest precedence first (C-like, with `^` as power, as in cpfg):
//! `c ? a : b`, `||`, `&&`, `== !=`, `< <= > >=`, `+ -`, `* / %`, unary `- + !`, `^`
//! (right-associative, binds tighter than unary minus), then numbers, names, calls and
//! parentheses. Trigonometric functions work in degrees, as in cpfg.

use super::syntax::{Cursor, PResult};
use crate::rng::Rng;
use std::collections::HashMap;

/// Deepest parenthesis/call nesting accepted, so hostile input cannot exhaust the stack.
pub(crate) const MAX_NESTING: usize = 100;
/// Largest evaluation stack an expression may need.
pub(crate) const MAX_STACK: usize = 256;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Func1 {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Exp,
    Log,
    Sqrt,
    Fabs,
    Floor,
    Ceil,
    Trunc,
    Sign,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Func2 {
    Atan2,
    Min,
    Max,
    Pow,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Op {
    Const(f64),
    Param(u16),
    Neg,
    Not,
    Add,
    Sub,
    Mul,
    Div,
    Rem,
    Pow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
    F1(Func1),
    F2(Func2),
    Ran,
    Nran,
    /// Pops; jumps to the target when the value is 0.
    JumpIfZero(u32),
    Jump(u32),
}

fn b(v: bool) -> f64 {
    if v { 1.0 } else { 0.0 }
}

impl Func1 {
    fn apply(self, x: f64) -> f64 {
        match self {
            Func1::Sin => libm::sin(x.to_radians()),
            Func1::Cos => libm::cos(x.to_radians()),
            Func1::Tan => libm::tan(x.to_radians()),
            Func1::Asin => libm::asin(x).to_degrees(),
            Func1::Acos => libm::acos(x).to_degrees(),
            Func1::Atan => libm::atan(x).to_degrees(),
            Func1::Exp => libm::exp(x),
            Func1::Log => libm::log(x),
            Func1::Sqrt => x.sqrt(),
            Func1::Fabs => x.abs(),
            Func1::Floor => x.floor(),
            Func1::Ceil => x.ceil(),
            Func1::Trunc => x.trunc(),
            Func1::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    0.0
                }
            }
        }
    }
}

impl Func2 {
    fn apply(self, x: f64, y: f64) -> f64 {
        match self {
            Func2::Atan2 => libm::atan2(x, y).to_degrees(),
            Func2::Min => x.min(y),
            Func2::Max => x.max(y),
            Func2::Pow => libm::pow(x, y),
        }
    }
}

fn is_binary(op: Op) -> bool {
    matches!(
        op,
        Op::Add
            | Op::Sub
            | Op::Mul
            | Op::Div
            | Op::Rem
            | Op::Pow
            | Op::Lt
            | Op::Le
            | Op::Gt
            | Op::Ge
            | Op::Eq
            | Op::Ne
            | Op::And
            | Op::Or
    )
}

#[inline]
fn binary(op: Op, x: f64, y: f64) -> f64 {
    match op {
        Op::Add => x + y,
        Op::Sub => x - y,
        Op::Mul => x * y,
        Op::Div => x / y,
        Op::Rem => x % y,
        Op::Pow => libm::pow(x, y),
        Op::Lt => b(x < y),
        Op::Le => b(x <= y),
        Op::Gt => b(x > y),
        Op::Ge => b(x >= y),
        Op::Eq => b(x == y),
        Op::Ne => b(x != y),
        Op::And => b(x != 0.0 && y != 0.0),
        Op::Or => b(x != 0.0 || y != 0.0),
        _ => unreachable!("not a binary operator: {op:?}"),
    }
}

/// An operand of [`Expr::Binary`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Operand {
    Const(f64),
    Param(u16),
}

impl Operand {
    #[inline(always)]
    fn get(self, args: &[f64]) -> f64 {
        match self {
            Operand::Const(c) => c,
            Operand::Param(i) => args[i as usize],
        }
    }
}

/// A compiled expression. The common shapes (`s * r`, `s >= min`, a parameter, a
/// constant) are evaluated directly; anything else runs as bytecode on a small stack.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Expr {
    Const(f64),
    Param(u16),
    Binary(Op, Operand, Operand),
    /// Bytecode and the deepest stack it needs.
    Code(Box<[Op]>, usize),
}

impl Expr {
    /// Evaluates with the production's bound parameters `args`.
    #[inline(always)]
    pub(crate) fn eval(&self, args: &[f64], rng: &mut Rng) -> f64 {
        match self {
            Expr::Const(c) => *c,
            Expr::Param(i) => args[*i as usize],
            Expr::Binary(op, a, b) => binary(*op, a.get(args), b.get(args)),
            Expr::Code(ops, depth) => run_code(ops, *depth, args, rng),
        }
    }

    /// Whether the value is known without any parameter or random draw.
    pub(crate) fn as_const(&self) -> Option<f64> {
        match self {
            Expr::Const(c) => Some(*c),
            // Code without parameters or random draws (a `?:`, say) has one value.
            Expr::Code(ops, depth)
                if ops
                    .iter()
                    .all(|op| !matches!(op, Op::Param(_) | Op::Ran | Op::Nran)) =>
            {
                Some(run_code(ops, *depth, &[], &mut Rng::new(0)))
            }
            _ => None,
        }
    }
}

/// Stack size evaluated without a heap allocation.
const SMALL_STACK: usize = 16;

#[inline(never)]
fn run_code(ops: &[Op], depth: usize, args: &[f64], rng: &mut Rng) -> f64 {
    if depth <= SMALL_STACK {
        run(ops, args, rng, &mut [0.0; SMALL_STACK])
    } else {
        run(ops, args, rng, &mut vec![0.0; depth])
    }
}

fn run(ops: &[Op], args: &[f64], rng: &mut Rng, stack: &mut [f64]) -> f64 {
    let mut sp = 0usize;
    let mut pc = 0usize;
    while pc < ops.len() {
        let op = ops[pc];
        pc += 1;
        match op {
            Op::Const(c) => {
                stack[sp] = c;
                sp += 1;
            }
            Op::Param(i) => {
                stack[sp] = args[i as usize];
                sp += 1;
            }
            Op::Neg => stack[sp - 1] = -stack[sp - 1],
            Op::Not => stack[sp - 1] = b(stack[sp - 1] == 0.0),
            Op::F1(f) => stack[sp - 1] = f.apply(stack[sp - 1]),
            Op::Ran => stack[sp - 1] *= rng.next_f64(),
            Op::F2(f) => {
                sp -= 1;
                stack[sp - 1] = f.apply(stack[sp - 1], stack[sp]);
            }
            Op::Nran => {
                sp -= 1;
                stack[sp - 1] = rng.normal(stack[sp - 1], stack[sp]);
            }
            Op::JumpIfZero(t) => {
                sp -= 1;
                if stack[sp] == 0.0 {
                    pc = t as usize;
                }
            }
            Op::Jump(t) => pc = t as usize,
            _ => {
                sp -= 1;
                stack[sp - 1] = binary(op, stack[sp - 1], stack[sp]);
            }
        }
    }
    debug_assert_eq!(sp, 1);
    stack[0]
}

/// What names mean while compiling: formal parameters (slots) and `#define`d constants.
pub(crate) struct Scope<'a> {
    pub(crate) params: &'a [(String, u16)],
    pub(crate) defines: &'a HashMap<String, f64>,
}

impl Scope<'_> {
    fn param(&self, name: &str) -> Option<u16> {
        self.params.iter().find(|(n, _)| n == name).map(|&(_, s)| s)
    }
}

struct Compiler<'s, 'c, 'src> {
    cur: &'c mut Cursor<'src>,
    scope: &'c Scope<'s>,
    ops: Vec<Op>,
    depth: usize,
    nesting: usize,
    max_depth: usize,
}

/// Parses and compiles one expression at the cursor; stops before `,`, `)`, or any other
/// text that cannot continue an expression.
pub(crate) fn compile(cur: &mut Cursor<'_>, scope: &Scope<'_>) -> PResult<Expr> {
    let start = cur.pos();
    let mut c = Compiler {
        cur,
        scope,
        ops: Vec::new(),
        depth: 0,
        nesting: 0,
        max_depth: 0,
    };
    c.ternary()?;
    if c.max_depth > MAX_STACK {
        return Err(c
            .cur
            .error_at(start, "a simpler expression (it is too deep)"));
    }
    let operand = |op: &Op| match *op {
        Op::Const(v) => Some(Operand::Const(v)),
        Op::Param(i) => Some(Operand::Param(i)),
        _ => None,
    };
    Ok(match c.ops.as_slice() {
        [Op::Const(v)] => Expr::Const(*v),
        [Op::Param(i)] => Expr::Param(*i),
        [a, b, op] if is_binary(*op) && operand(a).is_some() && operand(b).is_some() => {
            Expr::Binary(*op, operand(a).unwrap(), operand(b).unwrap())
        }
        _ => Expr::Code(c.ops.into_boxed_slice(), c.max_depth),
    })
}

impl Compiler<'_, '_, '_> {
    fn push(&mut self, op: Op) {
        match op {
            Op::Const(_) | Op::Param(_) => {
                self.depth += 1;
                self.max_depth = self.max_depth.max(self.depth);
            }
            Op::JumpIfZero(_) => self.depth -= 1,
            Op::Neg | Op::Not | Op::F1(_) | Op::Ran | Op::Jump(_) => {}
            _ => self.depth -= 1,
        }
        self.ops.push(op);
    }

    fn constant_since(&self, start: usize) -> Option<f64> {
        match &self.ops[start..] {
            [Op::Const(v)] => Some(*v),
            _ => None,
        }
    }

    /// Emits a binary operator whose operands' code starts at `left` and `right`,
    /// folding it when both operands are constants.
    fn emit_binary(&mut self, op: Op, left: usize, right: usize) {
        if right == left + 1 {
            if let (Op::Const(x), Some(y)) = (self.ops[left], self.constant_since(right)) {
                self.ops.truncate(left);
                self.depth -= 2;
                self.push(Op::Const(binary(op, x, y)));
                return;
            }
        }
        self.push(op);
    }

    /// Emits a one-operand operator whose operand's code starts at `start`, folding it
    /// when the operand is a constant (`ran` is never folded).
    fn emit_unary(&mut self, op: Op, start: usize) {
        if let Some(x) = self.constant_since(start) {
            let folded = match op {
                Op::Neg => Some(-x),
                Op::Not => Some(b(x == 0.0)),
                Op::F1(f) => Some(f.apply(x)),
                _ => None,
            };
            if let Some(v) = folded {
                self.ops.truncate(start);
                self.depth -= 1;
                self.push(Op::Const(v));
                return;
            }
        }
        self.push(op);
    }

    fn nest(&mut self) -> PResult<()> {
        self.nesting += 1;
        if self.nesting > MAX_NESTING {
            return Err(self.cur.error(&format!(
                "a shallower expression (at most {MAX_NESTING} nested levels)"
            )));
        }
        Ok(())
    }

    fn ternary(&mut self) -> PResult<()> {
        self.nest()?;
        self.or()?;
        self.cur.skip_ws();
        if self.cur.eat("?") {
            let jz = self.ops.len();
            self.push(Op::JumpIfZero(0));
            self.ternary()?;
            self.cur.skip_ws();
            if !self.cur.eat(":") {
                return Err(self.cur.error("`:` of a `?:` expression"));
            }
            let jmp = self.ops.len();
            self.push(Op::Jump(0));
            self.depth -= 1; // only one branch's value is on the stack
            self.ops[jz] = Op::JumpIfZero(self.ops.len() as u32);
            self.ternary()?;
            self.ops[jmp] = Op::Jump(self.ops.len() as u32);
        }
        self.nesting -= 1;
        Ok(())
    }

    fn binary_level(
        &mut self,
        ops: &[(&str, Op)],
        next: fn(&mut Self) -> PResult<()>,
    ) -> PResult<()> {
        let left = self.ops.len();
        next(self)?;
        loop {
            self.cur.skip_ws();
            let Some(&(tok, op)) = ops.iter().find(|(t, _)| self.cur.peek_str(t)) else {
                return Ok(());
            };
            // `->` and `-->` end an expression: they are the production arrow.
            if tok == "-" && (self.cur.peek_str("->") || self.cur.peek_str("-->")) {
                return Ok(());
            }
            self.cur.eat(tok);
            let right = self.ops.len();
            next(self)?;
            self.emit_binary(op, left, right);
        }
    }

    fn or(&mut self) -> PResult<()> {
        self.binary_level(&[("||", Op::Or)], Self::and)
    }

    fn and(&mut self) -> PResult<()> {
        self.binary_level(&[("&&", Op::And)], Self::equality)
    }

    fn equality(&mut self) -> PResult<()> {
        self.binary_level(&[("==", Op::Eq), ("!=", Op::Ne)], Self::relation)
    }

    fn relation(&mut self) -> PResult<()> {
        self.binary_level(
            &[("<=", Op::Le), (">=", Op::Ge), ("<", Op::Lt), (">", Op::Gt)],
            Self::additive,
        )
    }

    fn additive(&mut self) -> PResult<()> {
        self.binary_level(&[("+", Op::Add), ("-", Op::Sub)], Self::multiplicative)
    }

    fn multiplicative(&mut self) -> PResult<()> {
        self.binary_level(
            &[("*", Op::Mul), ("/", Op::Div), ("%", Op::Rem)],
            Self::unary,
        )
    }

    fn unary(&mut self) -> PResult<()> {
        // Iterative over prefix operators so a long run of them cannot overflow the stack.
        let mut prefix = Vec::new();
        loop {
            self.cur.skip_ws();
            if self.cur.peek_str("-") && !self.cur.peek_str("->") && !self.cur.peek_str("-->") {
                self.cur.eat("-");
                prefix.push(Op::Neg);
            } else if self.cur.peek_str("!") && !self.cur.peek_str("!=") {
                self.cur.eat("!");
                prefix.push(Op::Not);
            } else if self.cur.eat("+") {
            } else {
                break;
            }
        }
        let start = self.ops.len();
        self.power()?;
        for op in prefix.into_iter().rev() {
            self.emit_unary(op, start);
        }
        Ok(())
    }

    fn power(&mut self) -> PResult<()> {
        let left = self.ops.len();
        self.primary()?;
        self.cur.skip_ws();
        if self.cur.eat("^") {
            self.nest()?;
            let right = self.ops.len();
            self.unary()?;
            self.nesting -= 1;
            self.emit_binary(Op::Pow, left, right);
        }
        Ok(())
    }

    fn primary(&mut self) -> PResult<()> {
        self.cur.skip_ws();
        if let Some(v) = self.cur.number()? {
            self.push(Op::Const(v));
            return Ok(());
        }
        if self.cur.eat("(") {
            self.ternary()?;
            self.cur.skip_ws();
            if !self.cur.eat(")") {
                return Err(self.cur.error("`)` closing a parenthesis"));
            }
            return Ok(());
        }
        let at = self.cur.pos();
        let Some(name) = self.cur.identifier() else {
            return Err(self.cur.error("an expression (a number, a name or `(`)"));
        };
        self.cur.skip_ws();
        if self.cur.peek_str("(") {
            return self.call(name, at);
        }
        if let Some(slot) = self.scope.param(name) {
            self.push(Op::Param(slot));
        } else if let Some(&v) = self.scope.defines.get(name) {
            self.push(Op::Const(v));
        } else {
            return Err(self.cur.error_at(
                at,
                "a parameter of the production or a #define name (this name is undefined)",
            ));
        }
        Ok(())
    }

    fn call(&mut self, name: &str, at: usize) -> PResult<()> {
        enum F {
            One(Op),
            Two(Op),
            Atan,
        }
        let f = match name {
            "sin" => F::One(Op::F1(Func1::Sin)),
            "cos" => F::One(Op::F1(Func1::Cos)),
            "tan" => F::One(Op::F1(Func1::Tan)),
            "asin" => F::One(Op::F1(Func1::Asin)),
            "acos" => F::One(Op::F1(Func1::Acos)),
            "atan" => F::Atan,
            "exp" => F::One(Op::F1(Func1::Exp)),
            "log" => F::One(Op::F1(Func1::Log)),
            "sqrt" => F::One(Op::F1(Func1::Sqrt)),
            "fabs" | "abs" => F::One(Op::F1(Func1::Fabs)),
            "floor" => F::One(Op::F1(Func1::Floor)),
            "ceil" => F::One(Op::F1(Func1::Ceil)),
            "trunc" => F::One(Op::F1(Func1::Trunc)),
            "sign" => F::One(Op::F1(Func1::Sign)),
            "ran" => F::One(Op::Ran),
            "min" => F::Two(Op::F2(Func2::Min)),
            "max" => F::Two(Op::F2(Func2::Max)),
            "pow" => F::Two(Op::F2(Func2::Pow)),
            "nran" => F::Two(Op::Nran),
            _ => {
                return Err(self.cur.error_at(
                    at,
                    "a function: sin cos tan asin acos atan exp log sqrt fabs floor ceil \
                     trunc sign min max pow ran nran",
                ));
            }
        };
        self.cur.eat("(");
        self.nest()?;
        let mut args = 0;
        let start = self.ops.len();
        loop {
            self.ternary()?;
            args += 1;
            self.cur.skip_ws();
            if self.cur.eat(",") {
                continue;
            }
            if self.cur.eat(")") {
                break;
            }
            return Err(self.cur.error("`,` or `)` in a function call"));
        }
        self.nesting -= 1;
        let arity_error = |c: &mut Self, n: &str| {
            Err(c
                .cur
                .error_at(at, &format!("{n} argument(s) to `{name}`, not {args}")))
        };
        match f {
            F::One(op) => {
                if args != 1 {
                    return arity_error(self, "1");
                }
                self.emit_unary(op, start);
            }
            F::Two(op) => {
                if args != 2 {
                    return arity_error(self, "2");
                }
                self.push_two(op, start);
            }
            F::Atan => match args {
                1 => self.emit_unary(Op::F1(Func1::Atan), start),
                2 => self.push_two(Op::F2(Func2::Atan2), start),
                _ => return arity_error(self, "1 or 2"),
            },
        }
        Ok(())
    }

    fn push_two(&mut self, op: Op, start: usize) {
        if let [Op::Const(x), Op::Const(y)] = self.ops[start..] {
            if let Op::F2(f) = op {
                self.ops.truncate(start);
                self.depth -= 2;
                self.push(Op::Const(f.apply(x, y)));
                return;
            }
        }
        self.push(op);
    }
}

#[cfg(test)]
mod tests {
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
        let scope = Scope {
            params: &names,
            defines: &defines,
        };
        let mut cur = Cursor::new(text);
        let e = compile(&mut cur, &scope).map_err(|e| e.expected)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(format!("stopped at {}", cur.pos()));
        }
        Ok(e.eval(&args, &mut Rng::new(1)))
    }

    fn eval(text: &str) -> f64 {
        eval_with(text, &[("x", 3.0), ("y", 4.0)]).unwrap()
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(eval("1 + 2 * 3"), 7.0);
        assert_eq!(eval("(1 + 2) * 3"), 9.0);
        assert_eq!(eval("2 ^ 3 ^ 2"), 512.0);
        assert_eq!(eval("-2 ^ 2"), -4.0);
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
                2
            )
        );
    }

    #[test]
    fn errors_say_what_was_expected() {
        assert!(eval_with("1 +", &[]).unwrap_err().contains("an expression"));
        assert!(eval_with("zz", &[]).unwrap_err().contains("undefined"));
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
        };
        let mut cur = Cursor::new("1 > 0 --> F");
        assert_eq!(compile(&mut cur, &scope).unwrap(), Expr::Const(1.0));
        assert!(cur.peek_str("-->"));
        let mut cur = Cursor::new("2->F");
        assert_eq!(compile(&mut cur, &scope).unwrap(), Expr::Const(2.0));
    }
}
