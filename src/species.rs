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
//! assert_eq!(scene.textures.len(), 4); // bark colour, normal and roughness; the leaf atlas
//! assert!(scene.materials.iter().any(|m| m.alpha_cutoff.is_some()));
//! ```

use crate::error::{Error, Result};
use crate::mesh::LeafInstance;
use crate::mesh::{LeafOptions, MeshOptions};
use crate::models::growth::{GrowthParams, Species};
use crate::scene::Scene;
use crate::skeleton::twig::{TWIG_VARIANTS, Twig, TwigShape, graft, twig_sites};
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
    /// Its twigs, placed at the young tips and along the young shoots and carrying the
    /// leaves (`length` 0: none; the leaves sit on the tips and buds themselves).
    pub twig: TwigShape,
    /// A twig's length in metres (0: no twigs).
    pub twig_length: f32,
    /// A conifer's crown drawn into a cone: its half-width at the crown's base over the
    /// tree's height (0: the crown as it grew).
    pub cone: f32,
    /// A weeping crown drawn out into a dome: its half-width at the crown's base over the
    /// tree's height (0: the crown as it grew).
    pub dome: f32,
    /// Twigs grow on the branches of the last this many cycles (the leaves on the
    /// twigs, and on the tips of the last `leaf_cycles`).
    pub twig_cycles: u32,
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
            twig: TwigShape::new(),
            twig_length: 0.0,
            twig_cycles: 0,
            cone: 0.0,
            dome: 0.0,
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
            // A pine sheds its lower limbs: a tall clear bole under the crown.
            Species::Pine => l(28, 18.0, 0.45, LeafLook::pine(), 4.0, 4, BarkLook::pine()),
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
            // Twigs: length in metres, side stems, their angle, how far they hang, and
            // leaf cards on each stem's tip.
            let (twig_length, stems, spread, droop, leaves_per_tip) = match species {
                Species::Oak => (0.45, 4, 50.0, 0.15, 1.3),
                Species::Maple => (0.45, 4, 45.0, 0.1, 1.3),
                Species::Birch => (0.5, 5, 35.0, 0.6, 1.2),
                Species::Willow => (1.2, 8, 20.0, 0.95, 2.5),
                Species::Poplar => (0.35, 3, 35.0, 0.05, 1.3),
                Species::Pine => (0.35, 4, 40.0, 0.0, 2.5),
                Species::Spruce => (0.4, 6, 60.0, 0.3, 1.0),
                _ => (0.2, 4, 45.0, 0.1, 1.3),
            };
            let twig = TwigShape {
                stems,
                spread,
                droop,
                ..TwigShape::new()
            };
            Look {
                flare,
                roots,
                twig,
                twig_length,
                // Conifers keep needles on fewer years of shoots (and shed the rest).
                twig_cycles: match species {
                    Species::Pine => 7,
                    Species::Spruce => 10,
                    _ => 14,
                },
                cone: match species {
                    Species::Pine => 0.3,
                    Species::Spruce => 0.24,
                    _ => 0.0,
                },
                dome: if species == Species::Willow {
                    0.55
                } else {
                    0.0
                },
                leaves_per_tip,
                ..l
            }
        })
    }

    /// Every named species' look, in the enum's order.
    pub fn all() -> Vec<Look> {
        Species::ALL.iter().filter_map(|&s| Look::of(s)).collect()
    }

    /// The species' tree grown alone for its cycles, seeded with `seed`, its trunk
    /// cleared of branches up to [`clear_trunk`](Self::clear_trunk) of its height.
    pub fn grow(&self, seed: u64) -> Result<Skeleton> {
        self.finish(&self.grown(seed)?)
    }

    /// The species' tree grown alone without its twigs ([`finish_bare`](Self::finish_bare)):
    /// the tree a host draws instanced twigs on ([`twig_instances`]).
    pub fn grow_bare(&self, seed: u64) -> Result<Skeleton> {
        self.finish_bare(&self.grown(seed)?)
    }

    /// The species' preset grown alone for its cycles, as it grew: before
    /// [`finish`](Self::finish) (or [`finish_bare`](Self::finish_bare)) clears its trunk
    /// and grafts its twigs.
    pub fn grown(&self, seed: u64) -> Result<Skeleton> {
        Source::Growth(GrowthParams::preset(self.species), self.cycles).grow(seed)
    }

    /// A grown tree of this species with its trunk cleared (what [`grow`](Self::grow)
    /// does after growing).
    pub fn finish(&self, grown: &Skeleton) -> Result<Skeleton> {
        let bare = self.finish_bare(grown)?;
        let sites = self.twig_sites(&bare);
        if sites.is_empty() {
            return Ok(bare);
        }
        let twigs = self.twigs()?;
        graft(&bare, &twigs, &sites, newest(&bare) + 1)
    }

    /// [`finish`](Self::finish) without the twigs: the tree a host draws its instanced
    /// twigs on ([`twig_sites`](Self::twig_sites)).
    pub fn finish_bare(&self, grown: &Skeleton) -> Result<Skeleton> {
        let h = height_of(grown);
        let cleared = crate::skeleton::prune::clear_trunk(grown, h * self.clear_trunk).skeleton;
        // Limbs without a young shoot (no twig, no leaf) are shed.
        let window = self.twig_cycles.max(self.leaf_cycles);
        let cleared = if window > 0 {
            let min_birth = newest(&cleared).saturating_sub(window - 1);
            crate::skeleton::prune::shed_bare(&cleared, min_birth).skeleton
        } else {
            cleared
        };
        let bole = bole(cleared, h * self.clear_trunk.max(0.1))?;
        let shaped = cone(bole, self.cone, self.clear_trunk)?;
        let shaped = dome(shaped, self.dome, self.clear_trunk)?;
        flare_and_roots(&shaped, self.flare, self.roots)
    }

    /// The species' twig prototypes ([`TWIG_VARIANTS`] of them, the same for every tree
    /// of the species), one unit long; none when the species has no twigs.
    pub fn twigs(&self) -> Result<Vec<Twig>> {
        if self.twig_length <= 0.0 {
            return Ok(Vec::new());
        }
        (0..TWIG_VARIANTS as u64)
            .map(|k| Twig::new(&self.twig, k))
            .collect()
    }

    /// Where `bare` (a tree from [`finish_bare`](Self::finish_bare)) carries its twigs:
    /// the young tips and shoots (of the last [`twig_cycles`](Self::twig_cycles) cycles), each with its
    /// branch and its transform from twig space at the species' twig length; twig `k`
    /// is variant `k % TWIG_VARIANTS`.
    pub fn twig_sites(&self, bare: &Skeleton) -> Vec<(u32, LeafInstance)> {
        let h = height_of(bare);
        if self.twig_length <= 0.0 || !(h.is_finite() && h > 0.0) {
            return Vec::new();
        }
        let length = self.twig_length * h / self.height;
        let min_birth = newest(bare).saturating_sub(self.twig_cycles.saturating_sub(1));
        let mut sites = twig_sites(bare, min_birth, length, self.twig.droop, 0);
        // At most MAX_TWIGS, an even choice among them (the other tips carry leaves).
        if sites.len() > MAX_TWIGS {
            let keep = MAX_TWIGS as f64 / sites.len() as f64;
            let mut rng = crate::rng::Rng::new(0x0007_7196);
            sites.retain(|_| rng.next_f64() < keep);
        }
        sites
    }
}

