//! The links of a string that context matching reads: bracket partners, the `]` closing
//! each module's branch, and the next module not skipped by `ignore:`/`consider:`.

use super::grammar::{POP, PUSH};
use super::{LSystem, ModuleString};

/// What context matching needs of a string, computed once per step so that matching a
/// context costs time proportional to the context, not to the string: each bracket's
/// partner, and for grammars whose right contexts hold `=` the `]` that closes the branch
/// each module is in (`u32::MAX` for none), both in one pass from the right. The next
/// module not skipped by `ignore:`/`consider:` is found by a short scan, and by a table of
/// the whole string, built at most once a step, when a run of skipped modules is long
/// (each module of a long run asking would make the step quadratic) or the scans have
/// read more than a quarter of the string. A step after one that needed the table makes
/// it at once, right after pairing the brackets and before any scan (the strings of one
/// derivation are alike from step to step).
#[derive(Default)]
pub(crate) struct Links {
    pub(crate) partner: Vec<u32>,
    pub(super) close: Vec<u32>,
    /// The next module not skipped, for each position; valid when `next_built`.
    next: std::cell::RefCell<Vec<u32>>,
    next_built: std::cell::Cell<bool>,
    /// Modules the short scans of this step have read: past a quarter of the string the
    /// table costs less.
    scanned: std::cell::Cell<usize>,
    /// The `]`s not yet matched, during `build`.
    unmatched: Vec<u32>,
}

/// Skipped modules a scan reads before it builds the table.
const SHORT_SCAN: usize = 16;

impl Links {
    pub(crate) fn build(&mut self, ls: &LSystem, s: &ModuleString) {
        let n = s.len();
        let rest = ls.productions.has_rest || ls.homomorphism.has_rest;
        self.partner.clear();
        self.partner.resize(n, u32::MAX);
        self.close.clear();
        if rest {
            self.close.resize(n + 1, u32::MAX);
        }
        self.scanned.set(0);
        // From the right, a `[` takes the nearest `]` not yet taken: the pairs a forward
        // scan with a stack of `[`s makes, balanced or not.
        self.unmatched.clear();
        for j in (0..n).rev() {
            let sym = s.syms[j];
            if sym == POP {
                self.unmatched.push(j as u32);
            } else if sym == PUSH {
                if let Some(c) = self.unmatched.pop() {
                    self.partner[j] = c;
                    self.partner[c as usize] = j as u32;
                }
            }
            if rest {
                // The first `]` at or after j that closes the branch j is in (j itself at
                // a `]`), as scanning forward with a depth count finds it.
                self.close[j] = self.unmatched.last().copied().unwrap_or(u32::MAX);
            }
        }
        // The last string (of this derivation) needed the next-kept table: this one is
        // likely to, and it costs least made at once, before any scan.
        if self.next_built.get() {
            self.fill_next(ls, s);
        }
    }

    /// Makes the next-kept table of `s`.
    fn fill_next(&self, ls: &LSystem, s: &ModuleString) {
        let n = s.len();
        let mut next = self.next.borrow_mut();
        next.clear();
        next.resize(n + 1, n as u32);
        let mut after = n as u32;
        for (j, (slot, &sym)) in next.iter_mut().zip(&s.syms).enumerate().rev() {
            if kept(ls, sym) {
                after = j as u32;
            }
            *slot = after;
        }
        self.next_built.set(true);
    }

    /// Whether the next-kept table of the string `build` read is made.
    #[cfg(test)]
    pub(crate) fn table_ready(&self) -> bool {
        self.next_built.get()
    }

    /// The first module at or after `j` of `s` (the string `build` read; `s.len()` for
    /// none) that `ignore:`/`consider:` does not skip; brackets are never skipped here:
    /// they are the string's structure.
    #[inline]
    pub(super) fn next_kept(&self, ls: &LSystem, s: &ModuleString, j: usize) -> usize {
        let n = s.len();
        if self.next_built.get() {
            return self.next.borrow()[j.min(n)] as usize;
        }
        let kept = |k: usize| kept(ls, s.syms[k]);
        let start = j.min(n);
        let mut k = start;
        if self.scanned.get() <= n / 4 {
            let end = (k + SHORT_SCAN).min(n);
            while k < end && !kept(k) {
                k += 1;
            }
            self.scanned.set(self.scanned.get() + (k - start));
            if k < end || k == n {
                return k;
            }
        }
        self.fill_next(ls, s);
        self.next.borrow()[k] as usize
    }
}

/// Whether context matching reads module symbol `sym` (brackets always: they are the
/// string's structure).
#[inline(always)]
fn kept(ls: &LSystem, sym: u16) -> bool {
    sym == PUSH || sym == POP || !ls.skip[sym as usize]
}

/// For each bracket, the index of its partner (`u32::MAX` for none), by a forward scan:
/// what [`Links::build`] is checked against.
#[cfg(test)]
pub(crate) fn brackets(s: &ModuleString, partner: &mut Vec<u32>) {
    partner.clear();
    partner.resize(s.len(), u32::MAX);
    let mut stack: Vec<u32> = Vec::new();
    for (i, &sym) in s.syms.iter().enumerate() {
        if sym == PUSH {
            stack.push(i as u32);
        } else if sym == POP {
            if let Some(open) = stack.pop() {
                partner[open as usize] = i as u32;
                partner[i] = open;
            }
        }
    }
}
