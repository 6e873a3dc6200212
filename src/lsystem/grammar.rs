//! The compiled form of a grammar: interned symbols, productions with compiled
//! expressions, and the settings the turtle reads.

use super::expr::Expr;
use super::stmt::Stmt;
use glam::DVec3;
use std::collections::HashMap;

/// Symbol id of `[`; fixed so the hot loops can test for brackets cheaply.
pub(crate) const PUSH: u16 = 0;
/// Symbol id of `]`.
pub(crate) const POP: u16 = 1;
/// Symbol id of `%` (cut).
pub(crate) const CUT: u16 = 2;
/// Symbol id of `=`: in a right context, the rest of the current branch (cpfg).
pub(crate) const REST: u16 = 3;

/// Interned module names.
#[derive(Clone, Debug)]
pub(crate) struct Symbols {
    pub(crate) names: Vec<String>,
    map: HashMap<String, u16>,
}

impl Symbols {
    pub(crate) fn new() -> Self {
        let mut s = Symbols {
            names: Vec::new(),
            map: HashMap::new(),
        };
        for name in ["[", "]", "%", "="] {
            s.intern(name);
        }
        s
    }

    /// The id of `name`, interning it; `None` past 65,536 distinct symbols.
    pub(crate) fn intern(&mut self, name: &str) -> Option<u16> {
        if let Some(&id) = self.map.get(name) {
            return Some(id);
        }
        let id = u16::try_from(self.names.len()).ok()?;
        self.names.push(name.to_string());
        self.map.insert(name.to_string(), id);
        Some(id)
    }

    pub(crate) fn len(&self) -> usize {
        self.names.len()
    }

    /// The id of `name`, if it is interned.
    pub(crate) fn get(&self, name: &str) -> Option<u16> {
        self.map.get(name).copied()
    }
}

/// A module of a predecessor or context: symbol, number of formal parameters, and the
/// slot of its first parameter among the production's bound values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Pattern {
    pub(crate) sym: u16,
    pub(crate) arity: u16,
    pub(crate) slot: u16,
}

/// A module of a successor: its symbol and the range of its parameter expressions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SuccModule {
    pub(crate) sym: u16,
    pub(crate) first: u32,
    pub(crate) count: u32,
}

/// A module list with its parameter expressions (a successor or the axiom).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ModuleList {
    pub(crate) modules: Vec<SuccModule>,
    pub(crate) exprs: Vec<Expr>,
    /// The symbols alone, to append in one copy.
    pub(crate) syms: Vec<u16>,
    /// For each module, the number of parameter values up to and including it.
    pub(crate) param_ends: Vec<u32>,
    /// The line of the grammar it was written on (for messages); 0 when unknown.
    pub(crate) line: u32,
}

impl ModuleList {
    /// Fills `syms` and `param_ends` from `modules`.
    pub(crate) fn finish(&mut self) {
        self.syms = self.modules.iter().map(|m| m.sym).collect();
        self.param_ends = self.modules.iter().map(|m| m.first + m.count).collect();
    }

    pub(crate) fn params(&self, m: &SuccModule) -> &[Expr] {
        &self.exprs[m.first as usize..(m.first + m.count) as usize]
    }
}

/// One production `lc < pred > rc : condition --> successor : probability`.
#[derive(Clone, Debug)]
pub(crate) struct Production {
    pub(crate) pred: Pattern,
    /// The modules after the first of a predecessor of several (`AB`, `[F(x)A]`),
    /// matched one after another.
    pub(crate) pred_rest: Vec<Pattern>,
    /// Statements run before the condition (they may change the bound parameters).
    pub(crate) pre: Vec<Stmt>,
    /// Statements run when the condition holds, before the successor is made.
    pub(crate) post: Vec<Stmt>,
    /// Left context in text order.
    pub(crate) left: Vec<Pattern>,
    /// Right context in text order; may contain `[` and `]`.
    pub(crate) right: Vec<Pattern>,
    pub(crate) condition: Option<Expr>,
    pub(crate) successor: ModuleList,
    /// Weight for stochastic choice; `None` for a deterministic production.
    pub(crate) probability: Option<Expr>,
    /// Number of bound parameters (left, predecessor, right, in text order).
    pub(crate) slots: usize,
    /// The line of the grammar it starts on (for messages).
    pub(crate) line: u32,
}

