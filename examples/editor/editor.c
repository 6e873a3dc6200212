/*
 * arbor editor: bend a tree's branches by their handles, re-meshing only what changed.
 *
 * A click picks the branch under the cursor (the view ray against every branch's curve,
 * taken as 8 segments with the branch's radius), and shows its control points p1, p2 and
 * p3 as handles. Dragging a handle moves it in the plane facing the camera through
 * arbor_tree_set_curve (moving p3 carries the whole subtree along); arbor_mesh_rewrite_branch
 * then rewrites only the changed vertices in the CPU copy of the mesh, and only their
 * ranges (the branch's subtree and its parent, from arbor_mesh_branch_ranges) go up with
 * glBufferSubData. The window title shows that time beside what a full write and upload
 * of the same mesh takes. Z undoes the last edit, S saves edited.glb (glTF).
 *
 *   editor [--tree a..i] [--steps N] [--size WxH]
 *          [script...] [--screenshot FILE.png|FILE.ppm [--frames N]]
 *
 * The script runs in order, each step on the rendered frame before it (headless with
 * --screenshot, which is written after the last step):
 *   --click X,Y             pick the branch under the pixel (prints it, or "nothing")
 *   --click-branch N        click at the screen position of branch N's midpoint
 *   --drag-handle K DX,DY   drag the picked branch's handle K (1..3: p1, p2, p3) by pixels
 *   --undo                  undo the last edit
 *   --verify                read the vertex buffer back from the GPU and compare it with
 *                           a full arbor_mesh_write of the tree as it is now
 *   --verify-original       compare the GPU's vertices with the mesh as first written
 *   --save FILE.glb         write the tree as glTF (arbor_export_gltf)
 *
 * Mouse: left button picks and drags handles; right drag orbits; wheel zooms. Esc quits.
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
  int width, height;
  float yaw, pitch, zoom;
  double mouse_x, mouse_y;
  int orbiting, dragging; /* dragging: the handle (1..3), 0 none */
} st = {900, 700, 0.5f, 0.2f, 1.0f, 0, 0, 0, 0};

static const char *vs_src =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "uniform mat4 u_view_proj;\n"
    "uniform float u_point;\n"
    "out vec3 v_normal;\n"
    "out vec2 v_uv;\n"
    "void main() {\n"
    "  v_normal = a_normal; v_uv = a_uv;\n"
    "  gl_Position = u_view_proj * vec4(a_pos, 1.0);\n"
    "  gl_PointSize = u_point;\n"
    "}\n";

static const char *fs_src =
    "#version 330 core\n"
    "in vec3 v_normal;\n"
    "in vec2 v_uv;\n"
    "uniform int u_mode;\n" /* 0 bark, 1 the picked branch's handles and polygon */
    "uniform vec3 u_light;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "  if (u_mode == 1) { color = vec4(1.0, 0.85, 0.1, 1.0); return; }\n"
    "  float grain = 0.5 + 0.5 * sin(v_uv.x * 37.7 + sin(v_uv.y * 3.1) * 2.0);\n"
    "  vec3 base = mix(vec3(0.30, 0.20, 0.12), vec3(0.45, 0.32, 0.20), 0.6 * grain);\n"
    "  float d = max(dot(normalize(v_normal), u_light), 0.0);\n"
    "  color = vec4(base * (0.35 + 0.65 * d), 1.0);\n"
    "}\n";

/* ---- the tree, its mesh on the CPU and the GPU ---- */
static ArborTree *tree;
static ArborMeshOptions opts;
static size_t nb, nv, ni;
static ArborVertex *cpu_vertices, *original;
static uint32_t *cpu_indices;
static ArborCurve *curves;   /* kept up to date with the tree */
static ArborBranch *branch;  /* parents (they never change) */
static ArborBranchRange *ranges; /* each branch's vertices (an edit keeps them) */
static char *changed;            /* scratch: the branches an edit changed */
static GLuint program, vao, vbo, ebo, handle_vao, handle_vbo;
static long picked = -1;
static float lo[3], hi[3];

