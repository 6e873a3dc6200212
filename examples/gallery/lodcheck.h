/*
 * gallery --lod-check: a named species' levels of detail checked by the host's OpenGL, and
 * arbor's impostor baker timed against OpenGL drawing the same views.
 *
 *   gallery --species oak --lod-check
 *
 * 1. Silhouettes: the chain (arbor_tree_lods_create, the species' 256-pixel leaf atlas)
 *    is uploaded; each level k >= 1 and the full tree are drawn by OpenGL, orthographic,
 *    from 8 directions around the tree (none of those the chain was fitted from), at the
 *    size the tree has where level k is first drawn (level k - 1's screen coverage of a
 *    1080-pixel screen), 4 x 4 samples a pixel (fewer above 256 pixels: at most 1024
 *    samples a side), the leaves alpha-tested at one half against the atlas (nearest
 *    texel), the bark's back faces culled: the masks arbor's own rasterizer makes
 *    (lod::silhouette). A pixel is covered when half its samples are. Printed: each
 *    level's intersection over union with the full tree, mean and least.
 * 2. The baker: arbor_lods_impostor_create (12 x 12 hemi-octahedral views of 128 pixels of
 *    level 2, 3 x 3 samples a pixel, albedo and normal into host memory) against OpenGL
 *    drawing the same 144 views of the same level at 384 x 384 (the same samples) into colour and normal
 *    attachments and reading both back (glReadPixels) into host memory: milliseconds of
 *    each, best of three.
 *
 * 3. The impostor as a host draws it: the full tree's impostor (12 x 12 views of 128
 *    pixels) drawn by the reference shader (examples/common/impostor.glsl, built into the
 *    gallery) on one camera-facing quad, alpha-tested, against the full tree drawn by
 *    OpenGL as in 1, from 16 directions that are not baked views (level to 60 degrees up),
 *    at 96 pixels. And a field of 400 impostors, instanced, timed.
 *
 * One line a figure, prefixed "lod-check:", for tests/gallery.rs and BENCHMARKS.md.
 */

#include "impostor_glsl.h" /* impostor_glsl: examples/common/impostor.glsl as a string */

static const char *lc_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_normal;\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "uniform mat4 u_view_proj;\n"
    "out vec3 v_normal;\n"
    "out vec2 v_uv;\n"
    "void main() {\n"
    "  v_normal = a_normal;\n"
    "  v_uv = a_uv;\n"
    "  gl_Position = u_view_proj * vec4(a_pos, 1.0);\n"
    "}\n";

static const char *lc_fs =
    "#version 330 core\n"
    "in vec3 v_normal;\n"
    "in vec2 v_uv;\n"
    "uniform sampler2D u_atlas;\n"
    "uniform int u_leaves;\n"
    "uniform vec3 u_tint;\n"
    "layout(location = 0) out vec4 o_color;\n"
    "layout(location = 1) out vec4 o_normal;\n"
    "void main() {\n"
    "  vec4 c = vec4(92.0 / 255.0, 64.0 / 255.0, 44.0 / 255.0, 1.0);\n"
    "  vec3 n = normalize(v_normal);\n"
    "  if (u_leaves == 1) {\n"
    "    c = texture(u_atlas, v_uv);\n"
    "    if (c.a < 0.5) discard;\n"
    "    if (!gl_FrontFacing) n = -n;\n"
    "  }\n"
    "  o_color = vec4(c.rgb * u_tint, 1.0);\n"
    "  o_normal = vec4(n * 0.5 + 0.5, 1.0);\n"
    "}\n";

typedef struct {
  GLuint vao[2];
  size_t indices[2];
  size_t triangles;
  float coverage;
} LcLevel;

typedef struct {
  GLuint fbo, color, normal, depth;
  int side;
} LcTarget;

