//! Criterion benchmarks, one group per pipeline stage.

use arbor::{honda, mesh};
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

fn bench_honda(c: &mut Criterion) {
    let mut group = c.benchmark_group("honda_build");
    for name in ['a', 'f', 'h'] {
        let params = honda::HondaParams::preset(name).unwrap();
        let n = params.branch_count();
        group.throughput(Throughput::Elements(n));
        group.bench_with_input(BenchmarkId::from_parameter(name), &params, |b, p| {
            b.iter(|| honda::build(black_box(p)).unwrap())
        });
    }
    group.finish();
}

fn bench_mesh(c: &mut Criterion) {
    // Tree f: 5027 branches; tree a with n = 14: 16383 branches.
    let mut big = honda::HondaParams::preset('a').unwrap();
    big.steps = 14;
    let skeleton = honda::build(&big).unwrap();
    let mut group = c.benchmark_group("mesh_write");
    for topology in mesh::Topology::ALL {
        let options = mesh::MeshOptions {
            radial_segments: 8,
            topology,
        };
        let size = mesh::mesh_size(&skeleton, &options).unwrap();
        let bytes = size.vertices * std::mem::size_of::<mesh::Vertex>() + size.indices * 4;
        let mut vertices = vec![mesh::Vertex::default(); size.vertices];
        let mut indices = vec![0u32; size.indices];
        group.throughput(Throughput::Bytes(bytes as u64));
        group.bench_function(BenchmarkId::from_parameter(format!("{topology:?}")), |b| {
            b.iter(|| {
                mesh::write_mesh(black_box(&skeleton), &options, &mut vertices, &mut indices)
                    .unwrap()
            })
        });
        // Baseline: filling the same bytes with a plain memory fill.
        group.bench_function(
            BenchmarkId::new("baseline_fill", format!("{topology:?}")),
            |b| {
                b.iter(|| {
                    vertices.fill(black_box(mesh::Vertex::default()));
                    indices.fill(black_box(1));
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, bench_honda, bench_mesh);
criterion_main!(benches);