typedef struct {
  size_t branch;
  ArborCurve before, after;
} Edit;
static Edit *undo_stack;
static size_t undo_len, undo_cap;

static void read_tree(void) {
  if (arbor_tree_copy_curves(tree, curves, nb) != ARBOR_STATUS_OK) fail("arbor_tree_copy_curves");
}

static ArborHondaParams source; /* the tree as grown, for undo by replay */

static void load(char name, int steps) {
  ArborHondaParams p;
  if (arbor_honda_preset((uint32_t)name, &p) != ARBOR_STATUS_OK) fail("preset");
  if (steps >= 0) p.steps = (uint32_t)steps;
  source = p;
  if (arbor_tree_from_honda(&p, &tree) != ARBOR_STATUS_OK) fail("arbor_tree_from_honda");
  nb = arbor_tree_branch_count(tree);
  curves = malloc(nb * sizeof *curves);
  branch = malloc(nb * sizeof *branch);
  arbor_tree_copy_branches(tree, branch, nb);
  read_tree();
  for (int a = 0; a < 3; a++) lo[a] = FLT_MAX, hi[a] = -FLT_MAX;
  for (size_t i = 0; i < nb; i++)
    for (int a = 0; a < 3; a++) {
      lo[a] = fminf(lo[a], fminf(branch[i].start[a], branch[i].end[a]));
      hi[a] = fmaxf(hi[a], fmaxf(branch[i].start[a], branch[i].end[a]));
    }
  opts = arbor_mesh_options_default();
  opts.texture_scale = 6.0f;
  if (arbor_mesh_size(tree, &opts, &nv, &ni) != ARBOR_STATUS_OK) fail("arbor_mesh_size");
  cpu_vertices = malloc(nv * sizeof *cpu_vertices);
  original = malloc(nv * sizeof *original);
  cpu_indices = malloc(ni * sizeof *cpu_indices);
  if (arbor_mesh_write(tree, &opts, cpu_vertices, nv, cpu_indices, ni) != ARBOR_STATUS_OK) fail("arbor_mesh_write");
  memcpy(original, cpu_vertices, nv * sizeof *original);
  ranges = malloc(nb * sizeof *ranges);
  changed = malloc(nb);
  if (arbor_mesh_branch_ranges(tree, &opts, ranges, nb) != ARBOR_STATUS_OK) fail("arbor_mesh_branch_ranges");
}

static void upload_all(void) {
  p_glGenVertexArrays(1, &vao);
  p_glBindVertexArray(vao);
  p_glGenBuffers(1, &vbo);
  p_glGenBuffers(1, &ebo);
  p_glBindBuffer(GL_ARRAY_BUFFER, vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * sizeof(ArborVertex)), cpu_vertices, GL_DYNAMIC_DRAW);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * 4), cpu_indices, GL_STATIC_DRAW);
  vertex_layout();
  p_glGenVertexArrays(1, &handle_vao);
  p_glBindVertexArray(handle_vao);
  p_glGenBuffers(1, &handle_vbo);
  p_glBindBuffer(GL_ARRAY_BUFFER, handle_vbo);
  p_glBufferData(GL_ARRAY_BUFFER, 4 * sizeof(ArborVertex), NULL, GL_DYNAMIC_DRAW);
  vertex_layout(); /* only the position is read */
  p_glBindVertexArray(0);
}

/* ---- the camera, and rays from pixels ---- */
static const float fovy = 0.8f;
static float eye[3], centre[3];

