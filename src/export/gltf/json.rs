//! The glTF 2.0 document as typed values, serialized by serde_json: every string escaped,
//! every f32 written in its shortest round-trip form, optional members left out.

use serde::Serialize;

/// The document (glTF's root object).
#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Root {
    pub(super) asset: Asset,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) extensions_used: Vec<&'static str>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) extensions_required: Vec<&'static str>,
    pub(super) scene: usize,
    pub(super) scenes: [Scene; 1],
    pub(super) nodes: Vec<Node>,
    // glTF has no empty arrays: a file without triangles has nodes only.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) meshes: Vec<Mesh>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) materials: Vec<Material>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) textures: Vec<Texture>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) images: Vec<Image>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) samplers: Vec<Sampler>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) skins: Vec<Skin>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) animations: Vec<Animation>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) accessors: Vec<Accessor>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) buffer_views: Vec<BufferView>,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) buffers: Vec<Buffer>,
}

#[derive(Serialize)]
pub(super) struct Asset {
    pub(super) version: &'static str,
    pub(super) generator: String,
    /// The generator's settings.
    pub(super) extras: Extras,
}

/// `asset.extras`: what arbor made the file from (each file kind fills its own members).
#[derive(Default, Serialize)]
pub(super) struct Extras {
    pub(super) generator: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) branches: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) trees: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) distinct_trees: Option<usize>,
    pub(super) radial_segments: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) curve_rings: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) scale: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) leaves: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) leaf_instances: Option<usize>,
}

#[derive(Serialize)]
pub(super) struct Scene {
    pub(super) nodes: Vec<usize>,
}

#[derive(Serialize)]
pub(super) struct Node {
    pub(super) name: String,
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) children: Vec<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) mesh: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) skin: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) translation: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) rotation: Option<[f32; 4]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) scale: Option<[f32; 3]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) extensions: Option<NodeExtensions>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) extras: Option<NodeExtras>,
}

/// What arbor says of a node beyond glTF: the collision capsule it is, the coverages of
/// its levels of detail, its impostor.
#[derive(Default, Serialize)]
pub(super) struct NodeExtras {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) arbor_capsule: Option<CapsuleExtras>,
    #[serde(
        rename = "MSFT_screencoverage",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) screen_coverage: Option<Vec<f32>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) arbor_impostor: Option<ImpostorExtras>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) arbor_pivots: Option<PivotExtras>,
}

/// Where each branch's pivot is: accessor indices of VEC4 rows (start xyz, length) and
/// (axis xyz, parent index or -1).
#[derive(Serialize)]
pub(super) struct PivotExtras {
    pub(super) count: usize,
    pub(super) pivot_length: usize,
    pub(super) axis_parent: usize,
}

/// An octahedral impostor: its grid, its frame and its atlases (texture indices).
#[derive(Serialize)]
pub(super) struct ImpostorExtras {
    pub(super) frames: u32,
    pub(super) cell: u32,
    pub(super) hemi: bool,
    pub(super) centre: [f32; 3],
    pub(super) radius: f32,
    pub(super) up: [f32; 3],
    pub(super) albedo_texture: usize,
    pub(super) normal_texture: usize,
    pub(super) below_coverage: f32,
}

#[derive(Serialize)]
pub(super) struct CapsuleExtras {
    pub(super) a: [f32; 3],
    pub(super) b: [f32; 3],
    pub(super) radius: f32,
}

impl Node {
    /// A node named `name` drawing `mesh` (none: a tree without triangles), at the origin.
    pub(super) fn new(name: impl Into<String>, mesh: Option<usize>) -> Self {
        Node {
            name: name.into(),
            children: Vec::new(),
            mesh,
            skin: None,
            translation: None,
            rotation: None,
            scale: None,
            extensions: None,
            extras: None,
        }
    }
}

#[derive(Default, Serialize)]
pub(super) struct NodeExtensions {
    #[serde(
        rename = "EXT_mesh_gpu_instancing",
        skip_serializing_if = "Option::is_none"
    )]
    pub(super) instancing: Option<Instancing>,
    #[serde(rename = "MSFT_lod", skip_serializing_if = "Option::is_none")]
    pub(super) lod: Option<MsftLod>,
}

/// `MSFT_lod`: the nodes of the lower levels.
#[derive(Serialize)]
pub(super) struct MsftLod {
    pub(super) ids: Vec<usize>,
}

#[derive(Serialize)]
pub(super) struct Instancing {
    pub(super) attributes: InstanceAttributes,
}

#[derive(Serialize)]
#[serde(rename_all = "UPPERCASE")]
pub(super) struct InstanceAttributes {
    pub(super) translation: usize,
    pub(super) rotation: usize,
    pub(super) scale: usize,
}

#[derive(Serialize)]
pub(super) struct Mesh {
    pub(super) name: String,
    pub(super) primitives: Vec<Primitive>,
}

#[derive(Serialize)]
pub(super) struct Primitive {
    pub(super) attributes: Attributes,
    pub(super) indices: usize,
    pub(super) material: usize,
    /// 4: triangles.
    pub(super) mode: u32,
}

