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

use anyhow::{Result, anyhow, bail};
use arbor::lsystem::{LSystem, LsystemOptions};
use arbor::mesh::{LeafOptions, MeshOptions};
use arbor::models::growth::{GrowthParams, Species};
use arbor::models::honda::HondaParams;
use arbor::progress::{Run, Stage};
use arbor::skeleton::Skeleton;
use arbor::source::Source;
use clap::{Args, CommandFactory, FromArgMatches, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
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

/// Grow 3-D trees from L-systems and turn them into meshes
#[derive(Parser)]
#[command(name = "arbor", version, subcommand_required = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write the tree as .glb, .gltf or .obj
    Export(ExportArgs),
    /// Print counts and timings
    Info(InfoArgs),
}

/// What to grow: the source, its steps and its seed (the source's help names the species
/// at run time, in `cli`).
#[derive(Args)]
struct TreeArgs {
    #[arg(value_name = "source")]
    source: String,
    /// derivation steps (cycles for growth:); default: the source's own
    #[arg(long, value_name = "steps")]
    steps: Option<u32>,
    /// seed: varies stochastic grammars, the 1996 trees and growth
    #[arg(long, value_name = "seed")]
    seed: Option<u64>,
}

#[derive(Args)]
struct ExportArgs {
    #[command(flatten)]
    tree: TreeArgs,
    /// OUT.glb, OUT.gltf or OUT.obj
    #[arg(short = 'o', long = "output", value_name = "out", display_order = 0)]
    out: String,
    /// bake leaves into the file: at the model's leaf sites (~, with its polygons, spheres
    /// and surfaces), at the tips of the youngest branches, or auto (sites when the model
    /// has any, else tips)
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "auto",
          value_name = "leaves", value_parser = ["auto", "sites", "tips"])]
    leaves: Option<String>,
    /// leaf size in model units (default: 1 at sites, 4% of the tree's size at tips)
    #[arg(long, value_name = "leaf-size")]
    leaf_size: Option<f32>,
    /// glTF only: one leaf mesh drawn per leaf (EXT_mesh_gpu_instancing); placed as
    /// --leaves says (auto)
    #[arg(long)]
    instanced_leaves: bool,
    /// sides of every branch (3–64, default 8)
    #[arg(long, value_name = "radial-segments")]
    radial_segments: Option<u32>,
    /// rings inside every branch along its curve (default 0)
    #[arg(long, value_name = "curve-rings")]
    curve_rings: Option<u32>,
    /// glTF only: quantized vertices (KHR_mesh_quantization: normals in snorm16, 28 bytes
    /// a vertex)
    #[arg(long)]
    compact_vertices: bool,
    /// a named species (growth:oak ...): edge of its bark and leaf textures in pixels
    /// (16–4096, default 1024)
    #[arg(long, value_name = "pixels")]
    texture_size: Option<u32>,
    /// glTF only: up to 32 collision capsules for the trunk and limbs, as nodes named for
    /// Unreal (UCP_tree_NN) or Godot (tree_col_NN-convcolonly), each capsule also in the
    /// node's extras
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "unreal",
          value_name = "engine", value_parser = ["unreal", "godot"])]
    collision: Option<String>,
    /// glTF only: the whole game asset: --lod 4 --impostor octahedral --wind skin
    /// --collision
    #[arg(long)]
    game: bool,
    /// glTF only: this many levels of detail (1–8), nodes tree_LOD0... with MSFT_lod and
    /// the screen coverage each is drawn from
    #[arg(long, value_name = "levels")]
    lod: Option<u32>,
    /// glTF only, with levels of detail: an octahedral impostor's atlases (textures and
    /// node extras) for below the last level, or a billboard (crossed quads) as the last
    /// level, or none
    #[arg(long, value_name = "kind", value_parser = ["octahedral", "billboard", "none"])]
    impostor: Option<String>,
    /// glTF only: wind that plays in any viewer: bones along the trunk and limbs (up to
    /// 32), every vertex weighted to them, and a looping 4-second clip "wind"; or the data
    /// engines' wind shaders read, as attributes COLOR_0 (phase, stiffness, branch level,
    /// leaf flutter) and TEXCOORD_1 (along the branch, growth time). With levels of
    /// detail: skin (every level on one skeleton) or none
    #[arg(long, value_name = "kind", value_parser = ["skin", "attributes", "none"])]
    wind: Option<String>,
}

