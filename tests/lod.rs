//! Levels of detail: every level within its budget, its silhouette the full tree's where
//! it is first drawn (arbor's rasterizer), for every species and the 1996 trees.

use arbor::lod::{Frame, Level, LodOptions, chain, silhouette, silhouette_floor};
use arbor::mesh::{LeafOptions, MeshOptions};
use arbor::raster::iou;
use arbor::species::Look;
use arbor::texture::Image;
use glam::Vec3;

/// Directions around the tree and a little above and below it, none of them those the
/// chain was fitted from.
fn directions(n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|k| {
            let a = std::f32::consts::TAU * (k as f32 + 0.37) / n as f32;
            let y = [-0.15, 0.0, 0.2, 0.35][k % 4];
            Vec3::new(a.cos(), y, a.sin()).normalize()
        })
        .collect()
}

/// Checks a chain: budgets, and each level against the full tree where it is first
/// drawn (the previous level's switch), from 32 directions. Returns each level's mean IoU.
///
/// 32, not 8: a level first drawn at 14 pixels has an IoU that moves from 0.80 to 0.94
/// between neighbouring directions (a few pixels of its edge flip), so the mean of 8 is
/// off by a few hundredths (the oak's level 3: 0.889 from 8, 0.920 from 64).
///
/// With `floor`, each line also gives the measure's own floor there: the full tree
/// against itself moved a quarter of a pixel ([`silhouette_floor`]), from the same
/// directions.
fn check(
    name: &str,
    levels: &[Level],
    lod: &LodOptions,
    atlas: Option<&Image>,
    floor: bool,
) -> Vec<f32> {
    assert_eq!(levels.len(), lod.levels as usize);
    let full = &levels[0];
    let frame = Frame::of(full, full.mesh_options.up()).unwrap();
    let mut means = Vec::new();
    for (k, level) in levels.iter().enumerate().skip(1) {
        let share = level.triangles as f32 / full.triangles as f32;
        assert!(
            share <= lod.budget_of(k as u32),
            "{name} level {k}: {share} of the triangles"
        );
        assert!(level.screen_coverage <= levels[k - 1].screen_coverage);
        let coverage = levels[k - 1].screen_coverage;
        let pixels = frame.pixels(coverage);
        let (mut sum, mut min) = (0.0f32, 1.0f32);
        let dirs = directions(32);
        for &d in &dirs {
            let a = silhouette(full, atlas, &frame, d, pixels);
            let b = silhouette(level, atlas, &frame, d, pixels);
            let w = iou(&a, &b);
            sum += w;
            min = min.min(w);
        }
        let w = sum / dirs.len() as f32;
        let floor = if floor {
            let f: f32 = dirs
                .iter()
                .map(|&d| silhouette_floor(full, atlas, &frame, d, pixels, 0.25))
                .sum();
            format!(
                "; the tree against itself a quarter pixel off: {:.3}",
                f / dirs.len() as f32
            )
        } else {
            String::new()
        };
        println!(
            "{name} level {k}: {:.1}% of {} triangles, first drawn at coverage {coverage:.3} \
             ({pixels} px), IoU {w:.3} (least {min:.3}){floor}",
            100.0 * share,
            full.triangles
        );
        means.push(w);
    }
    means
}

/// The 1996 tree `name` with leaves at its tips, and its chain.
fn tree_1996(name: char, lod: &LodOptions) -> Vec<Level> {
    let p = arbor::HondaParams::preset(name).unwrap();
    let s = arbor::models::honda::build(&p).unwrap();
    let leaves = LeafOptions::default().tips(true).density(3.0).size(8.0);
    chain(&s, &MeshOptions::default(), Some(&leaves), None, lod).unwrap()
}

/// A species' tree and its chain, with its leaf atlas.
fn species(look: &Look, lod: &LodOptions) -> (Vec<Level>, Image) {
    let mesh = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    let tree = look.grow(1).unwrap();
    let (o, leaves) = arbor::species::options(look, &tree, &mesh).unwrap();
    let atlas = arbor::texture::leaf_atlas(&look.leaf, 256, 1)
        .unwrap()
        .image;
    let levels = chain(&tree, &o, Some(&leaves.seed(1)), Some(&atlas), lod).unwrap();
    (levels, atlas)
}

/// What a chain promises of a level: its silhouette kept where it is first drawn, seen
/// from 32 directions it was not fitted from (within 0.03 of its own figure), or its
/// switch at the least coverage and its figure short (it could not keep it).
fn holds(name: &str, levels: &[Level], lod: &LodOptions, means: &[f32]) {
    for (k, (level, &w)) in levels.iter().skip(1).zip(means).enumerate() {
        let first_drawn = levels[k].screen_coverage;
        if level.silhouette >= lod.silhouette {
            assert!(w >= 0.9, "{name} level {}: {w}", k + 1);
            assert!(
                (level.silhouette - w).abs() < 0.04,
                "{name} level {}: {} vs {w}",
                k + 1,
                level.silhouette
            );
        } else {
            assert_eq!(
                first_drawn,
                arbor::lod::MIN_COVERAGE,
                "{name} level {}",
                k + 1
            );
        }
    }
}