static Mat4 view_proj(void) {
  for (int a = 0; a < 3; a++) centre[a] = 0.5f * (lo[a] + hi[a]);
  float size = fmaxf(hi[0] - lo[0], fmaxf(hi[1] - lo[1], hi[2] - lo[2]));
  float dist = 1.6f * size / st.zoom;
  eye[0] = centre[0] + dist * cosf(st.pitch) * sinf(st.yaw);
  eye[1] = centre[1] + dist * sinf(st.pitch);
  eye[2] = centre[2] + dist * cosf(st.pitch) * cosf(st.yaw);
  return mat_mul(perspective(fovy, (float)st.width / (float)st.height, 0.01f * size, 10.0f * size),
                 look_at(eye, centre));
}

/* The view ray through pixel (x, y) (y down, as GLFW reports the cursor). */
static void ray(double x, double y, float dir[3]) {
  view_proj();
  float f[3] = {centre[0] - eye[0], centre[1] - eye[1], centre[2] - eye[2]};
  float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (int a = 0; a < 3; a++) f[a] /= fl;
  float up[3] = {0, 1, 0};
  float s[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]};
  float sl = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  for (int a = 0; a < 3; a++) s[a] /= sl;
  float u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
  float t = tanf(fovy / 2), aspect = (float)st.width / (float)st.height;
  float px = (float)(2 * (x + 0.5) / st.width - 1) * t * aspect, py = (float)(1 - 2 * (y + 0.5) / st.height) * t;
  float l = 0;
  for (int a = 0; a < 3; a++) {
    dir[a] = f[a] + s[a] * px + u[a] * py;
    l += dir[a] * dir[a];
  }
  for (int a = 0; a < 3; a++) dir[a] /= sqrtf(l);
}

/* Where point p lands on the screen (pixels, y down); 0 when behind the camera. */
static int project(const float p[3], double *x, double *y) {
  Mat4 vp = view_proj();
  float c[4];
  for (int r = 0; r < 4; r++) c[r] = vp.m[r] * p[0] + vp.m[4 + r] * p[1] + vp.m[8 + r] * p[2] + vp.m[12 + r];
  if (c[3] <= 0) return 0;
  *x = (c[0] / c[3] * 0.5 + 0.5) * st.width - 0.5;
  *y = (0.5 - c[1] / c[3] * 0.5) * st.height - 0.5;
  return 1;
}

static void bezier(const ArborCurve *c, float t, float out[3]) {
  float s = 1 - t;
  for (int a = 0; a < 3; a++)
    out[a] = s * s * s * c->p0[a] + 3 * s * s * t * c->p1[a] + 3 * s * t * t * c->p2[a] + t * t * t * c->p3[a];
}

/* Distance along the ray (o, d) to the capsule of segment a-b and radius r; -1 for a miss. */
static float ray_capsule(const float o[3], const float d[3], const float a[3], const float b[3], float r) {
  /* The closest points of the ray and the segment's line, then the distance between them. */
  float ab[3], ao[3];
  for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], ao[k] = o[k] - a[k];
  float aa = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
  float bd = ab[0] * d[0] + ab[1] * d[1] + ab[2] * d[2];
  float ad = ao[0] * d[0] + ao[1] * d[1] + ao[2] * d[2];
  float ab_ao = ab[0] * ao[0] + ab[1] * ao[1] + ab[2] * ao[2];
  float s = 0; /* along the segment, 0..1 */
  if (aa > 0) {
    float den = aa - bd * bd;
    s = den > 1e-12f * aa ? (ab_ao - bd * ad) / den : ab_ao / aa;
    s = fmaxf(0, fminf(1, s));
  }
  float q[3];
  for (int k = 0; k < 3; k++) q[k] = a[k] + ab[k] * s;
  float t = (q[0] - o[0]) * d[0] + (q[1] - o[1]) * d[1] + (q[2] - o[2]) * d[2];
  if (t < 0) return -1;
  float dist2 = 0;
  for (int k = 0; k < 3; k++) {
    float e = o[k] + d[k] * t - q[k];
    dist2 += e * e;
  }
  return dist2 <= r * r ? t - sqrtf(r * r - dist2) : -1;
}

