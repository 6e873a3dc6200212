// arbor's octahedral impostor for Unity (built-in pipeline): the vertex and fragment
// programs of Arbor/Impostor (ArborImpostor.shader), the HLSL of the reference GLSL shader
// examples/common/impostor.glsl. One quad a tree, turned in the tree's own space to face
// the camera; the fragment blends the three views of the atlas around the direction the
// camera sees the tree from, following the ray through the fragment in each view to the
// surface that view saw (its depth), so the views line up (docs/meshes.md, "Impostors").
//
// Needs UnityCG.cginc (unity_WorldToObject, _WorldSpaceCameraPos, UnityObjectToClipPos).

Texture2D _MainTex;        // "impostor albedo": sRGB colour, alpha the coverage
SamplerState sampler_MainTex;   // bilinear (Unity's default for a Texture2D)
Texture2D _DepthTex;       // "impostor normal": normal in RGB, depth in alpha (linear)
float _Frames;             // views a side of the grid
float _Cell;               // texels a side of a view
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
    float3 at : TEXCOORD0;      // the fragment's point on the quad, radii from the centre
    float3 from : TEXCOORD1;    // where the camera sees the tree from (tree space)
};

// The view's frame as arbor drew it: right = cross(-d, up), top = cross(right, -d).
void ArborImpostorBasis(float3 d, float3 up, out float3 right, out float3 top)
{
    right = cross(-d, up);
    right = dot(right, right) < 1e-10 ? float3(1.0, 0.0, 0.0) : normalize(right);
    top = cross(right, -d);
}

ArborImpostorOut ArborImpostorVertex(ArborImpostorIn v)
{
    ArborImpostorOut o;
    float3 camera = mul(unity_WorldToObject, float4(_WorldSpaceCameraPos, 1.0)).xyz;
    float3 up = normalize(_Up.xyz);
    float3 d = normalize(camera - _Centre.xyz);
    float3 right, top;
    ArborImpostorBasis(d, up, right, top);
    o.at = right * v.vertex.x + top * v.vertex.y;
    o.pos = UnityObjectToClipPos(float4(_Centre.xyz + o.at * _Radius, 1.0));
    o.from = d;
    return o;
}

float ArborImpostorSign(float x) { return x < 0.0 ? -1.0 : 1.0; }

// The axis besides X and up: Z for a Y-up tree, Y for a Z-up one.
float3 ArborImpostorAxisB(float3 up)
{
    return abs(up.z) > abs(up.y) ? float3(0.0, 1.0, 0.0) : float3(0.0, 0.0, 1.0);
}

// The grid coordinates in [-1, 1]^2 of a direction (arbor::impostor::grid_coordinates).
float2 ArborImpostorGrid(float3 d)
{
    float3 up = normalize(_Up.xyz);
    float x = d.x;
    float y = dot(d, ArborImpostorAxisB(up));
    float h = dot(d, up);
    if (_Hemi > 0.5) h = max(h, 0.0);
    float s = max(abs(x) + abs(y) + abs(h), 1e-20);
    x /= s;
    y /= s;
    if (h < 0.0)
    {
        float fx = (1.0 - abs(y)) * ArborImpostorSign(x);
        float fy = (1.0 - abs(x)) * ArborImpostorSign(y);
        x = fx;
        y = fy;
    }
    return _Hemi > 0.5 ? float2(x + y, x - y) : float2(x, y);
}

// The direction view (i, j) was drawn from (arbor::impostor::grid_direction).
float3 ArborImpostorViewDirection(float2 ij)
{
    float3 up = normalize(_Up.xyz);
    float2 q = 2.0 * (ij + 0.5) / _Frames - 1.0;
    float2 t = _Hemi > 0.5 ? float2(0.5 * (q.x + q.y), 0.5 * (q.x - q.y)) : q;
    float h = 1.0 - abs(t.x) - abs(t.y);
    if (h < 0.0) t = float2((1.0 - abs(t.y)) * ArborImpostorSign(t.x), (1.0 - abs(t.x)) * ArborImpostorSign(t.y));
    float3 d = float3(1.0, 0.0, 0.0) * t.x + ArborImpostorAxisB(up) * t.y + up * h;
    return dot(d, d) > 0.0 ? normalize(d) : up;
}

