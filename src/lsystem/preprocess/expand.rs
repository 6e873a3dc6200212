//! Macro expansion with C's rescanning rules, `#` stringizing and `##` pasting.

use super::*;

impl Pre<'_> {
    /// Expands a line; `None` when a function-like macro call is not closed on it.
    pub(super) fn expand_line(
        &mut self,
        line: &str,
        file: &str,
        line_no: u32,
    ) -> Result<Option<String>> {
        if !line.bytes().any(|b| b.is_ascii_alphabetic() || b == b'_') || self.macros.is_empty() {
            return Ok(Some(line.to_string()));
        }
        // Tokens cost tens of bytes each: a line whose macros need expanding is at most
        // 1 MiB (cpfg's lines are short; text without macros is not tokenized at all).
        if line.len() > MAX_EXPANDED_LINE {
            return Err(perr(
                file,
                line_no,
                format!(
                    "a line of {} bytes with macros to expand; at most {MAX_EXPANDED_LINE} bytes",
                    line.len()
                ),
            ));
        }
        let toks = tokenize(line);
        match self.expand(toks, file, line_no)? {
            Some(t) => Ok(Some(join(&t))),
            None => Ok(None),
        }
    }

    pub(super) fn count(&mut self, n: usize, file: &str, line: u32) -> Result<()> {
        self.tokens += n;
        if self.tokens > MAX_EXPANDED_TOKENS {
            return Err(perr(
                file,
                line,
                format!(
                    "macro expansion produces more than {MAX_EXPANDED_TOKENS} tokens \
                     (macros that multiply each other?)"
                ),
            ));
        }
        Ok(())
    }

    /// C's expansion with hide sets; `None` when a call's `)` is missing.
    pub(super) fn expand(
        &mut self,
        input: Vec<Tok>,
        file: &str,
        line: u32,
    ) -> Result<Option<Vec<Tok>>> {
        let mut out = Vec::with_capacity(input.len());
        let mut rest: std::collections::VecDeque<Tok> = input.into();
        while let Some(t) = rest.pop_front() {
            if t.kind != Kind::Ident {
                out.push(t);
                continue;
            }
            let Some(m) = self.macros.get(&t.text) else {
                out.push(t);
                continue;
            };
            // A function-like macro name not followed by `(` is an ordinary name.
            let call_open = rest.iter().position(|t| t.kind != Kind::Space);
            if m.params.is_some() && !call_open.is_some_and(|k| rest[k].is("(")) {
                out.push(t);
                continue;
            }
            if self.hides.contains(t.hide, m.id) {
                let chain: Vec<&str> = self.hides.sets[t.hide as usize]
                    .iter()
                    .map(|&i| self.names[i as usize].as_str())
                    .collect();
                return Err(perr(
                    file,
                    line,
                    format!(
                        "the macro `{}` expands to itself (recursive #define: {} → {})",
                        t.text,
                        chain.join(" → "),
                        t.text
                    ),
                ));
            }
            let m = m.clone();
            let hide = self.hides.with(t.hide, m.id);
            let body = match &m.params {
                None => self.substitute(&m, &[], hide, file, line)?,
                Some(_) => {
                    let k = call_open.expect("checked above");
                    let Some((args, close)) = collect_args(&rest, k) else {
                        return Ok(None);
                    };
                    let nparams = m.params.as_ref().map_or(0, Vec::len);
                    let variadic = m
                        .params
                        .as_ref()
                        .is_some_and(|p| p.last().is_some_and(|s| s == "..."));
                    let ok = args.len() == nparams
                        || (nparams == 0 && args.len() == 1 && args[0].is_empty())
                        || (variadic && args.len() >= nparams - 1);
                    if !ok {
                        return Err(perr(
                            file,
                            line,
                            format!(
                                "the macro `{}` takes {nparams} argument(s), not {}",
                                t.text,
                                args.len()
                            ),
                        ));
                    }
                    let args = if variadic && args.len() >= nparams {
                        let mut a = args[..nparams - 1].to_vec();
                        let mut tail = Vec::new();
                        for (i, arg) in args[nparams - 1..].iter().enumerate() {
                            if i > 0 {
                                tail.push(Tok {
                                    kind: Kind::Punct,
                                    text: ",".into(),
                                    hide: 0,
                                });
                            }
                            tail.extend(arg.iter().cloned());
                        }
                        a.push(tail);
                        a
                    } else {
                        args
                    };
                    rest.drain(..=close);
                    self.substitute(&m, &args, hide, file, line)?
                }
            };
            self.count(body.len(), file, line)?;
            for tok in body.into_iter().rev() {
                rest.push_front(tok);
            }
        }
        Ok(Some(out))
    }

    pub(super) fn substitute(
        &mut self,
        m: &Macro,
        args: &[Vec<Tok>],
        hide: u32,
        file: &str,
        line: u32,
    ) -> Result<Vec<Tok>> {
        let params = m.params.as_deref().unwrap_or(&[]);
        let index = |t: &Tok| {
            (t.kind == Kind::Ident)
                .then(|| {
                    params
                        .iter()
                        .position(|p| *p == t.text || (p == "..." && t.text == "__VA_ARGS__"))
                })
                .flatten()
        };
        let mut out: Vec<Tok> = Vec::new();
        let body = &m.body;
        let mut i = 0;
        while i < body.len() {
            let t = &body[i];
            // `#param`: the argument as a string literal.
            if t.is("#") && !params.is_empty() {
                let j = skip_space(body, i + 1);
                if let Some(k) = body.get(j).and_then(index) {
                    let text = join(&args[k])
                        .trim()
                        .replace('\\', "\\\\")
                        .replace('"', "\\\"");
                    out.push(Tok {
                        kind: Kind::Str,
                        text: format!("\"{text}\""),
                        hide: 0,
                    });
                    i = j + 1;
                    continue;
                }
            }
            // `a ## b`: paste the neighbours (arguments unexpanded).
            if t.is("##") {
                while out.last().is_some_and(|t| t.kind == Kind::Space) {
                    out.pop();
                }
                let j = skip_space(body, i + 1);
                let right: Vec<Tok> = match body.get(j) {
                    Some(r) => match index(r) {
                        Some(k) => args[k].clone(),
                        None => vec![r.clone()],
                    },
                    None => Vec::new(),
                };
                let left = out.pop();
                let mut text = left.map(|l| l.text).unwrap_or_default();
                let mut right = right.into_iter();
                if let Some(r) = right.next() {
                    text.push_str(&r.text);
                }
                out.extend(tokenize(&text));
                out.extend(right);
                i = j + 1;
                continue;
            }
            match index(t) {
                Some(k) => {
                    let next = skip_space(body, i + 1);
                    if body.get(next).is_some_and(|n| n.is("##")) {
                        out.extend(args[k].iter().cloned());
                    } else {
                        self.count(args[k].len(), file, line)?;
                        match self.expand(args[k].clone(), file, line)? {
                            Some(e) => out.extend(e),
                            None => {
                                return Err(err_unterminated(file, line));
                            }
                        }
                    }
                }
                None => out.push(t.clone()),
            }
            i += 1;
        }
        for t in &mut out {
            t.hide = self.hides.union(t.hide, hide);
        }
        Ok(out)
    }
}