/// A primitive's vertex attributes (accessor indices), with arbor's animation stream as
/// custom attributes where it is written.
#[derive(Serialize)]
pub(super) struct Attributes {
    #[serde(rename = "POSITION")]
    pub(super) position: usize,
    #[serde(rename = "NORMAL")]
    pub(super) normal: usize,
    #[serde(rename = "TEXCOORD_0")]
    pub(super) texcoord_0: usize,
    #[serde(rename = "TANGENT", skip_serializing_if = "Option::is_none")]
    pub(super) tangent: Option<usize>,
    #[serde(rename = "_GROWTH", skip_serializing_if = "Option::is_none")]
    pub(super) growth: Option<usize>,
    #[serde(rename = "_WIND", skip_serializing_if = "Option::is_none")]
    pub(super) wind: Option<usize>,
    #[serde(rename = "COLOR_0", skip_serializing_if = "Option::is_none")]
    pub(super) color_0: Option<usize>,
    #[serde(rename = "TEXCOORD_1", skip_serializing_if = "Option::is_none")]
    pub(super) texcoord_1: Option<usize>,
    #[serde(rename = "TEXCOORD_2", skip_serializing_if = "Option::is_none")]
    pub(super) texcoord_2: Option<usize>,
    #[serde(rename = "JOINTS_0", skip_serializing_if = "Option::is_none")]
    pub(super) joints: Option<usize>,
    #[serde(rename = "WEIGHTS_0", skip_serializing_if = "Option::is_none")]
    pub(super) weights: Option<usize>,
}

/// A skin: its joints' nodes and inverse bind matrices.
#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Skin {
    pub(super) name: &'static str,
    pub(super) inverse_bind_matrices: usize,
    pub(super) joints: Vec<usize>,
    pub(super) skeleton: usize,
}

/// An animation: channels driving node rotations from samplers.
#[derive(Serialize)]
pub(super) struct Animation {
    pub(super) name: &'static str,
    pub(super) channels: Vec<Channel>,
    pub(super) samplers: Vec<AnimationSampler>,
}

#[derive(Serialize)]
pub(super) struct Channel {
    pub(super) sampler: usize,
    pub(super) target: ChannelTarget,
}

#[derive(Serialize)]
pub(super) struct ChannelTarget {
    pub(super) node: usize,
    pub(super) path: &'static str,
}

#[derive(Serialize)]
pub(super) struct AnimationSampler {
    pub(super) input: usize,
    pub(super) interpolation: &'static str,
    pub(super) output: usize,
}

#[derive(Clone, Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Material {
    pub(super) name: String,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub(super) double_sided: bool,
    pub(super) pbr_metallic_roughness: Pbr,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) normal_texture: Option<TextureInfo>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) alpha_mode: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) alpha_cutoff: Option<f32>,
}

#[derive(Clone, Copy, Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Pbr {
    pub(super) base_color_factor: [f32; 4],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) base_color_texture: Option<TextureInfo>,
    pub(super) metallic_factor: f32,
    pub(super) roughness_factor: f32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) metallic_roughness_texture: Option<TextureInfo>,
}

/// A material's reference to a texture (texture coordinates 0).
#[derive(Clone, Copy, Serialize)]
pub(super) struct TextureInfo {
    pub(super) index: usize,
}

#[derive(Serialize)]
pub(super) struct Texture {
    pub(super) sampler: usize,
    pub(super) source: usize,
    pub(super) name: String,
}

/// A PNG image in a buffer view.
#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Image {
    pub(super) buffer_view: usize,
    pub(super) mime_type: &'static str,
    pub(super) name: String,
}

/// Linear filtering with mipmaps, repeat in both directions.
#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Sampler {
    pub(super) mag_filter: u32,
    pub(super) min_filter: u32,
    pub(super) wrap_s: u32,
    pub(super) wrap_t: u32,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Accessor {
    pub(super) buffer_view: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) byte_offset: Option<usize>,
    pub(super) component_type: u32,
    pub(super) count: usize,
    #[serde(rename = "type")]
    pub(super) kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) min: Option<Vec<f32>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) max: Option<Vec<f32>>,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub(super) normalized: bool,
}

impl Accessor {
    /// `count` elements of `kind` (`"VEC3"`, ...) in `component` (a glTF componentType),
    /// at `byte_offset` in `buffer_view`; no bounds, not normalized.
    pub(super) fn new(
        buffer_view: usize,
        byte_offset: Option<usize>,
        (component_type, kind): (u32, &'static str),
        count: usize,
    ) -> Self {
        Accessor {
            buffer_view,
            byte_offset,
            component_type,
            count,
            kind,
            min: None,
            max: None,
            normalized: false,
        }
    }
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct BufferView {
    pub(super) buffer: usize,
    pub(super) byte_offset: usize,
    pub(super) byte_length: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) byte_stride: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) target: Option<u32>,
}

#[derive(Serialize)]
#[serde(rename_all = "camelCase")]
pub(super) struct Buffer {
    pub(super) byte_length: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) uri: Option<String>,
}
