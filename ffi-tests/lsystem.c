/* Trees from grammar text through the C ABI: growth, options, parse errors with their
 * position, bytes that are not UTF-8, limits and NULLs. */
#include <sys/stat.h>
#include "arbor.h"
#include "check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *honda_g =
    "/* tree g of the 1996 paper */\n"
    "#define r1 0.80\n#define r2 0.80\n#define a1 30\n#define a2 -30\n"
    "#define p1 137\n#define p2 137\n#define w0 30\n#define q 0.50\n#define e 0.50\n"
    "#define min 0.0\n"
    "Lsystem: 1\n"
    "derivation length: 10\n"
    "Axiom: A(100,w0)\n"
    "A(s,w) : s >= min --> !(w)F(s)[+(a1)/(p1)A(s*r1,w*q^e)][+(a2)/(p2)A(s*r2,w*(1-q)^e)]\n"
    "endlsystem\n";

static void message_contains(const char *needle) {
  char m[512];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, needle) != NULL, "message '%s' lacks '%s'", m, needle);
}

static void grows_like_the_direct_model(void) {
  ArborTree *from_text = NULL, *direct = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(honda_g, strlen(honda_g), NULL, &from_text),
               ARBOR_STATUS_OK);
  ArborHondaParams p;
  arbor_honda_preset('g', &p);
  CHECK_STATUS(arbor_tree_from_honda(&p, &direct), ARBOR_STATUS_OK);
  size_t n = arbor_tree_branch_count(from_text);
  CHECK(n == 1023 && n == arbor_tree_branch_count(direct), "%zu branches", n);
  ArborBranch *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
  CHECK_STATUS(arbor_tree_copy_branches(from_text, a, n), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_tree_copy_branches(direct, b, n), ARBOR_STATUS_OK);
  for (size_t i = 0; i < n; i++) {
    float d = 0;
    for (int k = 0; k < 3; k++) {
      float x = a[i].end[k] - b[i].end[k];
      d += x * x;
    }
    if (!(d < 1e-4f) || a[i].parent != b[i].parent || a[i].order != b[i].order) {
      CHECK(0, "branch %zu differs", i);
      break;
    }
  }
  /* The mesh path works the same for grammar trees. */
  size_t nv, ni;
  CHECK_STATUS(arbor_mesh_size(from_text, NULL, &nv, &ni), ARBOR_STATUS_OK);
  CHECK(nv > n * 9 && ni == n * 48, "%zu vertices, %zu indices", nv, ni);
  free(a);
  free(b);
  arbor_tree_free(from_text);
  arbor_tree_free(direct);
}

static void options_apply(void) {
  const char *g = "Axiom: F\nF --> F[+F]F\nderivation length: 3\n";
  ArborLsystemOptions o = arbor_lsystem_options_default();
  CHECK(o.steps < 0 && o.override_flags == 0 && o.max_modules > 0, "defaults");
  ArborTree *t = NULL;
  o.steps = 2; /* 3^2 F's instead of 3^3 */
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), &o, &t), ARBOR_STATUS_OK);
  CHECK(arbor_tree_branch_count(t) == 9, "%zu", arbor_tree_branch_count(t));
  arbor_tree_free(t);
  t = NULL;
  o.override_flags = ARBOR_OVERRIDE_INITIAL_WIDTH;
  o.initial_width = 6.0f;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), &o, &t), ARBOR_STATUS_OK);
  ArborBranch b[9];
  CHECK_STATUS(arbor_tree_copy_branches(t, b, 9), ARBOR_STATUS_OK);
  CHECK(b[0].start_radius == 3.0f, "radius %f", b[0].start_radius);
  arbor_tree_free(t);
  t = NULL;
  o.override_flags = 64;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), &o, &t), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("override_flags");
  o = arbor_lsystem_options_default();
  o.steps = 40;
  o.max_modules = 1000;
  const char *bomb = "Axiom: F\nF --> FF\n";
  CHECK_STATUS(arbor_tree_from_lsystem(bomb, strlen(bomb), &o, &t), ARBOR_STATUS_LIMIT_EXCEEDED);
  message_contains("max_modules");
  message_contains("step 10");
  CHECK(t == NULL, "out written on failure");
}

