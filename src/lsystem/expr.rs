//! Expressions: parsed once, constant-folded, compiled to a compact stack bytecode.
//!
//! Grammar, lowest precedence first (C-like, as cpfg reads it): `c ? a : b`, `||`, `&&`,
//! `== != <>`, `< <= > >=`, `+ -`, `* / %`, `^` (power, left-associative and looser than
//! unary minus: `-2^2` is 4, `2^3^2` is 64), unary `- + !`, then numbers, names, array
//! elements `a[i][j]`, calls and parentheses. Trigonometric functions work in degrees;
//! `trunc` rounds to the nearest whole number and `%` works on the integer parts, as in
//! cpfg. A name that is neither a parameter of the production nor an array is a global
//! variable (0 until a statement assigns it).

use super::builtins::{
    Arity, BUILTINS, Func1, Func2, Special, beta, binomial, builtin_names, unsupported,
};
use super::syntax::{Cursor, PResult};
use crate::rng::Rng;
use std::cell::RefCell;
use std::collections::HashMap;

/// The prefix under which the view file's function names are kept among the defines:
/// they stand for their numbers only as the first argument of `func`.
pub(crate) const FUNCTION_NAME: &str = "\u{0}func:";

/// Most values all global variables and arrays of a grammar may hold together.
pub(crate) const MAX_GLOBAL_VALUES: usize = 1 << 22;

/// An array declared in a `define:` block.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ArrayDecl {
    pub(crate) name: String,
    pub(crate) dims: Vec<u32>,
    /// Index of its first element in [`Env::vars`].
    pub(crate) offset: u32,
}

/// The global variables and arrays of a grammar, named while parsing.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Globals {
    /// Plain variables: name and index in [`Env::vars`].
    pub(crate) vars: Vec<(String, u32)>,
    pub(crate) arrays: Vec<ArrayDecl>,
    /// Initial values of every slot (0, or an array's `= { ... }`).
    pub(crate) init: Vec<f64>,
}

impl Globals {
    pub(crate) fn var(&self, name: &str) -> Option<u32> {
        self.vars.iter().find(|(n, _)| n == name).map(|&(_, i)| i)
    }

    pub(crate) fn array(&self, name: &str) -> Option<u16> {
        self.arrays
            .iter()
            .position(|a| a.name == name)
            .map(|i| i as u16)
    }

    /// The slot of variable `name`, created (0) on first use; `None` past the limit.
    pub(crate) fn intern(&mut self, name: &str) -> Option<u32> {
        if let Some(i) = self.var(name) {
            return Some(i);
        }
        if self.init.len() >= MAX_GLOBAL_VALUES {
            return None;
        }
        let i = self.init.len() as u32;
        self.init.push(0.0);
        self.vars.push((name.to_string(), i));
        Some(i)
    }
}

/// What expressions and statements read and change while a grammar runs: the random
/// stream, the global variables, and the first run-time fault (an array index out of
/// range, a statement budget spent).
#[derive(Clone, Debug)]
pub(crate) struct Env {
    pub(crate) rng: Rng,
    pub(crate) vars: Vec<f64>,
    pub(crate) arrays: std::sync::Arc<[ArrayDecl]>,
    /// The view file's functions, read by `func(id, x)` (id from 1).
    pub(crate) functions: std::sync::Arc<[super::function_files::Function]>,
    /// The view file's curves (`curve:`), read by `curveX/Y/Z` and `curveGAL`.
    pub(crate) curves: std::sync::Arc<[super::function_files::Curve]>,
    pub(crate) fault: Option<String>,
}

impl Env {
    pub(crate) fn new(
        seed: u64,
        globals: &Globals,
        functions: std::sync::Arc<[super::function_files::Function]>,
    ) -> Self {
        Env {
            rng: Rng::new(seed),
            vars: globals.init.clone(),
            arrays: globals.arrays.clone().into(),
            functions,
            curves: Vec::new().into(),
            fault: None,
        }
    }

    /// An environment without variables (constant folding, tests).
    pub(crate) fn empty(seed: u64) -> Self {
        Env {
            rng: Rng::new(seed),
            vars: Vec::new(),
            arrays: Vec::new().into(),
            functions: Vec::new().into(),
            curves: Vec::new().into(),
            fault: None,
        }
    }

