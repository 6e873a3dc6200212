// Prints every field offset and the size of every blittable struct of the binding, for
// tests/unity.rs to compare with the C compiler's offsets of the same structs.
using System;
using System.Linq;
using System.Reflection;
using System.Runtime.InteropServices;

public static class ArborOffsets
{
    public static int Main()
    {
        var types = typeof(Arbor.Tree).Assembly.GetTypes()
            .Where(t => t.IsValueType && !t.IsEnum && t.Namespace == "Arbor" && t.IsLayoutSequential)
            .OrderBy(t => t.Name);
        foreach (var t in types)
        {
            Console.WriteLine(t.Name + " SIZE " + Marshal.SizeOf(t));
            foreach (var f in t.GetFields(BindingFlags.Public | BindingFlags.NonPublic | BindingFlags.Instance))
                Console.WriteLine(t.Name + " " + f.Name + " " + Marshal.OffsetOf(t, f.Name));
        }
        return 0;
    }
}
