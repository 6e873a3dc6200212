//! The mesh options: the enums a mesh is shaped by, [`MeshOptions`] with its defaults,
//! and their validation, in one place.

use super::{MAX_RADIAL_SEGMENTS, MIN_RADIAL_SEGMENTS, rings};
#[cfg(doc)]
use super::{MeshPlan, Vertex, VertexCompact};
use crate::error::{Error, Result};

/// Which vertex a mesh is written as (C: ArborVertexFormat, in
/// ArborMeshOptions.vertex_format).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum VertexFormat {
    /// [`Vertex`]: 32 bytes of f32. The default.
    #[default]
    F32 = 0,
    /// [`VertexCompact`]: 20 bytes (f32 position, octahedral snorm16 normal, unorm16 uv
    /// with v over the mesh's [`MeshPlan::v_scale`]).
    Compact = 1,
}

crate::enums::numbered!(VertexFormat as "ArborVertexFormat" { F32 = "f32", Compact = "compact" });

/// How the index buffer strings triangles together (C: ArborTopology, in
/// ArborMeshOptions.topology).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Topology {
    /// Three indices per triangle (Unity, Unreal, glDrawElements(GL_TRIANGLES)). The
    /// default.
    #[default]
    TriangleList = 0,
    /// One strip per branch, strips separated by the restart index (ARBOR_RESTART_INDEX);
    /// draw with GL_TRIANGLE_STRIP and GL_PRIMITIVE_RESTART_FIXED_INDEX enabled.
    TriangleStripRestart = 1,
    /// One strip for the whole mesh, branches joined by degenerate triangles.
    TriangleStripDegenerate = 2,
}

crate::enums::numbered!(Topology as "ArborTopology" {
    TriangleList = "triangle-list",
    TriangleStripRestart = "triangle-strip-restart",
    TriangleStripDegenerate = "triangle-strip-degenerate",
});

/// How a branch meets the branch it continues (C: ArborJoints, in
/// ArborMeshOptions.joints).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Joints {
    /// Every branch has its own two rings (cracks show at bends).
    Separate = 0,
    /// A continuing branch shares its parent's end ring, placed in the bisecting plane
    /// (watertight axes). The default.
    #[default]
    Mitred = 1,
}

crate::enums::numbered!(Joints as "ArborJoints" { Separate = "separate", Mitred = "mitred" });

/// How the last branch of an axis ends (C: ArborTip, in ArborMeshOptions.tip).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Tip {
    /// Open tube. The default.
    #[default]
    Open = 0,
    /// A flat disc.
    Cap = 1,
    /// A cone closing to a point one radius beyond the end.
    Point = 2,
}

crate::enums::numbered!(Tip as "ArborTip" { Open = "open", Cap = "cap", Point = "point" });

/// Which way front faces wind, seen from outside (C: ArborWinding, in
/// ArborMeshOptions.winding).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Winding {
    /// Counter-clockwise (OpenGL, glTF). The default.
    #[default]
    CounterClockwise = 0,
    /// Clockwise (Unity, Direct3D defaults).
    Clockwise = 1,
}

crate::enums::numbered!(Winding as "ArborWinding" {
    CounterClockwise = "counter-clockwise",
    Clockwise = "clockwise",
});

/// Which axis points up in the output (C: ArborUpAxis, in ArborMeshOptions.up_axis).
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum UpAxis {
    /// Y up, as arbor computes (OpenGL, Unity). The default.
    #[default]
    Y = 0,
    /// Z up (Blender): a rotation of +90 degrees about X, (x, y, z) -> (x, -z, y), which keeps
    /// handedness and winding. Unreal is left-handed: use the Unreal axes there.
    Z = 1,
}

crate::enums::numbered!(UpAxis as "ArborUpAxis" { Y = "y", Z = "z" });

