//! The studio (`examples/studio/`), driven headless by a script under `xvfb-run` with
//! Mesa's software OpenGL: a height map loaded, two species painted on two halves,
//! planted, grown 30 cycles, one species' apical control changed in the preview, and the
//! world exported. The test checks every root lies on the terrain (as arbor's own height
//! field decodes the same PNG), each half holds its species, the preview's oaks changed
//! while the original did not change at all, and the glTF
//! passes the Khronos validator and holds every tree as a node `SPECIES_k`.

mod common;
use arbor::models::growth::HeightField;
use common::pictures::require_gl_tools;
use common::{lib_dir, require, run};
use std::path::{Path, PathBuf};
use std::process::Command;

#[path = "common/validator.rs"]
mod validator;

fn tmp() -> &'static Path {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
}

/// Builds `examples/studio/studio.cpp` (C++17) against the test build's library.
fn build() -> PathBuf {
    // Once per test binary: two tests building one path at once would run a file another
    // is still writing.
    static BUILT: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    BUILT.get_or_init(build_once).clone()
}

fn build_once() -> PathBuf {
    require_gl_tools();
    require("g++");
    let ok = Command::new("pkg-config")
        .args(["--exists", "imgui"])
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        common::missing("Dear ImGui (libimgui-dev)");
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let exe = tmp().join("studio");
    let flags =
        run(Command::new("pkg-config").args(["--cflags", "--libs", "glfw3", "libpng", "imgui"]));
    run(Command::new("g++")
        .args(["-std=c++17", "-O1", "-Wall", "-Wextra", "-Werror"])
        .arg("-Wno-missing-field-initializers")
        .arg("-I")
        .arg(root.join("include"))
        .arg(root.join("examples/studio/studio.cpp"))
        .arg(lib_dir().join("libarbor.a"))
        .args(flags.split_whitespace())
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&exe));
    exe
}

/// A 64 x 64 grey height map: a ridge along z and a slope, 16 bits.
fn heightmap(path: &Path) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut e = png::Encoder::new(&mut out, 64, 64);
        e.set_color(png::ColorType::Grayscale);
        e.set_depth(png::BitDepth::Sixteen);
        let mut w = e.write_header().unwrap();
        let mut data = Vec::new();
        for y in 0..64 {
            for x in 0..64 {
                let (fx, fy) = (x as f32 / 63.0, y as f32 / 63.0);
                let v = 0.5 + 0.3 * (fx * 6.0).sin() * (fy * 4.0).cos() + 0.15 * fy;
                data.extend_from_slice(&((v.clamp(0.0, 1.0) * 65535.0) as u16).to_be_bytes());
            }
        }
        w.write_image_data(&data).unwrap();
    }
    std::fs::write(path, &out).unwrap();
    out
}

struct Line {
    world: String,
    index: usize,
    species: String,
    root: [f32; 3],
    branches: usize,
    hash: u64,
}

fn stats(path: &Path) -> Vec<Line> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            Line {
                world: f[0].into(),
                index: f[1].parse().unwrap(),
                species: f[2].into(),
                root: [
                    f[4].parse().unwrap(),
                    f[5].parse().unwrap(),
                    f[6].parse().unwrap(),
                ],
                branches: f[7].parse().unwrap(),
                hash: f[8].parse().unwrap(),
            }
        })
        .collect()
}

