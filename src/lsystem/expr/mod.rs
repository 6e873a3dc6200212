//! Expressions: parsed once, constant-folded, compiled to a compact stack bytecode.
//!
//! Grammar, lowest precedence first (C-like, as cpfg reads it): `c ? a : b`, `||`, `&&`,
//! `== != <>`, `< <= > >=`, `+ -`, `* / %`, `^` (power, left-associative and looser than
//! unary minus: `-2^2` is 4, `2^3^2` is 64), unary `- + !`, then numbers, names, array
//! elements `a[i][j]`, calls and parentheses. Trigonometric functions work in degrees;
//! `trunc` rounds to the nearest whole number and `%` works on the integer parts, as in
//! cpfg. A name that is neither a parameter of the production nor an array is a global
//! variable (0 until a statement assigns it).

mod compile;
#[cfg(test)]
mod tests;

pub(crate) use compile::{Scope, compile};

use super::builtins::{Arity, BUILTINS, Call, Func1, Func2, Special, builtin_names, unsupported};
use super::random::Random;
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
    /// Data files the grammar opens for reading (`fopen(name, "r")`), with where.
    pub(crate) reads: Vec<(String, usize)>,
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
    pub(crate) rng: Random,
    pub(crate) vars: Vec<f64>,
    pub(crate) arrays: std::sync::Arc<[ArrayDecl]>,
    /// The view file's functions, read by `func(id, x)` (id from 1).
    pub(crate) functions: std::sync::Arc<[super::function_files::Function]>,
    /// The view file's curves (`curve:`), read by `curveX/Y/Z` and `curveGAL`.
    pub(crate) curves: std::sync::Arc<[super::function_files::Curve]>,
    pub(crate) fault: Option<String>,
    /// Work units the last operations spent beyond their cost (a draw from `bran` or
    /// `biran` that took many tries), charged against `max_work` at the next spend.
    pub(crate) extra_work: u64,
}

impl Env {
    pub(crate) fn new(
        rng: Random,
        globals: &Globals,
        functions: std::sync::Arc<[super::function_files::Function]>,
    ) -> Self {
        Env {
            rng,
            vars: globals.init.clone(),
            arrays: globals.arrays.clone().into(),
            functions,
            curves: Vec::new().into(),
            fault: None,
            extra_work: 0,
        }
    }

    /// An environment without variables (constant folding, tests).
    pub(crate) fn empty(seed: u64) -> Self {
        Env {
            rng: Random::Arbor(Rng::new(seed)),
            vars: Vec::new(),
            arrays: Vec::new().into(),
            functions: Vec::new().into(),
            curves: Vec::new().into(),
            fault: None,
            extra_work: 0,
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

impl From<Call> for Op {
    fn from(call: Call) -> Op {
        match call {
            Call::F1(f) => Op::F1(f),
            Call::F2(f) => Op::F2(f),
            Call::Ran => Op::Ran,
            Call::Nran => Op::Nran,
            Call::Special(s) => Op::Special(s),
        }
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
    /// Bytecode, the deepest stack it needs, and its [`cost`](Expr::cost).
    Code(Box<[Op]>, usize, u32),
}

impl Expr {
    /// Evaluates with the production's bound parameters `args`.
    #[inline(always)]
    pub(crate) fn eval(&self, args: &[f64], env: &mut Env) -> f64 {
        match self {
            Expr::Const(c) => *c,
            Expr::Param(i) => args[*i as usize],
            Expr::Binary(op, a, b) => binary(*op, a.get(args), b.get(args)),
            Expr::Code(ops, depth, _) => run_code(ops, *depth, args, env),
        }
    }

    /// Work units one evaluation spends against `max_work` at most: one an operation,
    /// more for the calls that take longer (a power or a function of the C library
    /// four, a table or curve lookup sixteen). Jumps only shorten a run, so the count of
    /// the code is a bound. Counted once, when the expression is compiled.
    #[inline]
    pub(crate) fn cost(&self) -> u64 {
        match self {
            Expr::Const(_) | Expr::Param(_) => 1,
            Expr::Binary(op, _, _) => op_cost(op),
            Expr::Code(_, _, cost) => *cost as u64,
        }
    }

    /// Whether the value is known without any parameter or random draw.
    pub(crate) fn as_const(&self) -> Option<f64> {
        match self {
            Expr::Const(c) => Some(*c),
            // Code without parameters or random draws (a `?:`, say) has one value.
            Expr::Code(ops, depth, _)
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

/// See [`Expr::cost`].
pub(crate) fn op_cost(op: &Op) -> u64 {
    match op {
        Op::Pow | Op::F1(_) | Op::F2(_) | Op::Ran | Op::Nran => 4,
        Op::Special(_) => 16,
        _ => 1,
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
            // The common arithmetic in place, without a second dispatch in `binary`.
            Op::Add => {
                sp -= 1;
                stack[sp - 1] += stack[sp];
            }
            Op::Sub => {
                sp -= 1;
                stack[sp - 1] -= stack[sp];
            }
            Op::Mul => {
                sp -= 1;
                stack[sp - 1] *= stack[sp];
            }
            Op::Div => {
                sp -= 1;
                stack[sp - 1] /= stack[sp];
            }
            Op::Neg => stack[sp - 1] = -stack[sp - 1],
            Op::Not => stack[sp - 1] = b(stack[sp - 1] == 0.0),
            Op::F1(f) => stack[sp - 1] = f.apply(stack[sp - 1]),
            Op::Ran => stack[sp - 1] *= env.rng.uniform(),
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
            Op::Special(special) => sp = run_special(special, stack, sp, env),
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

/// The operations of [`Special`] (rare in a production, so out of the main loop): pops
/// and pushes on `stack` as [`run`] does, and returns the new stack height.
fn run_special(special: Special, stack: &mut [f64], mut sp: usize, env: &mut Env) -> usize {
    match special {
        Special::Srand => {
            env.rng.srand(stack[sp - 1]);
            stack[sp - 1] = 0.0;
        }
        Special::Bran => {
            sp -= 1;
            let mut tries = 0;
            stack[sp - 1] = env.rng.beta(stack[sp - 1], stack[sp], &mut tries);
            env.extra_work += 8 * tries;
        }
        Special::Func => {
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
        Special::CurveLength => {
            let id = stack[sp - 1];
            stack[sp - 1] = match env.curve(id) {
                Some(c) => c.length(),
                None => 0.0,
            };
        }
        Special::Curve(axis) => {
            sp -= 1;
            let (id, t) = (stack[sp - 1], stack[sp]);
            stack[sp - 1] = match env.curve(id) {
                Some(c) => c.at(t, axis as usize),
                None => 0.0,
            };
        }
        Special::Biran => {
            sp -= 1;
            let n = stack[sp - 1];
            stack[sp - 1] = env.rng.binomial(n, stack[sp]);
            if stack[sp - 1].is_finite() {
                // One draw a trial.
                env.extra_work += n as u64;
            }
        }
    }
    sp
}
