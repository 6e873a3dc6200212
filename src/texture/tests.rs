use super::*;

#[test]
fn sizes_are_checked_before_anything_is_drawn() {
    for size in [0, 15, 4097, u32::MAX] {
        let e = leaf_atlas(&LeafLook::oak(), size, 0).unwrap_err();
        assert!(e.to_string().contains("`size`"), "{e}");
        assert!(bark_textures(&BarkLook::oak(), size, 0).is_err());
    }
}

/// Mean absolute difference of the colour channels between columns (or rows) `a` and `b`.
fn seam(img: &Image, a: u32, b: u32, columns: bool) -> f64 {
    let n = if columns { img.height } else { img.width };
    let mut sum = 0u64;
    for k in 0..n {
        let (p, q) = if columns {
            (img.pixel(a, k), img.pixel(b, k))
        } else {
            (img.pixel(k, a), img.pixel(k, b))
        };
        sum += (0..3)
            .map(|c| (p[c] as i32 - q[c] as i32).unsigned_abs() as u64)
            .sum::<u64>();
    }
    sum as f64 / (3 * n) as f64
}

#[test]
fn bark_tiles_without_a_seam() {
    for look in [
        BarkLook::oak(),
        BarkLook::birch(),
        BarkLook::pine(),
        BarkLook::maple(),
    ] {
        let t = bark_textures(&look, 128, 3).unwrap();
        for img in [&t.color, &t.normal, &t.roughness] {
            for columns in [true, false] {
                // Across the wrap (last to first) no more change than between neighbours
                // inside the tile, on average over the inner pairs.
                let wrap = seam(img, 127, 0, columns);
                let inner = (1..127).map(|k| seam(img, k - 1, k, columns)).sum::<f64>() / 126.0;
                assert!(
                    wrap <= 2.0 * inner + 1.0,
                    "{:?}: wrap {wrap:.2} vs inner {inner:.2}",
                    look.kind
                );
            }
        }
    }
}

#[test]
fn textures_are_the_seeds() {
    let a = bark_textures(&BarkLook::oak(), 64, 1).unwrap();
    assert_eq!(a, bark_textures(&BarkLook::oak(), 64, 1).unwrap());
    assert_ne!(
        a.color,
        bark_textures(&BarkLook::oak(), 64, 2).unwrap().color
    );
    let l = leaf_atlas(&LeafLook::maple(), 64, 1).unwrap();
    assert_eq!(l, leaf_atlas(&LeafLook::maple(), 64, 1).unwrap());
    assert_ne!(
        l.image,
        leaf_atlas(&LeafLook::maple(), 64, 2).unwrap().image
    );
}

#[test]
fn every_atlas_cell_holds_a_blade_with_its_colour_bled_around_it() {
    for look in [
        LeafLook::oak(),
        LeafLook::maple(),
        LeafLook::birch(),
        LeafLook::willow(),
        LeafLook::pine(),
    ] {
        let a = leaf_atlas(&look, 256, 5).unwrap();
        assert_eq!(a.variants(), 8);
        for k in 0..a.variants() {
            let [u0, v0, u1, v1] = a.rect(k);
            let (x0, x1) = ((u0 * 256.0) as u32, (u1 * 256.0) as u32);
            let (y0, y1) = ((v0 * 256.0) as u32, (v1 * 256.0) as u32);
            let (mut inside, mut green, mut total) = (0, 0, 0);
            for y in y0..y1 {
                for x in x0..x1 {
                    let p = a.image.pixel(x, y);
                    total += 1;
                    let is_green = p[1] > p[2] && p[1] >= p[0];
                    if p[3] >= 128 {
                        inside += 1;
                        green += is_green as usize;
                    } else {
                        // Green where transparent (for filtering), even by the twig.
                        assert!(is_green, "{:?} cell {k} pixel {p:?}", look.shape);
                    }
                }
            }
            // The blades are green; the rest is the twig.
            assert!(
                green * 10 >= inside * 7,
                "{:?} cell {k}: {green} of {inside} green",
                look.shape
            );
            let f = inside as f64 / total as f64;
            let lo = if look.shape == LeafShape::Needles {
                0.03
            } else {
                0.12
            };
            assert!(
                (lo..0.8).contains(&f),
                "{:?} cell {k}: {f:.3} of the cell is leaf",
                look.shape
            );
            // The stem's end (the cell's top row, middle) is on the leaf: the petiole.
            let mid = a.image.pixel((x0 + x1) / 2, y0);
            assert!(mid[3] > 0, "{:?} cell {k}: no stem at the top", look.shape);
        }
    }
}

#[test]
fn one_bark_map_is_the_same_as_both() {
    let both = bark_textures(&BarkLook::pine(), 64, 9).unwrap();
    let run = Run::default();
    let color = bark::bark_map(&BarkLook::pine(), 64, 9, BarkMap::Color, &run).unwrap();
    assert_eq!(color, both.color);
    let normal = bark::bark_map(&BarkLook::pine(), 64, 9, BarkMap::Normal, &run).unwrap();
    assert_eq!(normal, both.normal);
    let rough = bark::bark_map(&BarkLook::pine(), 64, 9, BarkMap::Roughness, &run).unwrap();
    assert_eq!(rough, both.roughness);
}

#[test]
fn textures_are_the_same_on_any_threads() {
    // 256² is large enough to be split when the run allows it.
    let (one, three) = (Run::default().threads(1), Run::default().threads(3));
    let a = leaf_atlas_in(&LeafLook::oak(), 256, 4, &one).unwrap();
    assert_eq!(a, leaf_atlas_in(&LeafLook::oak(), 256, 4, &three).unwrap());
    let b = bark_textures_in(&BarkLook::birch(), 256, 4, &one).unwrap();
    assert_eq!(
        b,
        bark_textures_in(&BarkLook::birch(), 256, 4, &three).unwrap()
    );
}

#[test]
fn bark_is_rougher_in_its_furrows_and_birch_smoothest() {
    let mean_green = |img: &Image| {
        img.pixels.chunks_exact(4).map(|p| p[1] as f64).sum::<f64>() / (img.pixels.len() / 4) as f64
    };
    let oak = bark_textures(&BarkLook::oak(), 128, 3).unwrap();
    // glTF's layout: roughness in green, metalness (blue) 0.
    assert!(
        oak.roughness
            .pixels
            .chunks_exact(4)
            .all(|p| p[2] == 0 && p[3] == 255)
    );
    // The darkest tenth of the colour (the furrows) is rougher than the lightest tenth.
    let mut by_tone: Vec<(u32, u8)> = oak
        .color
        .pixels
        .chunks_exact(4)
        .zip(oak.roughness.pixels.chunks_exact(4))
        .map(|(c, r)| (c[0] as u32 + c[1] as u32 + c[2] as u32, r[1]))
        .collect();
    by_tone.sort();
    let tenth = by_tone.len() / 10;
    let mean = |s: &[(u32, u8)]| s.iter().map(|x| x.1 as f64).sum::<f64>() / s.len() as f64;
    let (dark, light) = (
        mean(&by_tone[..tenth]),
        mean(&by_tone[by_tone.len() - tenth..]),
    );
    assert!(dark > light + 10.0, "furrows {dark:.0}, ridges {light:.0}");
    let birch = bark_textures(&BarkLook::birch(), 128, 3).unwrap();
    assert!(mean_green(&birch.roughness) + 30.0 < mean_green(&oak.roughness));
}
