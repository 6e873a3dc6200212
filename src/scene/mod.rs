//! A scene: what an asset file holds, built from trees and forests and not yet in any
//! format. Meshes (each of primitives: an arbor [`Mesh`] with its material and, for bark,
//! its animation stream), materials, and nodes that place a mesh (with a transform, or
//! once per leaf instance), with the settings the trees were made with.
//!
//! The writers of [`crate::export`] only serialize a scene; what later assets add
//! (textures, levels of detail, skins, collision nodes) goes into the scene.
//!
//! ```
//! use arbor::mesh::MeshOptions;
//! use arbor::scene::Scene;
//!
//! let mut p = arbor::HondaParams::preset('a').unwrap();
//! p.steps = 4;
//! let tree = arbor::models::honda::build(&p).unwrap();
//! let scene = Scene::tree(&tree, &MeshOptions::default(), None).unwrap();
//! assert_eq!(scene.meshes.len(), 1);
//! assert_eq!(scene.materials[scene.meshes[0].primitives[0].material].name, "bark");
//! let glb = arbor::export::gltf_scene_bytes(&scene, &MeshOptions::default(), true).unwrap();
//! assert_eq!(&glb[..4], b"glTF");
//! ```

use crate::error::Result;
use crate::forest::Placed;
use crate::mesh::{self, AnimationVertex, LeafInstance, LeafOptions, Mesh, MeshOptions, Topology};
use crate::progress::Run;
use crate::skeleton::Skeleton;

/// What an asset file holds (see the [module](self)).
#[derive(Clone, Debug, Default)]
pub struct Scene {
    /// The meshes, each drawn by the nodes that name it.
    pub meshes: Vec<SceneMesh>,
    /// The materials the primitives name; the bark's first.
    pub materials: Vec<Material>,
    /// The images the materials sample (PNG in a file).
    pub textures: Vec<Texture>,
    /// The nodes, in the order a file lists them.
    pub nodes: Vec<Node>,
    /// What the scene was made from.
    pub settings: Settings,
    /// The bones the skinned primitives ride and their looping clip, or none (glTF: a
    /// node per bone, a skin on the first node, an animation "wind").
    pub rig: Option<SceneRig>,
}

/// A scene's skeleton of bones and its clip.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneRig {
    /// The bones (parents first), in the scene's space.
    pub bones: Vec<crate::wind::Bone>,
    /// The clip that moves them.
    pub clip: Option<crate::wind::Clip>,
}

/// A mesh of the scene: one or more primitives drawn together.
#[derive(Clone, Debug)]
pub struct SceneMesh {
    /// Its name in the file.
    pub name: String,
    /// Its parts, none of them empty.
    pub primitives: Vec<Primitive>,
}

/// A part of a mesh with one material.
#[derive(Clone, Debug)]
pub struct Primitive {
    /// The vertices and indices.
    pub mesh: Mesh,
    /// Index into [`Scene::materials`].
    pub material: usize,
    /// Per vertex, the growth time and wind weights (the bark's), or none.
    pub animation: Option<Vec<AnimationVertex>>,
    /// Per vertex, the bones of [`Scene::rig`] it rides and their weights, or none.
    pub skin: Option<Vec<crate::wind::Influence>>,
    /// Per vertex, wind data in standard attributes (glTF `COLOR_0`, `TEXCOORD_1`), or none.
    pub wind: Option<Vec<crate::wind::WindVertex>>,
}

/// A surface: a metallic-roughness material with a base colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Its name in the file.
    pub name: String,
    /// Drawn from both sides (leaves).
    pub double_sided: bool,
    /// Linear RGBA.
    pub base_color: [f32; 4],
    /// 0: a dielectric.
    pub metallic: f32,
    /// 0 (mirror) ..= 1 (matte).
    pub roughness: f32,
    /// Index into [`Scene::textures`] of the base colour (sRGB, times `base_color`).
    pub base_color_texture: Option<usize>,
    /// Index into [`Scene::textures`] of a tangent-space normal map.
    pub normal_texture: Option<usize>,
    /// Index into [`Scene::textures`] of a metallic-roughness map (glTF's layout: green
    /// roughness, blue metalness; times `roughness` and `metallic`).
    pub metallic_roughness_texture: Option<usize>,
    /// Alpha-cut: texels whose alpha is below this are not drawn (glTF's `MASK`); none:
    /// opaque.
    pub alpha_cutoff: Option<f32>,
}

/// An image of the scene, sampled with repeat in both directions.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Its name in the file.
    pub name: String,
    /// The pixels.
    pub image: crate::texture::Image,
}

