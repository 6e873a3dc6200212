//! Criterion benchmarks, one group per pipeline stage.

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh;
use arbor::models::honda;
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
        let options = mesh::MeshOptions::default()
            .radial_segments(8)
            .topology(topology);
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

fn grammar(name: &str) -> LSystem {
    let path = format!("{}/examples/grammars/{name}.l", env!("CARGO_MANIFEST_DIR"));
    LSystem::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// (label, grammar, steps): ABOP Fig. 1.24a at n = 7 and 8 (bracketed, no parameters) and
/// the 1996 tree g at n = 18 (parametric, about 3 million modules).
fn derivation_cases() -> Vec<(&'static str, LSystem, u32)> {
    vec![
        ("fig_1_24a_n7", grammar("abop_1_24a"), 7),
        ("fig_1_24a_n8", grammar("abop_1_24a"), 8),
        ("honda_g_n18", grammar("honda_g"), 18),
    ]
}

fn bench_parse(c: &mut Criterion) {
    let mut group = c.benchmark_group("parse");
    for name in ["honda_g", "context_1_31a", "parametric_tropism"] {
        let path = format!("{}/examples/grammars/{name}.l", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(path).unwrap();
        group.throughput(Throughput::Bytes(text.len() as u64));
        group.bench_with_input(BenchmarkId::from_parameter(name), &text, |b, t| {
            b.iter(|| LSystem::parse(black_box(t)).unwrap())
        });
    }
    group.finish();
}

fn bench_derive(c: &mut Criterion) {
    let mut group = c.benchmark_group("derive");
    group.sample_size(10);
    for (label, ls, steps) in derivation_cases() {
        let options = LsystemOptions::default().steps(Some(steps));
        let n = ls.derive(&options).unwrap().len();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(label), |b| {
            b.iter(|| ls.derive(black_box(&options)).unwrap())
        });
    }
    group.finish();
}

fn bench_interpret(c: &mut Criterion) {
    let mut group = c.benchmark_group("interpret");
    group.sample_size(10);
    for (label, ls, steps) in derivation_cases() {
        let options = LsystemOptions::default().steps(Some(steps));
        let string = ls.derive(&options).unwrap();
        group.throughput(Throughput::Elements(string.len() as u64));
        group.bench_function(BenchmarkId::from_parameter(label), |b| {
            b.iter(|| ls.interpret(black_box(&string), &options).unwrap())
        });
    }
    group.finish();
}

/// Mesh writing for a tree of 1,048,575 internodes (the 1996 tree a, n = 20), 8 sides,
/// beside a plain memory fill of the same bytes.
fn bench_mesh_large(c: &mut Criterion) {
    let mut params = honda::HondaParams::preset('a').unwrap();
    params.steps = 20;
    let skeleton = honda::build(&params).unwrap();
    let mut group = c.benchmark_group("mesh_write_1m");
    group.sample_size(10);
    for topology in [
        mesh::Topology::TriangleList,
        mesh::Topology::TriangleStripRestart,
    ] {
        let options = mesh::MeshOptions::default().topology(topology);
        let size = mesh::mesh_size(&skeleton, &options).unwrap();
        let bytes = size.vertices * std::mem::size_of::<mesh::Vertex>() + size.indices * 4;
        let mut vertices = vec![mesh::Vertex::default(); size.vertices];
        let mut indices = vec![0u32; size.indices];
        group.throughput(Throughput::Bytes(bytes as u64));
        group.bench_function(BenchmarkId::new("arbor", format!("{topology:?}")), |b| {
            b.iter(|| {
                mesh::write_mesh(black_box(&skeleton), &options, &mut vertices, &mut indices)
                    .unwrap()
            })
        });
        group.bench_function(BenchmarkId::new("fill", format!("{topology:?}")), |b| {
            b.iter(|| {
                vertices.fill(black_box(mesh::Vertex::default()));
                indices.fill(black_box(1));
            })
        });
    }
    group.finish();
}

/// Leaves of tree g with n = 14 (2 per tip): instances and the baked quad mesh.
fn bench_leaves(c: &mut Criterion) {
    let mut params = honda::HondaParams::preset('g').unwrap();
    params.steps = 14;
    let skeleton = honda::build(&params).unwrap();
    let leaves = mesh::LeafOptions::default().tips(true).density(2.0);
    let options = mesh::MeshOptions::default();
    let n = mesh::leaf_instances(&skeleton, &leaves, &options)
        .unwrap()
        .len();
    let mut group = c.benchmark_group("leaves");
    group.throughput(Throughput::Elements(n as u64));
    group.bench_function("instances", |b| {
        b.iter(|| mesh::leaf_instances(black_box(&skeleton), &leaves, &options).unwrap())
    });
    group.bench_function("baked_quads", |b| {
        b.iter(|| mesh::leaf_mesh(black_box(&skeleton), &leaves, &options).unwrap())
    });
    group.finish();
}

/// OBJ text for tree f (5,027 branches, 8 sides), written to memory.
fn bench_obj(c: &mut Criterion) {
    let skeleton = honda::build(&honda::HondaParams::preset('f').unwrap()).unwrap();
    let m = mesh::tubes(&skeleton, &mesh::MeshOptions::default()).unwrap();
    let mut out = Vec::new();
    arbor::export::write_obj(&m, &mut out).unwrap();
    let mut group = c.benchmark_group("obj_export");
    group.throughput(Throughput::Bytes(out.len() as u64));
    group.bench_function("tree_f", |b| {
        b.iter(|| {
            out.clear();
            arbor::export::write_obj(black_box(&m), &mut out).unwrap();
        })
    });
    group.finish();
}

/// The whole path: grammar text to vertex and index buffers (tree g, n = 14).
fn bench_whole_path(c: &mut Criterion) {
    let path = format!("{}/examples/grammars/honda_g.l", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let options = LsystemOptions::default().steps(Some(14));
    let mesh_options = mesh::MeshOptions::default();
    let probe = LSystem::parse(&text).unwrap().skeleton(&options).unwrap();
    let mut group = c.benchmark_group("text_to_buffers");
    group.sample_size(20);
    group.throughput(Throughput::Elements(probe.len() as u64));
    group.bench_function("honda_g_n14", |b| {
        b.iter(|| {
            let ls = LSystem::parse(black_box(&text)).unwrap();
            let skeleton = ls.skeleton(&options).unwrap();
            mesh::tubes(&skeleton, &mesh_options).unwrap()
        })
    });
    group.finish();
}

/// A forest of 36 trees (the nine presets four times, n + 2 steps): one after another,
/// and at once (on all cores with `--features parallel`).
fn bench_forest(c: &mut Criterion) {
    let items: Vec<arbor::forest::Item<'_>> = (0..36u64)
        .map(|k| {
            let mut p = honda::HondaParams::preset((b'a' + (k % 9) as u8) as char).unwrap();
            p.steps += 2;
            arbor::forest::Item {
                source: arbor::forest::Source::Honda(p),
                seed: k,
            }
        })
        .collect();
    let options = mesh::MeshOptions::default();
    let mut group = c.benchmark_group("forest");
    group.sample_size(10);
    group.throughput(Throughput::Elements(items.len() as u64));
    group.bench_function("serial", |b| {
        b.iter(|| arbor::forest::build_serial(black_box(&items), &options).unwrap())
    });
    let label = if cfg!(feature = "parallel") {
        "parallel"
    } else {
        "build_without_parallel_feature"
    };
    group.bench_function(label, |b| {
        b.iter(|| arbor::forest::build(black_box(&items), &options).unwrap())
    });
    group.finish();
}

criterion_group!(
    benches,
    bench_forest,
    bench_leaves,
    bench_obj,
    bench_whole_path,
    bench_mesh_large,
    bench_honda,
    bench_mesh,
    bench_parse,
    bench_derive,
    bench_interpret
);
criterion_main!(benches);
