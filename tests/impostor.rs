//! Impostors: the octahedral impostor's picture from directions it was not baked from
//! against the full tree's, and the billboard's quads.

use arbor::impostor::{Sphere, billboard, octahedral};
use arbor::lod::{Frame, LodOptions, chain, silhouette, silhouette_floor, surfaces};
use arbor::mesh::{LeafOptions, MeshOptions};
use arbor::raster::iou;
use arbor::species::Look;
use arbor::texture::Image;
use glam::Vec3;

/// 16 directions around the tree from level to 60 degrees above, none a baked view's.
fn directions() -> Vec<Vec3> {
    (0..16)
        .map(|k| {
            let a = std::f32::consts::TAU * (k as f32 * 0.618_034).fract() + 0.05;
            let e = (k as f32 / 15.0) * 60f32.to_radians();
            Vec3::new(a.cos() * e.cos(), e.sin(), a.sin() * e.cos())
        })
        .collect()
}

/// The impostor of a full level against the full tree from the 16 directions, at
/// `pixels`: the mean and least IoU.
fn check(name: &str, level: &arbor::lod::Level, atlas: Option<&Image>, pixels: u32) -> (f32, f32) {
    let up = level.mesh_options.up();
    let s = surfaces(level, atlas);
    let t = std::time::Instant::now();
    let imp = octahedral(&s, up, 12, 128, Sphere::Hemi).unwrap();
    let baked = t.elapsed();
    let frame = Frame::of(level, up).unwrap();
    assert_eq!(imp.albedo.width, 12 * 128);
    let (mut sum, mut least) = (0.0f32, 1.0f32);
    for d in directions() {
        // The tree seen from d: looking along -d.
        let full = silhouette(level, atlas, &frame, -d, pixels);
        let mine: Vec<bool> = imp.coverage(d, pixels).iter().map(|&a| a >= 0.5).collect();
        let w = iou(&full, &mine);
        sum += w;
        least = least.min(w);
    }
    let mean = sum / 16.0;
    // The measure's own floor there: the tree against itself a quarter pixel off.
    let floor = directions()
        .iter()
        .map(|&d| silhouette_floor(level, atlas, &frame, -d, pixels, 0.25))
        .sum::<f32>()
        / 16.0;
    println!(
        "{name}: impostor (12 x 12 views of 128 px, {} triangles baked in {:.0} ms) against the \
         tree at {pixels} px from 16 other directions: IoU {mean:.3} (least {least:.3}); the \
         tree against itself a quarter pixel off: {floor:.3}",
        level.triangles,
        baked.as_secs_f64() * 1e3
    );
    (mean, least)
}

#[test]
fn the_impostor_is_the_tree_from_directions_it_was_not_baked_from() {
    let lod = LodOptions::default().levels(1);
    let mesh = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    let look = Look::all()
        .into_iter()
        .find(|l| l.species.name() == "maple")
        .unwrap();
    let tree = look.grow(1).unwrap();
    let (o, leaves) = arbor::species::options(&look, &tree, &mesh).unwrap();
    let atlas = arbor::texture::leaf_atlas(&look.leaf, 256, 1)
        .unwrap()
        .image;
    let levels = chain(&tree, &o, Some(&leaves.seed(1)), Some(&atlas), &lod).unwrap();
    let (mean, _) = check("maple", &levels[0], Some(&atlas), 96);
    assert!(mean >= 0.85, "{mean}");
    // The billboard: three quads, each its view's cell.
    let s = surfaces(&levels[0], Some(&atlas));
    let b = billboard(&s, o.up(), 3, 64).unwrap();
    assert_eq!((b.albedo.width, b.albedo.height), (192, 64));
    let m = b.mesh(false);
    assert_eq!(m.indices.len(), 18);
    for v in &m.vertices {
        assert!((Vec3::from(v.position) - Vec3::from(b.centre)).length() <= b.radius * 1.5);
    }
    // Something is drawn in every cell, and the corners are clear.
    for k in 0..3 {
        let covered = (0..64u32)
            .flat_map(|y| (0..64u32).map(move |x| (x, y)))
            .filter(|&(x, y)| b.albedo.pixel(k * 64 + x, y)[3] > 0)
            .count();
        assert!(covered > 200, "cell {k}: {covered}");
        assert_eq!(b.albedo.pixel(k * 64, 0)[3], 0);
    }
    // Bad sizes are refused before anything is drawn.
    assert!(octahedral(&s, o.up(), 0, 128, Sphere::Hemi).is_err());
    assert!(octahedral(&s, o.up(), 32, 1024, Sphere::Hemi).is_err());
    assert!(billboard(&s, o.up(), 5, 64).is_err());
}

/// The figures of BENCHMARKS.md (`cargo test --release --test impostor -- --ignored
/// --nocapture`).
#[test]
#[ignore]
fn figures_for_every_species_and_1996_tree() {
    let lod = LodOptions::default().levels(1);
    for name in ['a', 'b', 'c', 'd', 'e', 'f', 'g', 'h', 'i'] {
        let p = arbor::HondaParams::preset(name).unwrap();
        let s = arbor::models::honda::build(&p).unwrap();
        let leaves = LeafOptions::default().tips(true).density(3.0).size(8.0);
        let levels = chain(&s, &MeshOptions::default(), Some(&leaves), None, &lod).unwrap();
        check(&format!("tree {name}"), &levels[0], None, 96);
    }
    let mesh = arbor::export::gltf_mesh_options(&MeshOptions::default()).unwrap();
    for look in Look::all() {
        let tree = look.grow(1).unwrap();
        let (o, leaves) = arbor::species::options(&look, &tree, &mesh).unwrap();
        let atlas = arbor::texture::leaf_atlas(&look.leaf, 256, 1)
            .unwrap()
            .image;
        let levels = chain(&tree, &o, Some(&leaves.seed(1)), Some(&atlas), &lod).unwrap();
        check(look.species.name(), &levels[0], Some(&atlas), 96);
    }
}

