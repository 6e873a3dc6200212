//! Draws a named species at every level of detail and as its octahedral impostor, side by
//! side, with arbor's own rasterizer (albedo lit by its normals from the upper left), into
//! a PNG: the picture of the README.
//!
//! ```text
//! cargo run --release --example levels -- [SPECIES] [OUT.png]
//! ```
//! SPECIES defaults to oak, OUT.png to docs/levels.png.

use arbor::impostor::{Sphere, octahedral};
use arbor::lod::{Frame, LodOptions, chain, surfaces};
use arbor::mesh::MeshOptions;
use arbor::raster::Target;
use arbor::species::Look;
use glam::Vec3;

const PANEL: u32 = 360;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let name = args.next().unwrap_or_else(|| "oak".into());
    let out = args.next().unwrap_or_else(|| "docs/levels.png".into());
    let look = Look::all()
        .into_iter()
        .find(|l| l.species.name() == name)
        .ok_or("unknown species")?;
    let mesh = arbor::export::gltf_mesh_options(&MeshOptions::default())?;
    let tree = look.grow(1)?;
    let (o, leaves) = arbor::species::options(&look, &tree, &mesh)?;
    let atlas = arbor::texture::leaf_atlas(&look.leaf, 256, 1)?.image;
    let levels = chain(
        &tree,
        &o,
        Some(&leaves.seed(1)),
        Some(&atlas),
        &LodOptions::default(),
    )?;
    let frame = Frame::of(&levels[0], o.up()).ok_or("an empty tree")?;
    // Seen from the side and a little above; lit from the upper left.
    let from = Vec3::new(0.9, 0.25, 0.4).normalize();
    let light = Vec3::new(-0.5, 0.8, 0.6).normalize();
    let panels = levels.len() as u32 + 1;
    let mut pixels = vec![255u8; (panels * PANEL * PANEL * 4) as usize];
    let mut put = |k: u32, x: u32, y: u32, c: [u8; 4]| {
        let i = ((y * panels * PANEL + k * PANEL + x) * 4) as usize;
        pixels[i..i + 4].copy_from_slice(&c);
    };
    for (k, level) in levels.iter().enumerate() {
        let mut t = Target::new(PANEL, PANEL);
        t.draw(&frame.view(-from), &surfaces(level, Some(&atlas)));
        for y in 0..PANEL {
            for x in 0..PANEL {
                let i = (y * PANEL + x) as usize;
                if t.depth[i].is_finite() {
                    let n = Vec3::new(
                        t.normal[i][0] as f32,
                        t.normal[i][1] as f32,
                        t.normal[i][2] as f32,
                    ) / 127.5
                        - 1.0;
                    let lit = 0.55 + 0.45 * n.dot(light).max(0.0);
                    let c = t.color[i];
                    let s = |v: u8| (v as f32 * lit).min(255.0) as u8;
                    put(k as u32, x, y, [s(c[0]), s(c[1]), s(c[2]), 255]);
                }
            }
        }
        println!(
            "level {k}: {} triangles, drawn from coverage {:.3}",
            level.triangles,
            if k == 0 {
                1.0
            } else {
                levels[k - 1].screen_coverage
            }
        );
    }
    // The impostor, baked from the level the CLI bakes it from, seen from the same side.
    let source = &levels[arbor::lod::impostor_source(&levels, 128)];
    let small = atlas.downsampled(arbor::lod::SILHOUETTE_ATLAS);
    let imp = octahedral(
        &surfaces(source, Some(&small)),
        o.up(),
        12,
        128,
        Sphere::Hemi,
    )?;
    let picture = imp.picture(from, PANEL);
    for y in 0..PANEL {
        for x in 0..PANEL {
            let c = picture[(y * PANEL + x) as usize];
            if c[3] >= 128 {
                put(levels.len() as u32, x, y, [c[0], c[1], c[2], 255]);
            }
        }
    }
    println!("impostor: 12 x 12 views of 128 px, 2 triangles");
    let image = arbor::texture::Image {
        width: panels * PANEL,
        height: PANEL,
        pixels,
    };
    std::fs::write(&out, image.png()?)?;
    println!("{out}");
    Ok(())
}