static void parse_errors(void) {
  ArborTree *t = NULL;
  const char *bad = "Axiom: F\nF(x) --> F(x +* 2)\n";
  CHECK_STATUS(arbor_tree_from_lsystem(bad, strlen(bad), NULL, &t), ARBOR_STATUS_PARSE_ERROR);
  message_contains("line 2, column 15");
  message_contains("found `*`");
  const char *unsupported = "Axiom: F\nF --> F(vvXmin(1))\n";
  CHECK_STATUS(arbor_tree_from_lsystem(unsupported, strlen(unsupported), NULL, &t),
               ARBOR_STATUS_PARSE_ERROR);
  message_contains("`vvXmin()` needs cpfg's viewer");
  const char not_utf8[] = "Axiom: F\nF --> G\xff\n";
  CHECK_STATUS(arbor_tree_from_lsystem(not_utf8, sizeof not_utf8 - 1, NULL, &t),
               ARBOR_STATUS_PARSE_ERROR);
  message_contains("line 2, column 8");
  message_contains("0xff");
  /* Only source_len bytes are read: a prefix of a valid text is a text of its own. */
  const char *g = "Axiom: F\nF --> FF\nderivation length: 2\nthis line is cut off";
  size_t len = strlen(g) - strlen("this line is cut off");
  CHECK_STATUS(arbor_tree_from_lsystem(g, len, NULL, &t), ARBOR_STATUS_OK);
  CHECK(arbor_tree_branch_count(t) == 4, "%zu", arbor_tree_branch_count(t));
  arbor_tree_free(t);
  t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(NULL, 0, NULL, &t), ARBOR_STATUS_PARSE_ERROR);
  message_contains("Axiom");
  CHECK_STATUS(arbor_tree_from_lsystem(NULL, 5, NULL, &t), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_tree_from_lsystem(g, len, NULL, NULL), ARBOR_STATUS_NULL_ARGUMENT);
  CHECK_STATUS(arbor_tree_from_lsystem(g, (size_t)1 << 40, NULL, &t),
               ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("source_len");
  CHECK(t == NULL, "out written on failure");
}

static void write_file(const char *dir, const char *name, const char *text) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  FILE *f = fopen(path, "w");
  CHECK(f != NULL, "cannot write %s", path);
  if (f) {
    fputs(text, f);
    fclose(f);
  }
}

/* The direction of branch i (its end minus its start). */
static void direction(const ArborTree *t, size_t i, float d[3]) {
  ArborBranch b[8];
  size_t n = arbor_tree_branch_count(t);
  CHECK(i < n && n <= 8, "%zu branches", n);
  arbor_tree_copy_branches(t, b, n);
  for (int k = 0; k < 3; k++) d[k] = b[i].end[k] - b[i].start[k];
}

