/*
 * What arbor's example programs (the gallery, the ray marcher, the editor, the studio)
 * share: the OpenGL functions they call, loaded with glfwGetProcAddress; the window;
 * column-major matrices; shader compilation; ArborVertex's attribute layout and the leaf
 * quad; a shadow map; the screenshot (PNG with libpng, or PPM) read back with
 * glReadPixels; a clock and the error exit. Header-only, C11 or C++17: each program
 * includes it once, after <GLFW/glfw3.h>, <GL/glcorearb.h> and "arbor.h" (with
 * _POSIX_C_SOURCE or _DEFAULT_SOURCE defined for clock_gettime), and sets `glapp_name`
 * for its messages.
 */
#ifndef ARBOR_EXAMPLES_GLAPP_H
#define ARBOR_EXAMPLES_GLAPP_H

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The program's name in messages ("gallery: ..."). */
static const char *glapp_name = "arbor";

/* Milliseconds on a monotonic clock. */
static inline double now_ms(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

/* Exits with arbor's message for the failed call `what`. */
static inline void fail(const char *what) {
  char msg[512];
  arbor_last_error_message(msg, sizeof msg);
  fprintf(stderr, "%s: %s: %s\n", glapp_name, what, msg);
  exit(1);
}

/* A window with an OpenGL `major`.`minor` core context, made current (hidden for
 * headless screenshots); exits with a message when there is none. */
static inline GLFWwindow *open_window(const char *title, int width, int height, int major, int minor, int hidden) {
  if (!glfwInit()) {
    fprintf(stderr, "%s: glfwInit failed (no display? try xvfb-run -a)\n", glapp_name);
    exit(1);
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, major);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, minor);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
  glfwWindowHint(GLFW_SAMPLES, hidden ? 0 : 4); /* screenshots compare exact pixels */
  if (hidden) glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
  GLFWwindow *win = glfwCreateWindow(width, height, title, NULL, NULL);
  if (!win) {
    fprintf(stderr, "%s: no OpenGL %d.%d core context\n", glapp_name, major, minor);
    glfwTerminate();
    exit(1);
  }
  glfwMakeContextCurrent(win);
  return win;
}

