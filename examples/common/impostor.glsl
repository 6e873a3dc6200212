// arbor's octahedral impostor: the reference shader (GLSL 3.30 core).
//
// One quad per tree, turned to face the camera. The fragment stage finds the three views
// of the atlas around the direction the camera sees the tree from and blends them by their
// weights on the grid; in each view it follows the ray through the fragment across the
// tree's bounding sphere until it meets the surface that view saw (the depth in the normal
// atlas's alpha), so the three views line up between the baked directions (docs/meshes.md,
// "Impostors"; arbor::impostor::Impostor::picture is the same on the CPU).
// Compile the vertex stage with `#define VERTEX` and the fragment stage with
// `#define FRAGMENT` after the #version line.
//
// Per tree (instance): its place and scale. Uniforms: the impostor's extras
// (arbor_impostor in the glTF node: frames, cell, hemi, centre, radius, up) and its two
// atlases: the march reads both texel by texel (texelFetch); the albedo where it ends is
// sampled through the albedo's sampler at level 0 (set its filter to GL_LINEAR: the
// coverage is then filtered as a pixel's footprint covers it). With `light` set, the
// colour is lit by the normal atlas (the CPU's picture is the albedo, unlit).

#ifdef VERTEX
layout(location = 0) in vec2 corner;       // the quad: (-1,-1) (1,-1) (1,1) (-1,1)
layout(location = 1) in vec4 placement;    // xyz where the tree stands, w its scale
uniform mat4 view_projection;
uniform vec3 camera;                       // the camera's position
uniform vec3 centre;                       // the bounding sphere's centre (tree space)
uniform float radius;                      // its radius
uniform vec3 up;                           // the tree's up axis
out vec3 at;                               // the fragment's point on the quad, radii from the centre
flat out vec3 from_dir;                    // where the camera sees the tree from
void main() {
    vec3 middle = placement.xyz + centre * placement.w;
    vec3 d = normalize(camera - middle);
    // The view's frame, as arbor drew it: right = cross(-d, up), top = cross(right, -d).
    vec3 right = cross(-d, up);
    right = dot(right, right) < 1e-10 ? vec3(1.0, 0.0, 0.0) : normalize(right);
    vec3 top = cross(right, -d);
    at = right * corner.x + top * corner.y;
    from_dir = d;
    gl_Position = view_projection * vec4(middle + at * radius * placement.w, 1.0);
}
#endif

#ifdef FRAGMENT
in vec3 at;
flat in vec3 from_dir;
uniform sampler2D albedo;                  // "impostor albedo": sRGB colour, alpha coverage
uniform sampler2D normal_depth;            // "impostor normal": normal, alpha the depth
uniform float frames;                      // views a side of the grid
uniform float cell;                        // texels a side of a view
uniform bool hemi;                         // the upper half of the sphere
uniform vec3 up;
uniform vec3 light;                        // toward the sun, tree space; zero: unlit
out vec4 colour;

// The axes besides up: X and Z for a Y-up tree, X and Y for a Z-up one.
vec3 axis_b() { return abs(up.z) > abs(up.y) ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0); }
float sgn(float x) { return x < 0.0 ? -1.0 : 1.0; }

// The grid coordinates in [-1, 1]^2 of a direction (arbor::impostor::grid_coordinates).
vec2 grid(vec3 d) {
    float x = d.x, y = dot(d, axis_b()), h = dot(d, up);
    if (hemi) h = max(h, 0.0);
    float s = max(abs(x) + abs(y) + abs(h), 1e-20);
    x /= s; y /= s;
    if (h < 0.0) {
        vec2 f = vec2((1.0 - abs(y)) * sgn(x), (1.0 - abs(x)) * sgn(y));
        x = f.x; y = f.y;
    }
    return hemi ? vec2(x + y, x - y) : vec2(x, y);
}

// The direction view (i, j) was drawn from (arbor::impostor::grid_direction).
vec3 view_direction(vec2 ij) {
    vec2 q = 2.0 * (ij + 0.5) / frames - 1.0;
    vec2 t = hemi ? vec2(0.5 * (q.x + q.y), 0.5 * (q.x - q.y)) : q;
    float h = 1.0 - abs(t.x) - abs(t.y);
    if (h < 0.0) t = vec2((1.0 - abs(t.y)) * sgn(t.x), (1.0 - abs(t.x)) * sgn(t.y));
    vec3 d = vec3(1.0, 0.0, 0.0) * t.x + axis_b() * t.y + up * h;
    return dot(d, d) > 0.0 ? normalize(d) : up;
}