/// The bit of [`ProductionTable::arities`] for `arity` parameters.
#[inline]
pub(crate) fn arity_bit(arity: usize) -> u64 {
    1 << arity.min(63)
}

impl Production {
    /// Whether it applies to every module of its symbol and arity, without a choice.
    fn decides_nothing(&self) -> bool {
        self.pred_rest.is_empty()
            && self.left.is_empty()
            && self.right.is_empty()
            && self.pre.is_empty()
            && self.post.is_empty()
            && self.condition.is_none()
            && self.probability.is_none()
    }
}

/// The `Start:`, `End:`, `StartEach:` and `EndEach:` blocks of a grammar.
#[derive(Clone, Debug, Default)]
pub(crate) struct Blocks {
    pub(crate) start: Vec<Stmt>,
    pub(crate) end: Vec<Stmt>,
    pub(crate) start_each: Vec<Stmt>,
    pub(crate) end_each: Vec<Stmt>,
}

impl Blocks {
    pub(crate) fn is_empty(&self) -> bool {
        self.start.is_empty()
            && self.end.is_empty()
            && self.start_each.is_empty()
            && self.end_each.is_empty()
    }
}

/// A table of productions found by the predecessor's symbol.
#[derive(Clone, Debug, Default)]
pub(crate) struct ProductionTable {
    pub(crate) productions: Vec<Production>,
    /// For each symbol id, the indices of its productions in file order.
    pub(crate) by_symbol: Vec<Vec<u32>>,
    /// For each symbol id, whether it has any production.
    pub(crate) has_rules: Vec<bool>,
    /// For each symbol id, whether a production with a predecessor of several modules
    /// starts with it.
    pub(crate) multi: Vec<bool>,
    /// Interpretation and decomposition: how many times rules may re-apply.
    pub(crate) max_depth: u32,
    /// Whether a production has a left or right context.
    pub(crate) has_context: bool,
    /// For each symbol id, its production when it is the symbol's only one and has
    /// nothing to decide (no context, statements, condition or probability, one module):
    /// it applies whenever the arity matches. `u32::MAX` otherwise.
    pub(crate) only: Vec<u32>,
    /// Whether a right context holds `=` (the rest of the branch).
    pub(crate) has_rest: bool,
    /// For each symbol id, bit k (k < 63) set when a production's predecessor takes k
    /// parameters, bit 63 for 63 or more: a module whose bit is clear has no production.
    pub(crate) arities: Vec<u64>,
    /// For each production, the work units (against `max_work`) of trying it (matching
    /// its predecessor and context, its condition and probability) and of making its
    /// successor (its modules and their parameters' expressions).
    pub(crate) costs: Vec<(u64, u64)>,
}

