//! Geometry shared by every stage: the turtle's frame and rotations, ring frames carried
//! along a tree, cubic Bézier curves, and a uniform 3-D grid.

pub mod curve;
mod frame;
pub mod grid;
pub(crate) mod lanes;
pub(crate) mod rotation;
pub mod transport;

pub use curve::Curve;
pub use frame::{Frame, cos_sin_deg};
