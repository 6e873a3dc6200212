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
    for o in &shapes {
        fast.add_obstacle(o, &mut crate::progress::Run::new(None))
            .unwrap();
    }
    // The grid grew to hold the shadow of the obstacle beyond the box.
    let mut slow = Env::new(&options).unwrap();
    slow.grid = fast.grid.clone();
    slow.grid.cells.iter_mut().for_each(|v| *v = 0);
    let [nx, _, nz] = slow.grid.dims;
    let ground = slow.grid.lo[1];
    let full = (slow.full_light / slow.strength * UNIT).round() as i32;
    for o in &shapes {
        let (lo, hi) = o.bounds();
        let (lo, hi) = (slow.lattice(lo), slow.lattice(hi));
        let (dims, falloff) = (slow.grid.dims, slow.falloff.clone());
        let mut opaque = 0;
        for y in lo[1].max(ground)..=hi[1] {
            for z in lo[2]..=hi[2] {
                for x in lo[0]..=hi[0] {
                    let c = (Vec3::new(x as f32, y as f32, z as f32) + 0.5) * slow.cell;
                    if !o.contains(c) {
                        continue;
                    }
                    opaque += 1;
                    let at = slow.grid.index([x, y, z]).unwrap();
                    let mut layers: Vec<&mut [i32]> = slow.grid.cells.chunks_mut(nx * nz).collect();
                    apply_changes(&[(at as u32, 1)], dims, &falloff, &mut layers, 0);
                    for below in ground..y {
                        let b = slow.grid.index([x, below, z]).unwrap();
                        slow.grid.cells[b] += full;
                    }
                }
            }
        }
        assert!(opaque > 4, "{o:?} covers {opaque} cell centers");
    }
    assert!(fast.grid.cells == slow.grid.cells, "the shadows differ");
    assert!(slow.grid.cells.iter().filter(|&&v| v > 0).count() > 1000);
    // The box obstacle reaching past the box's -x wall grew the grid that way.
    assert!(fast.grid.lo[0] < slow.lattice(Vec3::from(options.min))[0] - 5);

    // Buds inside an obstacle are dark; beside it they are not.
    assert!(fast.cell_word(Vec3::new(0.3, 2.0, -0.2)) & DARK != 0);
    assert!(fast.cell_word(Vec3::new(-2.0, 1.3, 2.0)) & DARK != 0);
    assert!(fast.cell_word(Vec3::new(0.3, 3.0, -2.0)) & DARK == 0);

    // A callback that stops at its second report: cancelled, nothing changed.
    let before = fast.grid.cells.clone();
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
        fast.grid.cells == before,
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
/// one thread and (with the feature) on two, for grids needing one to three passes; asked
/// to merge, it gives what merging the sorted changes gives.
#[test]
fn shadow_changes_sort_stably_by_cell() {
    let mut rng = crate::rng::Rng::new(7);
    for (cells, len) in [
        (100usize, 300usize),
        (5_000, 40_000),
        (4_608_000, 70_000),
        (1 << 31, 50_000),
    ] {
        let changes: Vec<(u64, i32)> = (0..len)
            .map(|k| (rng.next_u64() % cells as u64, k as i32))
            .collect();
        let mut expected = changes.clone();
        expected.sort_by_key(|&(c, _)| c);
        // A third of the cells have no storage index (under the ground): left out.
        let index = |k: u64| (k % 3 != 0).then_some(k as u32);
        expected.retain(|&(c, _)| index(c).is_some());
        let mut merged: Vec<(u32, i32)> = expected.iter().map(|&(c, n)| (c as u32, n)).collect();
        merge_changes(&mut merged);
        // Every grid but the largest (50,000 changes in 2^31 cells) has cells to merge.
        assert!(
            cells == 1 << 31 || merged.len() < expected.len(),
            "{cells} cells: no cell to merge"
        );
        for (parallel, merge) in [(false, false), (true, false), (false, true), (true, true)] {
            // As a flush gathers them: from several places, in order.
            let (head, tail) = changes.split_at(len / 3);
            let (mut got, mut scratch) = (
                vec![(9, 9); 5],
                [
                    vec![(7, 7); len + 9],
                    vec![(8, 8); 3],
                    Vec::new(),
                    vec![(1, 1); 2],
                ],
            );
            sort_changes(
                &[head, &[], tail],
                index,
                &mut got,
                &mut scratch,
                cells,
                parallel,
                merge,
            );
            let want: Vec<(u32, i32)> = if merge {
                merged.clone()
            } else {
                expected.iter().map(|&(c, n)| (c as u32, n)).collect()
            };
            assert!(
                got == want,
                "{cells} cells, {len} changes, parallel {parallel}, merge {merge}"
            );
        }
    }
}

