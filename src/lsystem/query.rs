//! cpfg's query modules: `?P(x, y, z)` learns the turtle's position where it stands, `?H`
//! its heading, `?U` its up and `?L` its left vector, after every derivation step (the
//! turtle's walk that answers them is `interpret::answer_queries`).

use super::grammar::{POP, PUSH};
use super::{LSystem, ModuleString};
use crate::geom::Frame;

/// What a query module asks the turtle: `?P` its position, `?H` heading, `?U` up, `?L`
/// left.
fn query_kind(name: &str) -> Option<usize> {
    ["?P", "?H", "?U", "?L"].iter().position(|q| *q == name)
}

/// Whether the grammar has query modules (`?P`, `?H`, `?U`, `?L`).
pub(crate) fn has_queries(ls: &LSystem) -> bool {
    ls.symbols.names.iter().any(|n| query_kind(n).is_some())
}

/// The questions of one walk of the turtle and their answers.
pub(crate) struct Asked {
    /// Per symbol: the vector its query asks for, or `None`.
    kinds: Vec<Option<usize>>,
    /// Module index and the answer, in walk order.
    answers: Vec<(usize, [f32; 3])>,
}

impl Asked {
    pub(crate) fn new(ls: &LSystem) -> Self {
        Asked {
            kinds: ls.symbols.names.iter().map(|n| query_kind(n)).collect(),
            answers: Vec::new(),
        }
    }

    /// The turtle stands at module `i` of `string` with `frame`: a query there is answered.
    pub(crate) fn ask(&mut self, string: &ModuleString, i: usize, frame: &Frame) {
        if let Some(&Some(kind)) = self.kinds.get(string.syms[i] as usize) {
            if !string.offsets.is_empty() {
                let v = [frame.position, frame.heading, frame.up, frame.left][kind];
                self.answers.push((i, v.as_vec3().to_array()));
            }
        }
    }

    /// What the walk that answers this step's queries must read of `string`: the modules
    /// before the last query, less each bracketed branch that holds no query (a `]`
    /// gives the turtle back the state its `[` saved, so such a branch changes no answer).
    /// `skip[i]` is the index of the `]` that closes a branch opened at `i` that may be
    /// left out (`u32::MAX` elsewhere); `end` is one past the last query. Valid only when
    /// the turtle draws no random numbers (turn jitter), which a skipped branch would
    /// leave undrawn.
    pub(crate) fn plan(&self, string: &ModuleString, skip: &mut Vec<u32>) -> usize {
        skip.clear();
        skip.resize(string.len(), u32::MAX);
        // The open brackets, each with whether its branch holds a query so far.
        let mut open: Vec<(u32, bool)> = Vec::new();
        let mut end = 0;
        for (i, &sym) in string.syms.iter().enumerate() {
            if sym == PUSH {
                open.push((i as u32, false));
            } else if sym == POP {
                if let Some((at, asks)) = open.pop() {
                    if asks {
                        if let Some(outer) = open.last_mut() {
                            outer.1 = true;
                        }
                    } else {
                        skip[at as usize] = i as u32;
                    }
                }
            } else if matches!(self.kinds.get(sym as usize), Some(Some(_))) {
                end = i + 1;
                if let Some(inner) = open.last_mut() {
                    inner.1 = true;
                }
            }
        }
        end
    }

    /// Writes the answers into the queries' parameters, as many as each has.
    pub(crate) fn answer(self, string: &mut ModuleString) {
        for (i, v) in self.answers {
            let (a, b) = (string.offsets[i] as usize, string.offsets[i + 1] as usize);
            for (slot, x) in string.params[a..b].iter_mut().zip(v) {
                *slot = x;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lsystem::LsystemOptions;

    #[test]
    fn the_walk_leaves_out_branches_without_queries_and_stops_after_the_last() {
        let ls =
            LSystem::parse("derivation length: 0\nAxiom: [F][+F[?P(0,0)]-F]F[G[F]]?P(0,0)[F]F\n")
                .unwrap();
        let s = ls.derive(&LsystemOptions::default()).unwrap();
        let mut skip = Vec::new();
        let end = Asked::new(&ls).plan(&s, &mut skip);
        // [F] at 0..=2 and [G[F]] at 13..=18 hold no query; the branch at 3 does, and
        // so does its inner one at 6; the last query is module 19.
        assert_eq!(ls.format(&s), "[F][+F[?P(0,0)]-F]F[G[F]]?P(0,0)[F]F");
        assert_eq!(end, 20);
        let skipped: Vec<(usize, u32)> = skip
            .iter()
            .enumerate()
            .filter(|(_, c)| **c != u32::MAX)
            .map(|(i, c)| (i, *c))
            .collect();
        assert_eq!(skipped, [(0, 2), (13, 18), (15, 17), (20, 22)]);
    }

    #[test]
    fn answers_are_those_of_the_whole_walk() {
        // Turns and moves inside the left-out branches must not reach the answers.
        let ls = LSystem::parse(
            "angle increment: 90\nderivation length: 1\n\
             Axiom: F(1)[+F(5)[-F(2)]?P(0,0)]F(1)[-F(7)[+F(1)]]+F(3)?P(0,0)[F(4)]\n\
             ?P(x,y) --> A(x,y)\n",
        )
        .unwrap();
        let s = ls.derive(&LsystemOptions::default()).unwrap();
        let text = ls.format(&s);
        assert!(text.contains("]A(-5,1)]"), "{text}");
        assert!(text.contains("+F(3)A(-3,2)[F(4)]"), "{text}");
    }
}
