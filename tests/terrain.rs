//! Worlds on a terrain: a height field under a world, trees planted on it and from a
//! species map, and the bounds every new input gets.

use arbor::models::growth::{GrowthParams, HeightField, Species, SpeciesMap, World, WorldOptions};
use glam::Vec3;

/// Rolling hills over the default box's floor: 41 × 41 samples a unit apart.
fn hills() -> HeightField {
    HeightField::from_fn(41, 41, 1.0, [-20.0, -20.0], |i, j| {
        let (x, z) = (i as f32 - 20.0, j as f32 - 20.0);
        3.0 + 1.5 * (x * 0.3).sin() * (z * 0.25).cos() + 0.05 * x
    })
    .unwrap()
}

fn seeding(species: Species) -> GrowthParams {
    let mut p = GrowthParams::preset(species);
    p.seed_age = 6;
    p
}

fn options() -> WorldOptions {
    WorldOptions::default()
        .min([-20.0, 0.0, -20.0])
        .max([20.0, 30.0, 20.0])
}

fn trees(w: &World) -> Vec<arbor::skeleton::Skeleton> {
    (0..w.tree_count()).map(|k| w.tree(k).unwrap()).collect()
}

#[test]
fn a_flat_ground_at_the_floor_grows_todays_forest_bit_for_bit() {
    let grow = |ground: bool| {
        let mut w = World::new(&options()).unwrap();
        if ground {
            let flat = HeightField::from_fn(9, 9, 5.0, [-20.0, -20.0], |_, _| 0.0).unwrap();
            w.set_ground(flat).unwrap();
        }
        for (k, s) in [Species::Decurrent, Species::Excurrent, Species::Bush]
            .iter()
            .enumerate()
        {
            w.plant(&seeding(*s), [k as f32 * 4.0 - 4.0, 0.0, 1.0], k as u64)
                .unwrap();
        }
        w.step(30).unwrap();
        w
    };
    let (plain, flat) = (grow(false), grow(true));
    assert!(
        plain.tree_count() > 3,
        "the forest seeded: {}",
        plain.tree_count()
    );
    assert_eq!(trees(&plain), trees(&flat));
}

#[test]
fn trees_and_their_seedlings_stand_on_the_ground() {
    let ground = hills();
    let mut w = World::new(&options()).unwrap();
    w.set_ground(ground.clone()).unwrap();
    for (k, x) in [-6.0f32, 0.0, 6.0].into_iter().enumerate() {
        w.plant_on_ground(&seeding(Species::Decurrent), [x, 2.0], k as u32, k as u64)
            .unwrap();
    }
    w.step(30).unwrap();
    assert!(w.tree_count() > 6, "seedlings: {}", w.tree_count());
    let (mut high, mut standing) = (0, 0);
    for k in 0..w.tree_count() {
        // A seedling that starved is an empty tree.
        let s = w.tree(k).unwrap();
        let Some(first) = s.branches().first() else {
            continue;
        };
        standing += 1;
        let root = first.start;
        let h = ground.height(root[0], root[2]);
        assert!(
            (root[1] - h).abs() < 1e-4,
            "tree {k} at {root:?}, the ground at {h}"
        );
        high += usize::from(h > 3.5);
        // A seedling keeps its parent's slot.
        assert!(w.tree_slot(k).unwrap() < 3);
    }
    assert!(standing > 6, "{standing} trees standing");
    assert!(high > 0, "some trees stand on the hills' tops");
    assert_eq!(w.ground_height(100.0, 100.0), ground.height(20.0, 20.0));
}

#[test]
fn a_hill_keeps_the_light_from_what_grows_into_it() {
    // A tree leaning into a steep bank: its buds inside the bank get no light, so it grows
    // less toward it than the same tree on flat ground.
    let bank = HeightField::from_fn(
        21,
        21,
        0.5,
        [-5.0, -5.0],
        |i, _| {
            if i >= 12 { 6.0 } else { 0.0 }
        },
    )
    .unwrap();
    let grow = |ground: Option<HeightField>| {
        let mut w = World::new(&options()).unwrap();
        if let Some(g) = ground {
            w.set_ground(g).unwrap();
        }
        w.plant(
            &GrowthParams::preset(Species::Decurrent),
            [0.0, 0.0, 0.0],
            3,
        )
        .unwrap();
        w.step(16).unwrap();
        let s = w.tree(0).unwrap();
        s.branches()
            .iter()
            .filter(|b| b.end[0] > 1.0 && b.end[1] < 6.0)
            .count()
    };
    let (open, banked) = (grow(None), grow(Some(bank)));
    assert!(open > 0, "the open tree reaches toward +x");
    assert!(banked < open, "into the bank {banked}, in the open {open}");
}