impl Material {
    /// Samples bark textures (indices into [`Scene::textures`]): colour, normal and
    /// roughness maps, its colour and roughness factors 1.
    fn texture_bark(&mut self, color: usize, normal: usize, rough: usize) {
        self.base_color = [1.0; 4];
        self.base_color_texture = Some(color);
        self.normal_texture = Some(normal);
        self.metallic_roughness_texture = Some(rough);
        self.roughness = 1.0;
    }

    /// Samples a leaf atlas (an index into [`Scene::textures`]): white, alpha-cut at 0.5,
    /// double-sided.
    fn texture_leaves(&mut self, atlas: usize) {
        self.base_color = [1.0; 4];
        self.base_color_texture = Some(atlas);
        self.alpha_cutoff = Some(0.5);
        self.double_sided = true;
    }

    /// Bark: brown, matte, one-sided.
    pub fn bark() -> Self {
        Material {
            name: "bark".into(),
            double_sided: false,
            base_color: [0.36, 0.24, 0.14, 1.0],
            metallic: 0.0,
            roughness: 0.9,
            base_color_texture: None,
            normal_texture: None,
            metallic_roughness_texture: None,
            alpha_cutoff: None,
        }
    }

    /// The ground: grass green, fully rough.
    pub fn ground() -> Self {
        Material {
            name: "ground".into(),
            base_color: [0.20, 0.26, 0.12, 1.0],
            roughness: 1.0,
            ..Material::bark()
        }
    }

    /// Leaves: green, double-sided.
    pub fn leaves() -> Self {
        Material {
            name: "leaves".into(),
            double_sided: true,
            base_color: [0.22, 0.52, 0.16, 1.0],
            metallic: 0.0,
            roughness: 0.8,
            base_color_texture: None,
            normal_texture: None,
            metallic_roughness_texture: None,
            alpha_cutoff: None,
        }
    }
}

/// A node: a mesh placed once (by its transform), or once per instance.
#[derive(Clone, Debug)]
pub struct Node {
    /// Its name in the file.
    pub name: String,
    /// Index into [`Scene::meshes`]; none for a tree without triangles.
    pub mesh: Option<usize>,
    /// Where the mesh stands; none: the identity.
    pub transform: Option<Transform>,
    /// Draw the mesh once per instance (leaves as instances of one leaf), or none.
    pub instances: Option<Vec<LeafInstance>>,
    /// The collision capsule this node's mesh is (in the file's node extras as
    /// `arbor_capsule`), or none.
    pub capsule: Option<crate::collision::Capsule>,
    /// This node is the first level of a level-of-detail group (glTF: `MSFT_lod` and
    /// `MSFT_screencoverage`), or none.
    pub lod: Option<NodeLod>,
    /// The octahedral impostor of the tree this node draws (in the file's node extras as
    /// `arbor_impostor`), or none.
    pub impostor: Option<ImpostorInfo>,
    /// Each branch's pivot ([`crate::wind::pivots`]; in the file, two VEC4 accessors
    /// named in the node's extras as `arbor_pivots`), or none.
    pub pivots: Option<Vec<[f32; 8]>>,
}

/// Whose importer collision nodes are named for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CollisionNames {
    /// Unreal's `UCP_` prefix (a capsule collision of the mesh it names).
    Unreal,
    /// Godot's `-convcolonly` suffix (a convex collision shape, the mesh dropped).
    Godot,
}

/// A level-of-detail group: the nodes of the lower levels, and from which screen
/// coverage each level is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeLod {
    /// Indices into [`Scene::nodes`] of levels 1, 2, ... (level 0 is the node itself).
    pub levels: Vec<usize>,
    /// One more than `levels`: level k is drawn while the tree covers at least
    /// `coverage[k]` of the screen's height (the last: below it, nothing).
    pub coverage: Vec<f32>,
}

/// Where an octahedral impostor's atlases are and how a shader reads them (see
/// [`crate::impostor`]).
#[derive(Clone, Debug, PartialEq)]
pub struct ImpostorInfo {
    /// Views a side of the grid.
    pub frames: u32,
    /// Pixels a side of a view.
    pub cell: u32,
    /// The upper half of the sphere (else the whole).
    pub hemi: bool,
    /// The bounding sphere's centre.
    pub centre: [f32; 3],
    /// Its radius.
    pub radius: f32,
    /// The up axis.
    pub up: [f32; 3],
    /// Index into [`Scene::textures`] of the albedo atlas.
    pub albedo: usize,
    /// Index into [`Scene::textures`] of the normal and depth atlas.
    pub normal: usize,
    /// Drawn while the tree covers less of the screen's height than this.
    pub below: f32,
}

impl Node {
    fn new(name: impl Into<String>, mesh: Option<usize>) -> Self {
        Node {
            name: name.into(),
            mesh,
            transform: None,
            instances: None,
            capsule: None,
            lod: None,
            impostor: None,
            pivots: None,
        }
    }
}

