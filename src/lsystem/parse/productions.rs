//! Productions: symbols, module lists, predecessor patterns with their contexts and
//! conditions, successors with their probabilities, and statements.

use super::scan::{find_arrow, skip_string, top_level, top_level_last};
use super::*;
use crate::lsystem::expr::Expr;

impl Parser<'_> {
    /// A symbol: one character, or `@` and a letter (`@M`, `@R`, `@v`, ...).
    pub(super) fn symbol(&mut self, cur: &mut Cursor<'_>) -> PResult<u16> {
        let at = cur.pos();
        let Some(c) = cur.bump() else {
            return Err(cur.error("a module"));
        };
        let name_end;
        // cpfg reads `@ Tx` as `@Tx`: blanks between `@` and its letters are passed over.
        let mut gap = None;
        if c == '@' && cur.peek().is_some_and(|b| b == ' ' || b == '\t') {
            let before = cur.pos();
            while cur.peek().is_some_and(|b| b == ' ' || b == '\t') {
                cur.bump();
            }
            gap = Some(before..cur.pos());
        }
        match c {
            '(' | ')' | ':' => {
                return Err(cur.error_at(at, "a module (a letter or a turtle symbol)"));
            }
            '@' => match cur.peek() {
                // `@;` `@!` and the like: cpfg's variants of the one-character modules.
                Some(p) if p.is_ascii_punctuation() && !matches!(p, '(' | ')' | '[' | ']') => {
                    cur.bump();
                    name_end = cur.pos();
                }
                Some(l) if l.is_ascii_alphabetic() => {
                    cur.bump();
                    // `@Tx`-style texture switches are three characters.
                    if l == 'T' && cur.peek().is_some_and(|c| c.is_ascii_lowercase()) {
                        cur.bump();
                    }
                    // cpfg's generalized cylinders are two letters after `@`: @Gs (start),
                    // @Gc (control point), @Ge (end), @Gt and @Gr (tangent, radius).
                    if l == 'G' && matches!(cur.peek(), Some('s' | 'c' | 'e' | 't' | 'r')) {
                        cur.bump();
                    }
                    name_end = cur.pos();
                }
                _ => return Err(cur.error("a letter after `@` (such as @M, @R or @v)")),
            },
            c if c.is_whitespace() || c.is_control() => {
                return Err(cur.error_at(at, "a module (a letter or a turtle symbol)"));
            }
            // Query modules (`?P`, `?H`, `?U`, `?L`, `?E`) and surfaces (`~l`) are two
            // characters, as cpfg reads them.
            '?' | '~' if cur.peek().is_some_and(|l| l.is_ascii_alphanumeric()) => {
                cur.bump();
                name_end = cur.pos();
            }
            _ => name_end = cur.pos(),
        }
        let name = match gap {
            Some(g) => format!("{}{}", &self.text[at..g.start], &self.text[g.end..name_end]),
            None => self.text[at..name_end].to_string(),
        };
        self.symbols
            .intern(&name)
            .ok_or_else(|| self.msg(at, "too many distinct symbols (at most 65536)"))
    }

    /// A successor or axiom: modules with parameter expressions, until the end of the
    /// range or a top-level `:`. Brackets must balance.
    pub(super) fn module_list(
        &mut self,
        cur: &mut Cursor<'_>,
        params: &[(String, u16)],
        stop_at_colon: bool,
        balanced: bool,
    ) -> PResult<ModuleList> {
        let mut list = ModuleList::default();
        let mut open: Vec<usize> = Vec::new();
        cur.skip_ws();
        if cur.rest().trim() == "*" {
            cur.eat("*");
            list.finish();
            return Ok(list);
        }
        loop {
            cur.skip_ws();
            if cur.at_end() || (stop_at_colon && cur.peek_str(":")) {
                break;
            }
            let at = cur.pos();
            let sym = self.symbol(cur)?;
            if sym == PUSH {
                open.push(at);
            } else if sym == POP && open.pop().is_none() && balanced {
                return Err(self.msg(at, "unbalanced brackets: this `]` closes no `[`"));
            }
            let first = list.exprs.len() as u32;
            cur.skip_ws();
            if cur.eat("(") {
                let scope = Scope {
                    params,
                    defines: &self.defines,
                    globals: Some(&self.globals),
                };
                loop {
                    cur.skip_ws();
                    if cur.peek_str("\"") {
                        // A text parameter (`@L("label")`): labels have no geometry, so
                        // the text is read and the value is 0.
                        skip_string(cur)?;
                        list.exprs.push(expr::Expr::Const(0.0));
                    } else {
                        list.exprs.push(expr::compile(cur, &scope)?);
                    }
                    cur.skip_ws();
                    if cur.eat(",") {
                        continue;
                    }
                    if cur.eat(")") {
                        break;
                    }
                    return Err(cur.error("`,` or `)` after a module parameter"));
                }
                if list.exprs.len() - first as usize > u16::MAX as usize {
                    return Err(self.err(at, "at most 65535 parameters on a module"));
                }
            }
            list.modules.push(SuccModule {
                sym,
                first,
                count: list.exprs.len() as u32 - first,
            });
        }
        if let (Some(&at), true) = (open.last(), balanced) {
            return Err(self.msg(at, "unbalanced brackets: this `[` is never closed"));
        }
        list.finish();
        Ok(list)
    }

    /// Modules with formal parameter names (a predecessor or a context).
    pub(super) fn patterns(
        &mut self,
        cur: &mut Cursor<'_>,
        names: &mut Vec<(String, u16)>,
        allow_brackets: bool,
    ) -> PResult<Vec<Pattern>> {
        let mut out = Vec::new();
        cur.skip_ws();
        if cur.rest().trim() == "*" {
            cur.eat("*");
            return Ok(out);
        }
        loop {
            cur.skip_ws();
            if cur.at_end() {
                return Ok(out);
            }
            let at = cur.pos();
            let sym = self.symbol(cur)?;
            if (sym == PUSH || sym == POP) && !allow_brackets {
                return Err(self.msg(at, "brackets are supported in a right context only"));
            }
            let slot = names.len() as u16;
            let mut arity = 0u16;
            cur.skip_ws();
            if cur.eat("(") {
                loop {
                    cur.skip_ws();
                    let name_at = cur.pos();
                    let Some(name) = cur.identifier() else {
                        return Err(cur.error("a parameter name"));
                    };
                    if names.iter().any(|(n, _)| n == name) {
                        return Err(self.err(
                            name_at,
                            "a parameter name not used before in this production",
                        ));
                    }
                    if names.len() >= 1024 {
                        return Err(self.err(name_at, "at most 1024 parameters in a production"));
                    }
                    names.push((name.to_string(), names.len() as u16));
                    arity += 1;
                    cur.skip_ws();
                    if cur.eat(",") {
                        continue;
                    }
                    if cur.eat(")") {
                        break;
                    }
                    return Err(cur.error("`,` or `)` after a parameter name"));
                }
            }
            out.push(Pattern { sym, arity, slot });
        }
    }

    pub(super) fn production(&mut self, start: usize, end: usize) -> PResult<()> {
        let text = &self.text[start..end];
        let Some((arrow, arrow_len)) = find_arrow(text) else {
            return Err(self.err(
                start,
                "a production with `-->` or a directive such as `Axiom:` or `derivation length:`",
            ));
        };
        let (arrow, after) = (start + arrow, start + arrow + arrow_len);
        // Left side: [lc <] pred [> rc] [: [{pre}] [condition] [{post}]]
        let left = &self.text[start..arrow];
        let colon = top_level(left, b':').map(|i| start + i);
        let pred_end = colon.unwrap_or(arrow);
        let pred_text = &self.text[start..pred_end];
        let lt = top_level(pred_text, b'<').map(|i| start + i);
        let gt = top_level_last(pred_text, b'>').map(|i| start + i);
        let (lc_range, pred_range, rc_range) = match (lt, gt) {
            (Some(l), Some(g)) if g > l => ((start, l), (l + 1, g), (g + 1, pred_end)),
            (Some(l), None) => ((start, l), (l + 1, pred_end), (pred_end, pred_end)),
            (None, Some(g)) => ((start, start), (start, g), (g + 1, pred_end)),
            (None, None) => ((start, start), (start, pred_end), (pred_end, pred_end)),
            (Some(_), Some(g)) => return Err(self.err(g, "`<` before `>` in the context")),
        };
        let mut names = Vec::new();
        let left_ctx = self.patterns(
            &mut Cursor::range(self.text, lc_range.0, lc_range.1),
            &mut names,
            false,
        )?;
        let pred = self.patterns(
            &mut Cursor::range(self.text, pred_range.0, pred_range.1),
            &mut names,
            true,
        )?;
        let right_ctx = self.patterns(
            &mut Cursor::range(self.text, rc_range.0, rc_range.1),
            &mut names,
            true,
        )?;
        let (pred, pred_rest) = match pred.split_first() {
            Some((p, rest)) => (*p, rest.to_vec()),
            None => return Err(self.err(pred_range.0, "a predecessor module before `-->`")),
        };
        if pred_rest.is_empty()
            && (pred.sym == PUSH || pred.sym == POP)
            && self.section != Section::Homomorphism
        {
            return Err(self.msg(
                pred_range.0,
                "a bracket alone as a predecessor is rewritten only by interpretation rules",
            ));
        }
        let mut scope_names = names.clone();
        let (pre, post, condition) = match colon {
            Some(c) => self.guard(c + 1, arrow, &scope_names)?,
            None => (Vec::new(), Vec::new(), None),
        };
        scope_names.truncate(names.len());
        let mut cur = Cursor::range(self.text, after, end);
        // Interpretation rules feed only the turtle, so they may open or close a branch
        // (`[ --> [+`); strings that are derived further must stay balanced.
        let interpretation = self.section == Section::Homomorphism;
        let successor_at = cur.pos();
        let mut successor = self.module_list(&mut cur, &scope_names, true, !interpretation)?;
        let line = crate::lsystem::syntax::line_col(self.text, start).0;
        successor.line = crate::lsystem::syntax::line_col(self.text, successor_at).0;
        let probability = self.probability(&mut cur, &scope_names)?;
        // Interpretation rules may have context (cpfg is built with it), read from the
        // L-system string; decomposition rules may not.
        if self.section == Section::Decomposition && (!left_ctx.is_empty() || !right_ctx.is_empty())
        {
            return Err(self.msg(start, "context in decomposition rules is not supported"));
        }
        let production = Production {
            pred,
            pred_rest,
            pre,
            post,
            left: left_ctx,
            right: right_ctx,
            condition,
            successor,
            probability,
            slots: names.len(),
            line,
        };
        match self.section {
            Section::Productions => self.productions.productions.push(production),
            Section::Homomorphism => self.homomorphism.productions.push(production),
            Section::Decomposition => self.decomposition.productions.push(production),
        }
        Ok(())
    }

    /// What stands between a production's `:` (at `from`) and its arrow: statements
    /// before, the condition (none for `*`), statements after.
    fn guard(
        &self,
        from: usize,
        arrow: usize,
        scope_names: &[(String, u16)],
    ) -> PResult<(Vec<Stmt>, Vec<Stmt>, Option<Expr>)> {
        let (mut pre, mut post, mut condition) = (Vec::new(), Vec::new(), None);
        let mut cur = Cursor::range(self.text, from, arrow);
        cur.skip_ws();
        if cur.peek_str("{") {
            pre = self.statements(&mut cur, scope_names)?;
            cur.skip_ws();
        }
        let star = cur.peek_str("*") && {
            let mut probe = cur.clone();
            probe.eat("*");
            probe.skip_ws();
            probe.at_end() || probe.peek_str("{")
        };
        if star {
            cur.eat("*");
        } else if !cur.at_end() && !cur.peek_str("{") {
            let scope = Scope {
                params: scope_names,
                defines: &self.defines,
                globals: Some(&self.globals),
            };
            condition = Some(expr::compile(&mut cur, &scope)?);
        }
        cur.skip_ws();
        if cur.peek_str("{") {
            post = self.statements(&mut cur, scope_names)?;
            cur.skip_ws();
        }
        if !cur.at_end() {
            return Err(cur.error("`-->` after the condition"));
        }
        Ok((pre, post, condition))
    }

    /// The probability after a successor's `:`, if it has one.
    fn probability(
        &self,
        cur: &mut Cursor<'_>,
        scope_names: &[(String, u16)],
    ) -> PResult<Option<Expr>> {
        if !cur.eat(":") {
            return Ok(None);
        }
        let scope = Scope {
            params: scope_names,
            defines: &self.defines,
            globals: Some(&self.globals),
        };
        cur.skip_ws();
        let at = cur.pos();
        let e = expr::compile(cur, &scope)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the production after its probability"));
        }
        if let Some(v) = e.as_const() {
            if !(v.is_finite() && v >= 0.0) {
                return Err(self.err(at, "a finite probability >= 0"));
            }
        }
        Ok(Some(e))
    }

    pub(super) fn statements(
        &self,
        cur: &mut Cursor<'_>,
        names: &[(String, u16)],
    ) -> PResult<Vec<Stmt>> {
        let scope = Scope {
            params: names,
            defines: &self.defines,
            globals: Some(&self.globals),
        };
        stmt::block(cur, &scope)
    }
}
