//! Shadow changes sorted by cell (a radix sort) and applied to the grid.

use super::grid::Divisor;

/// Sorts the shadow changes of `sources` (in that order) by storage index (`index` of
/// their cell, below `cells`; those it gives none are left out) into `sorted`, stably
/// (each cell's changes keep the order they were made in), through `scratch`: a
/// least-significant-digit radix sort. With `parallel` (and the `parallel` feature) on two
/// threads: each finds the cells of half of the changes and parts them by the half of the
/// grid they fall in, then each sorts the changes of one half of the grid. With `merge`,
/// each cell's changes are then merged ([`merge_changes`]), each half on its own thread
/// (no cell is in both).
pub(super) fn sort_changes(
    sources: &[&[(u64, i32)]],
    index: impl Fn(u64) -> Option<u32> + Sync,
    sorted: &mut Vec<(u32, i32)>,
    scratch: &mut [Vec<(u32, i32)>; 4],
    cells: usize,
    parallel: bool,
    merge: bool,
) {
    // Sorts `data` through `tmp` (and merges it with `merge`): true when the result ends
    // in `tmp`.
    let sort = |data: &mut Vec<(u32, i32)>, tmp: &mut Vec<(u32, i32)>| {
        // Buffers keep their length from flush to flush: every value is written below.
        tmp.resize(data.len(), (0, 0));
        let in_tmp = if data.len() < 256 {
            data.sort_by_key(|&(c, _)| c);
            false
        } else {
            radix_sort(data, tmp, cells)
        };
        if merge {
            merge_changes(if in_tmp { tmp } else { data });
        }
        in_tmp
    };
    // The changes of `run` with their cells, in order: those below `mid` into `low`, the
    // others into `high`.
    let part =
        |run: &[&[(u64, i32)]], mid: u32, low: &mut Vec<(u32, i32)>, high: &mut Vec<(u32, i32)>| {
            low.clear();
            high.clear();
            for &(k, n) in run.iter().flat_map(|s| s.iter()) {
                if let Some(c) = index(k) {
                    if c < mid {
                        low.push((c, n))
                    } else {
                        high.push((c, n))
                    }
                }
            }
        };
    let [a_low, a_high, b_low, b_high] = scratch;
    let total = sources.iter().map(|s| s.len()).sum::<usize>();
    #[cfg(feature = "parallel")]
    if parallel && total > 1 << 15 {
        let mid = (cells / 2) as u32;
        // The sources cut in two runs of about as many changes.
        let mut first: Vec<&[(u64, i32)]> = Vec::with_capacity(sources.len());
        let mut second = first.clone();
        let mut seen = 0;
        for &s in sources {
            let cut = (total / 2).saturating_sub(seen).min(s.len());
            first.push(&s[..cut]);
            second.push(&s[cut..]);
            seen += s.len();
        }
        rayon::join(
            || part(&first, mid, a_low, a_high),
            || part(&second, mid, b_low, b_high),
        );
        // The first run's changes before the second's: the order they were made in.
        let (low_in_tmp, high_in_tmp) = rayon::join(
            || {
                sorted.clear();
                sorted.extend_from_slice(a_low);
                sorted.extend_from_slice(b_low);
                sort(sorted, a_low)
            },
            || {
                a_high.extend_from_slice(b_high);
                sort(a_high, b_high)
            },
        );
        if low_in_tmp {
            std::mem::swap(sorted, a_low);
        }
        sorted.extend_from_slice(if high_in_tmp { b_high } else { a_high });
        return;
    }
    let _ = (parallel, total, b_low, b_high);
    // Every cell is below u32::MAX (a grid holds at most 2^31 cells): all go to `sorted`.
    part(sources, u32::MAX, sorted, a_high);
    if sort(sorted, a_low) {
        std::mem::swap(sorted, a_low);
    }
}