static void lc_target(LcTarget *t, int side) {
  if (t->fbo && t->side == side) return;
  if (!t->fbo) {
    p_glGenFramebuffers(1, &t->fbo);
    p_glGenTextures(1, &t->color);
    p_glGenTextures(1, &t->normal);
    p_glGenTextures(1, &t->depth);
  }
  t->side = side;
  p_glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
  GLuint tex[3] = {t->color, t->normal, t->depth};
  for (int k = 0; k < 3; k++) {
    p_glBindTexture(GL_TEXTURE_2D, tex[k]);
    if (k < 2)
      p_glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, side, side, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    else
      p_glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, side, side, 0, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, NULL);
    p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  p_glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->color, 0);
  p_glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, t->normal, 0);
  p_glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, t->depth, 0);
  GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  p_glDrawBuffers(2, both);
  if (p_glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) fail("lod-check framebuffer");
}

static void lc_normalize(float v[3]) {
  float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int k = 0; k < 3; k++) v[k] /= l;
}

static void lc_cross(const float a[3], const float b[3], float out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The orthographic view arbor's rasterizer draws (raster::View::looking with Y up): the
 * square of half-side `half` around `centre` seen along `forward`. */
static Mat4 lc_view(const float centre[3], const float forward_in[3], float half) {
  float f[3] = {forward_in[0], forward_in[1], forward_in[2]}, up[3] = {0, 1, 0}, r[3], u[3];
  lc_normalize(f);
  lc_cross(f, up, r);
  if (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] < 1e-8f) r[0] = 1, r[1] = 0, r[2] = 0;
  lc_normalize(r);
  lc_cross(r, f, u);
  Mat4 v;
  memset(&v, 0, sizeof v);
  v.m[0] = r[0]; v.m[4] = r[1]; v.m[8] = r[2];
  v.m[1] = u[0]; v.m[5] = u[1]; v.m[9] = u[2];
  v.m[2] = -f[0]; v.m[6] = -f[1]; v.m[10] = -f[2];
  v.m[12] = -(r[0] * centre[0] + r[1] * centre[1] + r[2] * centre[2]);
  v.m[13] = -(u[0] * centre[0] + u[1] * centre[1] + u[2] * centre[2]);
  v.m[14] = f[0] * centre[0] + f[1] * centre[1] + f[2] * centre[2];
  v.m[15] = 1;
  /* The view's depth runs from -half to half about the centre: a little more, so the
     bounding sphere's own surface is inside. */
  return mat_mul(orthographic(-half, half, -half, half, -1.01f * half, 1.01f * half), v);
}

static void lc_draw(const LcLevel *l, GLint u_leaves) {
  for (int part = 0; part < 2; part++) {
    if (!l->indices[part]) continue;
    p_glUniform1i(u_leaves, part);
    if (part == 1) p_glDisable(GL_CULL_FACE);
    else p_glEnable(GL_CULL_FACE);
    p_glBindVertexArray(l->vao[part]);
    p_glDrawElements(GL_TRIANGLES, (GLsizei)l->indices[part], GL_UNSIGNED_INT, NULL);
  }
}