#[test]
fn a_species_map_plants_each_half_with_its_species_and_repeats() {
    // Left half slot 0, right half slot 1; a strip in the middle bare.
    let (nx, nz) = (16u32, 16u32);
    let slots: Vec<u32> = (0..nx * nz)
        .map(|k| match k % nx {
            0..=6 => 0,
            9.. => 1,
            _ => SpeciesMap::EMPTY,
        })
        .collect();
    let density = vec![0.25; (nx * nz) as usize];
    let map = SpeciesMap::new(nx, nz, 2.0, [-16.0, -16.0], slots, density).unwrap();
    let species = [
        GrowthParams::preset(Species::Oak),
        GrowthParams::preset(Species::Pine),
    ];
    let plant = |seed| {
        let mut w = World::new(&options()).unwrap();
        w.set_ground(hills()).unwrap();
        let ids = w.plant_map(&map, &species, seed).unwrap();
        (w, ids)
    };
    let (w, ids) = plant(7);
    // 7 columns of 16 cells of 4 square units at 0.25 a unit: 112 expected a half.
    let halves = [0, 1].map(|slot| {
        (0..w.tree_count())
            .filter(|&k| w.tree_slot(k).unwrap() == slot)
            .count()
    });
    for n in halves {
        assert!(
            (80..=145).contains(&n),
            "a half planted {n} trees, about 112 expected"
        );
    }
    assert_eq!(ids.len(), w.tree_count());
    for k in 0..w.tree_count() {
        let root = w.tree(k).unwrap().branches()[0].start;
        let slot = w.tree_slot(k).unwrap();
        assert_eq!(map.slot_at(root[0], root[2]), slot, "tree {k} at {root:?}");
        assert!(if slot == 0 {
            root[0] < -2.0
        } else {
            root[0] > 2.0
        });
        assert!((root[1] - w.ground_height(root[0], root[2])).abs() < 1e-4);
    }
    let (again, _) = plant(7);
    assert_eq!(trees(&w), trees(&again), "same map and seed, same forest");
    let (other, _) = plant(8);
    assert_ne!(trees(&w), trees(&other), "another seed, another forest");
}

#[test]
fn a_slider_changes_one_species_and_leaves_the_other() {
    let mut w = World::new(&options()).unwrap();
    w.plant_on_ground(&GrowthParams::preset(Species::Decurrent), [-5.0, 0.0], 0, 1)
        .unwrap();
    w.plant_on_ground(&GrowthParams::preset(Species::Decurrent), [5.0, 0.0], 1, 2)
        .unwrap();
    w.step(5).unwrap();
    let mut preview = w.clone();
    let mut p = GrowthParams::preset(Species::Decurrent);
    p.apical_control = 0.8;
    assert_eq!(preview.set_species(1, &p).unwrap(), 1);
    preview.step(15).unwrap();
    w.step(15).unwrap();
    assert_eq!(
        w.tree(0).unwrap(),
        preview.tree(0).unwrap(),
        "slot 0 untouched"
    );
    assert_ne!(
        w.tree(1).unwrap(),
        preview.tree(1).unwrap(),
        "slot 1 changed"
    );
    p.apical_control = f32::NAN;
    assert!(preview.set_species(1, &p).is_err());
}