#[test]
fn levels_keep_their_silhouettes_where_they_are_first_drawn() {
    let lod = LodOptions::default();
    for name in ['a', 'e'] {
        let levels = tree_1996(name, &lod);
        let means = check(&format!("tree {name}"), &levels, &lod, None, false);
        holds(&format!("tree {name}"), &levels, &lod, &means);
        // Level 1 of the 1996 trees keeps its silhouette from half the screen down.
        assert!(levels[1].silhouette >= lod.silhouette, "tree {name}");
    }
    // The poplar's last level holds only with its inside leaves enlarged less
    // (`lod::ENLARGE_SHARES`: 0.86 at 11 pixels without).
    for species_name in ["oak", "birch", "poplar"] {
        let look = Look::all()
            .into_iter()
            .find(|l| l.species.name() == species_name)
            .unwrap();
        let (levels, atlas) = species(&look, &lod);
        let means = check(species_name, &levels, &lod, Some(&atlas), false);
        holds(species_name, &levels, &lod, &means);
        // Every level of these keeps it.
        for l in &levels {
            assert!(
                l.silhouette >= lod.silhouette,
                "{species_name}: {}",
                l.silhouette
            );
        }
    }
}

/// The figures of BENCHMARKS.md: every species and every 1996 tree, their budgets checked
/// (`cargo test --release --test lod -- --ignored --nocapture`). Where a level's figure is
/// short of the chain's it is printed, not asserted: a level drawn at a few pixels gives
/// noisy figures from directions it was not fitted from.
#[test]
#[ignore]
fn figures_for_every_species_and_1996_tree() {
    let lod = LodOptions::default();
    for name in ['a', 'b', 'c', 'd', 'e', 'f', 'g', 'h', 'i'] {
        let levels = tree_1996(name, &lod);
        check(&format!("tree {name}"), &levels, &lod, None, true);
    }
    for look in Look::all() {
        let (levels, atlas) = species(&look, &lod);
        check(look.species.name(), &levels, &lod, Some(&atlas), true);
    }
}

/// The measure's floor: the tree against itself unmoved is itself (1), moved a quarter of
/// a pixel a crown at 128 pixels keeps nearly all of it, and twigs drawn at 15 pixels
/// flip in and out: a 1996 tree's falls far below the 0.9 a level is asked to keep.
#[test]
fn the_measure_itself_moves_with_a_quarter_pixel_where_twigs_are_a_pixel_wide() {
    let lod = LodOptions::default().levels(1);
    let twigs = &tree_1996('g', &lod)[0];
    let look = Look::all()
        .into_iter()
        .find(|l| l.species.name() == "oak")
        .unwrap();
    let (crown, atlas) = species(&look, &lod);
    let crown = &crown[0];
    let mean = |level: &Level, atlas: Option<&Image>, pixels: u32, shift: f32| {
        let frame = Frame::of(level, level.mesh_options.up()).unwrap();
        let dirs = directions(8);
        dirs.iter()
            .map(|&d| silhouette_floor(level, atlas, &frame, d, pixels, shift))
            .sum::<f32>()
            / dirs.len() as f32
    };
    assert_eq!(mean(twigs, None, 15, 0.0), 1.0);
    let oak = mean(crown, Some(&atlas), 128, 0.25);
    let g = mean(twigs, None, 15, 0.25);
    println!("a quarter pixel off: the oak at 128 px {oak:.3}, tree g at 15 px {g:.3}");
    assert!(oak >= 0.9, "{oak}");
    assert!(g < 0.8, "{g}");
}

/// A trunk 10 tall with 64 straight twigs at its top: twig `k` as `twig(k)` gives it (its
/// direction, length and radius).
fn trunk_with_twigs(twig: impl Fn(usize) -> ([f32; 3], f32, f32)) -> arbor::skeleton::Skeleton {
    use arbor::skeleton::{Branch, NO_PARENT, SkeletonParts};
    let top = [0.0, 10.0, 0.0];
    let mut branches = vec![Branch {
        start: [0.0; 3],
        end: top,
        start_radius: 0.3,
        end_radius: 0.2,
        parent: NO_PARENT,
        birth: 0,
        order: 0,
        flags: 0,
    }];
    for k in 0..64 {
        let (d, length, radius) = twig(k);
        branches.push(Branch {
            start: top,
            end: [0, 1, 2].map(|i| top[i] + length * d[i]),
            start_radius: radius,
            end_radius: radius,
            parent: 0,
            birth: 1,
            order: 1,
            flags: 0,
        });
    }
    SkeletonParts {
        branches,
        ..SkeletonParts::default()
    }
    .build()
    .unwrap()
}