/* Which of `pixels` x `pixels` pixels the level covers from `dir`: half its samples. */
static unsigned char *lc_mask(const LcLevel *l, LcTarget *t, GLint u_vp, GLint u_leaves, const float centre[3],
                              float radius, const float dir[3], int pixels) {
  int ss = 1024 / pixels < 4 ? 1024 / pixels : 4;
  if (ss < 1) ss = 1;
  int side = pixels * ss;
  lc_target(t, side);
  p_glViewport(0, 0, side, side);
  p_glClearColor(0, 0, 0, 0);
  p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  Mat4 vp = lc_view(centre, dir, radius);
  p_glUniformMatrix4fv(u_vp, 1, GL_FALSE, vp.m);
  lc_draw(l, u_leaves);
  unsigned char *rgba = malloc((size_t)side * side * 4);
  p_glReadBuffer(GL_COLOR_ATTACHMENT0);
  p_glPixelStorei(GL_PACK_ALIGNMENT, 1);
  p_glReadPixels(0, 0, side, side, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  unsigned char *mask = calloc((size_t)pixels * pixels, 1);
  for (int y = 0; y < pixels; y++)
    for (int x = 0; x < pixels; x++) {
      int n = 0;
      for (int sy = 0; sy < ss; sy++)
        for (int sx = 0; sx < ss; sx++) n += rgba[(((size_t)(y * ss + sy) * side) + x * ss + sx) * 4 + 3] > 0;
      mask[(size_t)y * pixels + x] = 2 * n >= ss * ss;
    }
  free(rgba);
  return mask;
}

static float lc_iou(const unsigned char *a, const unsigned char *b, size_t n) {
  size_t both = 0, either = 0;
  for (size_t k = 0; k < n; k++) {
    both += a[k] && b[k];
    either += a[k] || b[k];
  }
  return either ? (float)both / (float)either : 1.0f;
}

/* An RGBA8 texture on unit `unit`, filtered by `filter`, no mipmaps. */
static GLuint lc_texture(const unsigned char *rgba, int side, int unit, GLint filter) {
  GLuint t = 0;
  p_glGenTextures(1, &t);
  p_glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
  p_glBindTexture(GL_TEXTURE_2D, t);
  p_glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  p_glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, side, side, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
  p_glActiveTexture(GL_TEXTURE0);
  return t;
}

/* The reference impostor shader compiled as a host compiles it, one impostor's atlases,
 * and a field of FIELD x FIELD of its quads (instanced): a jittered grid 2.2 radii apart,
 * the first tree at the origin, unscaled. */
enum { FIELD = 20 };
typedef struct {
  GLuint prog, vao, buf[3], albedo, normal;
  GLint vp, camera, light;
  float centre[3], radius, up[3];
} ImpostorField;

/* Bakes level `level` of `lods` (12 x 12 hemi-octahedral views of 128 px) into `f`. */
static void impostor_field_build(ImpostorField *f, const ArborLods *lods, size_t level, const unsigned char *atlas,
                                 uint32_t atlas_side) {
  const int frames = 12, cell = 128;
  ArborImpostor *imp = NULL;
  if (arbor_lods_impostor_create(lods, level, (uint32_t)frames, (uint32_t)cell, 1, atlas, atlas_side, atlas_side,
                                 &imp) != ARBOR_STATUS_OK)
    fail("arbor_lods_impostor_create");
  uint32_t side = 0;
  if (arbor_impostor_info(imp, &side, f->centre, &f->radius, f->up) != ARBOR_STATUS_OK) fail("arbor_impostor_info");
  size_t bytes = (size_t)side * side * 4;
  unsigned char *a = malloc(bytes), *n = malloc(bytes);
  if (arbor_impostor_atlas_write(imp, 0, a, bytes, NULL) != ARBOR_STATUS_OK ||
      arbor_impostor_atlas_write(imp, 1, n, bytes, NULL) != ARBOR_STATUS_OK)
    fail("arbor_impostor_atlas_write");
  arbor_impostor_free(imp);
  /* The albedo filtered (the shader samples it at level 0), the depth read texel by texel. */
  f->albedo = lc_texture(a, (int)side, 4, GL_LINEAR);
  f->normal = lc_texture(n, (int)side, 5, GL_NEAREST);
  free(a);
  free(n);

  size_t len = strlen(impostor_glsl) + 64;
  char *vs = malloc(len), *fs = malloc(len);
  snprintf(vs, len, "#version 330 core\n#define VERTEX\n%s", impostor_glsl);
  snprintf(fs, len, "#version 330 core\n#define FRAGMENT\n%s", impostor_glsl);
  GLuint prog = link_program(vs, fs);
  free(vs);
  free(fs);
  f->prog = prog;
  p_glUseProgram(prog);
  p_glUniform1i(p_glGetUniformLocation(prog, "albedo"), 4);
  p_glUniform1i(p_glGetUniformLocation(prog, "normal_depth"), 5);
  p_glUniform1f(p_glGetUniformLocation(prog, "frames"), (float)frames);
  p_glUniform1f(p_glGetUniformLocation(prog, "cell"), (float)cell);
  p_glUniform1i(p_glGetUniformLocation(prog, "hemi"), 1);
  p_glUniform3f(p_glGetUniformLocation(prog, "centre"), f->centre[0], f->centre[1], f->centre[2]);
  p_glUniform1f(p_glGetUniformLocation(prog, "radius"), f->radius);
  p_glUniform3f(p_glGetUniformLocation(prog, "up"), f->up[0], f->up[1], f->up[2]);
  f->vp = p_glGetUniformLocation(prog, "view_projection");
  f->camera = p_glGetUniformLocation(prog, "camera");
  f->light = p_glGetUniformLocation(prog, "light");

  /* The quad's corners (attribute 0) and one placement a tree (attribute 1, instanced). */
  static const float corners[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
  static const uint32_t quad[6] = {0, 1, 2, 0, 2, 3};
  float *place = malloc(sizeof(float) * 4 * FIELD * FIELD);
  for (int k = 0; k < FIELD * FIELD; k++) {
    float jx = (float)((k * 7919) % 13) / 13.0f - 0.5f, jz = (float)((k * 104729) % 17) / 17.0f - 0.5f;
    place[4 * k] = k == 0 ? 0.0f : ((float)(k % FIELD - FIELD / 2) + 0.9f * jx) * 2.2f * f->radius;
    place[4 * k + 1] = 0.0f;
    place[4 * k + 2] = k == 0 ? 0.0f : -((float)(k / FIELD) + 0.9f * jz) * 2.2f * f->radius;
    place[4 * k + 3] = k == 0 ? 1.0f : 0.8f + 0.4f * (float)((k * 37) % 11) / 10.0f;
  }
  p_glGenVertexArrays(1, &f->vao);
  p_glBindVertexArray(f->vao);
  p_glGenBuffers(3, f->buf);
  p_glBindBuffer(GL_ARRAY_BUFFER, f->buf[0]);
  p_glBufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
  p_glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
  p_glEnableVertexAttribArray(0);
  p_glBindBuffer(GL_ARRAY_BUFFER, f->buf[1]);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 4 * FIELD * FIELD), place, GL_STATIC_DRAW);
  p_glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 0, NULL);
  p_glEnableVertexAttribArray(1);
  p_glVertexAttribDivisor(1, 1);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, f->buf[2]);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  free(place);
}

