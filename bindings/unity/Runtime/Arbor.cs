// arbor for Unity (and any .NET host): P/Invoke declarations over arbor.h, blittable
// structs with the C layouts, and helpers that fill Unity meshes.
//
// Put the native library where Unity finds plugins (Assets/Plugins/<platform>/: libarbor.so,
// arbor.dll, libarbor.dylib; on iOS link libarbor.a, reached through "__Internal").
// Unity is left-handed with clockwise front faces: the helpers ask arbor for a triangle
// list with its Unity preset (Axes.Unity: x mirrored as Unity's glTF importers do, winding
// as Unity draws), so trees keep their handedness (g, h and i are not mirrored).
using System;
using System.Runtime.InteropServices;
using System.Text;

#if !UNITY_5_3_OR_NEWER
namespace AOT
{
    /// Unity's attribute for native-to-managed callbacks under IL2CPP (UnityEngine
    /// defines it; this stand-in lets the binding build elsewhere).
    [AttributeUsage(AttributeTargets.Method)]
    public sealed class MonoPInvokeCallbackAttribute : Attribute
    {
        public MonoPInvokeCallbackAttribute(Type type) { }
    }
}
#endif

namespace Arbor
{
    public enum Status : int
    {
        Ok = 0, NullArgument = 1, InvalidArgument = 2, ParseError = 3,
        LimitExceeded = 4, BufferTooSmall = 5, IoError = 6, Panic = 7, Cancelled = 8,
        OutOfMemory = 9,
    }

    /// ArborFileAccess: which files a model may read (its includes, its view file's
    /// functions, curves and surfaces, a leaf prefab).
    public enum FileAccess : uint { Bundle = 0, None = 1, Any = 2, Host = 3 }

    /// ArborReadFileFn: write at most `capacity` bytes of `path` to `buffer` and its full size
    /// to `size`; non-zero for "no such file".
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    public delegate int ReadFileFn(IntPtr userData, IntPtr path, IntPtr buffer, UIntPtr capacity, out UIntPtr size);

    /// ArborProgressFn: stage (0 derivation, 1 interpretation, 2 growth, 3 mesh, 4 loading,
    /// 5 writing a file), fraction in [0, 1]; non-zero cancels.
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    public delegate int ProgressFn(IntPtr userData, uint stage, float fraction);