/// Degrees a species' leaf cards are folded along their midribs.
pub const LEAF_FOLD: f32 = 30.0;

/// Branches thicker than this radius (metres) are wood a leaf card stays out of.
pub const TWIG_RADIUS: f32 = 0.03;

/// The most twigs a species' tree carries (about): a fine-branched tree has more young
/// tips than its crown needs twigs, and every twig is stems in the bark mesh.
pub const MAX_TWIGS: usize = 2500;

/// The latest birth of a branch of `skeleton`.
fn newest(skeleton: &Skeleton) -> u32 {
    skeleton
        .branches()
        .iter()
        .map(|b| b.birth)
        .max()
        .unwrap_or(0)
}

/// `skeleton` with its crown drawn into a cone about the trunk's axis: from the crown's
/// base (`base` of the height) its half-width may be at most `ratio` of the height, falling
/// linearly to none at the top. Every point at a height moves toward the axis by the same
/// factor (the crown's widest reach there over the cone's), so joints stay joined, radii
/// and heights stay as they are. `ratio` 0: the skeleton as it is.
fn cone(skeleton: Skeleton, ratio: f32, base: f32) -> Result<Skeleton> {
    envelope(skeleton, base, 1.0, |t| ratio * (1.0 - t))
}

/// `skeleton` with its crown drawn out into a dome about the trunk's axis: from the
/// crown's base (`base` of the height) its half-width is `ratio` of the height (a branch
/// reaching less is drawn out, up to three times), rounding to none at the top; below
/// the base, hanging branches keep the dome's width. `ratio` 0: the skeleton as it is.
fn dome(skeleton: Skeleton, ratio: f32, base: f32) -> Result<Skeleton> {
    envelope(skeleton, base, 3.0, |t| {
        ratio * (1.0 - t * t).max(0.0).sqrt()
    })
}

