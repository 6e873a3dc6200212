//! The mesher as a host calls it: through the C ABI (`arbor_mesh_size`, then
//! `arbor_mesh_write` into buffers the host owns and has already touched), beside a memset
//! of the same bytes in the same process. No allocator tuning: run it as
//! `cargo bench --bench host`.
//!
//! Trees: the 1996 tree a with n = 20 (1,048,575 branches, 8 sides, triangle list) and tree
//! g with n = 18 (restart strips). The buffers are touched with non-zero bytes before any
//! timing, and memset is the C library's, on the same buffers. Each tree is written as a
//! repeat write (the plan kept from the size call) and as the first write of a freshly
//! grown tree (grown outside the clock), on the default threads and on one: the size and
//! write calls together (`first_write_*`), and the write call alone after the size call
//! (`first_write_call_*`). The ratio memset time / mesh time is the fraction of memset
//! bandwidth a host gets. Memset runs as one call (`c_memset`) and as two calls at once on
//! the two halves (`c_memset_both_cores`): the bandwidth of the cores arbor writes with,
//! where one core alone cannot fill the memory bus.

// The C types ArborHondaParams, ArborTopology and ArborVertex are these Rust types.
use arbor::ffi::{
    ArborMeshOptions, ArborStatus, ArborTree, arbor_honda_preset, arbor_mesh_create,
    arbor_mesh_free, arbor_mesh_options_init, arbor_mesh_size, arbor_mesh_write, arbor_tree_free,
    arbor_tree_from_honda,
};
use arbor::{HondaParams as ArborHondaParams, Topology as ArborTopology, Vertex as ArborVertex};
use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use std::mem::size_of;

struct HostTree {
    tree: *mut ArborTree,
}

impl Drop for HostTree {
    fn drop(&mut self) {
        // SAFETY: `tree` came from arbor_tree_from_honda and is freed once.
        unsafe { arbor_tree_free(self.tree) }
    }
}

fn honda(letter: char, steps: u32) -> HostTree {
    let mut p = std::mem::MaybeUninit::<ArborHondaParams>::uninit();
    // SAFETY: `p` is writable; the preset exists.
    let status = unsafe { arbor_honda_preset(letter as u32, p.as_mut_ptr()) };
    assert_eq!(status, ArborStatus::Ok);
    // SAFETY: written on success.
    let mut p = unsafe { p.assume_init() };
    p.steps = steps;
    let mut tree = std::ptr::null_mut();
    // SAFETY: `p` is readable and `tree` writable.
    let status = unsafe { arbor_tree_from_honda(&p, &mut tree) };
    assert_eq!(status, ArborStatus::Ok);
    HostTree { tree }
}

fn options(topology: u32) -> ArborMeshOptions {
    // As the header's arbor_mesh_options_default() does it.
    let mut o = std::mem::MaybeUninit::<ArborMeshOptions>::zeroed();
    // SAFETY: `o` is writable for its full size.
    unsafe { arbor_mesh_options_init(o.as_mut_ptr(), size_of::<ArborMeshOptions>()) };
    // SAFETY: init wrote every field (over zeroed memory).
    let mut o = unsafe { o.assume_init() };
    o.topology = topology;
    o
}

fn size(tree: &HostTree, o: &ArborMeshOptions) -> (usize, usize) {
    let (mut nv, mut ni) = (0usize, 0usize);
    // SAFETY: the tree is live, the options and counts are valid.
    let status = unsafe { arbor_mesh_size(tree.tree, o, &mut nv, &mut ni) };
    assert_eq!(status, ArborStatus::Ok);
    (nv, ni)
}

/// What a host does each time it (re)uploads: size, then write into its own buffers.
fn size_then_write(tree: &HostTree, o: &ArborMeshOptions, v: &mut [ArborVertex], i: &mut [u32]) {
    let (nv, ni) = size(tree, black_box(o));
    write(tree, o, (nv, ni), v, i);
}

/// The write call alone, of a mesh sized `(nv, ni)`.
fn write(
    tree: &HostTree,
    o: &ArborMeshOptions,
    (nv, ni): (usize, usize),
    v: &mut [ArborVertex],
    i: &mut [u32],
) {
    assert!(nv <= v.len() && ni <= i.len());
    // SAFETY: the buffers hold at least nv vertices and ni indices.
    let status = unsafe { arbor_mesh_write(tree.tree, o, v.as_mut_ptr(), nv, i.as_mut_ptr(), ni) };
    assert_eq!(status, ArborStatus::Ok);
}

/// A buffer a host owns and has touched with non-zero bytes, so every page is faulted in
/// before the clock starts (a zero fill may become `calloc` and touch nothing).
fn touched<T: Copy>(n: usize, value: T) -> Vec<T> {
    vec![value; n]
}