/// A trunk with a fan of 64 twigs as thick as each other at its top.
fn fan() -> arbor::skeleton::Skeleton {
    trunk_with_twigs(|k| {
        let a = k as f32 * 0.7;
        let up = 0.3 + 0.6 * (k % 5) as f32 / 4.0;
        ([a.cos(), up, a.sin()], 3.0, 0.05)
    })
}

/// Which of the fan's twigs a level kept: those its skeleton did not merge into the
/// trunk's branch.
fn kept_twigs(level: &Level) -> Vec<bool> {
    (1..65)
        .map(|t| level.merged[t] != level.merged[0])
        .collect()
}

/// Branches as thick as each other are removed some at a time, in a fixed order: a level
/// keeps part of an even fan of twigs (not all of them or none), every twig a thinner
/// level keeps is one the level before kept, and the trunk stays.
#[test]
fn a_fan_of_equal_twigs_is_thinned_in_one_order() {
    let lod = LodOptions::default().silhouette(0.0).levels(4);
    let levels = chain(&fan(), &MeshOptions::default(), None, None, &lod).unwrap();
    let mut before = vec![true; 64];
    for (k, level) in levels.iter().enumerate().skip(1) {
        let kept = kept_twigs(level);
        let n = kept.iter().filter(|&&x| x).count();
        assert!(n > 0 && n < 64, "level {k} keeps {n} of 64 twigs");
        assert!(
            kept.iter().zip(&before).all(|(&now, &then)| !now || then),
            "level {k} keeps a twig level {} removed",
            k - 1
        );
        assert!(
            level.triangles as f32 <= lod.budget_of(k as u32) * levels[0].triangles as f32,
            "level {k}: {} triangles",
            level.triangles
        );
        // The trunk is there: a vertex at its foot.
        assert!(
            level
                .bark
                .vertices
                .iter()
                .any(|v| v.position[1] < 0.01 && v.position[0].abs() < 0.31),
            "level {k} has no trunk"
        );
        before = kept;
    }
}

/// A trunk with 32 long, thin twigs (4 long, radius 0.01) and 32 short, thicker ones (0.4
/// long, radius 0.03) at its top, alternating around it.
fn long_and_short() -> arbor::skeleton::Skeleton {
    trunk_with_twigs(|k| {
        let a = k as f32 * 0.7;
        let (length, radius) = if k % 2 == 0 { (4.0, 0.01) } else { (0.4, 0.03) };
        ([a.cos() * 0.8, 0.6, a.sin() * 0.8], length, radius)
    })
}

/// A level's bark keeps the branches that draw the most outline for their triangles: the
/// long, thin twigs (each as many triangles as a short one, ten times its length) outlast
/// the short, thicker ones, though they are thinner (a level that took the thinnest first
/// kept the short ones and lost a willow's hanging twigs).
#[test]
fn levels_keep_the_twigs_that_draw_the_most_outline() {
    let lod = LodOptions::default().silhouette(0.0).levels(4);
    let levels = chain(&long_and_short(), &MeshOptions::default(), None, None, &lod).unwrap();
    let mut thinned = false;
    for (k, level) in levels.iter().enumerate().skip(1) {
        let kept = kept_twigs(level);
        let long = (0..64).step_by(2).filter(|&t| kept[t]).count();
        let short = (1..64).step_by(2).filter(|&t| kept[t]).count();
        // Every short twig goes before any long one.
        assert!(
            short == 0 || long == 32,
            "level {k} keeps {short} short and {long} long twigs"
        );
        thinned |= long < 32 || short < 32;
    }
    assert!(thinned, "no level removed a twig");
}

/// No level of a 1996 tree is empty: its branches are all thin where the thinner levels
/// are drawn, but the trunk stays (tree i's levels 2 and 3 were empty).
#[test]
fn no_level_of_a_1996_tree_is_empty() {
    let lod = LodOptions::default();
    for name in ['c', 'i'] {
        for (k, level) in tree_1996(name, &lod).iter().enumerate() {
            assert!(level.bark.triangles().count() > 0, "tree {name} level {k}");
        }
    }
}