#[derive(Args)]
struct InfoArgs {
    #[command(flatten)]
    tree: TreeArgs,
    /// print JSON
    #[arg(long)]
    json: bool,
}

/// The command line's description, with the species named where SOURCE is explained.
fn cli() -> clap::Command {
    let source_help = format!(
        "a–i (the 1996 trees), FILE.l (a cpfg file), FOLDER (a vlab object), or \
         growth:SPECIES (a self-organizing tree: {})",
        species_names()
    );
    Cli::command()
        .about("Grow 3-D trees from L-systems and turn them into meshes")
        .after_help(format!(
            "SOURCE: a–i (the nine trees of the 1996 paper), FILE.l (a cpfg L-system, read \
             with its view file), FOLDER (a vlab object: the .l and .v its specifications \
             names), or growth:SPECIES with SPECIES one of {}.\n\
             Examples:\n  arbor export g -o tree_g.glb --leaves\n  \
             arbor export growth:weeping --steps 30 -o weeping.obj\n  arbor info a --json",
            species_names()
        ))
        .mut_subcommand("export", |c| {
            c.mut_arg("source", |a| a.help(source_help.clone()))
        })
        .mut_subcommand("info", |c| {
            c.mut_arg("source", |a| a.help(source_help.clone()))
        })
}

/// A progress bar on stderr when it is a terminal (indicatif), hidden otherwise.
struct Bar(ProgressBar);

impl Bar {
    fn new() -> Self {
        if !std::io::stderr().is_terminal() {
            return Bar(ProgressBar::hidden());
        }
        let bar = ProgressBar::new(100);
        bar.set_style(
            ProgressStyle::with_template("{msg:<14} [{bar:20}] {pos:>3}%")
                .expect("a valid template")
                .progress_chars("## "),
        );
        Bar(bar)
    }

    /// Draws the bar; false (stop) once Ctrl-C was pressed.
    fn show(&mut self, stage: Stage, fraction: f32) -> bool {
        if INTERRUPTED.load(Ordering::SeqCst) {
            return false;
        }
        self.0.set_message(stage.name());
        self.0.set_position((fraction * 100.0) as u64);
        true
    }

    fn done(&self) {
        self.0.finish_and_clear();
    }
}

