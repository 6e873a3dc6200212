// arbor's octahedral impostor for Unity (built-in pipeline): the vertex and fragment
// programs of Arbor/Impostor (ArborImpostor.shader), the HLSL of the reference GLSL shader
// examples/common/impostor.glsl. One quad a tree, turned in the tree's own space to face
// the camera; the fragment blends the three views of the atlas around the direction the
// camera sees the tree from (docs/meshes.md, "Impostors").
//
// Needs UnityCG.cginc (unity_WorldToObject, _WorldSpaceCameraPos, UnityObjectToClipPos).

Texture2D _MainTex;        // "impostor albedo": sRGB colour, alpha the coverage
SamplerState sampler_MainTex;
float _Frames;             // views a side of the grid
float _Hemi;               // 1: the upper half of the sphere (hemi-octahedral)
float4 _Centre;            // the bounding sphere's centre, tree space (xyz)
float _Radius;             // its radius
float4 _Up;                // the tree's up axis, tree space (xyz)
float _Cutoff;             // alpha below this is not drawn

struct ArborImpostorIn
{
    float4 vertex : POSITION;   // the quad's corner in xy: (-1,-1) (1,-1) (1,1) (-1,1)
};

struct ArborImpostorOut
{
    float4 pos : SV_POSITION;
    float2 uv : TEXCOORD0;      // within a view's cell, row 0 the top
    float3 from : TEXCOORD1;    // where the camera sees the tree from (tree space)
};

ArborImpostorOut ArborImpostorVertex(ArborImpostorIn v)
{
    ArborImpostorOut o;
    float3 camera = mul(unity_WorldToObject, float4(_WorldSpaceCameraPos, 1.0)).xyz;
    float3 up = normalize(_Up.xyz);
    float3 d = normalize(camera - _Centre.xyz);
    // The view's frame as arbor drew it: right = cross(-d, up), top = cross(right, -d).
    float3 right = cross(-d, up);
    right = dot(right, right) < 1e-8 ? float3(1.0, 0.0, 0.0) : normalize(right);
    float3 top = cross(right, -d);
    float3 p = _Centre.xyz + (right * v.vertex.x + top * v.vertex.y) * _Radius;
    o.pos = UnityObjectToClipPos(float4(p, 1.0));
    o.uv = float2(v.vertex.x * 0.5 + 0.5, 0.5 - v.vertex.y * 0.5);
    o.from = d;
    return o;
}

// The grid coordinates in [-1, 1]^2 of a direction (arbor::impostor::grid_coordinates).
float2 ArborImpostorGrid(float3 d)
{
    float3 up = normalize(_Up.xyz);
    // The two other axes: X and Z for a Y-up tree, X and Y for a Z-up one.
    float3 a = float3(1.0, 0.0, 0.0);
    float3 b = abs(up.z) > abs(up.y) ? float3(0.0, 1.0, 0.0) : float3(0.0, 0.0, 1.0);
    float x = dot(d, a);
    float y = dot(d, b);
    float h = dot(d, up);
    if (_Hemi > 0.5) h = max(h, 0.0);
    float s = max(abs(x) + abs(y) + abs(h), 1e-20);
    x /= s;
    y /= s;
    if (h < 0.0)
    {
        float fx = (1.0 - abs(y)) * (x < 0.0 ? -1.0 : 1.0);
        float fy = (1.0 - abs(x)) * (y < 0.0 ? -1.0 : 1.0);
        x = fx;
        y = fy;
    }
    return _Hemi > 0.5 ? float2(x + y, x - y) : float2(x, y);
}

// View (i, j) of the atlas at `uv` within its cell (no mipmaps: the cells' borders).
float4 ArborImpostorCell(float2 ij, float2 uv)
{
    float2 c = clamp(ij, float2(0.0, 0.0), float2(_Frames - 1.0, _Frames - 1.0));
    return _MainTex.SampleLevel(sampler_MainTex, (c + uv) / _Frames, 0.0);
}

float4 ArborImpostorFragment(ArborImpostorOut i) : SV_Target
{
    float2 q = ArborImpostorGrid(normalize(i.from));
    float2 p = clamp((q * 0.5 + 0.5) * _Frames - 0.5, float2(0.0, 0.0), float2(_Frames - 1.0, _Frames - 1.0));
    float2 ij = floor(p);
    float2 f = p - ij;
    float4 sum;
    if (f.x + f.y < 1.0)
    {
        sum = ArborImpostorCell(ij, i.uv) * (1.0 - f.x - f.y)
            + ArborImpostorCell(ij + float2(1.0, 0.0), i.uv) * f.x
            + ArborImpostorCell(ij + float2(0.0, 1.0), i.uv) * f.y;
    }
    else
    {
        sum = ArborImpostorCell(ij + float2(1.0, 1.0), i.uv) * (f.x + f.y - 1.0)
            + ArborImpostorCell(ij + float2(1.0, 0.0), i.uv) * (1.0 - f.y)
            + ArborImpostorCell(ij + float2(0.0, 1.0), i.uv) * (1.0 - f.x);
    }
    clip(sum.a - _Cutoff);
    return float4(sum.rgb, 1.0);
}
