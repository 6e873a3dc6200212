//! Scale sweep: the 1996 tree a with n = 10, 13, 16, 19, 22 (1,023 to 4,194,303
//! internodes) through every stage. Throughput is in internodes, so criterion's
//! elements/s is the inverse of the cost per internode; flat cost = linear work.
//!
//! `cargo bench --bench scale` (about three minutes); `benches/plot_scale.py` turns
//! criterion's output into `docs/scale.png`.

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh;
use arbor::models::honda;
use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

const STEPS: [u32; 5] = [10, 13, 16, 19, 22];

fn sweep(c: &mut Criterion) {
    let path = format!("{}/examples/grammars/honda_a.l", env!("CARGO_MANIFEST_DIR"));
    let grammar = LSystem::parse(&std::fs::read_to_string(path).unwrap()).unwrap();
    let mesh_options = mesh::MeshOptions::default().radial_segments(6);
    for stage in ["direct_build", "derive", "interpret", "mesh_write"] {
        let mut group = c.benchmark_group(format!("scale_{stage}"));
        group.sample_size(10);
        for steps in STEPS {
            let mut params = honda::HondaParams::preset('a').unwrap();
            params.steps = steps;
            let internodes = (1u64 << steps) - 1;
            let options = LsystemOptions::default()
                .steps(Some(steps))
                .max_modules(usize::MAX)
                .max_params(usize::MAX);
            group.throughput(Throughput::Elements(internodes));
            let id = BenchmarkId::from_parameter(internodes);
            match stage {
                "direct_build" => {
                    group.bench_function(id, |b| {
                        b.iter(|| honda::build(black_box(&params)).unwrap())
                    });
                }
                "derive" => {
                    group.bench_function(id, |b| {
                        b.iter(|| grammar.derive(black_box(&options)).unwrap())
                    });
                }
                "interpret" => {
                    let string = grammar.derive(&options).unwrap();
                    group.bench_function(id, |b| {
                        b.iter(|| grammar.interpret(black_box(&string), &options).unwrap())
                    });
                }
                _ => {
                    let skeleton = honda::build(&params).unwrap();
                    let size = mesh::mesh_size(&skeleton, &mesh_options).unwrap();
                    let mut v = vec![mesh::Vertex::default(); size.vertices];
                    let mut i = vec![0u32; size.indices];
                    group.bench_function(id, |b| {
                        b.iter(|| {
                            mesh::write_mesh(black_box(&skeleton), &mesh_options, &mut v, &mut i)
                                .unwrap()
                        })
                    });
                }
            }
        }
        group.finish();
    }
}

criterion_group!(benches, sweep);
criterion_main!(benches);
