//! The first phases: logical lines (splices and comments) and tokens.

use super::*;

/// Splices `\`-newline and replaces comments by a space; returns logical lines with the
/// physical line each starts on. Newlines inside a block comment end the logical line,
/// so line numbers stay those of the file.
pub(super) fn logical_lines(text: &str, file: &str) -> Result<Vec<(u32, String)>> {
    let mut lines = Vec::new();
    let mut cur = String::new();
    let mut start_line = 1u32;
    let mut line = 1u32;
    let mut chars = text.chars().peekable();
    let mut in_block: Option<(u32, u32)> = None;
    let mut quote: Option<char> = None;
    // 1-based column (in characters) of the next character, for a comment left open.
    let mut col = 1u32;
    while let Some(c) = chars.next() {
        let here = col;
        col = if c == '\n' { 1 } else { col + 1 };
        // A line ending in backslashes continues (cpfg's models also write `\\`).
        while c == '\\' && chars.peek() == Some(&'\\') && in_block.is_none() && quote.is_none() {
            let mut ahead = chars.clone();
            while ahead.peek() == Some(&'\\') {
                ahead.next();
            }
            if !matches!(ahead.peek(), Some('\n') | Some('\r')) {
                break;
            }
            chars.next();
        }
        if c == '\\' && matches!(chars.peek(), Some('\n') | Some('\r')) {
            if chars.next() == Some('\r') && chars.peek() == Some(&'\n') {
                chars.next();
            }
            line += 1;
            continue;
        }
        if c == '\n' {
            line += 1;
            // An unterminated literal ends at the line's end, as in cpp.
            quote = None;
            lines.push((start_line, std::mem::take(&mut cur)));
            start_line = line;
            continue;
        }
        if in_block.is_some() {
            if c == '*' && chars.peek() == Some(&'/') {
                chars.next();
                in_block = None;
                cur.push(' ');
            }
            continue;
        }
        if let Some(q) = quote {
            cur.push(c);
            if c == '\\' {
                if let Some(&n) = chars.peek() {
                    if n != '\n' {
                        cur.push(n);
                        chars.next();
                    }
                }
            } else if c == q {
                quote = None;
            }
            continue;
        }
        match c {
            '"' => {
                quote = Some(c);
                cur.push(c);
            }
            '/' if chars.peek() == Some(&'*') => {
                chars.next();
                col += 1;
                in_block = Some((line, here));
            }
            '/' if chars.peek() == Some(&'/') => {
                while let Some(&n) = chars.peek() {
                    if n == '\n' {
                        break;
                    }
                    chars.next();
                }
                cur.push(' ');
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            _ => cur.push(c),
        }
    }
    if let Some((at, column)) = in_block {
        let mut e = perr(
            file,
            at,
            "unterminated comment: `/*` has no closing `*/`".into(),
        );
        if let Error::Parse { column: c, .. } = &mut e {
            *c = column;
        }
        return Err(e);
    }
    lines.push((start_line, cur));
    Ok(lines)
}

pub(super) fn tokenize(s: &str) -> Vec<Tok> {
    let mut out = Vec::new();
    let b = s.as_bytes();
    let mut i = 0;
    let tok = |kind, text: &str| Tok {
        kind,
        text: text.to_string(),
        hide: 0,
    };
    while i < b.len() {
        let c = b[i];
        let start = i;
        if c == b' ' || c == b'\t' || c == b'\x0c' || c == b'\x0b' || c == b'\r' {
            while i < b.len() && matches!(b[i], b' ' | b'\t' | b'\x0c' | b'\x0b' | b'\r') {
                i += 1;
            }
            // Kept as written: a leading TAB continues a production in cpfg.
            out.push(tok(Kind::Space, &s[start..i]));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push(tok(Kind::Ident, &s[start..i]));
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            // A preprocessing number: digits, letters, `.`, and a sign after an exponent.
            i += 1;
            while i < b.len() {
                let d = b[i];
                let sign = (d == b'+' || d == b'-') && matches!(b[i - 1], b'e' | b'E');
                if sign || d.is_ascii_alphanumeric() || d == b'.' || d == b'_' {
                    i += 1;
                } else {
                    break;
                }
            }
            out.push(tok(Kind::Number, &s[start..i]));
        } else if c == b'"' || c == b'\'' {
            i += 1;
            while i < b.len() && b[i] != c {
                if b[i] == b'\\' {
                    i += 1;
                }
                i += 1;
            }
            i = (i + 1).min(b.len());
            out.push(tok(Kind::Str, &s[start..i]));
        } else {
            let two = s.get(i..i + 2);
            if matches!(two, Some("##")) {
                i += 2;
            } else {
                i += s[i..].chars().next().map_or(1, char::len_utf8);
            }
            out.push(tok(Kind::Punct, &s[start..i]));
        }
    }
    out
}

pub(super) fn join(tokens: &[Tok]) -> String {
    tokens.iter().map(|t| t.text.as_str()).collect()
}