/// memset through the C library over both buffers, as a host's own fill would run.
fn c_memset<T>(v: &mut [T], byte: i32) {
    // SAFETY: the slice is live and writable for its full size in bytes.
    unsafe { libc::memset(v.as_mut_ptr().cast(), byte, std::mem::size_of_val(v)) };
}

/// [`c_memset`] on both cores: each buffer's two halves set by two threads at once (the
/// bandwidth a host gets when it fills with as many threads as arbor writes with).
fn c_memset_both_cores<T: Send>(v: &mut [T], i: &mut [u32], byte: i32) {
    let (v0, v1) = v.split_at_mut(v.len() / 2);
    let (i0, i1) = i.split_at_mut(i.len() / 2);
    std::thread::scope(|s| {
        s.spawn(|| {
            c_memset(v1, byte);
            c_memset(i1, byte);
        });
        c_memset(v0, byte);
        c_memset(i0, byte);
    });
}

fn bench_host(c: &mut Criterion) {
    let mut group = c.benchmark_group("host_mesh");
    group.sample_size(10);
    for (letter, steps, topology, name) in [
        ('a', 20, ArborTopology::TriangleList, "a20_list"),
        ('g', 18, ArborTopology::TriangleStripRestart, "g18_restart"),
    ] {
        let tree = honda(letter, steps);
        let o = options(topology as u32);
        let (nv, ni) = size(&tree, &o);
        // The host's buffers, allocated once and touched (as a mapped GPU buffer would be).
        let one_vertex = ArborVertex {
            position: [1.0; 3],
            normal: [1.0; 3],
            uv: [1.0; 2],
        };
        let mut vertices: Vec<ArborVertex> = touched(nv, one_vertex);
        let mut indices: Vec<u32> = touched(ni, 0x0101_0101);
        let bytes = nv * size_of::<ArborVertex>() + ni * 4;
        group.throughput(Throughput::Bytes(bytes as u64));
        let one = ArborMeshOptions { threads: 1, ..o };
        for (threads, o) in [("default_threads", o), ("1_thread", one)] {
            // A tree written again: the plan the size call made is kept.
            group.bench_function(
                BenchmarkId::new(format!("repeat_write_{threads}"), name),
                |b| b.iter(|| size_then_write(&tree, &o, &mut vertices, &mut indices)),
            );
            // A freshly grown tree's first size and write (the tree is grown outside the
            // clock): the plan is made on the way, as on a host's first call.
            group.bench_function(
                BenchmarkId::new(format!("first_write_{threads}"), name),
                |b| {
                    b.iter_batched(
                        || honda(letter, steps),
                        |fresh| {
                            size_then_write(&fresh, &o, &mut vertices, &mut indices);
                            fresh
                        },
                        BatchSize::PerIteration,
                    )
                },
            );
            // The same, timing the write call alone: the host has sized the fresh tree
            // (outside the clock, and the plan is kept), then maps its buffer and writes.
            group.bench_function(
                BenchmarkId::new(format!("first_write_call_{threads}"), name),
                |b| {
                    b.iter_batched(
                        || {
                            let fresh = honda(letter, steps);
                            let counts = size(&fresh, &o);
                            (fresh, counts)
                        },
                        |(fresh, counts)| {
                            write(&fresh, &o, counts, &mut vertices, &mut indices);
                            fresh
                        },
                        BatchSize::PerIteration,
                    )
                },
            );
        }
        group.bench_function(BenchmarkId::new("c_memset", name), |b| {
            b.iter(|| {
                c_memset(&mut vertices, black_box(0x5a));
                c_memset(&mut indices, black_box(0x5a));
            })
        });
        group.bench_function(BenchmarkId::new("c_memset_both_cores", name), |b| {
            b.iter(|| c_memset_both_cores(&mut vertices, &mut indices, black_box(0x5a)))
        });
    }
    group.finish();
}

/// Bytes a host hands to arbor_mesh_write_bytes: `n` vertices of `stride` bytes, touched,
/// 4-byte aligned.
fn touched_bytes(n: usize, stride: usize) -> Vec<u32> {
    touched(n * stride / 4, 0x3f80_0000)
}

/// Size, then arbor_mesh_write_bytes in the options' vertex format.
fn size_then_write_bytes(tree: &HostTree, o: &ArborMeshOptions, v: &mut [u32], i: &mut [u32]) {
    let (_, ni) = size(tree, black_box(o));
    // SAFETY: `v` holds its length in u32s (4-byte aligned), `i` at least ni indices.
    let status = unsafe {
        arbor::ffi::arbor_mesh_write_bytes(
            tree.tree,
            o,
            v.as_mut_ptr().cast(),
            v.len() * 4,
            i.as_mut_ptr(),
            ni,
        )
    };
    assert_eq!(status, ArborStatus::Ok);
}

