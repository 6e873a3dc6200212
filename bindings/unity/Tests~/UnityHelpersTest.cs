// Runs the binding's Unity helper (compiled with UNITY_5_3_OR_NEWER against the stubs):
// UnityMeshes.Fill must hand the "mesh" the tree's arrays, 32-byte vertices, 32-bit
// indices and one submesh over all of them.
using System;
using Arbor;

public static class UnityHelpersTest
{
    public static int Main()
    {
        int failed = 0;
        Action<bool, string> expect = (ok, what) => { if (!ok) { failed++; Console.WriteLine("FAILED: " + what); } };
        using (var tree = Tree.FromPreset('g'))
        {
            var options = MeshOptions.Default();
            Vertex[] v; int[] i;
            tree.UnityMeshArrays(options, out v, out i);
            var mesh = new UnityEngine.Mesh();
            UnityMeshes.Fill(mesh, tree, options);
            expect(mesh.vertexCount == v.Length && mesh.vertexCount > 0, "vertex count " + mesh.vertexCount);
            expect(mesh.indexCount == i.Length && mesh.indexCount % 3 == 0, "index count " + mesh.indexCount);
            expect(mesh.vertexStride == 32 && mesh.layout.Length == 3, "layout");
            expect(mesh.indexFormat == UnityEngine.Rendering.IndexFormat.UInt32, "32-bit indices");
            expect(mesh.subMeshCount == 1 && mesh.subMesh.indexCount == i.Length, "one submesh");
            expect(mesh.boundsRecalculated, "bounds");
            // Collision: one child with a capsule collider per capsule, along it.
            var caps = tree.UnityCapsules(options, 12, 0f);
            expect(caps.Length > 0 && caps.Length <= 12, "capsules " + caps.Length);
            var root = new UnityEngine.GameObject("tree");
            var made = UnityColliders.Add(root.transform, caps);
            expect(made.Length == caps.Length, "one child a capsule");
            for (int k = 0; k < made.Length; k++)
            {
                var col = (UnityEngine.CapsuleCollider)made[k].components[0];
                expect(made[k].transform.parent == root.transform, "parented");
                expect(col.direction == 1 && col.radius == caps[k].Radius && col.height >= 2f * col.radius, "collider " + k);
                expect(made[k].name.StartsWith("UCP_"), "named " + made[k].name);
            }
        }
        // Levels of detail: a LODGroup of four children, coverages falling, bark then leaves.
        using (var tree = Tree.FromPreset('b'))
        {
            var mo = MeshOptions.Default();
            mo.Axes = (uint)Arbor.Axes.Unity;
            mo.Threads = 1;
            var lo = LeafOptions.Default();
            lo.Sites = 0; lo.Tips = 1; lo.Density = 3f; lo.Size = 8f;
            var lod = LodOptions.Default();
            expect(lod.Levels == 4 && lod.StructSize == (uint)System.Runtime.InteropServices.Marshal.SizeOf(typeof(LodOptions)), "lod defaults");
            using (var lods = tree.Lods(mo, lo, lod, null, 0, 0))
            {
                var root = new UnityEngine.GameObject("tree");
                var group = UnityLods.Build(root, lods, "tree");
                expect(group.lods.Length == 4 && group.boundsRecalculated, "four levels");
                for (int k = 0; k < group.lods.Length; k++)
                {
                    expect(group.lods[k].renderers.Length == 1, "a renderer a level");
                    expect(k == 0 || group.lods[k].screenRelativeTransitionHeight <= group.lods[k - 1].screenRelativeTransitionHeight, "coverage falls at " + k);
                }
                // Every level's bark and leaves skinned on the tree's bones, a skin vertex a
                // mesh vertex, the weights summing to one.
                float[] ib;
                int boneCount = tree.Bones(mo, 16, out ib).Length;
                var pivots = tree.Pivots(mo);
                expect(pivots.Length == 8 * tree.BranchCount && pivots[7] == -1f, "a pivot a branch, the trunk a root");
                for (int k = 0; k < lods.Count; k++)
                {
                    for (uint part = 0; part < 2; part++)
                    {
                        Vertex[] lv; uint[] li; ushort[] sj; float[] sw;
                        lods.Mesh(k, part, out lv, out li);
                        lods.Skin(k, part, 16, out sj, out sw);
                        bool summed = sw.Length == 4 * lv.Length && sj.Length == sw.Length;
                        for (int v = 0; summed && v < lv.Length; v++)
                            summed = Math.Abs(sw[4 * v] + sw[4 * v + 1] + sw[4 * v + 2] + sw[4 * v + 3] - 1f) < 1e-4f
                                && sj[4 * v] < boneCount;
                        expect(summed && lv.Length > 0, "level " + k + " part " + part + "'s skin");
                    }
                }
                // The billboard as a fifth level: both sides, its albedo the material's.
                using (var bb = lods.Billboard(lods.Count - 1, 3, 32, null, 0, 0))
                {
                    var withCard = new UnityEngine.GameObject("tree");
                    var material = new UnityEngine.Material();
                    var g5 = UnityLods.Build(withCard, lods, "tree", bb, material, 0f);
                    expect(g5.lods.Length == 5, "five levels with the billboard");
                    var card = g5.lods[4];
                    expect(card.screenRelativeTransitionHeight > 0f && card.screenRelativeTransitionHeight < g5.lods[3].screenRelativeTransitionHeight, "the billboard drawn farthest");
                    var tex = (UnityEngine.Texture2D)material.mainTexture;
                    expect(tex != null && tex.width == 96 && tex.height == 32 && tex.data.Length == 96 * 32 * 4 && tex.applied, "the billboard's texture");
                    expect(card.renderers[0].sharedMaterial == material, "the billboard's material");
                    Vertex[] cv; uint[] ci;
                    bb.Mesh(true, out cv, out ci);
                    expect(cv.Length == 24 && ci.Length == 36, "three quads, both sides: " + cv.Length);
                }
                // The octahedral impostor as a fifth level: one quad bounded by the
                // impostor's sphere, the material given its albedo and frame.
                // Baked from the level made for views of its cells' size: every level is
                // first drawn at least 8 pixels across, none at a million.
                expect(lods.ImpostorLevel(8) == lods.Count - 1 && lods.ImpostorLevel(1u << 20) == 0, "the impostor's level");
                using (var imp = lods.Impostor(lods.ImpostorLevel(32), 8, 32, true, null, 0, 0))
                {
                    var withImpostor = new UnityEngine.GameObject("tree");
                    var material = new UnityEngine.Material();
                    int before = UnityEngine.Mesh.made.Count;
                    var g5 = UnityLods.Build(withImpostor, lods, "tree", imp, material, 0f);
                    expect(g5.lods.Length == 5 && g5.boundsRecalculated, "five levels with the impostor");
                    var last = g5.lods[4];
                    expect(last.screenRelativeTransitionHeight > 0f && last.screenRelativeTransitionHeight < g5.lods[3].screenRelativeTransitionHeight, "the impostor drawn farthest");
                    expect(last.renderers[0].sharedMaterial == material, "the impostor's material");
                    float[] c = new float[3], u = new float[3]; float r;
                    uint side = imp.Frame(c, out r, u);
                    expect(side == 256 && r > 0f, "8 x 8 views of 32 pixels: " + side);
                    expect(Math.Abs(u[1] - 1f) < 1e-6f && u[0] == 0f && u[2] == 0f, "Unity's up is Y");
                    var tex = (UnityEngine.Texture2D)material.mainTexture;
                    expect(tex != null && tex.width == 256 && tex.height == 256 && tex.data.Length == 256 * 256 * 4 && tex.applied, "the impostor's albedo");
                    int drawn = 0;
                    for (int p = 3; p < tex.data.Length; p += 4) if (tex.data[p] > 0) drawn++;
                    expect(drawn > 0 && drawn < 256 * 256, "the albedo's coverage: " + drawn);
                    expect(material.floats["_Frames"] == 8f && material.floats["_Cell"] == 32f && material.floats["_Hemi"] == 1f && material.floats["_Radius"] == r, "the frame's numbers");
                    var depth = (UnityEngine.Texture2D)material.textures["_DepthTex"];
                    expect(depth.linear && depth.width == 256 && depth.data.Length == 256 * 256 * 4 && depth.applied, "the normal and depth atlas, linear");
                    bool depths = true;
                    for (int p = 3; p < tex.data.Length; p += 4) if (tex.data[p] > 0 && depth.data[p] == 255 && depth.data[p - 1] == 128) depths = false;
                    expect(depths, "a covered texel has a depth and a normal");
                    var centre = material.vectors["_Centre"];
                    var up = material.vectors["_Up"];
                    expect(centre.x == c[0] && centre.y == c[1] && centre.z == c[2] && up.y == u[1], "the frame's vectors");
                    var quad = UnityEngine.Mesh.made[UnityEngine.Mesh.made.Count - 1];
                    expect(UnityEngine.Mesh.made.Count == before + 5, "four mesh levels and the quad");
                    expect(quad.vertexCount == 4 && quad.indexCount == 6 && ((UnityEngine.Vector3[])quad.vertices)[2].x == 1f, "one quad, corners +-1");
                    expect(quad.bounds.center.y == c[1] && quad.bounds.size.x == 2f * r, "bounded by the sphere");
                }
                Vertex[] v0, v1; uint[] i0, i1;
                lods.Mesh(0, 0, out v0, out i0);
                lods.Mesh(1, 0, out v1, out i1);
                expect(i1.Length < i0.Length && i0.Length % 3 == 0, "level 1 lighter");
            }
        }
        Console.WriteLine("unity helpers: " + failed + " failed");
        return failed == 0 ? 0 : 1;
    }
}
