/*
 * arbor ray marcher: tree bodies drawn without triangles, from arbor's curve records.
 *
 * Each branch is a cubic Bezier curve with a radius at each end, one 80-byte std430 record
 * (arbor_tree_curve_records_write) in a shader storage buffer. The program draws one
 * instanced box per record (the box around the four control points, widened by the
 * radius); the fragment shader marches the view ray from the box's face by the distance
 * to the curve's tube (sphere tracing: the closest curve parameter by sampling and Newton
 * steps, the tube's radius interpolated along it) and writes the hit's depth, so boxes and
 * other geometry meet correctly. The texture's u and v come from the curve parameter and
 * the branch's arc-length offset. A shadow map is made by the same march from the light
 * (parallel rays), and the march's tolerance grows with distance: a per-pixel level of
 * detail. Leaves are instanced quads (arbor_leaf_instances_write) textured from the oak's
 * leaf atlas (arbor_species_texture_write), each on its arbor_leaf_cell(). M switches to arbor's
 * triangle mesh of the same trees, shaded the same way, for comparison.
 *
 *   raymarch [--tree a..i] [--steps N] [--world CYCLES [--world-trees K]] [--mesh]
 *            [--segments K] [--no-shadow] [--no-ground] [--no-leaves] [--compare]
 *            [--pitch RADIANS] [--yaw RADIANS] [--zoom Z]
 *            [--size WxH] [--screenshot FILE.png|FILE.ppm --frames N]
 *
 * Keys: M mesh / ray march; H shadows; L leaves; mouse drag orbits, wheel zooms; Esc.
 * It prints the bytes each renderer keeps on the GPU, and (--compare) the frame time of
 * both, measured alternately in one run.
 */
#define GLFW_INCLUDE_NONE
/* clock_gettime (POSIX) under -std=c11. */
#define _POSIX_C_SOURCE 199309L
#include <GLFW/glfw3.h>
#include <GL/glcorearb.h>

#include "arbor.h"
#include "../common/glapp.h"

#include <float.h>

static struct {
  int width, height, mesh, shadow, ground, leaves, segments;
  float yaw, pitch, zoom;
  double drag_x, drag_y;
  int dragging;
} st = {900, 700, 0, 1, 1, 1, 16, 0.6f, 0.25f, 1.0f, 0, 0, 0};

/* ---- shaders ---- */
/* Shading shared by both renderers: bark grain from uv, a lambert term, the shadow map. */
#define SHADE_GLSL                                                                        \
  "uniform vec3 u_light;\n"                                                               \
  "uniform mat4 u_light_vp;\n"                                                            \
  "uniform sampler2D u_shadow_map;\n"                                                     \
  "uniform int u_shadows;\n"                                                              \
  "float lit(vec3 p, vec3 n) {\n"                                                         \
  "  if (u_shadows == 0) return 1.0;\n"                                                   \
  "  vec4 s = u_light_vp * vec4(p, 1.0);\n"                                               \
  "  vec3 c = s.xyz / s.w * 0.5 + 0.5;\n"                                                 \
  "  if (any(lessThan(c, vec3(0.0))) || any(greaterThan(c, vec3(1.0)))) return 1.0;\n"    \
  "  float bias = 0.002 + 0.004 * (1.0 - abs(dot(n, u_light)));\n"                        \
  "  return c.z - bias > texture(u_shadow_map, c.xy).r ? 0.0 : 1.0;\n"                    \
  "}\n"                                                                                   \
  "vec3 shade(vec3 base, vec3 p, vec3 n) {\n"                                             \
  "  float d = max(dot(n, u_light), 0.0) * lit(p, n);\n"                                  \
  "  return base * (0.35 + 0.65 * d);\n"                                                  \
  "}\n"                                                                                   \
  "vec3 bark(vec2 uv) {\n"                                                                \
  "  float grain = 0.5 + 0.5 * sin(uv.x * 37.7 + sin(uv.y * 3.1) * 2.0);\n"               \
  "  float rings = 0.5 + 0.5 * sin(uv.y * 1.7);\n"                                        \
  "  return mix(vec3(0.30, 0.20, 0.12), vec3(0.45, 0.32, 0.20), 0.6 * grain + 0.4 * rings);\n" \
  "}\n"

