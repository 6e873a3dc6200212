//! `arbor`, the command-line tool: grow a tree from a 1996 preset, a cpfg file or a
//! self-organizing species, and write it as glTF or OBJ, or print what it is.
//!
//! ```text
//! arbor export SOURCE -o OUT.{glb,gltf,obj} [--steps N] [--seed S]
//!              [--leaves[=auto|sites|tips]] [--leaf-size S] [--instanced-leaves]
//!              [--radial-segments K] [--curve-rings K] [--compact-vertices]
//! arbor info SOURCE [--steps N] [--seed S] [--json]
//! ```
//! SOURCE: a letter a–i (the 1996 trees), a `.l` file (read as cpfg reads it), or
//! `growth:SPECIES` (excurrent, decurrent, columnar, bush, weeping; `--steps` cycles).

use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::{LeafOptions, MeshOptions};
use arbor::models::growth::{GrowthParams, Species};
use arbor::models::honda::HondaParams;
use arbor::progress::{Run, Stage};
use arbor::skeleton::Skeleton;
use arbor::source::Source;
use clap::{Arg, ArgAction, ArgMatches, Command, value_parser};
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

/// Set by Ctrl-C: every progress callback then answers "stop", so the work ends with
/// `Cancelled` and an export removes its temporary file, leaving the target as it was. A
/// second Ctrl-C ends the process at once.
static INTERRUPTED: AtomicBool = AtomicBool::new(false);

/// The species names, as `growth:NAME` takes them.
fn species_names() -> String {
    Species::ALL.map(Species::name).join(", ")
}

fn cli() -> Command {
    let source = Arg::new("source").required(true).help(format!(
        "a–i (the 1996 trees), FILE.l (a cpfg file), FOLDER (a vlab object), or \
         growth:SPECIES (a self-organizing tree: {})",
        species_names()
    ));
    let steps = Arg::new("steps")
        .long("steps")
        .value_parser(value_parser!(u32))
        .help("derivation steps (cycles for growth:); default: the source's own");
    let seed = Arg::new("seed")
        .long("seed")
        .value_parser(value_parser!(u64))
        .help("seed: varies stochastic grammars, the 1996 trees and growth");
    Command::new("arbor")
        .version(env!("CARGO_PKG_VERSION"))
        .about("Grow 3-D trees from L-systems and turn them into meshes")
        .after_help(format!(
            "SOURCE: a–i (the nine trees of the 1996 paper), FILE.l (a cpfg L-system, read \
             with its view file), FOLDER (a vlab object: the .l and .v its specifications \
             names), or growth:SPECIES with SPECIES one of {}.\n\
             Examples:\n  arbor export g -o tree_g.glb --leaves\n  \
             arbor export growth:weeping --steps 30 -o weeping.obj\n  arbor info a --json",
            species_names()
        ))
        .subcommand_required(true)
        .subcommand(
            Command::new("export")
                .about("Write the tree as .glb, .gltf or .obj")
                .arg(source.clone())
                .arg(
                    Arg::new("out")
                        .short('o')
                        .long("output")
                        .required(true)
                        .help("OUT.glb, OUT.gltf or OUT.obj"),
                )
                .arg(steps.clone())
                .arg(seed.clone())
                .arg(
                    Arg::new("leaves")
                        .long("leaves")
                        .num_args(0..=1)
                        .require_equals(true)
                        .default_missing_value("auto")
                        .value_parser(["auto", "sites", "tips"])
                        .help(
                            "bake leaves into the file: at the model's leaf sites (~, with its \
                             polygons, spheres and surfaces), at the tips of the youngest \
                             branches, or auto (sites when the model has any, else tips)",
                        ),
                )
                .arg(
                    Arg::new("leaf-size")
                        .long("leaf-size")
                        .value_parser(value_parser!(f32))
                        .help("leaf size in model units (default: 1 at sites, 4% of the tree's size at tips)"),
                )
                .arg(
                    Arg::new("instanced-leaves")
                        .long("instanced-leaves")
                        .action(ArgAction::SetTrue)
                        .help("glTF only: one leaf mesh drawn per leaf (EXT_mesh_gpu_instancing); placed as --leaves says (auto)"),
                )
                .arg(
                    Arg::new("radial-segments")
                        .long("radial-segments")
                        .value_parser(value_parser!(u32))
                        .help("sides of every branch (3–64, default 8)"),
                )
                .arg(
                    Arg::new("curve-rings")
                        .long("curve-rings")
                        .value_parser(value_parser!(u32))
                        .help("rings inside every branch along its curve (default 0)"),
                )
                .arg(
                    Arg::new("compact-vertices")
                        .long("compact-vertices")
                        .action(ArgAction::SetTrue)
                        .help("glTF only: quantized vertices (KHR_mesh_quantization: normals in snorm16, 28 bytes a vertex)"),
                ),
        )
        .subcommand(
            Command::new("info")
                .about("Print counts and timings")
                .arg(source)
                .arg(steps)
                .arg(seed)
                .arg(
                    Arg::new("json")
                        .long("json")
                        .action(ArgAction::SetTrue)
                        .help("print JSON"),
                ),
        )
}

