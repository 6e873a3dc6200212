//! Progress and cancellation: derivation, interpretation and growth report fractions that
//! never go back, end at 1, and stop with `Error::Cancelled` (building nothing) when the
//! callback says so; a callback that never stops changes nothing.

use arbor::Error;
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::models::growth::{GrowthParams, World, WorldOptions};
use arbor::progress::{Run, Stage};

#[test]
fn derivation_and_interpretation_report_and_stop() {
    // A grammar big enough to report inside steps and inside interpretation.
    let ls = LSystem::parse("derivation length: 9\nAxiom: F\nF --> F[+F]F[-F]F\n").unwrap();
    let options = LsystemOptions::default();
    let mut seen: Vec<(Stage, f32)> = Vec::new();
    let mut record = |stage: Stage, f: f32| {
        seen.push((stage, f));
        true
    };
    let with = ls
        .skeleton_in(&options, &mut Run::reporting(&mut record))
        .unwrap();
    assert_eq!(
        with,
        ls.skeleton(&options).unwrap(),
        "progress changes nothing"
    );
    let derivation: Vec<f32> = seen
        .iter()
        .filter(|s| s.0 == Stage::Derivation)
        .map(|s| s.1)
        .collect();
    let interpretation: Vec<f32> = seen
        .iter()
        .filter(|s| s.0 == Stage::Interpretation)
        .map(|s| s.1)
        .collect();
    // 5^9 F and more: reports within the last steps and within interpretation.
    assert!(
        derivation.len() > 9 + 10,
        "{} derivation reports",
        derivation.len()
    );
    assert!(
        interpretation.len() > 10,
        "{} interpretation reports",
        interpretation.len()
    );
    for v in [&derivation, &interpretation] {
        assert!(
            v.windows(2).all(|w| w[0] <= w[1]),
            "fractions never go back"
        );
        assert_eq!(*v.last().unwrap(), 1.0);
        assert!(v.iter().all(|f| (0.0..=1.0).contains(f)));
    }
    // Stopping at any report stops the work.
    for stop in [1usize, 5, derivation.len() + 3] {
        let mut calls = 0;
        let mut cancel = |_: Stage, _: f32| {
            calls += 1;
            calls < stop
        };
        match ls.skeleton_in(&options, &mut Run::reporting(&mut cancel)) {
            Err(Error::Cancelled { stage }) => {
                let expect = if stop <= derivation.len() {
                    "derivation"
                } else {
                    "interpretation"
                };
                assert_eq!(stage, expect);
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(calls, stop);
    }
}

#[test]
fn growth_reports_every_cycle_and_stops_between_cycles() {
    let make = || {
        let mut w = World::new(&WorldOptions::default()).unwrap();
        w.plant(&GrowthParams::default(), [0.0, 0.0, 0.0], 3)
            .unwrap();
        w
    };
    let mut plain = make();
    plain.step(6).unwrap();
    let mut reported = make();
    let mut fractions = Vec::new();
    let mut record = |stage, f| {
        assert_eq!(stage, Stage::Growth);
        fractions.push(f);
        true
    };
    reported
        .step_in(6, &mut Run::reporting(&mut record))
        .unwrap();
    assert_eq!(fractions.len(), 7);
    assert_eq!(fractions.last(), Some(&1.0));
    assert_eq!(reported.branch_count(), plain.branch_count());
    // Cancelled before the fourth cycle: the world holds three whole cycles.
    let mut three = make();
    three.step(3).unwrap();
    let mut stopped = make();
    let mut calls = 0;
    let mut stop = |_, _| {
        calls += 1;
        calls <= 3
    };
    let r = stopped.step_in(6, &mut Run::reporting(&mut stop));
    assert!(matches!(r, Err(Error::Cancelled { stage: "growth" })));
    assert_eq!(stopped.branch_count(), three.branch_count());
    // A run on one thread grows the same world.
    let mut one = make();
    one.step_in(6, &mut Run::default().threads(1)).unwrap();
    assert_eq!(one.tree(0).unwrap(), plain.tree(0).unwrap());
}

#[test]
fn mesh_writes_report_and_stop() {
    use arbor::mesh::{MeshOptions, MeshPlan, Topology};
    // 5^8 = 390,625 branches: six rounds of 65,536.
    let ls = LSystem::parse("derivation length: 8\nAxiom: F\nF --> F[+F]F[-F]F\n").unwrap();
    let s = ls.skeleton(&LsystemOptions::default()).unwrap();
    assert!(s.len() > 2 * 65_536, "{} branches", s.len());
    for topology in [
        Topology::TriangleList,
        Topology::TriangleStripRestart,
        Topology::TriangleStripDegenerate,
    ] {
        for threads in [1, 2] {
            let o = MeshOptions::default().topology(topology);
            let plan = MeshPlan::new_in(&s, &o, &Run::default().threads(threads)).unwrap();
            let plain = plan
                .mesh_in(&s, &mut Run::default().threads(threads))
                .unwrap();
            let mut seen = Vec::new();
            let mut record = |stage: Stage, f: f32| {
                seen.push((stage, f));
                true
            };
            let with = plan.mesh_in(&s, &mut Run::reporting(&mut record)).unwrap();
            assert!(
                with == plain,
                "{topology:?} on {threads}: progress changes nothing"
            );
            assert!(seen.iter().all(|x| x.0 == Stage::Mesh));
            // Another thread count in the run changes nothing.
            let other = plan.mesh_in(&s, &mut Run::default().threads(3 - threads));
            assert!(
                other.unwrap() == plain,
                "{topology:?} on {} threads",
                3 - threads
            );
            // One report per round of 65,536 branches (1 or 2 threads keep that round).
            assert_eq!(seen.len(), s.len().div_ceil(65_536), "{seen:?}");
            assert!(seen.windows(2).all(|w| w[0].1 < w[1].1));
            assert_eq!(seen.last().unwrap().1, 1.0);
            let mut calls = 0;
            let mut stop = |_: Stage, _: f32| {
                calls += 1;
                false
            };
            let e = plan
                .mesh_in(&s, &mut Run::reporting(&mut stop))
                .unwrap_err();
            assert!(matches!(e, Error::Cancelled { stage: "mesh" }), "{e}");
            assert_eq!(calls, 1, "stops at the first report");
        }
    }
    // An export that is cancelled creates no file.
    let path = std::env::temp_dir().join(format!("arbor-cancel-{}.glb", std::process::id()));
    let mut stop = |_: Stage, _: f32| false;
    let mut run = Run::reporting(&mut stop);
    let e = arbor::export::save_gltf_in(&s, &MeshOptions::default(), None, &path, &mut run)
        .unwrap_err();
    assert!(matches!(e, Error::Cancelled { .. }));
    assert!(!path.exists());
}

/// The work budget (`max_work`) counts the statements of one production as they run,
/// and the progress callback hears that work (every 2^20 units: milliseconds), so a loop
/// that never ends inside one production is stopped by the budget, and a callback that
/// asks to stop is heard long before the budget is spent.
#[test]
fn statements_inside_one_production_report_and_stop() {
    let ls =
        LSystem::parse("derivation length: 1\nAxiom: A\nA : { while (1) { x = x + 1; } } --> F\n")
            .unwrap();
    let options = LsystemOptions::default().max_work(64 << 20);
    let mut calls = 0usize;
    let mut count = |_: Stage, _: f32| {
        calls += 1;
        true
    };
    match ls.skeleton_in(&options, &mut Run::reporting(&mut count)) {
        Err(Error::LimitExceeded { limit_name, .. }) => assert_eq!(limit_name, "max_work"),
        other => panic!("{other:?}"),
    }
    // 64 Mi units heard every 1 Mi units: about 64 reports, all within the one step.
    assert!(calls >= 60, "{calls} reports");
    let mut calls = 0usize;
    let mut stop = |_: Stage, _: f32| {
        calls += 1;
        calls < 3
    };
    match ls.skeleton_in(&options, &mut Run::reporting(&mut stop)) {
        Err(Error::Cancelled { stage }) => assert_eq!(stage, "derivation"),
        other => panic!("{other:?}"),
    }
    assert_eq!(calls, 3);
}

/// Interpretation rules spend from what the derivation left of the budget, not from a
/// fresh one: a `Start:` loop and rules that each fit the budget alone do not fit it
/// together.
#[test]
fn interpretation_rules_spend_what_the_derivation_left() {
    let rules = "homomorphism\nmaximum depth: 100\nA --> FA\n";
    let grammar = |start: &str| {
        LSystem::parse(&format!(
            "{start}derivation length: 12\nAxiom: A\nA --> AA\n{rules}"
        ))
        .unwrap()
    };
    let work = LsystemOptions::default().max_work(8 << 20);
    let spin = "Start: { i = 0; while (i < 600000) { i = i + 1; } }\n";
    // The rules alone (4,096 modules drawn 100 levels deep) fit.
    assert!(grammar("").skeleton(&work).is_ok());
    // The loop alone fits: the same grammar without its rules.
    let no_rules = LSystem::parse(&format!(
        "{spin}derivation length: 12\nAxiom: A\nA --> AA\n"
    ))
    .unwrap();
    assert!(no_rules.skeleton(&work).is_ok());
    // Together they do not: the rules got what the loop left.
    match grammar(spin).skeleton(&work) {
        Err(Error::LimitExceeded { limit_name, .. }) => assert_eq!(limit_name, "max_work"),
        other => panic!("{:?}", other.map(|s| s.len())),
    }
    // With room for both, the same grammar grows.
    assert!(grammar(spin).skeleton(&work.max_work(32 << 20)).is_ok());
}