/// `skeleton` with its crown's reach from the trunk's axis made `width(t)` of the height at
/// each height above the crown's base (t from 0 there to 1 at the top; below the base,
/// `width(0)`): every point at a height moves along the ray from the axis by that
/// height's factor (wanted reach over the reach there, at most `most`), so joints stay
/// joined, heights and radii as they were. A width of 0 everywhere: as it is.
fn envelope(
    skeleton: Skeleton,
    base: f32,
    most: f32,
    width: impl Fn(f32) -> f32,
) -> Result<Skeleton> {
    let Some((lo, hi)) = skeleton.bounds() else {
        return Ok(skeleton);
    };
    let b = skeleton.branches();
    let foot = b
        .iter()
        .find(|x| x.parent == NO_PARENT && x.order == 0)
        .map(|x| x.start);
    let h = hi.y - lo.y;
    let Some([ax, _, az]) = foot.filter(|_| width(0.0) > 0.0 && h > 0.0) else {
        return Ok(skeleton);
    };
    let base_y = lo.y + base * h;
    let wanted = |y: f32| h * width(((y - base_y) / (hi.y - base_y).max(1e-6)).clamp(0.0, 1.0));
    // The crown's reach from the axis in bands of height.
    const BANDS: usize = 48;
    let band = |y: f32| (((y - lo.y) / h * BANDS as f32) as usize).min(BANDS - 1);
    let mut reach = [0.0f32; BANDS];
    for x in b {
        for p in [x.start, x.end] {
            let d = ((p[0] - ax).powi(2) + (p[2] - az).powi(2)).sqrt();
            let k = band(p[1]);
            reach[k] = reach[k].max(d);
        }
    }
    // The factor at each band's centre, then read between them (continuous in height).
    let factor: Vec<f32> = (0..BANDS)
        .map(|k| {
            let y = lo.y + (k as f32 + 0.5) / BANDS as f32 * h;
            if reach[k] > 0.0 {
                (wanted(y) / reach[k]).min(most)
            } else {
                1.0
            }
        })
        .collect();
    let at = |y: f32| {
        let t = ((y - lo.y) / h * BANDS as f32 - 0.5).clamp(0.0, (BANDS - 1) as f32);
        let k = (t as usize).min(BANDS - 2);
        factor[k] + (factor[k + 1] - factor[k]) * (t - k as f32)
    };
    let squeeze = |p: [f32; 3]| {
        let f = at(p[1]);
        [ax + (p[0] - ax) * f, p[1], az + (p[2] - az) * f]
    };
    let mut parts = skeleton.into_parts();
    for x in &mut parts.branches {
        (x.start, x.end) = (squeeze(x.start), squeeze(x.end));
    }
    for c in &mut parts.curves {
        *c = [squeeze(c[0]), squeeze(c[1])];
    }
    for l in &mut parts.leaves {
        l.position = squeeze(l.position);
    }
    for p in &mut parts.polygon_points {
        *p = squeeze(*p);
    }
    parts.build()
}