/* The curve records, as arbor writes them (std430, 80 bytes). */
#define CURVES_GLSL                                                                       \
  "struct Curve { vec4 p0_r0; vec4 p1_r1; vec4 p2_v0; vec4 p3_length;\n"                  \
  "               float u_offset; uint order; uint parent; uint birth; };\n"              \
  "layout(std430, binding = 0) readonly buffer Curves { Curve curves[]; };\n"             \
  "void bounds(Curve c, out vec3 lo, out vec3 hi) {\n"                                    \
  "  float r = max(c.p0_r0.w, c.p1_r1.w);\n"                                              \
  "  lo = min(min(c.p0_r0.xyz, c.p1_r1.xyz), min(c.p2_v0.xyz, c.p3_length.xyz)) - vec3(r);\n" \
  "  hi = max(max(c.p0_r0.xyz, c.p1_r1.xyz), max(c.p2_v0.xyz, c.p3_length.xyz)) + vec3(r);\n" \
  "}\n"

static const char *march_vs =
    "#version 430 core\n" CURVES_GLSL
    "uniform mat4 u_view_proj;\n"
    "flat out int v_id;\n"
    "out vec3 v_world;\n"
    "void main() {\n"
    "  /* A unit cube from the vertex index: 12 triangles, outward, counter-clockwise. */\n"
    "  const int faces[36] = int[36](0,2,1, 1,2,3, 4,5,6, 5,7,6, 0,1,4, 1,5,4,\n"
    "                                2,6,3, 3,6,7, 0,4,2, 2,4,6, 1,3,5, 3,7,5);\n"
    "  int k = faces[gl_VertexID];\n"
    "  vec3 corner = vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);\n"
    "  vec3 lo, hi;\n"
    "  bounds(curves[gl_InstanceID], lo, hi);\n"
    "  v_world = mix(lo, hi, corner);\n"
    "  v_id = gl_InstanceID;\n"
    "  gl_Position = u_view_proj * vec4(v_world, 1.0);\n"
    "}\n";

