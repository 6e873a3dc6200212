//! Wavefront OBJ: positions, texture coordinates, normals and triangles.

use crate::error::Result;
use crate::mesh::Mesh;
use std::io::Write;
use std::path::Path;

/// Writes `mesh` as Wavefront OBJ text: one `v`, `vt` and `vn` line per vertex (in that
/// order, so a vertex's three indices are equal) and one `f` line per triangle, whatever
/// the mesh's topology (strips are decoded, degenerate joins skipped). Counter-clockwise
/// winding is kept. The writer is buffered internally; pass an unbuffered `File` freely.
pub fn write_obj<W: Write>(mesh: &Mesh, out: W) -> Result<()> {
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    let triangles = mesh.triangles().count();
    writeln!(
        w,
        "# arbor {}: {} vertices, {} triangles",
        env!("CARGO_PKG_VERSION"),
        mesh.vertices.len(),
        triangles
    )?;
    for v in &mesh.vertices {
        let [x, y, z] = v.position;
        writeln!(w, "v {x} {y} {z}")?;
    }
    for v in &mesh.vertices {
        let [s, t] = v.uv;
        writeln!(w, "vt {s} {t}")?;
    }
    for v in &mesh.vertices {
        let [x, y, z] = v.normal;
        writeln!(w, "vn {x} {y} {z}")?;
    }
    for [a, b, c] in mesh.triangles() {
        let (a, b, c) = (a + 1, b + 1, c + 1);
        writeln!(w, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
    }
    w.flush()?;
    Ok(())
}

/// Writes `mesh` as OBJ to the file at `path`, creating or truncating it.
pub fn save_obj(mesh: &Mesh, path: impl AsRef<Path>) -> Result<()> {
    write_obj(mesh, std::fs::File::create(path)?)
}