#[test]
fn bad_ground_and_maps_are_refused_by_name() {
    let err = |r: arbor::Result<HeightField>| r.unwrap_err().to_string();
    assert!(err(HeightField::new(1, 5, 1.0, [0.0; 2], vec![0.0; 5])).contains("at least 2 x 2"));
    assert!(
        err(HeightField::new(2, 2, 1.0, [0.0; 2], vec![0.0; 3])).contains("expected 2 x 2 = 4")
    );
    let nan = err(HeightField::new(
        2,
        2,
        1.0,
        [0.0; 2],
        vec![0.0, 0.0, f32::NAN, 0.0],
    ));
    assert!(nan.contains("sample (0, 1)"), "{nan}");
    assert!(err(HeightField::new(2, 2, 0.0, [0.0; 2], vec![0.0; 4])).contains("cell_size"));
    assert!(
        err(HeightField::new(
            2,
            2,
            1.0,
            [f32::INFINITY, 0.0],
            vec![0.0; 4]
        ))
        .contains("origin")
    );
    // Too many samples: refused before anything is read or allocated.
    let big = err(HeightField::from_fn(
        1 << 13,
        1 << 13,
        1.0,
        [0.0; 2],
        |_, _| unreachable!(),
    ));
    assert!(big.contains("MAX_GROUND_SAMPLES"), "{big}");
    // Outside the box, or laid after planting.
    let mut w = World::new(&options()).unwrap();
    let tall = HeightField::from_fn(2, 2, 1.0, [0.0; 2], |i, _| i as f32 * 40.0).unwrap();
    assert!(
        w.set_ground(tall)
            .unwrap_err()
            .to_string()
            .contains("y range")
    );
    w.plant(&GrowthParams::default(), [0.0; 3], 0).unwrap();
    assert!(
        w.set_ground(hills())
            .unwrap_err()
            .to_string()
            .contains("laid first")
    );
    // A map's slot past the species given; more trees than max_trees.
    let map = SpeciesMap::new(2, 2, 4.0, [0.0; 2], vec![0, 1, 2, 0], vec![1.0; 4]).unwrap();
    let mut w = World::new(&options()).unwrap();
    let e = w
        .plant_map(&map, &[GrowthParams::default(); 2], 1)
        .unwrap_err();
    assert!(e.to_string().contains("species slot 2"), "{e}");
    assert_eq!(w.tree_count(), 0, "nothing planted");
    let mut w = World::new(&options().max_trees(10)).unwrap();
    let e = w
        .plant_map(&map, &[GrowthParams::default(); 3], 1)
        .unwrap_err();
    assert!(e.to_string().contains("max_trees"), "{e}");
    assert_eq!(w.tree_count(), 0);
    let e = SpeciesMap::new(2, 2, 1.0, [0.0; 2], vec![0; 4], vec![0.0, -1.0, 0.0, 0.0]);
    assert!(e.unwrap_err().to_string().contains("cell (1, 0)"));
}

/// A PNG of `width × height` grey pixels at `depth` bits, as an encoder writes it.
fn grey_png(width: u32, height: u32, sixteen: bool, pixel: impl Fn(u32, u32) -> u16) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut e = png::Encoder::new(&mut out, width, height);
        e.set_color(png::ColorType::Grayscale);
        e.set_depth(if sixteen {
            png::BitDepth::Sixteen
        } else {
            png::BitDepth::Eight
        });
        let mut w = e.write_header().unwrap();
        let mut data = Vec::new();
        for y in 0..height {
            for x in 0..width {
                let v = pixel(x, y);
                if sixteen {
                    data.extend_from_slice(&v.to_be_bytes());
                } else {
                    data.push(v as u8);
                }
            }
        }
        w.write_image_data(&data).unwrap();
    }
    out
}

#[test]
fn png_height_maps_decode_at_8_and_16_bits() {
    let eight = grey_png(4, 3, false, |x, y| (x * 60 + y) as u16);
    let g = HeightField::from_png(&eight, 10.0, 1.0, 2.0, [0.0, 0.0]).unwrap();
    assert_eq!((g.columns(), g.rows()), (4, 3));
    assert!((g.height(6.0, 0.0) - (1.0 + 180.0 / 255.0 * 10.0)).abs() < 1e-5);
    assert!((g.height(0.0, 4.0) - (1.0 + 2.0 / 255.0 * 10.0)).abs() < 1e-5);
    let sixteen = grey_png(3, 2, true, |x, _| [0, 32768, 65535][x as usize]);
    let g = HeightField::from_png(&sixteen, 4.0, 0.0, 1.0, [0.0, 0.0]).unwrap();
    assert!((g.height(1.0, 0.5) - 4.0 * 32768.0 / 65535.0).abs() < 1e-5);
    assert_eq!(g.range(), (0.0, 4.0));
    // Not a PNG, cut short, and a header claiming 65,535 × 65,535 pixels.
    let e = HeightField::from_png(b"GIF89a", 1.0, 0.0, 1.0, [0.0; 2]).unwrap_err();
    assert!(e.to_string().contains("height map"), "{e}");
    let e = HeightField::from_png(&eight[..eight.len() - 20], 1.0, 0.0, 1.0, [0.0; 2]);
    assert!(e.is_err());
    let mut huge = grey_png(2, 2, false, |_, _| 0);
    huge[16..24].copy_from_slice(&[0, 0, 255, 255, 0, 0, 255, 255]);
    let crc = crc32(&huge[12..29]);
    huge[29..33].copy_from_slice(&crc.to_be_bytes());
    let e = HeightField::from_png(&huge, 1.0, 0.0, 1.0, [0.0; 2]).unwrap_err();
    assert!(e.to_string().contains("MAX_GROUND_SAMPLES"), "{e}");
}