static const char *march_fs =
    "#version 430 core\n" CURVES_GLSL SHADE_GLSL
    "uniform mat4 u_view_proj;\n"
    "uniform vec3 u_eye;\n"
    "uniform int u_parallel;\n"   /* 1: rays along u_ray (the shadow pass) */
    "uniform vec3 u_ray;\n"
    "uniform float u_pixel;\n"    /* a pixel's size per unit of distance: the LOD */
    "uniform float u_texture_scale;\n"
    "flat in int v_id;\n"
    "in vec3 v_world;\n"
    "out vec4 color;\n"
    "vec3 at(Curve c, float t) {\n"
    "  float s = 1.0 - t;\n"
    "  return s * s * s * c.p0_r0.xyz + 3.0 * s * s * t * c.p1_r1.xyz\n"
    "       + 3.0 * s * t * t * c.p2_v0.xyz + t * t * t * c.p3_length.xyz;\n"
    "}\n"
    "vec3 tangent(Curve c, float t) {\n"
    "  float s = 1.0 - t;\n"
    "  return 3.0 * s * s * (c.p1_r1.xyz - c.p0_r0.xyz) + 6.0 * s * t * (c.p2_v0.xyz - c.p1_r1.xyz)\n"
    "       + 3.0 * t * t * (c.p3_length.xyz - c.p2_v0.xyz);\n"
    "}\n"
    "/* The curve parameter closest to p: the best of 9 samples, then Newton steps on\n"
    "   (B(t) - p) . B'(t) = 0, kept in [0, 1]. */\n"
    "float closest(Curve c, vec3 p) {\n"
    "  float best = 0.0, bd = 1e30;\n"
    "  for (int i = 0; i <= 8; i++) {\n"
    "    float t = float(i) / 8.0;\n"
    "    vec3 d = at(c, t) - p;\n"
    "    float dd = dot(d, d);\n"
    "    if (dd < bd) { bd = dd; best = t; }\n"
    "  }\n"
    "  for (int i = 0; i < 3; i++) {\n"
    "    vec3 d = at(c, best) - p, b1 = tangent(c, best);\n"
    "    float s = 1.0 - best;\n"
    "    vec3 b2 = 6.0 * s * (c.p2_v0.xyz - 2.0 * c.p1_r1.xyz + c.p0_r0.xyz)\n"
    "            + 6.0 * best * (c.p3_length.xyz - 2.0 * c.p2_v0.xyz + c.p1_r1.xyz);\n"
    "    float f = dot(d, b1), df = dot(b1, b1) + dot(d, b2);\n"
    "    if (abs(df) > 1e-12) best = clamp(best - f / df, 0.0, 1.0);\n"
    "  }\n"
    "  return best;\n"
    "}\n"
    "float tube(Curve c, vec3 p, out float t) {\n"
    "  t = closest(c, p);\n"
    "  return length(p - at(c, t)) - mix(c.p0_r0.w, c.p1_r1.w, t);\n"
    "}\n"
    "void main() {\n"
    "  Curve c = curves[v_id];\n"
    "  vec3 lo, hi;\n"
    "  bounds(c, lo, hi);\n"
    "  vec3 rd = u_parallel == 1 ? u_ray : normalize(v_world - u_eye);\n"
    "  /* Where the ray leaves the box (slab test). */\n"
    "  vec3 inv = 1.0 / rd;\n"
    "  vec3 t1 = (lo - v_world) * inv, t2 = (hi - v_world) * inv;\n"
    "  float exit_t = min(min(max(t1.x, t2.x), max(t1.y, t2.y)), max(t1.z, t2.z));\n"
    "  vec3 p = v_world;\n"
    "  float travelled = 0.0, t = 0.0;\n"
    "  bool hit = false;\n"
    "  for (int i = 0; i < 64; i++) {\n"
    "    float d = tube(c, p, t);\n"
    "    float eps = u_parallel == 1 ? 1e-3 * max(c.p0_r0.w, 1e-3)\n"
    "                                : max(0.1 * u_pixel * distance(p, u_eye), 1e-5);\n"
    "    if (d < eps) { hit = true; break; }\n"
    "    travelled += d;\n"
    "    if (travelled > exit_t) break;\n"
    "    p += rd * d;\n"
    "  }\n"
    "  if (!hit) discard;\n"
    "  vec4 clip = u_view_proj * vec4(p, 1.0);\n"
    "  gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;\n"
    "  if (u_parallel == 1) { color = vec4(1.0); return; }\n"
    "  vec3 centre = at(c, t), n = normalize(p - centre);\n"
    "  /* u: the angle about the curve from a reference perpendicular; v: arc length. */\n"
    "  vec3 tg = normalize(tangent(c, t));\n"
    "  vec3 ref = normalize(cross(tg, abs(tg.y) < 0.99 ? vec3(0, 1, 0) : vec3(1, 0, 0)));\n"
    "  float angle = atan(dot(n, cross(tg, ref)), dot(n, ref));\n"
    "  vec2 uv = vec2(c.u_offset + angle / 6.2831853, (c.p2_v0.w + c.p3_length.w * t) / u_texture_scale);\n"
    "  color = vec4(shade(bark(uv), p, n), 1.0);\n"
    "}\n";

/* Triangles: arbor's mesh (mode 0), the ground (1) and instanced leaves (2). */
static const char *mesh_vs =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "layout(location = 3) in vec3 i_pos;\n"
    "layout(location = 4) in vec4 i_rot;\n"
    "layout(location = 5) in float i_scale;\n"
    "layout(location = 8) in float i_cell;\n" /* a leaf's atlas cell (arbor_leaf_cell) */
    "uniform mat4 u_view_proj;\n"
    "uniform int u_mode;\n"
    "flat out float v_cell;\n"
    "out vec3 v_world;\n"
    "out vec3 v_normal;\n"
    "out vec2 v_uv;\n"
    "vec3 rotate(vec4 q, vec3 v) { return v + 2.0 * cross(q.xyz, cross(q.xyz, v) + q.w * v); }\n"
    "void main() {\n"
    "  vec3 p = a_pos, n = a_normal;\n"
    "  if (u_mode == 2) { p = i_pos + rotate(i_rot, a_pos * i_scale); n = rotate(i_rot, a_normal); }\n"
    "  v_world = p; v_normal = n; v_uv = a_uv; v_cell = i_cell;\n"
    "  gl_Position = u_view_proj * vec4(p, 1.0);\n"
    "}\n";