/// The shadow is integer: buds added in one order and taken away in another, over several
/// flushes, leave a grid of exact zeros, and a flat field has no direction at all.
#[test]
fn the_shadow_grid_is_exact_in_any_order() {
    let mut env = Env::new(&WorldOptions::default()).unwrap();
    let mut rng = crate::rng::Rng::new(11);
    let points: Vec<Vec3> = (0..5000)
        .map(|_| {
            Vec3::new(
                rng.next_f64() as f32 * 20.0 - 10.0,
                rng.next_f64() as f32 * 20.0,
                rng.next_f64() as f32 * 20.0 - 10.0,
            )
        })
        .collect();
    let words: Vec<Key> = points.iter().map(|&p| env.cell_word(p)).collect();
    env.cover(points).unwrap();
    for (k, &w) in words.iter().enumerate() {
        env.cast(w, 1 + (k % 3) as i32);
        if k % 777 == 0 {
            env.flush(false);
        }
    }
    env.flush(true);
    assert!(env.grid.cells.iter().any(|&v| v != 0));
    let some = words[17];
    assert!(env.shadow_q(some) < env.full_light);
    for (k, &w) in words.iter().enumerate().rev() {
        env.cast(w, -(1 + (k % 3) as i32));
        if k % 1013 == 0 {
            env.flush(true);
        }
    }
    env.flush(false);
    assert!(
        env.grid.cells.iter().all(|&v| v == 0),
        "the shadow came back exactly"
    );
    assert_eq!(env.shadow_v(some), Vec3::ZERO, "flat: no direction");
    assert_eq!(env.shadow_q(some), env.full_light + env.strength);
}

/// Layer by layer, with difference arrays where they pay, the pyramids land as adding
/// each one cell by cell does (the definition), on grids and change sets of several
/// densities, and for a band of layers starting above the ground.
#[test]
fn layers_get_the_same_shadow_either_way() {
    let mut rng = crate::rng::Rng::new(5);
    for (dims, count) in [([7, 9, 5], 3), ([30, 12, 25], 400), ([64, 20, 48], 20_000)] {
        let [nx, ny, nz] = dims;
        let cells = nx * ny * nz;
        let falloff: Vec<i32> = (0..6).map(|q| 65536 >> q).collect();
        let mut changes: Vec<(u32, i32)> = (0..count)
            .map(|_| {
                let c = (rng.next_u64() % cells as u64) as u32;
                (c, (rng.next_u64() % 5) as i32 - 2)
            })
            .collect();
        changes.sort_by_key(|c| c.0);
        for first in [0, ny / 3] {
            let mut slow = vec![0i32; cells];
            let mut fast = vec![7i32; cells];
            slow.iter_mut().for_each(|v| *v = 7);
            let mut a: Vec<&mut [i32]> = slow.chunks_mut(nx * nz).skip(first).collect();
            apply_changes(&changes, dims, &falloff, &mut a, first);
            let mut merged = changes.clone();
            merge_changes(&mut merged);
            let mut b: Vec<&mut [i32]> = fast.chunks_mut(nx * nz).skip(first).collect();
            let mut diff = Vec::new();
            apply_layers(&merged, dims, &falloff, &mut b, first, &mut diff);
            assert!(
                slow == fast,
                "{dims:?}, {count} changes, from layer {first}"
            );
            assert!(
                diff.iter().all(|&v| v == 0),
                "the difference array is left zero"
            );
        }
    }
}

