// Sample: grows the 1996 tree g (or the cpfg file at `lsystemPath`) into this object's
// MeshFilter in one upload, left-handed and clockwise as Unity wants.
using UnityEngine;

namespace Arbor.Samples
{
    [RequireComponent(typeof(MeshFilter))]
    public class GrowATree : MonoBehaviour
    {
        public string lsystemPath = "";
        public char preset = 'g';

        void Start()
        {
            var options = MeshOptions.Default();
            using (var tree = string.IsNullOrEmpty(lsystemPath) ? Tree.FromPreset(preset) : Tree.FromLsystemFile(lsystemPath))
            {
                var mesh = new Mesh();
                UnityMeshes.Fill(mesh, tree, options);
                GetComponent<MeshFilter>().mesh = mesh;
            }
        }
    }
}