/* Draws the first `count` impostors of `f` seen through `vp` from `eye`, lit from `light`
 * (NULL: unlit), both sides of the quads. Leaves f's program bound. */
static void impostor_field_draw(const ImpostorField *f, const Mat4 *vp, const float eye[3], const float *light,
                                int count) {
  p_glUseProgram(f->prog);
  p_glUniformMatrix4fv(f->vp, 1, GL_FALSE, vp->m);
  p_glUniform3f(f->camera, eye[0], eye[1], eye[2]);
  p_glUniform3f(f->light, light ? light[0] : 0.0f, light ? light[1] : 0.0f, light ? light[2] : 0.0f);
  p_glDisable(GL_CULL_FACE);
  p_glBindVertexArray(f->vao);
  p_glDrawElementsInstanced(GL_TRIANGLES, 6, GL_UNSIGNED_INT, NULL, count);
}

static void impostor_field_free(ImpostorField *f) {
  p_glDeleteVertexArrays(1, &f->vao);
  p_glDeleteBuffers(3, f->buf);
  p_glDeleteTextures(1, &f->albedo);
  p_glDeleteTextures(1, &f->normal);
  p_glDeleteProgram(f->prog);
}

/* Part 3: the full tree's impostor drawn by the reference shader against the full tree
 * drawn by OpenGL, and a field of them. */