#[test]
fn divisors_divide_every_index_exactly() {
    use grid::Divisor;
    let mut rng = crate::rng::Rng::new(7);
    let mut divisors: Vec<u32> = vec![1, 2, 3, 7, 33, 43 * 43, 65_535, 65_536, u32::MAX];
    divisors.extend((0..200).map(|_| (rng.next_u64() as u32 >> (rng.next_u64() % 32)).max(1)));
    for d in divisors {
        let div = Divisor::new(d);
        let mut values: Vec<u32> = vec![0, 1, d - 1, d, d.wrapping_add(1), u32::MAX, u32::MAX - 1];
        values.extend((0..2_000).map(|_| rng.next_u64() as u32));
        values.extend((0..200).map(|k| d.wrapping_mul(k).wrapping_sub(k % 2)));
        for a in values {
            assert_eq!(div.div(a), a / d, "{a} / {d}");
            assert_eq!(div.rem(a), a % d, "{a} % {d}");
        }
    }
}

/// Growing the grid keeps every stored cell and column at its lattice coordinates, with
/// zeros where it reaches anew: upward, sideways and both (the rows moved within the
/// store), and, where the room to spare would pass `max_cells`, just over what is asked;
/// past that it is refused, the grid unchanged.
#[test]
fn a_growing_grid_keeps_every_cell_where_it_was() {
    use grid::Grid;
    let mut rng = crate::rng::Rng::new(3);
    let mut g = Grid::empty(0);
    g.cover([0, 0, 0], [4, 3, 6], 1 << 20).unwrap();
    let fill = |g: &mut Grid, rng: &mut crate::rng::Rng| {
        for v in g.cells.iter_mut().chain(g.columns.iter_mut()) {
            *v = rng.next_u64() as i32;
        }
    };
    // The cells and columns as lattice coordinates, with their values.
    let snapshot = |g: &Grid| {
        let [nx, ny, nz] = g.dims;
        let mut cells = Vec::new();
        for y in 0..ny {
            for z in 0..nz {
                for x in 0..nx {
                    let c = [g.lo[0] + x as i64, g.lo[1] + y as i64, g.lo[2] + z as i64];
                    cells.push((c, g.cells[(y * nz + z) * nx + x]));
                }
            }
        }
        let columns: Vec<([i64; 3], i32)> = (0..nz)
            .flat_map(|z| (0..nx).map(move |x| (x, z)))
            .map(|(x, z)| {
                let c = [g.lo[0] + x as i64, 0, g.lo[2] + z as i64];
                (c, g.columns[z * nx + x])
            })
            .collect();
        (cells, columns)
    };
    type Values = Vec<([i64; 3], i32)>;
    let check = |g: &Grid, (cells, columns): &(Values, Values)| {
        let stored: usize = g.dims.iter().product();
        assert_eq!(g.cells.len(), stored);
        assert_eq!(g.columns.len(), g.dims[0] * g.dims[2]);
        for &(c, v) in cells {
            assert_eq!(g.at(c), v, "cell {c:?}");
        }
        for &(c, v) in columns {
            assert_eq!(g.column(c), v, "column {c:?}");
        }
        // Everything else is zero.
        let old: i64 = cells.iter().map(|&(_, v)| v as i64).sum();
        let all: i64 = g.cells.iter().map(|&v| v as i64).sum();
        assert_eq!(old, all);
        let old: i64 = columns.iter().map(|&(_, v)| v as i64).sum();
        let all: i64 = g.columns.iter().map(|&v| v as i64).sum();
        assert_eq!(old, all);
    };
    fill(&mut g, &mut rng);
    // Up only: in place.
    let before = snapshot(&g);
    let (lo, dims) = (g.lo, g.dims);
    g.cover([0, 0, 0], [4, dims[1] as i64 + 5, 6], 1 << 20)
        .unwrap();
    assert_eq!((g.lo, g.dims[0], g.dims[2]), (lo, dims[0], dims[2]));
    assert!(g.dims[1] > dims[1]);
    check(&g, &before);
    // Sideways, toward -x and +z: rows move in the store, zeros around them. The sides
    // more than a spare (16 cells here) from what is asked stay.
    fill(&mut g, &mut rng);
    let before = snapshot(&g);
    let (lo, dims) = (g.lo, g.dims);
    let hi = [0, 2].map(|k| g.lo[k] + g.dims[k] as i64 - 1);
    let mid = [0, 2].map(|k| g.lo[k] + g.dims[k] as i64 / 2);
    assert!(hi[0] - mid[0] > 16 && mid[1] - lo[2] > 16 && dims[1] > 16 + 2);
    g.cover([lo[0] - 3, 0, mid[1]], [mid[0], 1, hi[1] + 1], 1 << 20)
        .unwrap();
    assert!(g.lo[0] < lo[0] - 3 && g.lo[0] + g.dims[0] as i64 - 1 == hi[0]);
    assert!(g.lo[2] == lo[2] && g.lo[2] + g.dims[2] as i64 - 1 > hi[1] + 1);
    assert_eq!(g.dims[1], dims[1]);
    check(&g, &before);
    // A sideways growth takes the sides (and the top) within a spare of what is asked
    // with it: the store is re-laid once, not a side at a time.
    fill(&mut g, &mut rng);
    let before = snapshot(&g);
    let (lo, dims) = (g.lo, g.dims);
    let hi = [0, 1, 2].map(|k| g.lo[k] + g.dims[k] as i64 - 1);
    g.cover(
        [lo[0] - 1, 0, lo[2] + 2],
        [hi[0] - 2, hi[1] - 3, hi[2] - 2],
        1 << 22,
    )
    .unwrap();
    assert!(g.lo[0] < lo[0] - 1 && g.lo[2] < lo[2]);
    assert!(
        (0..3).all(|k| g.lo[k] + g.dims[k] as i64 - 1 > hi[k]),
        "{dims:?} -> {:?}",
        g.dims
    );
    check(&g, &before);
    // Toward +x and -z, with layers above.
    fill(&mut g, &mut rng);
    let before = snapshot(&g);
    let (lo, dims) = (g.lo, g.dims);
    g.cover(
        [lo[0], 0, lo[2] - 1],
        [lo[0] + dims[0] as i64, dims[1] as i64, lo[2]],
        1 << 20,
    )
    .unwrap();
    assert!(g.lo[2] < lo[2] - 1 && g.dims[0] > dims[0] && g.dims[1] > dims[1]);
    check(&g, &before);
    // No room to spare within max_cells: just what is asked.
    fill(&mut g, &mut rng);
    let before = snapshot(&g);
    let (lo, dims) = (g.lo, g.dims);
    let want = [lo[0], 0, lo[2]];
    let top = [
        lo[0] + dims[0] as i64 - 1,
        dims[1] as i64 + 2,
        lo[2] + dims[2] as i64,
    ];
    let exact = dims[0] * (dims[1] + 3) * (dims[2] + 1);
    g.cover(want, top, exact).unwrap();
    assert_eq!(g.cells.len(), exact);
    check(&g, &before);
    // Past max_cells: refused, unchanged.
    let before = snapshot(&g);
    let e = g
        .cover(want, [top[0] + 1, top[1], top[2]], exact)
        .unwrap_err();
    assert!(e.to_string().contains("max_cells"), "{e}");
    assert_eq!(snapshot(&g), before);
}

