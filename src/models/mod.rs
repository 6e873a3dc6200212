//! Tree models that build skeletons directly: the 1996 branching model (trees a–i) and
//! self-organizing trees that grow toward light and space.

pub mod growth;
pub mod honda;
