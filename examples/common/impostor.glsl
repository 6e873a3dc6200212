// arbor's octahedral impostor: the reference shader (GLSL 3.30 core).
//
// One quad per tree, turned to face the camera, samples the three views of the atlas
// around the direction the camera sees the tree from and blends them by their weights
// on the grid (docs/meshes.md, "Impostors"; arbor::impostor::Impostor::coverage is the
// same on the CPU). Compile the vertex stage with `#define VERTEX` and the fragment
// stage with `#define FRAGMENT` after the #version line.
//
// Per tree (instance): its place and scale. Uniforms: the impostor's extras
// (arbor_impostor in the glTF node: frames, hemi, centre, radius, up) and its atlases.

#ifdef VERTEX
layout(location = 0) in vec2 corner;       // the quad: (-1,-1) (1,-1) (1,1) (-1,1)
layout(location = 1) in vec4 placement;    // xyz where the tree stands, w its scale
uniform mat4 view_projection;
uniform vec3 camera;                       // the camera's position
uniform vec3 centre;                       // the bounding sphere's centre (tree space)
uniform float radius;                      // its radius
uniform vec3 up;                           // the tree's up axis
out vec2 uv;
out vec3 from_dir;                         // where the camera sees the tree from
void main() {
    vec3 middle = placement.xyz + centre * placement.w;
    vec3 d = normalize(camera - middle);
    // The view's frame, as arbor drew it: right = cross(-d, up), top = cross(right, -d).
    vec3 right = cross(-d, up);
    right = dot(right, right) < 1e-8 ? vec3(1.0, 0.0, 0.0) : normalize(right);
    vec3 top = cross(right, -d);
    vec3 p = middle + (right * corner.x + top * corner.y) * radius * placement.w;
    uv = vec2(corner.x * 0.5 + 0.5, 0.5 - corner.y * 0.5);   // row 0 is the top
    from_dir = d;
    gl_Position = view_projection * vec4(p, 1.0);
}
#endif

#ifdef FRAGMENT
in vec2 uv;
in vec3 from_dir;
uniform sampler2D albedo;                  // "impostor albedo": sRGB colour, alpha coverage
uniform float frames;                      // views a side of the grid
uniform bool hemi;                         // the upper half of the sphere
uniform vec3 up;
out vec4 colour;

// The grid coordinates in [-1, 1]^2 of a direction (arbor::impostor::grid_coordinates).
vec2 grid(vec3 d) {
    // The two other axes: X and Z for a Y-up tree, X and Y for a Z-up one.
    vec3 a = vec3(1.0, 0.0, 0.0);
    vec3 b = abs(up.z) > abs(up.y) ? vec3(0.0, 1.0, 0.0) : vec3(0.0, 0.0, 1.0);
    float x = dot(d, a), y = dot(d, b), h = dot(d, up);
    if (hemi) h = max(h, 0.0);
    float s = max(abs(x) + abs(y) + abs(h), 1e-20);
    x /= s; y /= s;
    if (h < 0.0) {
        vec2 f = vec2((1.0 - abs(y)) * (x < 0.0 ? -1.0 : 1.0),
                      (1.0 - abs(x)) * (y < 0.0 ? -1.0 : 1.0));
        x = f.x; y = f.y;
    }
    return hemi ? vec2(x + y, x - y) : vec2(x, y);
}

vec4 cell(vec2 ij) {
    vec2 c = clamp(ij, vec2(0.0), vec2(frames - 1.0));
    return texture(albedo, (c + uv) / frames);
}

void main() {
    vec2 q = grid(normalize(from_dir));
    vec2 p = clamp((q * 0.5 + 0.5) * frames - 0.5, vec2(0.0), vec2(frames - 1.0));
    vec2 ij = floor(p), f = p - ij;
    vec4 sum;
    if (f.x + f.y < 1.0) {
        sum = cell(ij) * (1.0 - f.x - f.y) + cell(ij + vec2(1.0, 0.0)) * f.x
            + cell(ij + vec2(0.0, 1.0)) * f.y;
    } else {
        sum = cell(ij + vec2(1.0, 1.0)) * (f.x + f.y - 1.0)
            + cell(ij + vec2(1.0, 0.0)) * (1.0 - f.y) + cell(ij + vec2(0.0, 1.0)) * (1.0 - f.x);
    }
    if (sum.a < 0.5) discard;
    colour = vec4(sum.rgb, 1.0);
}
#endif
