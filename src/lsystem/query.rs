//! cpfg's query modules: `?P(x, y, z)` learns the turtle's position where it stands, `?H`
//! its heading, `?U` its up and `?L` its left vector, after every derivation step (the
//! turtle's walk that answers them is `interpret::answer_queries`).

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
