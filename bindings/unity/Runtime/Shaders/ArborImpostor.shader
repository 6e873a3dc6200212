// arbor's octahedral impostor (Lods.Impostor, UnityLods.Build): one quad a tree, turned
// to the camera, blending the three baked views around the direction it is seen from.
// Unlit, alpha-tested; the built-in render pipeline (the programs are plain HLSL in
// ArborImpostor.hlsl, for a pipeline's own pass). Batching is off: the quad is turned in
// the tree's own space.
Shader "Arbor/Impostor"
{
    Properties
    {
        _MainTex ("Impostor albedo (sRGB, alpha coverage)", 2D) = "white" {}
        _DepthTex ("Impostor normal (linear, alpha depth)", 2D) = "white" {}
        _Frames ("Views a side", Float) = 12
        _Cell ("Texels a side of a view", Float) = 128
        _Hemi ("Hemi-octahedral (1) or whole sphere (0)", Float) = 1
        _Centre ("Bounding sphere centre (tree space)", Vector) = (0, 0, 0, 0)
        _Radius ("Bounding sphere radius", Float) = 1
        _Up ("Up axis (tree space)", Vector) = (0, 1, 0, 0)
        _Cutoff ("Alpha cutoff", Range(0, 1)) = 0.5
    }
    SubShader
    {
        Tags { "Queue" = "AlphaTest" "RenderType" = "TransparentCutout" "DisableBatching" = "True" }
        Cull Off
        Pass
        {
            CGPROGRAM
            #pragma target 3.5
            #pragma vertex ArborImpostorVertex
            #pragma fragment ArborImpostorFragment
            #include "UnityCG.cginc"
            #include "ArborImpostor.hlsl"
            ENDCG
        }
    }
}
