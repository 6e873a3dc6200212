//! A cursor over grammar text, the positioned errors the parser raises, and the size
//! limit of any text a model brings.

use crate::error::{Error, Result};

/// Longest accepted grammar text (16 MiB).
pub const MAX_SOURCE_BYTES: usize = 16 << 20;

/// Refuses a text over [`MAX_SOURCE_BYTES`] before it is parsed.
pub(crate) fn check_size(source: &str) -> Result<()> {
    if source.len() > MAX_SOURCE_BYTES {
        return Err(Error::Parse {
            line: 1,
            column: 1,
            message: format!(
                "the grammar is {} bytes; at most {MAX_SOURCE_BYTES} are accepted",
                source.len()
            ),
        });
    }
    Ok(())
}

/// A parse error at a byte offset of the source; turned into line and column at the end.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PErr {
    pub(crate) pos: usize,
    /// What stood there (`` `)` ``, "end of line", ...), or empty for an error that names
    /// its construct itself.
    pub(crate) found: String,
    /// What was expected, or the whole message when `found` is empty.
    pub(crate) expected: String,
}

pub(crate) type PResult<T> = Result<T, PErr>;

/// A position in a range of the source text.
#[derive(Clone, Debug)]
pub(crate) struct Cursor<'a> {
    text: &'a str,
    pos: usize,
    end: usize,
}

impl<'a> Cursor<'a> {
    pub(crate) fn new(text: &'a str) -> Self {
        Cursor {
            text,
            pos: 0,
            end: text.len(),
        }
    }

    /// A cursor over `text[start..end]` that reports offsets into the whole `text`.
    pub(crate) fn range(text: &'a str, start: usize, end: usize) -> Self {
        Cursor {
            text,
            pos: start,
            end,
        }
    }

    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    pub(crate) fn rest(&self) -> &'a str {
        &self.text[self.pos..self.end]
    }

    pub(crate) fn at_end(&self) -> bool {
        self.pos >= self.end
    }

    pub(crate) fn peek(&self) -> Option<char> {
        self.rest().chars().next()
    }

    pub(crate) fn peek_str(&self, s: &str) -> bool {
        self.rest().starts_with(s)
    }

    pub(crate) fn bump(&mut self) -> Option<char> {
        let c = self.peek()?;
        self.pos += c.len_utf8();
        Some(c)
    }

    pub(crate) fn eat(&mut self, s: &str) -> bool {
        if self.peek_str(s) {
            self.pos += s.len();
            true
        } else {
            false
        }
    }

    pub(crate) fn skip_ws(&mut self) {
        while let Some(c) = self.peek() {
            if c.is_whitespace() {
                self.pos += c.len_utf8();
            } else {
                break;
            }
        }
    }

    /// A C identifier (letters, digits, `_`, not starting with a digit).
    pub(crate) fn identifier(&mut self) -> Option<&'a str> {
        let rest = self.rest();
        let mut chars = rest.char_indices();
        match chars.next() {
            Some((_, c)) if c.is_ascii_alphabetic() || c == '_' => {}
            _ => return None,
        }
        let len = chars
            .find(|(_, c)| !(c.is_ascii_alphanumeric() || *c == '_'))
            .map_or(rest.len(), |(i, _)| i);
        self.pos += len;
        Some(&rest[..len])
    }

    /// A decimal number such as `3`, `0.5`, `.5`, `1e-3`; `None` when none starts here.
    pub(crate) fn number(&mut self) -> PResult<Option<f64>> {
        let rest = self.rest().as_bytes();
        let mut i = 0;
        while i < rest.len() && rest[i].is_ascii_digit() {
            i += 1;
        }
        let int_digits = i;
        if i < rest.len() && rest[i] == b'.' {
            i += 1;
            while i < rest.len() && rest[i].is_ascii_digit() {
                i += 1;
            }
        }
        if i == 0 || (int_digits == 0 && i == 1) {
            return Ok(None);
        }
        if i < rest.len() && (rest[i] == b'e' || rest[i] == b'E') {
            let mut j = i + 1;
            if j < rest.len() && (rest[j] == b'+' || rest[j] == b'-') {
                j += 1;
            }
            let digits = j;
            while j < rest.len() && rest[j].is_ascii_digit() {
                j += 1;
            }
            if j > digits {
                i = j;
            }
        }
        let text = &self.rest()[..i];
        let v: f64 = text.parse().map_err(|_| self.error("a number"))?;
        self.pos += i;
        Ok(Some(v))
    }

    /// An error at the cursor: "found X, expected `expected`".
    pub(crate) fn error(&self, expected: &str) -> PErr {
        self.error_at(self.pos, expected)
    }

    pub(crate) fn error_at(&self, pos: usize, expected: &str) -> PErr {
        PErr {
            pos,
            found: describe(&self.text[pos.min(self.end)..self.end]),
            expected: expected.to_string(),
        }
    }

    /// An error whose message names the construct itself.
    pub(crate) fn message_at(&self, pos: usize, message: &str) -> PErr {
        PErr {
            pos,
            found: String::new(),
            expected: message.to_string(),
        }
    }
}

/// Names the token at the start of `rest` for an error message.
pub(crate) fn describe(rest: &str) -> String {
    let rest = rest.trim_start_matches([' ', '\t']);
    let Some(c) = rest.chars().next() else {
        return "end of line".to_string();
    };
    if c == '\n' || c == '\r' {
        return "end of line".to_string();
    }
    let len = if c.is_ascii_alphanumeric() || c == '_' || c == '.' {
        rest.find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.'))
            .unwrap_or(rest.len())
    } else {
        c.len_utf8()
    };
    let token: String = rest[..len].chars().take(24).collect();
    let more = if token.len() < len { "…" } else { "" };
    format!("`{token}{more}`")
}

/// 1-based line and column (in characters) of byte offset `pos`.
pub(crate) fn line_col(text: &str, pos: usize) -> (u32, u32) {
    let pos = pos.min(text.len());
    let before = &text[..pos];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = text[line_start..pos].chars().count() + 1;
    (line as u32, column as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_identifiers() {
        let mut c = Cursor::new("12.5e-1x .5 7. abc_1(");
        assert_eq!(c.number().unwrap(), Some(1.25));
        assert_eq!(c.identifier(), Some("x"));
        c.skip_ws();
        assert_eq!(c.number().unwrap(), Some(0.5));
        c.skip_ws();
        assert_eq!(c.number().unwrap(), Some(7.0));
        c.skip_ws();
        assert_eq!(c.number().unwrap(), None);
        assert_eq!(c.identifier(), Some("abc_1"));
        assert!(c.eat("("));
        assert!(c.at_end());
    }

    #[test]
    fn positions_and_descriptions() {
        assert_eq!(line_col("ab\ncdé f", 7), (2, 4));
        assert_eq!(line_col("ab\ncdé f", 8), (2, 5));
        assert_eq!(describe("  foo(1)"), "`foo`");
        assert_eq!(describe(")"), "`)`");
        assert_eq!(describe("\nx"), "end of line");
        assert_eq!(describe(""), "end of line");
    }
}
