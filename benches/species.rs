//! Named species: the textures as a host draws them into its own memory through the C ABI
//! (`arbor_species_texture_write`, 1024² RGBA8, the buffer prefaulted with a non-zero
//! byte), and an adult oak exported whole as the CLI does it (`arbor export growth:oak`:
//! grow, clear the trunk, mesh bark and leaves at 18 m, draw the 1024² leaf atlas and
//! bark maps, encode the PNGs and the GLB). Throughput of the textures is in pixels.
//!
//! `cargo bench --bench species`

use arbor::ffi::{ArborStatus, ArborTexture, arbor_species_texture_write};
use arbor::mesh::MeshOptions;
use arbor::models::growth::Species;
use arbor::species::{Look, tree_scene};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;

fn bench_species(c: &mut Criterion) {
    let mut group = c.benchmark_group("species");
    group.sample_size(10);
    let size = 1024u32;
    let mut rgba = vec![1u8; (size * size * 4) as usize];
    group.throughput(Throughput::Elements(u64::from(size * size)));
    // The oak's four maps, and the costliest of every species' (the pine's plated bark,
    // cellular noise; the spruce's needle atlas is cheaper than any blade atlas).
    for (name, species, which) in [
        (
            "texture_leaf_atlas_oak_1024",
            Species::Oak,
            ArborTexture::LeafAtlas,
        ),
        (
            "texture_bark_color_oak_1024",
            Species::Oak,
            ArborTexture::BarkColor,
        ),
        (
            "texture_bark_normal_oak_1024",
            Species::Oak,
            ArborTexture::BarkNormal,
        ),
        (
            "texture_bark_roughness_oak_1024",
            Species::Oak,
            ArborTexture::BarkRoughness,
        ),
        (
            "texture_leaf_atlas_birch_1024",
            Species::Birch,
            ArborTexture::LeafAtlas,
        ),
        (
            "texture_bark_color_pine_1024",
            Species::Pine,
            ArborTexture::BarkColor,
        ),
        (
            "texture_bark_normal_pine_1024",
            Species::Pine,
            ArborTexture::BarkNormal,
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| {
                // SAFETY: `rgba` holds `len` writable bytes.
                let s = unsafe {
                    arbor_species_texture_write(
                        species as u32,
                        which as u32,
                        size,
                        1,
                        0,
                        rgba.as_mut_ptr(),
                        rgba.len(),
                    )
                };
                assert_eq!(s, ArborStatus::Ok);
                black_box(rgba[0])
            })
        });
    }
    group.throughput(Throughput::Elements(1));
    let look = Look::of(Species::Oak).unwrap();
    let options = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    group.bench_function("export_oak_glb_textures_1024", |b| {
        b.iter(|| {
            let tree = look.grow(1).unwrap();
            let scene = tree_scene(&look, &tree, &options, size, 1).unwrap();
            black_box(
                arbor::export::gltf_scene_bytes(&scene, &options, true)
                    .unwrap()
                    .len(),
            )
        })
    });
    group.finish();
}

/// The game asset's parts for the oak: the chain of levels fitted to its silhouette, and
/// the octahedral impostor baked from level 2 (12 x 12 views of 128 pixels) on every
/// core, beside the same views of the full tree (the baker's speed in triangles).
fn bench_game(c: &mut Criterion) {
    let mut group = c.benchmark_group("game");
    group.sample_size(10);
    let look = Look::of(Species::Oak).unwrap();
    let options = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    let tree = look.grow(1).unwrap();
    let (o, leaves) = arbor::species::options(&look, &tree, &options).unwrap();
    let atlas = arbor::texture::leaf_atlas(&look.leaf, 256, 1)
        .unwrap()
        .image;
    let lod = arbor::lod::LodOptions::default();
    let leaves = leaves.seed(1);
    group.bench_function("lod_chain_oak", |b| {
        b.iter(|| {
            black_box(
                arbor::lod::chain(&tree, &o, Some(&leaves), Some(&atlas), &lod)
                    .unwrap()
                    .len(),
            )
        })
    });
    let levels = arbor::lod::chain(&tree, &o, Some(&leaves), Some(&atlas), &lod).unwrap();
    for (name, level) in [
        ("impostor_oak_level2", &levels[2]),
        ("impostor_oak_full", &levels[0]),
    ] {
        let surfaces = arbor::lod::surfaces(level, Some(&atlas));
        group.throughput(Throughput::Elements(144 * level.triangles as u64));
        group.bench_function(name, |b| {
            b.iter(|| {
                black_box(
                    arbor::impostor::octahedral(
                        &surfaces,
                        o.up(),
                        12,
                        128,
                        arbor::impostor::Sphere::Hemi,
                    )
                    .unwrap()
                    .frames,
                )
            })
        });
    }
    // The path a host takes: the oak's chain through the C ABI once, then its impostor
    // baked from level 2 and the albedo atlas written into host memory (prefaulted with a
    // non-zero byte) per iteration.
    let mut oak = std::ptr::null_mut();
    let mut lods = std::ptr::null_mut();
    let mut mo = arbor::ffi::ArborMeshOptions::default();
    let mut lo = arbor::ffi::ArborLeafOptions::default();
    // SAFETY: live outputs; the options are this build's defaults.
    unsafe {
        assert_eq!(
            arbor::ffi::arbor_tree_from_species(Species::Oak as u32, 1, &mut oak),
            ArborStatus::Ok
        );
        assert_eq!(
            arbor::ffi::arbor_species_options(Species::Oak as u32, oak, &mut mo, &mut lo),
            ArborStatus::Ok
        );
        assert_eq!(
            arbor::ffi::arbor_tree_lods_create(
                oak,
                &mo,
                &lo,
                atlas.pixels.as_ptr(),
                atlas.width,
                atlas.height,
                std::ptr::null(),
                &mut lods,
            ),
            ArborStatus::Ok
        );
    }
    let mut out = vec![1u8; 12 * 128 * 12 * 128 * 4];
    group.throughput(Throughput::Elements(144));
    group.bench_function("impostor_oak_level2_c_abi", |b| {
        b.iter(|| {
            let mut imp = std::ptr::null_mut();
            let mut size = 0usize;
            // SAFETY: `lods` is live, `out` holds the atlas' bytes.
            unsafe {
                assert_eq!(
                    arbor::ffi::arbor_lods_impostor_create(
                        lods,
                        2,
                        12,
                        128,
                        1,
                        atlas.pixels.as_ptr(),
                        atlas.width,
                        atlas.height,
                        &mut imp,
                    ),
                    ArborStatus::Ok
                );
                assert_eq!(
                    arbor::ffi::arbor_impostor_atlas_write(
                        imp,
                        0,
                        out.as_mut_ptr(),
                        out.len(),
                        &mut size
                    ),
                    ArborStatus::Ok
                );
                arbor::ffi::arbor_impostor_free(imp);
            }
            black_box(size)
        })
    });
    // SAFETY: made above, freed once.
    unsafe {
        arbor::ffi::arbor_lods_free(lods);
        arbor::ffi::arbor_tree_free(oak);
    }
    group.finish();
}

criterion_group!(benches, bench_species, bench_game);
criterion_main!(benches);