#define GLAPP_FUNCTIONS(X)                                                 \
  X(PFNGLCREATESHADERPROC, glCreateShader)                                 \
  X(PFNGLSHADERSOURCEPROC, glShaderSource)                                 \
  X(PFNGLCOMPILESHADERPROC, glCompileShader)                               \
  X(PFNGLGETSHADERIVPROC, glGetShaderiv)                                   \
  X(PFNGLGETSHADERINFOLOGPROC, glGetShaderInfoLog)                         \
  X(PFNGLCREATEPROGRAMPROC, glCreateProgram)                               \
  X(PFNGLATTACHSHADERPROC, glAttachShader)                                 \
  X(PFNGLLINKPROGRAMPROC, glLinkProgram)                                   \
  X(PFNGLGETPROGRAMIVPROC, glGetProgramiv)                                 \
  X(PFNGLGETPROGRAMINFOLOGPROC, glGetProgramInfoLog)                       \
  X(PFNGLDELETEPROGRAMPROC, glDeleteProgram)                               \
  X(PFNGLUSEPROGRAMPROC, glUseProgram)                                     \
  X(PFNGLGETUNIFORMLOCATIONPROC, glGetUniformLocation)                     \
  X(PFNGLUNIFORMMATRIX4FVPROC, glUniformMatrix4fv)                         \
  X(PFNGLUNIFORM1IPROC, glUniform1i)                                       \
  X(PFNGLUNIFORM3FPROC, glUniform3f)                                       \
  X(PFNGLUNIFORM1FPROC, glUniform1f)                                       \
  X(PFNGLGENVERTEXARRAYSPROC, glGenVertexArrays)                           \
  X(PFNGLDELETEVERTEXARRAYSPROC, glDeleteVertexArrays)                     \
  X(PFNGLBINDVERTEXARRAYPROC, glBindVertexArray)                           \
  X(PFNGLGENBUFFERSPROC, glGenBuffers)                                     \
  X(PFNGLDELETEBUFFERSPROC, glDeleteBuffers)                               \
  X(PFNGLBINDBUFFERPROC, glBindBuffer)                                     \
  X(PFNGLBINDBUFFERBASEPROC, glBindBufferBase)                             \
  X(PFNGLBUFFERDATAPROC, glBufferData)                                     \
  X(PFNGLBUFFERSUBDATAPROC, glBufferSubData)                               \
  X(PFNGLGETBUFFERSUBDATAPROC, glGetBufferSubData)                         \
  X(PFNGLMAPBUFFERRANGEPROC, glMapBufferRange)                             \
  X(PFNGLUNMAPBUFFERPROC, glUnmapBuffer)                                   \
  X(PFNGLVERTEXATTRIBPOINTERPROC, glVertexAttribPointer)                   \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, glEnableVertexAttribArray)           \
  X(PFNGLDISABLEVERTEXATTRIBARRAYPROC, glDisableVertexAttribArray)         \
  X(PFNGLVERTEXATTRIBDIVISORPROC, glVertexAttribDivisor)                   \
  X(PFNGLDRAWARRAYSPROC, glDrawArrays)                                     \
  X(PFNGLDRAWARRAYSINSTANCEDPROC, glDrawArraysInstanced)                   \
  X(PFNGLDRAWELEMENTSPROC, glDrawElements)                                 \
  X(PFNGLDRAWELEMENTSINSTANCEDPROC, glDrawElementsInstanced)               \
  X(PFNGLGENTEXTURESPROC, glGenTextures)                                   \
  X(PFNGLDELETETEXTURESPROC, glDeleteTextures)                             \
  X(PFNGLBINDTEXTUREPROC, glBindTexture)                                   \
  X(PFNGLACTIVETEXTUREPROC, glActiveTexture)                               \
  X(PFNGLTEXIMAGE2DPROC, glTexImage2D)                                     \
  X(PFNGLTEXPARAMETERIPROC, glTexParameteri)                               \
  X(PFNGLGENERATEMIPMAPPROC, glGenerateMipmap)                             \
  X(PFNGLGENFRAMEBUFFERSPROC, glGenFramebuffers)                           \
  X(PFNGLBINDFRAMEBUFFERPROC, glBindFramebuffer)                           \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, glFramebufferTexture2D)                 \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, glCheckFramebufferStatus)             \
  X(PFNGLDRAWBUFFERPROC, glDrawBuffer)                                     \
  X(PFNGLDRAWBUFFERSPROC, glDrawBuffers)                                   \
  X(PFNGLENABLEPROC, glEnable)                                             \
  X(PFNGLDISABLEPROC, glDisable)                                           \
  X(PFNGLCULLFACEPROC, glCullFace)                                         \
  X(PFNGLCLEARCOLORPROC, glClearColor)                                     \
  X(PFNGLCLEARPROC, glClear)                                               \
  X(PFNGLVIEWPORTPROC, glViewport)                                         \
  X(PFNGLSCISSORPROC, glScissor)                                           \
  X(PFNGLPOLYGONMODEPROC, glPolygonMode)                                   \
  X(PFNGLREADPIXELSPROC, glReadPixels)                                     \
  X(PFNGLPIXELSTOREIPROC, glPixelStorei)                                   \
  X(PFNGLREADBUFFERPROC, glReadBuffer)                                     \
  X(PFNGLFINISHPROC, glFinish)                                             \
  X(PFNGLGETSTRINGPROC, glGetString)

#define GLAPP_DECLARE(type, name) static type p_##name;
GLAPP_FUNCTIONS(GLAPP_DECLARE)
#undef GLAPP_DECLARE

