//! `#if` and `#elif` expressions.

use super::*;

impl Pre<'_> {
    /// Evaluates an `#if` / `#elif` expression.
    pub(super) fn condition(&mut self, args: &str, file: &str, line: u32) -> Result<bool> {
        // `defined X` and `defined(X)` first, before expansion.
        let toks = tokenize(args);
        let mut pre = Vec::new();
        let mut i = 0;
        while i < toks.len() {
            if toks[i].kind == Kind::Ident && toks[i].text == "defined" {
                let mut j = skip_space(&toks, i + 1);
                let paren = toks.get(j).is_some_and(|t| t.is("("));
                if paren {
                    j = skip_space(&toks, j + 1);
                }
                let Some(name) = toks.get(j).filter(|t| t.kind == Kind::Ident) else {
                    return Err(perr(file, line, "a macro name after `defined`".into()));
                };
                let v = self.macros.contains_key(&name.text);
                if paren {
                    j = skip_space(&toks, j + 1);
                    if !toks.get(j).is_some_and(|t| t.is(")")) {
                        return Err(perr(file, line, "`)` after `defined(NAME`".into()));
                    }
                }
                pre.push(Tok {
                    kind: Kind::Number,
                    text: if v { "1".into() } else { "0".into() },
                    hide: 0,
                });
                i = j + 1;
                continue;
            }
            pre.push(toks[i].clone());
            i += 1;
        }
        let Some(expanded) = self.expand(pre, file, line)? else {
            return Err(err_unterminated(file, line));
        };
        let toks: Vec<Tok> = expanded
            .into_iter()
            .filter(|t| t.kind != Kind::Space)
            .collect();
        let mut e = CondEval {
            toks: &toks,
            pos: 0,
            depth: 0,
        };
        let v = e
            .ternary()
            .map_err(|m| perr(file, line, format!("in `#if {}`: {m}", args.trim())))?;
        if e.pos < toks.len() {
            return Err(perr(
                file,
                line,
                format!(
                    "in `#if {}`: unexpected `{}` after the condition",
                    args.trim(),
                    toks[e.pos].text
                ),
            ));
        }
        Ok(v != 0)
    }
}

/// Integer expressions of `#if` (names left after expansion are 0, as in C).
struct CondEval<'a> {
    toks: &'a [Tok],
    pos: usize,
    depth: usize,
}

type CResult = std::result::Result<i64, String>;

impl CondEval<'_> {
    fn peek(&self) -> Option<&str> {
        self.toks.get(self.pos).map(|t| t.text.as_str())
    }

    /// Eats a punctuator sequence such as `&&` or `<=` (tokens are single characters).
    fn eat(&mut self, op: &str) -> bool {
        let n = op.chars().count();
        if self.pos + n > self.toks.len() {
            return false;
        }
        let text: String = self.toks[self.pos..self.pos + n]
            .iter()
            .map(|t| t.text.as_str())
            .collect();
        let all_punct = self.toks[self.pos..self.pos + n]
            .iter()
            .all(|t| t.kind == Kind::Punct);
        if all_punct && text == op {
            // `<` must not be the start of `<=` or `<<` unless asked.
            self.pos += n;
            true
        } else {
            false
        }
    }

    fn ternary(&mut self) -> CResult {
        self.depth += 1;
        if self.depth > 200 {
            return Err("the condition nests too deeply".into());
        }
        let c = self.binary(0)?;
        let v = if self.eat("?") {
            let a = self.ternary()?;
            if !self.eat(":") {
                return Err("`:` of `?:`".into());
            }
            let b = self.ternary()?;
            if c != 0 { a } else { b }
        } else {
            c
        };
        self.depth -= 1;
        Ok(v)
    }

    fn binary(&mut self, level: usize) -> CResult {
        const LEVELS: &[&[&str]] = &[
            &["||"],
            &["&&"],
            &["|"],
            &["^"],
            &["&"],
            &["==", "!="],
            &["<=", ">=", "<<", ">>", "<", ">"],
            &["+", "-"],
            &["*", "/", "%"],
        ];
        if level == LEVELS.len() {
            return self.unary();
        }
        let mut v = self.binary(level + 1)?;
        'outer: loop {
            for &op in LEVELS[level] {
                // `&` and `|` must not eat `&&` / `||`.
                if (op == "&" && self.peek_two("&&")) || (op == "|" && self.peek_two("||")) {
                    continue;
                }
                if (op == "<" || op == ">") && (self.peek_two("<=") || self.peek_two(">=")) {
                    continue;
                }
                if self.eat(op) {
                    let r = self.binary(level + 1)?;
                    v = match op {
                        "||" => ((v != 0) || (r != 0)) as i64,
                        "&&" => ((v != 0) && (r != 0)) as i64,
                        "|" => v | r,
                        "^" => v ^ r,
                        "&" => v & r,
                        "==" => (v == r) as i64,
                        "!=" => (v != r) as i64,
                        "<=" => (v <= r) as i64,
                        ">=" => (v >= r) as i64,
                        "<<" => v.wrapping_shl(r as u32),
                        ">>" => v.wrapping_shr(r as u32),
                        "<" => (v < r) as i64,
                        ">" => (v > r) as i64,
                        "+" => v.wrapping_add(r),
                        "-" => v.wrapping_sub(r),
                        "*" => v.wrapping_mul(r),
                        "/" | "%" if r == 0 => return Err("division by zero".into()),
                        "/" => v.wrapping_div(r),
                        _ => v.wrapping_rem(r),
                    };
                    continue 'outer;
                }
            }
            return Ok(v);
        }
    }

    fn peek_two(&self, s: &str) -> bool {
        let a = self.toks.get(self.pos).map(|t| t.text.as_str());
        let b = self.toks.get(self.pos + 1).map(|t| t.text.as_str());
        matches!((a, b), (Some(x), Some(y)) if format!("{x}{y}") == s)
    }

    fn unary(&mut self) -> CResult {
        let mut ops = Vec::new();
        loop {
            if self.eat("-") {
                ops.push('-');
            } else if self.eat("+") {
            } else if self.peek() == Some("!") && !self.peek_two("!=") {
                self.pos += 1;
                ops.push('!');
            } else if self.eat("~") {
                ops.push('~');
            } else {
                break;
            }
            if ops.len() > 10_000 {
                return Err("too many unary operators".into());
            }
        }
        let mut v = self.primary()?;
        for op in ops.into_iter().rev() {
            v = match op {
                '-' => v.wrapping_neg(),
                '!' => (v == 0) as i64,
                _ => !v,
            };
        }
        Ok(v)
    }

    fn primary(&mut self) -> CResult {
        let Some(t) = self.toks.get(self.pos) else {
            return Err("an expression, found the end of the line".into());
        };
        self.pos += 1;
        match t.kind {
            Kind::Number => {
                let s = t.text.trim_end_matches(['u', 'U', 'l', 'L']);
                let v = if let Some(h) = s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
                    i64::from_str_radix(h, 16).ok()
                } else if s.len() > 1 && s.starts_with('0') {
                    i64::from_str_radix(&s[1..], 8).ok()
                } else {
                    s.parse::<i64>().ok()
                };
                v.ok_or_else(|| format!("an integer, not `{}`", t.text))
            }
            Kind::Ident => Ok(0),
            Kind::Str => Err(format!("an integer, not the string {}", t.text)),
            _ if t.text == "(" => {
                let v = self.ternary()?;
                if !self.eat(")") {
                    return Err("`)`".into());
                }
                Ok(v)
            }
            _ => Err(format!("an expression, not `{}`", t.text)),
        }
    }
}
