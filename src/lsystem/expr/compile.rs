//! Compiling expression text into bytecode: precedence climbing, constant folding and
//! calls of the built-ins.

use super::*;

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
        _ => {
            let cost = c.ops.iter().map(super::op_cost).sum::<u64>();
            Expr::Code(
                c.ops.into_boxed_slice(),
                c.max_depth,
                cost.min(u32::MAX as u64) as u32,
            )
        }
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
            (Arity::One(op), 1) | (Arity::OneOrTwo(op, _), 1) => self.emit_unary(op.into(), start),
            (Arity::Two(op), 2) | (Arity::OneOrTwo(_, op), 2) => self.push_two(op.into(), start),
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
    /// goes to the log; one opened for reading is noted for the loader (see
    /// `parse::data_files`) and is cpfg's handle of a file it could not open (-1).
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
            if let Some(globals) = self.scope.globals {
                globals.borrow_mut().reads.push((strings[0].clone(), at));
                self.push(Op::Const(-1.0));
                return Ok(());
            }
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
