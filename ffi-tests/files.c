/* Untrusted model files through the C ABI: what a model may read under each
   ArborFileAccess policy, bounded reads, the byte budget, counts of companions, the host's
   reader, progress and cancellation while loading, and leaf prefabs that are not files. */
#define _POSIX_C_SOURCE 200809L
#include "arbor.h"
#include "check.h"

#include <stdint.h>
#include <dirent.h>
#include <signal.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

static char root[1024];

static void message_contains(const char *needle) {
  char m[2048];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, needle) != NULL, "message '%s' lacks '%s'", m, needle);
}

static void message_lacks(const char *needle) {
  char m[2048];
  arbor_last_error_message(m, sizeof m);
  CHECK(strstr(m, needle) == NULL, "message '%s' quotes '%s'", m, needle);
}

/* root/rel, written with `text`. */
static void put(const char *rel, const char *text) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", root, rel);
  FILE *f = fopen(p, "wb");
  CHECK(f != NULL, "cannot write %s", p);
  if (!f) return;
  fputs(text, f);
  fclose(f);
}

static void path_of(char *out, size_t cap, const char *rel) {
  snprintf(out, cap, "%s/%s", root, rel);
}

static const char *tiny = "derivation length: 1\nAxiom: F\n";

/* Loads root/rel with `o` and expects `status`; frees any tree. */
static void load(const char *rel, const ArborLsystemOptions *o, ArborStatus status) {
  char p[2048];
  path_of(p, sizeof p, rel);
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem_file(p, o, &t), status);
  CHECK((t != NULL) == (status == ARBOR_STATUS_OK), "out written on %d", (int)status);
  arbor_tree_free(t);
}