/// A progress bar on stderr when it is a terminal.
struct Bar {
    on: bool,
    last: (Stage, u32),
}

impl Bar {
    fn new() -> Self {
        Bar {
            on: std::io::stderr().is_terminal(),
            last: (Stage::Derivation, u32::MAX),
        }
    }

    /// Draws the bar; false (stop) once Ctrl-C was pressed.
    fn show(&mut self, stage: Stage, fraction: f32) -> bool {
        if INTERRUPTED.load(Ordering::SeqCst) {
            return false;
        }
        let pct = (fraction * 100.0) as u32;
        if self.on && (stage, pct) != self.last {
            self.last = (stage, pct);
            let filled = (pct / 5) as usize;
            eprint!(
                "\r{:<14} [{}{}] {pct:3}%",
                stage.name(),
                "#".repeat(filled),
                " ".repeat(20 - filled.min(20))
            );
            let _ = std::io::stderr().flush();
        }
        true
    }

    fn done(&self) {
        if self.on && self.last.1 != u32::MAX {
            eprint!("\r{:50}\r", "");
        }
    }
}

/// Grows the source; returns the skeleton and a description.
fn grow(m: &ArgMatches, bar: &mut Bar) -> Result<(Skeleton, String), String> {
    let source: &String = m.get_one("source").expect("required");
    let steps = m.get_one::<u32>("steps").copied();
    let seed = m.get_one::<u64>("seed").copied().unwrap_or(0);
    let err = |e: arbor::Error| format!("{source}: {e}");
    let mut show = |s: Stage, f: f32| bar.show(s, f);
    let mut run = Run::reporting(&mut show);
    if let Some(species) = source.strip_prefix("growth:") {
        let kind = Species::from_name(species).ok_or_else(|| {
            format!(
                "{source}: unknown species; expected one of {}",
                species_names()
            )
        })?;
        let cycles = steps.unwrap_or(12);
        let s = Source::Growth(GrowthParams::preset(kind), cycles)
            .grow_in(seed, &mut run)
            .map_err(err)?;
        return Ok((s, format!("{species}, {cycles} growth cycles")));
    }
    let mut chars = source.chars();
    if let (Some(c @ 'a'..='i'), None) = (chars.next(), chars.next()) {
        let mut p = HondaParams::preset(c).expect("a to i are presets");
        if let Some(n) = steps {
            p.steps = n;
        }
        let s = Source::Honda(p).grow_in(seed, &mut run).map_err(err)?;
        return Ok((s, format!("1996 tree {c}, {} steps", p.steps)));
    }
    let path = std::path::Path::new(source);
    if !(path.is_file() || path.is_dir()) {
        return Err(format!(
            "{source}: no such file; SOURCE is a letter a–i, a cpfg .l file, a vlab object's \
             folder or growth:SPECIES"
        ));
    }
    let ls = LSystem::from_file(source, None).map_err(err)?;
    for w in ls.warnings() {
        eprintln!("warning: {source}: {w}");
    }
    let options = LsystemOptions::default().steps(steps);
    let s = Source::Grammar(&ls, options)
        .grow_in(seed, &mut run)
        .map_err(err)?;
    let n = steps.unwrap_or(ls.derivation_length());
    Ok((s, format!("cpfg file, {n} steps")))
}