static void files_as_cpfg_reads_them(const char *dir) {
  /* A grammar that includes a header, with its angle in the view file beside it. */
  write_file(dir, "cpfg_inc.h", "#define LEN(k) (2*(k))\n#define TURN +\n");
  write_file(dir, "cpfg_plant.l",
             "#include \"cpfg_inc.h\"\n// a comment, not two rolls\nLsystem: 1\n"
             "derivation length: 1\nAxiom: A\nA --> F(LEN(1))TURN F(1)\nendlsystem\n");
  write_file(dir, "cpfg_plant.v", "angle factor: 4\ninitial line width: 3 pixels\n");
  char path[1024];
  snprintf(path, sizeof path, "%s/cpfg_plant.l", dir);
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem_file(path, NULL, &t), ARBOR_STATUS_OK);
  CHECK(arbor_tree_branch_count(t) == 2, "%zu branches", arbor_tree_branch_count(t));
  float d[3];
  direction(t, 0, d);
  CHECK(d[1] > 1.99f && d[1] < 2.01f, "first branch %g long up", d[1]);
  direction(t, 1, d);
  /* angle factor 4: 90 degrees, + turns left: from +Y to -X. */
  CHECK(d[0] < -0.99f && d[1] < 0.01f && d[1] > -0.01f, "turned to (%g, %g, %g)", d[0], d[1], d[2]);
  arbor_tree_free(t);

  /* An explicit view file wins over the one beside the grammar. */
  write_file(dir, "cpfg_other.v", "angle increment: 180\n");
  char view[1024];
  snprintf(view, sizeof view, "%s/cpfg_other.v", dir);
  ArborLsystemOptions o = arbor_lsystem_options_default();
  o.view_path = view;
  CHECK_STATUS(arbor_tree_from_lsystem_file(path, &o, &t), ARBOR_STATUS_OK);
  direction(t, 1, d);
  CHECK(d[1] < -0.99f, "turned around: (%g, %g, %g)", d[0], d[1], d[2]);
  arbor_tree_free(t);

  /* A vlab object: its folder, whose specifications names the grammar and view file
     (the model: command's cpfg line), opened by the same entry point. */
  char object[1024];
  snprintf(object, sizeof object, "%s/cpfg_object", dir);
  mkdir(object, 0755);
  write_file(object, "tree.l", "derivation length: 1\nAxiom: A\nA --> F(2)+F(1)\n");
  write_file(object, "turn.v", "angle factor: 4\n");
  write_file(object, "specifications",
             "tree.l\nturn.v\nignore:\n*\nmodel:\n\tgenerate:\n\t\tcpfg tree.l turn.v\n");
  CHECK_STATUS(arbor_tree_from_lsystem_file(object, NULL, &t), ARBOR_STATUS_OK);
  direction(t, 1, d);
  CHECK(d[0] < -0.99f, "the object's view file turned it to (%g, %g, %g)", d[0], d[1], d[2]);
  arbor_tree_free(t);

  /* Text in memory with the view file's text. */
  const char *g = "derivation length: 1\nAxiom: A\nA --> F+F\n";
  o = arbor_lsystem_options_default();
  o.view_text = "angle factor: 4\n";
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), &o, &t), ARBOR_STATUS_OK);
  direction(t, 1, d);
  CHECK(d[0] < -0.99f, "view text turned to (%g, %g, %g)", d[0], d[1], d[2]);
  arbor_tree_free(t);

  /* Errors name the file: a missing grammar, a missing include. */
  t = NULL;
  snprintf(path, sizeof path, "%s/cpfg_missing.l", dir);
  CHECK_STATUS(arbor_tree_from_lsystem_file(path, NULL, &t), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("cpfg_missing.l");
  write_file(dir, "cpfg_bad.l", "Lsystem: 1\n#include \"cpfg_nowhere.h\"\nAxiom: F\n");
  snprintf(path, sizeof path, "%s/cpfg_bad.l", dir);
  CHECK_STATUS(arbor_tree_from_lsystem_file(path, NULL, &t), ARBOR_STATUS_PARSE_ERROR);
  message_contains("line 2");
  message_contains("cpfg_nowhere.h");
  CHECK(t == NULL, "out written on failure");
  CHECK_STATUS(arbor_tree_from_lsystem_file(NULL, NULL, &t), ARBOR_STATUS_NULL_ARGUMENT);

  /* glTF 2.0: a .glb starts with its magic and version 2; another extension is refused. */
  const char *leafy = "derivation length: 3\nAxiom: A\nA --> F[+A~][-A@O(1)]\n";
  CHECK_STATUS(arbor_tree_from_lsystem(leafy, strlen(leafy), NULL, &t), ARBOR_STATUS_OK);
  ArborLeafOptions lo = arbor_leaf_options_default();
  char glb[1024];
  snprintf(glb, sizeof glb, "%s/cpfg_tree.glb", dir);
  CHECK_STATUS(arbor_export_gltf(t, NULL, &lo, glb), ARBOR_STATUS_OK);
  FILE *f = fopen(glb, "rb");
  unsigned char head[8] = {0};
  CHECK(f && fread(head, 1, 8, f) == 8, "read %s", glb);
  if (f) fclose(f);
  CHECK(memcmp(head, "glTF", 4) == 0 && head[4] == 2, "glb header");
  snprintf(glb, sizeof glb, "%s/cpfg_tree.fbx", dir);
  CHECK_STATUS(arbor_export_gltf(t, NULL, NULL, glb), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains(".glb or .gltf");
  arbor_tree_free(t);
}

static void organs_and_colours(void) {
  const char *g = "Axiom: F(2)@O(2);F@o(1)\n";
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), NULL, &t), ARBOR_STATUS_OK);
  CHECK(arbor_tree_organ_count(t) == 2, "%zu organs", arbor_tree_organ_count(t));
  ArborOrgan o[2];
  CHECK_STATUS(arbor_tree_copy_organs(t, o, 1), ARBOR_STATUS_BUFFER_TOO_SMALL);
  CHECK_STATUS(arbor_tree_copy_organs(t, o, 2), ARBOR_STATUS_OK);
  CHECK(o[0].kind == ARBOR_ORGAN_SPHERE && o[0].size == 2.0f && o[0].position[1] == 2.0f,
        "sphere %u %g", o[0].kind, o[0].size);
  CHECK(o[1].kind == ARBOR_ORGAN_DISC && o[1].color == 2 && o[1].branch == 1, "disc %u %u",
        o[1].kind, o[1].color);
  uint32_t colors[2];
  CHECK_STATUS(arbor_tree_copy_branch_colors(t, colors, 2), ARBOR_STATUS_OK);
  CHECK(colors[0] == 1 && colors[1] == 2, "colours %u %u", colors[0], colors[1]);
  ArborMeshOptions mo = arbor_mesh_options_default();
  mo.radial_segments = 8;
  ArborLeafOptions lo = arbor_leaf_options_default();
  size_t nv = 0, ni = 0;
  CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, &mo, &nv, &ni), ARBOR_STATUS_OK);
  /* A sphere of 5 rings of 9 vertices, a disc of 8 corners. */
  CHECK(nv == 5 * 9 + 8 && ni > 0, "%zu vertices, %zu indices", nv, ni);
  CHECK(arbor_struct_size(16) == sizeof(ArborOrgan), "ArborOrgan size");
  arbor_tree_free(t);
}