/// `skeleton` with its trunk below `height` (above its foot) a bole: nearly a cylinder,
/// its radius the trunk's at `height` and a quarter more at the foot, where the pipe
/// model (each branch as thick as all it carries) would make it a steep cone. Never
/// thicker than it was.
fn bole(skeleton: Skeleton, height: f32) -> Result<Skeleton> {
    let b = skeleton.branches();
    let Some(foot) = b.iter().position(|x| x.parent == NO_PARENT && x.order == 0) else {
        return Ok(skeleton);
    };
    let base = b[foot].start[1];
    let top = base + height;
    // The trunk's radius where it reaches `height`: along its axis from the foot.
    let adjacency = skeleton.adjacency();
    let (mut i, mut r_top) = (foot, None);
    loop {
        let x = &b[i];
        if x.end[1] >= top && x.start[1] <= top {
            let t = ((top - x.start[1]) / (x.end[1] - x.start[1]).max(1e-6)).clamp(0.0, 1.0);
            r_top = Some(x.start_radius + (x.end_radius - x.start_radius) * t);
            break;
        }
        match adjacency.continuation(i) {
            Some(c) => i = c as usize,
            None => break,
        }
    }
    let Some(r_top) = r_top else {
        return Ok(skeleton);
    };
    let profile = |y: f32| r_top * (1.0 + 0.25 * (1.0 - ((y - base) / height).clamp(0.0, 1.0)));
    let mut parts = skeleton.into_parts();
    for x in parts.branches.iter_mut().filter(|x| x.order == 0) {
        if x.start[1] < top {
            x.start_radius = x.start_radius.min(profile(x.start[1]));
        }
        if x.end[1] < top {
            x.end_radius = x.end_radius.min(profile(x.end[1]));
        }
    }
    parts.build()
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
    // Radii fall smoothly along an axis (no step at each node), as bark does.
    o.smooth_taper = true;
    // Sides by radius, unless the host chose: up to 12 round the trunk and limbs (at
    // least the host's count), down to 4 (even texels round 3 up) for twigs' stems.
    if o.min_radial_segments == 0 {
        o.radial_segments = o.radial_segments.max(12);
        o.min_radial_segments = 3;
    }
    let last = newest(skeleton);
    // The leaves are on the tips of the last `leaf_cycles` cycles (the twigs' stems are
    // the newest), and on the buds there when the species has no twigs.
    let leaves = LeafOptions::default()
        .sites(look.twig_length <= 0.0)
        .polygons(false)
        .tips(true)
        .min_birth(last.saturating_sub(look.leaf_cycles.saturating_sub(1)))
        .density(look.leaves_per_tip)
        .size(look.leaf.size / to_m)
        .size_jitter(0.25)
        .tilt(40.0)
        .atlas_columns(crate::texture::ATLAS_COLUMNS)
        .atlas_rows(crate::texture::ATLAS_ROWS)
        // No card inside a branch thicker than a twig.
        .wood_clearance(TWIG_RADIUS / to_m)
        // Folded a little along the midrib, turned toward the light (give or take 35°).
        .fold(LEAF_FOLD)
        .face_light(true)
        .rotation_jitter(35.0);
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

/// Twig `variant` of `look` (taken modulo [`TWIG_VARIANTS`]) as a prototype of its own:
/// its stems in metres (twig space: +Y along the twig, +Z the side its spray faces) and
/// leaf sites at their tips, as many as the species' leaves per tip (rounded, at least
/// one). Mesh it once with [`twig_options`]; draw it at each of [`twig_instances`]: the
/// twigs [`Look::grow`] bakes into the tree. A species without twigs: an error naming
/// `look`.
pub fn twig_prototype(look: &Look, variant: usize) -> Result<Skeleton> {
    let twigs = look.twigs()?;
    let Some(twig) = twigs.get(variant % TWIG_VARIANTS.max(1)) else {
        return Err(Error::invalid(
            "look",
            format!(
                "{:?} has no twigs (twig_length {})",
                look.species, look.twig_length
            ),
        ));
    };
    twig.skeleton(
        look.twig_length,
        look.leaves_per_tip.round().max(1.0) as u32,
    )
}

/// The options that draw a [`twig_prototype`] of `look` with the host's `mesh`
/// conventions (its up axis, scale, winding, layout): the stems at an even bark texel
/// density, the leaves on the prototype's sites, in metres, on the atlas' cells.
pub fn twig_options(look: &Look, mesh: &MeshOptions) -> (MeshOptions, LeafOptions) {
    let mut o = *mesh;
    o.texture_scale = look.bark.tile;
    o.even_texels = true;
    o.smooth_taper = true;
    o.radial_segments = o.radial_segments.clamp(3, 4);
    o.min_radial_segments = 0;
    let leaves = LeafOptions::default()
        .sites(true)
        .tips(false)
        .polygons(false)
        .size(look.leaf.size)
        .size_jitter(0.25)
        .tilt(40.0)
        .atlas_columns(crate::texture::ATLAS_COLUMNS)
        .atlas_rows(crate::texture::ATLAS_ROWS)
        .fold(LEAF_FOLD)
        .face_light(true)
        .rotation_jitter(35.0);
    (o, leaves)
}

/// Where `bare` (a tree of `look` from [`Look::grow_bare`]) carries its twigs, as the
/// transforms that place a [`twig_prototype`] meshed with [`twig_options`] into the
/// tree's mesh drawn with [`options`]`(look, bare, mesh)`: position in the tree's
/// output space, rotation (x, y, z, w) and scale (the twig's size over the prototype's,
/// about 1) in the same conventions. Instance `k` is variant `k % TWIG_VARIANTS`, as are
/// the twigs [`Look::grow`] bakes.
pub fn twig_instances(
    look: &Look,
    bare: &Skeleton,
    mesh: &MeshOptions,
) -> Result<Vec<LeafInstance>> {
    let (tree, _) = options(look, bare, mesh)?;
    let (out, twig_out) = (tree.out(), twig_options(look, mesh).0.out());
    let conjugate = out.map.conjugate();
    let unit = look.twig_length * twig_out.scale;
    Ok(look
        .twig_sites(bare)
        .into_iter()
        .map(|(_, t)| LeafInstance {
            position: out.pos(glam::Vec3::from(t.position)),
            rotation: conjugate(glam::Quat::from_array(t.rotation)).to_array(),
            scale: t.scale * out.scale / unit,
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{Axes, UpAxis};
    use glam::{Quat, Vec3};

    /// The baked twigs' stems, and the prototypes placed by the instances, in the output
    /// space of `mesh`: the same points.
    fn check_instances(species: Species, mesh: &MeshOptions) {
        let look = Look::of(species).unwrap();
        let bare = look.grow_bare(1).unwrap();
        let baked = look.grow(1).unwrap();
        let instances = twig_instances(&look, &bare, mesh).unwrap();
        assert!(instances.len() > 50, "{}", instances.len());
        let tree = options(&look, &bare, mesh).unwrap().0.out();
        let proto_out = twig_options(&look, mesh).0.out();
        let added = &baked.branches()[bare.branches().len()..];
        let scale = tree.scale * look.height;
        let mut k = 0;
        for (i, t) in instances.iter().enumerate() {
            let proto = twig_prototype(&look, i).unwrap();
            let (p, q) = (Vec3::from(t.position), Quat::from_array(t.rotation));
            for s in proto.branches() {
                // The prototype's vertex as the host's mesh of it has it, then placed.
                let local = Vec3::from(proto_out.pos(Vec3::from(s.end)));
                let placed = p + q * (local * t.scale);
                let want = Vec3::from(tree.pos(Vec3::from(added[k].end)));
                assert!(
                    (placed - want).length() < 1e-4 * scale,
                    "{species:?} twig {i} stem: {placed} vs {want}"
                );
                k += 1;
            }
        }
        assert_eq!(k, added.len());
    }

    #[test]
    fn instanced_twigs_are_the_baked_ones_in_any_conventions() {
        check_instances(Species::Poplar, &MeshOptions::default());
        check_instances(Species::Poplar, &MeshOptions::default().up_axis(UpAxis::Z));
        check_instances(Species::Willow, &MeshOptions::default().axes(Axes::Unity));
        check_instances(
            Species::Willow,
            &MeshOptions::default().axes(Axes::Unreal).scale(2.0),
        );
    }

    #[test]
    fn a_prototype_carries_its_leaves_on_its_stems_tips() {
        let look = Look::of(Species::Oak).unwrap();
        let p = twig_prototype(&look, 5).unwrap();
        assert_eq!(p.branches().len(), look.twig.stems as usize + 1);
        let per = look.leaves_per_tip.round() as usize;
        assert_eq!(p.leaves().len(), p.branches().len() * per);
        for l in p.leaves() {
            assert_eq!(l.position, p.branches()[l.branch as usize].end);
        }
        // One twig_length long, in metres.
        let (lo, hi) = p.bounds().unwrap();
        assert!((hi.y - lo.y - look.twig_length).abs() < 0.2 * look.twig_length);
        let none = Look {
            twig_length: 0.0,
            ..look
        };
        assert!(
            twig_prototype(&none, 0)
                .unwrap_err()
                .to_string()
                .contains("`look`")
        );
    }

    #[test]
    fn a_conifer_crown_is_drawn_into_its_cone() {
        let look = Look::of(Species::Spruce).unwrap();
        assert!(look.cone > 0.0);
        let grown = Source::Growth(GrowthParams::preset(Species::Spruce), look.cycles)
            .grow(2)
            .unwrap();
        let free = Look { cone: 0.0, ..look }.finish_bare(&grown).unwrap();
        let coned = look.finish_bare(&grown).unwrap();
        assert_eq!(free.len(), coned.len());
        let (lo, hi) = coned.bounds().unwrap();
        let h = hi.y - lo.y;
        let axis = coned.branches()[0].start;
        let base = lo.y + look.clear_trunk * h;
        let reach = |s: &Skeleton| {
            let mut outside = 0.0f32;
            for b in s.branches().iter().filter(|b| b.order > 0) {
                let p = b.end;
                let d = ((p[0] - axis[0]).powi(2) + (p[2] - axis[2]).powi(2)).sqrt();
                let allowed = look.cone * h * ((hi.y - p[1]) / (hi.y - base)).clamp(0.0, 1.0);
                outside = outside.max(d - allowed);
            }
            outside
        };
        // As grown, the crown leaves the cone by metres' worth; drawn in, by little (the
        // factor is read between bands of height).
        assert!(reach(&free) > 0.1 * h, "{}", reach(&free));
        assert!(reach(&coned) < 0.02 * h, "{}", reach(&coned));
        // Heights and radii are the grown ones.
        for (a, b) in free.branches().iter().zip(coned.branches()) {
            assert_eq!(
                (a.start[1], a.end[1], a.end_radius),
                (b.start[1], b.end[1], b.end_radius)
            );
        }
    }

    #[test]
    fn a_weeping_crown_is_drawn_out_into_its_dome() {
        let look = Look::of(Species::Willow).unwrap();
        assert!(look.dome > 0.0);
        let grown = Source::Growth(GrowthParams::preset(Species::Willow), look.cycles)
            .grow(2)
            .unwrap();
        let free = Look { dome: 0.0, ..look }.finish_bare(&grown).unwrap();
        let domed = look.finish_bare(&grown).unwrap();
        let width = |s: &Skeleton| {
            let (lo, hi) = s.bounds().unwrap();
            (hi.x - lo.x).max(hi.z - lo.z) / (hi.y - lo.y)
        };
        // As grown, narrow; drawn out, about the dome's width (twice its half-width).
        assert!(width(&free) < 1.5 * look.dome, "{}", width(&free));
        assert!(
            (width(&domed) - 2.0 * look.dome).abs() < 0.35 * look.dome,
            "{}",
            width(&domed)
        );
        for (a, b) in free.branches().iter().zip(domed.branches()) {
            assert_eq!(
                (a.end[1], a.end_radius, a.parent),
                (b.end[1], b.end_radius, b.parent)
            );
        }
    }
}
