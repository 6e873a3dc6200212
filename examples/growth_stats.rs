//! Grows each preset alone (and the 100-tree forest) and prints what the growth tests
//! check, cycle by cycle: internodes, the largest one-cycle fall, height and crown widths.
//!
//! `cargo run --release --example growth_stats -- [CYCLES] [SPECIES]`

use arbor::models::growth::{GrowthParams, Species, World, WorldOptions};

#[path = "../tests/common/forest.rs"]
mod forest;

fn main() -> Result<(), arbor::Error> {
    let args: Vec<String> = std::env::args().collect();
    let cycles: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(80);
    let only = args.get(2).cloned();
    if only.as_deref() == Some("forest") {
        return forest(cycles);
    }
    for species in Species::ALL {
        if only.as_deref().is_some_and(|o| o != species.name()) {
            continue;
        }
        let mut world = World::new(&WorldOptions::default())?;
        let mut p = GrowthParams::preset(species);
        tune(&mut p);
        world.plant(&p, [0.0, 0.0, 0.0], 1)?;
        let (mut most, mut worst, mut last) = (0usize, 0.0f64, 0usize);
        let mut line = String::new();
        for c in 1..=cycles {
            if let Err(e) = world.step(1) {
                line += &format!(" stopped at cycle {c}: {e}");
                break;
            }
            let n = world.branch_count();
            if c > 8 && last > 0 {
                worst = worst.max(1.0 - n as f64 / last as f64);
            }
            most = most.max(n);
            last = n;
            if c % 10 == 0 {
                let t = world.tree(0)?;
                let (h, w25, w75) = shape(&t);
                let (down, y) = hang(&t);
                line += &format!(
                    " c{c}:{n} h{h:.1} w{w25:.1}/{w75:.1} down{:.0}%/{y:.2} grid{}MB",
                    down * 100.0,
                    world.grid_bytes() >> 20
                );
            }
        }
        println!(
            "{:10} max {most} end {last} worst-fall {:.0}%{line}",
            species.name(),
            worst * 100.0
        );
    }
    Ok(())
}

/// Height, and the crown's width at 25% and 75% of it: twice the farthest branch end
/// from the trunk's axis within 5% of the height of that level.
fn shape(t: &arbor::skeleton::Skeleton) -> (f32, f32, f32) {
    let h = t.branches().iter().map(|b| b.end[1]).fold(0.0, f32::max);
    let width = |y: f32| {
        let mut r = 0.0f32;
        for b in t.branches() {
            if (b.end[1] - y).abs() <= h * 0.05 {
                r = r.max(b.end[0].hypot(b.end[2]));
            }
        }
        2.0 * r
    };
    (h, width(h * 0.25), width(h * 0.75))
}

/// Of the end internodes of order >= 2: the share pointing below the horizontal and their
/// mean unit direction's y.
fn hang(t: &arbor::skeleton::Skeleton) -> (f32, f32) {
    let b = t.branches();
    let mut has_child = vec![false; b.len()];
    for x in b {
        if x.parent != u32::MAX {
            has_child[x.parent as usize] = true;
        }
    }
    let (mut n, mut down, mut sum) = (0, 0, glam::Vec3::ZERO);
    for (i, x) in b.iter().enumerate() {
        if has_child[i] || x.order < 2 {
            continue;
        }
        let d = (glam::Vec3::from(x.end) - glam::Vec3::from(x.start)).normalize_or_zero();
        n += 1;
        down += usize::from(d.y < 0.0);
        sum += d;
    }
    let n = n.max(1) as f32;
    (down as f32 / n, (sum / n).y)
}

/// `ARBOR_TUNE="field=value,..."` changes preset fields (for trying values).
fn tune(p: &mut GrowthParams) {
    let Ok(spec) = std::env::var("ARBOR_TUNE") else {
        return;
    };
    for kv in spec.split(',').filter(|s| !s.is_empty()) {
        let (k, v) = kv.split_once('=').expect("field=value");
        let f: f32 = v.parse().expect("a number");
        match k {
            "apical_control" => p.apical_control = f,
            "vigor_multiplier" => p.vigor_multiplier = f,
            "young_apical_control" => p.young_apical_control = f,
            "young_vigor_multiplier" => p.young_vigor_multiplier = f,
            "maturity_age" => p.maturity_age = f as u32,
            "max_age" => p.max_age = f as u32,
            "max_height" => p.max_height = f,
            "max_shoot" => p.max_shoot = f as u32,
            "shed_light" => p.shed_light = f,
            "shed_delay" => p.shed_delay = f as u32,
            "droop" => p.droop = f,
            "tropism" => p.tropism = f,
            "branch_angle" => p.branch_angle = f,
            "environment_weight" => p.environment_weight = f,
            _ => panic!("unknown field {k}"),
        }
    }
}

/// The 100-tree benchmark forest (decurrent, 5 apart, seeding from 20 cycles): planted
/// trees alive, their trunks against the tallest, and the seedlings' share.
fn forest(cycles: u32) -> Result<(), arbor::Error> {
    let mut p = GrowthParams::preset(Species::Decurrent);
    p.seed_age = 20;
    tune(&mut p);
    let mut world = forest::forest_world(WorldOptions::default(), &p);
    let t0 = std::time::Instant::now();
    for c in 1..=cycles {
        world.step(1)?;
        if c % 10 != 0 {
            continue;
        }
        let mut heights = Vec::new();
        let (mut planted, mut seeded, mut alive_seedlings) = (0usize, 0usize, 0usize);
        for k in 0..world.tree_count() {
            let t = world.tree(k)?;
            if k < 100 {
                planted += t.len();
                heights.push(t.branches().iter().map(|b| b.end[1]).fold(0.0, f32::max));
            } else {
                seeded += t.len();
                alive_seedlings += usize::from(!t.is_empty());
            }
        }
        let tallest = heights.iter().copied().fold(0.0, f32::max);
        let alive = heights.iter().filter(|&&h| h > 0.0).count();
        let tall = heights.iter().filter(|&&h| h >= tallest * 0.5).count();
        println!(
            "c{c}: trees {} planted alive {alive} (>= half the tallest {tall}), tallest {tallest:.1}; internodes planted {planted} seedlings {seeded} ({:.0}%), seedlings alive {alive_seedlings}; grid {} MB; {:.1} s",
            world.tree_count(),
            100.0 * seeded as f64 / (planted + seeded).max(1) as f64,
            world.grid_bytes() >> 20,
            t0.elapsed().as_secs_f64()
        );
    }
    Ok(())
}