/* Progress: what the callback saw, and after how many calls it says stop (0: never). */
typedef struct {
  int calls, stop_after, stages[4];
  float last;
  int backwards;
} Seen;

static int32_t on_progress(void *user, uint32_t stage, float fraction) {
  Seen *s = user;
  s->calls++;
  if (stage < 4) s->stages[stage]++;
  if (fraction < 0.0f || fraction > 1.0f) s->backwards = 1;
  s->last = fraction;
  return s->stop_after > 0 && s->calls >= s->stop_after;
}

static void progress_and_cancellation(void) {
  const char *g = "derivation length: 12\nAxiom: F\nF --> F[+F]F\n";
  ArborLsystemOptions o = arbor_lsystem_options_default();
  Seen seen = {0};
  o.progress = on_progress;
  o.progress_user_data = &seen;
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), &o, &t), ARBOR_STATUS_OK);
  CHECK(seen.stages[ARBOR_STAGE_DERIVATION] >= 12 && seen.stages[ARBOR_STAGE_INTERPRETATION] >= 2,
        "stages seen: %d derivation, %d interpretation", seen.stages[0], seen.stages[1]);
  CHECK(seen.last == 1.0f && !seen.backwards, "last fraction %g", seen.last);
  arbor_tree_free(t);
  /* A non-zero return stops: CANCELLED, nothing written, nothing leaked (valgrind). */
  for (int stop = 1; stop <= 14; stop += 3) {
    Seen cancel = {0};
    cancel.stop_after = stop;
    o.progress_user_data = &cancel;
    t = NULL;
    CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), &o, &t), ARBOR_STATUS_CANCELLED);
    CHECK(t == NULL && cancel.calls == stop, "stopped after %d calls, out %p", cancel.calls, (void *)t);
    message_contains("cancelled");
  }
  CHECK(strcmp(arbor_status_str(ARBOR_STATUS_CANCELLED), "cancelled") == 0, "status string");
}

/* Mesh writes report ARBOR_STAGE_MESH every 65,536 branches and stop when asked; engine
   presets mirror (Unity: x negated) and unknown presets are refused by name. */