/// Where `--leaves=PLACE` puts leaves on this skeleton, and a note that says so.
fn leaf_options(
    skeleton: &Skeleton,
    place: &str,
    size: Option<f32>,
    source: &str,
) -> Result<(LeafOptions, String), String> {
    let has_sites = !skeleton.leaves().is_empty()
        || !skeleton.polygons().is_empty()
        || !skeleton.organs().is_empty();
    if let Some(s) = size
        && !(s.is_finite() && s > 0.0)
    {
        return Err(format!("--leaf-size {s}: expected a finite size above 0"));
    }
    let tips = match place {
        "sites" if !has_sites => {
            return Err(format!(
                "{source}: the model has no leaf sites (~) or organs; --leaves=tips puts \
                 leaves at the branch tips"
            ));
        }
        "sites" => false,
        "tips" => true,
        _ => !has_sites,
    };
    if !tips {
        let l = LeafOptions::default().size(size.unwrap_or(1.0));
        return Ok((l, "at the model's leaf sites".to_string()));
    }
    // Tips of the branches born in the last three steps (or cycles), two leaves each on
    // average, sized to the tree.
    let last = skeleton
        .branches()
        .iter()
        .map(|b| b.birth)
        .max()
        .unwrap_or(0);
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for b in skeleton.branches() {
        for p in [b.start, b.end] {
            for c in 0..3 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
    }
    let extent = (0..3).map(|c| hi[c] - lo[c]).fold(0.0f32, f32::max);
    let l = LeafOptions::default()
        .sites(false)
        .polygons(false)
        .tips(true)
        .min_birth(last.saturating_sub(2))
        .density(2.0)
        .size(size.unwrap_or(if extent > 0.0 { 0.04 * extent } else { 1.0 }));
    let why = if place == "tips" {
        "at the tips of the youngest branches"
    } else {
        "at the tips of the youngest branches (the model has no leaf sites)"
    };
    Ok((l, why.to_string()))
}

fn run() -> Result<(), String> {
    let matches = cli().get_matches();
    let (name, m) = matches.subcommand().expect("a subcommand is required");
    let mut bar = Bar::new();
    let t0 = Instant::now();
    let grown = grow(m, &mut bar);
    bar.done();
    let (skeleton, what) = grown?;
    let grow_ms = t0.elapsed().as_secs_f64() * 1e3;
    match name {
        "export" => export(m, &skeleton, &what, grow_ms),
        _ => info(m, &skeleton, &what, grow_ms),
    }
}

/// `arbor export`: writes the tree (and its leaves) as glTF, GLB or OBJ.
fn export(m: &ArgMatches, skeleton: &Skeleton, what: &str, grow_ms: f64) -> Result<(), String> {
    let out: &String = m.get_one("out").expect("required");
    let mut o = MeshOptions::default();
    if let Some(&k) = m.get_one::<u32>("radial-segments") {
        o.radial_segments = k;
    }
    if let Some(&k) = m.get_one::<u32>("curve-rings") {
        o.curve_rings = k;
    }
    let lower = out.to_ascii_lowercase();
    let format = [".glb", ".gltf", ".obj"]
        .into_iter()
        .find(|e| lower.ends_with(e))
        .ok_or_else(|| format!("{out}: expected a .glb, .gltf or .obj file name"))?;
    if m.get_flag("compact-vertices") {
        if format == ".obj" {
            return Err(format!(
                "{out}: --compact-vertices is for glTF (KHR_mesh_quantization); OBJ is text"
            ));
        }
        o.vertex_format = arbor::mesh::VertexFormat::Compact;
    }
    let instanced = m.get_flag("instanced-leaves");
    if instanced && format == ".obj" {
        return Err(format!(
            "{out}: --instanced-leaves is for glTF (EXT_mesh_gpu_instancing); OBJ has \
             no instancing, use --leaves to bake them"
        ));
    }
    let placement = m
        .get_one::<String>("leaves")
        .map(String::as_str)
        .or(instanced.then_some("auto"));
    if m.get_one::<f32>("leaf-size").is_some() && placement.is_none() {
        return Err("--leaf-size needs --leaves or --instanced-leaves".to_string());
    }
    let leaves = match placement {
        Some(place) => Some(placed_leaves(m, skeleton, place)?),
        None => None,
    };
    let t1 = Instant::now();
    let mut bar = Bar::new();
    let mut show = |s: Stage, f: f32| bar.show(s, f);
    let mut run = Run::reporting(&mut show);
    let r = if lower.ends_with(".obj") {
        arbor::export::save_obj_tree_in(skeleton, &o, leaves.as_ref(), out, &mut run)
    } else if instanced {
        let l = leaves.as_ref().expect("instanced leaves are placed");
        arbor::export::save_gltf_instanced_in(skeleton, &o, l, out, &mut run)
    } else {
        arbor::export::save_gltf_in(skeleton, &o, leaves.as_ref(), out, &mut run)
    };
    bar.done();
    if INTERRUPTED.load(Ordering::SeqCst) && r.is_err() {
        return Err(format!(
            "interrupted; {out} was not written (an existing file is as it was)"
        ));
    }
    r.map_err(|e| format!("{out}: {e}"))?;
    eprintln!(
        "{out}: {} branches ({what}); grown in {grow_ms:.1} ms, written in {:.1} ms",
        skeleton.len(),
        t1.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// The leaves `--leaves PLACE` (or `--instanced-leaves`) places, reported on stderr.
fn placed_leaves(m: &ArgMatches, skeleton: &Skeleton, place: &str) -> Result<LeafOptions, String> {
    let size = m.get_one::<f32>("leaf-size").copied();
    let source: &String = m.get_one("source").expect("required");
    let (l, note) = leaf_options(skeleton, place, size, source)?;
    let o = MeshOptions::default();
    let n = arbor::mesh::leaf_instances(skeleton, &l, &o)
        .map_err(|e| e.to_string())?
        .len();
    let (polygons, organs) = if l.sites {
        (skeleton.polygons().len(), skeleton.organs().len())
    } else {
        (0, 0)
    };
    if n + polygons + organs == 0 {
        eprintln!("warning: {source}: no leaves were placed ({note})");
    } else if l.sites {
        eprintln!("leaves: {n} {note}, with its {polygons} polygons and {organs} organs");
    } else {
        eprintln!("leaves: {n} {note}");
    }
    Ok(l)
}

/// `arbor info`: counts and sizes, as text or JSON.
fn info(m: &ArgMatches, skeleton: &Skeleton, what: &str, grow_ms: f64) -> Result<(), String> {
    let o = MeshOptions::default();
    let t1 = Instant::now();
    let size = arbor::mesh::mesh_size(skeleton, &o).map_err(|e| e.to_string())?;
    let mesh_ms = t1.elapsed().as_secs_f64() * 1e3;
    let (branches, leaves, polygons, organs) = (
        skeleton.len(),
        skeleton.leaves().len(),
        skeleton.polygons().len(),
        skeleton.organs().len(),
    );
    if m.get_flag("json") {
        let json = serde_json::json!({
            "source": m.get_one::<String>("source").expect("required"),
            "what": what,
            "branches": branches,
            "leaf_sites": leaves,
            "polygons": polygons,
            "organs": organs,
            "vertices": size.vertices,
            "indices": size.indices,
            "grow_ms": grow_ms,
            "mesh_size_ms": mesh_ms,
        });
        println!("{json}");
    } else {
        println!("{what}");
        println!("branches    {branches}");
        println!("leaf sites  {leaves}");
        println!("polygons    {polygons}");
        println!("organs      {organs}");
        println!("vertices    {} (default mesh options)", size.vertices);
        println!("indices     {}", size.indices);
        println!("grown in    {grow_ms:.2} ms");
    }
    Ok(())
}

fn main() {
    // Without a handler (where one cannot be installed) Ctrl-C ends the process as before:
    // an export then leaves the target as it was and at most its `.arbor-*.tmp` file.
    let _ = ctrlc::set_handler(|| {
        if INTERRUPTED.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
    });
    if let Err(e) = run() {
        eprintln!("arbor: {e}");
        // 130: ended by Ctrl-C (SIGINT), as shells report it.
        std::process::exit(if INTERRUPTED.load(Ordering::SeqCst) {
            130
        } else {
            1
        });
    }
}
