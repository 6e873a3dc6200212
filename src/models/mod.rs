//! Tree models that build skeletons directly: the 1996 branching model (trees a–i).

pub mod honda;