/* Loads every function of the list (a current context first); 0 when one is missing. */
static inline int load_gl(void) {
#define GLAPP_LOAD(type, name)                                                       \
  p_##name = (type)glfwGetProcAddress(#name);                                        \
  if (!p_##name) {                                                                   \
    fprintf(stderr, "%s: OpenGL function %s is missing\n", glapp_name, #name);       \
    return 0;                                                                        \
  }
  GLAPP_FUNCTIONS(GLAPP_LOAD)
#undef GLAPP_LOAD
  return 1;
}

/* ---- small matrix helpers (column-major, as OpenGL) ---- */
typedef struct { float m[16]; } Mat4;

static inline Mat4 mat_mul(Mat4 a, Mat4 b) {
  Mat4 r;
  for (int c = 0; c < 4; c++)
    for (int row = 0; row < 4; row++) {
      float s = 0;
      for (int k = 0; k < 4; k++) s += a.m[k * 4 + row] * b.m[c * 4 + k];
      r.m[c * 4 + row] = s;
    }
  return r;
}

static inline Mat4 perspective(float fovy, float aspect, float near, float far) {
  Mat4 r;
  memset(&r, 0, sizeof r);
  float f = 1.0f / tanf(fovy / 2);
  r.m[0] = f / aspect;
  r.m[5] = f;
  r.m[10] = (far + near) / (near - far);
  r.m[11] = -1;
  r.m[14] = 2 * far * near / (near - far);
  return r;
}

/* An orthographic projection of the box [l, r] x [b, t] x [-n, -f] (view space). */
static inline Mat4 orthographic(float l, float r, float b, float t, float n, float f) {
  Mat4 m;
  memset(&m, 0, sizeof m);
  m.m[0] = 2 / (r - l);
  m.m[5] = 2 / (t - b);
  m.m[10] = -2 / (f - n);
  m.m[12] = -(r + l) / (r - l);
  m.m[13] = -(t + b) / (t - b);
  m.m[14] = -(f + n) / (f - n);
  m.m[15] = 1;
  return m;
}

static inline Mat4 look_at(const float eye[3], const float at[3]) {
  float f[3] = {at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]};
  float fl = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  for (int i = 0; i < 3; i++) f[i] /= fl;
  float up[3] = {0, 1, 0};
  if (fabsf(f[1]) > 0.999f) up[1] = 0, up[2] = 1; /* looking straight down or up */
  float s[3] = {f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2], f[0] * up[1] - f[1] * up[0]};
  float sl = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  for (int i = 0; i < 3; i++) s[i] /= sl;
  float u[3] = {s[1] * f[2] - s[2] * f[1], s[2] * f[0] - s[0] * f[2], s[0] * f[1] - s[1] * f[0]};
  Mat4 r;
  memset(&r, 0, sizeof r);
  r.m[0] = s[0]; r.m[4] = s[1]; r.m[8] = s[2];
  r.m[1] = u[0]; r.m[5] = u[1]; r.m[9] = u[2];
  r.m[2] = -f[0]; r.m[6] = -f[1]; r.m[10] = -f[2];
  r.m[12] = -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
  r.m[13] = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
  r.m[14] = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
  r.m[15] = 1;
  return r;
}

static inline Mat4 model_matrix(float x, float z, float yaw, float scale) {
  Mat4 r;
  memset(&r, 0, sizeof r);
  float c = cosf(yaw) * scale, s = sinf(yaw) * scale;
  r.m[0] = c; r.m[2] = -s;
  r.m[5] = scale;
  r.m[8] = s; r.m[10] = c;
  r.m[12] = x; r.m[14] = z; r.m[15] = 1;
  return r;
}

/* ---- orbit camera ---- */
/* A drag of the orbit camera from (*from_x, *from_y) to (x, y): yaw and pitch turn 0.01
 * radian a pixel, pitch stays within lo..hi, and the drag goes on from (x, y). */
static inline void orbit_drag(float *yaw, float *pitch, double *from_x, double *from_y,
                              double x, double y, float lo, float hi) {
  *yaw -= (float)(x - *from_x) * 0.01f;
  *pitch = fmaxf(lo, fminf(hi, *pitch + (float)(y - *from_y) * 0.01f));
  *from_x = x;
  *from_y = y;
}

/* The orbit camera's distance factor after a scroll of dy: 10% a notch, within 0.2..8. */
static inline float orbit_zoom(float zoom, double dy) {
  return fmaxf(0.2f, fminf(8.0f, zoom * (dy > 0 ? 1.1f : 1 / 1.1f)));
}

/* ---- shaders ---- */
static inline GLuint compile(GLenum kind, const char *src) {
  GLuint s = p_glCreateShader(kind);
  p_glShaderSource(s, 1, &src, NULL);
  p_glCompileShader(s);
  GLint ok = 0;
  p_glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048];
    p_glGetShaderInfoLog(s, sizeof log, NULL, log);
    fprintf(stderr, "%s: shader: %s\n", glapp_name, log);
    exit(1);
  }
  return s;
}

