// The few UnityEngine types the binding's `#if UNITY_5_3_OR_NEWER` helpers and the sample
// use, as stand-ins that record what they are given: tests/unity.rs compiles the helpers
// against them (with UNITY_5_3_OR_NEWER defined) and checks what reached the "mesh".
using System;

namespace AOT
{
    [AttributeUsage(AttributeTargets.Method)]
    public sealed class MonoPInvokeCallbackAttribute : Attribute
    {
        public MonoPInvokeCallbackAttribute(Type type) { }
    }
}

namespace UnityEngine.Rendering
{
    public enum VertexAttribute { Position, Normal, Tangent, Color, TexCoord0 }
    public enum VertexAttributeFormat { Float32 }
    public enum IndexFormat { UInt16, UInt32 }
    public struct VertexAttributeDescriptor
    {
        public VertexAttribute attribute; public VertexAttributeFormat format; public int dimension;
        public VertexAttributeDescriptor(VertexAttribute a, VertexAttributeFormat f, int d) { attribute = a; format = f; dimension = d; }
    }
    public struct SubMeshDescriptor
    {
        public int indexStart, indexCount;
        public SubMeshDescriptor(int start, int count) { indexStart = start; indexCount = count; }
    }
}

namespace UnityEngine
{
    using UnityEngine.Rendering;

    public class Object { }
    public class Component : Object
    {
        public T GetComponent<T>() where T : new() { return new T(); }
    }
    public class Behaviour : Component { }
    public class MonoBehaviour : Behaviour { }
    public class MeshFilter : Component { public Mesh mesh; }

    [AttributeUsage(AttributeTargets.Class, AllowMultiple = true)]
    public sealed class RequireComponent : Attribute { public RequireComponent(Type t) { } }

    public class Mesh : Object
    {
        /// Every mesh made, in order (a test finds the ones the helpers made).
        public static System.Collections.Generic.List<Mesh> made = new System.Collections.Generic.List<Mesh>();
        public Mesh() { made.Add(this); }
        public Bounds bounds;
        public System.Collections.Generic.List<SubMeshDescriptor> subMeshes = new System.Collections.Generic.List<SubMeshDescriptor>();
        public int vertexCount, indexCount, vertexStride;
        public IndexFormat indexFormat;
        public VertexAttributeDescriptor[] layout;
        public Array vertices, indices;
        public SubMeshDescriptor subMesh;
        public int subMeshCount { get; set; }
        public bool boundsRecalculated;
        public void SetVertexBufferParams(int count, params VertexAttributeDescriptor[] l) { vertexCount = count; layout = l; }
        public void SetVertexBufferData<T>(T[] data, int start, int meshStart, int count) where T : struct { vertices = data; vertexStride = System.Runtime.InteropServices.Marshal.SizeOf(typeof(T)); }
        public void SetIndexBufferParams(int count, IndexFormat f) { indexCount = count; indexFormat = f; }
        public void SetIndexBufferData<T>(T[] data, int start, int meshStart, int count) where T : struct { indices = data; }
        public void SetSubMesh(int i, SubMeshDescriptor d) { subMesh = d; subMeshes.Add(d); }
        public void RecalculateBounds() { boundsRecalculated = true; }
    }

    public struct Vector3
    {
        public float x, y, z;
        public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public static Vector3 up { get { return new Vector3(0, 1, 0); } }
        public float magnitude { get { return (float)Math.Sqrt(x * x + y * y + z * z); } }
        public static Vector3 operator +(Vector3 a, Vector3 b) { return new Vector3(a.x + b.x, a.y + b.y, a.z + b.z); }
        public static Vector3 operator -(Vector3 a, Vector3 b) { return new Vector3(a.x - b.x, a.y - b.y, a.z - b.z); }
        public static Vector3 operator *(Vector3 a, float f) { return new Vector3(a.x * f, a.y * f, a.z * f); }
    }
    public struct Vector4
    {
        public float x, y, z, w;
        public Vector4(float x, float y, float z, float w) { this.x = x; this.y = y; this.z = z; this.w = w; }
    }
    public struct Bounds
    {
        public Vector3 center, size;
        public Bounds(Vector3 center, Vector3 size) { this.center = center; this.size = size; }
    }
    public struct Quaternion
    {
        public Vector3 from, to;
        public static Quaternion FromToRotation(Vector3 f, Vector3 t) { return new Quaternion { from = f, to = t }; }
    }
    public class Transform : Component
    {
        public Transform parent;
        public Vector3 localPosition;
        public Quaternion localRotation;
        public void SetParent(Transform p, bool worldPositionStays) { parent = p; }
    }
    public class Collider : Component { }
    public class Renderer : Component { public Material sharedMaterial; }
    public class Texture { }
    public enum TextureFormat { RGBA32 = 4 }
    public class Texture2D : Texture
    {
        public int width, height;
        public TextureFormat format;
        public byte[] data;
        public bool applied;
        public bool linear;
        public Texture2D(int w, int h, TextureFormat f, bool mipChain) { width = w; height = h; format = f; }
        public Texture2D(int w, int h, TextureFormat f, bool mipChain, bool linearData) { width = w; height = h; format = f; linear = linearData; }
        public void LoadRawTextureData(byte[] d) { data = d; }
        public void Apply() { applied = true; }
    }
    public class Material : Object
    {
        public Texture mainTexture;
        public System.Collections.Generic.Dictionary<string, float> floats = new System.Collections.Generic.Dictionary<string, float>();
        public System.Collections.Generic.Dictionary<string, Vector4> vectors = new System.Collections.Generic.Dictionary<string, Vector4>();
        public void SetFloat(string name, float value) { floats[name] = value; }
        public void SetVector(string name, Vector4 value) { vectors[name] = value; }
        public System.Collections.Generic.Dictionary<string, Texture> textures = new System.Collections.Generic.Dictionary<string, Texture>();
        public void SetTexture(string name, Texture value) { textures[name] = value; }
    }
    public class MeshRenderer : Renderer { }
    public struct LOD
    {
        public float screenRelativeTransitionHeight;
        public Renderer[] renderers;
        public LOD(float height, Renderer[] r) { screenRelativeTransitionHeight = height; renderers = r; }
    }
    public class LODGroup : Component
    {
        public LOD[] lods;
        public bool boundsRecalculated;
        public void SetLODs(LOD[] l) { lods = l; }
        public void RecalculateBounds() { boundsRecalculated = true; }
    }
    public class CapsuleCollider : Collider
    {
        public float radius, height;
        public int direction;
    }
    public class GameObject : Object
    {
        public string name;
        public Transform transform = new Transform();
        public System.Collections.Generic.List<Component> components = new System.Collections.Generic.List<Component>();
        public GameObject(string name) { this.name = name; }
        public T AddComponent<T>() where T : Component, new() { var c = new T(); components.Add(c); return c; }
    }
}
