//! Wavefront OBJ: positions, texture coordinates, normals and triangles, one group per part.

use crate::error::{Error, Result};
use crate::mesh::{self, LeafOptions, Mesh, MeshOptions};
use crate::progress::{EVERY, Run, Stage};
use crate::skeleton::Skeleton;
use std::io::Write;
use std::path::Path;

/// Writes `mesh` as Wavefront OBJ text (one part named `arbor`); see [`write_obj_parts`].
pub fn write_obj<W: Write>(mesh: &Mesh, out: W) -> Result<()> {
    write_obj_parts(&[("arbor", mesh)], out)
}

/// Writes several meshes (for example `("bark", &bark)` and `("leaves", &leaves)`) as one
/// OBJ file, each part under its own `g name` line: one `v`, `vt` and `vn` line per vertex
/// (in that order, so a vertex's three indices are equal, counted across parts as OBJ
/// requires) and one `f` line per triangle, whatever the topology (strips are decoded,
/// degenerate joins skipped, winding kept). The writer is buffered internally.
pub fn write_obj_parts<W: Write>(parts: &[(&str, &Mesh)], out: W) -> Result<()> {
    let mut w = std::io::BufWriter::with_capacity(1 << 16, out);
    write_lines(parts, &mut w, &mut Run::default())?;
    w.flush()?;
    Ok(())
}

/// The lines of [`write_obj_parts`], reporting [`Stage::Write`] (lines written) every
/// [`EVERY`] lines.
fn write_lines<W: Write>(parts: &[(&str, &Mesh)], w: &mut W, p: &mut Run<'_>) -> Result<()> {
    let vertices: usize = parts.iter().map(|(_, m)| m.vertices.len()).sum();
    let triangles: usize = parts.iter().map(|(_, m)| m.triangles().count()).sum();
    writeln!(
        w,
        "# arbor {}: {vertices} vertices, {triangles} triangles",
        env!("CARGO_PKG_VERSION"),
    )?;
    let total = (3 * vertices + triangles).max(1) as f64;
    let mut lines = 0usize;
    let mut tick = |p: &mut Run<'_>| {
        lines += 1;
        if lines % EVERY == 0 && p.active() {
            p.report(Stage::Write, lines as f64 / total)
        } else {
            Ok(())
        }
    };
    let mut base = 1u64;
    for (name, mesh) in parts {
        let name: String = name
            .chars()
            .map(|c| if c.is_whitespace() { '_' } else { c })
            .collect();
        writeln!(w, "g {name}")?;
        for v in &mesh.vertices {
            let [x, y, z] = v.position;
            writeln!(w, "v {x} {y} {z}")?;
            tick(p)?;
        }
        for v in &mesh.vertices {
            let [s, t] = v.uv;
            writeln!(w, "vt {s} {t}")?;
            tick(p)?;
        }
        for v in &mesh.vertices {
            let [x, y, z] = v.normal;
            writeln!(w, "vn {x} {y} {z}")?;
            tick(p)?;
        }
        for [a, b, c] in mesh.triangles() {
            let (a, b, c) = (a as u64 + base, b as u64 + base, c as u64 + base);
            writeln!(w, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}")?;
            tick(p)?;
        }
        base += mesh.vertices.len() as u64;
    }
    Ok(())
}

/// Writes `mesh` as OBJ to the file at `path`, whole or not at all (an existing file is
/// replaced only when the new one is complete).
pub fn save_obj(mesh: &Mesh, path: impl AsRef<Path>) -> Result<()> {
    save_obj_parts(&[("arbor", mesh)], path)
}

/// Writes several named meshes as one OBJ file at `path` (see [`write_obj_parts`]), whole
/// or not at all; errors name the path.
pub fn save_obj_parts(parts: &[(&str, &Mesh)], path: impl AsRef<Path>) -> Result<()> {
    save_obj_parts_in(parts, path, &mut Run::default())
}

/// [`save_obj_parts`] in `run`, reporting [`Stage::Write`] (lines written, every 65,536);
/// `false` stops with `Cancelled` and leaves an existing file as it was.
pub fn save_obj_parts_in(
    parts: &[(&str, &Mesh)],
    path: impl AsRef<Path>,
    run: &mut Run<'_>,
) -> Result<()> {
    let path = path.as_ref();
    super::atomic::write_atomic(path, run, |w, p| {
        write_lines(parts, w, p).map_err(|e| match e {
            Error::Io(e) => super::atomic::io(path, "write", e),
            other => other,
        })
    })
}

/// Writes the bark of `skeleton` (group `bark`) and, when `leaves` is given, its baked
/// leaves (group `leaves`) as OBJ to `path`, whole or not at all. OBJ is text: its numbers
/// are f32 whatever `options.vertex_format` asks.
pub fn save_obj_tree(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    path: impl AsRef<Path>,
) -> Result<()> {
    save_obj_tree_in(skeleton, options, leaves, path, &mut Run::default())
}

/// [`save_obj_tree`] in `run`: the bark is meshed on the run's threads, reporting
/// [`Stage::Mesh`], then [`Stage::Write`]; `false` stops with
/// [`Error::Cancelled`](crate::error::Error::Cancelled) and leaves an existing file as it
/// was.
pub fn save_obj_tree_in(
    skeleton: &Skeleton,
    options: &MeshOptions,
    leaves: Option<&LeafOptions>,
    path: impl AsRef<Path>,
    run: &mut Run<'_>,
) -> Result<()> {
    let o = options.vertex_format(mesh::VertexFormat::F32);
    let bark = mesh::MeshPlan::new_in(skeleton, &o, run)?.mesh_in(skeleton, run)?;
    let leaves = match leaves {
        Some(l) => Some(mesh::leaf_mesh(skeleton, l, &o)?),
        None => None,
    };
    let mut parts = vec![("bark", &bark)];
    parts.extend(leaves.as_ref().map(|l| ("leaves", l)));
    save_obj_parts_in(&parts, path, run)
}