static void bundle_confines_reads(void) {
  /* A secret beside the bundle, and the bundle in a folder of its own. */
  put("secret.txt", "TOKEN=hunter2\n");
  put("bundle/ok.h", "#define N 1\n");
  put("bundle/sub/deep.h", "#define M 1\n");

  put("bundle/abs.l", "#include \"/etc/passwd\"\nderivation length: 1\nAxiom: F\n");
  load("bundle/abs.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_contains("/etc/passwd");
  message_contains("absolute path");
  message_lacks("root");

  put("bundle/up.l", "#include \"../secret.txt\"\nderivation length: 1\nAxiom: F\n");
  load("bundle/up.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_contains("`..` leaves the model's folder");
  message_lacks("hunter2");

  /* A symlink inside the bundle that leads out of it. */
  char target[2048], link[2048];
  path_of(target, sizeof target, "secret.txt");
  path_of(link, sizeof link, "bundle/link.h");
  unlink(link);
  CHECK(symlink(target, link) == 0, "symlink");
  put("bundle/sym.l", "#include \"link.h\"\nderivation length: 1\nAxiom: F\n");
  load("bundle/sym.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_contains("symbolic link");
  message_lacks("hunter2");

  /* What stays inside is read, `..` that stays inside too. */
  put("bundle/good.l",
      "#include \"ok.h\"\n#include \"sub/../sub/deep.h\"\nderivation length: N\nAxiom: F\n");
  load("bundle/good.l", NULL, ARBOR_STATUS_OK);

  /* A view file's companions: function:, function set:, curve:, surface:. */
  put("bundle/env.l", tiny);
  put("bundle/env.v", "function: /proc/self/environ\n");
  load("bundle/env.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_contains("/proc/self/environ");
  put("bundle/env.v", "function set: ../secret.txt\n");
  load("bundle/env.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_lacks("hunter2");
  put("bundle/env.v", "curve: /proc/self/environ\n");
  load("bundle/env.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_contains("absolute path");
  /* A surface that cannot be read leaves its `~` a plain leaf site (cpfg draws on); its
     content is never read. */
  put("bundle/env.v", "surface: l /proc/self/environ\n");
  load("bundle/env.l", NULL, ARBOR_STATUS_OK);

  /* ARBOR_FILE_ACCESS_ANY opts in to the secret; NONE reads not even the bundle. */
  ArborLsystemOptions o = arbor_lsystem_options_default();
  put("bundle/up.l", "#include \"../secret.txt\"\nderivation length: 1\nAxiom: F\n");
  o.file_access = ARBOR_FILE_ACCESS_ANY;
  load("bundle/up.l", &o, ARBOR_STATUS_PARSE_ERROR); /* read, and not a grammar */
  o.file_access = ARBOR_FILE_ACCESS_NONE;
  load("bundle/good.l", &o, ARBOR_STATUS_IO_ERROR);
  message_contains("file access is `none`");
  /* Under NONE the .v beside the grammar is not read either: a bad one (it names a
     function file that is not there) does not fail. */
  put("bundle/env.v", "function: missing.func\n");
  load("bundle/env.l", &o, ARBOR_STATUS_OK);
  o.file_access = ARBOR_FILE_ACCESS_BUNDLE;
  load("bundle/env.l", &o, ARBOR_STATUS_PARSE_ERROR);
  put("bundle/env.v", "\n");

  /* Bad fields are refused by name. */
  o = arbor_lsystem_options_default();
  o.file_access = 7;
  load("bundle/good.l", &o, ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("file_access");
  o.file_access = ARBOR_FILE_ACCESS_HOST;
  load("bundle/good.l", &o, ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("read_file");
  o = arbor_lsystem_options_default();
  o.max_file_bytes = 0;
  load("bundle/good.l", &o, ARBOR_STATUS_INVALID_ARGUMENT);
  message_contains("max_file_bytes");
}

static void devices_and_fifos_are_never_read(void) {
  ArborLsystemOptions o = arbor_lsystem_options_default();
  o.file_access = ARBOR_FILE_ACCESS_ANY;
  put("dev/zero.l", "#include \"/dev/zero\"\nderivation length: 1\nAxiom: F\n");
  load("dev/zero.l", &o, ARBOR_STATUS_IO_ERROR);
  message_contains("not a regular file");
  put("dev/stdin.l", tiny);
  put("dev/stdin.v", "curve: /dev/stdin\n");
  load("dev/stdin.l", &o, ARBOR_STATUS_IO_ERROR);
  message_contains("not a regular file");
  /* A FIFO in the bundle: refused before it is opened, so nothing blocks. */
  char fifo[2048];
  path_of(fifo, sizeof fifo, "dev/pipe.h");
  unlink(fifo);
  CHECK(mkfifo(fifo, 0600) == 0, "mkfifo");
  put("dev/pipe.l", "#include \"pipe.h\"\nderivation length: 1\nAxiom: F\n");
  load("dev/pipe.l", NULL, ARBOR_STATUS_IO_ERROR);
  message_contains("not a regular file");
  o.file_access = ARBOR_FILE_ACCESS_BUNDLE;
  put("dev/pv.l", tiny);
  put("dev/pv.v", "function: pipe.h\n");
  load("dev/pv.l", &o, ARBOR_STATUS_IO_ERROR);
  unlink(fifo);

  /* A leaf prefab that is a device: an error, not an abort. */
  const char *leafy = "derivation length: 2\nAxiom: A\nA --> F[+A~][-A~]\n";
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem(leafy, strlen(leafy), NULL, &t), ARBOR_STATUS_OK);
  ArborLeafOptions lo = arbor_leaf_options_default();
  lo.prefab_obj_path = "/dev/zero";
  char glb[2048];
  path_of(glb, sizeof glb, "dev/leaves.glb");
  CHECK_STATUS(arbor_export_gltf(t, NULL, &lo, glb), ARBOR_STATUS_IO_ERROR);
  message_contains("not a regular file");
  size_t n = 0;
  CHECK_STATUS(arbor_leaf_mesh_size(t, &lo, NULL, &n, &n), ARBOR_STATUS_IO_ERROR);
  arbor_tree_free(t);
}

/* A file of `bytes` bytes: a comment, so it preprocesses to nothing. */
static void put_big(const char *rel, size_t bytes) {
  char p[2048];
  path_of(p, sizeof p, rel);
  FILE *f = fopen(p, "wb");
  CHECK(f != NULL, "cannot write %s", p);
  if (!f) return;
  fputs("/*", f);
  char line[1024];
  memset(line, 'x', sizeof line - 1);
  line[sizeof line - 1] = '\n';
  for (size_t k = 4; k + sizeof line <= bytes; k += sizeof line) fwrite(line, 1, sizeof line, f);
  fputs("*/", f);
  fclose(f);
}

static void one_budget_over_all_files(void) {
  put_big("budget/big.h", 15u << 20);
  /* Five includes of 15 MiB: past the 64 MiB default budget at the fifth, before it is
     read; each file read whole is under the 16 MiB a file may have. */
  put("budget/five.l",
      "#include \"big.h\"\n#include \"big.h\"\n#include \"big.h\"\n#include \"big.h\"\n"
      "#include \"big.h\"\nderivation length: 1\nAxiom: F\n");
  load("budget/five.l", NULL, ARBOR_STATUS_LIMIT_EXCEEDED);
  message_contains("max_file_bytes");
  message_contains("big.h");
  put("budget/one.l", "#include \"big.h\"\nderivation length: 1\nAxiom: F\n");
  load("budget/one.l", NULL, ARBOR_STATUS_OK);
  ArborLsystemOptions o = arbor_lsystem_options_default();
  o.max_file_bytes = 1u << 20;
  load("budget/one.l", &o, ARBOR_STATUS_LIMIT_EXCEEDED);

  /* Curves, functions and surfaces are counted: 1,025 of a kind is refused. */
  put("budget/c.con", "points: 2\n0 0 0\n1 1 1\n");
  put("budget/f.func", "range: 0 1\npoints: 2\n0 0\n1 1\n");
  char *view = malloc(40000u * 16u);
  CHECK(view != NULL, "malloc");
  if (!view) return;
  size_t at = 0;
  for (int k = 0; k < 1025; k++) at += (size_t)sprintf(view + at, "curve: c.con\n");
  put("budget/curves.l", tiny);
  put("budget/curves.v", view);
  load("budget/curves.l", NULL, ARBOR_STATUS_LIMIT_EXCEEDED);
  message_contains("curves of a view file");
  at = 0;
  for (int k = 0; k < 1024; k++) at += (size_t)sprintf(view + at, "curve: c.con\n");
  put("budget/curves.v", view);
  load("budget/curves.l", NULL, ARBOR_STATUS_OK);
  at = 0;
  for (int k = 0; k < 1025; k++) at += (size_t)sprintf(view + at, "function: f.func\n");
  put("budget/funcs.l", tiny);
  put("budget/funcs.v", view);
  load("budget/funcs.l", NULL, ARBOR_STATUS_LIMIT_EXCEEDED);
  message_contains("functions of a view file");
  /* One function set with more functions than the bound. */
  at = (size_t)sprintf(view, "funcgalleryver 1 1\nitems: 2000\n");
  for (int k = 0; k < 2000; k++)
    at += (size_t)sprintf(view + at, "fver 1 1\nname: f%d\nsamples: 5\nflip: off\npoints: 2\n0 0\n1 1\n", k);
  put("budget/many.fset", view);
  put("budget/set.l", tiny);
  put("budget/set.v", "function set: many.fset\n");
  load("budget/set.l", NULL, ARBOR_STATUS_PARSE_ERROR);
  message_contains("1024");
  free(view);
}

typedef struct Loads {
  int calls;
  int load_calls;
  float last;
  int monotone;
  int stop_at; /* stop at this call (0: never) */
} Loads;

static int32_t on_progress(void *user, uint32_t stage, float fraction) {
  Loads *l = user;
  l->calls++;
  if (stage == ARBOR_STAGE_LOAD) {
    l->load_calls++;
    if (fraction < l->last) l->monotone = 0;
    l->last = fraction;
  }
  return l->stop_at != 0 && l->calls >= l->stop_at;
}

static void progress_while_loading(void) {
  put_big("progress/big.h", 4u << 20);
  put("progress/p.l", "#include \"big.h\"\nderivation length: 1\nAxiom: F\n");
  ArborLsystemOptions o = arbor_lsystem_options_default();
  Loads l = {0, 0, 0.0f, 1, 0};
  o.progress = on_progress;
  o.progress_user_data = &l;
  load("progress/p.l", &o, ARBOR_STATUS_OK);
  CHECK(l.load_calls >= 3, "%d load reports", l.load_calls);
  CHECK(l.monotone && l.last == 1.0f, "load fractions monotone %d, last %g", l.monotone,
        (double)l.last);
  /* Stopping at each of the load's reports stops the load. */
  int total = l.load_calls;
  for (int k = 1; k <= total; k++) {
    Loads s = {0, 0, 0.0f, 1, k};
    o.progress_user_data = &s;
    load("progress/p.l", &o, ARBOR_STATUS_CANCELLED);
  }
  /* Preprocessing reports too: 200,000 lines of defines. */
  char p[2048];
  path_of(p, sizeof p, "progress/lines.l");
  FILE *f = fopen(p, "wb");
  CHECK(f != NULL, "write %s", p);
  if (!f) return;
  for (int k = 0; k < 200000; k++) fputc('\n', f);
  fputs("derivation length: 1\nAxiom: F\n", f);
  fclose(f);
  /* One report for the read, one every 65,536 lines, one at the end. */
  Loads m = {0, 0, 0.0f, 1, 0};
  o.progress_user_data = &m;
  load("progress/lines.l", &o, ARBOR_STATUS_OK);
  CHECK(m.load_calls >= 5, "%d load reports for 200,000 lines", m.load_calls);
  Loads c = {0, 0, 0.0f, 1, 2};
  o.progress_user_data = &c;
  load("progress/lines.l", &o, ARBOR_STATUS_CANCELLED);
  CHECK(c.load_calls == 2, "stopped at the first preprocessing report, %d", c.load_calls);
}

/* The host's asset system: a few files in memory. */
typedef struct Asset {
  const char *path;
  const char *text;
} Asset;

static const Asset assets[] = {
    {"models/tree.l", "#include \"defs.h\"\nderivation length: N\nAxiom: A\nA --> F[+A][-A]\n"},
    {"models/defs.h", "#define N 3\n"},
    {"models/tree.v", "angle factor: 8\n"},
    {"models/esc.l", "#include \"../secret.h\"\nAxiom: F\n"},
    {"secret.h", "#define SECRET hunter2\n"},
    {"models/abs.l", "#include \"/models/defs.h\"\nAxiom: F\n"},
    {"models/missing.l", "#include \"nowhere.h\"\nAxiom: F\n"},
};

typedef struct Host {
  int calls;
  char asked[16][128];
} Host;

static int32_t host_read(void *user, const char *path, uint8_t *buffer, size_t capacity,
                         size_t *size) {
  Host *h = user;
  if (h->calls < 16) snprintf(h->asked[h->calls], sizeof h->asked[0], "%s", path);
  h->calls++;
  for (size_t k = 0; k < sizeof assets / sizeof assets[0]; k++) {
    if (strcmp(assets[k].path, path) == 0) {
      size_t n = strlen(assets[k].text);
      *size = n;
      if (capacity > 0) memcpy(buffer, assets[k].text, n < capacity ? n : capacity);
      return 0;
    }
  }
  return 1;
}

static void host_reader_serves_every_file(void) {
  ArborLsystemOptions o = arbor_lsystem_options_default();
  Host h;
  memset(&h, 0, sizeof h);
  o.file_access = ARBOR_FILE_ACCESS_HOST;
  o.read_file = host_read;
  o.read_file_user_data = &h;
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem_file("models/tree.l", &o, &t), ARBOR_STATUS_OK);
  CHECK(t && arbor_tree_branch_count(t) == 7, "%zu branches",
        t ? arbor_tree_branch_count(t) : 0);
  int saw_view = 0, saw_defs = 0;
  for (int k = 0; k < h.calls && k < 16; k++) {
    saw_view |= strcmp(h.asked[k], "models/tree.v") == 0;
    saw_defs |= strcmp(h.asked[k], "models/defs.h") == 0;
  }
  CHECK(saw_view && saw_defs, "the host was asked for the view file and the include");
  arbor_tree_free(t);
  t = NULL;
  CHECK_STATUS(arbor_tree_from_lsystem_file("models/esc.l", &o, &t), ARBOR_STATUS_IO_ERROR);
  message_contains("`..` leaves the model's folder");
  message_lacks("hunter2");
  CHECK_STATUS(arbor_tree_from_lsystem_file("models/abs.l", &o, &t), ARBOR_STATUS_IO_ERROR);
  message_contains("absolute path");
  /* A file the model names that does not exist is an error of its text, at its line. */
  CHECK_STATUS(arbor_tree_from_lsystem_file("models/missing.l", &o, &t),
               ARBOR_STATUS_PARSE_ERROR);
  message_contains("line 1");
  message_contains("models/nowhere.h");
  CHECK_STATUS(arbor_tree_from_lsystem_file("models/none.l", &o, &t),
               ARBOR_STATUS_INVALID_ARGUMENT);
  CHECK(t == NULL, "out written on failure");
}

/* Files in root/sub whose names hold `part`. */
static int count_files(const char *sub, const char *part) {
  char p[2048];
  path_of(p, sizeof p, sub);
  DIR *d = opendir(p);
  if (!d) return -1;
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) n += strstr(e->d_name, part) != NULL;
  closedir(d);
  return n;
}

static char *slurp(const char *path, size_t *n) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  char *b = malloc(1 << 20);
  *n = b ? fread(b, 1, 1 << 20, f) : 0;
  fclose(f);
  return b;
}

static int32_t stop_now(void *user, uint32_t stage, float fraction) {
  (void)user;
  (void)stage;
  (void)fraction;
  return 1;
}

/* Exports are whole or nothing: a failure or a cancel leaves the old file as it was and no
   temporary file; a device is never written through. */
static void exports_are_atomic(void) {
  ArborHondaParams p;
  arbor_honda_preset('b', &p);
  ArborTree *t = NULL;
  CHECK_STATUS(arbor_tree_from_honda(&p, &t), ARBOR_STATUS_OK);
  char glb[2048], obj[2048];
  path_of(glb, sizeof glb, "export/tree.glb");
  path_of(obj, sizeof obj, "export/tree.obj");
  CHECK_STATUS(arbor_export_gltf(t, NULL, NULL, glb), ARBOR_STATUS_OK);
  CHECK_STATUS(arbor_export_obj(t, NULL, NULL, obj), ARBOR_STATUS_OK);
  size_t n0 = 0, n1 = 0;
  char *before = slurp(glb, &n0);
  /* A cancel: the old file stays, no partial file. */
  ArborMeshOptions o = arbor_mesh_options_default();
  o.progress = stop_now;
  o.radial_segments = 12;
  CHECK_STATUS(arbor_export_gltf(t, &o, NULL, glb), ARBOR_STATUS_CANCELLED);
  CHECK_STATUS(arbor_export_obj(t, &o, NULL, obj), ARBOR_STATUS_CANCELLED);
  char *after = slurp(glb, &n1);
  CHECK(before && after && n0 == n1 && memcmp(before, after, n0) == 0, "cancel kept the old file");
  free(after);
  /* A write that fails midway (the file-size limit: EFBIG, as a full disk gives ENOSPC). */
  struct rlimit old, small;
  getrlimit(RLIMIT_FSIZE, &old);
  small = old;
  small.rlim_cur = 4096;
  void (*was)(int) = signal(SIGXFSZ, SIG_IGN);
  setrlimit(RLIMIT_FSIZE, &small);
  o = arbor_mesh_options_default();
  o.radial_segments = 12;
  ArborStatus sg = arbor_export_gltf(t, &o, NULL, glb);
  ArborStatus so = arbor_export_obj(t, &o, NULL, obj);
  setrlimit(RLIMIT_FSIZE, &old);
  signal(SIGXFSZ, was);
  CHECK(sg == ARBOR_STATUS_IO_ERROR && so == ARBOR_STATUS_IO_ERROR, "too large: %d %d", (int)sg,
        (int)so);
  message_contains("tree.obj");
  after = slurp(glb, &n1);
  CHECK(after && n0 == n1 && memcmp(before, after, n0) == 0, "a failed write kept the old file");
  free(after);
  free(before);
  CHECK(count_files("export", ".tmp") == 0, "no temporary file left: %d", count_files("export", ".tmp"));
  CHECK(count_files("export", "tree.") == 2, "two files: %d", count_files("export", "tree."));
  /* A device is never written through, nor replaced. */
  CHECK_STATUS(arbor_export_obj(t, NULL, NULL, "/dev/full"), ARBOR_STATUS_IO_ERROR);
  message_contains("not a regular file");
  struct stat st;
  CHECK(stat("/dev/full", &st) == 0 && S_ISCHR(st.st_mode), "/dev/full is still a device");
  /* A folder no one can write files in, root included. */
  CHECK_STATUS(arbor_export_gltf(t, NULL, NULL, "/proc/arbor_export_test.glb"), ARBOR_STATUS_IO_ERROR);
  message_contains("/proc/arbor_export_test.glb");
  CHECK(access("/proc/arbor_export_test.glb", F_OK) != 0, "nothing made in /proc");
  /* A folder without write permission (for users other than root). */
  if (geteuid() != 0) {
    char ro[1900], in[2048];
    snprintf(ro, sizeof ro, "%.1800s/export/ro", root);
    mkdir(ro, 0500);
    snprintf(in, sizeof in, "%s/tree.glb", ro);
    CHECK_STATUS(arbor_export_gltf(t, NULL, NULL, in), ARBOR_STATUS_IO_ERROR);
    chmod(ro, 0700);
  }
  arbor_tree_free(t);
}

int main(int argc, char **argv) {
  const char *dir = argc > 1 ? argv[1] : ".";
  snprintf(root, sizeof root, "%s/files_models", dir);
  mkdir(root, 0700);
  const char *subs[] = {"bundle", "bundle/sub", "dev", "budget", "progress", "export"};
  for (size_t k = 0; k < sizeof subs / sizeof subs[0]; k++) {
    char p[2048];
    path_of(p, sizeof p, subs[k]);
    mkdir(p, 0700);
  }
  bundle_confines_reads();
  devices_and_fifos_are_never_read();
  one_budget_over_all_files();
  progress_while_loading();
  host_reader_serves_every_file();
  exports_are_atomic();
  return check_report("files");
}