    /// Curve `id` (from 1) of the view file, or `None` with a fault noted.
    fn curve(&mut self, id: f64) -> Option<&super::function_files::Curve> {
        let n = self.curves.len();
        if id >= 1.0 && id < n as f64 + 1.0 {
            return Some(&self.curves[id as usize - 1]);
        }
        if self.fault.is_none() {
            self.fault = Some(format!(
                "curve {id}: the view file lists {n} curve(s) (`curve: file.con`)"
            ));
        }
        None
    }

    /// The slot of element `idx` of array `a`, or `None` (with a fault noted) when an
    /// index is outside its dimension.
    pub(crate) fn element(&mut self, a: u16, idx: &[f64]) -> Option<usize> {
        let decl = &self.arrays[a as usize];
        let mut linear = 0usize;
        for (k, (&i, &d)) in idx.iter().zip(&decl.dims).enumerate() {
            let i = i.floor();
            if !(i >= 0.0 && i < d as f64) {
                if self.fault.is_none() {
                    self.fault = Some(format!(
                        "index {} of `{}` is {i}, outside 0..{}",
                        k + 1,
                        decl.name,
                        d
                    ));
                }
                return None;
            }
            linear = linear * d as usize + i as usize;
        }
        Some(decl.offset as usize + linear)
    }
}

/// Deepest parenthesis/call nesting accepted, so hostile input cannot exhaust the stack.
pub(crate) const MAX_NESTING: usize = 100;
/// Largest evaluation stack an expression may need.
pub(crate) const MAX_STACK: usize = 256;

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
    /// A global variable's slot in [`Env::vars`].
    Var(u32),
    /// Pops the array's indices (one per dimension) and pushes the element.
    Elem(u16),
    Special(Special),
    /// Pops; jumps to the target when the value is 0.
    JumpIfZero(u32),
    Jump(u32),
}

fn b(v: bool) -> f64 {
    if v { 1.0 } else { 0.0 }
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
        Op::Rem => {
            let (a, b) = (x.trunc(), y.trunc());
            if b == 0.0 { f64::NAN } else { a % b }
        }
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
    pub(crate) fn eval(&self, args: &[f64], env: &mut Env) -> f64 {
        match self {
            Expr::Const(c) => *c,
            Expr::Param(i) => args[*i as usize],
            Expr::Binary(op, a, b) => binary(*op, a.get(args), b.get(args)),
            Expr::Code(ops, depth) => run_code(ops, *depth, args, env),
        }
    }

    /// Whether the value is known without any parameter or random draw.
    pub(crate) fn as_const(&self) -> Option<f64> {
        match self {
            Expr::Const(c) => Some(*c),
            // Code without parameters or random draws (a `?:`, say) has one value.
            Expr::Code(ops, depth)
                if ops.iter().all(|op| {
                    !matches!(
                        op,
                        Op::Param(_)
                            | Op::Ran
                            | Op::Nran
                            | Op::Var(_)
                            | Op::Elem(_)
                            | Op::Special(_)
                    )
                }) =>
            {
                Some(run_code(ops, *depth, &[], &mut Env::empty(0)))
            }
            _ => None,
        }
    }
}

/// Stack size evaluated without a heap allocation.
const SMALL_STACK: usize = 16;

#[inline(never)]
fn run_code(ops: &[Op], depth: usize, args: &[f64], env: &mut Env) -> f64 {
    if depth <= SMALL_STACK {
        run(ops, args, env, &mut [0.0; SMALL_STACK])
    } else {
        run(ops, args, env, &mut vec![0.0; depth])
    }
}