#[test]
fn a_png_species_map_reads_its_legend() {
    let mut out = Vec::new();
    {
        let mut e = png::Encoder::new(&mut out, 4, 2);
        e.set_color(png::ColorType::Rgb);
        e.set_depth(png::BitDepth::Eight);
        let mut w = e.write_header().unwrap();
        let red = [255u8, 0, 0];
        let green = [0u8, 128, 0];
        let white = [255u8, 255, 255];
        let row = [red, red, white, green].concat();
        w.write_image_data(&[row.clone(), row].concat()).unwrap();
    }
    let legend = [([255, 0, 0], 0), ([0, 128, 0], 1)];
    let map = SpeciesMap::from_png(&out, &legend, 0.5, 1.0, [0.0, 0.0]).unwrap();
    assert_eq!(
        map.slots(),
        &[0, 0, SpeciesMap::EMPTY, 1, 0, 0, SpeciesMap::EMPTY, 1]
    );
    assert_eq!(map.slot_at(3.5, 1.5), 1);
    assert_eq!(map.slot_at(-0.5, 0.5), SpeciesMap::EMPTY);
}

/// CRC-32 (IEEE) of a PNG chunk's type and data, to forge a header.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xFFFF_FFFFu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

#[test]
fn the_ground_mesh_follows_the_heights() {
    let g = hills();
    let m = g.mesh();
    assert_eq!(m.vertices.len(), 41 * 41);
    assert_eq!(m.indices.len(), 40 * 40 * 6);
    for v in &m.vertices {
        assert!((v.position[1] - g.height(v.position[0], v.position[2])).abs() < 1e-5);
        assert!(Vec3::from(v.normal).y > 0.5);
    }
    // Counter-clockwise seen from above: every triangle's normal points up.
    for t in m.indices.chunks(3) {
        let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(m.vertices[t[k] as usize].position));
        assert!((b - a).cross(c - a).y > 0.0);
    }
}

#[test]
fn obstacles_and_colonization_work_on_a_terrain() {
    // A wall beside a tree on the hills shades it: it grows less than without the wall.
    let grow = |wall: bool| {
        let mut w = World::new(&options()).unwrap();
        w.set_ground(hills()).unwrap();
        if wall {
            let y = w.ground_height(2.0, 0.0);
            w.add_obstacle(arbor::models::growth::Obstacle::Box {
                min: [1.0, y, -6.0],
                max: [2.0, y + 12.0, 6.0],
            })
            .unwrap();
        }
        w.plant_on_ground(&GrowthParams::preset(Species::Decurrent), [0.0, 0.0], 0, 1)
            .unwrap();
        w.step(14).unwrap();
        w.tree(0)
            .unwrap()
            .branches()
            .iter()
            .filter(|b| b.end[0] > 1.0)
            .count()
    };
    let (open, walled) = (grow(false), grow(true));
    assert!(
        walled < open,
        "beside the wall {walled}, in the open {open}"
    );
    // Space colonization: the markers under the ground are gone and a bud under it
    // perceives none. A drooping tree (tropism -0.3) on a raised flat ground (y = 4) dips
    // under it only as its shoots bend (less than two internodes); the same tree at y = 4
    // without the ground grows metres down to the markers below.
    let lowest = |ground: bool| {
        let mut w = World::new(
            &options()
                .environment(arbor::models::growth::Environment::SpaceColonization)
                .min([-6.0, 0.0, -6.0])
                .max([6.0, 12.0, 6.0]),
        )
        .unwrap();
        if ground {
            let flat = HeightField::from_fn(13, 13, 1.0, [-6.0, -6.0], |_, _| 4.0).unwrap();
            w.set_ground(flat).unwrap();
        }
        let mut p = GrowthParams::preset(Species::Decurrent);
        p.tropism = -0.3;
        w.plant(&p, [0.0, 4.0, 0.0], 1).unwrap();
        w.step(12).unwrap();
        let s = w.tree(0).unwrap();
        assert!(s.len() > 20, "{} branches", s.len());
        s.branches()
            .iter()
            .map(|b| b.end[1])
            .fold(f32::INFINITY, f32::min)
    };
    let (bare, grounded) = (lowest(false), lowest(true));
    println!("lowest end: {bare} without the ground, {grounded} on it");
    assert!(bare < 3.5, "without the ground the lowest end is at {bare}");
    assert!(
        grounded > 3.5,
        "on the ground the lowest end is at {grounded}"
    );
}