// View (i, j)'s texel where the ray through `at` along -d first meets the surface it saw
// (the first of `steps` points across the sphere over a covered texel whose depth is at
// most three steps nearer and a hundredth of the radius farther), as the GLSL's march().
float4 ArborImpostorMarch(float2 ij, float3 at, float3 d)
{
    float3 up = normalize(_Up.xyz);
    float3 dk = ArborImpostorViewDirection(ij);
    float3 right, top;
    ArborImpostorBasis(dk, up, right, top);
    float s = length(d - dk * dot(d, dk));
    int steps = (int)clamp(ceil(1.5 * _Cell * s), 4.0, 4.0 * _Cell);
    float stepLength = 2.0 / (float)steps;
    int cell = (int)_Cell;
    int2 origin = (int2)ij * cell;
    [loop]
    for (int k = 0; k <= steps; k++)
    {
        float3 p = at + d * (1.0 - (float)k * stepLength);
        float2 uv = float2(0.5 + dot(p, right) * 0.5, 0.5 - dot(p, top) * 0.5);
        if (any(uv < 0.0) || any(uv >= 1.0)) continue;
        int2 texel = origin + min((int2)(uv * _Cell), int2(cell - 1, cell - 1));
        float4 c = _MainTex.Load(int3(texel, 0));
        if (c.a == 0.0) continue;
        float surface = _DepthTex.Load(int3(texel, 0)).a * 2.0 - 1.0;
        float depth = dot(p, -dk);
        if (depth >= surface - 0.01 && depth <= surface + 3.0 * stepLength)
        {
            // The albedo there filtered (bilinear, level 0), kept within the view's cell.
            float2 t = ((float2)origin + clamp(uv * _Cell, 0.5, _Cell - 0.5)) / (_Frames * _Cell);
            return _MainTex.SampleLevel(sampler_MainTex, t, 0.0);
        }
    }
    return float4(0.0, 0.0, 0.0, 0.0);
}

float4 ArborImpostorFragment(ArborImpostorOut i) : SV_Target
{
    float3 d = normalize(i.from);
    float2 p = clamp((ArborImpostorGrid(d) * 0.5 + 0.5) * _Frames - 0.5, float2(0.0, 0.0), float2(_Frames - 1.0, _Frames - 1.0));
    float2 ij = floor(p);
    float2 f = p - ij;
    float2 last = float2(_Frames - 1.0, _Frames - 1.0);
    float2 cells[3];
    float3 w;
    if (f.x + f.y < 1.0)
    {
        cells[0] = ij; cells[1] = ij + float2(1.0, 0.0); cells[2] = ij + float2(0.0, 1.0);
        w = float3(1.0 - f.x - f.y, f.x, f.y);
    }
    else
    {
        cells[0] = ij + float2(1.0, 1.0); cells[1] = ij + float2(1.0, 0.0); cells[2] = ij + float2(0.0, 1.0);
        w = float3(f.x + f.y - 1.0, 1.0 - f.y, 1.0 - f.x);
    }
    // Colour weighted by coverage (an empty texel has no colour), as on the CPU.
    float4 sum = float4(0.0, 0.0, 0.0, 0.0);
    [unroll]
    for (int k = 0; k < 3; k++)
    {
        if (w[k] > 0.0)
        {
            float4 t = ArborImpostorMarch(min(cells[k], last), i.at, d);
            sum += float4(t.rgb * t.a, t.a) * w[k];
        }
    }
    clip(sum.a - _Cutoff);
    return float4(sum.rgb / max(sum.a, 1e-6), 1.0);
}
