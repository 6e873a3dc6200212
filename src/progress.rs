//! How long work runs: [`Run`], one context of threads, progress and cancellation that
//! every long operation of arbor takes the same way.
//!
//! Each long operation has a plain form, which runs quietly with the options' own thread
//! count, and an `_in` form that takes a `&mut Run`:
//!
//! | work | plain | in a run |
//! | --- | --- | --- |
//! | reading a model | [`LSystem::from_file`](crate::lsystem::LSystem::from_file) | [`LSystem::from_file_with`](crate::lsystem::LSystem::from_file_with) (with file options) |
//! | rewriting | [`LSystem::derive`](crate::lsystem::LSystem::derive) | [`LSystem::derive_in`](crate::lsystem::LSystem::derive_in) |
//! | the turtle | [`LSystem::interpret`](crate::lsystem::LSystem::interpret) | [`LSystem::interpret_in`](crate::lsystem::LSystem::interpret_in) |
//! | both | [`LSystem::skeleton`](crate::lsystem::LSystem::skeleton) | [`LSystem::skeleton_in`](crate::lsystem::LSystem::skeleton_in) |
//! | growth | [`World::step`](crate::models::growth::World::step) | [`World::step_in`](crate::models::growth::World::step_in) |
//! | obstacles | [`World::add_obstacle`](crate::models::growth::World::add_obstacle) | [`World::add_obstacle_in`](crate::models::growth::World::add_obstacle_in) |
//! | a mesh | [`MeshPlan::mesh`](crate::mesh::MeshPlan::mesh) | [`MeshPlan::mesh_in`](crate::mesh::MeshPlan::mesh_in) |
//! | into buffers | [`MeshPlan::write_uninit`](crate::mesh::MeshPlan::write_uninit) | [`MeshPlan::write_uninit_in`](crate::mesh::MeshPlan::write_uninit_in) |
//! | a forest | [`forest::write_merged_uninit`](crate::forest::write_merged_uninit) | [`forest::write_merged_uninit_in`](crate::forest::write_merged_uninit_in) |
//! | glTF | [`export::save_gltf`](crate::export::save_gltf) | [`export::save_gltf_in`](crate::export::save_gltf_in) |
//! | instanced glTF | [`export::save_gltf_instanced`](crate::export::save_gltf_instanced) | [`export::save_gltf_instanced_in`](crate::export::save_gltf_instanced_in) |
//! | OBJ | [`export::save_obj_parts`](crate::export::save_obj_parts) | [`export::save_obj_parts_in`](crate::export::save_obj_parts_in) |
//!
//! The C ABI carries the same context in the options struct of each long stage:
//! `progress` and `progress_user_data` (and `threads` in `ArborMeshOptions`).
//!
//! ```
//! use arbor::lsystem::{LSystem, LsystemOptions};
//! use arbor::progress::{Run, Stage};
//!
//! let ls = LSystem::parse("derivation length: 12\nAxiom: F\nF --> F[+F]F")?;
//! let mut calls = 0;
//! let mut stop_early = |_: Stage, fraction: f32| {
//!     calls += 1;
//!     fraction < 0.5 // keep going until half way
//! };
//! let r = ls.derive_in(&LsystemOptions::default(), &mut Run::reporting(&mut stop_early));
//! assert!(matches!(r, Err(arbor::Error::Cancelled { .. })));
//! # Ok::<(), arbor::Error>(())
//! ```

use crate::error::{Error, Result};

/// What is being reported (C: ArborStage, the `stage` a progress callback receives).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Stage {
    /// Rewriting the string (fraction: steps done, and modules within a step). The
    /// default.
    #[default]
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

/// One context for a long piece of work: how many threads it may use and the callback
/// that hears its progress and may cancel it. `Run::default()` is quiet and uses each
/// stage's own thread setting.
#[derive(Default)]
pub struct Run<'a> {
    threads: Option<u32>,
    f: Option<ProgressFn<'a>>,
}

impl std::fmt::Debug for Run<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Run")
            .field("threads", &self.threads)
            .field("progress", &self.f.is_some())
            .finish()
    }
}

impl<'a> Run<'a> {
    /// A run that reports to `progress`: called on the calling thread with the stage and
    /// a fraction in [0, 1]; `false` stops the work with [`Error::Cancelled`].
    pub fn reporting(progress: ProgressFn<'a>) -> Self {
        Run {
            threads: None,
            f: Some(progress),
        }
    }

    /// The same run on up to `threads` threads (0, the default: the machine's cores, at
    /// most 8 for a mesh write; 1: the calling thread only). The thread count lives here
    /// only, never in an options struct: mesh plans and writes (a tree under 16,384
    /// branches a thread is written on fewer; a plan of 32,768 branches or more takes two),
    /// forests, exports and growth (on all cores with the `parallel` feature unless
    /// `threads` is 1) take it from their run; the L-system stages run on the calling
    /// thread. The output is the same byte for byte whatever the count.
    pub fn threads(mut self, threads: u32) -> Self {
        self.threads = Some(threads);
        self
    }

    /// A run reporting to `f` when there is one (the C ABI's callback may be NULL).
    pub(crate) fn new(f: Option<ProgressFn<'a>>) -> Self {
        Run { threads: None, f }
    }

    /// The run's thread count, or `default` (the stage's own) when it sets none.
    #[inline]
    pub(crate) fn threads_or(&self, default: u32) -> u32 {
        self.threads.unwrap_or(default)
    }

    /// The callback, reborrowed (for work that keeps it for a while).
    pub(crate) fn callback(&mut self) -> Option<ProgressFn<'_>> {
        self.f.as_mut().map(|f| &mut **f as ProgressFn<'_>)
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