/* The branch the ray through pixel (x, y) meets first, or -1. */
static long pick(double x, double y) {
  float d[3];
  ray(x, y, d);
  long best = -1;
  float best_t = FLT_MAX;
  for (size_t i = 0; i < nb; i++) {
    const ArborCurve *c = &curves[i];
    float prev[3], next[3];
    bezier(c, 0, prev);
    for (int k = 1; k <= 8; k++) {
      float t = (float)k / 8;
      bezier(c, t, next);
      float r = c->r0 + (c->r1 - c->r0) * t;
      float h = ray_capsule(eye, d, prev, next, r);
      if (h >= 0 && h < best_t) best_t = h, best = (long)i;
      memcpy(prev, next, sizeof prev);
    }
  }
  return best;
}

/* ---- edits ---- */
/* Sizes, writes and uploads the whole mesh (and its ranges): after an edit that changed
 * the mesh's layout, and after an undo by replay. */
static void write_whole(void) {
  if (arbor_mesh_size(tree, &opts, &nv, &ni) != ARBOR_STATUS_OK) fail("arbor_mesh_size");
  cpu_vertices = realloc(cpu_vertices, nv * sizeof *cpu_vertices);
  cpu_indices = realloc(cpu_indices, ni * sizeof *cpu_indices);
  if (arbor_mesh_write(tree, &opts, cpu_vertices, nv, cpu_indices, ni) != ARBOR_STATUS_OK) fail("arbor_mesh_write");
  if (arbor_mesh_branch_ranges(tree, &opts, ranges, nb) != ARBOR_STATUS_OK) fail("arbor_mesh_branch_ranges");
  p_glBindBuffer(GL_ARRAY_BUFFER, vbo);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(nv * sizeof(ArborVertex)), cpu_vertices, GL_DYNAMIC_DRAW);
  p_glBindVertexArray(vao);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(ni * 4), cpu_indices, GL_STATIC_DRAW);
  p_glBindVertexArray(0);
}

static double last_rewrite_ms, last_full_ms;
static size_t last_uploaded;

/* Rewrites what changed after an edit of branch i, uploads its vertex ranges (the subtree
 * of i and its parent), and times it against a full write and upload. */
static void rewrite_and_upload(size_t i) {
  p_glFinish(); /* the frame drawn before is not the edit's time */
  double t0 = now_ms();
  size_t new_nv = 0, new_ni = 0;
  if (arbor_mesh_size(tree, &opts, &new_nv, &new_ni) != ARBOR_STATUS_OK) fail("arbor_mesh_size");
  if (new_nv != nv || new_ni != ni) {
    /* A bend past 90 degrees turns a mitred joint into two rings: the mesh's layout
       changes, so it is sized, written and uploaded whole. */
    write_whole();
    printf("editor: branch %zu: the edit changed the mesh's layout (a joint past 90 degrees); written whole, "
           "%zu vertices\n", i, nv);
    last_rewrite_ms = last_full_ms = now_ms() - t0;
    last_uploaded = nv;
    return;
  }
  if (arbor_mesh_rewrite_branch(tree, &opts, i, cpu_vertices, nv, cpu_indices, ni) != ARBOR_STATUS_OK)
    fail("arbor_mesh_rewrite_branch");
  /* The subtree of i (parents come before children), and i's parent. */
  const ArborBranchRange *r = ranges;
  memset(changed, 0, nb);
  changed[i] = 1;
  for (size_t j = i + 1; j < nb; j++)
    if (branch[j].parent != ARBOR_NO_PARENT && changed[branch[j].parent]) changed[j] = 1;
  if (branch[i].parent != ARBOR_NO_PARENT) changed[branch[i].parent] = 1;
  p_glBindBuffer(GL_ARRAY_BUFFER, vbo);
  size_t uploaded = 0;
  for (size_t j = 0; j < nb;) {
    if (!changed[j]) { j++; continue; }
    size_t first = r[j].first_vertex, end = first + r[j].vertex_count;
    for (j++; j < nb && changed[j]; j++) end = r[j].first_vertex + r[j].vertex_count;
    p_glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)(first * sizeof(ArborVertex)),
                      (GLsizeiptr)((end - first) * sizeof(ArborVertex)), cpu_vertices + first);
    uploaded += end - first;
  }
  p_glFinish();
  last_rewrite_ms = now_ms() - t0;
  last_uploaded = uploaded;
  /* What a full write and upload of the same mesh takes (into a scratch buffer). */
  double t1 = now_ms();
  ArborVertex *v = malloc(nv * sizeof *v);
  uint32_t *ix = malloc(ni * sizeof *ix);
  if (arbor_mesh_write(tree, &opts, v, nv, ix, ni) != ARBOR_STATUS_OK) fail("arbor_mesh_write");
  p_glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(nv * sizeof *v), v);
  p_glFinish();
  last_full_ms = now_ms() - t1;
  free(v);
  free(ix);
  printf("editor: branch %zu: rewrite + upload %.3f ms (%zu of %zu vertices); full write + upload %.3f ms "
         "(%.1fx)\n",
         i, last_rewrite_ms, uploaded, nv, last_full_ms, last_full_ms / fmax(last_rewrite_ms, 1e-6));
}