/// A translation, a rotation (unit quaternion x, y, z, w) and a uniform scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    /// Where the origin goes.
    pub translation: [f32; 3],
    /// The turn, as a unit quaternion (x, y, z, w).
    pub rotation: [f32; 4],
    /// Uniform scale.
    pub scale: f32,
}

/// What a scene was made from (a glTF file keeps it in `asset.extras`); each kind of
/// scene fills its own members.
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Settings {
    /// Branches of the tree.
    pub branches: Option<usize>,
    /// Trees of the forest.
    pub trees: Option<usize>,
    /// Distinct trees (each one mesh) of the forest.
    pub distinct_trees: Option<usize>,
    /// Sides of the bark's tubes.
    pub radial_segments: u32,
    /// Rings inside each branch.
    pub curve_rings: Option<u32>,
    /// The mesh's scale.
    pub scale: Option<f32>,
    /// Whether baked leaves are there (asked for and found somewhere to go).
    pub leaves: Option<bool>,
    /// Leaves drawn as instances.
    pub leaf_instances: Option<usize>,
}

impl Scene {
    /// One tree: a node "tree" drawing a mesh "tree" of the bark (with its animation
    /// stream) and, when `leaves` is given, the baked leaves; a part without triangles is
    /// left out. The meshes are in `options`' conventions.
    pub fn tree(
        skeleton: &Skeleton,
        options: &MeshOptions,
        leaves: Option<&LeafOptions>,
    ) -> Result<Scene> {
        Scene::tree_in(skeleton, options, leaves, &mut Run::default())
    }

    /// [`tree`](Self::tree) in `run`: the bark is meshed on the run's threads, reporting
    /// as [`MeshPlan::mesh_in`](crate::mesh::MeshPlan::mesh_in) does.
    pub fn tree_in(
        skeleton: &Skeleton,
        options: &MeshOptions,
        leaves: Option<&LeafOptions>,
        run: &mut Run<'_>,
    ) -> Result<Scene> {
        let mut scene = Scene::default();
        let plan = mesh::MeshPlan::new_in(skeleton, options, run)?;
        let bark = plan.mesh_in(skeleton, run)?;
        let animation = plan.animation(skeleton)?;
        let mut primitives = Vec::new();
        scene.add(&mut primitives, bark, Material::bark(), Some(animation));
        if let Some(l) = leaves {
            let baked = mesh::leaf_mesh(skeleton, l, options)?;
            scene.add(&mut primitives, baked, Material::leaves(), None);
        }
        scene.settings = Settings {
            branches: Some(skeleton.len()),
            radial_segments: options.radial_segments,
            curve_rings: Some(options.curve_rings),
            scale: Some(options.scale),
            leaves: Some(scene.materials.contains(&Material::leaves())),
            ..Settings::default()
        };
        scene.one_tree(primitives);
        Ok(scene)
    }

    /// One tree with its leaves as instances of one leaf mesh (the leaf options' prefab,
    /// else the quad): the tree's node and mesh as [`tree`](Self::tree) makes them
    /// without leaves, then a mesh "leaf" and a node "leaves" that draws it once per leaf
    /// site (no polygons or spheres). No leaf sites: no leaf mesh or node.
    pub fn tree_instanced(
        skeleton: &Skeleton,
        options: &MeshOptions,
        leaves: &LeafOptions,
    ) -> Result<Scene> {
        Scene::tree_instanced_in(skeleton, options, leaves, &mut Run::default())
    }

    /// [`tree_instanced`](Self::tree_instanced) in `run`, as [`tree_in`](Self::tree_in).
    pub fn tree_instanced_in(
        skeleton: &Skeleton,
        options: &MeshOptions,
        leaves: &LeafOptions,
        run: &mut Run<'_>,
    ) -> Result<Scene> {
        let mut scene = Scene::tree_in(skeleton, options, None, run)?;
        let instances = mesh::leaf_instances(skeleton, leaves, options)?;
        let prefab = leaves
            .prefab
            .clone()
            .unwrap_or_else(|| std::sync::Arc::new(mesh::LeafPrefab::quad()));
        let leaf = Mesh {
            vertices: prefab.vertices.clone(),
            indices: prefab.triangles.iter().flatten().copied().collect(),
            topology: Topology::TriangleList,
            ranges: Vec::new(),
        };
        scene.settings = Settings {
            branches: Some(skeleton.len()),
            radial_segments: options.radial_segments,
            leaf_instances: Some(instances.len()),
            ..Settings::default()
        };
        if !instances.is_empty() {
            // A prefab without triangles adds nothing (`add` leaves it out).
            let mut primitives = Vec::new();
            scene.add(&mut primitives, leaf, Material::leaves(), None);
            if let Some(mesh) = scene.push_mesh("leaf", primitives) {
                let mut node = Node::new("leaves", Some(mesh));
                node.instances = Some(instances);
                scene.nodes.push(node);
            }
        }
        Ok(scene)
    }

