// Runs the Unity binding under Mono against the built library: layouts, trees a-i, the
// Unity mesh arrays, leaves and an error message.
using System;
using System.Text;
using System.Runtime.InteropServices;
using Arbor;

static class ArborTest
{
    static int passed, failed;

    static void Expect(bool ok, string what)
    {
        if (ok) passed++;
        else { failed++; Console.Error.WriteLine("FAILED: " + what); }
    }

    static int Main()
    {
        Expect(Marshal.SizeOf(typeof(HondaParams)) == (int)Native.arbor_struct_size((uint)StructId.HondaParams), "HondaParams size");
        Expect(Marshal.SizeOf(typeof(Branch)) == (int)Native.arbor_struct_size((uint)StructId.Branch), "Branch size");
        Expect(Marshal.SizeOf(typeof(Vertex)) == (int)Native.arbor_struct_size((uint)StructId.Vertex), "Vertex size");
        Expect(Marshal.SizeOf(typeof(MeshOptions)) == (int)Native.arbor_struct_size((uint)StructId.MeshOptions), "MeshOptions size");
        Expect(Marshal.SizeOf(typeof(LsystemOptions)) == (int)Native.arbor_struct_size((uint)StructId.LsystemOptions), "LsystemOptions size");
        Expect(Marshal.SizeOf(typeof(LeafOptions)) == (int)Native.arbor_struct_size((uint)StructId.LeafOptions), "LeafOptions size");
        Expect(Marshal.SizeOf(typeof(LeafInstance)) == (int)Native.arbor_struct_size((uint)StructId.LeafInstance), "LeafInstance size");
        Expect(Marshal.SizeOf(typeof(BranchRange)) == (int)Native.arbor_struct_size((uint)StructId.BranchRange), "BranchRange size");
        Expect(Marshal.SizeOf(typeof(LeafSite)) == (int)Native.arbor_struct_size((uint)StructId.LeafSite), "LeafSite size");
        Expect(Marshal.SizeOf(typeof(WorldOptions)) == (int)Native.arbor_struct_size((uint)StructId.WorldOptions), "WorldOptions size");
        Expect(Marshal.SizeOf(typeof(GrowthParams)) == (int)Native.arbor_struct_size((uint)StructId.GrowthParams), "GrowthParams size");
        Expect(Marshal.SizeOf(typeof(Curve)) == (int)Native.arbor_struct_size((uint)StructId.Curve), "Curve size");
        using (var bent = Tree.FromPreset('c'))
        {
            bent.Smooth(1.0f);
            var opts = MeshOptions.Default();
            Vertex[] bv, fv;
            int[] bi, fi;
            bent.Mesh(opts, out bv, out bi);
            var curves = bent.Curves();
            var last = curves[curves.Length - 1];
            last.P3Y += 0.5f;
            bent.SetCurve(curves.Length - 1, last);
            bent.RewriteBranch(opts, curves.Length - 1, bv, bi);
            bent.Mesh(opts, out fv, out fi);
            bool same = bv.Length == fv.Length;
            for (int k = 0; same && k < bv.Length; k++) same = bv[k].PX == fv[k].PX && bv[k].PY == fv[k].PY && bv[k].NZ == fv[k].NZ;
            Expect(same, "rewrite after an edit equals a full write");
        }
        {
            // A model served by the host's asset system: arbor opens no file.
            var assets = new System.Collections.Generic.Dictionary<string, string>
            {
                { "m/tree.l", "#include \"defs.h\"\nderivation length: N\nAxiom: A\nA --> F[+A][-A]\n" },
                { "m/defs.h", "#define N 3\n" },
                { "m/esc.l", "#include \"../secret.h\"\nAxiom: F\n" },
                { "secret.h", "#define S hunter2\n" },
            };
            var asked = new System.Collections.Generic.List<string>();
            Func<string, byte[]> read = p =>
            {
                asked.Add(p);
                string text;
                return assets.TryGetValue(p, out text) ? Encoding.UTF8.GetBytes(text) : null;
            };
            using (var t = Tree.FromLsystemFile("m/tree.l", read))
                Expect(t.BranchCount == 7, "a host-read model: " + t.BranchCount);
            Expect(asked.Contains("m/defs.h"), "the include came from the host");
            try
            {
                Tree.FromLsystemFile("m/esc.l", read).Dispose();
                Expect(false, "an include leaving the model's folder is refused");
            }
            catch (ArborException e)
            {
                Expect(e.Status == Status.IoError && !e.Message.Contains("hunter2"), "refused by name: " + e.Message);
            }
            Expect(!asked.Contains("secret.h"), "the host was never asked for the secret");
        }
        using (var world = new World(WorldOptions.Default()))
        {
            world.Plant(GrowthParams.Preset(Species.Excurrent), 0, 0, 0, 1);
            world.Plant(GrowthParams.Default(), 3, 0, 0, 2);
            world.Step(6);
            Expect(world.TreeCount == 2, "two trees in the world");
            using (var t = world.Tree(0))
            {
                Expect(t.BranchCount > 30, "a grown tree: " + t.BranchCount);
                Vertex[] gv;
                int[] gi;
                t.UnityMeshArrays(MeshOptions.Default(), out gv, out gi);
                Expect(gi.Length > 0, "the snapshot meshes");
            }
        }
        /* A world on a slope: trees stand on it, slots are kept, a preview copy changes
           one slot and leaves the original alone; bad ground is refused by name. */
        using (var world = new World(WorldOptions.Default()))
        {
            var heights = new float[9 * 9];
            for (int k = 0; k < heights.Length; k++) heights[k] = 1.0f + 0.1f * (k % 9);
            try
            {
                world.SetGround(new[] { 0.0f, 0.0f, float.NaN, 0.0f }, 2, 2, 1.0f, 0, 0);
                Expect(false, "a NaN height is refused");
            }
            catch (ArborException e)
            {
                Expect(e.Status == Status.InvalidArgument && e.Message.Contains("sample (0, 1)"), "NaN named: " + e.Message);
            }
            world.SetGround(heights, 9, 9, 2.5f, -10, -10);
            Expect(Math.Abs(world.GroundHeight(0, 0) - 1.4f) < 1e-4f, "ground at the centre: " + world.GroundHeight(0, 0));
            world.PlantOnGround(GrowthParams.Preset(Species.Decurrent), -8, 0, 0, 1);
            world.PlantOnGround(GrowthParams.Preset(Species.Decurrent), 8, 0, 1, 2);
            world.Step(4);
            Expect(world.TreeSlot(1) == 1, "slot kept");
            using (var preview = world.Clone())
            {
                var p = GrowthParams.Preset(Species.Decurrent);
                p.ApicalControl = 0.8f;
                Expect(preview.SetSpecies(1, p) == 1, "one tree changed");
                preview.Step(8);
                world.Step(8);
                using (var a = world.Tree(0))
                using (var b = preview.Tree(0))
                using (var c = world.Tree(1))
                using (var d = preview.Tree(1))
                {
                    Expect(a.BranchCount == b.BranchCount, "slot 0 grows alike");
                    Expect(c.BranchCount != d.BranchCount, "slot 1 changed: " + c.BranchCount + " and " + d.BranchCount);
                }
            }
        }
        Expect((int)Marshal.OffsetOf(typeof(Vertex), "NX") == 12 && (int)Marshal.OffsetOf(typeof(Vertex), "U") == 24, "Vertex offsets");
        Expect((int)Marshal.OffsetOf(typeof(LsystemOptions), "Seed") == 8, "LsystemOptions.Seed offset");
        Expect((int)Marshal.OffsetOf(typeof(MeshOptions), "StructSize") == 0 && (int)Marshal.OffsetOf(typeof(MeshOptions), "Threads") == 52, "MeshOptions offsets");
        Expect((int)Marshal.OffsetOf(typeof(LeafOptions), "MaxLeaves") == 56, "LeafOptions.MaxLeaves offset");
        Expect(Marshal.PtrToStringAnsi(Native.arbor_version()).Length >= 5, "version string");

        var defaults = MeshOptions.Default();
        Expect(defaults.StructSize == Marshal.SizeOf(typeof(MeshOptions)) && defaults.RadialSegments == 8 && defaults.Scale == 1.0f && defaults.Joints == (uint)Joints.Mitred, "mesh defaults");
        Expect(LeafOptions.Default().StructSize == Marshal.SizeOf(typeof(LeafOptions)) && LsystemOptions.Default().Steps == -1, "leaf and lsystem defaults");

        int[] counts = { 1023, 2223, 510, 1023, 1990, 5027, 1023, 919, 1586 };
        for (int k = 0; k < 9; k++)
        {
            char name = (char)('a' + k);
            using (var tree = Tree.FromPreset(name))
            {
                Expect(tree.BranchCount == counts[k], "tree " + name + " count " + tree.BranchCount);
                var b = tree.Branches();
                Expect(b[0].EndY == 100.0f && b[0].Parent == uint.MaxValue, "tree " + name + " trunk");
                Vertex[] v;
                int[] i;
                tree.UnityMeshArrays(defaults, out v, out i);
                Expect(i.Length == counts[k] * 6 * 8, "tree " + name + " triangle list");
                bool inRange = true;
                foreach (int x in i) inRange &= x >= 0 && x < v.Length;
                Expect(inRange, "tree " + name + " indices in range");
                // Unity: a triangle is front-facing when it winds clockwise seen from the
                // front, which makes Vector3.Cross(b - a, c - a) point out of that front
                // (Unity's own face-normal formula). It must agree with the vertex normal.
                int agree = 0;
                for (int t = 0; t < i.Length; t += 3)
                {
                    Vertex a = v[i[t]], c1 = v[i[t + 1]], c2 = v[i[t + 2]];
                    float e1x = c1.PX - a.PX, e1y = c1.PY - a.PY, e1z = c1.PZ - a.PZ;
                    float e2x = c2.PX - a.PX, e2y = c2.PY - a.PY, e2z = c2.PZ - a.PZ;
                    float nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
                    if (nx * a.NX + ny * a.NY + nz * a.NZ > 0) agree++;
                }
                Expect(agree == i.Length / 3, "tree " + name + " winding: " + agree + " of " + i.Length / 3);
                // The Unity preset is arbor's mesh with x mirrored, never rotated.
                Vertex[] own;
                int[] ownIdx;
                tree.Mesh(defaults, out own, out ownIdx);
                bool mirrored = own.Length == v.Length;
                for (int q = 0; mirrored && q < v.Length; q += 7)
                    mirrored = v[q].PX == -own[q].PX && v[q].PY == own[q].PY && v[q].PZ == own[q].PZ && v[q].NX == -own[q].NX;
                Expect(mirrored, "tree " + name + " mirrored by x");
                // Compact vertices: the same positions and indices, v within its scale.
                VertexCompact[] cv;
                int[] ci;
                float vScale = tree.MeshCompact(defaults, out cv, out ci);
                bool same = cv.Length == own.Length && ci.Length == ownIdx.Length;
                for (int q = 0; same && q < cv.Length; q += 5)
                    same = cv[q].PX == own[q].PX && cv[q].PY == own[q].PY && cv[q].PZ == own[q].PZ
                        && System.Math.Abs(cv[q].V / 65535.0 * vScale - own[q].V) <= vScale / 65535.0;
                Expect(same && vScale >= 1, "tree " + name + " compact vertices (v_scale " + vScale + ")");
            }
        }

        using (var tree = Tree.FromLsystem("angle increment: 45\nAxiom: F[+F~][-F~]F~\n"))
        {
            var leaves = LeafOptions.Default();
            Expect(tree.Leaves(leaves, defaults).Length == 3, "three leaf sites");
        }

        try
        {
            Tree.FromLsystem("Axiom: F\nF --> F(+)\n");
            Expect(false, "no exception for a parse error");
        }
        catch (ArborException e)
        {
            Expect(e.Status == Status.ParseError, "parse error status " + e.Status);
            Expect(e.Message.Contains("line 2, column 10"), "message: " + e.Message);
        }
        // A grammar with the text of its view file: angle factor 4 is 90 degrees.
        using (var tree = Tree.FromLsystem("derivation length: 1\nAxiom: A\nA --> F+F\n", "angle factor: 4\n"))
        {
            var b = tree.Branches();
            Expect(b.Length == 2 && b[1].EndX - b[1].StartX < -0.99f, "view text turns 90 degrees");
        }
        // Progress from a managed lambda through the static trampoline; false cancels.
        int calls = 0;
        try
        {
            Tree.FromLsystem("derivation length: 8\nAxiom: F\nF --> F[+F]F\n", (stage, f) => ++calls < 3);
            Expect(false, "no exception for a cancelled derivation");
        }
        catch (ArborException e)
        {
            Expect(e.Status == Status.Cancelled && calls == 3, "cancelled after " + calls + " calls: " + e.Status);
        }
        using (var tree = Tree.FromLsystem("derivation length: 3\nAxiom: F\nF --> FF\n", (stage, f) => true))
        {
            Expect(tree.BranchCount == 8, "progress that never cancels");
            // Mesh writes report stage 3 and stop when asked.
            int meshCalls = 0;
            Vertex[] mv;
            int[] mi;
            tree.Mesh(MeshOptions.Default(), (stage, f) => { meshCalls += stage == 3 ? 1 : 0; return true; }, out mv, out mi);
            Expect(meshCalls == 1 && mi.Length > 0, "mesh progress: " + meshCalls + " reports");
            try
            {
                tree.Mesh(MeshOptions.Default(), (stage, f) => false, out mv, out mi);
                Expect(false, "no exception for a cancelled mesh");
            }
            catch (ArborException e)
            {
                Expect(e.Status == Status.Cancelled, "cancelled mesh: " + e.Status);
            }
        }
        Expect(Marshal.SizeOf(typeof(Bone)) == (int)Native.arbor_struct_size((uint)StructId.Bone), "Bone size");
        using (var windy = Tree.FromPreset('b'))
        {
            var opts = MeshOptions.Default();
            float[] ibm;
            var bones = windy.Bones(opts, 16, out ibm);
            Expect(bones.Length > 1 && bones.Length <= 16 && ibm.Length == 16 * bones.Length, "bones: " + bones.Length);
            Expect(bones[0].Parent == 0xFFFFFFFFu && ibm[12] == -bones[0].HeadX, "root bone and its inverse bind");
            ushort[] joints;
            float[] weights;
            windy.Skin(opts, 16, out joints, out weights);
            Vertex[] wv;
            int[] wi;
            windy.Mesh(opts, out wv, out wi);
            bool sums = joints.Length == 4 * wv.Length;
            for (int v = 0; sums && v < wv.Length; v++)
            {
                float sum = weights[4 * v] + weights[4 * v + 1] + weights[4 * v + 2] + weights[4 * v + 3];
                sums = Math.Abs(sum - 1f) < 1e-4f && joints[4 * v] < bones.Length;
            }
            Expect(sums, "skin: four weights summing to one a vertex");
            float[] times;
            var rot = windy.WindClip(opts, 16, null, 1f, 2f, 10, 3, out times);
            Expect(times.Length == 21 && rot.Length == 4 * 21 * bones.Length && times[20] == 2f, "clip: " + times.Length + " keys");
        }
        try
        {
            Tree.FromLsystemFile("no/such/grammar.l");
            Expect(false, "no exception for a missing file");
        }
        catch (ArborException e)
        {
            Expect(e.Status == Status.InvalidArgument && e.Message.Contains("grammar.l"), "missing file: " + e.Message);
        }
        try
        {
            Tree.FromPreset('z');
            Expect(false, "no exception for a bad preset");
        }
        catch (ArborException e)
        {
            Expect(e.Status == Status.InvalidArgument && e.Message.Contains("preset"), "bad preset: " + e.Message);
        }

        Console.WriteLine("unity binding: " + passed + " passed, " + failed + " failed");
        return failed == 0 ? 0 : 1;
    }
}