/// Small cubes far from the centre and at different depths: seen from between the baked
/// directions, each of the three cells shows them displaced by a few pixels; followed
/// along the pixel's ray to the depth each cell saw, the three line up where the cubes
/// are (sampled at the same uv they do not: the blend smears and thins them).
#[test]
fn the_views_line_up_between_the_baked_directions() {
    use arbor::mesh::{Mesh, Topology, Vertex};
    use arbor::raster::{Surface, Target};
    let mut mesh = Mesh {
        vertices: Vec::new(),
        indices: Vec::new(),
        topology: Topology::TriangleList,
        ranges: Vec::new(),
    };
    let places = [
        Vec3::new(0.8, 0.0, 0.0),
        Vec3::new(0.0, 0.4, 0.8),
        Vec3::new(-0.6, -0.4, -0.5),
        Vec3::new(0.2, 0.8, -0.5),
        Vec3::new(-0.5, 0.1, 0.6),
    ];
    for &at in &places {
        // Six faces of a cube of side 0.2, wound counter-clockwise seen from outside.
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let n =
                    Vec3::from_array(std::array::from_fn(|k| if k == axis { sign } else { 0.0 }));
                let (a, b) = (
                    n.any_orthonormal_vector(),
                    n.cross(n.any_orthonormal_vector()),
                );
                let base = mesh.vertices.len() as u32;
                for (s, t) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    mesh.vertices.push(Vertex {
                        position: (at + 0.1 * (n + a * s + b * t)).to_array(),
                        normal: n.to_array(),
                        uv: [0.0, 0.0],
                    });
                }
                mesh.indices
                    .extend([0, 1, 2, 0, 2, 3].map(|k: u32| base + k));
            }
        }
    }
    let surfaces = [Surface {
        mesh: &mesh,
        texture: None,
        color: [90, 60, 40],
        alpha_cutoff: 0,
        double_sided: true,
        clockwise: false,
    }];
    let imp = octahedral(&surfaces, Vec3::Y, 12, 128, Sphere::Hemi).unwrap();
    let (centre, radius) = arbor::raster::bounds(&surfaces).unwrap();
    let pixels = 96;
    let (mut sum, mut least) = (0.0f32, 1.0f32);
    for d in directions() {
        // The cubes drawn directly, 4 x 4 samples a pixel, covered where half are. (Sampled at
        // the same uv in the three cells, as the shader did before, the mean was 0.66.)
        let mut t = Target::coverage_only(pixels * 4, pixels * 4);
        t.draw(
            &arbor::impostor::view_from(d, centre, radius, Vec3::Y),
            &surfaces,
        );
        let full = arbor::lod::coverage_mask(&t.mask(), pixels, 4);
        let mine: Vec<bool> = imp.coverage(d, pixels).iter().map(|&a| a >= 0.5).collect();
        let w = iou(&full, &mine);
        sum += w;
        least = least.min(w);
    }
    let mean = sum / 16.0;
    assert!(mean >= 0.85 && least >= 0.75, "mean {mean}, least {least}");
    // An empty texel beside a covered one has the cubes' colour (alpha 0), so a host's
    // bilinear filter does not darken their edges.
    let a = &imp.albedo;
    let mut edges = 0;
    for y in 1..a.height - 1 {
        for x in 1..a.width - 1 {
            let t = a.pixel(x, y);
            let beside = [(x - 1, y), (x + 1, y), (x, y - 1), (x, y + 1)]
                .iter()
                .any(|&(u, v)| a.pixel(u, v)[3] > 0);
            if t[3] == 0
                && beside
                && (x % 128 != 0 && x % 128 != 127)
                && (y % 128 != 0 && y % 128 != 127)
            {
                assert_eq!(&t[..3], &[90, 60, 40], "texel ({x}, {y})");
                edges += 1;
            }
        }
    }
    assert!(edges > 1000, "{edges}");
}

/// An impostor put together by hand whose atlases do not hold its grid (no views, or an
/// atlas too small) draws nothing rather than reading past its pixels.
#[test]
fn a_hand_made_impostor_that_does_not_add_up_draws_nothing() {
    use arbor::impostor::Impostor;
    let image = |side: u32| Image {
        width: side,
        height: side,
        pixels: vec![255; (side * side * 4) as usize],
    };
    for (frames, cell, side) in [(0, 128, 256), (12, 0, 256), (12, 128, 256), (2, 8, 16)] {
        let imp = Impostor {
            frames,
            cell,
            sphere: Sphere::Hemi,
            centre: [0.0; 3],
            radius: 1.0,
            up: [0.0, 1.0, 0.0],
            albedo: image(side),
            normal: image(side),
        };
        let covered = imp.coverage(Vec3::new(0.3, 0.5, 0.8).normalize(), 16);
        assert_eq!(covered.len(), 256);
        // Only the last one, whose atlases hold its 2 x 2 grid, draws (every texel full).
        let drawn = covered.iter().filter(|&&a| a > 0.0).count();
        assert_eq!(
            drawn > 0,
            frames == 2,
            "{frames} x {cell} in {side}: {drawn}"
        );
    }
}