/// Sorts `data` by cell (below `cells`), stably, ping-ponging with `tmp` (as long): in at
/// most three passes over digits of up to 13 bits. True when the result ends in `tmp`.
pub(super) fn radix_sort(data: &mut [(u32, i32)], tmp: &mut [(u32, i32)], cells: usize) -> bool {
    let bits = usize::BITS - cells.saturating_sub(1).max(1).leading_zeros();
    let passes = bits.div_ceil(13);
    let digit = bits.div_ceil(passes);
    let mask = (1u32 << digit) - 1;
    let mut counts = vec![0u32; (passes as usize) << digit];
    for &(c, _) in data.iter() {
        for p in 0..passes {
            counts[((p as usize) << digit) + ((c >> (p * digit)) & mask) as usize] += 1;
        }
    }
    let (mut from, mut to) = (data, tmp);
    for p in 0..passes {
        let count = &mut counts[(p as usize) << digit..((p as usize) + 1) << digit];
        let mut at = 0u32;
        for c in count.iter_mut() {
            let n = *c;
            *c = at;
            at += n;
        }
        for &change in from.iter() {
            let d = ((change.0 >> (p * digit)) & mask) as usize;
            to[count[d] as usize] = change;
            count[d] += 1;
        }
        std::mem::swap(&mut from, &mut to);
    }
    passes % 2 == 1
}

/// Adds the shadow pyramids of `changes` ((cell, buds), sorted by cell) to `layers`, the
/// grid's layers from `first` on (the parts of pyramids outside them are left out). One
/// cell's changes are summed first (buds added and removed cancel), so each changed
/// cell's pyramid is added once, in cell order.
#[cfg(test)]
pub(super) fn apply_changes(
    changes: &[(u32, i32)],
    [nx, _, nz]: [usize; 3],
    falloff: &[i32],
    layers: &mut [&mut [i32]],
    first: usize,
) {
    let mut merged = changes.to_vec();
    merge_changes(&mut merged);
    for (cell, count) in merged {
        let c = cell as usize;
        let (cx, cy, cz) = (c % nx, c / (nx * nz), (c / nx) % nz);
        for (q, &f) in falloff.iter().enumerate() {
            if q > cy || cy - q < first {
                break;
            }
            if let Some(layer) = layers.get_mut(cy - q - first) {
                let x = (cx.saturating_sub(q), (cx + q).min(nx - 1) + 1);
                let z = (cz.saturating_sub(q), (cz + q).min(nz - 1) + 1);
                add_rect(layer, x, z, nx, f.wrapping_mul(count));
            }
        }
    }
}

/// Adds `add` to a `W` × `W` square of a layer whose rows are `stride` apart, from
/// `start`.
#[inline(always)]
fn add_square<const W: usize>(layer: &mut [i32], start: usize, stride: usize, add: i32) {
    let slab = &mut layer[start..start + (W - 1) * stride + W];
    for r in 0..W {
        if let Some(row) = slab[r * stride..].first_chunk_mut::<W>() {
            for v in row {
                *v = v.wrapping_add(add);
            }
        }
    }
}

/// Sums each cell's run of sorted changes into one (cell, buds) and drops those that
/// cancel, in place.
pub(super) fn merge_changes(changes: &mut Vec<(u32, i32)>) {
    let mut out = 0;
    let mut k = 0;
    while k < changes.len() {
        let cell = changes[k].0;
        let mut count = 0i32;
        while k < changes.len() && changes[k].0 == cell {
            count = count.wrapping_add(changes[k].1);
            k += 1;
        }
        if count != 0 {
            changes[out] = (cell, count);
            out += 1;
        }
    }
    changes.truncate(out);
}