/// Engine conventions of the output: the axes, handedness, units and winding a host's
/// engine uses, converted as that engine's own glTF importer converts (a mirror into a
/// left-handed space, never a rotation, so a tree keeps its handedness: trees g, h and i
/// spiral the same way in every engine). C: ArborAxes, in ArborMeshOptions.axes.
#[repr(u32)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Axes {
    /// arbor's own right-handed space, with the options' `up_axis`, `winding` and `scale`
    /// as given (OpenGL, glTF, Vulkan). The default.
    #[default]
    Arbor = 0,
    /// Unity: left-handed, Y up, metres (one model unit = one metre, as in glTF):
    /// (x, y, z) -> (-x, y, z), as Unity's glTF importers (glTFast, UnityGLTF) do; front
    /// faces wind clockwise seen from outside in Unity's space, so the cross product of a
    /// triangle's edges points out, as `Mesh.RecalculateNormals` expects.
    Unity = 1,
    /// Unreal: left-handed, Z up, centimetres: (x, y, z) -> (100x, 100z, 100y), the
    /// inverse of Unreal's own glTF exporter; front faces as Unreal's renderer culls them
    /// (the cross product of a triangle's edges points in, as Epic documents for its
    /// clockwise convention).
    Unreal = 2,
}

crate::enums::numbered!(Axes as "ArborAxes" { Arbor = "arbor", Unity = "unity", Unreal = "unreal" });

crate::options::options! {
/// Options of the tube mesher. Plain data; `Default` gives the documented defaults.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshOptions {
    /// Sides of each truncated cone, 3..=64 (the most, when LOD is on). Default 8.
    pub radial_segments: u32 = 8, checked In(MIN_RADIAL_SEGMENTS, MAX_RADIAL_SEGMENTS), format!("{MIN_RADIAL_SEGMENTS}..={MAX_RADIAL_SEGMENTS}"),
    /// Index buffer layout. Default [`Topology::TriangleList`].
    pub topology: Topology = Topology::TriangleList,
    /// LOD by radius: 0 (default) gives every branch `radial_segments`; otherwise a branch
    /// gets ⌈radial_segments * r / r_max⌉ sides clamped to `min_radial_segments..=
    /// radial_segments`, where r is its larger radius and r_max the tree's largest.
    pub min_radial_segments: u32 = 0,
    /// Branches whose larger radius is below this are dropped with their whole subtree.
    /// Default 0 (none).
    pub cull_radius: f32 = 0.0, checked AtLeast(0.0), "a finite number >= 0",
    /// Joints between a branch and the branch it continues. Default [`Joints::Mitred`].
    pub joints: Joints = Joints::Mitred,
    /// A branch's end radius becomes the start radius of the branch that continues it, so
    /// widths fall smoothly instead of in steps. Default false.
    pub smooth_taper: bool = false,
    /// A flat disc closing the base of each root. Default false.
    pub base_cap: bool = false,
    /// How axes end. Default [`Tip::Open`].
    pub tip: Tip = Tip::Open,
    /// `v` = arc length from the root / texture_scale (model units). Finite, > 0. Default 1.
    pub texture_scale: f32 = 1.0, checked Above(0.0), "a finite number > 0",
    /// Front-face winding. Default [`Winding::CounterClockwise`].
    pub winding: Winding = Winding::CounterClockwise,
    /// Up axis of the output. Default [`UpAxis::Y`].
    pub up_axis: UpAxis = UpAxis::Y,
    /// Uniform scale applied to positions. Finite, > 0. Default 1.
    pub scale: f32 = 1.0, checked Above(0.0), "a finite number > 0",
    /// Engine conventions. Default [`Axes::Arbor`]; an engine preset sets the axes and
    /// winding itself, so `up_axis` and `winding` must then stay at their defaults, and
    /// `scale` applies before the preset's units.
    pub axes: Axes = Axes::Arbor,
    /// Sizing or writing a mesh of more vertices than this fails with
    /// [`Error::LimitExceeded`](crate::error::Error::LimitExceeded) naming `max_vertices`, before
    /// any buffer is allocated. Default [`DEFAULT_MAX_VERTICES`](crate::limits::DEFAULT_MAX_VERTICES).
    pub max_vertices: usize = crate::limits::DEFAULT_MAX_VERTICES,
    /// Extra rings inside every branch, placed along its curve (a sweep), 0..=64: 0 (the
    /// default) draws each branch as one truncated cone between its end rings, exactly as
    /// without curves; k >= 1 adds k rings at equal curve parameters, framed by rotation-
    /// minimising frames continuous across joints, with radii interpolated and v by arc
    /// length.
    pub curve_rings: u32 = 0, checked AtMost(64), "0..=64 rings inside each branch",
    /// The vertex the writes take: [`VertexFormat::F32`] ([`Vertex`], the default) or
    /// [`VertexFormat::Compact`] ([`VertexCompact`]). A write into the other kind of buffer
    /// is [`Error::InvalidArgument`](crate::error::Error::InvalidArgument) naming
    /// `vertex_format`.
    pub vertex_format: VertexFormat = VertexFormat::F32,
    /// Bark texels of one size everywhere: around each branch u runs from 0 to
    /// round(circumference / `texture_scale`) (at least 1) instead of to 1, so a texture
    /// that tiles covers the bark at the same scale around as along (v), on the trunk as
    /// on a twig. Where a continuation's count differs from its parent's, it starts a
    /// ring of its own (no smear across the joint). A branch thinner than one repeat
    /// takes a fraction of it twice, mirrored (u 0 to w and back), and every branch an even
    /// number of sides (an odd count rounded up) so the turn is on a vertex. Not with
    /// [`VertexFormat::Compact`], whose u is a unorm16 (at most 1). Default false.
    pub even_texels: bool = false,
}
}