static void set_curve(size_t i, const ArborCurve *c, int record) {
  if (record) {
    if (undo_len == undo_cap) {
      undo_cap = undo_cap ? 2 * undo_cap : 64;
      undo_stack = realloc(undo_stack, undo_cap * sizeof *undo_stack);
    }
    undo_stack[undo_len++] = (Edit){i, curves[i], *c};
  }
  if (arbor_tree_set_curve(tree, i, c) != ARBOR_STATUS_OK) fail("arbor_tree_set_curve");
  read_tree();
  rewrite_and_upload(i);
}

/* Undoes the last edit. One that kept the branch's end (p1, p2, radii) is set back and
 * rewritten in place. One that moved the end translated the subtree, and a translation
 * back is off by float rounding; so the tree is grown again and the other edits replayed,
 * which gives the earlier bytes exactly, and the mesh is written and uploaded whole. */
static void undo(void) {
  if (!undo_len) return;
  Edit e = undo_stack[--undo_len];
  if (!memcmp(e.before.p3, e.after.p3, sizeof e.before.p3)) {
    set_curve(e.branch, &e.before, 0);
    printf("editor: undid the edit of branch %zu in place\n", e.branch);
    return;
  }
  p_glFinish();
  double t0 = now_ms();
  arbor_tree_free(tree);
  if (arbor_tree_from_honda(&source, &tree) != ARBOR_STATUS_OK) fail("arbor_tree_from_honda");
  for (size_t k = 0; k < undo_len; k++)
    if (arbor_tree_set_curve(tree, undo_stack[k].branch, &undo_stack[k].after) != ARBOR_STATUS_OK)
      fail("arbor_tree_set_curve");
  read_tree();
  write_whole();
  p_glFinish();
  printf("editor: undid the edit of branch %zu by regrowing and replaying %zu edits (%.2f ms)\n", e.branch,
         undo_len, now_ms() - t0);
}

static float *handle_point(ArborCurve *c, int k) { return k == 1 ? c->p1 : k == 2 ? c->p2 : c->p3; }

/* Moves handle k of the picked branch so it follows the cursor from (x0, y0) to (x1, y1):
 * in the plane through the handle that faces the camera. */
