//! A skeleton with the mesh plans it was last sized or written with, so that sizing then
//! writing, a re-upload, or rewriting the branches an edit changed computes each layout
//! once and allocates nothing in proportion to the tree. The C ABI's tree is one of these.

use super::{MeshOptions, MeshPlan};
use crate::error::Result;
use crate::progress::Run;
use crate::skeleton::Skeleton;
use std::sync::{Arc, Mutex, MutexGuard};

/// Mesh plans kept (one per distinct set of options, most recent first).
const KEPT_PLANS: usize = 4;

/// A plan kept, with the branches whose vertices edits changed since it was made (sorted,
/// each once).
#[derive(Debug)]
struct Kept {
    plan: Arc<MeshPlan>,
    pending: Vec<u32>,
}

/// A skeleton and the mesh plans of the last few mesh options it was meshed with.
///
/// `&PlanCache` may be shared between threads: [`plan`](Self::plan) makes a missing plan
/// outside the lock, so other threads keep meshing meanwhile. Editing needs `&mut`.
///
/// ```
/// use arbor::mesh::{MeshOptions, PlanCache};
/// use arbor::models::honda::{self, HondaParams};
///
/// let tree = PlanCache::new(honda::build(&HondaParams::preset('a').unwrap())?);
/// let options = MeshOptions::default();
/// let size = tree.plan(&options)?.size(); // sized once...
/// let mesh = tree.plan(&options)?.mesh(tree.skeleton())?; // ...written with the same plan
/// assert_eq!(mesh.vertices.len(), size.vertices);
/// # Ok::<(), arbor::Error>(())
/// ```
#[derive(Debug)]
pub struct PlanCache {
    skeleton: Skeleton,
    kept: Mutex<Vec<Kept>>,
}

impl PlanCache {
    /// A cache of `skeleton` with no plan yet.
    pub fn new(skeleton: Skeleton) -> Self {
        PlanCache {
            skeleton,
            kept: Mutex::new(Vec::new()),
        }
    }

    /// The skeleton.
    pub fn skeleton(&self) -> &Skeleton {
        &self.skeleton
    }

    /// The skeleton, giving up the plans.
    pub fn into_skeleton(self) -> Skeleton {
        self.skeleton
    }

    fn lock(&self) -> MutexGuard<'_, Vec<Kept>> {
        // A poisoned lock only means another thread panicked while holding it; the list
        // itself is always valid.
        self.kept.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Changes the skeleton with `f` (nothing changes if it fails) and drops the plans,
    /// which were made for the old one.
    pub fn edit(&mut self, f: impl FnOnce(&mut Skeleton) -> Result<()>) -> Result<()> {
        f(&mut self.skeleton)?;
        self.kept
            .get_mut()
            .unwrap_or_else(|e| e.into_inner())
            .clear();
        Ok(())
    }

    /// Changes branch `i`'s curve with `f`: every plan is brought up to date (in time
    /// proportional to the branch's subtree) and remembers the branches to rewrite (see
    /// [`pending`](Self::pending)); a plan whose branch ranges the edit would change is
    /// dropped.
    pub fn edit_branch(
        &mut self,
        i: usize,
        f: impl FnOnce(&mut Skeleton) -> Result<()>,
    ) -> Result<()> {
        f(&mut self.skeleton)?;
        let skeleton = &self.skeleton;
        let kept = self.kept.get_mut().unwrap_or_else(|e| e.into_inner());
        kept.retain_mut(
            |k| match Arc::make_mut(&mut k.plan).update_after_edit(skeleton, i) {
                Ok(changed) => {
                    k.pending.extend(changed);
                    k.pending.sort_unstable();
                    k.pending.dedup();
                    true
                }
                Err(_) => false,
            },
        );
        Ok(())
    }

    /// The plan for `options`: kept from an earlier call, or made now and kept.
    pub fn plan(&self, options: &MeshOptions) -> Result<Arc<MeshPlan>> {
        self.plan_in(options, &Run::default())
    }

    /// [`plan`](Self::plan), a missing plan made on `run`'s threads.
    pub fn plan_in(&self, options: &MeshOptions, run: &Run<'_>) -> Result<Arc<MeshPlan>> {
        if let Some(k) = self.lock().iter().find(|k| k.plan.serves(options)) {
            return Ok(k.plan.clone());
        }
        // Made outside the lock, so other threads keep meshing meanwhile.
        let plan = Arc::new(MeshPlan::new_in(&self.skeleton, options, run)?);
        let mut kept = self.lock();
        kept.retain(|k| !k.plan.serves(options));
        kept.insert(
            0,
            Kept {
                plan: plan.clone(),
                pending: Vec::new(),
            },
        );
        kept.truncate(KEPT_PLANS);
        Ok(plan)
    }

    /// The kept plan for `options` and every branch edits changed since it was made
    /// (sorted, each once); `None` when no plan for `options` is kept. Not cleared by
    /// writes or rewrites: any buffer holding a full write made with this plan, whenever,
    /// is correct after rewriting them.
    pub fn pending(&self, options: &MeshOptions) -> Option<(Arc<MeshPlan>, Vec<u32>)> {
        let kept = self.lock();
        let k = kept.iter().find(|k| k.plan.serves(options))?;
        Some((k.plan.clone(), k.pending.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::honda::{self, HondaParams};

    #[test]
    fn plans_are_kept_per_options_and_edits_mark_their_branches() {
        let mut tree = PlanCache::new(honda::build(&HondaParams::preset('a').unwrap()).unwrap());
        let a = MeshOptions::default();
        let b = a.radial_segments(5);
        let pa = tree.plan(&a).unwrap();
        assert!(
            Arc::ptr_eq(&pa, &tree.plan(&a).unwrap()),
            "kept, not remade"
        );
        tree.plan(&b).unwrap();
        assert_eq!(tree.pending(&a).unwrap().1, Vec::<u32>::new());
        // Bending a twig keeps the plans and marks that twig to rewrite.
        let last = tree.skeleton().len() - 1;
        let b_ = tree.skeleton().branches()[last];
        let mut c = tree.skeleton().curve(last);
        c.p1 += glam::Vec3::X;
        tree.edit_branch(last, |s| {
            s.set_curve(last, &c, b_.start_radius, b_.end_radius)
        })
        .unwrap();
        let (plan, pending) = tree.pending(&a).unwrap();
        // The twig, and its parent, whose end ring is mitred toward the twig's new tangent.
        let parent = tree.skeleton().branches()[last].parent;
        assert_eq!(pending, vec![parent, last as u32]);
        assert!(Arc::ptr_eq(&plan, &tree.plan(&a).unwrap()));
        // Any other edit drops them.
        tree.edit(|s| s.smooth(0.5)).unwrap();
        assert!(tree.pending(&a).is_none() && tree.pending(&b).is_none());
    }
}