static const char *mesh_fs =
    "#version 430 core\n" SHADE_GLSL ATLAS_GLSL
    "uniform int u_mode;\n"
    "uniform float u_texture_scale;\n"
    "flat in float v_cell;\n"
    "in vec3 v_world;\n"
    "in vec3 v_normal;\n"
    "in vec2 v_uv;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "  vec3 n = normalize(v_normal);\n"
    "  if (u_mode == 2 && !gl_FrontFacing) n = -n;\n"
    "  vec4 leaf = u_mode == 2 ? atlas(v_cell, v_uv) : vec4(1.0);\n" /* the oak's sprays */
    "  if (leaf.a < 0.5) discard;\n"
    "  vec3 base = u_mode == 0 ? bark(vec2(v_uv.x, v_uv.y)) : u_mode == 1 ? vec3(0.42, 0.45, 0.38)\n"
    "                                                     : leaf.rgb * 1.3;\n"
    "  color = vec4(shade(base, v_world, n), 1.0);\n"
    "}\n";

/* ---- the scene: every tree's records, mesh and leaves, merged ---- */
static GLuint march_program, mesh_program;
static GLuint curves_ssbo, march_vao;
static GLuint mesh_vao, ground_vao, leaf_vao, leaf_inst;
static GLuint shadow_fbo, shadow_tex;
static size_t branches, mesh_indices, mesh_bytes, leaves;
static float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
static const float texture_scale = 6.0f;
enum { SHADOW_SIZE = 2048 };

static ArborMeshOptions mesh_options(void) {
  ArborMeshOptions o = arbor_mesh_options_default();
  o.radial_segments = (uint32_t)st.segments;
  o.tip = ARBOR_TIP_POINT;
  o.texture_scale = texture_scale;
  return o;
}

/* Appends tree t's curve records, mesh and leaf instances to the scene's arrays. */
typedef struct {
  ArborCurveRecord *curves;
  ArborVertex *vertices;
  uint32_t *indices;
  ArborLeafInstance *leaves;
  float *cells;
  size_t nc, nv, ni, nl;
} Scene;

static void add_tree(Scene *s, const ArborTree *t) {
  size_t nb = arbor_tree_branch_count(t);
  s->curves = realloc(s->curves, (s->nc + nb + 1) * sizeof *s->curves);
  if (arbor_tree_curve_records_write(t, s->curves + s->nc, nb) != ARBOR_STATUS_OK) fail("curve records");
  for (size_t i = s->nc; i < s->nc + nb; i++) {
    const ArborCurveRecord *c = &s->curves[i];
    const float *pts[4] = {c->p0, c->p1, c->p2, c->p3};
    float r = c->r0 > c->r1 ? c->r0 : c->r1;
    for (int k = 0; k < 4; k++)
      for (int a = 0; a < 3; a++) {
        lo[a] = fminf(lo[a], pts[k][a] - r);
        hi[a] = fmaxf(hi[a], pts[k][a] + r);
      }
  }
  s->nc += nb;
  ArborMeshOptions o = mesh_options();
  size_t nv = 0, ni = 0;
  if (arbor_mesh_size(t, &o, &nv, &ni) != ARBOR_STATUS_OK) fail("arbor_mesh_size");
  s->vertices = realloc(s->vertices, (s->nv + nv + 1) * sizeof *s->vertices);
  s->indices = realloc(s->indices, (s->ni + ni + 1) * sizeof *s->indices);
  if (arbor_mesh_write(t, &o, s->vertices + s->nv, nv, s->indices + s->ni, ni) != ARBOR_STATUS_OK)
    fail("arbor_mesh_write");
  for (size_t k = s->ni; k < s->ni + ni; k++) s->indices[k] += (uint32_t)s->nv;
  s->nv += nv;
  s->ni += ni;
  ArborLeafOptions lo_ = arbor_leaf_options_default();
  lo_.tips = 1;
  lo_.density = 2.0f;
  /* A card is a spray of leaves (the atlas), alpha-cut: larger than one leaf. */
  lo_.size = 0.07f * (hi[1] - lo[1] > 0 ? hi[1] - lo[1] : 1.0f);
  lo_.atlas_columns = 4; /* the species atlas' grid (arbor_leaf_atlas_rect) */
  lo_.atlas_rows = 2;
  size_t nl = 0;
  if (arbor_leaf_instance_count(t, &lo_, &o, &nl) != ARBOR_STATUS_OK) fail("leaves");
  s->leaves = realloc(s->leaves, (s->nl + nl + 1) * sizeof *s->leaves);
  if (arbor_leaf_instances_write(t, &lo_, &o, s->leaves + s->nl, nl) != ARBOR_STATUS_OK) fail("leaves");
  float *cells = leaf_cells(&lo_, nl);
  s->cells = realloc(s->cells, (s->nl + nl + 1) * sizeof *s->cells);
  memcpy(s->cells + s->nl, cells, nl * sizeof *cells);
  free(cells);
  s->nl += nl;
}