impl MeshOptions {
    /// Refuses options out of their documented ranges, or that contradict themselves (an
    /// engine preset with another up axis or winding, a scale that leaves the f32 range in
    /// the preset's units), naming the first; every mesh and export call checks this.
    pub fn validate(&self) -> crate::error::Result<()> {
        check_options(self)
    }

    /// How positions and directions go from arbor's space into the output's.
    pub(crate) fn out(&self) -> rings::Out {
        let (map, units) = match (self.axes, self.up_axis) {
            (Axes::Arbor, UpAxis::Y) => (rings::AxisMap::IDENTITY, 1.0),
            (Axes::Arbor, UpAxis::Z) => (rings::AxisMap::Z_UP, 1.0),
            (Axes::Unity, _) => (rings::AxisMap::UNITY, 1.0),
            (Axes::Unreal, _) => (rings::AxisMap::UNREAL, 100.0),
        };
        rings::Out {
            scale: self.scale * units,
            map,
        }
    }

    /// Whether triangles are written in the reverse of arbor's counter-clockwise order.
    pub(crate) fn reversed(&self) -> bool {
        match self.axes {
            Axes::Arbor => self.winding == Winding::Clockwise,
            // A mirror turns arbor's order clockwise; Unity wants the edges' cross product
            // outward again, Unreal keeps the mirrored order.
            Axes::Unity => true,
            Axes::Unreal => false,
        }
    }

    /// The output's up direction.
    pub fn up(&self) -> glam::Vec3 {
        glam::Vec3::from(self.out().map.apply(glam::Vec3::Y))
    }
}

pub(crate) fn check_options(o: &MeshOptions) -> Result<()> {
    check_fields(o)?;
    if o.even_texels && o.vertex_format == VertexFormat::Compact {
        return Err(Error::invalid(
            "even_texels",
            "true with vertex_format Compact, whose u is unorm16 in 0..=1; expected F32 \
             vertices (or even_texels false)",
        ));
    }
    if !o.out().scale.is_finite() {
        return Err(Error::invalid(
            "scale",
            format!(
                "{}; in {:?}'s units it leaves the f32 range",
                o.scale, o.axes
            ),
        ));
    }
    Ok(())
}

/// Each field in its range, and no field that contradicts an engine preset: what the
/// options say, whatever space they are written in (glTF checks these, then writes its
/// own conventions).
pub(crate) fn check_fields(o: &MeshOptions) -> Result<()> {
    o.check_fields()?;
    let (s, m) = (o.radial_segments, o.min_radial_segments);
    if m != 0 && !(MIN_RADIAL_SEGMENTS..=s).contains(&m) {
        return Err(Error::invalid(
            "min_radial_segments",
            format!("{m}; expected 0 (no LOD) or {MIN_RADIAL_SEGMENTS}..=radial_segments ({s})"),
        ));
    }
    if o.axes != Axes::Arbor {
        let (up, winding) = (
            o.up_axis != UpAxis::Y,
            o.winding != Winding::CounterClockwise,
        );
        if up || winding {
            let (field, value) = if up {
                ("up_axis", format!("{:?}", o.up_axis))
            } else {
                ("winding", format!("{:?}", o.winding))
            };
            return Err(Error::invalid(
                field,
                format!(
                    "{value} with axes {:?}; an engine preset sets the axes and winding \
                     itself, so leave up_axis and winding at their defaults (Y, \
                     CounterClockwise)",
                    o.axes
                ),
            ));
        }
    }
    Ok(())
}