static void lc_impostor(const ArborLods *lods, const unsigned char *atlas, uint32_t atlas_side, const LcLevel *full,
                        LcTarget *target, GLint u_vp, GLint u_leaves, GLuint level_prog, const char *shot) {
  const int frames = 12, cell = 128, pixels = 96;
  ImpostorField f;
  impostor_field_build(&f, lods, 0, atlas, atlas_side);
  const float *centre = f.centre, radius = f.radius;

  /* 16 directions from level to 60 degrees up, none a baked view's (tests/impostor.rs). */
  float sum = 0, least = 1;
  p_glDisable(GL_CULL_FACE);
  for (int k = 0; k < 16; k++) {
    float turn = 6.2831853f * fmodf((float)k * 0.618034f, 1.0f) + 0.05f;
    float e = ((float)k / 15.0f) * 1.0471976f;
    float d[3] = {cosf(turn) * cosf(e), sinf(e), sinf(turn) * cosf(e)};
    float forward[3] = {-d[0], -d[1], -d[2]};
    p_glUseProgram(level_prog);
    unsigned char *m0 = lc_mask(full, target, u_vp, u_leaves, centre, radius, forward, pixels);
    /* The impostor: one sample a pixel (the shader's alpha test is the coverage). */
    lc_target(target, pixels);
    p_glViewport(0, 0, pixels, pixels);
    p_glClearColor(0, 0, 0, 0);
    p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    Mat4 vp = lc_view(centre, forward, radius);
    float camera[3] = {centre[0] + d[0] * 1e4f * radius, centre[1] + d[1] * 1e4f * radius,
                       centre[2] + d[2] * 1e4f * radius};
    impostor_field_draw(&f, &vp, camera, NULL, 1);
    unsigned char *rgba = malloc((size_t)pixels * pixels * 4), *m1 = malloc((size_t)pixels * pixels);
    p_glReadBuffer(GL_COLOR_ATTACHMENT0);
    p_glPixelStorei(GL_PACK_ALIGNMENT, 1);
    p_glReadPixels(0, 0, pixels, pixels, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    for (int i = 0; i < pixels * pixels; i++) m1[i] = rgba[4 * i + 3] > 0;
    float w = lc_iou(m0, m1, (size_t)pixels * pixels);
    sum += w;
    least = fminf(least, w);
    free(rgba);
    free(m0);
    free(m1);
  }
  printf("lod-check: impostor: the full tree's, %d x %d views of %d px, by examples/common/impostor.glsl at %d px "
         "from 16 other directions: OpenGL IoU %.3f (least %.3f)\n",
         frames, frames, cell, pixels, (double)(sum / 16.0f), (double)least);

  /* The field: 400 impostors seen in perspective, 1024 x 576, best of three. */
  const int fw = 1024, fh = 576;
  lc_target(target, fw);
  p_glViewport(0, 0, fw, fh);
  float eye[3] = {0.0f, 3.0f * radius, 6.0f * radius}, look[3] = {0.0f, radius, -10.0f * radius};
  Mat4 field = mat_mul(perspective(0.9f, (float)fw / (float)fh, 0.5f * radius, 200.0f * radius),
                       look_at(eye, look));
  double best = 1e30;
  size_t covered = 0;
  for (int run = 0; run < 3; run++) {
    p_glFinish();
    double t0 = now_ms();
    p_glClearColor(0, 0, 0, 0);
    p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    impostor_field_draw(&f, &field, eye, NULL, FIELD * FIELD);
    p_glFinish();
    double t1 = now_ms();
    if (t1 - t0 < best) best = t1 - t0;
  }
  unsigned char *rgba = malloc((size_t)fw * fh * 4);
  p_glReadBuffer(GL_COLOR_ATTACHMENT0);
  p_glReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  for (size_t i = 0; i < (size_t)fw * fh; i++) covered += rgba[4 * i + 3] > 0;
  free(rgba);
  if (shot) {
    /* The picture: the field lit from the upper left, over a sky and a ground. */
    p_glClearColor(0.62f, 0.74f, 0.86f, 0.0f);
    p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    ArborVertex g[4];
    uint32_t gi[6];
    ground_square(0.0f, -12.0f * radius, 40.0f * radius, g, gi);
    GLuint gvao = vertex_array(g, 4, gi, 6, NULL, NULL);
    p_glUseProgram(level_prog);
    p_glUniformMatrix4fv(u_vp, 1, GL_FALSE, field.m);
    p_glUniform1i(u_leaves, 0);
    /* The bark's brown turned to a grass's olive. */
    GLint tint = p_glGetUniformLocation(level_prog, "u_tint");
    p_glUniform3f(tint, 0.8f, 1.45f, 0.55f);
    p_glDisable(GL_CULL_FACE);
    p_glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_INT, NULL);
    p_glUniform3f(tint, 1.0f, 1.0f, 1.0f);
    p_glDeleteVertexArrays(1, &gvao);
    const float light[3] = {-0.5f, 0.8f, 0.4f};
    impostor_field_draw(&f, &field, eye, light, FIELD * FIELD);
    if (!save_image(shot, fw, fh)) fail("the screenshot");
    printf("lod-check: impostor field written to %s\n", shot);
  }
  printf("lod-check: impostor field: %d impostors drawn by the reference shader at %d x %d in %.1f ms (%s), "
         "%.1f%% of the pixels covered\n",
         FIELD * FIELD, fw, fh, best, (const char *)p_glGetString(GL_RENDERER),
         100.0 * (double)covered / (double)(fw * fh));
  impostor_field_free(&f);
  p_glUseProgram(level_prog);
}