static void upload(Scene *s) {
  branches = s->nc;
  p_glGenBuffers(1, &curves_ssbo);
  p_glBindBuffer(GL_SHADER_STORAGE_BUFFER, curves_ssbo);
  p_glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(s->nc * sizeof *s->curves), s->curves, GL_STATIC_DRAW);
  p_glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, curves_ssbo);
  p_glGenVertexArrays(1, &march_vao);

  mesh_vao = vertex_array(s->vertices, s->nv, s->indices, s->ni, NULL, NULL);
  mesh_indices = s->ni;
  mesh_bytes = s->nv * sizeof *s->vertices + s->ni * 4;

  /* Ground: a square at y = 0 under the scene. */
  float r = 2.0f * fmaxf(hi[0] - lo[0], fmaxf(hi[1] - lo[1], hi[2] - lo[2]));
  ArborVertex g[4];
  uint32_t gi[6];
  ground_square(0.5f * (lo[0] + hi[0]), 0.5f * (lo[2] + hi[2]), r, g, gi);
  ground_vao = vertex_array(g, 4, gi, 6, NULL, NULL);
  /* Leaves: the leaf quad, instanced. */
  ArborVertex q[4];
  uint32_t qi[6];
  leaf_quad(q, qi);
  leaf_vao = vertex_array(q, 4, qi, 6, NULL, NULL);
  p_glGenBuffers(1, &leaf_inst);
  p_glBindBuffer(GL_ARRAY_BUFFER, leaf_inst);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(s->nl * sizeof *s->leaves), s->leaves, GL_STATIC_DRAW);
  GLsizei ls = (GLsizei)sizeof(ArborLeafInstance);
  p_glVertexAttribPointer(3, 3, GL_FLOAT, GL_FALSE, ls, (void *)offsetof(ArborLeafInstance, position));
  p_glVertexAttribPointer(4, 4, GL_FLOAT, GL_FALSE, ls, (void *)offsetof(ArborLeafInstance, rotation));
  p_glVertexAttribPointer(5, 1, GL_FLOAT, GL_FALSE, ls, (void *)offsetof(ArborLeafInstance, scale));
  for (GLuint k = 3; k < 6; k++) {
    p_glEnableVertexAttribArray(k);
    p_glVertexAttribDivisor(k, 1);
  }
  GLuint cells_vbo = 0;
  p_glGenBuffers(1, &cells_vbo);
  p_glBindBuffer(GL_ARRAY_BUFFER, cells_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((s->nl + 1) * sizeof *s->cells), s->cells, GL_STATIC_DRAW);
  p_glVertexAttribPointer(8, 1, GL_FLOAT, GL_FALSE, sizeof *s->cells, (void *)0);
  p_glEnableVertexAttribArray(8);
  p_glVertexAttribDivisor(8, 1);
  leaves = s->nl;
  p_glBindVertexArray(0);

  /* The shadow map: a depth texture the light's pass renders into. */
  shadow_fbo = shadow_map(SHADOW_SIZE, &shadow_tex);
}

/* ---- drawing ---- */
static const float light_dir[3] = {0.4319f, 0.7198f, 0.5399f}; /* (0.45, 0.75, 0.5.), unit */

static void set_common(GLuint prog, Mat4 vp, Mat4 light_vp, int shadows) {
  p_glUseProgram(prog);
  p_glUniformMatrix4fv(p_glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, vp.m);
  p_glUniformMatrix4fv(p_glGetUniformLocation(prog, "u_light_vp"), 1, GL_FALSE, light_vp.m);
  p_glUniform3f(p_glGetUniformLocation(prog, "u_light"), light_dir[0], light_dir[1], light_dir[2]);
  p_glUniform1i(p_glGetUniformLocation(prog, "u_shadow_map"), 0);
  p_glUniform1i(p_glGetUniformLocation(prog, "u_shadows"), shadows);
  p_glUniform1f(p_glGetUniformLocation(prog, "u_texture_scale"), texture_scale);
}

