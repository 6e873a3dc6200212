//! Vertex-cache order beside meshoptimizer's (`meshopt::optimize_vertex_cache`) on the
//! same meshes: prints the average cache misses per triangle (ACMR) through FIFO caches of
//! 16 and 32 entries for trees a, f and g in every topology (strips decoded), and times
//! arbor's mesh against meshoptimizer's reordering of it (the pass arbor's order spares a
//! host). Run as `cargo bench --bench vertex_cache`.

#[path = "../tests/common/vertex_cache.rs"]
mod vertex_cache;

use arbor::mesh::{self, MeshOptions};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use vertex_cache::{acmr, topologies, trees, triangles};

fn table() {
    println!(
        "| tree | topology | arbor ACMR 16 | meshoptimizer 16 | ratio | arbor 32 | meshoptimizer 32 |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (name, s) in trees() {
        for (topology, o) in topologies() {
            let m = mesh::tubes(&s, &o).unwrap();
            let ours = triangles(&m);
            let flat: Vec<u32> = ours.iter().flatten().copied().collect();
            let theirs: Vec<[u32; 3]> = meshopt::optimize_vertex_cache(&flat, m.vertices.len())
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect();
            let (a16, b16) = (acmr(&ours, 16), acmr(&theirs, 16));
            println!(
                "| {name} | {topology:?} | {a16:.3} | {b16:.3} | {:.3} | {:.3} | {:.3} |",
                a16 / b16,
                acmr(&ours, 32),
                acmr(&theirs, 32)
            );
        }
    }
}

fn bench(c: &mut Criterion) {
    table();
    let mut group = c.benchmark_group("vertex_cache");
    for (name, s) in trees() {
        let o = MeshOptions::default();
        group.bench_function(BenchmarkId::new("arbor_mesh", &name), |b| {
            b.iter(|| mesh::tubes(black_box(&s), &o).unwrap())
        });
        let m = mesh::tubes(&s, &o).unwrap();
        group.bench_function(BenchmarkId::new("meshopt_reorder", &name), |b| {
            b.iter(|| meshopt::optimize_vertex_cache(black_box(&m.indices), m.vertices.len()))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