/* A species' chain of levels (arbor_tree_lods_create, defaults) with its leaves alpha-tested
 * against its `atlas_side`-square leaf atlas, which *atlas gets (free it). */
static ArborLods *species_lods(uint32_t species, uint32_t atlas_side, unsigned char **atlas) {
  ArborTree *tree = NULL;
  if (arbor_tree_from_species(species, 1, &tree) != ARBOR_STATUS_OK) fail("arbor_tree_from_species");
  ArborMeshOptions o = arbor_mesh_options_default();
  ArborLeafOptions lo = arbor_leaf_options_default();
  if (arbor_species_options(species, tree, &o, &lo) != ARBOR_STATUS_OK) fail("arbor_species_options");
  o.topology = ARBOR_TOPOLOGY_TRIANGLE_LIST;
  size_t atlas_bytes = (size_t)atlas_side * atlas_side * 4;
  *atlas = malloc(atlas_bytes);
  if (arbor_species_texture_write(species, ARBOR_TEXTURE_LEAF_ATLAS, atlas_side, 1, 0, *atlas, atlas_bytes) !=
      ARBOR_STATUS_OK)
    fail("arbor_species_texture_write");
  ArborLodOptions lod = arbor_lod_options_default();
  ArborLods *lods = NULL;
  if (arbor_tree_lods_create(tree, &o, &lo, *atlas, atlas_side, atlas_side, &lod, &lods) != ARBOR_STATUS_OK)
    fail("arbor_tree_lods_create");
  arbor_tree_free(tree);
  return lods;
}