/* A program of a vertex and a fragment shader; exits with the log when it does not link. */
static inline GLuint link_program(const char *vs_src, const char *fs_src) {
  GLuint vs = compile(GL_VERTEX_SHADER, vs_src), fs = compile(GL_FRAGMENT_SHADER, fs_src);
  GLuint program = p_glCreateProgram();
  p_glAttachShader(program, vs);
  p_glAttachShader(program, fs);
  p_glLinkProgram(program);
  GLint linked = 0;
  p_glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!linked) {
    char log[2048];
    p_glGetProgramInfoLog(program, sizeof log, NULL, log);
    fprintf(stderr, "%s: link: %s\n", glapp_name, log);
    exit(1);
  }
  return program;
}

/* ---- arbor's vertices ---- */
/* ArborVertex as attributes 0 (position), 1 (normal) and 2 (uv) of the bound buffer. */
static inline void vertex_layout(void) {
  GLsizei s = (GLsizei)sizeof(ArborVertex);
  p_glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, s, (void *)offsetof(ArborVertex, position));
  p_glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, s, (void *)offsetof(ArborVertex, normal));
  p_glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, s, (void *)offsetof(ArborVertex, uv));
  for (GLuint k = 0; k < 3; k++) p_glEnableVertexAttribArray(k);
}

/* A vertex array holding `n` ArborVertex and `m` indices (GL_STATIC_DRAW), laid out by
 * vertex_layout(); its buffers go to *vbo and *ebo when those are not NULL. Left bound, so
 * a caller can add attributes (leaf instances) to it. */
static inline GLuint vertex_array(const ArborVertex *v, size_t n, const uint32_t *ix, size_t m, GLuint *vbo,
                                  GLuint *ebo) {
  GLuint vao, buffers[2];
  p_glGenVertexArrays(1, &vao);
  p_glBindVertexArray(vao);
  p_glGenBuffers(2, buffers);
  p_glBindBuffer(GL_ARRAY_BUFFER, buffers[0]);
  p_glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(n * sizeof *v), v, GL_STATIC_DRAW);
  p_glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[1]);
  p_glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(m * sizeof *ix), ix, GL_STATIC_DRAW);
  vertex_layout();
  if (vbo) *vbo = buffers[0];
  if (ebo) *ebo = buffers[1];
  return vao;
}

/* A square of half-side `r` at y = 0 around (cx, cz), facing up: 4 vertices, 6 indices. */
static inline void ground_square(float cx, float cz, float r, ArborVertex g[4], uint32_t gi[6]) {
  static const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  static const uint32_t order[6] = {0, 2, 1, 0, 3, 2};
  memset(g, 0, 4 * sizeof *g);
  for (int k = 0; k < 4; k++) {
    g[k].position[0] = cx + r * corners[k][0];
    g[k].position[2] = cz + r * corners[k][1];
    g[k].normal[1] = 1;
  }
  memcpy(gi, order, sizeof order);
}

/* The quad an ArborLeafInstance places: leaf space, +Y along the blade, +Z its face. */
static inline void leaf_quad(ArborVertex q[4], uint32_t qi[6]) {
  static const float corners[4][2] = {{-0.25f, 0}, {0.25f, 0}, {0.25f, 1}, {-0.25f, 1}};
  static const uint32_t order[6] = {0, 1, 2, 0, 2, 3};
  memset(q, 0, 4 * sizeof *q);
  for (int k = 0; k < 4; k++) {
    q[k].position[0] = corners[k][0];
    q[k].position[1] = corners[k][1];
    q[k].normal[2] = 1;
    /* The whole leaf cell: u across, v from the stem. */
    q[k].uv[0] = corners[k][0] * 2 + 0.5f;
    q[k].uv[1] = corners[k][1];
  }
  memcpy(qi, order, sizeof order);
}

/* ---- shadows ---- */
/* A shadow map: a size x size depth texture (32-bit float, nearest, clamped to its edge)
 * as the only attachment of a framebuffer that draws no colour. Writes the texture to
 * *tex and returns the framebuffer, the default one bound again; exits with a message when
 * the framebuffer is incomplete. */
static inline GLuint shadow_map(int size, GLuint *tex) {
  p_glGenTextures(1, tex);
  p_glBindTexture(GL_TEXTURE_2D, *tex);
  p_glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, size, size, 0, GL_DEPTH_COMPONENT, GL_FLOAT, NULL);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  GLuint fbo = 0;
  p_glGenFramebuffers(1, &fbo);
  p_glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  p_glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, *tex, 0);
  p_glDrawBuffer(GL_NONE);
  if (p_glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    fprintf(stderr, "%s: the shadow framebuffer is incomplete\n", glapp_name);
    exit(1);
  }
  p_glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return fbo;
}