static void drag_handle(int k, double x0, double y0, double x1, double y1) {
  if (picked < 0) return;
  ArborCurve c = curves[picked];
  float *h = handle_point(&c, k);
  float d0[3], d1[3], n[3] = {centre[0] - eye[0], centre[1] - eye[1], centre[2] - eye[2]};
  ray(x0, y0, d0);
  ray(x1, y1, d1);
  float along = (h[0] - eye[0]) * n[0] + (h[1] - eye[1]) * n[1] + (h[2] - eye[2]) * n[2];
  float t0 = along / (d0[0] * n[0] + d0[1] * n[1] + d0[2] * n[2]);
  float t1 = along / (d1[0] * n[0] + d1[1] * n[1] + d1[2] * n[2]);
  for (int a = 0; a < 3; a++) h[a] += d1[a] * t1 - d0[a] * t0;
  set_curve((size_t)picked, &c, 1);
}

/* The handle (1..3) of the picked branch within 12 pixels of (x, y), or 0. */
static int handle_at(double x, double y) {
  if (picked < 0) return 0;
  for (int k = 3; k >= 1; k--) {
    double hx, hy;
    if (project(handle_point(&curves[picked], k), &hx, &hy) && fabs(hx - x) < 12 && fabs(hy - y) < 12) return k;
  }
  return 0;
}

/* ---- drawing ---- */
static void render(void) {
  Mat4 vp = view_proj();
  p_glViewport(0, 0, st.width, st.height);
  p_glClearColor(0.62f, 0.74f, 0.86f, 1.0f);
  p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  p_glEnable(GL_DEPTH_TEST);
  p_glEnable(GL_CULL_FACE);
  p_glUseProgram(program);
  p_glUniformMatrix4fv(p_glGetUniformLocation(program, "u_view_proj"), 1, GL_FALSE, vp.m);
  p_glUniform3f(p_glGetUniformLocation(program, "u_light"), 0.4319f, 0.7198f, 0.5399f);
  p_glUniform1i(p_glGetUniformLocation(program, "u_mode"), 0);
  p_glUniform1f(p_glGetUniformLocation(program, "u_point"), 1.0f);
  p_glBindVertexArray(vao);
  p_glDrawElements(GL_TRIANGLES, (GLsizei)ni, GL_UNSIGNED_INT, 0);
  if (picked >= 0) {
    /* The control polygon and its handles, over the bark. */
    const ArborCurve *c = &curves[picked];
    ArborVertex h[4];
    memset(h, 0, sizeof h);
    const float *pts[4] = {c->p0, c->p1, c->p2, c->p3};
    for (int k = 0; k < 4; k++) memcpy(h[k].position, pts[k], sizeof h[k].position);
    p_glBindVertexArray(handle_vao);
    p_glBindBuffer(GL_ARRAY_BUFFER, handle_vbo);
    p_glBufferSubData(GL_ARRAY_BUFFER, 0, sizeof h, h);
    p_glDisable(GL_DEPTH_TEST);
    p_glUniform1i(p_glGetUniformLocation(program, "u_mode"), 1);
    p_glUniform1f(p_glGetUniformLocation(program, "u_point"), 9.0f);
    p_glDrawArrays(GL_LINE_STRIP, 0, 4);
    p_glDrawArrays(GL_POINTS, 1, 3);
    p_glEnable(GL_DEPTH_TEST);
  }
}

static void click(double x, double y) {
  picked = pick(x, y);
  if (picked >= 0) printf("editor: picked branch %ld\n", picked);
  else printf("editor: picked nothing\n");
}

/* ---- input ---- */
static GLFWwindow *window;

static void title(void) {
  char t[256];
  snprintf(t, sizeof t, "arbor editor: %zu branches; last edit: rewrite + upload %.3f ms (%zu vertices), full write + upload %.2f ms",
           nb, last_rewrite_ms, last_uploaded, last_full_ms);
  glfwSetWindowTitle(window, t);
}