    /// A forest merged into one bark mesh (one draw call), as
    /// [`forest::merged`](crate::forest::merged) places the trees.
    pub fn forest(placed: &[Placed<'_>], options: &MeshOptions) -> Result<Scene> {
        let mut scene = Scene::default();
        let merged = crate::forest::merged(placed, options)?;
        let mut primitives = Vec::new();
        scene.add(&mut primitives, merged, Material::bark(), None);
        scene.settings = Settings {
            trees: Some(placed.len()),
            radial_segments: options.radial_segments,
            scale: Some(options.scale),
            ..Settings::default()
        };
        scene.one_tree(primitives);
        Ok(scene)
    }

    /// A forest as one node per placed tree ("tree k", with the placement's translation,
    /// rotation about Y and uniform scale): one mesh per distinct tree (same source and
    /// seed, as [`forest::instanced`](crate::forest::instanced) finds them), shared by
    /// every node that places it. An engine keeps each tree a node of its own (to move,
    /// cull or swap); [`forest`](Self::forest) merges.
    pub fn forest_nodes(placed: &[Placed<'_>], options: &MeshOptions) -> Result<Scene> {
        let mut scene = Scene::default();
        let (meshes, which) = crate::forest::instanced(placed, options)?;
        let distinct = meshes.len();
        let mut mesh_of = Vec::with_capacity(distinct);
        for m in meshes {
            let mut primitives = Vec::new();
            scene.add(&mut primitives, m, Material::bark(), None);
            mesh_of.push(scene.push_mesh("tree", primitives));
        }
        for (k, (p, (mesh, _))) in placed.iter().zip(which).enumerate() {
            let q = crate::geom::rotation::axis_angle(glam::Vec3::Y, p.rotation.to_radians());
            let mut node = Node::new(format!("tree {k}"), mesh_of[mesh as usize]);
            node.transform = Some(Transform {
                translation: p.position,
                rotation: q.to_array(),
                scale: p.scale,
            });
            scene.nodes.push(node);
        }
        scene.settings = Settings {
            trees: Some(placed.len()),
            distinct_trees: Some(distinct),
            radial_segments: options.radial_segments,
            scale: Some(options.scale),
            ..Settings::default()
        };
        Ok(scene)
    }

    /// A world's trees as one node each, named `NAME_k` by the name of its species slot
    /// (`names[slot]`, "tree" past the list) and its index `k` in the world, in world
    /// space (a world's units are metres: the mesh options' scale stands). Each tree's
    /// mesh is its bark and, when `leaves` is given, its baked leaves. A slot named for a
    /// species with a look of its own ([`crate::species::Look`]: oak, pine, ...) gets
    /// that species' bark and leaf textures (`texture_size` pixels square; 0: untextured)
    /// as materials `bark NAME` and `leaves NAME`, and is shaped and leafed as the species
    /// shapes and leafs its own trees ([`Look::finish`](crate::species::Look::finish),
    /// [`crate::species::options`]; leaves and bark tiles in metres). With `ground`, the world's height field is a node "ground" (material
    /// "ground"). A tree that starved to nothing is a node without a mesh.
    pub fn world(
        world: &crate::models::growth::World,
        names: &[&str],
        options: &MeshOptions,
        leaves: Option<&LeafOptions>,
        texture_size: u32,
        ground: bool,
    ) -> Result<Scene> {
        use crate::models::growth::Species;
        use crate::species::Look;
        let mut scene = Scene::default();
        // The textured materials of each named slot, made once.
        let mut looks: Vec<Option<(Look, Material, Material)>> = Vec::new();
        for (k, name) in names.iter().enumerate() {
            let look = Species::from_name(name).and_then(Look::of);
            looks.push(match look {
                Some(look) if texture_size > 0 => {
                    let bark = crate::texture::bark_textures(&look.bark, texture_size, k as u64)?;
                    let atlas = crate::texture::leaf_atlas(&look.leaf, texture_size, k as u64)?;
                    let [color, normal, rough, atlas_index] =
                        scene.push_textures(bark, atlas, &format!(" {name}"));
                    let mut bark = Material::bark();
                    bark.texture_bark(color, normal, rough);
                    bark.name = format!("bark {name}");
                    let mut leaves = Material::leaves();
                    leaves.texture_leaves(atlas_index);
                    leaves.name = format!("leaves {name}");
                    Some((look, bark, leaves))
                }
                _ => None,
            });
        }
        let mut branches = 0;
        for k in 0..world.tree_count() {
            let skeleton = world.tree(k)?;
            branches += skeleton.len();
            let slot = world.tree_slot(k)? as usize;
            let name = names.get(slot).copied().unwrap_or("tree");
            let look = looks.get(slot).and_then(|l| l.as_ref());
            let mut o = *options;
            let mut l = leaves.cloned();
            let mut skeleton = skeleton;
            let (bark_material, leaf_material) = match look {
                Some((look, bark, leaf)) if !skeleton.is_empty() => {
                    // Shaped as the species shapes its own trees, its leaves and bark in
                    // metres (the species' options size the tree to its adult height: the
                    // world keeps its own).
                    skeleton = look.finish(&skeleton)?;
                    let (so, sl) = crate::species::options(look, &skeleton, options)?;
                    let f = so.scale / options.scale;
                    o = so;
                    o.scale = options.scale;
                    o.texture_scale = look.bark.tile;
                    l = l.map(|_| {
                        let mut sl = sl.seed(k as u64);
                        sl.size *= f;
                        sl.wood_clearance *= f;
                        sl
                    });
                    (bark.clone(), leaf.clone())
                }
                _ => (Material::bark(), Material::leaves()),
            };
            let mut primitives = Vec::new();
            if !skeleton.is_empty() {
                let bark = mesh::MeshPlan::new(&skeleton, &o)?.mesh(&skeleton)?;
                scene.add(&mut primitives, bark, bark_material, None);
                if let Some(l) = &l {
                    let baked = mesh::leaf_mesh(&skeleton, l, &o)?;
                    scene.add(&mut primitives, baked, leaf_material, None);
                }
            }
            let node_name = format!("{name}_{k}");
            let mesh = scene.push_mesh(&node_name, primitives);
            scene.nodes.push(Node::new(node_name, mesh));
        }
        if ground && let Some(g) = world.ground() {
            let mut m = g.mesh();
            for v in &mut m.vertices {
                v.position = v.position.map(|p| p * options.scale);
            }
            let mut primitives = Vec::new();
            scene.add(&mut primitives, m, Material::ground(), None);
            let mesh = scene.push_mesh("ground", primitives);
            scene.nodes.push(Node::new("ground", mesh));
        }
        scene.settings = Settings {
            branches: Some(branches),
            trees: Some(world.tree_count()),
            radial_segments: options.radial_segments,
            scale: Some(options.scale),
            leaves: Some(leaves.is_some()),
            ..Settings::default()
        };
        Ok(scene)
    }

    /// Textures the bark and leaf materials: the bark samples `bark`'s colour, normal and
    /// roughness maps (its colour and roughness factors 1), the leaves `atlas` (alpha-cut at 0.5, double-sided,
    /// white). The meshes must carry the uvs these images expect: bark with
    /// `texture_scale` the bark's tile, baked leaves with the atlas' columns and rows
    /// ([`LeafOptions::atlas_columns`]). A material of another name is left as it is.
    pub fn texture(
        &mut self,
        bark: crate::texture::BarkTextures,
        atlas: crate::texture::LeafAtlas,
    ) {
        let [color, normal, rough, leaves] = self.push_textures(bark, atlas, "");
        for m in &mut self.materials {
            match m.name.as_str() {
                "bark" => m.texture_bark(color, normal, rough),
                "leaves" => m.texture_leaves(leaves),
                _ => {}
            }
        }
    }

    /// Pushes a species' bark colour, normal and roughness maps and its leaf atlas, named
    /// "bark", "bark normal", "bark roughness" and "leaves" followed by `suffix`; their
    /// indices in [`Scene::textures`].
    fn push_textures(
        &mut self,
        bark: crate::texture::BarkTextures,
        atlas: crate::texture::LeafAtlas,
        suffix: &str,
    ) -> [usize; 4] {
        let mut push = |name: &str, image: crate::texture::Image| {
            self.textures.push(Texture {
                name: format!("{name}{suffix}"),
                image,
            });
            self.textures.len() - 1
        };
        [
            push("bark", bark.color),
            push("bark normal", bark.normal),
            push("bark roughness", bark.roughness),
            push("leaves", atlas.image),
        ]
    }

    /// The levels of detail of one tree ([`crate::lod::chain`]) as nodes `NAME_LOD0`,
    /// `NAME_LOD1`, ... (the suffix engines' importers group), each drawing a mesh of the
    /// level's bark and baked leaves, the first carrying the group and its coverages. The
    /// meshes are in the levels' own options' conventions.
    pub fn levels(levels: &[crate::lod::Level], name: &str) -> Scene {
        let mut scene = Scene::default();
        let mut nodes = Vec::new();
        for (k, level) in levels.iter().enumerate() {
            let mut primitives = Vec::new();
            scene.add(&mut primitives, level.bark.clone(), Material::bark(), None);
            if let Some(l) = &level.leaves {
                scene.add(&mut primitives, l.clone(), Material::leaves(), None);
            }
            let label = format!("{name}_LOD{k}");
            let mesh = scene.push_mesh(&label, primitives);
            scene.nodes.push(Node::new(label, mesh));
            nodes.push(scene.nodes.len() - 1);
        }
        if let Some(first) = nodes.first().copied() {
            scene.nodes[first].lod = Some(NodeLod {
                levels: nodes[1..].to_vec(),
                coverage: levels.iter().map(|l| l.screen_coverage).collect(),
            });
        }
        if let Some(full) = levels.first() {
            scene.settings = Settings {
                radial_segments: full.mesh_options.radial_segments,
                scale: Some(full.mesh_options.scale),
                leaves: Some(full.leaves.is_some()),
                ..Settings::default()
            };
        }
        scene
    }

    /// Adds `billboard` as the last level of the scene's level-of-detail group (a node
    /// `NAME_LODn` after the others, its quads sampling the billboard's albedo, alpha-cut
    /// at one half and two-sided), drawn down to `coverage` of the screen's height.
    pub fn billboard(
        &mut self,
        billboard: &crate::impostor::Billboard,
        clockwise: bool,
        coverage: f32,
    ) {
        let Some(first) = self.nodes.iter().position(|n| n.lod.is_some()) else {
            return;
        };
        self.textures.push(Texture {
            name: "billboard".into(),
            image: billboard.albedo.clone(),
        });
        let material = Material {
            name: "billboard".into(),
            double_sided: true,
            base_color: [1.0; 4],
            base_color_texture: Some(self.textures.len() - 1),
            alpha_cutoff: Some(0.5),
            ..Material::leaves()
        };
        let mut primitives = Vec::new();
        self.add(&mut primitives, billboard.mesh(clockwise), material, None);
        let base = self.nodes[first].name.trim_end_matches("_LOD0").to_string();
        let lod = self.nodes[first]
            .lod
            .as_ref()
            .map_or(0, |l| l.levels.len() + 1);
        let label = format!("{base}_LOD{lod}");
        let mesh = self.push_mesh(&label, primitives);
        self.nodes.push(Node::new(label, mesh));
        let node = self.nodes.len() - 1;
        if let Some(l) = self.nodes[first].lod.as_mut() {
            l.levels.push(node);
            l.coverage.push(coverage);
        }
    }

    /// Adds an octahedral impostor's atlases as textures ("impostor albedo", "impostor
    /// normal") and what a shader needs to draw them to the first node's extras
    /// (`arbor_impostor`), for the coverage below `below`.
    pub fn impostor(&mut self, impostor: &crate::impostor::Impostor, below: f32) {
        if self.nodes.is_empty() {
            return;
        }
        let mut push = |name: &str, image: &crate::texture::Image| {
            self.textures.push(Texture {
                name: name.into(),
                image: image.clone(),
            });
            self.textures.len() - 1
        };
        let albedo = push("impostor albedo", &impostor.albedo);
        let normal = push("impostor normal", &impostor.normal);
        self.nodes[0].impostor = Some(ImpostorInfo {
            frames: impostor.frames,
            cell: impostor.cell,
            hemi: impostor.sphere == crate::impostor::Sphere::Hemi,
            centre: impostor.centre,
            radius: impostor.radius,
            up: impostor.up,
            albedo,
            normal,
            below,
        });
    }

    /// Skins the first node's mesh on `rig`: each primitive's influences in `influences`
    /// (one list per primitive, one influence per vertex), and `clip` to play. A list of
    /// the wrong length is an error naming it.
    pub fn skin(
        &mut self,
        rig: &crate::wind::Rig,
        influences: Vec<Vec<crate::wind::Influence>>,
        clip: Option<crate::wind::Clip>,
    ) -> Result<()> {
        if self.nodes.is_empty() {
            return Err(crate::Error::invalid("scene", "no mesh to skin"));
        }
        self.skin_nodes(rig, vec![(0, influences)], clip)
    }

    /// Skins the meshes of several nodes (a chain's levels) on one `rig`: for each node
    /// (an index into [`nodes`](Self::nodes)), its primitives' influences (one list per
    /// primitive, one influence per vertex), and `clip` to play. A node without a mesh or
    /// a list of the wrong length is an error naming it.
    pub fn skin_nodes(
        &mut self,
        rig: &crate::wind::Rig,
        nodes: Vec<(usize, Vec<Vec<crate::wind::Influence>>)>,
        clip: Option<crate::wind::Clip>,
    ) -> Result<()> {
        for (node, influences) in nodes {
            let Some(mesh) = self.nodes.get(node).and_then(|n| n.mesh) else {
                return Err(crate::Error::invalid(
                    "scene",
                    format!("node {node} has no mesh to skin"),
                ));
            };
            let prims = &mut self.meshes[mesh].primitives;
            if influences.len() != prims.len() {
                return Err(crate::Error::invalid(
                    "influences",
                    format!(
                        "node {node}: {} lists; expected one per primitive ({})",
                        influences.len(),
                        prims.len()
                    ),
                ));
            }
            if let Some((k, (p, i))) = prims
                .iter()
                .zip(&influences)
                .enumerate()
                .find(|(_, (p, i))| i.len() != p.mesh.vertices.len())
            {
                return Err(crate::Error::invalid(
                    "influences",
                    format!(
                        "node {node}, primitive {k}: {} influences; expected one per vertex ({})",
                        i.len(),
                        p.mesh.vertices.len()
                    ),
                ));
            }
            for (p, i) in prims.iter_mut().zip(influences) {
                p.skin = Some(i);
            }
        }
        self.rig = Some(SceneRig {
            bones: rig.bones.clone(),
            clip,
        });
        Ok(())
    }

    /// Gives the first node's mesh wind attributes: `attributes` one list per primitive,
    /// one entry per vertex ([`crate::wind::bark_attributes`], `leaf_attributes`). A list
    /// of the wrong length is an error naming it.
    pub fn wind_attributes(&mut self, attributes: Vec<Vec<crate::wind::WindVertex>>) -> Result<()> {
        let Some(mesh) = self.nodes.first().and_then(|n| n.mesh) else {
            return Err(crate::Error::invalid(
                "scene",
                "no mesh to give wind attributes",
            ));
        };
        let prims = &mut self.meshes[mesh].primitives;
        if attributes.len() != prims.len()
            || prims
                .iter()
                .zip(&attributes)
                .any(|(p, a)| a.len() != p.mesh.vertices.len())
        {
            return Err(crate::Error::invalid(
                "attributes",
                "expected one list per primitive, one entry per vertex",
            ));
        }
        for (p, a) in prims.iter_mut().zip(attributes) {
            p.wind = Some(a);
        }
        Ok(())
    }

    /// Puts each branch's pivot ([`crate::wind::pivots`]) on the first node, for a
    /// Pivot-Painter-style shader that finds a vertex's row by its `TEXCOORD_2`.x.
    pub fn pivots(&mut self, pivots: Vec<[f32; 8]>) {
        if let Some(n) = self.nodes.first_mut() {
            n.pivots = Some(pivots);
        }
    }

    /// Adds collision capsules (from [`capsules`](crate::collision::capsules), in the
    /// scene's conventions): each a node and a mesh named `UCP_<tree>_NN` (Unreal's
    /// prefix for a capsule collision of the mesh `<tree>`, the scene's first node), a
    /// low-poly capsule (8 sides, 3 bands a cap) with a material "collision", and the
    /// capsule itself in the node's extras.
    pub fn collide(&mut self, capsules: &[crate::collision::Capsule]) {
        self.collide_for(capsules, CollisionNames::Unreal);
    }

    /// [`collide`](Self::collide) with the nodes named for `names`' importer: Unreal's
    /// `UCP_<tree>_NN`, or Godot's `<tree>_col_NN-convcolonly` (Godot's importer makes a
    /// convex collision shape of the mesh and drops the mesh).
    pub fn collide_for(&mut self, capsules: &[crate::collision::Capsule], names: CollisionNames) {
        if capsules.is_empty() {
            return;
        }
        let tree = self.nodes.first().map_or_else(
            || "tree".to_string(),
            |n| n.name.trim_end_matches("_LOD0").to_string(),
        );
        let material = self.materials.len();
        self.materials.push(Material {
            name: "collision".into(),
            base_color: [0.5, 0.5, 0.5, 1.0],
            ..Material::bark()
        });
        for (k, c) in capsules.iter().enumerate() {
            let name = match names {
                CollisionNames::Unreal => format!("UCP_{tree}_{k:02}"),
                CollisionNames::Godot => format!("{tree}_col_{k:02}-convcolonly"),
            };
            self.meshes.push(SceneMesh {
                name: name.clone(),
                primitives: vec![Primitive {
                    mesh: capsule_mesh(c, 8, 3),
                    material,
                    animation: None,
                    skin: None,
                    wind: None,
                }],
            });
            let mut node = Node::new(name, Some(self.meshes.len() - 1));
            node.capsule = Some(*c);
            self.nodes.push(node);
        }
    }

    /// Adds `mesh` with `material` to `primitives` unless it has no triangles; the
    /// material joins the scene's list where it is new (the builders add the bark first).
    fn add(
        &mut self,
        primitives: &mut Vec<Primitive>,
        mesh: Mesh,
        material: Material,
        animation: Option<Vec<AnimationVertex>>,
    ) {
        if mesh.indices.is_empty() {
            return;
        }
        let material = match self.materials.iter().position(|m| *m == material) {
            Some(k) => k,
            None => {
                self.materials.push(material);
                self.materials.len() - 1
            }
        };
        primitives.push(Primitive {
            mesh,
            material,
            animation,
            skin: None,
            wind: None,
        });
    }

    /// The mesh of `primitives` named `name`, and its index; none when it has none.
    fn push_mesh(&mut self, name: &str, primitives: Vec<Primitive>) -> Option<usize> {
        if primitives.is_empty() {
            return None;
        }
        self.meshes.push(SceneMesh {
            name: name.into(),
            primitives,
        });
        Some(self.meshes.len() - 1)
    }

    /// A node "tree" at the origin drawing the mesh "tree" of `primitives` (none when
    /// they are empty).
    fn one_tree(&mut self, primitives: Vec<Primitive>) {
        let mesh = self.push_mesh("tree", primitives);
        self.nodes.push(Node::new("tree", mesh));
    }
}

/// A capsule as triangles: a pole vertex at each end and `bands` rings per cap of
/// `sides` vertices, counter-clockwise seen from outside, normals outward.
fn capsule_mesh(c: &crate::collision::Capsule, sides: usize, bands: usize) -> Mesh {
    use glam::Vec3;
    let (a, b) = (Vec3::from(c.a), Vec3::from(c.b));
    let axis = (b - a).try_normalize().unwrap_or(Vec3::Y);
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let mut vertices = Vec::with_capacity(2 + 2 * bands * sides);
    let mut put = |centre: Vec3, n: Vec3| {
        vertices.push(crate::mesh::Vertex {
            position: (centre + n * c.radius).to_array(),
            normal: n.to_array(),
            uv: [0.0, 0.0],
        })
    };
    put(a, -axis);
    // Latitudes from the pole at `a` to the equator, then from the equator to `b`'s pole.
    let half = std::f32::consts::FRAC_PI_2;
    let rings: Vec<(Vec3, f32)> = (1..=bands)
        .map(|j| (a, -half + half * j as f32 / bands as f32))
        .chain((0..bands).map(|j| (b, half * j as f32 / bands as f32)))
        .collect();
    for &(centre, phi) in &rings {
        for s in 0..sides {
            let t = std::f32::consts::TAU * s as f32 / sides as f32;
            let around = u * t.cos() + v * t.sin();
            put(centre, around * phi.cos() + axis * phi.sin());
        }
    }
    put(b, axis);
    let ring = |r: usize, s: usize| (1 + r * sides + s % sides) as u32;
    let last = (vertices.len() - 1) as u32;
    let mut indices = Vec::new();
    for s in 0..sides {
        indices.extend([0, ring(0, s + 1), ring(0, s)]);
    }
    for r in 0..rings.len() - 1 {
        for s in 0..sides {
            let (p, q) = (ring(r, s), ring(r, s + 1));
            let (p2, q2) = (ring(r + 1, s), ring(r + 1, s + 1));
            indices.extend([p, q, q2, p, q2, p2]);
        }
    }
    for s in 0..sides {
        let r = rings.len() - 1;
        indices.extend([ring(r, s), ring(r, s + 1), last]);
    }
    Mesh {
        vertices,
        indices,
        topology: crate::mesh::Topology::TriangleList,
        ranges: Vec::new(),
    }
}

#[cfg(test)]
mod capsule_tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_capsule_mesh_faces_out_and_holds_its_capsule() {
        let c = crate::collision::Capsule {
            a: [1.0, 0.0, 0.0],
            b: [1.0, 2.0, 0.5],
            radius: 0.3,
            branch: 0,
        };
        let m = capsule_mesh(&c, 8, 3);
        assert_eq!(m.vertices.len(), 2 + 2 * 3 * 8);
        let (a, b) = (Vec3::from(c.a), Vec3::from(c.b));
        let nearest = |p: Vec3| {
            let d = b - a;
            a + d * ((p - a).dot(d) / d.length_squared()).clamp(0.0, 1.0)
        };
        for v in &m.vertices {
            let p = Vec3::from(v.position);
            // On the capsule's surface, the normal outward.
            assert!(((p - nearest(p)).length() - c.radius).abs() < 1e-5, "{p}");
            assert!(Vec3::from(v.normal).dot(p - nearest(p)) > 0.0);
        }
        for t in m.indices.chunks_exact(3) {
            let p = |k: usize| Vec3::from(m.vertices[t[k] as usize].position);
            let n = (p(1) - p(0)).cross(p(2) - p(0));
            let centre = (p(0) + p(1) + p(2)) / 3.0;
            assert!(n.length() > 1e-8, "{t:?} degenerate");
            assert!(n.dot(centre - nearest(centre)) > 0.0, "{t:?} faces in");
        }
    }
}