static int lod_check(uint32_t species, const char *shot) {
  const uint32_t atlas_side = 256;
  unsigned char *atlas = NULL;
  double t0 = now_ms();
  ArborLods *lods = species_lods(species, atlas_side, &atlas);
  printf("lod-check: %s: chain made in %.0f ms\n", arbor_species_name(species), now_ms() - t0);

  /* The atlas as the rasterizer samples it: nearest texel, no mipmaps. */
  GLuint tex = 0;
  p_glGenTextures(1, &tex);
  p_glActiveTexture(GL_TEXTURE3);
  p_glBindTexture(GL_TEXTURE_2D, tex);
  p_glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  p_glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, (GLsizei)atlas_side, (GLsizei)atlas_side, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 atlas);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  p_glActiveTexture(GL_TEXTURE0);

  GLuint prog = link_program(lc_vs, lc_fs);
  p_glUseProgram(prog);
  p_glUniform1i(p_glGetUniformLocation(prog, "u_atlas"), 3);
  p_glUniform3f(p_glGetUniformLocation(prog, "u_tint"), 1.0f, 1.0f, 1.0f);
  GLint u_vp = p_glGetUniformLocation(prog, "u_view_proj"), u_leaves = p_glGetUniformLocation(prog, "u_leaves");
  p_glEnable(GL_DEPTH_TEST);
  p_glDisable(GL_PRIMITIVE_RESTART_FIXED_INDEX);

  size_t count = arbor_lods_count(lods);
  LcLevel *levels = calloc(count, sizeof *levels);
  float lo_box[3] = {1e30f, 1e30f, 1e30f}, hi_box[3] = {-1e30f, -1e30f, -1e30f}, centre[3], radius = 0;
  ArborVertex *full[2] = {NULL, NULL};
  size_t full_n[2] = {0, 0};
  for (size_t k = 0; k < count; k++) {
    float silhouette = 0;
    if (arbor_lods_level_info(lods, k, &levels[k].coverage, &silhouette, &levels[k].triangles) != ARBOR_STATUS_OK)
      fail("arbor_lods_level_info");
    for (uint32_t part = 0; part < 2; part++) {
      size_t nv = 0, ni = 0;
      if (arbor_lods_mesh_write(lods, k, part, NULL, 0, NULL, 0, &nv, &ni) != ARBOR_STATUS_OK) fail("lods size");
      ArborVertex *v = malloc((nv ? nv : 1) * sizeof *v);
      uint32_t *ix = malloc((ni ? ni : 1) * sizeof *ix);
      if (arbor_lods_mesh_write(lods, k, part, v, nv, ix, ni, NULL, NULL) != ARBOR_STATUS_OK) fail("lods write");
      levels[k].vao[part] = vertex_array(v, nv, ix, ni, NULL, NULL);
      levels[k].indices[part] = ni;
      free(ix);
      if (k == 0) full[part] = v, full_n[part] = nv;
      else free(v);
    }
  }
  /* The full tree's frame (lod::Frame): its box's middle, the farthest vertex from it,
     its height along Y. */
  for (int part = 0; part < 2; part++)
    for (size_t i = 0; i < full_n[part]; i++)
      for (int c = 0; c < 3; c++) {
        lo_box[c] = fminf(lo_box[c], full[part][i].position[c]);
        hi_box[c] = fmaxf(hi_box[c], full[part][i].position[c]);
      }
  for (int c = 0; c < 3; c++) centre[c] = 0.5f * (lo_box[c] + hi_box[c]);
  for (int part = 0; part < 2; part++) {
    for (size_t i = 0; i < full_n[part]; i++) {
      const float *p = full[part][i].position;
      float d = (p[0] - centre[0]) * (p[0] - centre[0]) + (p[1] - centre[1]) * (p[1] - centre[1]) +
                (p[2] - centre[2]) * (p[2] - centre[2]);
      if (d > radius) radius = d;
    }
    free(full[part]);
  }
  radius = sqrtf(radius);
  float height = hi_box[1] - lo_box[1];

  LcTarget target = {0, 0, 0, 0, 0};
  p_glBindFramebuffer(GL_FRAMEBUFFER, 0);
  static const float lift[4] = {-0.15f, 0.0f, 0.2f, 0.35f};
  for (size_t k = 1; k < count; k++) {
    float c = levels[k - 1].coverage;
    int pixels = (int)lroundf(c * 1080.0f * 2.0f * radius / height);
    if (pixels < 8) pixels = 8;
    if (pixels > 4096) pixels = 4096;
    float sum = 0, least = 1;
    for (int d = 0; d < 8; d++) {
      float a = 6.2831853f * ((float)d + 0.37f) / 8.0f;
      float dir[3] = {cosf(a), lift[d % 4], sinf(a)};
      lc_normalize(dir);
      unsigned char *m0 = lc_mask(&levels[0], &target, u_vp, u_leaves, centre, radius, dir, pixels);
      unsigned char *mk = lc_mask(&levels[k], &target, u_vp, u_leaves, centre, radius, dir, pixels);
      float w = lc_iou(m0, mk, (size_t)pixels * pixels);
      sum += w;
      least = fminf(least, w);
      free(m0);
      free(mk);
    }
    printf("lod-check: %s level %zu: %.1f%% of %zu triangles, first drawn at coverage %.3f (%d px): "
           "OpenGL IoU %.3f (least %.3f)\n",
           arbor_species_name(species), k, 100.0 * (double)levels[k].triangles / (double)levels[0].triangles,
           levels[0].triangles, (double)c, pixels, (double)(sum / 8.0f), (double)least);
  }

  /* The baker: arbor's 144 views against OpenGL's, of the level the impostor is baked
   * from (the coarsest made for views of its cells' size). */
  const int frames = 12, cell = 128, side = 3 * cell;
  size_t src = arbor_lods_impostor_level(lods, (uint32_t)cell);
  double best_arbor = 1e30, best_gl = 1e30;
  size_t bytes = (size_t)side * side * 4;
  unsigned char *albedo = malloc(bytes * (size_t)(frames * frames)), *normal = malloc(bytes * (size_t)(frames * frames));
  memset(albedo, 1, bytes * (size_t)(frames * frames)); /* prefaulted with a non-zero byte */
  memset(normal, 1, bytes * (size_t)(frames * frames));
  size_t atlas_out = (size_t)(frames * cell) * (size_t)(frames * cell) * 4;
  unsigned char *imp_albedo = malloc(atlas_out), *imp_normal = malloc(atlas_out);
  memset(imp_albedo, 1, atlas_out);
  memset(imp_normal, 1, atlas_out);
  for (int run = 0; run < 3; run++) {
    double a0 = now_ms();
    ArborImpostor *imp = NULL;
    if (arbor_lods_impostor_create(lods, src, (uint32_t)frames, (uint32_t)cell, 1, atlas, atlas_side, atlas_side,
                                   &imp) != ARBOR_STATUS_OK)
      fail("arbor_lods_impostor_create");
    if (arbor_impostor_atlas_write(imp, 0, imp_albedo, atlas_out, NULL) != ARBOR_STATUS_OK ||
        arbor_impostor_atlas_write(imp, 1, imp_normal, atlas_out, NULL) != ARBOR_STATUS_OK)
      fail("arbor_impostor_atlas_write");
    double a1 = now_ms();
    arbor_impostor_free(imp);
    if (a1 - a0 < best_arbor) best_arbor = a1 - a0;

    p_glFinish();
    double g0 = now_ms();
    lc_target(&target, side);
    p_glViewport(0, 0, side, side);
    p_glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int j = 0; j < frames; j++)
      for (int i = 0; i < frames; i++) {
        /* The hemi-octahedral grid's direction of cell (i, j) (docs/meshes.md). */
        float qx = 2.0f * ((float)i + 0.5f) / (float)frames - 1.0f, qy = 2.0f * ((float)j + 0.5f) / (float)frames - 1.0f;
        float tx = 0.5f * (qx + qy), ty = 0.5f * (qx - qy);
        float d[3] = {tx, 1.0f - fabsf(tx) - fabsf(ty), ty};
        lc_normalize(d);
        float forward[3] = {-d[0], -d[1], -d[2]};
        p_glClearColor(0, 0, 0, 0);
        p_glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        Mat4 vp = lc_view(centre, forward, radius);
        p_glUniformMatrix4fv(u_vp, 1, GL_FALSE, vp.m);
        lc_draw(&levels[src], u_leaves);
        size_t at = bytes * (size_t)(j * frames + i);
        p_glReadBuffer(GL_COLOR_ATTACHMENT0);
        p_glReadPixels(0, 0, side, side, GL_RGBA, GL_UNSIGNED_BYTE, albedo + at);
        p_glReadBuffer(GL_COLOR_ATTACHMENT1);
        p_glReadPixels(0, 0, side, side, GL_RGBA, GL_UNSIGNED_BYTE, normal + at);
      }
    p_glFinish();
    double g1 = now_ms();
    if (g1 - g0 < best_gl) best_gl = g1 - g0;
  }
  size_t drawn = 0;
  for (size_t k = 3; k < atlas_out; k += 4) drawn += imp_albedo[k] > 0;
  size_t gl_drawn = 0;
  for (size_t k = 3; k < bytes * (size_t)(frames * frames); k += 4) gl_drawn += albedo[k] > 0;
  printf("lod-check: %s baker: level %zu (%zu triangles), %d x %d views at %d x %d samples: arbor %.0f ms "
         "(%zu texels covered), OpenGL (%s) %.0f ms (%zu samples covered); arbor/OpenGL %.2f\n",
         arbor_species_name(species), src, levels[src].triangles, frames, frames, side, side, best_arbor, drawn,
         (const char *)p_glGetString(GL_RENDERER), best_gl, gl_drawn, best_arbor / best_gl);
  free(albedo);
  free(normal);
  free(imp_albedo);
  free(imp_normal);
  lc_impostor(lods, atlas, atlas_side, &levels[0], &target, u_vp, u_leaves, prog, shot);
  free(atlas);
  free(levels);
  arbor_lods_free(lods);
  p_glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return 0;
}