/// Adds the shadow pyramids of merged, sorted `changes` ((cell, buds), one per cell) to
/// `layers`, the grid's layers from `first` on, one target layer at a time: the changes
/// of the q_max + 1 layers above it land in it, each a square of half-width q. Where
/// adding the squares cell by cell costs more than a 2-D difference array (four corners a
/// square, then one running sum over the squares' bounds, in `diff`), the difference
/// array is used; the sums are integers, so both give the same grid.
pub(super) fn apply_layers(
    changes: &[(u32, i32)],
    [nx, ny, nz]: [usize; 3],
    falloff: &[i32],
    layers: &mut [&mut [i32]],
    first: usize,
    diff: &mut Vec<i32>,
) {
    let (layer_cells, row) = (Divisor::new((nx * nz) as u32), Divisor::new(nx as u32));
    // Each change's column (x, z) and buds, found once; where each source layer's
    // changes start, and the columns they span (min x, max x, min z, max z).
    let mut starts = vec![changes.len(); ny + 1];
    let mut span = vec![[u32::MAX, 0, u32::MAX, 0]; ny];
    let mut at: Vec<(u32, u32, i32)> = Vec::with_capacity(changes.len());
    for (k, &(c, n)) in changes.iter().enumerate() {
        let (y, col) = (layer_cells.div(c) as usize, layer_cells.rem(c));
        let (x, z) = (row.rem(col), row.div(col));
        starts[y] = starts[y].min(k);
        let b = &mut span[y];
        *b = [b[0].min(x), b[1].max(x), b[2].min(z), b[3].max(z)];
        at.push((x, z, n));
    }
    for y in (0..ny).rev() {
        starts[y] = starts[y].min(starts[y + 1]);
    }
    // The difference array is left zero after every layer: it is cleared only when the
    // grid's layers changed size.
    let w = nx + 1;
    if diff.len() != w * (nz + 1) {
        diff.clear();
        diff.resize(w * (nz + 1), 0);
    }
    let mut colsum = vec![0i32; nx];
    // A change's square in the layer q below it: the shadow it adds, and its bounds
    // [x0, x1) × [z0, z1) clipped to the grid.
    let square = |q: usize, f: i32, &(cx, cz, count): &(u32, u32, i32)| {
        let (cx, cz) = (cx as usize, cz as usize);
        (
            f.wrapping_mul(count),
            clipped(cx, q, nx),
            clipped(cz, q, nz),
        )
    };
    let (at, starts, span) = (&at[..], &starts[..], &span[..]);
    for (i, layer) in layers.iter_mut().enumerate() {
        let t = first + i;
        // The squares landing in layer t: those of the changes q layers above it.
        let sources = || {
            falloff
                .iter()
                .enumerate()
                .take_while(move |&(q, _)| t + q < ny)
                .map(move |(q, &f)| (q, f, &at[starts[t + q]..starts[t + q + 1]]))
        };
        // Their cost row by row (a square's rows are vector adds), and their bounds: the
        // union of the squares' clipped bounds, from each source layer's span.
        let (mut direct, mut n) = (0usize, 0usize);
        let (mut bx0, mut bx1, mut bz0, mut bz1) = (usize::MAX, 0, usize::MAX, 0);
        for (q, _, here) in sources() {
            if here.is_empty() {
                continue;
            }
            let [x0, x1, z0, z1] = span[t + q].map(|v| v as usize);
            (bx0, bx1) = (bx0.min(x0.saturating_sub(q)), bx1.max((x1 + q).min(nx - 1)));
            (bz0, bz1) = (bz0.min(z0.saturating_sub(q)), bz1.max((z1 + q).min(nz - 1)));
            direct += here.len() * 2 * (2 * q + 1);
            n += here.len();
        }
        if n == 0 {
            continue;
        }
        let area = (bx1 - bx0 + 1) * (bz1 - bz0 + 1);
        if direct <= 4 * n + 3 * area {
            for (q, f, here) in sources() {
                add_source_squares(layer, q, f, here, (nx, nz));
            }
            continue;
        }
        for (v, (x0, x1), (z0, z1)) in
            sources().flat_map(|(q, f, here)| here.iter().map(move |c| square(q, f, c)))
        {
            let d = &mut diff[..];
            d[z0 * w + x0] = d[z0 * w + x0].wrapping_add(v);
            d[z0 * w + x1] = d[z0 * w + x1].wrapping_sub(v);
            d[z1 * w + x0] = d[z1 * w + x0].wrapping_sub(v);
            d[z1 * w + x1] = d[z1 * w + x1].wrapping_add(v);
        }
        // The running sums over the bounds, added to the layer; the array is left zero.
        let cols = &mut colsum[bx0..=bx1];
        cols.iter_mut().for_each(|v| *v = 0);
        for z in bz0..=bz1 {
            let row = &mut diff[z * w + bx0..z * w + bx1 + 2];
            let out = &mut layer[z * nx + bx0..=z * nx + bx1];
            let mut run = 0i32;
            for ((d, col), o) in row.iter_mut().zip(cols.iter_mut()).zip(out.iter_mut()) {
                run = run.wrapping_add(*d);
                *d = 0;
                *col = col.wrapping_add(run);
                *o = o.wrapping_add(*col);
            }
            row[bx1 + 1 - bx0] = 0;
        }
        diff[(bz1 + 1) * w + bx0..=(bz1 + 1) * w + bx1 + 1]
            .iter_mut()
            .for_each(|v| *v = 0);
    }
}

