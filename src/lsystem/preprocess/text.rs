//! The first phases: logical lines (splices and comments) and tokens.

use super::*;

/// One logical line: its text after splices and comments, the file line it starts on,
/// and where each of its characters stands in the file.
#[derive(Clone, Debug, Default)]
pub(crate) struct Logical {
    /// The file line the logical line starts on (1-based).
    pub(crate) line: u32,
    pub(crate) text: String,
    /// Characters in `text`.
    pub(crate) chars: u32,
    /// `[k, line, column]` (k 0-based in characters, line and column 1-based in the file)
    /// for the first character and for every character that does not stand right after
    /// the one before it in the file (after a `\`-newline splice or a comment).
    pub(crate) places: Vec<[u32; 3]>,
}

impl Logical {
    fn new(line: u32) -> Self {
        Logical {
            line,
            ..Default::default()
        }
    }

    /// Appends `c`, which stands at (`line`, `column`) in the file.
    fn push(&mut self, c: char, line: u32, column: u32) {
        let k = self.chars;
        self.chars += 1;
        self.text.push(c);
        match self.places.last() {
            Some(&[i, l, col]) if l == line && col + (k - i) == column => {}
            _ => self.places.push([k, line, column]),
        }
    }

    /// Whether every character stands where its column says, on the line the logical
    /// line starts on (no splice, no comment inside it): no places need keeping.
    pub(crate) fn plain(&self) -> bool {
        self.places.len() <= 1 && self.places.first().is_none_or(|p| *p == [0, self.line, 1])
    }
}

/// The file line and column of column `column` (1-based, in characters) of a logical
/// line with `places` (see [`Logical::places`]), starting on file line `line`.
pub(crate) fn file_place(places: &[[u32; 3]], line: u32, column: u32) -> (u32, u32) {
    let k = column.saturating_sub(1);
    match places.iter().rev().find(|p| p[0] <= k) {
        Some(&[i, l, c]) => (l, c + (k - i)),
        None => (line, column.max(1)),
    }
}

/// Splices `\`-newline and replaces comments by a space; returns logical lines with the
/// physical line each starts on and the place in the file of each character. Newlines
/// inside a block comment end the logical line, so line numbers stay those of the file.
pub(super) fn logical_lines(text: &str, file: &str) -> Result<Vec<Logical>> {
    let mut lines = Vec::new();
    let mut line = 1u32;
    let mut cur = Logical::new(line);
    let mut chars = text.chars().peekable();
    let mut in_block: Option<(u32, u32)> = None;
    let mut quote: Option<char> = None;
    // 1-based column (in characters) of the next character.
    let mut col = 1u32;
    while let Some(c) = chars.next() {
        let (at, here) = (line, col);
        col += 1;
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
            col += 1;
        }
        if c == '\\' && matches!(chars.peek(), Some('\n') | Some('\r')) {
            if chars.next() == Some('\r') && chars.peek() == Some(&'\n') {
                chars.next();
            }
            line += 1;
            col = 1;
            continue;
        }
        if c == '\n' {
            line += 1;
            col = 1;
            // An unterminated literal ends at the line's end, as in cpp.
            quote = None;
            lines.push(std::mem::replace(&mut cur, Logical::new(line)));
            continue;
        }
        if in_block.is_some() {
            if c == '*' && chars.peek() == Some(&'/') {
                chars.next();
                col += 1;
                in_block = None;
                cur.push(' ', at, here);
            }
            continue;
        }
        if let Some(q) = quote {
            cur.push(c, at, here);
            if c == '\\' {
                if let Some(&n) = chars.peek() {
                    if n != '\n' {
                        cur.push(n, line, col);
                        chars.next();
                        col += 1;
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
                cur.push(c, at, here);
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
                    col += 1;
                }
                cur.push(' ', at, here);
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            _ => cur.push(c, at, here),
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
    lines.push(cur);
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