static void key(GLFWwindow *win, int k, int scancode, int action, int mods) {
  (void)scancode;
  (void)mods;
  if (action != GLFW_PRESS) return;
  if (k == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(win, 1);
  else if (k == GLFW_KEY_Z) { undo(); title(); }
  else if (k == GLFW_KEY_S) {
    if (arbor_export_gltf(tree, &opts, NULL, "edited.glb") != ARBOR_STATUS_OK) fail("arbor_export_gltf");
    printf("editor: saved edited.glb\n");
  }
}

static void mouse_button(GLFWwindow *win, int button, int action, int mods) {
  (void)mods;
  glfwGetCursorPos(win, &st.mouse_x, &st.mouse_y);
  if (button == GLFW_MOUSE_BUTTON_RIGHT) st.orbiting = action == GLFW_PRESS;
  if (button != GLFW_MOUSE_BUTTON_LEFT) return;
  if (action == GLFW_PRESS) {
    st.dragging = handle_at(st.mouse_x, st.mouse_y);
    if (!st.dragging) click(st.mouse_x, st.mouse_y);
  } else {
    st.dragging = 0;
  }
}

static void cursor(GLFWwindow *win, double x, double y) {
  (void)win;
  if (st.orbiting) {
    st.yaw -= (float)(x - st.mouse_x) * 0.01f;
    st.pitch = fmaxf(-0.2f, fminf(1.5f, st.pitch + (float)(y - st.mouse_y) * 0.01f));
  } else if (st.dragging) {
    drag_handle(st.dragging, st.mouse_x, st.mouse_y, x, y);
    title();
  }
  st.mouse_x = x;
  st.mouse_y = y;
}

static void scroll(GLFWwindow *win, double dx, double dy) {
  (void)win;
  (void)dx;
  st.zoom = orbit_zoom(st.zoom, dy);
}

/* Compares the GPU's vertex buffer with `expected` (nv vertices); prints and returns 1 when
 * they are equal byte for byte. */
static int gpu_equals(const ArborVertex *expected, const char *what) {
  ArborVertex *gpu = malloc(nv * sizeof *gpu);
  p_glBindBuffer(GL_ARRAY_BUFFER, vbo);
  p_glGetBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(nv * sizeof *gpu), gpu);
  int same = memcmp(gpu, expected, nv * sizeof *gpu) == 0;
  printf("editor: %s: %s (%zu bytes)\n", what, same ? "equal" : "DIFFERENT", nv * sizeof *gpu);
  free(gpu);
  return same;
}

/* Runs one script step (argv[*i] and its arguments); 0 on a bad step. */
static int step(int argc, char **argv, int *i) {
  const char *s = argv[*i];
  double x, y, x1, y1;
  if (!strcmp(s, "--click") && *i + 1 < argc && sscanf(argv[++*i], "%lf,%lf", &x, &y) == 2) {
    click(x, y);
  } else if (!strcmp(s, "--click-branch") && *i + 1 < argc) {
    long b = atol(argv[++*i]);
    if (b < 0 || (size_t)b >= nb) return 0;
    float m[3];
    bezier(&curves[b], 0.5f, m);
    if (!project(m, &x, &y)) return 0;
    printf("editor: clicking branch %ld's midpoint at %.1f,%.1f\n", b, x, y);
    click(x, y);
  } else if (!strcmp(s, "--drag-handle") && *i + 2 < argc) {
    int k = atoi(argv[++*i]);
    if (k < 1 || k > 3 || sscanf(argv[++*i], "%lf,%lf", &x1, &y1) != 2 || picked < 0) return 0;
    if (!project(handle_point(&curves[picked], k), &x, &y)) return 0;
    drag_handle(k, x, y, x + x1, y + y1);
  } else if (!strcmp(s, "--undo")) {
    undo();
  } else if (!strcmp(s, "--verify")) {
    ArborVertex *v = malloc(nv * sizeof *v);
    uint32_t *ix = malloc(ni * sizeof *ix);
    if (arbor_mesh_write(tree, &opts, v, nv, ix, ni) != ARBOR_STATUS_OK) fail("arbor_mesh_write");
    gpu_equals(v, "GPU vertices against a full write of the edited tree");
    free(v);
    free(ix);
  } else if (!strcmp(s, "--verify-original")) {
    gpu_equals(original, "GPU vertices against the mesh as first written");
  } else if (!strcmp(s, "--save") && *i + 1 < argc) {
    const char *path = argv[++*i];
    if (arbor_export_gltf(tree, &opts, NULL, path) != ARBOR_STATUS_OK) fail("arbor_export_gltf");
    printf("editor: saved %s\n", path);
  } else {
    return 0;
  }
  return 1;
}