/* ---- the leaf atlas ---- */
/* Texture `which` of a named species (ARBOR_TEXTURE_LEAF_ATLAS: sprays of its blades in a
 * grid of cells, alpha-cut; ARBOR_TEXTURE_BARK_COLOR: its tiling bark), drawn by arbor into
 * memory (arbor_species_texture_write, on the calling thread) and uploaded with mipmaps on
 * texture unit `unit` (as RGBA8: the programs shade in display space); the bark repeats,
 * the atlas is clamped. Returns the texture; exits with arbor's message when it cannot be
 * drawn. */
static inline GLuint species_texture(uint32_t species, uint32_t which, uint32_t size, GLenum unit) {
  size_t bytes = (size_t)size * size * 4;
  unsigned char *rgba = (unsigned char *)malloc(bytes);
  if (!rgba) return 0;
  if (arbor_species_texture_write(species, which, size, 1, 1, rgba, bytes) != ARBOR_STATUS_OK)
    fail("species texture");
  GLuint tex = 0;
  p_glGenTextures(1, &tex);
  p_glActiveTexture(unit);
  p_glBindTexture(GL_TEXTURE_2D, tex);
  p_glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  p_glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, (GLsizei)size, (GLsizei)size, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  p_glGenerateMipmap(GL_TEXTURE_2D);
  GLint wrap = which == ARBOR_TEXTURE_LEAF_ATLAS ? GL_CLAMP_TO_EDGE : GL_REPEAT;
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, wrap);
  p_glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, wrap);
  p_glActiveTexture(GL_TEXTURE0);
  free(rgba);
  return tex;
}

/* Each leaf instance's atlas cell (arbor_leaf_cell: the cell arbor's own baked leaves
 * sample), as floats for a per-instance vertex attribute. The caller frees it. */
static inline float *leaf_cells(const ArborLeafOptions *lo, size_t n) {
  float *cells = (float *)malloc((n ? n : 1) * sizeof *cells);
  for (size_t k = 0; k < n; k++) cells[k] = (float)arbor_leaf_cell(lo, k);
  return cells;
}

/* GLSL: the atlas texel of leaf-quad uv `uv` (u across 0..1, v from the stem 0 to the
 * tip 1) in cell `cell` of the 4 x 2 grid (arbor_leaf_atlas_rect). */
#define ATLAS_GLSL                                                                     \
  "uniform sampler2D u_atlas;\n"                                                       \
  "vec4 atlas(float cell, vec2 uv) {\n"                                                \
  "  float c = mod(cell, 4.0), r = floor(cell / 4.0);\n"                               \
  "  return texture(u_atlas, vec2((c + uv.x) / 4.0, (r + uv.y) / 2.0));\n"             \
  "}\n"

/* ---- screenshots ---- */
/* Reads the w x h framebuffer back and writes it to `path`: PPM when it ends in .ppm,
 * else PNG. Returns 0 on failure (with a message). */
static inline int save_image(const char *path, int w, int h) {
  unsigned char *rgb = (unsigned char *)malloc((size_t)w * (size_t)h * 3);
  p_glFinish();
  p_glPixelStorei(GL_PACK_ALIGNMENT, 1);
  p_glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb);
  FILE *f = fopen(path, "wb");
  if (!f) {
    fprintf(stderr, "%s: cannot write %s\n", glapp_name, path);
    free(rgb);
    return 0;
  }
  size_t len = strlen(path);
  if (len > 4 && strcmp(path + len - 4, ".ppm") == 0) {
    fprintf(f, "P6\n%d %d\n255\n", w, h);
    for (int y = h - 1; y >= 0; y--) fwrite(rgb + (size_t)y * (size_t)w * 3, 1, (size_t)w * 3, f);
  } else {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
      fprintf(stderr, "%s: libpng failed on %s\n", glapp_name, path);
      fclose(f);
      free(rgb);
      return 0;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = h - 1; y >= 0; y--) png_write_row(png, rgb + (size_t)y * (size_t)w * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
  }
  fclose(f);
  free(rgb);
  printf("%s: wrote %s (%dx%d)\n", glapp_name, path, w, h);
  return 1;
}

#endif /* ARBOR_EXAMPLES_GLAPP_H */
