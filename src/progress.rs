//! Progress and cancellation of long work: derivation, interpretation and growth report
//! how far they are, on the calling thread, and stop when the caller says so.
//!
//! ```
//! use arbor::lsystem::{LSystem, LsystemOptions};
//! use arbor::progress::Stage;
//!
//! let ls = LSystem::parse("derivation length: 12\nAxiom: F\nF --> F[+F]F")?;
//! let mut calls = 0;
//! let mut stop_early = |_: Stage, fraction: f32| {
//!     calls += 1;
//!     fraction < 0.5 // keep going until half way
//! };
//! let r = ls.derive_with_progress(&LsystemOptions::default(), &mut stop_early);
//! assert!(matches!(r, Err(arbor::Error::Cancelled { .. })));
//! # Ok::<(), arbor::Error>(())
//! ```

use crate::error::{Error, Result};

/// What is being reported (C: ArborStage, the `stage` a progress callback receives).
#[repr(u32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Rewriting the string (fraction: steps done, and modules within a step).
    Derivation = 0,
    /// The turtle reading the string (fraction: modules read).
    Interpretation = 1,
    /// Growth cycles of a self-organizing world (fraction: cycles done).
    Growth = 2,
    /// Writing a mesh (fraction: branches written).
    Mesh = 3,
    /// Reading a model's files and preprocessing them (fraction: the part of the load's
    /// byte budget, `max_file_bytes`, read so far; 1 when the load is done).
    Load = 4,
    /// Writing a file of an export (fraction: its lines or bytes written; 1 just before
    /// it replaces the target, the last moment a cancel leaves the old file).
    Write = 5,
}

crate::enums::numbered!(Stage as "ArborStage" {
    Derivation = "derivation",
    Interpretation = "interpretation",
    Growth = "growth",
    Mesh = "mesh",
    Load = "loading",
    Write = "writing",
});

/// A progress callback: called with the stage and a fraction in [0, 1]; `false` stops the
/// work, which then returns [`Error::Cancelled`] and builds nothing.
pub type ProgressFn<'a> = &'a mut dyn FnMut(Stage, f32) -> bool;

/// How often work between its natural steps reports: every this many modules.
pub(crate) const EVERY: usize = 1 << 16;

/// An optional callback, with the cancellation it may ask for.
#[derive(Default)]
pub(crate) struct Progress<'a> {
    f: Option<ProgressFn<'a>>,
}

impl<'a> Progress<'a> {
    pub(crate) fn new(f: Option<ProgressFn<'a>>) -> Self {
        Progress { f }
    }

    /// Whether there is a callback.
    #[inline]
    pub(crate) fn active(&self) -> bool {
        self.f.is_some()
    }

    /// Reports `fraction` of `stage`; `Err(Cancelled)` when the callback says stop.
    pub(crate) fn report(&mut self, stage: Stage, fraction: f64) -> Result<()> {
        if let Some(f) = self.f.as_mut() {
            let fraction = if fraction.is_finite() {
                fraction.clamp(0.0, 1.0)
            } else {
                0.0
            };
            if !f(stage, fraction as f32) {
                return Err(Error::Cancelled {
                    stage: stage.name(),
                });
            }
        }
        Ok(())
    }
}
