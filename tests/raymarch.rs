//! The ray marcher (`examples/raymarch/`): tree bodies drawn from arbor's curve records by
//! sphere tracing agree with arbor's triangle mesh of the same tree, its shadow map darkens
//! the ground, and it draws a grown world. Rendered headless under `xvfb-run` with Mesa's
//! software OpenGL, as the gallery's tests are.

mod common;
use common::pictures::{Image, build, render, render_with_output, require_gl_tools};

/// Intersection over union of two pictures' tree (bark) pixels.
fn silhouette_iou(a: &Image, b: &Image) -> f64 {
    let (mut both, mut either) = (0usize, 0usize);
    for y in 0..a.height {
        for x in 0..a.width {
            let (p, q) = (a.tree(x, y), b.tree(x, y));
            both += (p && q) as usize;
            either += (p || q) as usize;
        }
    }
    both as f64 / either.max(1) as f64
}

/// Whether a pixel shows the ground: grey-green, green a little above red (leaves are far
/// greener, bark is red above green, the sky blue).
fn ground(img: &Image, x: usize, y: usize) -> bool {
    let (r, g, b) = img.pixel(x, y);
    g >= r && (g as f64) < 1.3 * r as f64 && g > b
}

/// Mean luminance of `img` over the pixels of its lower half (where the tree's shadow falls
/// in the view below) that show the ground in `mask`.
fn ground_luminance(img: &Image, mask: &Image) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    for y in img.height / 2..img.height {
        for x in 0..img.width {
            if ground(mask, x, y) {
                let (r, g, b) = img.pixel(x, y);
                sum += 0.2126 * r as f64 + 0.7152 * g as f64 + 0.0722 * b as f64;
                n += 1;
            }
        }
    }
    assert!(n > 1000, "the ground shows in {n} pixels");
    sum / n as f64
}

#[test]
fn ray_marched_and_meshed_trees_agree_and_shadows_fall() {
    require_gl_tools();
    let exe = build("raymarch");
    let bare = [
        "--tree",
        "a",
        "--size",
        "400x400",
        "--no-ground",
        "--no-leaves",
        "--no-shadow",
    ];
    let mut iou = Vec::new();
    for segments in ["16", "8"] {
        let marched = render(
            &exe,
            &format!("rm_a_{segments}"),
            &[&bare[..], &["--segments", segments]].concat(),
        );
        let meshed = render(
            &exe,
            &format!("rm_a_mesh_{segments}"),
            &[&bare[..], &["--segments", segments, "--mesh"]].concat(),
        );
        let tree = marched.share(0, 0, 400, 400);
        assert!(
            tree > 0.02,
            "the ray-marched tree covers {tree:.4} of the picture"
        );
        iou.push(silhouette_iou(&marched, &meshed));
    }
    println!(
        "silhouette overlap, ray-marched against meshed: {:.3} at 16 sides, {:.3} at 8",
        iou[0], iou[1]
    );
    assert!(
        iou[0] >= 0.9,
        "silhouettes overlap by {:.3} at 16 sides",
        iou[0]
    );
    assert!(
        iou[1] > 0.8,
        "silhouettes overlap by {:.3} at 8 sides",
        iou[1]
    );

    // The shadow pass darkens the ground: its mean luminance over the pixels that show the
    // ground in the picture without shadows, seen from the side the shadow falls on.
    let lit = [
        "--tree", "a", "--size", "400x400", "--pitch", "0.8", "--yaw", "3.74",
    ];
    let shadowed = render(&exe, "rm_a_shadow", &lit);
    let unshadowed = render(
        &exe,
        "rm_a_no_shadow",
        &[&lit[..], &["--no-shadow"]].concat(),
    );
    let (with, without) = (
        ground_luminance(&shadowed, &unshadowed),
        ground_luminance(&unshadowed, &unshadowed),
    );
    let fall = 1.0 - with / without;
    println!(
        "ground luminance: {with:.1} with shadows, {without:.1} without ({:.1}% darker)",
        100.0 * fall
    );
    assert!(
        fall >= 0.10,
        "shadows darken the ground by {:.1}% only",
        100.0 * fall
    );
}

#[test]
fn a_grown_world_is_ray_marched_with_its_figures() {
    require_gl_tools();
    let exe = build("raymarch");
    let (img, out) = render_with_output(
        &exe,
        "rm_world",
        &[
            "--world",
            "20",
            "--world-trees",
            "9",
            "--size",
            "400x300",
            "--compare",
            "--frames",
            "2",
        ],
    );
    println!("{out}");
    assert!(img.share(0, 0, 400, 300) > 0.005, "the world's trees show");
    let bytes = out
        .lines()
        .find(|l| l.contains("curve records"))
        .expect("the bytes line");
    assert!(bytes.contains("(80 a branch)"), "{bytes}");
    let frame = out
        .lines()
        .find(|l| l.contains("ray-marched,"))
        .expect("the frame-time line");
    assert!(frame.contains("ms meshed"), "{frame}");
}