// View (i, j)'s texel where the ray through `at` along -d first meets the surface it saw:
// the first of `steps` points from the sphere's near side to its far side over a covered
// texel whose depth is at most three steps nearer (arbor::impostor::SHELL_STEPS) and at
// most a hundredth of the radius farther (DEPTH_SLACK).
vec4 march(vec2 ij, vec3 d, out vec3 normal) {
    normal = vec3(0.0);
    vec3 dk = view_direction(ij);
    vec3 right = cross(-dk, up);
    right = dot(right, right) < 1e-10 ? vec3(1.0, 0.0, 0.0) : normalize(right);
    vec3 top = cross(right, -dk);
    float s = length(d - dk * dot(d, dk));
    int steps = int(clamp(ceil(1.5 * cell * s), 4.0, 4.0 * cell));
    float step = 2.0 / float(steps);
    ivec2 origin = ivec2(ij) * int(cell);
    for (int k = 0; k <= steps; k++) {
        vec3 p = at + d * (1.0 - float(k) * step);
        vec2 uv = vec2(0.5 + dot(p, right) * 0.5, 0.5 - dot(p, top) * 0.5);
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThanEqual(uv, vec2(1.0)))) continue;
        ivec2 texel = origin + min(ivec2(uv * cell), ivec2(int(cell) - 1));
        vec4 c = texelFetch(albedo, texel, 0);
        if (c.a == 0.0) continue;
        vec4 nd = texelFetch(normal_depth, texel, 0);
        float surface = nd.a * 2.0 - 1.0;
        float depth = dot(p, -dk);
        if (depth >= surface - 0.01 && depth <= surface + 3.0 * step) {
            // The albedo there filtered (the sampler's bilinear filter, level 0), kept
            // within the view's cell.
            vec2 t = (vec2(origin) + clamp(uv * cell, vec2(0.5), vec2(cell - 0.5))) / (frames * cell);
            normal = nd.rgb * 2.0 - 1.0;
            return textureLod(albedo, t, 0.0);
        }
    }
    return vec4(0.0);
}

void main() {
    vec3 d = normalize(from_dir);
    vec2 p = clamp((grid(d) * 0.5 + 0.5) * frames - 0.5, vec2(0.0), vec2(frames - 1.0));
    vec2 ij = floor(p), f = p - ij;
    vec2 a, b, c;
    vec3 w;
    if (f.x + f.y < 1.0) {
        a = ij; b = ij + vec2(1.0, 0.0); c = ij + vec2(0.0, 1.0);
        w = vec3(1.0 - f.x - f.y, f.x, f.y);
    } else {
        a = ij + vec2(1.0, 1.0); b = ij + vec2(1.0, 0.0); c = ij + vec2(0.0, 1.0);
        w = vec3(f.x + f.y - 1.0, 1.0 - f.y, 1.0 - f.x);
    }
    vec2 last = vec2(frames - 1.0);
    // Colour weighted by coverage (an empty texel has no colour), as on the CPU.
    vec4 sum = vec4(0.0);
    vec3 normal = vec3(0.0);
    vec2 cells[3] = vec2[3](min(a, last), min(b, last), min(c, last));
    for (int k = 0; k < 3; k++) {
        if (w[k] <= 0.0) continue;
        vec3 n;
        vec4 t = march(cells[k], d, n);
        sum += vec4(t.rgb * t.a, t.a) * w[k];
        normal += n * t.a * w[k];
    }
    if (sum.a < 0.5) discard;
    vec3 rgb = sum.rgb / sum.a;
    // Lit by the normal atlas where a light is given (a half-Lambert: leaves pass light).
    if (dot(light, light) > 0.0 && dot(normal, normal) > 0.0)
        rgb *= 0.35 + 0.65 * clamp(0.5 + 0.5 * dot(normalize(normal), normalize(light)), 0.0, 1.0);
    colour = vec4(rgb, 1.0);
}
#endif