    public enum Topology : uint { TriangleList = 0, TriangleStripRestart = 1, TriangleStripDegenerate = 2 }
    public enum Joints : uint { Separate = 0, Mitred = 1 }
    public enum Tip : uint { Open = 0, Cap = 1, Point = 2 }
    public enum Winding : uint { CounterClockwise = 0, Clockwise = 1 }
    public enum UpAxis : uint { Y = 0, Z = 1 }
    /// Engine conventions (ArborAxes): Unity and Unreal convert by a mirror, as their
    /// importers do; with a preset, Winding and UpAxis stay at their defaults.
    public enum Axes : uint { Arbor = 0, Unity = 1, Unreal = 2 }
    /// The vertex a mesh is written as (ArborVertexFormat, MeshOptions.VertexFormat).
    public enum VertexFormat : uint { F32 = 0, Compact = 1 }
    public enum StructId : uint
    {
        HondaParams = 0, Branch = 1, Vertex = 2, MeshOptions = 3, LsystemOptions = 4,
        LeafOptions = 5, LeafInstance = 6, BranchRange = 7, LeafSite = 8,
        AnimationVertex = 9, ForestTree = 10, WorldOptions = 11, GrowthParams = 12,
        Curve = 13, CurveRecord = 14, CurveGrowthRecord = 15, Organ = 16, VertexCompact = 17,
        AnimationVertexCompact = 18, ForestPlant = 19, Capsule = 20, LodOptions = 21,
        Bone = 22,
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct HondaParams
    {
        public float TrunkLength, TrunkWidth, R1, R2, Alpha1, Alpha2, Phi1, Phi2, Q, E, MinLength;
        public uint Steps;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct Branch
    {
        public float StartX, StartY, StartZ, EndX, EndY, EndZ, StartRadius, EndRadius;
        public uint Parent, Depth, Order, Flags;
    }

    /// Position, normal, uv: 32 bytes, the layout of Unity's Position/Normal/TexCoord0
    /// float32 stream.
    [StructLayout(LayoutKind.Sequential)]
    public struct Vertex
    {
        public float PX, PY, PZ, NX, NY, NZ, U, V;
    }

    /// Position (float32 x 3), octahedral normal (SNorm16 x 2), uv (UNorm16 x 2, v over
    /// the mesh's v_scale): 20 bytes, for a Unity stream of Position Float32 x 3,
    /// TexCoord1 SNorm16 x 2 (decode the normal in the shader) and TexCoord0 UNorm16 x 2.
    [StructLayout(LayoutKind.Sequential)]
    public struct VertexCompact
    {
        public float PX, PY, PZ;
        public short NX, NY;
        public ushort U, V;
    }

    /// The animation stream packed to match VertexCompact: growth, along and phase in
    /// UNorm16, Order an integer (8 bytes).
    [StructLayout(LayoutKind.Sequential)]
    public struct AnimationVertexCompact
    {
        public ushort Growth, Order, Along, Phase;
    }

    // Structs that grow: StructSize first, the size this binding was written against.
    // Always start from Default(), which asks the library to fill exactly that many bytes,
    // so this binding keeps working with a newer library.

    [StructLayout(LayoutKind.Sequential)]
    public struct MeshOptions
    {
        public uint StructSize;
        public uint RadialSegments, Topology, MinRadialSegments;
        public float CullRadius;
        public uint Joints, SmoothTaper, BaseCap, Tip;
        public float TextureScale;
        public uint Winding, UpAxis;
        public float Scale;
        public uint Threads;
        public ulong MaxVertices;
        public uint CurveRings;
        /// An ArborProgressFn (Marshal.GetFunctionPointerForDelegate) and its user data,
        /// called while a mesh is written; IntPtr.Zero for none.
        public IntPtr Progress, ProgressUserData;
        /// An Axes value. Default Axes.Arbor.
        public uint Axes;
        /// A VertexFormat value. Default VertexFormat.F32; Compact is written by MeshCompact.
        public uint VertexFormat;
        /// 1: bark texels of one size (u wraps by circumference over TextureScale). Default 0.
        public uint EvenTexels;

        public static MeshOptions Default()
        {
            var o = new MeshOptions();
            Native.arbor_mesh_options_init(ref o, (UIntPtr)Marshal.SizeOf(typeof(MeshOptions)));
            return o;
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct LsystemOptions
    {
        public uint StructSize;
        public int Steps;
        public ulong Seed, MaxModules, MaxParams, MaxBranches;
        public uint OverrideFlags;
        public float AngleIncrement, InitialWidth, WidthIncrement, TurnJitter;
        public ulong VariationSeed, MaxWork;
        /// A NUL-terminated UTF-8 path (FromLsystemFile) or view-file text (FromLsystem);
        /// IntPtr.Zero for none. The wrappers below fill them for you.
        public IntPtr ViewPath, ViewText;
        /// An ArborProgressFn (Marshal.GetFunctionPointerForDelegate) and its user data;
        /// Tree.FromLsystem(source, progress) fills them.
        public IntPtr Progress, ProgressUserData;
        /// A FileAccess (default Bundle: the model's folder and below).
        public uint FileAccess;
        /// A ReadFileFn (Marshal.GetFunctionPointerForDelegate) and its user data, for
        /// FileAccess.Host; Tree.FromLsystemFile(path, read) fills them.
        public IntPtr ReadFile, ReadFileUserData;
        /// Bytes read over all files of one load (default 64 MiB).
        public ulong MaxFileBytes;

        public static LsystemOptions Default()
        {
            var o = new LsystemOptions();
            Native.arbor_lsystem_options_init(ref o, (UIntPtr)Marshal.SizeOf(typeof(LsystemOptions)));
            return o;
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct LeafOptions
    {
        public uint StructSize;
        public uint Sites, Polygons, Tips, MinDepth;
        public float Density, Size, SizeJitter, RotationJitter, Tilt;
        public ulong Seed;
        public IntPtr PrefabObjPath;
        public ulong MaxLeaves;
        /// How PrefabObjPath is read: FileAccess.Host through ReadFile, else from disk as a
        /// regular file.
        public uint FileAccess;
        public IntPtr ReadFile, ReadFileUserData;
        public ulong MaxFileBytes;
        /// An ArborLeafPrefab from Native.arbor_leaf_prefab_load (the file read once);
        /// IntPtr.Zero for none. Set this or PrefabObjPath, not both.
        public IntPtr Prefab;
        /// The leaf atlas' grid: each baked leaf samples one cell. Default 1 x 1.
        public uint AtlasColumns, AtlasRows;
        /// Leaves reaching into a branch thicker than this radius are left out (0: none).
        public float WoodClearance;
        /// The default card folded along its midrib, degrees (0..90; baked leaves).
        public float Fold;
        /// 1: each leaf turned to face up (the light) before RotationJitter varies it.
        public uint FaceLight;
        /// The fraction of leaves kept (0..1], each enlarged by 1/sqrt(Keep): levels of
        /// detail, the same leaves from level to level. Default 1.
        public float Keep;
        /// How much the inside leaves a Keep below 1 leaves are enlarged: by the leaves
        /// there over those kept, to this power (0..1; default 0.5 keeps their area).
        public float KeepEnlarge;

        public static LeafOptions Default()
        {
            var o = new LeafOptions();
            Native.arbor_leaf_options_init(ref o, (UIntPtr)Marshal.SizeOf(typeof(LeafOptions)));
            return o;
        }
    }

    /// How a chain of levels of detail is made (Native.arbor_tree_lods_create): a struct
    /// that grows; start from LodOptions.Default().
    [StructLayout(LayoutKind.Sequential)]
    public struct LodOptions
    {
        public uint StructSize;
        /// Mesh levels, the full tree included (1..8). Default 4.
        public uint Levels;
        /// Level 1's share of the triangles (0.4), each further level's the one before's
        /// times Step (0.5).
        public float Budget, Step;
        /// The first switch's screen coverage (0.5) and each further one's factor (0.5),
        /// before they are fitted to the silhouette.
        public float Coverage, CoverageStep;
        /// The silhouette IoU each level keeps where it is first drawn (0.91; 0: not fitted).
        public float Silhouette;
        /// Threads (0: the mesh options' threads).
        public uint Threads;

        public static LodOptions Default()
        {
            var o = new LodOptions();
            Native.arbor_lod_options_init(ref o, (UIntPtr)Marshal.SizeOf(typeof(LodOptions)));
            return o;
        }
    }

    /// One branch as a cubic Bezier (56 bytes): p0 its start, p3 its end.
    [StructLayout(LayoutKind.Sequential)]
    public struct Curve
    {
        public float P0X, P0Y, P0Z, P1X, P1Y, P1Z, P2X, P2Y, P2Z, P3X, P3Y, P3Z;
        public float R0, R1;
    }

    public enum Environment : uint { Shadow = 0, SpaceColonization = 1 }
    public enum Species : uint
    {
        Excurrent = 0, Decurrent = 1, Columnar = 2, Bush = 3, Weeping = 4,
        Oak = 5, Maple = 6, Birch = 7, Willow = 8, Poplar = 9, Pine = 10, Spruce = 11, Shrub = 12,
    }

    /// Which texture of a named species Native.arbor_species_texture_write draws
    /// (ArborTexture): RGBA8 rows from the top, for Texture2D.LoadRawTextureData after a
    /// vertical flip (Unity's rows start at the bottom).
    public enum Texture : uint { LeafAtlas = 0, BarkColor = 1, BarkNormal = 2, BarkRoughness = 3 }

    /// What a ForestPlant grows from (ArborPlantSource).
    public enum PlantSource : uint { Honda = 0, Growth = 1 }

    /// One tree of a forest of any source (ArborForestPlant): the 1996 model's parameters or
    /// a species (a pointer to a GrowthParams the caller keeps alive, IntPtr.Zero for the
    /// default) grown alone for Cycles cycles, and its placement. Pass an array of them to
    /// arbor_forest_plants_mesh_create.
    [StructLayout(LayoutKind.Sequential)]
    public struct ForestPlant
    {
        public uint StructSize;
        public PlantSource Source;
        public HondaParams Honda;
        public IntPtr Species;
        public uint Cycles;
        public ulong Seed;
        public float PositionX, PositionY, PositionZ;
        public float Rotation, Scale;

        public static ForestPlant Default()
        {
            var p = new ForestPlant();
            Native.arbor_forest_plant_init(ref p, (UIntPtr)Marshal.SizeOf(typeof(ForestPlant)));
            return p;
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct WorldOptions
    {
        public uint StructSize;
        public uint Environment;
        public float MinX, MinY, MinZ, MaxX, MaxY, MaxZ;
        public float CellSize;
        public ulong Seed;
        public float ShadowStrength, ShadowFalloff;
        public uint ShadowDepth;
        public float FullLight;
        public ulong MaxCells, MaxBranches;
        public uint MaxTrees, Parallel;
        public IntPtr Progress, ProgressUserData;

        public static WorldOptions Default()
        {
            var o = new WorldOptions();
            Native.arbor_world_options_init(ref o, (UIntPtr)Marshal.SizeOf(typeof(WorldOptions)));
            return o;
        }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct GrowthParams
    {
        public uint StructSize;
        public float ApicalControl, VigorMultiplier, InternodeLength, BranchAngle, Phyllotaxis,
            Tropism, EnvironmentWeight, PipeExponent, TipRadius, ShedMultiplier, ShedExponent;
        public uint ShedDelay, SeedAge;
        public float SeedSpread, PerceptionAngle, PerceptionReach, OccupancyReach;
        public uint MaxShoot;
        // Added after the first layout: shedding by light, aging, adult size, weeping,
        // germination.
        public float ShedLight, YoungApicalControl, YoungVigorMultiplier;
        public uint MaturityAge, MaxAge;
        public float MaxHeight, Droop, GerminationLight;

        public static GrowthParams Default()
        {
            var p = new GrowthParams();
            Native.arbor_growth_params_init(ref p, (UIntPtr)Marshal.SizeOf(typeof(GrowthParams)));
            return p;
        }

        public static GrowthParams Preset(Species species)
        {
            var p = new GrowthParams();
            ArborException.Check(Native.arbor_growth_params_preset((uint)species, ref p, (UIntPtr)Marshal.SizeOf(typeof(GrowthParams))));
            return p;
        }
    }

    /// A collision capsule (ArborCapsule): the segment A to B swept by a sphere of Radius,
    /// on branch Branch (Native.arbor_tree_capsules_write).
    [StructLayout(LayoutKind.Sequential)]
    public struct Capsule
    {
        public float AX, AY, AZ, BX, BY, BZ;
        public float Radius;
        public uint Branch;
    }

    /// One bone of the wind skin (ArborBone): a segment of an axis from its head (the
    /// joint) to its tail, its parent (0xFFFFFFFF, ARBOR_NO_PARENT, for the root) and the wood's radius
    /// at its head (Native.arbor_tree_bones_write).
    [StructLayout(LayoutKind.Sequential)]
    public struct Bone
    {
        public float HeadX, HeadY, HeadZ, TailX, TailY, TailZ;
        public uint Parent;
        public float Radius;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct LeafInstance
    {
        public float PX, PY, PZ, QX, QY, QZ, QW, Scale;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct BranchRange
    {
        public uint FirstVertex, VertexCount, FirstIndex, IndexCount;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct LeafSite
    {
        public float PX, PY, PZ, HX, HY, HZ, UX, UY, UZ;
        public uint Branch, Depth;
    }

    public static class Native
    {
#if UNITY_IOS && !UNITY_EDITOR
        const string Lib = "__Internal";
#else
        const string Lib = "arbor";
#endif
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr arbor_status_str(uint status);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_last_error_message(byte[] buf, UIntPtr capacity);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr arbor_version();
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern uint arbor_abi_version();
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_struct_size(uint id);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_honda_preset(uint name, out HondaParams outParams);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_from_honda(ref HondaParams p, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_from_lsystem(byte[] source, UIntPtr len, IntPtr options, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_from_lsystem(byte[] source, UIntPtr len, ref LsystemOptions options, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_from_lsystem_file(IntPtr path, ref LsystemOptions options, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_tree_free(IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_tree_branch_count(IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_copy_branches(IntPtr tree, [Out] Branch[] output, UIntPtr capacity);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_mesh_options_init(ref MeshOptions options, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_lsystem_options_init(ref LsystemOptions options, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_leaf_options_init(ref LeafOptions options, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_leaf_prefab_load([MarshalAs(UnmanagedType.LPUTF8Str)] string objPath, IntPtr options, out IntPtr prefab);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_leaf_prefab_triangle_count(IntPtr prefab);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_leaf_prefab_free(IntPtr prefab);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_mesh_size(IntPtr tree, ref MeshOptions options, out UIntPtr vertexCount, out UIntPtr indexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_mesh_write(IntPtr tree, ref MeshOptions options, [Out] Vertex[] vertices, UIntPtr vertexCapacity, [Out] int[] indices, UIntPtr indexCapacity);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_mesh_write_bytes(IntPtr tree, ref MeshOptions options, [Out] VertexCompact[] vertices, UIntPtr vertexBytes, [Out] int[] indices, UIntPtr indexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_mesh_v_scale(IntPtr tree, ref MeshOptions options, out float vScale);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_copy_curves(IntPtr tree, [Out] Curve[] output, UIntPtr capacity);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_set_curve(IntPtr tree, UIntPtr branch, ref Curve curve);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_smooth(IntPtr tree, float tension);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_mesh_rewrite_branch(IntPtr tree, ref MeshOptions options, UIntPtr branch, [In, Out] Vertex[] vertices, UIntPtr vertexCount, [In, Out] int[] indices, UIntPtr indexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_world_options_init(ref WorldOptions options, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_growth_params_init(ref GrowthParams p, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_forest_plant_init(ref ForestPlant p, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_from_species(uint species, ulong seed, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_species_options(uint species, IntPtr tree, ref MeshOptions meshOptions, ref LeafOptions leafOptions);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_species_texture_write(uint species, uint which, uint size, ulong seed, uint threads, [Out] byte[] rgba, UIntPtr capacity);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_from_species_bare(uint species, ulong seed, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_capsules_write(IntPtr tree, ref MeshOptions meshOptions, uint maxCapsules, float minRadius, [Out] Capsule[] output, UIntPtr capacity, out UIntPtr count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_bones_write(IntPtr tree, ref MeshOptions meshOptions, uint maxBones, [Out] Bone[] output, [Out] float[] inverseBind, UIntPtr capacity, out UIntPtr count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_mesh_skin_write(IntPtr tree, ref MeshOptions options, uint maxBones, [Out] ushort[] joints, [Out] float[] weights, UIntPtr vertexCapacity, out UIntPtr vertexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_pivots_write(IntPtr tree, ref MeshOptions meshOptions, [Out] float[] output, UIntPtr capacity, out UIntPtr count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_wind_clip_write(IntPtr tree, ref MeshOptions meshOptions, uint maxBones, float[] wind, float strength, float duration, uint keysPerSecond, ulong seed, [Out] float[] times, UIntPtr keyCapacity, [Out] float[] rotations, UIntPtr boneCapacity, out UIntPtr keyCount, out UIntPtr boneCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_lod_options_init(ref LodOptions options, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_tree_lods_create(IntPtr tree, ref MeshOptions meshOptions, ref LeafOptions leafOptions, byte[] atlasRgba, uint atlasWidth, uint atlasHeight, ref LodOptions lodOptions, out IntPtr lods);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_lods_free(IntPtr lods);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_lods_count(IntPtr lods);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_lods_impostor_level(IntPtr lods, uint cell);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_lods_skin_write(IntPtr lods, UIntPtr level, uint part, uint maxBones, [Out] ushort[] joints, [Out] float[] weights, UIntPtr vertexCapacity, out UIntPtr vertexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_lods_level_info(IntPtr lods, UIntPtr level, out float screenCoverage, out float silhouette, out UIntPtr triangles);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_lods_mesh_write(IntPtr lods, UIntPtr level, uint part, [Out] Vertex[] vertices, UIntPtr vertexCapacity, [Out] uint[] indices, UIntPtr indexCapacity, out UIntPtr vertexCount, out UIntPtr indexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_lods_impostor_create(IntPtr lods, UIntPtr level, uint frames, uint cell, uint hemi, byte[] atlasRgba, uint atlasWidth, uint atlasHeight, out IntPtr impostor);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_impostor_free(IntPtr impostor);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_impostor_atlas_write(IntPtr impostor, uint which, [Out] byte[] output, UIntPtr capacity, out UIntPtr size);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_impostor_info(IntPtr impostor, out uint atlasSize, [Out] float[] centre, out float radius, [Out] float[] up);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_lods_billboard_create(IntPtr lods, UIntPtr level, uint planes, uint cell, byte[] atlasRgba, uint atlasWidth, uint atlasHeight, out IntPtr billboard);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_billboard_free(IntPtr billboard);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_billboard_mesh_write(IntPtr billboard, uint twoSided, [Out] Vertex[] vertices, UIntPtr vertexCapacity, [Out] uint[] indices, UIntPtr indexCapacity, out UIntPtr vertexCount, out UIntPtr indexCount);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_billboard_atlas_write(IntPtr billboard, uint which, [Out] byte[] output, UIntPtr capacity, out uint width, out uint height);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_species_twig_create(uint species, uint variant, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_species_twig_options(uint species, ref MeshOptions meshOptions, ref LeafOptions leafOptions);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_species_twig_instances_write(uint species, IntPtr tree, ref MeshOptions meshOptions, [Out] LeafInstance[] output, UIntPtr capacity, out UIntPtr count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_leaf_atlas_rect(uint cell, [Out] float[] rect, out uint cells);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_forest_plants_mesh_create(ForestPlant[] plants, UIntPtr count, ref MeshOptions options, out IntPtr mesh);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_growth_params_preset(uint species, ref GrowthParams p, UIntPtr structSize);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_create(ref WorldOptions options, out IntPtr world);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern void arbor_world_free(IntPtr world);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_plant(IntPtr world, ref GrowthParams species, float[] position, ulong seed, out uint treeId);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_step(IntPtr world, uint cycles);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern UIntPtr arbor_world_tree_count(IntPtr world);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_tree(IntPtr world, UIntPtr index, out IntPtr tree);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_set_ground(IntPtr world, float[] heights, uint columns, uint rows, float cellSize, float originX, float originZ);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_set_ground_png(IntPtr world, byte[] png, UIntPtr pngLen, float heightScale, float baseHeight, float cellSize, float originX, float originZ);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_ground_height(IntPtr world, float x, float z, out float height);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_plant_on_ground(IntPtr world, ref GrowthParams species, float x, float z, uint slot, ulong seed, out uint treeId);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_tree_slot(IntPtr world, UIntPtr index, out uint slot);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_set_species(IntPtr world, uint slot, ref GrowthParams species, out UIntPtr changed);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_world_clone(IntPtr world, out IntPtr copy);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_leaf_instance_count(IntPtr tree, ref LeafOptions leaves, ref MeshOptions options, out UIntPtr count);
        [DllImport(Lib, CallingConvention = CallingConvention.Cdecl)]
        public static extern Status arbor_leaf_instances_write(IntPtr tree, ref LeafOptions leaves, ref MeshOptions options, [Out] LeafInstance[] output, UIntPtr capacity);
    }

    public class ArborException : Exception
    {
        public readonly Status Status;
        public ArborException(Status status, string message) : base(message) { Status = status; }

        public static string LastMessage()
        {
            int n = (int)Native.arbor_last_error_message(null, UIntPtr.Zero);
            var buf = new byte[n + 1];
            Native.arbor_last_error_message(buf, (UIntPtr)buf.Length);
            return Encoding.UTF8.GetString(buf, 0, n);
        }

        public static void Check(Status s)
        {
            if (s != Status.Ok) throw new ArborException(s, LastMessage());
        }
    }

    /// Self-organizing trees growing together; Dispose (or using) frees it.
    public sealed class World : IDisposable
    {
        IntPtr handle;

        public World(WorldOptions options)
        {
            ArborException.Check(Native.arbor_world_create(ref options, out handle));
        }

        public uint Plant(GrowthParams species, float x, float y, float z, ulong seed)
        {
            uint id;
            ArborException.Check(Native.arbor_world_plant(handle, ref species, new[] { x, y, z }, seed, out id));
            return id;
        }

        public void Step(uint cycles) { ArborException.Check(Native.arbor_world_step(handle, cycles)); }

        World(IntPtr h) { handle = h; }

        /// Lays a height field (columns x rows heights, x fastest, `cellSize` apart from
        /// (originX, originZ)) under the empty world.
        public void SetGround(float[] heights, uint columns, uint rows, float cellSize, float originX, float originZ)
        {
            if (heights == null || heights.Length != (long)columns * rows)
                throw new ArgumentException("heights: expected columns * rows samples");
            ArborException.Check(Native.arbor_world_set_ground(handle, heights, columns, rows, cellSize, originX, originZ));
        }

        /// Lays a PNG height map (black at `baseHeight`, white at `baseHeight + heightScale`).
        public void SetGroundPng(byte[] png, float heightScale, float baseHeight, float cellSize, float originX, float originZ)
        {
            ArborException.Check(Native.arbor_world_set_ground_png(handle, png, (UIntPtr)png.Length, heightScale, baseHeight, cellSize, originX, originZ));
        }

        /// The ground's height at (x, z).
        public float GroundHeight(float x, float z)
        {
            float h;
            ArborException.Check(Native.arbor_world_ground_height(handle, x, z, out h));
            return h;
        }

        /// Plants a tree standing on the ground at (x, z) in species slot `slot`.
        public uint PlantOnGround(GrowthParams species, float x, float z, uint slot, ulong seed)
        {
            uint id;
            ArborException.Check(Native.arbor_world_plant_on_ground(handle, ref species, x, z, slot, seed, out id));
            return id;
        }

        /// The species slot tree `index` was planted in (a seedling: its parent's).
        public uint TreeSlot(int index)
        {
            uint slot;
            ArborException.Check(Native.arbor_world_tree_slot(handle, (UIntPtr)index, out slot));
            return slot;
        }

        /// Gives every tree of `slot` new parameters (a slider's change); returns how many.
        public int SetSpecies(uint slot, GrowthParams species)
        {
            UIntPtr n;
            ArborException.Check(Native.arbor_world_set_species(handle, slot, ref species, out n));
            return (int)n;
        }

        /// A copy that grows on by itself (a preview).
        public World Clone()
        {
            IntPtr c;
            ArborException.Check(Native.arbor_world_clone(handle, out c));
            return new World(c);
        }

        public int TreeCount { get { return (int)Native.arbor_world_tree_count(handle); } }

        /// A snapshot of tree `index` as an ordinary tree (mesh it like any other).
        public Tree Tree(int index)
        {
            IntPtr t;
            ArborException.Check(Native.arbor_world_tree(handle, (UIntPtr)index, out t));
            return new Tree(t);
        }

        public void Dispose()
        {
            if (handle != IntPtr.Zero)
            {
                Native.arbor_world_free(handle);
                handle = IntPtr.Zero;
            }
        }
    }

    /// A generated tree; Dispose (or using) frees it.
    public sealed class Tree : IDisposable
    {
        IntPtr handle;
        internal Tree(IntPtr h) { handle = h; }

        public static Tree FromPreset(char name)
        {
            HondaParams p;
            ArborException.Check(Native.arbor_honda_preset(name, out p));
            return FromHonda(p);
        }

        public static Tree FromHonda(HondaParams p)
        {
            IntPtr t;
            ArborException.Check(Native.arbor_tree_from_honda(ref p, out t));
            return new Tree(t);
        }

        public static Tree FromLsystem(string source)
        {
            byte[] bytes = Encoding.UTF8.GetBytes(source);
            IntPtr t;
            ArborException.Check(Native.arbor_tree_from_lsystem(bytes, (UIntPtr)bytes.Length, IntPtr.Zero, out t));
            return new Tree(t);
        }

        static IntPtr Utf8(string s)
        {
            byte[] b = Encoding.UTF8.GetBytes(s + "\0");
            IntPtr p = Marshal.AllocHGlobal(b.Length);
            Marshal.Copy(b, 0, p, b.Length);
            return p;
        }

        /// A grammar in memory with the text of its view file (.v).
        public static Tree FromLsystem(string source, string viewText)
        {
            byte[] bytes = Encoding.UTF8.GetBytes(source);
            var o = LsystemOptions.Default();
            o.ViewText = Utf8(viewText);
            try
            {
                IntPtr t;
                ArborException.Check(Native.arbor_tree_from_lsystem(bytes, (UIntPtr)bytes.Length, ref o, out t));
                return new Tree(t);
            }
            finally { Marshal.FreeHGlobal(o.ViewText); }
        }

        // One static callback for every call (IL2CPP needs a static method marked
        // MonoPInvokeCallback); the managed callback travels in a GCHandle as user data.
        static readonly ProgressFn progressTrampoline = ProgressTrampoline;

        [AOT.MonoPInvokeCallback(typeof(ProgressFn))]
        static int ProgressTrampoline(IntPtr user, uint stage, float fraction)
        {
            var f = (Func<uint, float, bool>)GCHandle.FromIntPtr(user).Target;
            try { return f(stage, fraction) ? 0 : 1; }
            catch (Exception) { return 1; } // an exception never crosses into native code
        }

        /// A grammar in memory, with `progress(stage, fraction)` called on this thread
        /// (return false to cancel: ArborException with Status.Cancelled).
        public static Tree FromLsystem(string source, Func<uint, float, bool> progress)
        {
            byte[] bytes = Encoding.UTF8.GetBytes(source);
            var o = LsystemOptions.Default();
            var handle = GCHandle.Alloc(progress);
            o.Progress = Marshal.GetFunctionPointerForDelegate(progressTrampoline);
            o.ProgressUserData = GCHandle.ToIntPtr(handle);
            try
            {
                IntPtr t;
                ArborException.Check(Native.arbor_tree_from_lsystem(bytes, (UIntPtr)bytes.Length, ref o, out t));
                return new Tree(t);
            }
            finally { handle.Free(); }
        }

        /// A cpfg file read as cpfg reads it: preprocessed, with its view file (viewPath,
        /// else the .v beside it).
        public static Tree FromLsystemFile(string path, string viewPath = null)
        {
            return FromLsystemFile(path, Arbor.FileAccess.Bundle, viewPath);
        }

        // One static reader for every call (IL2CPP-safe); the managed reader travels in a
        // GCHandle as user data.
        static readonly ReadFileFn readTrampoline = ReadTrampoline;

        [AOT.MonoPInvokeCallback(typeof(ReadFileFn))]
        static int ReadTrampoline(IntPtr user, IntPtr path, IntPtr buffer, UIntPtr capacity, out UIntPtr size)
        {
            size = UIntPtr.Zero;
            try
            {
                var read = (Func<string, byte[]>)GCHandle.FromIntPtr(user).Target;
                int n = 0;
                while (Marshal.ReadByte(path, n) != 0) n++;
                byte[] name = new byte[n];
                Marshal.Copy(path, name, 0, n);
                byte[] bytes = read(Encoding.UTF8.GetString(name));
                if (bytes == null) return 1;
                size = (UIntPtr)bytes.Length;
                int copy = (int)Math.Min((ulong)bytes.Length, (ulong)capacity);
                if (copy > 0) Marshal.Copy(bytes, 0, buffer, copy);
                return 0;
            }
            catch (Exception) { return 1; } // an exception never crosses into native code
        }

        /// A model read entirely through `read(path)` (FileAccess.Host): the grammar, its
        /// view file and everything they name come from the host (StreamingAssets,
        /// Addressables, a pak file); return null for "no such file". arbor opens nothing.
        public static Tree FromLsystemFile(string path, Func<string, byte[]> read)
        {
            var o = LsystemOptions.Default();
            var handle = GCHandle.Alloc(read);
            o.FileAccess = (uint)Arbor.FileAccess.Host;
            o.ReadFile = Marshal.GetFunctionPointerForDelegate(readTrampoline);
            o.ReadFileUserData = GCHandle.ToIntPtr(handle);
            try { return LoadFile(path, null, o); }
            finally { handle.Free(); }
        }

        /// A model file under a file policy (FileAccess.Bundle by default: its own folder).
        public static Tree FromLsystemFile(string path, FileAccess access, string viewPath = null)
        {
            var o = LsystemOptions.Default();
            o.FileAccess = (uint)access;
            return LoadFile(path, viewPath, o);
        }

        /// The one call behind the public overloads: `path` and `viewPath` as UTF-8 for the
        /// call's duration, with options the overload filled.
        static Tree LoadFile(string path, string viewPath, LsystemOptions o)
        {
            IntPtr p = Utf8(path);
            o.ViewPath = viewPath == null ? IntPtr.Zero : Utf8(viewPath);
            try
            {
                IntPtr t;
                ArborException.Check(Native.arbor_tree_from_lsystem_file(p, ref o, out t));
                return new Tree(t);
            }
            finally
            {
                Marshal.FreeHGlobal(p);
                if (o.ViewPath != IntPtr.Zero) Marshal.FreeHGlobal(o.ViewPath);
            }
        }

        public int BranchCount { get { return (int)Native.arbor_tree_branch_count(handle); } }

        public Curve[] Curves()
        {
            var c = new Curve[BranchCount];
            ArborException.Check(Native.arbor_tree_copy_curves(handle, c, (UIntPtr)c.Length));
            return c;
        }

        public void Smooth(float tension) { ArborException.Check(Native.arbor_tree_smooth(handle, tension)); }

        /// Replaces one branch's curve; its subtree follows the end.
        public void SetCurve(int branch, Curve curve) { ArborException.Check(Native.arbor_tree_set_curve(handle, (UIntPtr)branch, ref curve)); }

        /// Rewrites, in arrays holding the whole mesh (from Mesh()), what the edits since changed.
        public void RewriteBranch(MeshOptions options, int branch, Vertex[] vertices, int[] indices)
        {
            ArborException.Check(Native.arbor_mesh_rewrite_branch(handle, ref options, (UIntPtr)branch, vertices, (UIntPtr)vertices.Length, indices, (UIntPtr)indices.Length));
        }

        public Branch[] Branches()
        {
            var b = new Branch[BranchCount];
            ArborException.Check(Native.arbor_tree_copy_branches(handle, b, (UIntPtr)b.Length));
            return b;
        }

        /// The mesh as arrays, with arbor's own conventions.
        public void Mesh(MeshOptions options, out Vertex[] vertices, out int[] indices)
        {
            UIntPtr nv, ni;
            ArborException.Check(Native.arbor_mesh_size(handle, ref options, out nv, out ni));
            vertices = new Vertex[(int)nv];
            indices = new int[(int)ni];
            ArborException.Check(Native.arbor_mesh_write(handle, ref options, vertices, nv, indices, ni));
        }

        /// The mesh as compact vertices (20 bytes each); returns the v_scale a vertex's V is
        /// stored over (v = V / 65535 * vScale).
        public float MeshCompact(MeshOptions options, out VertexCompact[] vertices, out int[] indices)
        {
            options.VertexFormat = (uint)Arbor.VertexFormat.Compact;
            UIntPtr nv, ni;
            ArborException.Check(Native.arbor_mesh_size(handle, ref options, out nv, out ni));
            vertices = new VertexCompact[(int)nv];
            indices = new int[(int)ni];
            var bytes = (UIntPtr)((ulong)nv * (ulong)Marshal.SizeOf(typeof(VertexCompact)));
            ArborException.Check(Native.arbor_mesh_write_bytes(handle, ref options, vertices, bytes, indices, ni));
            float vScale;
            ArborException.Check(Native.arbor_mesh_v_scale(handle, ref options, out vScale));
            return vScale;
        }

        /// The mesh as arrays, with `progress(stage, fraction)` called on this thread while
        /// it is written (return false to cancel: ArborException with Status.Cancelled).
        public void Mesh(MeshOptions options, Func<uint, float, bool> progress, out Vertex[] vertices, out int[] indices)
        {
            var handle = GCHandle.Alloc(progress);
            options.Progress = Marshal.GetFunctionPointerForDelegate(progressTrampoline);
            options.ProgressUserData = GCHandle.ToIntPtr(handle);
            try { Mesh(options, out vertices, out indices); }
            finally { handle.Free(); }
        }

        /// A triangle list for Unity, by arbor's Unity preset: x mirrored into Unity's
        /// left-handed space and clockwise front faces, written by the library in one pass.
        /// Feed the arrays to Mesh.SetVertexBufferData / SetIndexBufferData.
        public void UnityMeshArrays(MeshOptions options, out Vertex[] vertices, out int[] indices)
        {
            options.Topology = (uint)Arbor.Topology.TriangleList;
            options.Winding = (uint)Winding.CounterClockwise;
            options.UpAxis = (uint)UpAxis.Y;
            options.Axes = (uint)Arbor.Axes.Unity;
            Mesh(options, out vertices, out indices);
        }

        /// Up to `max` collision capsules of the trunk and limbs thicker than `minRadius`
        /// (0: a tenth of the trunk's), in the conventions of `options`.
        public Capsule[] Capsules(MeshOptions options, uint max, float minRadius)
        {
            UIntPtr n;
            ArborException.Check(Native.arbor_tree_capsules_write(handle, ref options, max, minRadius, null, UIntPtr.Zero, out n));
            var c = new Capsule[(int)n];
            UIntPtr again;
            ArborException.Check(Native.arbor_tree_capsules_write(handle, ref options, max, minRadius, c, n, out again));
            return c;
        }

        /// Capsules in Unity's conventions (left-handed, Y up): what UnityColliders.Add takes.
        public Capsule[] UnityCapsules(MeshOptions options, uint max, float minRadius)
        {
            options.UpAxis = (uint)UpAxis.Y;
            options.Axes = (uint)Arbor.Axes.Unity;
            return Capsules(options, max, minRadius);
        }

        /// The wind skin's bones (at most `maxBones`, 1..=64) in the conventions of `options`,
        /// and their inverse bind matrices, 16 floats a bone, column-major.
        public Bone[] Bones(MeshOptions options, uint maxBones, out float[] inverseBind)
        {
            UIntPtr n;
            ArborException.Check(Native.arbor_tree_bones_write(handle, ref options, maxBones, null, null, UIntPtr.Zero, out n));
            var bones = new Bone[(int)n];
            inverseBind = new float[16 * (int)n];
            UIntPtr again;
            ArborException.Check(Native.arbor_tree_bones_write(handle, ref options, maxBones, bones, inverseBind, n, out again));
            return bones;
        }

        /// Each branch's pivot for a Pivot-Painter-style wind shader (arbor_tree_pivots_write):
        /// 8 floats a branch, its start (x, y, z), length, unit axis (x, y, z) and parent
        /// (-1 for a root), in the conventions of `options`.
        public float[] Pivots(MeshOptions options)
        {
            UIntPtr n, again;
            ArborException.Check(Native.arbor_tree_pivots_write(handle, ref options, null, UIntPtr.Zero, out n));
            var pivots = new float[8 * (int)n];
            ArborException.Check(Native.arbor_tree_pivots_write(handle, ref options, pivots, n, out again));
            return pivots;
        }

        /// Four joints and four weights (summing to one) a vertex of the mesh Mesh(options)
        /// writes, on the bones of Bones(options, maxBones): Unity's BoneWeight layout.
        public void Skin(MeshOptions options, uint maxBones, out ushort[] joints, out float[] weights)
        {
            UIntPtr n;
            ArborException.Check(Native.arbor_mesh_skin_write(handle, ref options, maxBones, null, null, UIntPtr.Zero, out n));
            joints = new ushort[4 * (int)n];
            weights = new float[4 * (int)n];
            UIntPtr again;
            ArborException.Check(Native.arbor_mesh_skin_write(handle, ref options, maxBones, joints, weights, n, out again));
        }

        /// The looping wind clip of Bones(options, maxBones): key times, and each bone's
        /// rotation from its rest at each key (x, y, z, w; bone b's key k at 4 * (b * keys + k)).
        public float[] WindClip(MeshOptions options, uint maxBones, float[] wind, float strength, float duration, uint keysPerSecond, ulong seed, out float[] times)
        {
            UIntPtr keys, bones;
            ArborException.Check(Native.arbor_tree_wind_clip_write(handle, ref options, maxBones, wind, strength, duration, keysPerSecond, seed, null, UIntPtr.Zero, null, UIntPtr.Zero, out keys, out bones));
            times = new float[(int)keys];
            var rotations = new float[4 * (int)keys * (int)bones];
            ArborException.Check(Native.arbor_tree_wind_clip_write(handle, ref options, maxBones, wind, strength, duration, keysPerSecond, seed, times, keys, rotations, bones, out keys, out bones));
            return rotations;
        }

        /// The tree's levels of detail (bark and baked leaves), in the conventions of
        /// `options`; `atlas` (RGBA8, width x height, or null) is the leaf atlas the
        /// leaves' silhouettes are tested against.
        public Lods Lods(MeshOptions options, LeafOptions leaves, LodOptions lod, byte[] atlas, uint width, uint height)
        {
            IntPtr l;
            ArborException.Check(Native.arbor_tree_lods_create(handle, ref options, ref leaves, atlas, width, height, ref lod, out l));
            return new Lods(l);
        }

        public LeafInstance[] Leaves(LeafOptions leaves, MeshOptions options)
        {
            UIntPtr n;
            ArborException.Check(Native.arbor_leaf_instance_count(handle, ref leaves, ref options, out n));
            var l = new LeafInstance[(int)n];
            ArborException.Check(Native.arbor_leaf_instances_write(handle, ref leaves, ref options, l, n));
            return l;
        }

        public void Dispose()
        {
            if (handle != IntPtr.Zero)
            {
                Native.arbor_tree_free(handle);
                handle = IntPtr.Zero;
            }
        }
    }

    /// A tree's levels of detail (Tree.Lods): each level's screen coverage, silhouette and
    /// meshes.
    public sealed class Lods : IDisposable
    {
        IntPtr handle;
        internal Lods(IntPtr h) { handle = h; }

        public int Count { get { return (int)Native.arbor_lods_count(handle); } }

        /// Drawn while the tree covers at least this share of the screen's height (Unity's
        /// LOD.screenRelativeTransitionHeight).
        public float ScreenCoverage(int level)
        {
            float c, s; UIntPtr t;
            ArborException.Check(Native.arbor_lods_level_info(handle, (UIntPtr)level, out c, out s, out t));
            return c;
        }

        /// Part 0 (bark) or 1 (leaves) of a level, size then fill.
        public void Mesh(int level, uint part, out Vertex[] vertices, out uint[] indices)
        {
            UIntPtr nv, ni;
            ArborException.Check(Native.arbor_lods_mesh_write(handle, (UIntPtr)level, part, null, UIntPtr.Zero, null, UIntPtr.Zero, out nv, out ni));
            vertices = new Vertex[(int)nv];
            indices = new uint[(int)ni];
            ArborException.Check(Native.arbor_lods_mesh_write(handle, (UIntPtr)level, part, vertices, nv, indices, ni, out nv, out ni));
        }

        /// The billboard of a level (arbor_lods_billboard_create): `planes` (2..=4) crossed
        /// quads, each drawn into a cell of `cell` pixels; the leaves sample the atlas the
        /// levels were made with (null: opaque cards).
        public Billboard Billboard(int level, uint planes, uint cell, byte[] atlasRgba, uint atlasWidth, uint atlasHeight)
        {
            IntPtr b;
            ArborException.Check(Native.arbor_lods_billboard_create(handle, (UIntPtr)level, planes, cell, atlasRgba, atlasWidth, atlasHeight, out b));
            return new Billboard(b);
        }

        /// The skin of part 0 (bark) or 1 (leaves) of a level (arbor_lods_skin_write): four
        /// joints and four weights a vertex, in Mesh()'s vertex order, on the tree's
        /// Bones(options, maxBones) for the options the levels were made with.
        public void Skin(int level, uint part, uint maxBones, out ushort[] joints, out float[] weights)
        {
            UIntPtr n, again;
            ArborException.Check(Native.arbor_lods_skin_write(handle, (UIntPtr)level, part, maxBones, null, null, UIntPtr.Zero, out n));
            joints = new ushort[4 * (int)n];
            weights = new float[4 * (int)n];
            ArborException.Check(Native.arbor_lods_skin_write(handle, (UIntPtr)level, part, maxBones, joints, weights, n, out again));
        }

        /// The level an impostor of `cell`-pixel views is best baked from
        /// (arbor_lods_impostor_level): the coarsest made for views at least that large,
        /// 0 (the full tree) when none is.
        public int ImpostorLevel(uint cell) { return (int)Native.arbor_lods_impostor_level(handle, cell); }

        /// The octahedral impostor of a level (arbor_lods_impostor_create): `frames` x
        /// `frames` views (1..=32) of `cell` pixels (8..=1024), of the upper half of the
        /// sphere when `hemi`, the leaves sampling the leaf atlas `atlasRgba` (null:
        /// opaque cards). The package's Arbor/Impostor shader draws it (UnityLods.Build).
        public Impostor Impostor(int level, uint frames, uint cell, bool hemi, byte[] atlasRgba, uint atlasWidth, uint atlasHeight)
        {
            IntPtr i;
            ArborException.Check(Native.arbor_lods_impostor_create(handle, (UIntPtr)level, frames, cell, hemi ? 1u : 0u, atlasRgba, atlasWidth, atlasHeight, out i));
            return new Impostor(i, frames, hemi);
        }

        public void Dispose()
        {
            if (handle != IntPtr.Zero)
            {
                Native.arbor_lods_free(handle);
                handle = IntPtr.Zero;
            }
        }
    }

    /// Crossed quads with their atlas, for hosts without an impostor shader: any
    /// alpha-tested material draws them.
    public sealed class Billboard : IDisposable
    {
        IntPtr handle;
        internal Billboard(IntPtr h) { handle = h; }

        /// The quads (a triangle list; with `twoSided` each also wound the other way).
        public void Mesh(bool twoSided, out Vertex[] vertices, out uint[] indices)
        {
            UIntPtr nv, ni;
            uint t = twoSided ? 1u : 0u;
            ArborException.Check(Native.arbor_billboard_mesh_write(handle, t, null, UIntPtr.Zero, null, UIntPtr.Zero, out nv, out ni));
            vertices = new Vertex[(int)nv];
            indices = new uint[(int)ni];
            ArborException.Check(Native.arbor_billboard_mesh_write(handle, t, vertices, nv, indices, ni, out nv, out ni));
        }

        /// Atlas `which` (0: albedo and coverage, 1: normal and depth), RGBA8, rows from
        /// the top (the quads' v 0): loaded as is, Unity's first row is v 0 too.
        public byte[] Atlas(uint which, out uint width, out uint height)
        {
            ArborException.Check(Native.arbor_billboard_atlas_write(handle, which, null, UIntPtr.Zero, out width, out height));
            var rgba = new byte[(int)(width * height * 4)];
            ArborException.Check(Native.arbor_billboard_atlas_write(handle, which, rgba, (UIntPtr)rgba.Length, out width, out height));
            return rgba;
        }

        public void Dispose()
        {
            if (handle != IntPtr.Zero)
            {
                Native.arbor_billboard_free(handle);
                handle = IntPtr.Zero;
            }
        }
    }

    /// An octahedral impostor's atlases and frame (Lods.Impostor), in the tree's space:
    /// the package's Arbor/Impostor shader draws it on one quad turned to the camera
    /// (UnityLods.Build; docs/meshes.md, "Impostors", for the layout).
    public sealed class Impostor : IDisposable
    {
        IntPtr handle;
        /// Views a side of the grid.
        public readonly uint Frames;
        /// Views of the upper half of the sphere (hemi-octahedral), else the whole.
        public readonly bool Hemi;
        internal Impostor(IntPtr h, uint frames, bool hemi) { handle = h; Frames = frames; Hemi = hemi; }

        /// The bounding sphere the views frame (`centre`, 3 floats, and `radius`) and the
        /// tree's up axis (`up`, 3 floats); returns the atlases' side in pixels.
        public uint Frame(float[] centre, out float radius, float[] up)
        {
            if (centre == null || centre.Length < 3 || up == null || up.Length < 3)
                throw new ArgumentException("centre and up need 3 floats each");
            uint size;
            ArborException.Check(Native.arbor_impostor_info(handle, out size, centre, out radius, up));
            return size;
        }

        /// Atlas `which` (0: albedo and coverage, sRGB; 1: normal and depth), RGBA8, rows
        /// from the top: loaded as is, Unity's first row is v 0, where the shader reads the
        /// top row of a view.
        public byte[] Atlas(uint which, out uint size)
        {
            UIntPtr n;
            ArborException.Check(Native.arbor_impostor_atlas_write(handle, which, null, UIntPtr.Zero, out n));
            var rgba = new byte[(int)n];
            ArborException.Check(Native.arbor_impostor_atlas_write(handle, which, rgba, n, out n));
            float r;
            size = Frame(new float[3], out r, new float[3]);
            return rgba;
        }

        public void Dispose()
        {
            if (handle != IntPtr.Zero)
            {
                Native.arbor_impostor_free(handle);
                handle = IntPtr.Zero;
            }
        }
    }

#if UNITY_5_3_OR_NEWER
    public static class UnityMeshes
    {
        /// arbor's 32-byte Vertex as Unity's vertex buffer layout: position, normal, uv.
        public static UnityEngine.Rendering.VertexAttributeDescriptor[] VertexLayout()
        {
            return new[]
            {
                new UnityEngine.Rendering.VertexAttributeDescriptor(UnityEngine.Rendering.VertexAttribute.Position, UnityEngine.Rendering.VertexAttributeFormat.Float32, 3),
                new UnityEngine.Rendering.VertexAttributeDescriptor(UnityEngine.Rendering.VertexAttribute.Normal, UnityEngine.Rendering.VertexAttributeFormat.Float32, 3),
                new UnityEngine.Rendering.VertexAttributeDescriptor(UnityEngine.Rendering.VertexAttribute.TexCoord0, UnityEngine.Rendering.VertexAttributeFormat.Float32, 2),
            };
        }

        /// Fills `mesh` with the tree's bark in one upload (32-bit indices).
        public static void Fill(UnityEngine.Mesh mesh, Tree tree, MeshOptions options)
        {
            Vertex[] v;
            int[] i;
            tree.UnityMeshArrays(options, out v, out i);
            SetBuffers(mesh, v, VertexLayout(), i, i.Length);
            mesh.RecalculateBounds();
        }

        /// Gives `mesh` its vertices (laid out as `layout`), 32-bit indices and one
        /// submesh per count of `submeshes`, each the next run of indices.
        public static void SetBuffers<T>(UnityEngine.Mesh mesh, T[] vertices, UnityEngine.Rendering.VertexAttributeDescriptor[] layout, int[] indices, params int[] submeshes) where T : struct
        {
            mesh.SetVertexBufferParams(vertices.Length, layout);
            mesh.SetVertexBufferData(vertices, 0, 0, vertices.Length);
            mesh.SetIndexBufferParams(indices.Length, UnityEngine.Rendering.IndexFormat.UInt32);
            mesh.SetIndexBufferData(indices, 0, 0, indices.Length);
            mesh.subMeshCount = submeshes.Length;
            int start = 0;
            for (int k = 0; k < submeshes.Length; k++)
            {
                mesh.SetSubMesh(k, new UnityEngine.Rendering.SubMeshDescriptor(start, submeshes[k]));
                start += submeshes[k];
            }
        }
    }

    public static class UnityLods
    {
        /// Builds a LODGroup on `root`: a child "NAME_LODk" per level with a MeshFilter and
        /// a MeshRenderer (submesh 0 the bark, 1 the leaves), each drawn down to its
        /// screen coverage. Make `lods` in Unity's conventions (MeshOptions.Axes Unity,
        /// a triangle list). Returns the LODGroup.
        public static UnityEngine.LODGroup Build(UnityEngine.GameObject root, Lods lods, string name)
        {
            return Build(root, lods, name, (Billboard)null, null, 0f);
        }

        /// Build, then the billboard as the last level ("NAME_LODn", both sides, drawn
        /// down to `coverage`; 0: a quarter of the last mesh level's), with `material`
        /// (alpha-tested; null: none set) its main texture the billboard's albedo.
        public static UnityEngine.LODGroup Build(UnityEngine.GameObject root, Lods lods, string name, Billboard billboard, UnityEngine.Material material, float coverage)
        {
            var group = root.AddComponent<UnityEngine.LODGroup>();
            int meshes = lods.Count;
            var levels = MeshLevels(root, lods, name, billboard != null ? 1 : 0);
            if (billboard != null)
            {
                var go = new UnityEngine.GameObject(name + "_LOD" + meshes);
                go.transform.SetParent(root.transform, false);
                Vertex[] v; uint[] bi;
                billboard.Mesh(true, out v, out bi);
                var i = new int[bi.Length];
                for (int j = 0; j < bi.Length; j++) i[j] = (int)bi[j];
                var mesh = new UnityEngine.Mesh();
                UnityMeshes.SetBuffers(mesh, v, UnityMeshes.VertexLayout(), i, i.Length);
                mesh.RecalculateBounds();
                go.AddComponent<UnityEngine.MeshFilter>().mesh = mesh;
                var renderer = go.AddComponent<UnityEngine.MeshRenderer>();
                if (material != null)
                {
                    uint w, h;
                    var rgba = billboard.Atlas(0, out w, out h);
                    var texture = new UnityEngine.Texture2D((int)w, (int)h, UnityEngine.TextureFormat.RGBA32, false);
                    texture.LoadRawTextureData(rgba);
                    texture.Apply();
                    material.mainTexture = texture;
                    renderer.sharedMaterial = material;
                }
                levels[meshes] = new UnityEngine.LOD(Farthest(lods, coverage), new UnityEngine.Renderer[] { renderer });
            }
            group.SetLODs(levels);
            group.RecalculateBounds();
            return group;
        }

        /// Build, then the octahedral impostor as the last level ("NAME_LODn": one quad,
        /// its corners (+-1, +-1, 0), that the package's Arbor/Impostor shader turns to
        /// the camera about the impostor's bounding sphere, its bounds that sphere), with
        /// `material` (its shader Arbor/Impostor; null: none set) given the albedo and the
        /// normal and depth atlases and the impostor's frame, drawn down to `coverage` (0: a quarter of the last
        /// mesh level's). Make the impostor from `lods` (Lods.Impostor).
        public static UnityEngine.LODGroup Build(UnityEngine.GameObject root, Lods lods, string name, Impostor impostor, UnityEngine.Material material, float coverage)
        {
            var group = root.AddComponent<UnityEngine.LODGroup>();
            int meshes = lods.Count;
            var levels = MeshLevels(root, lods, name, 1);
            var centre = new float[3];
            var up = new float[3];
            float radius;
            impostor.Frame(centre, out radius, up);
            var go = new UnityEngine.GameObject(name + "_LOD" + meshes);
            go.transform.SetParent(root.transform, false);
            var corners = new UnityEngine.Vector3[]
            {
                new UnityEngine.Vector3(-1f, -1f, 0f), new UnityEngine.Vector3(1f, -1f, 0f),
                new UnityEngine.Vector3(1f, 1f, 0f), new UnityEngine.Vector3(-1f, 1f, 0f),
            };
            var quad = new int[] { 0, 1, 2, 0, 2, 3 };
            var mesh = new UnityEngine.Mesh();
            var position = new UnityEngine.Rendering.VertexAttributeDescriptor(UnityEngine.Rendering.VertexAttribute.Position, UnityEngine.Rendering.VertexAttributeFormat.Float32, 3);
            UnityMeshes.SetBuffers(mesh, corners, new[] { position }, quad, quad.Length);
            // The shader moves the corners: the bounds are the sphere it keeps them in.
            var middle = new UnityEngine.Vector3(centre[0], centre[1], centre[2]);
            mesh.bounds = new UnityEngine.Bounds(middle, new UnityEngine.Vector3(2f * radius, 2f * radius, 2f * radius));
            go.AddComponent<UnityEngine.MeshFilter>().mesh = mesh;
            var renderer = go.AddComponent<UnityEngine.MeshRenderer>();
            if (material != null)
            {
                uint size;
                var rgba = impostor.Atlas(0, out size);
                var texture = new UnityEngine.Texture2D((int)size, (int)size, UnityEngine.TextureFormat.RGBA32, false);
                texture.LoadRawTextureData(rgba);
                texture.Apply();
                material.mainTexture = texture;
                // The normal and depth atlas, linear (its alpha is a depth, not a colour).
                var depth = new UnityEngine.Texture2D((int)size, (int)size, UnityEngine.TextureFormat.RGBA32, false, true);
                depth.LoadRawTextureData(impostor.Atlas(1, out size));
                depth.Apply();
                material.SetTexture("_DepthTex", depth);
                material.SetFloat("_Frames", impostor.Frames);
                material.SetFloat("_Cell", size / impostor.Frames);
                material.SetFloat("_Hemi", impostor.Hemi ? 1f : 0f);
                material.SetVector("_Centre", new UnityEngine.Vector4(centre[0], centre[1], centre[2], 0f));
                material.SetFloat("_Radius", radius);
                material.SetVector("_Up", new UnityEngine.Vector4(up[0], up[1], up[2], 0f));
                renderer.sharedMaterial = material;
            }
            levels[meshes] = new UnityEngine.LOD(Farthest(lods, coverage), new UnityEngine.Renderer[] { renderer });
            group.SetLODs(levels);
            group.RecalculateBounds();
            return group;
        }

        /// Where the last level is drawn down to: `coverage`, or (0) a quarter of the last
        /// mesh level's.
        static float Farthest(Lods lods, float coverage)
        {
            float last = lods.Count > 0 ? lods.ScreenCoverage(lods.Count - 1) : 1f;
            return coverage > 0f ? coverage : 0.25f * last;
        }

        /// The mesh levels' children and LOD entries, with `extra` entries left at the end.
        static UnityEngine.LOD[] MeshLevels(UnityEngine.GameObject root, Lods lods, string name, int extra)
        {
            var levels = new UnityEngine.LOD[lods.Count + extra];
            for (int k = 0; k < lods.Count; k++)
            {
                var go = new UnityEngine.GameObject(name + "_LOD" + k);
                go.transform.SetParent(root.transform, false);
                var mesh = new UnityEngine.Mesh();
                Vertex[] bark, leaves; uint[] bi, li;
                lods.Mesh(k, 0, out bark, out bi);
                lods.Mesh(k, 1, out leaves, out li);
                var v = new Vertex[bark.Length + leaves.Length];
                Array.Copy(bark, v, bark.Length);
                Array.Copy(leaves, 0, v, bark.Length, leaves.Length);
                var i = new int[bi.Length + li.Length];
                for (int j = 0; j < bi.Length; j++) i[j] = (int)bi[j];
                for (int j = 0; j < li.Length; j++) i[bi.Length + j] = (int)(li[j] + (uint)bark.Length);
                UnityMeshes.SetBuffers(mesh, v, UnityMeshes.VertexLayout(), i, bi.Length, li.Length);
                mesh.RecalculateBounds();
                go.AddComponent<UnityEngine.MeshFilter>().mesh = mesh;
                var renderer = go.AddComponent<UnityEngine.MeshRenderer>();
                levels[k] = new UnityEngine.LOD(lods.ScreenCoverage(k), new UnityEngine.Renderer[] { renderer });
            }
            return levels;
        }
    }

    public static class UnityColliders
    {
        /// Adds a child "UCP_NN" with a CapsuleCollider under `parent` for each capsule
        /// (from Tree.UnityCapsules): centred between its ends, along them, its height the
        /// length plus both caps. Returns the children.
        public static UnityEngine.GameObject[] Add(UnityEngine.Transform parent, Capsule[] capsules)
        {
            var made = new UnityEngine.GameObject[capsules.Length];
            for (int k = 0; k < capsules.Length; k++)
            {
                var c = capsules[k];
                var a = new UnityEngine.Vector3(c.AX, c.AY, c.AZ);
                var b = new UnityEngine.Vector3(c.BX, c.BY, c.BZ);
                var go = new UnityEngine.GameObject("UCP_" + k.ToString("00"));
                go.transform.SetParent(parent, false);
                go.transform.localPosition = (a + b) * 0.5f;
                go.transform.localRotation = UnityEngine.Quaternion.FromToRotation(UnityEngine.Vector3.up, b - a);
                var collider = go.AddComponent<UnityEngine.CapsuleCollider>();
                collider.direction = 1;
                collider.radius = c.Radius;
                collider.height = (b - a).magnitude + 2f * c.Radius;
                made[k] = go;
            }
            return made;
        }
    }
#endif
}