static void mesh_progress_and_presets(void) {
  const char *g = "derivation length: 11\nAxiom: F\nF --> F[+F]F\n";
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(g, strlen(g), NULL, &t), ARBOR_STATUS_OK);
  size_t n = arbor_tree_branch_count(t);
  ArborMeshOptions o = arbor_mesh_options_default();
  o.radial_segments = 3;
  /* One thread: Rust's scoped threads keep a handle to the calling thread that valgrind
     counts as possibly lost at exit (the Rust tests cover threaded writes). */
  o.threads = 1;
  size_t nv = 0, ni = 0;
  CHECK_STATUS(arbor_mesh_size(t, &o, &nv, &ni), ARBOR_STATUS_OK);
  ArborVertex *v = malloc(nv * sizeof *v), *u = malloc(nv * sizeof *u);
  uint32_t *idx = malloc(ni * sizeof *idx);
  Seen seen = {0};
  o.progress = on_progress;
  o.progress_user_data = &seen;
  CHECK_STATUS(arbor_mesh_write(t, &o, v, nv, idx, ni), ARBOR_STATUS_OK);
  size_t rounds = (n + 65535) / 65536;
  CHECK(seen.stages[ARBOR_STAGE_MESH] == (int)rounds && seen.calls == (int)rounds,
        "%zu branches: %d mesh reports, expected %zu", n, seen.stages[ARBOR_STAGE_MESH], rounds);
  CHECK(seen.last == 1.0f && !seen.backwards, "last fraction %g", seen.last);
  for (int stop = 1; stop <= 2; stop++) {
    Seen cancel = {0};
    cancel.stop_after = stop;
    o.progress_user_data = &cancel;
    CHECK_STATUS(arbor_mesh_write(t, &o, u, nv, idx, ni), ARBOR_STATUS_CANCELLED);
    CHECK(cancel.calls == stop, "mesh write stopped after %d calls", cancel.calls);
    message_contains("cancelled");
  }
  /* An export that is cancelled writes no file. */
  Seen cancel = {0};
  cancel.stop_after = 1;
  o.progress_user_data = &cancel;
  remove("cancelled.glb");
  CHECK_STATUS(arbor_export_gltf(t, &o, NULL, "cancelled.glb"), ARBOR_STATUS_CANCELLED);
  FILE *f = fopen("cancelled.glb", "rb");
  CHECK(f == NULL, "a cancelled export left a file");
  if (f) fclose(f);
  cancel.calls = 0;
  remove("cancelled.obj");
  CHECK_STATUS(arbor_export_obj(t, &o, NULL, "cancelled.obj"), ARBOR_STATUS_CANCELLED);
  f = fopen("cancelled.obj", "rb");
  CHECK(f == NULL && cancel.calls == 1, "a cancelled OBJ export left a file (%d calls)", cancel.calls);
  if (f) fclose(f);
  /* Unity: the same mesh with x negated. */
  o.progress = NULL;
  o.axes = ARBOR_AXES_UNITY;
  CHECK_STATUS(arbor_mesh_write(t, &o, u, nv, idx, ni), ARBOR_STATUS_OK);
  int mirrored = 1;
  for (size_t k = 0; k < nv; k += 997)
    mirrored &= u[k].position[0] == -v[k].position[0] && u[k].position[1] == v[k].position[1] &&
                u[k].normal[0] == -v[k].normal[0];
  CHECK(mirrored, "ARBOR_AXES_UNITY mirrors x");
  o.axes = 7;
  CHECK_STATUS(arbor_mesh_write(t, &o, u, nv, idx, ni), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("axes");
  o.axes = ARBOR_AXES_UNREAL;
  o.winding = ARBOR_WINDING_CLOCKWISE;
  CHECK_STATUS(arbor_mesh_size(t, &o, &nv, &ni), ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("winding");
  free(v);
  free(u);
  free(idx);
  arbor_tree_free(t);
}

int main(int argc, char **argv) {
  progress_and_cancellation();
  mesh_progress_and_presets();
  organs_and_colours();
  grows_like_the_direct_model();
  options_apply();
  parse_errors();
  files_as_cpfg_reads_them(argc > 1 ? argv[1] : ".");
  return check_report("lsystem");
}