/// Adds the squares of one source layer, `q` layers above the target `layer`
/// (`nx` × `nz`), cell by cell: `f` units a bud over half-width `q`.
fn add_source_squares(
    layer: &mut [i32],
    q: usize,
    f: i32,
    here: &[(u32, u32, i32)],
    (nx, nz): (usize, usize),
) {
    // One width for every square of a source layer, chosen once here rather than a
    // square at a time (an indirect jump, mispredicted as q changes).
    let dims = (nx, nz);
    match q {
        0 => add_squares::<1>(layer, here, f, dims),
        1 => add_squares::<3>(layer, here, f, dims),
        2 => add_squares::<5>(layer, here, f, dims),
        3 => add_squares::<7>(layer, here, f, dims),
        4 => add_squares::<9>(layer, here, f, dims),
        5 => add_squares::<11>(layer, here, f, dims),
        6 => add_squares::<13>(layer, here, f, dims),
        _ => {
            for &(cx, cz, count) in here {
                let (x, z) = (clipped(cx as usize, q, nx), clipped(cz as usize, q, nz));
                add_rect(layer, x, z, nx, f.wrapping_mul(count));
            }
        }
    }
}

/// Adds the squares of width `W` (half-width q = (W - 1) / 2) of `changes` ((x, z,
/// buds), one source layer's) to a target layer `nx` × `nz`, `falloff` units a bud: those
/// inside the layer as `W` × `W` squares, those it clips cell row by cell row.
#[inline(always)]
fn add_squares<const W: usize>(
    layer: &mut [i32],
    changes: &[(u32, u32, i32)],
    falloff: i32,
    (nx, nz): (usize, usize),
) {
    let q = (W - 1) / 2;
    for &(cx, cz, count) in changes {
        let (cx, cz, v) = (cx as usize, cz as usize, falloff.wrapping_mul(count));
        if cx >= q && cz >= q && cx + q < nx && cz + q < nz {
            add_square::<W>(layer, (cz - q) * nx + cx - q, nx, v);
        } else {
            add_rect(layer, clipped(cx, q, nx), clipped(cz, q, nz), nx, v);
        }
    }
}

/// The cells [c - q, c + q] of an axis `n` cells long, clipped to it, as [start, end).
#[inline(always)]
fn clipped(c: usize, q: usize, n: usize) -> (usize, usize) {
    (c.saturating_sub(q), (c + q).min(n - 1) + 1)
}

/// Adds `add` to the cells [x0, x1) × [z0, z1) of a layer `nx` wide.
#[inline]
fn add_rect(
    layer: &mut [i32],
    (x0, x1): (usize, usize),
    (z0, z1): (usize, usize),
    nx: usize,
    add: i32,
) {
    let (w, h) = (x1 - x0, z1 - z0);
    let start = z0 * nx + x0;
    match (w == h).then_some(w) {
        Some(1) => layer[start] = layer[start].wrapping_add(add),
        Some(3) => add_square::<3>(layer, start, nx, add),
        Some(5) => add_square::<5>(layer, start, nx, add),
        Some(7) => add_square::<7>(layer, start, nx, add),
        Some(9) => add_square::<9>(layer, start, nx, add),
        Some(11) => add_square::<11>(layer, start, nx, add),
        Some(13) => add_square::<13>(layer, start, nx, add),
        _ => {
            for r in 0..h {
                let o = start + r * nx;
                for v in &mut layer[o..o + w] {
                    *v = v.wrapping_add(add);
                }
            }
        }
    }
}
