//! Vertex-cache figures shared by the vertex-cache test and benchmark.

use arbor::mesh::{self, MeshOptions, Topology};
use arbor::models::honda::{self, HondaParams};

/// Average cache misses per triangle (ACMR) of `triangles` through a FIFO post-transform
/// cache of `size` entries, as a GPU's classic vertex cache runs it.
pub fn acmr(triangles: &[[u32; 3]], size: usize) -> f64 {
    let mut fifo = std::collections::VecDeque::with_capacity(size + 1);
    let mut misses = 0usize;
    for &v in triangles.iter().flatten() {
        if !fifo.contains(&v) {
            misses += 1;
            fifo.push_back(v);
            if fifo.len() > size {
                fifo.pop_front();
            }
        }
    }
    misses as f64 / triangles.len().max(1) as f64
}

/// The triangles of a mesh in drawing order (strips decoded, restarts and degenerate
/// joins dropped).
pub fn triangles(m: &mesh::Mesh) -> Vec<[u32; 3]> {
    m.triangles().collect()
}

/// The trees the figures are taken on: (name, skeleton) for trees a, f and g.
pub fn trees() -> Vec<(String, arbor::skeleton::Skeleton)> {
    [('a', 10u32), ('f', 12), ('g', 10)]
        .iter()
        .map(|&(name, steps)| {
            let mut p = HondaParams::preset(name).unwrap();
            p.steps = steps;
            (format!("{name}{steps}"), honda::build(&p).unwrap())
        })
        .collect()
}

/// The topologies the figures cover, with their mesh options.
pub fn topologies() -> [(Topology, MeshOptions); 3] {
    Topology::ALL.map(|t| (t, MeshOptions::default().topology(t)))
}