/* The tree bodies: ray-marched boxes, or the mesh. `parallel`: the light's pass. */
static void draw_bodies(int mesh, Mat4 vp, Mat4 light_vp, const float eye[3], int parallel, float pixel) {
  if (mesh) {
    set_common(mesh_program, vp, light_vp, !parallel && st.shadow);
    p_glUniform1i(p_glGetUniformLocation(mesh_program, "u_mode"), 0);
    p_glBindVertexArray(mesh_vao);
    p_glDrawElements(GL_TRIANGLES, (GLsizei)mesh_indices, GL_UNSIGNED_INT, 0);
  } else {
    set_common(march_program, vp, light_vp, !parallel && st.shadow);
    p_glUniform3f(p_glGetUniformLocation(march_program, "u_eye"), eye[0], eye[1], eye[2]);
    p_glUniform1i(p_glGetUniformLocation(march_program, "u_parallel"), parallel);
    p_glUniform3f(p_glGetUniformLocation(march_program, "u_ray"), -light_dir[0], -light_dir[1], -light_dir[2]);
    p_glUniform1f(p_glGetUniformLocation(march_program, "u_pixel"), pixel);
    p_glBindVertexArray(march_vao);
    p_glDrawArraysInstanced(GL_TRIANGLES, 0, 36, (GLsizei)branches);
  }
}

static void draw_leaves(Mat4 vp, Mat4 light_vp, int shadows) {
  if (!st.leaves || !leaves) return;
  set_common(mesh_program, vp, light_vp, shadows);
  p_glUniform1i(p_glGetUniformLocation(mesh_program, "u_mode"), 2);
  p_glBindVertexArray(leaf_vao);
  p_glDisable(GL_CULL_FACE);
  p_glDrawElementsInstanced(GL_TRIANGLES, 6, GL_UNSIGNED_INT, 0, (GLsizei)leaves);
  p_glEnable(GL_CULL_FACE);
}

static void render(int mesh) {
  float c[3] = {0.5f * (lo[0] + hi[0]), 0.5f * (lo[1] + hi[1]), 0.5f * (lo[2] + hi[2])};
  float size = fmaxf(hi[0] - lo[0], fmaxf(hi[1] - lo[1], hi[2] - lo[2]));
  float dist = 1.6f * size / st.zoom;
  float eye[3] = {c[0] + dist * cosf(st.pitch) * sinf(st.yaw), c[1] + dist * sinf(st.pitch),
                  c[2] + dist * cosf(st.pitch) * cosf(st.yaw)};
  float fovy = 0.8f;
  Mat4 vp = mat_mul(perspective(fovy, (float)st.width / (float)st.height, 0.01f * size, 10.0f * size),
                    look_at(eye, c));
  /* The light: parallel rays over a box around the scene. */
  float radius = 0.75f * sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                               (hi[2] - lo[2]) * (hi[2] - lo[2]));
  float light_eye[3] = {c[0] + light_dir[0] * 2 * radius, c[1] + light_dir[1] * 2 * radius,
                        c[2] + light_dir[2] * 2 * radius};
  Mat4 light_vp = mat_mul(orthographic(-radius, radius, -radius, radius, 0.5f * radius, 3.5f * radius),
                          look_at(light_eye, c));
  p_glEnable(GL_DEPTH_TEST);
  p_glEnable(GL_CULL_FACE);
  if (st.shadow) {
    p_glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo);
    p_glViewport(0, 0, SHADOW_SIZE, SHADOW_SIZE);
    p_glClear(GL_DEPTH_BUFFER_BIT);
    draw_bodies(mesh, light_vp, light_vp, light_eye, 1, 0.0f);
    draw_leaves(light_vp, light_vp, 0);
    p_glBindFramebuffer(GL_FRAMEBUFFER, 0);
  }
  p_glViewport(0, 0, st.width, st.height);
  p_glClearColor(0.62f, 0.74f, 0.86f, 1.0f);
  p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  p_glActiveTexture(GL_TEXTURE0);
  p_glBindTexture(GL_TEXTURE_2D, shadow_tex);
  draw_bodies(mesh, vp, light_vp, eye, 0, 2.0f * tanf(fovy / 2) / (float)st.height);
  draw_leaves(vp, light_vp, st.shadow);
  if (st.ground) {
    set_common(mesh_program, vp, light_vp, st.shadow);
    p_glUniform1i(p_glGetUniformLocation(mesh_program, "u_mode"), 1);
    p_glBindVertexArray(ground_vao);
    p_glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_INT, 0);
  }
}

