//! Named species as a user asks for them: an oak, a pine, a birch. Each is a preset of the
//! self-organizing model ([`GrowthParams::preset`]) with its cycles, its adult height in
//! metres, its leaves (shape, colour, size, where they grow) and its bark, and
//! [`tree_scene`] turns one into a textured, leafy asset at real scale.
//!
//! ```
//! use arbor::models::growth::Species;
//! use arbor::species::{Look, tree_scene};
//!
//! let look = Look::of(Species::Birch).unwrap();
//! let skeleton = look.grow(3).unwrap();
//! let scene = tree_scene(&look, &skeleton, &arbor::mesh::MeshOptions::default(), 64, 3).unwrap();
//! assert_eq!(scene.textures.len(), 3); // bark colour and normal, the leaf atlas
//! assert!(scene.materials.iter().any(|m| m.alpha_cutoff.is_some()));
//! ```

use crate::error::{Error, Result};
use crate::mesh::{LeafOptions, MeshOptions};
use crate::models::growth::{GrowthParams, Species};
use crate::scene::Scene;
use crate::skeleton::{Branch, NO_PARENT, Skeleton};
use crate::source::Source;
use crate::texture::{BarkLook, LeafLook, bark_textures, leaf_atlas};

/// How a named species grows and looks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Look {
    /// The species (its growth parameters are [`GrowthParams::preset`]).
    pub species: Species,
    /// Growth cycles of an adult tree.
    pub cycles: u32,
    /// The adult tree's height in metres: the mesh is scaled to it.
    pub height: f32,
    /// Its leaves' blade, colour and size.
    pub leaf: LeafLook,
    /// Leaves per young tip (the whole part always, the fraction by chance).
    pub leaves_per_tip: f32,
    /// Leaves grow on the branches of the last this many cycles.
    pub leaf_cycles: u32,
    /// The trunk is clear of branches up to this fraction of the tree's height.
    pub clear_trunk: f32,
    /// The trunk's radius at the ground over its radius above the flare (1: no flare).
    pub flare: f32,
    /// Surface roots spreading from the trunk's foot into the ground (0: none).
    pub roots: u32,
    /// Its bark.
    pub bark: BarkLook,
}

impl Look {
    /// The look of a named species; none for the five crown archetypes (excurrent,
    /// decurrent, columnar, bush, weeping), which have no leaves or bark of their own.
    pub fn of(species: Species) -> Option<Look> {
        let l = |cycles, height, clear_trunk, leaf, leaves_per_tip, leaf_cycles, bark| Look {
            species,
            cycles,
            height,
            clear_trunk,
            flare: 1.0,
            roots: 0,
            leaf,
            leaves_per_tip,
            leaf_cycles,
            bark,
        };
        Some(match species {
            Species::Oak => l(36, 18.0, 0.22, LeafLook::oak(), 6.0, 3, BarkLook::oak()),
            Species::Maple => l(34, 15.0, 0.22, LeafLook::maple(), 5.0, 3, BarkLook::maple()),
            Species::Birch => l(34, 16.0, 0.3, LeafLook::birch(), 8.0, 3, BarkLook::birch()),
            Species::Willow => l(
                34,
                12.0,
                0.18,
                LeafLook::willow(),
                8.0,
                4,
                BarkLook::willow(),
            ),
            Species::Poplar => l(
                34,
                22.0,
                0.1,
                LeafLook::poplar(),
                6.0,
                3,
                BarkLook::poplar(),
            ),
            Species::Pine => l(32, 18.0, 0.45, LeafLook::pine(), 4.0, 4, BarkLook::pine()),
            Species::Spruce => l(
                26,
                20.0,
                0.06,
                LeafLook::spruce(),
                4.0,
                5,
                BarkLook::spruce(),
            ),
            Species::Shrub => l(24, 2.5, 0.0, LeafLook::shrub(), 5.0, 3, BarkLook::shrub()),
            _ => return None,
        })
        .map(|l| {
            let (flare, roots) = match species {
                Species::Oak => (1.4, 5),
                Species::Maple => (1.35, 4),
                Species::Birch => (1.3, 0),
                Species::Willow => (1.4, 4),
                Species::Poplar => (1.4, 3),
                Species::Pine => (1.3, 0),
                Species::Spruce => (1.5, 4),
                _ => (1.0, 0),
            };
            Look { flare, roots, ..l }
        })
    }

    /// Every named species' look, in the enum's order.
    pub fn all() -> Vec<Look> {
        Species::ALL.iter().filter_map(|&s| Look::of(s)).collect()
    }

    /// The species' tree grown alone for its cycles, seeded with `seed`, its trunk
    /// cleared of branches up to [`clear_trunk`](Self::clear_trunk) of its height.
    pub fn grow(&self, seed: u64) -> Result<Skeleton> {
        let grown = Source::Growth(GrowthParams::preset(self.species), self.cycles).grow(seed)?;
        self.finish(&grown)
    }

    /// A grown tree of this species with its trunk cleared (what [`grow`](Self::grow)
    /// does after growing).
    pub fn finish(&self, grown: &Skeleton) -> Result<Skeleton> {
        let h = height_of(grown);
        let cleared = crate::skeleton::prune::clear_trunk(grown, h * self.clear_trunk).skeleton;
        flare_and_roots(&cleared, self.flare, self.roots)
    }
}