pub(super) fn err_unterminated(file: &str, line: u32) -> Error {
    perr(
        file,
        line,
        "unterminated macro call: its `(` is never closed".into(),
    )
}

pub(super) fn macro_name(args: &str) -> Option<&str> {
    let len = args
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(args.len());
    let name = &args[..len];
    (!name.is_empty() && !name.as_bytes()[0].is_ascii_digit()).then_some(name)
}

pub(super) fn skip_space(toks: &[Tok], mut i: usize) -> usize {
    while toks.get(i).is_some_and(|t| t.kind == Kind::Space) {
        i += 1;
    }
    i
}

/// The arguments of a call whose `(` is at `open`, and the index of its `)`.
pub(super) fn collect_args(
    toks: &std::collections::VecDeque<Tok>,
    open: usize,
) -> Option<(Vec<Vec<Tok>>, usize)> {
    let mut args = vec![Vec::new()];
    let mut depth = 0usize;
    for (i, t) in toks.iter().enumerate().skip(open + 1) {
        if t.is("(") {
            depth += 1;
        } else if t.is(")") {
            if depth == 0 {
                for a in &mut args {
                    while a.first().is_some_and(|t: &Tok| t.kind == Kind::Space) {
                        a.remove(0);
                    }
                    while a.last().is_some_and(|t| t.kind == Kind::Space) {
                        a.pop();
                    }
                }
                return Some((args, i));
            }
            depth -= 1;
        } else if t.is(",") && depth == 0 {
            args.push(Vec::new());
            continue;
        }
        args.last_mut().expect("never empty").push(t.clone());
    }
    None
}