/// Prefetching is only a hint: at cells inside the grid, on its edges, outside it, far
/// beyond the lattice and dark, it reads nothing a read could not and changes nothing.
#[test]
fn prefetching_any_cell_changes_nothing() {
    let mut env = Env::new(&WorldOptions::default()).unwrap();
    env.cover([Vec3::new(0.0, 3.0, 0.0)]).unwrap();
    env.cast(env.cell_word(Vec3::new(0.0, 3.0, 0.0)), 3);
    env.flush(false);
    let before = env.grid.cells.clone();
    assert!(before.iter().any(|&v| v != 0), "nothing cast");
    let [nx, ny, nz] = env.grid.dims;
    let lo = env.grid.lo;
    let mut words = vec![
        env.cell_word(Vec3::new(0.0, 3.0, 0.0)),
        env.cell_word(Vec3::new(1e9, -1e9, 1e9)),
        key(lo),
        key([lo[0] - 1, lo[1] - 1, lo[2] - 1]),
        key([0, 1, 2].map(|k| lo[k] + [nx, ny, nz][k] as i64)),
        u64::MAX,
        0,
    ];
    words.extend(words.clone().into_iter().map(|w| w | DARK));
    for w in words {
        env.prefetch(w);
        env.prefetch_v(w);
        assert_eq!(env.shadow_q(w), env.shadow_q(w));
    }
    assert_eq!(env.grid.cells, before);
}