/// `skeleton` with its trunk flared toward the ground (radius times `flare` at the foot,
/// easing to none at four foot radii up) and `roots` surface roots: chains of three
/// tapering branches that leave the foot evenly around it, spread and sink into the
/// ground. A skeleton without a single trunk comes back as it is.
fn flare_and_roots(skeleton: &Skeleton, flare: f32, roots: u32) -> Result<Skeleton> {
    let b = skeleton.branches();
    let Some(trunk) = b.iter().position(|x| x.parent == NO_PARENT) else {
        return Ok(skeleton.clone());
    };
    let foot = b[trunk].start;
    let r0 = b[trunk].start_radius;
    if r0.is_nan() || r0 <= 0.0 || (flare <= 1.0 && roots == 0) {
        return Ok(skeleton.clone());
    }
    let mut parts = skeleton.clone().into_parts();
    let up_to = 4.0 * r0;
    let widen = |p: [f32; 3], r: f32| {
        let t = ((p[1] - foot[1]) / up_to).clamp(0.0, 1.0);
        r * (1.0 + (flare - 1.0).max(0.0) * (1.0 - t) * (1.0 - t))
    };
    for x in parts.branches.iter_mut().filter(|x| x.order == 0) {
        x.start_radius = widen(x.start, x.start_radius);
        x.end_radius = widen(x.end, x.end_radius);
    }
    let color = parts.colors.get(trunk).copied();
    let (has_ups, has_curves) = (!parts.ups.is_empty(), !parts.curves.is_empty());
    for k in 0..roots {
        let a =
            std::f32::consts::TAU * (k as f32 + 0.3 * ((k * 7 % 5) as f32 / 5.0)) / roots as f32;
        let (c, s) = (a.cos(), a.sin());
        // Out and down from inside the foot: (reach out, drop) per segment, in foot radii.
        let steps = [(0.0, -0.4), (0.8, 0.7), (0.7, 0.9), (0.5, 1.0)];
        let radii = [0.3, 0.2, 0.12, 0.05];
        let mut at = [foot[0], foot[1] - steps[0].1 * r0, foot[2]];
        let mut out = 0.4 * r0;
        at = [at[0] + c * out, at[1], at[2] + s * out];
        for seg in 1..4 {
            out = steps[seg].0 * r0;
            let end = [at[0] + c * out, at[1] - steps[seg].1 * r0, at[2] + s * out];
            let parent = if seg == 1 {
                NO_PARENT
            } else {
                (parts.branches.len() - 1) as u32
            };
            parts.branches.push(Branch {
                start: at,
                end,
                start_radius: radii[seg - 1] * r0,
                end_radius: radii[seg] * r0,
                parent,
                birth: 0,
                order: 1,
                flags: 0,
            });
            if has_ups {
                parts.ups.push([0.0, 1.0, 0.0]);
            }
            if has_curves {
                let third = |t: f32| std::array::from_fn(|i| at[i] + (end[i] - at[i]) * t);
                parts.curves.push([third(1.0 / 3.0), third(2.0 / 3.0)]);
            }
            if let Some(c) = color {
                parts.colors.push(c);
            }
            at = end;
        }
    }
    parts.build()
}

/// The height of `skeleton` (its highest branch end above its lowest), in model units.
fn height_of(skeleton: &Skeleton) -> f32 {
    skeleton.bounds().map_or(0.0, |(lo, hi)| hi.y - lo.y)
}

/// The mesh and leaf options that draw `skeleton` as `look` at its height: `options`
/// with its scale multiplied so the tree is `look.height` metres tall and its
/// `texture_scale` one bark tile, and leaves at the tips and buds of the youngest
/// branches, sized in metres, on the atlas' cells.
pub fn options(
    look: &Look,
    skeleton: &Skeleton,
    options: &MeshOptions,
) -> Result<(MeshOptions, LeafOptions)> {
    let h = height_of(skeleton);
    if !(h.is_finite() && h > 0.0) {
        return Err(Error::invalid(
            "skeleton",
            format!("a tree of height {h}; expected a grown tree"),
        ));
    }
    // Model units to metres.
    let to_m = look.height / h;
    let mut o = *options;
    o.scale *= to_m;
    o.texture_scale = look.bark.tile / to_m;
    o.even_texels = true;
    let last = skeleton
        .branches()
        .iter()
        .map(|b| b.birth)
        .max()
        .unwrap_or(0);
    let leaves = LeafOptions::default()
        .sites(true)
        .polygons(false)
        .tips(true)
        .min_birth(last.saturating_sub(look.leaf_cycles.saturating_sub(1)))
        .density(look.leaves_per_tip)
        .size(look.leaf.size / to_m)
        .size_jitter(0.25)
        .tilt(40.0)
        .atlas_columns(crate::texture::ATLAS_COLUMNS)
        .atlas_rows(crate::texture::ATLAS_ROWS);
    Ok((o, leaves))
}

/// One tree of `look` as a scene: bark and baked leaves at the species' height
/// ([`options`]), the bark textured with its colour and normal maps and the leaves with
/// the species' atlas, all `texture_size` pixels square (16..=4096) and drawn from `seed`.
pub fn tree_scene(
    look: &Look,
    skeleton: &Skeleton,
    mesh: &MeshOptions,
    texture_size: u32,
    seed: u64,
) -> Result<Scene> {
    let (o, leaves) = options(look, skeleton, mesh)?;
    let leaves = leaves.seed(seed);
    // The textures are checked (their size) before the meshes are built.
    let bark = bark_textures(&look.bark, texture_size, seed)?;
    let atlas = leaf_atlas(&look.leaf, texture_size, seed)?;
    let mut scene = Scene::tree(skeleton, &o, Some(&leaves))?;
    scene.texture(bark, atlas);
    Ok(scene)
}
