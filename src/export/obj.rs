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
    write_lines_with(parts, w, p, false)
}

/// [`write_lines`], each group with `usemtl` of its name when `materials`.
fn write_lines_with<W: Write>(
    parts: &[(&str, &Mesh)],
    w: &mut W,
    p: &mut Run<'_>,
    materials: bool,
) -> Result<()> {
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
        if materials {
            writeln!(w, "usemtl {name}")?;
        }
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

/// A scene's tree as OBJ with its materials: `path` (the first node's mesh, a group per
/// primitive, each with `usemtl` of its material), `<stem>.mtl` beside it (colour, and
/// `map_Kd`, `map_d` for alpha-cut materials, `map_Bump` for normal maps, `map_Pr` for
/// roughness, written grey), and each texture as `<stem>_<name>.png` (spaces as `_`). OBJ reads uv from the image's bottom row, so
/// the images are written upside down (a normal map's green turned with them) and the
/// uvs stay as arbor writes them. Every file is written whole or not at all; the images
/// and the `.mtl` first, the `.obj` last.
pub fn save_obj_scene(scene: &crate::scene::Scene, path: impl AsRef<Path>) -> Result<()> {
    let path = path.as_ref();
    let stem = path.file_stem().and_then(|s| s.to_str()).ok_or_else(|| {
        Error::invalid("path", format!("{}; expected a file name", path.display()))
    })?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let file_of = |name: &str| format!("{stem}_{}.png", name.replace(char::is_whitespace, "_"));
    let mut run = Run::default();
    for (k, t) in scene.textures.iter().enumerate() {
        let normal = scene.materials.iter().any(|m| m.normal_texture == Some(k));
        let mut image = flipped(&t.image, normal);
        // MTL's roughness map is one channel: glTF's green, grey.
        if scene
            .materials
            .iter()
            .any(|m| m.metallic_roughness_texture == Some(k))
        {
            for px in image.pixels.chunks_exact_mut(4) {
                (px[0], px[2]) = (px[1], px[1]);
            }
        }
        let png = image.png()?;
        let target = dir.join(file_of(&t.name));
        super::atomic::write_atomic(&target, &mut run, |w, _| Ok(w.write_all(&png)?))?;
    }
    let mut mtl = String::new();
    for m in &scene.materials {
        let [r, g, b, a] = m.base_color;
        mtl += &format!(
            "newmtl {}\nKd {r} {g} {b}\nKs 0 0 0\nd {a}\nillum 1\n",
            m.name
        );
        if let Some(k) = m.base_color_texture {
            let png = file_of(&scene.textures[k].name);
            mtl += &format!("map_Kd {png}\n");
            if m.alpha_cutoff.is_some() {
                mtl += &format!("map_d {png}\n");
            }
        }
        if let Some(k) = m.normal_texture {
            mtl += &format!("map_Bump {}\n", file_of(&scene.textures[k].name));
        }
        if let Some(k) = m.metallic_roughness_texture {
            mtl += &format!("map_Pr {}\n", file_of(&scene.textures[k].name));
        }
        mtl += "\n";
    }
    let mtl_name = format!("{stem}.mtl");
    super::atomic::write_atomic(&dir.join(&mtl_name), &mut run, |w, _| {
        Ok(w.write_all(mtl.as_bytes())?)
    })?;
    let prims = scene
        .nodes
        .iter()
        .find_map(|n| n.mesh)
        .map_or(&[][..], |k| &scene.meshes[k].primitives[..]);
    let names: Vec<&str> = prims
        .iter()
        .map(|p| scene.materials[p.material].name.as_str())
        .collect();
    let parts: Vec<(&str, &Mesh)> = names
        .iter()
        .zip(prims)
        .map(|(n, p)| (*n, &p.mesh))
        .collect();
    super::atomic::write_atomic(path, &mut run, |w, p| {
        writeln!(w, "mtllib {mtl_name}")?;
        write_lines_with(&parts, w, p, true).map_err(|e| match e {
            Error::Io(e) => super::atomic::io(path, "write", e),
            other => other,
        })
    })
}

/// `image` upside down (OBJ's uv origin is the bottom row); a normal map's green (up the
/// image) turned with it.
fn flipped(image: &crate::texture::Image, normal: bool) -> crate::texture::Image {
    let row = image.width as usize * 4;
    let mut pixels: Vec<u8> = image
        .pixels
        .chunks_exact(row)
        .rev()
        .flatten()
        .copied()
        .collect();
    if normal {
        for px in pixels.chunks_exact_mut(4) {
            px[1] = 255 - px[1];
        }
    }
    crate::texture::Image {
        width: image.width,
        height: image.height,
        pixels,
    }
}