#[test]
fn a_scripted_session_paints_plants_grows_previews_and_exports() {
    let exe = build();
    let hm = tmp().join("studio_height.png");
    let png = heightmap(&hm);
    let glb = tmp().join("studio_forest.glb");
    let (before, after) = (
        tmp().join("studio_before.txt"),
        tmp().join("studio_after.txt"),
    );
    let shot = tmp().join("studio_shot.png");
    let script = tmp().join("studio_session.txt");
    // The terrain is 126 m a side (cells of 2 m), from -63 to 63.
    std::fs::write(
        &script,
        format!(
            "# two species on two halves\n\
             heightmap {} 8 2\n\
             paint oak -63 -63 -3 63 0.5\n\
             paint pine 3 -63 63 63 0.5\n\
             plant 4\n\
             step 30\n\
             ahead 5\n\
             stats {}\n\
             set oak apical_control 0.9\n\
             stats {}\n\
             pick 0\n\
             export {}\n\
             ui off\n\
             screenshot {}\n",
            hm.display(),
            before.display(),
            after.display(),
            glb.display(),
            shot.display()
        ),
    )
    .unwrap();
    let out = run(Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(&exe)
        .args(["--size", "960x600", "--script"])
        .arg(&script));
    println!("{out}");
    assert!(out.contains("studio: tree 0: "), "{out}");
    let ground = HeightField::from_png(&png, 8.0, 0.0, 2.0, [-63.0, -63.0]).unwrap();
    let (b, a) = (stats(&before), stats(&after));
    let original: Vec<&Line> = b.iter().filter(|l| l.world == "original").collect();
    assert!(original.len() > 40, "{} trees", original.len());
    // Within a tenth of a cell (2 m) of the terrain, as the test decodes it.
    let mut per_species = [0, 0];
    for l in &original {
        if l.branches == 0 {
            continue; // starved
        }
        let h = ground.height(l.root[0], l.root[2]);
        assert!(
            (l.root[1] - h).abs() < 0.2,
            "tree {} at {:?}, ground {h}",
            l.index,
            l.root
        );
        match l.species.as_str() {
            "oak" => {
                assert!(l.root[0] < 0.0, "oak {} at {:?}", l.index, l.root);
                per_species[0] += 1;
            }
            "pine" => {
                assert!(l.root[0] > 0.0, "pine {} at {:?}", l.index, l.root);
                per_species[1] += 1;
            }
            other => panic!("species {other}"),
        }
    }
    assert!(per_species.iter().all(|&n| n > 10), "{per_species:?}");
    // The original is untouched by the change; the preview changed the oaks only.
    let hashes = |lines: &[Line], world: &str, species: &str| -> Vec<u64> {
        lines
            .iter()
            .filter(|l| l.world == world && l.species == species)
            .map(|l| l.hash)
            .collect()
    };
    for s in ["oak", "pine"] {
        assert_eq!(
            hashes(&b, "original", s),
            hashes(&a, "original", s),
            "original {s}"
        );
    }
    // (The preview's pines may change too: they share light with the oaks.)
    let (po, pa) = (hashes(&b, "preview", "oak"), hashes(&a, "preview", "oak"));
    let changed = po.iter().zip(&pa).filter(|(x, y)| x != y).count();
    assert!(
        changed * 2 > po.len(),
        "{changed} of {} oaks changed",
        po.len()
    );
    // The file: valid, a node a tree named by species and number, and the ground.
    validator::assert_valid(std::slice::from_ref(&glb));
    let names: Vec<String> = nodes(&glb).into_iter().map(|n| n.0).collect();
    for l in &original {
        let name = format!("{}_{}", l.species, l.index);
        assert!(names.contains(&name), "{name} missing");
    }
    assert!(names.iter().any(|n| n == "ground"));
    // The screenshot (windows hidden) shows leaves and grass, not only sky: a fifth of it
    // green.
    let img = image_rgb(&shot);
    let green = img
        .chunks(3)
        .filter(|p| p[1] as i32 > p[0] as i32 + 10 && p[1] > p[2])
        .count();
    assert!(
        green * 5 > img.len() / 3,
        "{green} green pixels of {}",
        img.len() / 3
    );
}

/// Each node of a GLB file: its name and its mesh's lowest z (none without a mesh), from
/// the file's JSON chunk.
fn nodes(path: &Path) -> Vec<(String, Option<f32>)> {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..4], b"glTF");
    let n = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + n]).unwrap();
    json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|node| {
            let z = node["mesh"].as_u64().map(|m| {
                let p = json["meshes"][m as usize]["primitives"][0]["attributes"]["POSITION"]
                    .as_u64()
                    .unwrap();
                json["accessors"][p as usize]["min"][2].as_f64().unwrap() as f32
            });
            (node["name"].as_str().unwrap_or("").to_string(), z)
        })
        .collect()
}

/// A PNG's pixels as RGB bytes.
fn image_rgb(path: &Path) -> Vec<u8> {
    let d = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = d.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgb);
    buf
}

#[test]
fn the_one_line_session_takes_a_map_and_its_legend() {
    let exe = build();
    let hm = tmp().join("studio_line_height.png");
    heightmap(&hm);
    // A 16 x 16 map: red (oak) above, blue (birch) below.
    let map = tmp().join("studio_map.png");
    let mut out = Vec::new();
    {
        let mut e = png::Encoder::new(&mut out, 16, 16);
        e.set_color(png::ColorType::Rgb);
        e.set_depth(png::BitDepth::Eight);
        let mut w = e.write_header().unwrap();
        let data: Vec<u8> = (0..16 * 16)
            .flat_map(|k| {
                if k / 16 < 8 {
                    [255u8, 0, 0]
                } else {
                    [0, 0, 255]
                }
            })
            .collect();
        w.write_image_data(&data).unwrap();
    }
    std::fs::write(&map, out).unwrap();
    let glb = tmp().join("studio_line.glb");
    let shot = tmp().join("studio_line.png");
    let text = run(Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(&exe)
        .args(["--size", "800x500", "--heightmap"])
        .arg(&hm)
        .args(["--cell", "2"])
        .arg("--map")
        .arg(&map)
        .args([
            "--legend",
            "ff0000=oak,0000ff=birch",
            "--density",
            "0.5",
            "--steps",
            "12",
        ])
        .arg("--export")
        .arg(&glb)
        .arg("--screenshot")
        .arg(&shot));
    println!("{text}");
    let nodes = nodes(&glb);
    let names: Vec<&String> = nodes.iter().map(|n| &n.0).collect();
    let oaks = names.iter().filter(|n| n.starts_with("oak_")).count();
    let birches = names.iter().filter(|n| n.starts_with("birch_")).count();
    assert!(oaks > 5 && birches > 5, "{oaks} oaks, {birches} birches");
    // Red rows are the image's top, the lowest z: the oaks stand at z < 0.
    for (name, min_z) in &nodes {
        let Some(z) = *min_z else { continue };
        if name.starts_with("oak_") {
            assert!(z < 2.0, "{name} at z {z}");
        }
    }
    assert!(std::fs::metadata(&shot).unwrap().len() > 10_000);
}