/// The compact vertex format (20 bytes) beside the f32 one (32 bytes), both through
/// arbor_mesh_write_bytes into touched buffers, in vertices per second: repeat writes on
/// the default threads and on one.
fn bench_compact(c: &mut Criterion) {
    let mut group = c.benchmark_group("host_compact");
    group.sample_size(10);
    for (letter, steps, topology, name) in [
        ('a', 20, ArborTopology::TriangleList, "a20_list"),
        ('g', 18, ArborTopology::TriangleStripRestart, "g18_restart"),
    ] {
        let tree = honda(letter, steps);
        let o = options(topology as u32);
        let (nv, ni) = size(&tree, &o);
        group.throughput(Throughput::Elements(nv as u64));
        let mut indices: Vec<u32> = touched(ni, 0x0101_0101);
        for (format, stride, label) in [(0u32, 32usize, "f32"), (1, 20, "compact")] {
            let mut vertices = touched_bytes(nv, stride);
            for (threads, count) in [("default_threads", 0u32), ("1_thread", 1)] {
                let o = ArborMeshOptions {
                    vertex_format: format,
                    threads: count,
                    ..o
                };
                group.bench_function(
                    BenchmarkId::new(format!("{label}_repeat_write_{threads}"), name),
                    |b| b.iter(|| size_then_write_bytes(&tree, &o, &mut vertices, &mut indices)),
                );
            }
        }
    }
    group.finish();
}

/// Editing a twig of tree a at n = 18 (262,143 branches) and rewriting only what changed
/// inside the host's buffers, beside writing the whole mesh, both through the C ABI.
fn bench_rewrite(c: &mut Criterion) {
    let mut group = c.benchmark_group("host_rewrite");
    group.sample_size(20);
    let tree = honda('a', 18);
    let o = options(ArborTopology::TriangleList as u32);
    let (nv, ni) = size(&tree, &o);
    // SAFETY: the tree is live.
    let branches = unsafe { arbor::ffi::arbor_tree_branch_count(tree.tree) };
    let mut vertices: Vec<ArborVertex> = vec![ArborVertex::default(); nv];
    let mut indices: Vec<u32> = vec![0; ni];
    size_then_write(&tree, &o, &mut vertices, &mut indices);
    let twig = branches - 1;
    let mut curves = vec![arbor::ffi::ArborCurve::default(); branches];
    // SAFETY: the buffer holds every branch's curve.
    let status =
        unsafe { arbor::ffi::arbor_tree_copy_curves(tree.tree, curves.as_mut_ptr(), branches) };
    assert_eq!(status, ArborStatus::Ok);
    let mut edit = curves[twig];
    let mut flip = 1.0f32;
    group.bench_function("edit_twig_and_rewrite", |b| {
        b.iter(|| {
            flip = -flip;
            edit.p2[0] += 0.01 * flip;
            // SAFETY: the tree is live and only this thread uses it; the buffers hold the
            // complete mesh.
            unsafe {
                assert_eq!(
                    arbor::ffi::arbor_tree_set_curve(tree.tree, twig, &edit),
                    ArborStatus::Ok
                );
                assert_eq!(
                    arbor::ffi::arbor_mesh_rewrite_branch(
                        tree.tree,
                        &o,
                        twig,
                        vertices.as_mut_ptr(),
                        nv,
                        indices.as_mut_ptr(),
                        ni,
                    ),
                    ArborStatus::Ok
                );
            }
        })
    });
    group.bench_function("full_write", |b| {
        b.iter(|| size_then_write(&tree, &o, &mut vertices, &mut indices))
    });
    group.finish();
}

/// An owned mesh through the C ABI (`arbor_mesh_create`, then `arbor_mesh_free`): its
/// buffers are the library's, allocated at their exact size and written once. The first
/// create of a freshly grown tree a (n = 20, grown outside the clock), and repeated creates
/// of smaller trees, whose buffers come from memory the allocator reuses.
fn bench_owned(c: &mut Criterion) {
    let mut group = c.benchmark_group("host_owned");
    group.sample_size(10);
    let create = |tree: &HostTree, o: &ArborMeshOptions| {
        let mut mesh = std::ptr::null_mut();
        // SAFETY: the tree is live, the options readable, `mesh` writable.
        let status = unsafe { arbor_mesh_create(tree.tree, o, &mut mesh) };
        assert_eq!(status, ArborStatus::Ok);
        // SAFETY: `mesh` came from arbor_mesh_create and is freed once.
        unsafe { arbor_mesh_free(black_box(mesh)) };
    };
    let o = options(ArborTopology::TriangleList as u32);
    group.bench_function("first_create_a20", |b| {
        b.iter_batched(
            || honda('a', 20),
            |fresh| {
                create(&fresh, &o);
                fresh
            },
            BatchSize::PerIteration,
        )
    });
    for (letter, steps, name) in [
        ('a', 14, "repeat_create_a14"),
        ('g', 10, "repeat_create_g10"),
    ] {
        let tree = honda(letter, steps);
        group.bench_function(name, |b| b.iter(|| create(&tree, &o)));
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_host,
    bench_rewrite,
    bench_compact,
    bench_owned
);
criterion_main!(benches);
