//! Scanning a line outside parentheses, braces and string literals.

use super::*;

/// Open parentheses and statement braces of a production or directive being read.
#[derive(Default)]
pub(super) struct Depth {
    pub(super) parens: i64,
    pub(super) braces: i64,
    pub(super) arrow: bool,
    pub(super) quoted: bool,
}

impl Depth {
    pub(super) fn scan(&mut self, s: &str) {
        let b = s.as_bytes();
        for (i, &c) in b.iter().enumerate() {
            match c {
                b'"' => self.quoted = !self.quoted,
                _ if self.quoted => {}
                b'(' => self.parens += 1,
                b')' => self.parens -= 1,
                b'{' if !self.arrow => self.braces += 1,
                b'}' if !self.arrow => self.braces -= 1,
                b'-' if self.parens <= 0 && self.braces <= 0 && b[i..].starts_with(b"->") => {
                    self.arrow = true
                }
                b'-' if self.parens <= 0 && self.braces <= 0 && b[i..].starts_with(b"-->") => {
                    self.arrow = true
                }
                _ => {}
            }
        }
    }
}

/// Depth of parentheses and braces before each byte of `s`, strings skipped: calls
/// `visit(i, byte)` for every byte outside both and outside string literals.
pub(super) fn scan_top(s: &str, mut visit: impl FnMut(usize, u8) -> bool) {
    let b = s.as_bytes();
    let (mut depth, mut quoted) = (0i64, false);
    for (i, &c) in b.iter().enumerate() {
        match c {
            b'"' => quoted = !quoted,
            _ if quoted => {}
            b'(' | b'{' => depth += 1,
            b')' | b'}' => depth -= 1,
            _ if depth == 0 && !visit(i, c) => return,
            _ => {}
        }
    }
}

/// The first `-->` or `->` outside parentheses, braces and strings: (offset, length).
pub(super) fn find_arrow(s: &str) -> Option<(usize, usize)> {
    let b = s.as_bytes();
    let mut found = None;
    scan_top(s, |i, c| {
        if c == b'-' {
            if b[i..].starts_with(b"-->") {
                found = Some((i, 3));
                return false;
            }
            if b[i..].starts_with(b"->") {
                found = Some((i, 2));
                return false;
            }
        }
        true
    });
    found
}

pub(super) fn top_level(s: &str, target: u8) -> Option<usize> {
    let mut found = None;
    scan_top(s, |i, c| {
        if c == target {
            found = Some(i);
            return false;
        }
        true
    });
    found
}

pub(super) fn top_level_last(s: &str, target: u8) -> Option<usize> {
    let mut found = None;
    scan_top(s, |i, c| {
        if c == target {
            found = Some(i);
        }
        true
    });
    found
}

pub(super) fn skip_string(cur: &mut Cursor<'_>) -> PResult<()> {
    cur.eat("\"");
    loop {
        match cur.bump() {
            Some('"') => return Ok(()),
            Some('\\') => {
                cur.bump();
            }
            Some(_) => {}
            None => return Err(cur.error("`\"` closing the text")),
        }
    }
}
