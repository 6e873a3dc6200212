use super::*;

/// The shadow obstacles add, from summed-area tables, equals adding each opaque cell's
/// pyramid and column one by one (the definition), for shapes clipped by the grid's
/// sides and floor, overlapping, on a small grid; cancelling leaves the grid as it was.
#[test]
fn obstacle_shadow_is_each_opaque_cells_pyramid_and_column() {
    let options = WorldOptions {
        min: [-3.0, 0.0, -2.5],
        max: [3.0, 4.0, 2.5],
        cell_size: 0.25,
        ..WorldOptions::default()
    };
    let shapes = [
        Obstacle::Sphere {
            center: [0.3, 2.0, -0.2],
            radius: 0.9,
        },
        Obstacle::Box {
            min: [-4.0, 1.0, 1.5],
            max: [-1.8, 1.6, 4.0],
        },
        Obstacle::Sphere {
            center: [2.8, 0.3, 2.4],
            radius: 0.7,
        },
        Obstacle::Box {
            min: [-1.0, 3.1, -1.0],
            max: [1.0, 3.9, 1.0],
        },
    ];
    let mut fast = Env::new(&options).unwrap();
    let mut slow = Env::new(&options).unwrap();
    let [nx, _, nz] = slow.dims;
    for o in &shapes {
        fast.add_obstacle(o, &mut crate::progress::Run::new(None))
            .unwrap();
        let (lo, hi) = o.bounds();
        let (lo, hi) = (slow.cell_of(lo), slow.cell_of(hi));
        let (dims, falloff, full) = (slow.dims, slow.falloff.clone(), slow.full_light);
        let mut opaque = 0;
        for y in lo[1]..=hi[1] {
            for z in lo[2]..=hi[2] {
                for x in lo[0]..=hi[0] {
                    let c =
                        slow.origin + (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * slow.cell;
                    if !o.contains(c) {
                        continue;
                    }
                    opaque += 1;
                    let mut layers: Vec<&mut [f32]> = slow.shadow.chunks_mut(nx * nz).collect();
                    let cell = ((y * nz + z) * nx + x) as u32;
                    apply_changes(&[(cell, 1.0)], dims, &falloff, &mut layers, 0);
                    for layer in &mut layers[..y] {
                        layer[z * nx + x] += full;
                    }
                }
            }
        }
        assert!(opaque > 4, "{o:?} covers {opaque} cell centers");
    }
    let mut worst = 0.0f32;
    for (a, b) in fast.shadow.iter().zip(&slow.shadow) {
        worst = worst.max((a - b).abs() / b.abs().max(1.0));
    }
    assert!(worst < 1e-5, "largest relative difference {worst}");
    assert!(slow.shadow.iter().filter(|&&v| v > 0.0).count() > 1000);

    // Buds inside an obstacle are dark; beside it they are not.
    assert!(fast.cell_word(Vec3::new(0.3, 2.0, -0.2)) & DARK != 0);
    assert!(fast.cell_word(Vec3::new(-2.0, 1.3, 2.0)) & DARK != 0);
    assert!(fast.cell_word(Vec3::new(0.3, 3.0, -2.0)) & DARK == 0);

    // A callback that stops at its second report: cancelled, nothing changed.
    let before = fast.shadow.clone();
    let mut calls = 0;
    let mut stop = |_: crate::progress::Stage, _: f32| {
        calls += 1;
        calls < 2
    };
    let big = Obstacle::Box {
        min: [-3.0, 0.0, -2.5],
        max: [3.0, 4.0, 2.5],
    };
    let r = fast.add_obstacle(&big, &mut crate::progress::Run::new(Some(&mut stop)));
    assert!(matches!(r, Err(Error::Cancelled { .. })), "{r:?}");
    assert!(
        fast.shadow == before,
        "a cancelled obstacle changed the shadow"
    );
    assert_eq!(fast.obstacles.len(), shapes.len());
    assert!(fast.cell_word(Vec3::new(0.3, 3.0, -2.0)) & DARK == 0);
}

/// A world holds at most MAX_OBSTACLES; the next is refused by name.
#[test]
fn obstacles_are_counted() {
    let options = WorldOptions {
        min: [0.0, 0.0, 0.0],
        max: [1.0, 1.0, 1.0],
        cell_size: 1.0,
        ..WorldOptions::default()
    };
    let mut env = Env::new(&options).unwrap();
    let o = Obstacle::Sphere {
        center: [0.5, 0.5, 0.5],
        radius: 0.1,
    };
    let mut none = crate::progress::Run::new(None);
    for _ in 0..MAX_OBSTACLES {
        env.add_obstacle(&o, &mut none).unwrap();
    }
    let e = env.add_obstacle(&o, &mut none).unwrap_err();
    assert!(e.to_string().contains("MAX_OBSTACLES"), "{e}");
}

/// The radix sort orders by cell and keeps each cell's changes in the order made, on
/// one thread and (with the feature) on two, for grids needing one to three passes.
#[test]
fn shadow_changes_sort_stably_by_cell() {
    let mut rng = crate::rng::Rng::new(7);
    for (cells, len) in [
        (100usize, 300usize),
        (5_000, 40_000),
        (4_608_000, 70_000),
        (1 << 31, 50_000),
    ] {
        let changes: Vec<(u32, f32)> = (0..len)
            .map(|k| ((rng.next_u64() % cells as u64) as u32, k as f32))
            .collect();
        let mut expected = changes.clone();
        expected.sort_by_key(|&(c, _)| c);
        for parallel in [false, true] {
            // As a flush gathers them: from several places, in order.
            let (head, tail) = changes.split_at(len / 3);
            let (mut got, mut scratch) = (vec![(9, 9.0); 5], vec![(7, 7.0); len + 9]);
            sort_changes(&[head, &[], tail], &mut got, &mut scratch, cells, parallel);
            let same = got
                .iter()
                .zip(&expected)
                .all(|(a, b)| a.0 == b.0 && a.1.to_bits() == b.1.to_bits());
            assert!(
                same && got.len() == len,
                "{cells} cells, {len} changes, parallel {parallel}"
            );
        }
    }
}
