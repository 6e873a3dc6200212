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
}

impl Node {
    fn new(name: impl Into<String>, mesh: Option<usize>) -> Self {
        Node {
            name: name.into(),
            mesh,
            transform: None,
            instances: None,
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
        let mut push = |name: &str, image: crate::texture::Image| {
            self.textures.push(Texture {
                name: name.into(),
                image,
            });
            self.textures.len() - 1
        };
        let (color, normal, rough, leaves) = (
            push("bark", bark.color),
            push("bark normal", bark.normal),
            push("bark roughness", bark.roughness),
            push("leaves", atlas.image),
        );
        for m in &mut self.materials {
            match m.name.as_str() {
                "bark" => {
                    m.base_color = [1.0; 4];
                    m.base_color_texture = Some(color);
                    m.normal_texture = Some(normal);
                    m.metallic_roughness_texture = Some(rough);
                    m.roughness = 1.0;
                }
                "leaves" => {
                    m.base_color = [1.0; 4];
                    m.base_color_texture = Some(leaves);
                    m.alpha_cutoff = Some(0.5);
                    m.double_sided = true;
                }
                _ => {}
            }
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
