//! The lines before and between productions: blocks, sections, settings, arrays and
//! tropisms.

use super::*;

impl Parser<'_> {
    pub(super) fn line(&mut self, start: usize, end: usize) -> PResult<()> {
        let raw = &self.text[start..end];
        let lead = raw.len() - raw.trim_start().len();
        let line = raw.trim();
        let at = start + lead;
        if line.is_empty() {
            return Ok(());
        }
        // Where the text after a keyword starts, past its leading blanks.
        let rest_at = |rest: &str| at + (line.len() - rest.trim_start().len());
        if self.ended {
            if keyword(line, "lsystem:").is_some() {
                return Err(self.msg(at, "sub-L-systems (a second `Lsystem:`) are not supported"));
            }
            return Err(self.err(at, "nothing after `endlsystem`"));
        }
        for (key, which) in [
            ("starteach:", 2),
            ("start each:", 2),
            ("endeach:", 3),
            ("end each:", 3),
            ("start:", 0),
            ("end:", 1),
        ] {
            if let Some(rest) = keyword(line, key) {
                let stmts = self.block(rest_at(rest), end)?;
                let b = &mut self.blocks;
                let slot = [&mut b.start, &mut b.end, &mut b.start_each, &mut b.end_each];
                slot.into_iter()
                    .nth(which)
                    .expect("four blocks")
                    .extend(stmts);
                return Ok(());
            }
        }
        if let Some(rest) = keyword(line, "define:") {
            return self.arrays(rest_at(rest), end);
        }
        if keyword(line, "ring lsystem").is_some() || keyword(line, "ring l-system").is_some() {
            self.ring = true;
            return Ok(());
        }
        if let Some(rest) = keyword(line, "lsystem:") {
            if self.lsystem_seen {
                return Err(self.msg(at, "sub-L-systems (a second `Lsystem:`) are not supported"));
            }
            self.lsystem_seen = true;
            let _ = rest;
            return Ok(());
        }
        if keyword(line, "endlsystem").is_some() {
            self.ended = true;
            return Ok(());
        }
        if self.setting(line, at, end)? {
            return Ok(());
        }
        // `homomorphism`, `homomorphism:`, `homomorphism: warnings` / `no warnings`, and
        // what follows on the line when a TAB continued it.
        for (key, section) in [
            ("homomorphism", Section::Homomorphism),
            ("interpretation:", Section::Homomorphism),
            ("decomposition", Section::Decomposition),
        ] {
            if let Some(rest) = keyword(line, key) {
                self.section = section;
                let mut rest = rest.trim_start();
                rest = rest.strip_prefix(':').unwrap_or(rest).trim_start();
                for w in ["no warnings", "warnings"] {
                    if let Some(r) = keyword(rest, w) {
                        rest = r.trim_start();
                    }
                }
                if rest.is_empty() {
                    return Ok(());
                }
                let at = rest_at(rest);
                return self.line(at, end);
            }
        }
        if let Some(rest) = keyword(line, "tropism:") {
            return self.tropism(rest_at(rest), end);
        }
        self.production(at, end)
    }

    /// A setting line at `at` (derivation length, seed, axiom, ignore/consider, maximum
    /// depth, view numbers); `false` when `line` is none of them.
    fn setting(&mut self, line: &str, at: usize, end: usize) -> PResult<bool> {
        // Where the text after a keyword starts, past its leading blanks.
        let rest_at = |rest: &str| at + (line.len() - rest.trim_start().len());
        if let Some(rest) =
            keyword(line, "derivation length:").or_else(|| keyword(line, "derivationlength:"))
        {
            let v = self.const_expr(rest_at(rest), end, "a derivation length")?;
            // cpfg takes any int; a long derivation ends itself (`stop()`) or meets
            // max_work, which every step spends at least STEP_WORK of.
            if !(v.is_finite() && v >= 0.0 && v <= u32::MAX as f64 && v.fract() == 0.0) {
                return Err(self.err(
                    rest_at(rest),
                    "a whole number of steps from 0 to 4294967295",
                ));
            }
            self.derivation_length = v as u32;
            return Ok(true);
        }
        if let Some(rest) = keyword(line, "seed:") {
            let v = self.const_expr(rest_at(rest), end, "a seed")?;
            if !(v.is_finite() && v >= 0.0 && v.fract() == 0.0) {
                return Err(self.err(rest_at(rest), "a whole, non-negative seed"));
            }
            self.seed = Some(v as u64);
            return Ok(true);
        }
        if let Some(rest) = keyword(line, "axiom:") {
            if self.axiom.is_some() {
                return Err(self.err(at, "one `Axiom:` line only"));
            }
            let mut cur = Cursor::range(self.text, rest_at(rest), end);
            let axiom_at = cur.pos();
            let mut list = self.module_list(&mut cur, &[], false, true)?;
            list.line = crate::lsystem::syntax::line_col(self.text, axiom_at).0;
            cur.skip_ws();
            if !cur.at_end() {
                return Err(cur.error("a module"));
            }
            self.axiom = Some(list);
            return Ok(true);
        }
        for (key, is_ignore) in [
            ("ignore:", true),
            ("#ignore:", true),
            ("consider:", false),
            ("#consider:", false),
        ] {
            if let Some(rest) = keyword(line, key) {
                if self.ignore.is_some() || self.consider.is_some() {
                    return Err(self.err(at, "one `ignore:` or `consider:` line, not both"));
                }
                let mut cur = Cursor::range(self.text, rest_at(rest), end);
                let mut list = Vec::new();
                loop {
                    cur.skip_ws();
                    if cur.at_end() {
                        break;
                    }
                    let sym = self.symbol(&mut cur)?;
                    list.push(sym);
                }
                if is_ignore {
                    self.ignore = Some(list);
                } else {
                    self.consider = Some(list);
                }
                return Ok(true);
            }
        }
        if let Some(rest) = keyword(line, "maximum depth:") {
            let v = self.const_expr(rest_at(rest), end, "a maximum depth")?;
            if !(v.is_finite() && (0.0..=1_000_000.0).contains(&v) && v.fract() == 0.0) {
                return Err(self.err(rest_at(rest), "a whole maximum depth from 0 to 1000000"));
            }
            match self.section {
                Section::Homomorphism => self.homomorphism.max_depth = v as u32,
                Section::Decomposition => self.decomposition.max_depth = v as u32,
                Section::Productions => {
                    return Err(self.err(
                        at,
                        "`maximum depth:` after `homomorphism` or `decomposition`",
                    ));
                }
            }
            return Ok(true);
        }
        for (key, field) in [
            ("angle increment:", 0),
            ("initial line width:", 1),
            ("line width increment:", 2),
            ("step size:", 3),
        ] {
            if let Some(rest) = keyword(line, key) {
                let v = self.const_expr(rest_at(rest), end, "a number")?;
                if !v.is_finite() || (field != 0 && v < 0.0) {
                    return Err(self.err(rest_at(rest), "a finite, non-negative number"));
                }
                match field {
                    0 => self.view.angle_increment = v,
                    1 => self.view.initial_width = v,
                    2 => self.view.width_increment = v,
                    _ => self.view.step_size = v,
                }
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// `define: { array a[n] = { v, ... }, b[n][m]; ... }`.
    pub(super) fn arrays(&mut self, pos: usize, end: usize) -> PResult<()> {
        let mut cur = Cursor::range(self.text, pos, end);
        cur.skip_ws();
        if !cur.eat("{") {
            return Err(cur.error("`{` opening the `define:` block"));
        }
        loop {
            cur.skip_ws();
            if cur.eat("}") {
                break;
            }
            if cur.eat(";") {
                continue;
            }
            if cur.identifier() != Some("array") {
                return Err(cur.error("`array name[size];` in the `define:` block"));
            }
            loop {
                cur.skip_ws();
                let name_at = cur.pos();
                let Some(name) = cur.identifier() else {
                    return Err(cur.error("an array name"));
                };
                let name = name.to_string();
                let mut dims = Vec::new();
                let mut total = 1usize;
                loop {
                    cur.skip_ws();
                    if !cur.eat("[") {
                        break;
                    }
                    let at = cur.pos();
                    let e = {
                        let scope = Scope {
                            params: &[],
                            defines: &self.defines,
                            globals: None,
                        };
                        expr::compile(&mut cur, &scope)?
                    };
                    let n = e.as_const().unwrap_or(f64::NAN);
                    if !(n >= 1.0 && n <= expr::MAX_GLOBAL_VALUES as f64) {
                        return Err(self.err(at, "a constant array size from 1 to 4194304"));
                    }
                    cur.skip_ws();
                    if !cur.eat("]") {
                        return Err(cur.error("`]` after the array size"));
                    }
                    dims.push(n as u32);
                    total = total.saturating_mul(n as usize);
                }
                if dims.is_empty() {
                    return Err(cur.error("`[size]` after the array name"));
                }
                let mut g = self.globals.borrow_mut();
                if g.array(&name).is_some() || g.var(&name).is_some() {
                    return Err(self.msg(name_at, &format!("`{name}` is declared twice")));
                }
                if g.init.len() + total > expr::MAX_GLOBAL_VALUES {
                    return Err(self.msg(name_at, "arrays of at most 4194304 values in all"));
                }
                let offset = g.init.len() as u32;
                let len = g.init.len() + total;
                g.init.resize(len, 0.0);
                g.arrays.push(expr::ArrayDecl { name, dims, offset });
                drop(g);
                cur.skip_ws();
                if cur.eat("=") {
                    let values = self.initial_values(&mut cur, name_at, total)?;
                    let o = offset as usize;
                    self.globals.borrow_mut().init[o..o + values.len()].copy_from_slice(&values);
                }
                cur.skip_ws();
                if cur.eat(",") {
                    continue;
                }
                break;
            }
            cur.skip_ws();
            if !cur.eat(";") && !cur.peek_str("}") {
                return Err(cur.error("`;` after the array declaration"));
            }
        }
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the line after the `define:` block"));
        }
        Ok(())
    }

    /// The initial values after an array's `=`, flat or nested in braces, in row-major
    /// order: at most `total` of them.
    fn initial_values(
        &self,
        cur: &mut Cursor<'_>,
        name_at: usize,
        total: usize,
    ) -> PResult<Vec<f64>> {
        let mut values = Vec::new();
        let mut depth = 0usize;
        loop {
            cur.skip_ws();
            if cur.eat("{") {
                depth += 1;
                if depth > 16 {
                    return Err(cur.error("initial values nested at most 16 deep"));
                }
                continue;
            }
            if cur.eat("}") {
                if depth == 0 {
                    return Err(cur.error("a value"));
                }
                depth -= 1;
                if depth == 0 {
                    break;
                }
                continue;
            }
            if cur.eat(",") {
                continue;
            }
            let at = cur.pos();
            let scope = Scope {
                params: &[],
                defines: &self.defines,
                globals: None,
            };
            let v = expr::compile(cur, &scope)?
                .as_const()
                .ok_or_else(|| self.err(at, "a constant initial value"))?;
            values.push(v);
            if depth == 0 {
                break;
            }
        }
        if values.len() > total {
            return Err(self.err(
                name_at,
                &format!("at most {total} initial values for this array"),
            ));
        }
        Ok(values)
    }

    pub(super) fn const_expr(&self, pos: usize, end: usize, what: &str) -> PResult<f64> {
        let mut cur = Cursor::range(self.text, pos, end);
        cur.skip_ws();
        if cur.at_end() {
            return Err(cur.error(what));
        }
        let scope = Scope {
            params: &[],
            defines: &self.defines,
            globals: None,
        };
        let e = expr::compile(&mut cur, &scope)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the line after the value"));
        }
        e.as_const()
            .ok_or_else(|| self.err(pos, &format!("{what} that is constant (no ran/nran)")))
    }

    pub(super) fn tropism(&mut self, pos: usize, end: usize) -> PResult<()> {
        let mut cur = Cursor::range(self.text, pos, end);
        // Components are separated by spaces or commas, so each is a signed number or a
        // #define name, not a full expression (`0 -1 0` is three numbers).
        let defines = &self.defines;
        let number = |cur: &mut Cursor<'_>| -> PResult<f64> {
            cur.skip_ws();
            cur.eat(",");
            cur.skip_ws();
            let at = cur.pos();
            let sign = if cur.eat("-") {
                -1.0
            } else {
                cur.eat("+");
                1.0
            };
            let v = match cur.number()? {
                Some(v) => v,
                None => match cur.identifier().and_then(|n| defines.get(n)) {
                    Some(&v) => v,
                    None => return Err(cur.error_at(at, "a number or a #define name")),
                },
            };
            Ok(sign * v)
        };
        cur.skip_ws();
        if !(cur.eat("T:") || cur.eat("t:")) {
            return Err(cur.error("`T:` and the tropism vector (tropism: T: x y z E: e)"));
        }
        let t = DVec3::new(number(&mut cur)?, number(&mut cur)?, number(&mut cur)?);
        cur.skip_ws();
        cur.eat(",");
        cur.skip_ws();
        if !(cur.eat("E:") || cur.eat("e:")) {
            return Err(cur.error("`E:` and the elasticity (tropism: T: x y z E: e)"));
        }
        let e = number(&mut cur)?;
        cur.skip_ws();
        if !cur.at_end() {
            return Err(cur.error("the end of the tropism line"));
        }
        self.view.tropism = Some((t, e));
        Ok(())
    }
}
