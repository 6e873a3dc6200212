//! Vertex-cache order: how many vertices a GPU's post-transform cache (FIFO, 16 or 32
//! entries) transforms again, on trees a, f and g.

#[path = "common/vertex_cache.rs"]
mod vertex_cache;

use arbor::mesh::{self, MeshOptions, Topology};
use vertex_cache::{acmr, topologies, trees, triangles};

/// A triangle list transforms each vertex once with a cache of 16 entries: along an axis
/// every tube's top ring is still cached when the next tube reads it as its bottom ring.
#[test]
fn lists_make_every_vertex_once_with_a_cache_of_16() {
    for (name, s) in trees() {
        let m = mesh::tubes(&s, &MeshOptions::default()).unwrap();
        let t = triangles(&m);
        let least = m.vertices.len() as f64 / t.len() as f64;
        for size in [16, 32] {
            let got = acmr(&t, size);
            assert!(
                (got - least).abs() < 1e-12,
                "{name}: {got} at {size}, least {least}"
            );
        }
    }
}

/// Decoded strips make at most two vertices again per axis start (a tube with a ring of
/// its own, written as two strips; about one on trees a and g, 1.3 on tree f): a strip
/// cannot order a tube as freely as a list.
#[test]
fn strips_remake_at_most_two_vertices_per_axis_start() {
    for (name, s) in trees() {
        for (topology, o) in topologies() {
            if topology == Topology::TriangleList {
                continue;
            }
            let m = mesh::tubes(&s, &o).unwrap();
            let ring = o.radial_segments + 1;
            let own_rings = mesh::branch_ranges(&s, &o)
                .unwrap()
                .iter()
                .filter(|r| r.vertex_count == 2 * ring)
                .count();
            let t = triangles(&m);
            let misses = (acmr(&t, 16) * t.len() as f64).round() as usize;
            assert!(
                misses <= m.vertices.len() + 2 * own_rings,
                "{name} {topology:?}: {misses} misses for {} vertices, {own_rings} axis starts",
                m.vertices.len()
            );
        }
    }
}

/// Lists are within 3% of meshoptimizer's vertex-cache order on the same mesh, with 16
/// entries and with 32.
#[test]
fn lists_are_on_par_with_meshoptimizer() {
    for (name, s) in trees() {
        let m = mesh::tubes(&s, &MeshOptions::default()).unwrap();
        let ours = triangles(&m);
        let theirs: Vec<[u32; 3]> = meshopt::optimize_vertex_cache(&m.indices, m.vertices.len())
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        for size in [16, 32] {
            let (a, b) = (acmr(&ours, size), acmr(&theirs, size));
            assert!(
                a <= 1.03 * b,
                "{name} at {size}: arbor {a:.3}, meshoptimizer {b:.3}"
            );
        }
    }
}