/// Grows the source; returns the skeleton and a description.
fn grow(t: &TreeArgs, bar: &mut Bar) -> Result<(Skeleton, String)> {
    let (source, steps, seed) = (&t.source, t.steps, t.seed.unwrap_or(0));
    let err = |e: arbor::Error| anyhow!("{source}: {e}");
    let mut show = |s: Stage, f: f32| bar.show(s, f);
    let mut run = Run::reporting(&mut show);
    if let Some(species) = source.strip_prefix("growth:") {
        let kind = Species::from_name(species).ok_or_else(|| {
            anyhow!(
                "{source}: unknown species; expected one of {}",
                species_names()
            )
        })?;
        let look = arbor::species::Look::of(kind);
        let cycles = steps.unwrap_or(look.map_or(12, |l| l.cycles));
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
        bail!(
            "{source}: no such file; SOURCE is a letter a–i, a cpfg .l file, a vlab object's \
             folder or growth:SPECIES"
        );
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
) -> Result<(LeafOptions, String)> {
    let has_sites = !skeleton.leaves().is_empty()
        || !skeleton.polygons().is_empty()
        || !skeleton.organs().is_empty();
    if let Some(s) = size
        && !(s.is_finite() && s > 0.0)
    {
        bail!("--leaf-size {s}: expected a finite size above 0");
    }
    let tips = match place {
        "sites" if !has_sites => {
            bail!(
                "{source}: the model has no leaf sites (~) or organs; --leaves=tips puts \
                 leaves at the branch tips"
            );
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
    let extent = skeleton
        .bounds()
        .map_or(0.0, |(lo, hi)| (hi - lo).max_element());
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

fn run() -> Result<()> {
    let cli = Cli::from_arg_matches(&cli().get_matches()).unwrap_or_else(|e| e.exit());
    let tree = match &cli.command {
        Command::Export(e) => &e.tree,
        Command::Info(i) => &i.tree,
    };
    let mut bar = Bar::new();
    let t0 = Instant::now();
    let grown = grow(tree, &mut bar);
    bar.done();
    let (skeleton, what) = grown?;
    let grow_ms = t0.elapsed().as_secs_f64() * 1e3;
    match &cli.command {
        Command::Export(e) => export(e, &skeleton, &what, grow_ms),
        Command::Info(i) => info(i, &skeleton, &what, grow_ms),
    }
}

/// `arbor export`: writes the tree (and its leaves) as glTF, GLB or OBJ.
fn export(m: &ExportArgs, skeleton: &Skeleton, what: &str, grow_ms: f64) -> Result<()> {
    let out = &m.out;
    let mut o = MeshOptions::default();
    if let Some(k) = m.radial_segments {
        o.radial_segments = k;
    }
    if let Some(k) = m.curve_rings {
        o.curve_rings = k;
    }
    let lower = out.to_ascii_lowercase();
    let format = [".glb", ".gltf", ".obj"]
        .into_iter()
        .find(|e| lower.ends_with(e))
        .ok_or_else(|| anyhow!("{out}: expected a .glb, .gltf or .obj file name"))?;
    if m.compact_vertices {
        if format == ".obj" {
            bail!("{out}: --compact-vertices is for glTF (KHR_mesh_quantization); OBJ is text");
        }
        o.vertex_format = arbor::mesh::VertexFormat::Compact;
    }
    let look = m
        .tree
        .source
        .strip_prefix("growth:")
        .and_then(Species::from_name)
        .and_then(arbor::species::Look::of);
    if let Some(look) = look {
        return export_species(m, &look, skeleton, &o, what, grow_ms);
    }
    if m.texture_size.is_some() {
        bail!("--texture-size is for a named species (growth:oak, growth:pine, ...)");
    }
    let instanced = m.instanced_leaves;
    if instanced && format == ".obj" {
        bail!(
            "{out}: --instanced-leaves is for glTF (EXT_mesh_gpu_instancing); OBJ has \
             no instancing, use --leaves to bake them"
        );
    }
    let placement = m.leaves.as_deref().or(instanced.then_some("auto"));
    if m.leaf_size.is_some() && placement.is_none() {
        bail!("--leaf-size needs --leaves or --instanced-leaves");
    }
    let leaves = match placement {
        Some(place) => Some(placed_leaves(m, skeleton, place)?),
        None => None,
    };
    if m.collision.is_some() && format == ".obj" {
        bail!("{out}: --collision is for glTF (capsule nodes); OBJ has no nodes");
    }
    if let Some(game) = Game::of(m)? {
        if format == ".obj" {
            bail!("{out}: levels of detail and impostors are for glTF (nodes); OBJ has none");
        }
        if instanced {
            bail!("{out}: levels of detail bake their leaves; leave out --instanced-leaves");
        }
        let t1 = Instant::now();
        let go = arbor::export::gltf_mesh_options(&o).map_err(|e| anyhow!("{out}: {e}"))?;
        let scene = game
            .scene(skeleton, &go, leaves.as_ref(), None, [92, 64, 44], |_| {})
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        arbor::export::save_gltf_scene(&scene, &o, out).map_err(|e| anyhow!("{out}: {e}"))?;
        game.report(&scene, out, skeleton.len(), what, grow_ms, t1);
        return Ok(());
    }
    let skin = m.wind.as_deref() == Some("skin");
    let attributes = m.wind.as_deref() == Some("attributes");
    if (skin || attributes) && (format == ".obj" || instanced) {
        bail!("{out}: --wind skin and attributes are for glTF with baked leaves");
    }
    let t1 = Instant::now();
    let mut bar = Bar::new();
    let mut show = |s: Stage, f: f32| bar.show(s, f);
    let mut run = Run::reporting(&mut show);
    let r = if skin || attributes {
        let go = arbor::export::gltf_mesh_options(&o);
        go.and_then(|go| {
            let mut scene = arbor::scene::Scene::tree(skeleton, &go, leaves.as_ref())?;
            if let Some(names) = collision_names(m) {
                scene.collide_for(
                    &arbor::collision::capsules(skeleton, COLLISION_CAPSULES, 0.0, &go)?,
                    names,
                );
            }
            if attributes {
                wind_attributes(&mut scene, skeleton, &go, leaves.as_ref())?;
                return arbor::export::save_gltf_scene(&scene, &o, out);
            }
            wind_skin(
                &mut scene,
                skeleton,
                &go,
                leaves.as_ref(),
                m.tree.seed.unwrap_or(0),
            )?;
            arbor::export::save_gltf_scene(&scene, &o, out)
        })
    } else if m.collision.is_some() {
        collided_scene(skeleton, &o, leaves.as_ref(), instanced, collision_names(m))
            .and_then(|scene| arbor::export::save_gltf_scene(&scene, &o, out))
    } else if lower.ends_with(".obj") {
        arbor::export::save_obj_tree_in(skeleton, &o, leaves.as_ref(), out, &mut run)
    } else if instanced {
        let l = leaves.as_ref().expect("instanced leaves are placed");
        arbor::export::save_gltf_instanced_in(skeleton, &o, l, out, &mut run)
    } else {
        arbor::export::save_gltf_in(skeleton, &o, leaves.as_ref(), out, &mut run)
    };
    bar.done();
    if INTERRUPTED.load(Ordering::SeqCst) && r.is_err() {
        bail!("interrupted; {out} was not written (an existing file is as it was)");
    }
    r.map_err(|e| anyhow!("{out}: {e}"))?;
    eprintln!(
        "{out}: {} branches ({what}); grown in {grow_ms:.1} ms, written in {:.1} ms",
        skeleton.len(),
        t1.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// What `--game`, `--lod` and `--impostor` ask for.
struct Game {
    levels: u32,
    /// Skin every level on one rig and bake the wind clip, seeded by this.
    wind: Option<u64>,
    impostor: String,
    collision: Option<arbor::scene::CollisionNames>,
}

/// The collision naming `--collision` asks for, or none.
fn collision_names(m: &ExportArgs) -> Option<arbor::scene::CollisionNames> {
    m.collision.as_deref().map(|e| match e {
        "godot" => arbor::scene::CollisionNames::Godot,
        _ => arbor::scene::CollisionNames::Unreal,
    })
}

impl Game {
    /// The levels, impostor and collision asked for; none when none of them is.
    fn of(m: &ExportArgs) -> Result<Option<Game>> {
        if !m.game && m.lod.is_none() && m.impostor.is_none() {
            return Ok(None);
        }
        if m.wind.as_deref() == Some("attributes") {
            bail!(
                "--wind attributes with levels of detail: the attributes are for one mesh; \
                 use --wind skin (every level on one skeleton) or export one level"
            );
        }
        let skin = match m.wind.as_deref() {
            Some("skin") => true,
            Some(_) => false,
            None => m.game,
        };
        let levels = m.lod.unwrap_or(4);
        if !(1..=8).contains(&levels) {
            bail!("--lod {levels}: expected 1..=8 levels");
        }
        let impostor = m
            .impostor
            .clone()
            .unwrap_or_else(|| if m.game { "octahedral" } else { "none" }.into());
        Ok(Some(Game {
            levels,
            wind: skin.then(|| m.tree.seed.unwrap_or(0)),
            impostor,
            collision: collision_names(m)
                .or(m.game.then_some(arbor::scene::CollisionNames::Unreal)),
        }))
    }

    /// The scene: the levels of `skeleton` (its leaves baked, alpha-tested against
    /// `atlas` when given), `texture` applied to them, the impostor, the capsules.
    fn scene(
        &self,
        skeleton: &Skeleton,
        o: &MeshOptions,
        leaves: Option<&LeafOptions>,
        atlas: Option<&arbor::texture::Image>,
        bark_color: [u8; 3],
        texture: impl FnOnce(&mut arbor::scene::Scene),
    ) -> arbor::Result<arbor::scene::Scene> {
        let lod = arbor::lod::LodOptions::default().levels(self.levels);
        let t = Instant::now();
        let levels = arbor::lod::chain(skeleton, o, leaves, atlas, &lod)?;
        let chain_ms = t.elapsed().as_secs_f64() * 1e3;
        let t = Instant::now();
        let mut scene = arbor::scene::Scene::levels(&levels, "tree");
        texture(&mut scene);
        if let Some(seed) = self.wind {
            skin_levels(&mut scene, &levels, skeleton, o, seed)?;
        }
        let last = levels.last().map_or(0.0, |l| l.screen_coverage);
        // The impostor is drawn from the coarsest level made for views at least as large
        // as its cells (the full tree when none is).
        let source = &levels[arbor::lod::impostor_source(&levels, IMPOSTOR_CELL)];
        let small = atlas.map(|a| a.downsampled(arbor::lod::SILHOUETTE_ATLAS));
        let mut surfaces = arbor::lod::surfaces(source, small.as_ref());
        for s in &mut surfaces {
            if s.texture.is_none() && !s.double_sided {
                s.color = bark_color;
            }
        }
        match self.impostor.as_str() {
            "octahedral" => {
                let imp = arbor::impostor::octahedral(
                    &surfaces,
                    o.up(),
                    IMPOSTOR_FRAMES,
                    IMPOSTOR_CELL,
                    arbor::impostor::Sphere::Hemi,
                )?;
                scene.impostor(&imp, last);
            }
            "billboard" => {
                let b = arbor::impostor::billboard(&surfaces, o.up(), 3, IMPOSTOR_CELL)?;
                scene.billboard(
                    &b,
                    o.winding == arbor::mesh::Winding::Clockwise,
                    last * 0.25,
                );
            }
            _ => {}
        }
        eprintln!(
            "made in: levels {chain_ms:.0} ms, textures and impostor {:.0} ms",
            t.elapsed().as_secs_f64() * 1e3
        );
        if let Some(names) = self.collision {
            scene.collide_for(
                &arbor::collision::capsules(skeleton, COLLISION_CAPSULES, 0.0, o)?,
                names,
            );
        }
        Ok(scene)
    }

    /// One line on stderr: what was written, and how fast.
    fn report(
        &self,
        scene: &arbor::scene::Scene,
        out: &str,
        branches: usize,
        what: &str,
        grow_ms: f64,
        t1: Instant,
    ) {
        let triangles: Vec<String> = scene
            .nodes
            .iter()
            .filter(|n| n.name.contains("_LOD"))
            .filter_map(|n| n.mesh)
            .map(|k| {
                scene.meshes[k]
                    .primitives
                    .iter()
                    .map(|p| p.mesh.triangles().count())
                    .sum::<usize>()
                    .to_string()
            })
            .collect();
        let coverage = scene
            .nodes
            .iter()
            .find_map(|n| n.lod.as_ref())
            .map(|l| {
                l.coverage
                    .iter()
                    .map(|c| format!("{c:.3}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            })
            .unwrap_or_default();
        eprintln!(
            "levels: {} triangles, drawn from screen coverage {coverage}; impostor: {}; \
             collision: {}",
            triangles.join(", "),
            self.impostor,
            match self.collision {
                Some(arbor::scene::CollisionNames::Godot) => "capsules (Godot)",
                Some(_) => "capsules (Unreal)",
                None => "none",
            }
        );
        eprintln!(
            "{out}: {branches} branches ({what}); grown in {grow_ms:.1} ms, written in {:.1} ms",
            t1.elapsed().as_secs_f64() * 1e3
        );
    }
}

/// Views a side of the octahedral impostor `--impostor octahedral` bakes.
const IMPOSTOR_FRAMES: u32 = 12;

/// Pixels a side of each impostor view.
const IMPOSTOR_CELL: u32 = 128;

/// The mean colour of an image (sRGB bytes).
fn mean_color(image: &arbor::texture::Image) -> [u8; 3] {
    let mut sum = [0u64; 3];
    for p in image.pixels.chunks_exact(4) {
        for (s, &c) in sum.iter_mut().zip(p) {
            *s += c as u64;
        }
    }
    let n = (image.pixels.len() / 4).max(1) as u64;
    sum.map(|s| (s / n) as u8)
}

/// The tree's bark and, when baked into it, its leaf mesh, as the scene's first node
/// draws them (with the bark's branch ranges): the meshes the wind is fitted to, not made
/// again.
fn tree_meshes(scene: &arbor::scene::Scene) -> arbor::Result<(&arbor::Mesh, Option<&arbor::Mesh>)> {
    let prims = scene
        .nodes
        .first()
        .and_then(|n| n.mesh)
        .map(|k| &scene.meshes[k].primitives[..])
        .unwrap_or(&[]);
    match prims {
        [bark, rest @ ..] => Ok((&bark.mesh, rest.first().map(|p| &p.mesh))),
        [] => Err(arbor::Error::InvalidArgument {
            field: "scene",
            reason: "no tree mesh; expected a tree".into(),
        }),
    }
}

/// Bones `--wind skin` gives a tree at most.
const WIND_BONES: usize = 32;

/// Skins the tree's mesh in `scene` (bark, then its baked `leaves` when given) on a rig of
/// `skeleton` drawn with `o`, with a 4-second wind clip seeded by `seed`.
fn wind_skin(
    scene: &mut arbor::scene::Scene,
    skeleton: &Skeleton,
    o: &MeshOptions,
    leaves: Option<&LeafOptions>,
    seed: u64,
) -> arbor::Result<()> {
    let rig = arbor::wind::rig(skeleton, WIND_BONES, o)?;
    let (bark, baked) = tree_meshes(scene)?;
    let mut influences = vec![arbor::wind::weights(&rig, bark)?];
    if let (Some(l), Some(baked)) = (leaves, baked) {
        let branches = arbor::mesh::leaf_branches(skeleton, l, o)?;
        let per_leaf = l.shape().vertices.len();
        influences.push(arbor::wind::leaf_weights(&rig, baked, &branches, per_leaf));
    }
    let clip = arbor::wind::clip(&rig, o.up(), glam::Vec3::X, 2.0, 4.0, 30, seed)?;
    scene.skin(&rig, influences, Some(clip))
}

/// Skins every level of `levels` in `scene` (the nodes `tree_LOD0...`, made by
/// [`arbor::scene::Scene::levels`]) on one rig of `skeleton` drawn with `o`: a level's bark
/// by the branches it merged ([`arbor::wind::level_weights`]), its leaves by the branch
/// each is on; with a 4-second wind clip seeded by `seed`.
fn skin_levels(
    scene: &mut arbor::scene::Scene,
    levels: &[arbor::lod::Level],
    skeleton: &Skeleton,
    o: &MeshOptions,
    seed: u64,
) -> arbor::Result<()> {
    let rig = arbor::wind::rig(skeleton, WIND_BONES, o)?;
    let first = scene.nodes.iter().position(|n| n.lod.is_some());
    let nodes: Vec<usize> = first
        .into_iter()
        .chain(
            first
                .and_then(|k| scene.nodes[k].lod.as_ref())
                .map_or(Vec::new(), |l| l.levels.clone()),
        )
        .collect();
    let mut skins = Vec::new();
    for (&node, level) in nodes.iter().zip(levels) {
        let mut influences = Vec::new();
        if !level.bark.indices.is_empty() {
            influences.push(arbor::wind::level_part_weights(
                &rig, skeleton, o, level, false,
            )?);
        }
        if level.leaf_options.is_some()
            && level.leaves.as_ref().is_some_and(|m| !m.indices.is_empty())
        {
            influences.push(arbor::wind::level_part_weights(
                &rig, skeleton, o, level, true,
            )?);
        }
        skins.push((node, influences));
    }
    let clip = arbor::wind::clip(&rig, o.up(), glam::Vec3::X, 2.0, 4.0, 30, seed)?;
    scene.skin_nodes(&rig, skins, Some(clip))
}

/// Gives the tree's mesh in `scene` (bark, then its baked `leaves` when given) the wind
/// attributes engines' shaders read (COLOR_0, TEXCOORD_1).
fn wind_attributes(
    scene: &mut arbor::scene::Scene,
    skeleton: &Skeleton,
    o: &MeshOptions,
    leaves: Option<&LeafOptions>,
) -> arbor::Result<()> {
    let (bark, baked) = tree_meshes(scene)?;
    let mut all = vec![arbor::wind::bark_attributes(skeleton, bark, o)?];
    if let (Some(l), Some(baked)) = (leaves, baked) {
        all.push(arbor::wind::leaf_attributes(skeleton, l, o, baked)?);
    }
    scene.wind_attributes(all)?;
    scene.pivots(arbor::wind::pivots(skeleton, o));
    Ok(())
}

/// Capsules `--collision` writes at most.
const COLLISION_CAPSULES: usize = 32;

/// The scene of a tree (its leaves baked or instanced) with its collision capsules.
fn collided_scene(
    skeleton: &arbor::skeleton::Skeleton,
    o: &MeshOptions,
    leaves: Option<&arbor::mesh::LeafOptions>,
    instanced: bool,
    names: Option<arbor::scene::CollisionNames>,
) -> arbor::Result<arbor::scene::Scene> {
    let go = arbor::export::gltf_mesh_options(o)?;
    let mut scene = match leaves {
        Some(l) if instanced => arbor::scene::Scene::tree_instanced(skeleton, &go, l)?,
        _ => arbor::scene::Scene::tree(skeleton, &go, leaves)?,
    };
    scene.collide_for(
        &arbor::collision::capsules(skeleton, COLLISION_CAPSULES, 0.0, &go)?,
        names.unwrap_or(arbor::scene::CollisionNames::Unreal),
    );
    Ok(scene)
}

/// `arbor export growth:SPECIES` of a named species: its textured, leafy tree at its
/// height, as one glTF scene.
fn export_species(
    m: &ExportArgs,
    look: &arbor::species::Look,
    skeleton: &Skeleton,
    o: &MeshOptions,
    what: &str,
    grow_ms: f64,
) -> Result<()> {
    let out = &m.out;
    if m.leaves.is_some() || m.leaf_size.is_some() || m.instanced_leaves {
        bail!(
            "{}: a named species places its own leaves; --leaves, --leaf-size and \
             --instanced-leaves are for the other sources",
            m.tree.source
        );
    }
    let obj = out.to_ascii_lowercase().ends_with(".obj");
    let t1 = Instant::now();
    let size = m.texture_size.unwrap_or(1024);
    let seed = m.tree.seed.unwrap_or(0);
    let go = arbor::export::gltf_mesh_options(o).map_err(|e| anyhow!("{out}: {e}"))?;
    let skeleton = &look
        .finish(skeleton)
        .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
    if let Some(game) = Game::of(m)? {
        if obj {
            bail!("{out}: levels of detail and impostors are for glTF (nodes); OBJ has none");
        }
        let (tree_options, leaves) = arbor::species::options(look, skeleton, &go)
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        let leaves = leaves.seed(seed);
        let bark = arbor::texture::bark_textures(&look.bark, size, seed)
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        let atlas = arbor::texture::leaf_atlas(&look.leaf, size, seed)
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        let bark_color = mean_color(&bark.color);
        let atlas_image = atlas.image.clone();
        let scene = game
            .scene(
                skeleton,
                &tree_options,
                Some(&leaves),
                Some(&atlas_image),
                bark_color,
                |scene| scene.texture(bark, atlas),
            )
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        arbor::export::save_gltf_scene(&scene, o, out).map_err(|e| anyhow!("{out}: {e}"))?;
        game.report(&scene, out, skeleton.len(), what, grow_ms, t1);
        return Ok(());
    }
    let mut scene = arbor::species::tree_scene(look, skeleton, &go, size, seed)
        .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
    if let Some(names) = collision_names(m) {
        if obj {
            bail!("{out}: --collision is for glTF (capsule nodes); OBJ has no nodes");
        }
        let (tree_options, _) = arbor::species::options(look, skeleton, &go)
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        let capsules = arbor::collision::capsules(skeleton, COLLISION_CAPSULES, 0.0, &tree_options)
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        scene.collide_for(&capsules, names);
    }
    if m.wind.as_deref() == Some("skin") {
        if obj {
            bail!("{out}: --wind skin is for glTF (a skin and a clip); OBJ has neither");
        }
        let (tree_options, leaves) = arbor::species::options(look, skeleton, &go)
            .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
        wind_skin(
            &mut scene,
            skeleton,
            &tree_options,
            Some(&leaves.seed(seed)),
            seed,
        )
        .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
    }
    if obj {
        arbor::export::save_obj_scene(&scene, out).map_err(|e| anyhow!("{out}: {e}"))?;
    } else {
        arbor::export::save_gltf_scene(&scene, o, out).map_err(|e| anyhow!("{out}: {e}"))?;
    }
    // Vertices a card: its shape's.
    let (_, leaf_options) = arbor::species::options(look, skeleton, &go)
        .map_err(|e| anyhow!("{}: {e}", m.tree.source))?;
    let per_card = leaf_options.shape().vertices.len().max(1);
    let cards = scene
        .meshes
        .iter()
        .flat_map(|m| &m.primitives)
        .filter(|p| scene.materials[p.material].name == "leaves")
        .map(|p| p.mesh.vertices.len() / per_card)
        .sum::<usize>();
    if look.twig_length > 0.0 {
        eprintln!("leaves: {cards} leaf cards of the species, on its twigs and young tips");
    } else {
        eprintln!("leaves: {cards} leaf cards of the species, at its buds and young tips");
    }
    eprintln!(
        "{out}: {} branches ({what}), {} m tall, textures {size} px; grown in {grow_ms:.1} ms, \
         written in {:.1} ms",
        skeleton.len(),
        look.height,
        t1.elapsed().as_secs_f64() * 1e3
    );
    Ok(())
}

/// The leaves `--leaves PLACE` (or `--instanced-leaves`) places, reported on stderr.
fn placed_leaves(m: &ExportArgs, skeleton: &Skeleton, place: &str) -> Result<LeafOptions> {
    let source = &m.tree.source;
    let (l, note) = leaf_options(skeleton, place, m.leaf_size, source)?;
    let o = MeshOptions::default();
    let n = arbor::mesh::leaf_instances(skeleton, &l, &o)?.len();
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
fn info(m: &InfoArgs, skeleton: &Skeleton, what: &str, grow_ms: f64) -> Result<()> {
    let o = MeshOptions::default();
    let t1 = Instant::now();
    let size = arbor::mesh::mesh_size(skeleton, &o)?;
    let mesh_ms = t1.elapsed().as_secs_f64() * 1e3;
    let (branches, leaves, polygons, organs) = (
        skeleton.len(),
        skeleton.leaves().len(),
        skeleton.polygons().len(),
        skeleton.organs().len(),
    );
    if m.json {
        let json = serde_json::json!({
            "source": m.tree.source,
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