/* ---- input ---- */
static void key(GLFWwindow *win, int k, int scancode, int action, int mods) {
  (void)scancode;
  (void)mods;
  if (action != GLFW_PRESS) return;
  if (k == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(win, 1);
  else if (k == GLFW_KEY_M) st.mesh = !st.mesh;
  else if (k == GLFW_KEY_H) st.shadow = !st.shadow;
  else if (k == GLFW_KEY_L) st.leaves = !st.leaves;
}

static void mouse_button(GLFWwindow *win, int button, int action, int mods) {
  (void)mods;
  if (button != GLFW_MOUSE_BUTTON_LEFT) return;
  st.dragging = action == GLFW_PRESS;
  glfwGetCursorPos(win, &st.drag_x, &st.drag_y);
}

static void cursor(GLFWwindow *win, double x, double y) {
  (void)win;
  if (!st.dragging) return;
  orbit_drag(&st.yaw, &st.pitch, &st.drag_x, &st.drag_y, x, y, -0.2f, 1.5f);
}

static void scroll(GLFWwindow *win, double dx, double dy) {
  (void)win;
  (void)dx;
  st.zoom = orbit_zoom(st.zoom, dy);
}

static void resize(GLFWwindow *win, int w, int h) {
  (void)win;
  st.width = w;
  st.height = h;
}

/* Milliseconds a frame of one renderer takes (mean of `n`, after one warm-up frame). */
static double frame_ms(GLFWwindow *win, int mesh, int n) {
  render(mesh);
  p_glFinish();
  double t0 = now_ms();
  for (int k = 0; k < n; k++) render(mesh);
  p_glFinish();
  glfwPollEvents();
  (void)win;
  return (now_ms() - t0) / n;
}

int main(int argc, char **argv) {
  glapp_name = "raymarch";
  const char *shot = NULL;
  int frames = 2, headless = 0, compare = 0, world_cycles = 0, world_trees = 12, steps = -1;
  char tree_name = 'g';
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--screenshot") && i + 1 < argc) { shot = argv[++i]; headless = 1; }
    else if (!strcmp(argv[i], "--frames") && i + 1 < argc) frames = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--tree") && i + 1 < argc) tree_name = argv[++i][0];
    else if (!strcmp(argv[i], "--steps") && i + 1 < argc) steps = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--world") && i + 1 < argc) world_cycles = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--world-trees") && i + 1 < argc) world_trees = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--size") && i + 1 < argc) sscanf(argv[++i], "%dx%d", &st.width, &st.height);
    else if (!strcmp(argv[i], "--segments") && i + 1 < argc) st.segments = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--pitch") && i + 1 < argc) st.pitch = (float)atof(argv[++i]);
    else if (!strcmp(argv[i], "--yaw") && i + 1 < argc) st.yaw = (float)atof(argv[++i]);
    else if (!strcmp(argv[i], "--zoom") && i + 1 < argc) st.zoom = (float)atof(argv[++i]);
    else if (!strcmp(argv[i], "--mesh")) st.mesh = 1;
    else if (!strcmp(argv[i], "--no-shadow")) st.shadow = 0;
    else if (!strcmp(argv[i], "--no-ground")) st.ground = 0;
    else if (!strcmp(argv[i], "--no-leaves")) st.leaves = 0;
    else if (!strcmp(argv[i], "--compare")) compare = 1;
    else {
      fprintf(stderr,
              "usage: raymarch [--tree a..i] [--steps N] [--world CYCLES [--world-trees K]] [--mesh] "
              "[--segments K] [--no-shadow] [--no-ground] [--no-leaves] [--compare] [--pitch RADIANS] [--yaw RADIANS] [--zoom Z] "
              "[--size WxH] [--screenshot FILE.png|FILE.ppm --frames N]\n");
      return 2;
    }
  }
  if (tree_name < 'a' || tree_name > 'i' || st.width < 64 || st.height < 64 || frames < 1 || st.segments < 3 ||
      st.segments > 64 || world_trees < 1 || world_trees > 400) {
    fprintf(stderr, "raymarch: bad --tree, --size, --frames, --segments or --world-trees\n");
    return 2;
  }

  /* The trees: one 1996 preset, or a self-organized world grown for `world_cycles`. */
  Scene scene = {0};
  double t0 = now_ms();
  if (world_cycles > 0) {
    ArborWorldOptions wo = arbor_world_options_default();
    int side = (int)ceil(sqrt((double)world_trees));
    float half = 3.0f * (float)side;
    wo.min[0] = -half; wo.min[1] = 0; wo.min[2] = -half;
    wo.max[0] = half; wo.max[1] = 24; wo.max[2] = half;
    ArborWorld *world = NULL;
    if (arbor_world_create(&wo, &world) != ARBOR_STATUS_OK) fail("arbor_world_create");
    for (int k = 0; k < world_trees; k++) {
      ArborGrowthParams p;
      if (arbor_growth_params_preset((uint32_t)k % 5, &p, sizeof p) != ARBOR_STATUS_OK) fail("preset");
      float pos[3] = {(float)(k % side) * 6.0f - half + 3.0f, 0, (float)(k / side) * 6.0f - half + 3.0f};
      if (arbor_world_plant(world, &p, pos, (uint64_t)k + 1, NULL) != ARBOR_STATUS_OK) fail("plant");
    }
    if (arbor_world_step(world, (uint32_t)world_cycles) != ARBOR_STATUS_OK) fail("arbor_world_step");
    for (size_t k = 0; k < arbor_world_tree_count(world); k++) {
      ArborTree *t = NULL;
      if (arbor_world_tree(world, k, &t) != ARBOR_STATUS_OK) fail("arbor_world_tree");
      add_tree(&scene, t);
      arbor_tree_free(t);
    }
    arbor_world_free(world);
  } else {
    ArborHondaParams p;
    ArborTree *t = NULL;
    if (arbor_honda_preset((uint32_t)tree_name, &p) != ARBOR_STATUS_OK) fail("preset");
    if (steps >= 0) p.steps = (uint32_t)steps;
    if (arbor_tree_from_honda(&p, &t) != ARBOR_STATUS_OK) fail("arbor_tree_from_honda");
    add_tree(&scene, t);
    arbor_tree_free(t);
  }
  double grow_ms = now_ms() - t0;

  GLFWwindow *win = open_window("arbor ray marcher", st.width, st.height, 4, 3, headless);
  if (!load_gl()) return 1;
  glfwGetFramebufferSize(win, &st.width, &st.height);
  glfwSetKeyCallback(win, key);
  glfwSetMouseButtonCallback(win, mouse_button);
  glfwSetCursorPosCallback(win, cursor);
  glfwSetScrollCallback(win, scroll);
  glfwSetFramebufferSizeCallback(win, resize);
  march_program = link_program(march_vs, march_fs);
  mesh_program = link_program(mesh_vs, mesh_fs);
  upload(&scene);
  /* The leaves: the oak's leaf atlas, drawn by arbor, on texture unit 1. */
  species_texture(ARBOR_SPECIES_OAK, ARBOR_TEXTURE_LEAF_ATLAS, 512, GL_TEXTURE1);
  p_glUseProgram(mesh_program);
  p_glUniform1i(p_glGetUniformLocation(mesh_program, "u_atlas"), 1);
  printf("raymarch: arbor %s, OpenGL %s\n", arbor_version(), (const char *)p_glGetString(GL_VERSION));
  printf("raymarch: %zu branches (%.1f ms to grow); on the GPU: curve records %zu bytes (%zu a branch), "
         "mesh at %d sides %zu bytes (%.0f a branch); %zu leaves\n",
         branches, grow_ms, branches * sizeof(ArborCurveRecord), sizeof(ArborCurveRecord), st.segments,
         mesh_bytes, branches ? (double)mesh_bytes / (double)branches : 0.0, leaves);
  free(scene.curves);
  free(scene.vertices);
  free(scene.indices);
  free(scene.leaves);
  free(scene.cells);

  if (compare) {
    /* Both renderers alternately, so the machine's noise falls on both. */
    double march = 0, mesh = 0;
    for (int round = 0; round < 3; round++) {
      march += frame_ms(win, 0, frames);
      mesh += frame_ms(win, 1, frames);
    }
    printf("raymarch: frame %.2f ms ray-marched, %.2f ms meshed (ratio %.2f), %dx%d\n", march / 3, mesh / 3,
           march / mesh, st.width, st.height);
  }
  for (int frame = 0; !glfwWindowShouldClose(win); frame++) {
    render(st.mesh);
    if (headless && frame + 1 >= frames) {
      int ok = save_image(shot, st.width, st.height);
      glfwDestroyWindow(win);
      glfwTerminate();
      return ok ? 0 : 1;
    }
    glfwSwapBuffers(win);
    glfwPollEvents();
  }
  glfwDestroyWindow(win);
  glfwTerminate();
  return 0;
}