/// Leaves placed once and thinned for each level are the leaves placed again for it: the
/// same mesh for every keep, and options other than `keep` (or another mesh's) placed
/// afresh.
#[test]
fn leaves_placed_once_bake_as_leaves_placed_again() {
    use arbor::mesh::{leaf_mesh, leaf_mesh_placed, place_all};
    let tree = arbor::models::honda::build(&arbor::HondaParams::preset('b').unwrap()).unwrap();
    let mesh = MeshOptions::default();
    let leaves = LeafOptions::default().tips(true).density(4.0).size(6.0);
    let placed = place_all(&tree, &leaves.clone().keep(0.3), &mesh).unwrap();
    assert!(placed.len() > 1000, "{}", placed.len());
    for keep in [1.0, 0.5, 0.1, 0.01] {
        let l = leaves.clone().keep(keep);
        assert_eq!(
            leaf_mesh_placed(&tree, &placed, &l, &mesh).unwrap(),
            leaf_mesh(&tree, &l, &mesh).unwrap(),
            "keep {keep}"
        );
    }
    let other = leaves.clone().size(9.0).keep(0.5);
    assert_eq!(
        leaf_mesh_placed(&tree, &placed, &other, &mesh).unwrap(),
        leaf_mesh(&tree, &other, &mesh).unwrap()
    );
    let thin = MeshOptions::default().cull_radius(0.05);
    assert_eq!(
        leaf_mesh_placed(&tree, &placed, &leaves, &thin).unwrap(),
        leaf_mesh(&tree, &leaves, &thin).unwrap()
    );
}

/// A level meshed with fewer sides is widened to keep the trunk as wide as the full tree
/// draws it on average over the directions it is seen from (an inscribed triangle is 16%
/// narrower than an inscribed 12-gon): the mean width of each level's trunk across 64
/// directions is the full tree's within 1%, and the polygon's mean width is its perimeter
/// over pi.
#[test]
fn fewer_sides_keep_the_trunk_as_wide() {
    use arbor::lod::polygon_width;
    for (n, w) in [(3, 0.826_993), (4, 0.900_316), (12, 0.988_616)] {
        assert!(
            (polygon_width(n) - w).abs() < 1e-5,
            "{n}: {}",
            polygon_width(n)
        );
    }
    // A trunk alone, so no level can prune it: only its sides change.
    let tree = trunk_with_twigs(|_| ([0.0, 1.0, 0.0], 1e-4, 1e-5));
    let mesh = MeshOptions::default().radial_segments(12);
    let lod = LodOptions::default().silhouette(0.0);
    let levels = chain(&tree, &mesh, None, None, &lod).unwrap();
    // The width of the trunk's base ring across direction `a`.
    let width = |level: &Level, a: f32| {
        let (c, s) = (a.cos(), a.sin());
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for v in &level.bark.vertices {
            if v.position[1].abs() < 1e-4 {
                let x = v.position[0] * c + v.position[2] * s;
                (lo, hi) = (lo.min(x), hi.max(x));
            }
        }
        hi - lo
    };
    let mean = |level: &Level| {
        (0..64)
            .map(|k| width(level, k as f32 * std::f32::consts::TAU / 64.0 + 0.01))
            .sum::<f32>()
            / 64.0
    };
    let full = mean(&levels[0]);
    assert!(
        (full / (2.0 * 0.3) - polygon_width(12)).abs() < 0.01,
        "{full}"
    );
    for (k, level) in levels.iter().enumerate().skip(1) {
        assert!(level.mesh_options.radial_segments < 12, "level {k}");
        let w = mean(level);
        assert!(
            (w / full - 1.0).abs() < 0.01,
            "level {k}: {w} against {full}"
        );
    }
}

/// The level an impostor is baked from is the coarsest made for views of its cells' size:
/// at 128 pixels it keeps the full tree's silhouette, and the level after it (made for a
/// few pixels: its axes straightened, its twigs pruned for that size) does not. Tree a's
/// level 2, which the CLI baked from before, keeps 0.58 there, its level 1 0.92.
#[test]
fn the_impostor_is_baked_from_the_coarsest_level_made_for_its_views() {
    let lod = LodOptions::default();
    for name in ['a', 'e'] {
        let levels = tree_1996(name, &lod);
        let full = &levels[0];
        let frame = Frame::of(full, full.mesh_options.up()).unwrap();
        let mean = |level: &Level| {
            let dirs = directions(8);
            let sum: f32 = dirs
                .iter()
                .map(|&d| {
                    iou(
                        &silhouette(full, None, &frame, d, 128),
                        &silhouette(level, None, &frame, d, 128),
                    )
                })
                .sum();
            sum / dirs.len() as f32
        };
        let source = arbor::lod::impostor_source(&levels, 128);
        assert!(source >= 1, "tree {name}: a level is made for 128 pixels");
        let kept = mean(&levels[source]);
        assert!(kept >= 0.9, "tree {name}: level {source} keeps {kept}");
        if let Some(next) = levels.get(source + 1) {
            let lost = mean(next);
            assert!(lost < 0.9, "tree {name}: level {} keeps {lost}", source + 1);
        }
        // Ends: every level is first drawn at least 8 pixels across, none at 4,097.
        assert_eq!(arbor::lod::impostor_source(&levels, 8), levels.len() - 1);
        assert_eq!(arbor::lod::impostor_source(&levels, 4097), 0);
    }
}