static void usage(void) {
  fprintf(stderr,
          "usage: editor [--tree a..i] [--steps N] [--size WxH] [--click X,Y] [--click-branch N] "
          "[--drag-handle 1..3 DX,DY] [--undo] [--verify] [--verify-original] [--save FILE.glb] "
          "[--screenshot FILE.png|FILE.ppm]\n");
}

int main(int argc, char **argv) {
  glapp_name = "editor";
  const char *shot = NULL;
  char name = 'a';
  int steps = -1, script_from = argc;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--tree") && i + 1 < argc) name = argv[++i][0];
    else if (!strcmp(argv[i], "--steps") && i + 1 < argc) steps = atoi(argv[++i]);
    else if (!strcmp(argv[i], "--size") && i + 1 < argc) sscanf(argv[++i], "%dx%d", &st.width, &st.height);
    else if (!strcmp(argv[i], "--screenshot") && i + 1 < argc) shot = argv[++i];
    else if (!strcmp(argv[i], "--frames") && i + 1 < argc) i++; /* as the gallery's; one frame a step */
    else if (!strncmp(argv[i], "--", 2)) {
      if (script_from == argc) script_from = i;
      /* Script steps are checked when they run; skip their arguments here. */
      if (!strcmp(argv[i], "--drag-handle")) i += 2;
      else if (!strcmp(argv[i], "--click") || !strcmp(argv[i], "--click-branch") || !strcmp(argv[i], "--save")) i++;
    } else {
      usage();
      return 2;
    }
  }
  if (name < 'a' || name > 'i' || st.width < 64 || st.height < 64) {
    usage();
    return 2;
  }
  load(name, steps);
  window = open_window("arbor editor", st.width, st.height, 3, 3, shot != NULL);
  if (!load_gl()) return 1;
  glfwGetFramebufferSize(window, &st.width, &st.height);
  glfwSetKeyCallback(window, key);
  glfwSetMouseButtonCallback(window, mouse_button);
  glfwSetCursorPosCallback(window, cursor);
  glfwSetScrollCallback(window, scroll);
  p_glEnable(GL_PROGRAM_POINT_SIZE);
  program = link_program(vs_src, fs_src);
  upload_all();
  printf("editor: tree %c, %zu branches, %zu vertices\n", name, nb, nv);
  /* The script, each step on the frame before it. */
  for (int i = script_from; i < argc; i++) {
    if (!strcmp(argv[i], "--tree") || !strcmp(argv[i], "--steps") || !strcmp(argv[i], "--size") ||
        !strcmp(argv[i], "--screenshot") || !strcmp(argv[i], "--frames")) {
      i++;
      continue;
    }
    render();
    if (!step(argc, argv, &i)) {
      fprintf(stderr, "editor: bad script step %s\n", argv[i]);
      usage();
      return 2;
    }
  }
  if (shot) {
    render();
    int ok = save_image(shot, st.width, st.height);
    glfwDestroyWindow(window);
    glfwTerminate();
    return ok ? 0 : 1;
  }
  title();
  while (!glfwWindowShouldClose(window)) {
    render();
    glfwSwapBuffers(window);
    glfwWaitEvents();
  }
  glfwDestroyWindow(window);
  glfwTerminate();
  return 0;
}