impl ProductionTable {
    pub(crate) fn index(&mut self, symbols: usize) {
        self.by_symbol = vec![Vec::new(); symbols];
        for (i, p) in self.productions.iter().enumerate() {
            self.by_symbol[p.pred.sym as usize].push(i as u32);
        }
        self.has_rules = self.by_symbol.iter().map(|v| !v.is_empty()).collect();
        self.arities = vec![0; symbols];
        for p in &self.productions {
            self.arities[p.pred.sym as usize] |= arity_bit(p.pred.arity as usize);
        }
        self.has_rest = self
            .productions
            .iter()
            .any(|p| p.right.iter().any(|r| r.sym == REST));
        self.only = self
            .by_symbol
            .iter()
            .map(|v| match v[..] {
                [p] if self.productions[p as usize].decides_nothing() => p,
                _ => u32::MAX,
            })
            .collect();
        self.costs = self
            .productions
            .iter()
            .map(|p| {
                let tried = 1
                    + (p.pred_rest.len() + p.left.len() + p.right.len()) as u64
                    + p.slots as u64
                    + p.condition.as_ref().map_or(0, Expr::cost)
                    + p.probability.as_ref().map_or(0, Expr::cost);
                let made = p.successor.modules.len() as u64
                    + p.successor.exprs.iter().map(Expr::cost).sum::<u64>();
                (tried, made)
            })
            .collect();
        self.multi = vec![false; symbols];
        self.has_context = self
            .productions
            .iter()
            .any(|p| !p.left.is_empty() || !p.right.is_empty());
        for p in &self.productions {
            if !p.pred_rest.is_empty() {
                self.multi[p.pred.sym as usize] = true;
            }
        }
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.productions.is_empty()
    }

    #[inline]
    pub(crate) fn candidates(&self, sym: u16) -> &[u32] {
        &self.by_symbol[sym as usize]
    }
}

/// Settings cpfg keeps in its view file, written as directives in the grammar. Read it
/// with [`LSystem::view`](crate::lsystem::LSystem::view); `#[non_exhaustive]`: settings
/// may be added.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct ViewSettings {
    /// `angle increment:` degrees turned by `+ - & ^ / \` without a parameter. Default 45.
    pub angle_increment: f64,
    /// `initial line width:` the turtle's starting width (a diameter). Default 1.
    pub initial_width: f64,
    /// `line width increment:` what `!` and `#` without a parameter subtract and add.
    /// Default 1.
    pub width_increment: f64,
    /// `tropism: T: x y z E: e`: the tropism vector T and elasticity e; before each `F`
    /// the heading bends toward T by e·|H × T| radians (at most 1). Default none.
    pub tropism: Option<(DVec3, f64)>,
    /// Length of `F`, `G`, `f`, `g` without a parameter. Default 1.
    pub step_size: f64,
    /// The view file's `tropism direction:` with `initial elasticity:` and `elasticity
    /// increment:` (cpfg's older tropism). Default none.
    pub old_tropism: Option<OldTropism>,
    /// The view file's `initial color:`: the turtle's first colour index. Default 1.
    pub initial_color: u32,
    /// The view file's `color increment:`: what `;` adds and `,` subtracts. Default 1.
    pub color_increment: u32,
    /// The view file's `interpretation past %:` (default on): the turtle draws past a `%`
    /// the last step made (off: it skips the rest of that branch).
    pub interpretation_past_cut: bool,
}

/// cpfg's older tropism: after every `F` the heading H turns toward the tropism vector T
/// by asin(e·(T·U)) about L (toward U) and by asin(e·(T·L)) about U (toward L); `_(e)`
/// sets e and `_` adds the increment.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct OldTropism {
    /// T, a unit vector.
    pub direction: DVec3,
    /// e at the start.
    pub elasticity: f64,
    /// What `_` without a parameter adds to e.
    pub increment: f64,
}

impl Default for ViewSettings {
    fn default() -> Self {
        ViewSettings {
            angle_increment: 45.0,
            initial_width: 1.0,
            width_increment: 1.0,
            tropism: None,
            step_size: 1.0,
            old_tropism: None,
            initial_color: 1,
            color_increment: 1,
            interpretation_past_cut: true,
        }
    }
}

/// The index of the `]` that closes the branch `syms[from..]` starts inside (nested
/// branches skipped whole); `None` when it is never closed.
pub(super) fn branch_end(syms: &[u16], from: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (k, &sym) in syms.iter().enumerate().skip(from) {
        match sym {
            PUSH => depth += 1,
            POP if depth == 0 => return Some(k),
            POP => depth -= 1,
            _ => {}
        }
    }
    None
}