fn run(ops: &[Op], args: &[f64], env: &mut Env, stack: &mut [f64]) -> f64 {
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
            Op::Ran => stack[sp - 1] *= env.rng.next_f64(),
            Op::Var(i) => {
                stack[sp] = env.vars.get(i as usize).copied().unwrap_or(0.0);
                sp += 1;
            }
            Op::Elem(a) => {
                let n = env.arrays[a as usize].dims.len();
                sp -= n;
                let v = match env.element(a, &stack[sp..sp + n]) {
                    Some(slot) => env.vars[slot],
                    None => 0.0,
                };
                stack[sp] = v;
                sp += 1;
            }
            Op::Special(Special::Srand) => {
                env.rng = Rng::new(stack[sp - 1] as i64 as u64);
                stack[sp - 1] = 0.0;
            }
            Op::Special(Special::Bran) => {
                sp -= 1;
                stack[sp - 1] = beta(&mut env.rng, stack[sp - 1], stack[sp]);
            }
            Op::Special(Special::Func) => {
                sp -= 1;
                let (id, x) = (stack[sp - 1], stack[sp]);
                let n = env.functions.len();
                stack[sp - 1] = if id >= 1.0 && id < n as f64 + 1.0 {
                    env.functions[id as usize - 1].eval(x)
                } else {
                    if env.fault.is_none() {
                        env.fault = Some(format!(
                            "func({id}, ...): the view file lists {n} function(s) \
                             (`function: file.func` or `function set: file.fset`)"
                        ));
                    }
                    0.0
                };
            }
            Op::Special(Special::CurveLength) => {
                let id = stack[sp - 1];
                stack[sp - 1] = match env.curve(id) {
                    Some(c) => c.length(),
                    None => 0.0,
                };
            }
            Op::Special(Special::Curve(axis)) => {
                sp -= 1;
                let (id, t) = (stack[sp - 1], stack[sp]);
                stack[sp - 1] = match env.curve(id) {
                    Some(c) => c.at(t, axis as usize),
                    None => 0.0,
                };
            }
            Op::Special(Special::Biran) => {
                sp -= 1;
                stack[sp - 1] = binomial(&mut env.rng, stack[sp - 1], stack[sp]);
            }
            Op::F2(f) => {
                sp -= 1;
                stack[sp - 1] = f.apply(stack[sp - 1], stack[sp]);
            }
            Op::Nran => {
                sp -= 1;
                stack[sp - 1] = env.rng.normal(stack[sp - 1], stack[sp]);
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

/// What names mean while compiling: formal parameters (slots), `#define`d constants
/// (the view file's own), and the grammar's global variables and arrays.
pub(crate) struct Scope<'a> {
    pub(crate) params: &'a [(String, u16)],
    pub(crate) defines: &'a HashMap<String, f64>,
    /// `None`: an unknown name is an error (a constant is wanted).
    pub(crate) globals: Option<&'a RefCell<Globals>>,
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
            Op::Const(_) | Op::Param(_) | Op::Var(_) => {
                self.depth += 1;
                self.max_depth = self.max_depth.max(self.depth);
            }
            Op::JumpIfZero(_) => self.depth -= 1,
            Op::Neg | Op::Not | Op::F1(_) | Op::Ran | Op::Jump(_) | Op::Special(Special::Srand) => {
            }
            // The caller accounts for the indices an element pops.
            Op::Elem(_) => {}
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
            // `<>` is `!=`, one level up.
            if tok == "<" && self.cur.peek_str("<>") {
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
        self.binary_level(
            &[("==", Op::Eq), ("!=", Op::Ne), ("<>", Op::Ne)],
            Self::relation,
        )
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
            Self::power,
        )
    }

    /// `a ^ b ^ c`, left to right, over unary operands (so `-2^2` is `(-2)^2`).
    fn power(&mut self) -> PResult<()> {
        self.binary_level(&[("^", Op::Pow)], Self::unary)
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
        self.primary()?;
        for op in prefix.into_iter().rev() {
            self.emit_unary(op, start);
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
            if self.cur.peek_str("[") {
                return Err(self.cur.message_at(
                    at,
                    &format!("`{name}[` subscripts a name that is not an array (a parameter)"),
                ));
            }
            self.push(Op::Param(slot));
            return Ok(());
        }
        if let Some(&v) = self.scope.defines.get(name) {
            self.push(Op::Const(v));
            return Ok(());
        }
        let Some(globals) = self.scope.globals else {
            return Err(self
                .cur
                .error_at(at, "a number or a #define name (this name is undefined)"));
        };
        let array = globals.borrow().array(name);
        if self.cur.peek_str("[") || array.is_some() {
            let Some(a) = array else {
                return Err(self.cur.message_at(
                    at,
                    &format!("`{name}` is subscripted but never declared as an array (define: {{ array {name}[n]; }})"),
                ));
            };
            let dims = globals.borrow().arrays[a as usize].dims.len();
            self.nest()?;
            for _ in 0..dims {
                self.cur.skip_ws();
                if !self.cur.eat("[") {
                    return Err(self.cur.error(&format!(
                        "`[` and an index: `{name}` has {dims} dimension(s)"
                    )));
                }
                self.ternary()?;
                self.cur.skip_ws();
                if !self.cur.eat("]") {
                    return Err(self.cur.error("`]` closing an array index"));
                }
            }
            self.nesting -= 1;
            self.push(Op::Elem(a));
            self.depth -= dims - 1;
            return Ok(());
        }
        let Some(slot) = globals.borrow_mut().intern(name) else {
            return Err(self.cur.message_at(at, "too many global variables"));
        };
        self.push(Op::Var(slot));
        Ok(())
    }

    fn call(&mut self, name: &str, at: usize) -> PResult<()> {
        if name == "fopen" {
            return self.fopen(at);
        }
        if let Some(what) = unsupported(name) {
            return Err(self.cur.message_at(
                at,
                &format!(
                    "`{name}()` needs {what}, which arbor does not have; the grammar cannot \
                     run without it"
                ),
            ));
        }
        let Some(builtin) = BUILTINS.iter().find(|b| b.name == name) else {
            return Err(self
                .cur
                .error_at(at, &format!("a function: {}", builtin_names())));
        };
        self.cur.eat("(");
        self.nest()?;
        let mut args = 0;
        let start = self.ops.len();
        if name == "func" {
            // `func(NAME, x)`: a function of the view file named by its `name:`.
            let mut probe = self.cur.clone();
            probe.skip_ws();
            if let Some(id) = probe.identifier() {
                let key = format!("{FUNCTION_NAME}{id}");
                probe.skip_ws();
                if let (Some(&v), true) = (self.scope.defines.get(&key), probe.peek_str(",")) {
                    *self.cur = probe;
                    self.cur.eat(",");
                    self.push(Op::Const(v));
                    args = 1;
                }
            }
        }
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
        match (builtin.arity, args) {
            (Arity::One(op), 1) | (Arity::OneOrTwo(op, _), 1) => self.emit_unary(op, start),
            (Arity::Two(op), 2) | (Arity::OneOrTwo(_, op), 2) => self.push_two(op, start),
            _ => {
                return Err(self.cur.error_at(
                    at,
                    &format!(
                        "{} argument(s) to `{name}`, not {args}",
                        builtin.arity.count()
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `fopen("name", "mode")`: a file opened for writing is a handle whose `fprintf`
    /// goes to the log; reading files is refused, naming the file.
    fn fopen(&mut self, at: usize) -> PResult<()> {
        self.cur.eat("(");
        let mut strings = Vec::new();
        for k in 0..2 {
            self.cur.skip_ws();
            if k == 1 && !self.cur.eat(",") {
                return Err(self.cur.error("`,` and the mode of fopen"));
            }
            self.cur.skip_ws();
            if !self.cur.eat("\"") {
                return Err(self.cur.error("a file name or mode in double quotes"));
            }
            let s = self.cur.rest();
            let Some(end) = s.find('"') else {
                return Err(self.cur.error("`\"` closing the text"));
            };
            strings.push(s[..end].to_string());
            self.cur.eat(&s[..=end]);
        }
        self.cur.skip_ws();
        if !self.cur.eat(")") {
            return Err(self.cur.error("`)` closing fopen"));
        }
        if strings[1].starts_with('r') {
            return Err(self.cur.message_at(
                at,
                &format!(
                    "fopen(\"{}\", \"{}\"): the grammar reads a data file, which arbor does \
                     not do; it cannot run without `{}`",
                    strings[0], strings[1], strings[0]
                ),
            ));
        }
        self.push(Op::Const(1.0));
        Ok(())
    }

    fn push_two(&mut self, op: Op, start: usize) {
        if let Op::Special(_) = op {
            self.depth -= 1;
            self.ops.push(op);
            return;
        }
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
            &mut Env::new(1, &globals.borrow(), Vec::new().into()),
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
                2
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
}
