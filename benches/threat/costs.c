/* The cost table of the README's threat model: time and peak memory of the worst input
   of each kind, through the C ABI. Build and run (release library):
     cargo build --release && cc -O2 -Iinclude benches/threat/costs.c \
       target/release/libarbor.a -lpthread -ldl -lm -o target/threat_costs && \
       target/threat_costs target/threat
   Each case runs in a child process so its peak memory (ru_maxrss) is its own. Run it from
   the checkout's top folder: the derivation-work table reads ffi-tests/hostile/. */
#define _POSIX_C_SOURCE 200809L
#include "arbor.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static char dir[1024];

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + t.tv_nsec * 1e-9;
}

static void put(const char *name, const char *text) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  FILE *f = fopen(p, "wb");
  fputs(text, f);
  fclose(f);
}

static size_t file_size(const char *name) {
  char p[2048];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  struct stat st;
  return stat(p, &st) == 0 ? (size_t)st.st_size : 0;
}

/* Loads dir/name in a child; prints time, peak RSS and the status. `model_bytes`: the
   bytes of the model an attacker sends. */
static void measure(const char *what, const char *name, size_t model_bytes, int any) {
  fflush(stdout);
  pid_t pid = fork();
  if (pid == 0) {
    char p[2048];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    ArborLsystemOptions o = arbor_lsystem_options_default();
    if (any) o.file_access = ARBOR_FILE_ACCESS_ANY;
    ArborTree *t = NULL;
    double t0 = now();
    ArborStatus s = arbor_tree_from_lsystem_file(p, &o, &t);
    double ms = (now() - t0) * 1e3;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    double kib = model_bytes / 1024.0;
    printf("| %s | %.1f KiB | %s | %.1f ms (%.3f ms/KiB) | %.1f MB (%.2f MB/KiB) |\n", what, kib,
           arbor_status_str((uint32_t)s), ms, ms / kib, ru.ru_maxrss / 1024.0,
           ru.ru_maxrss / 1024.0 / kib);
    arbor_tree_free(t);
    fflush(stdout);
    _exit(0);
  }
  int st;
  waitpid(pid, &st, 0);
}

/* The longest time between two progress reports of one load, in seconds. */
static double last_report, longest_gap;
static int32_t note_report(void *user, uint32_t stage, float fraction) {
  (void)user;
  (void)stage;
  (void)fraction;
  double t = now();
  if (t - last_report > longest_gap) longest_gap = t - last_report;
  last_report = t;
  return 0;
}

/* Derives `text` with `steps` (-1: its own) and the default limits, twice: without a
   callback (the time a default-limited load takes), and with one (the longest gap between
   its reports, the time a host waits at most for a cancel to be heard). */
static void work(const char *what, const char *text, int32_t steps) {
  ArborLsystemOptions o = arbor_lsystem_options_default();
  o.steps = steps;
  ArborTree *t = NULL;
  double t0 = now();
  ArborStatus s = arbor_tree_from_lsystem(text, strlen(text), &o, &t);
  double ms = (now() - t0) * 1e3;
  arbor_tree_free(t);
  t = NULL;
  o.progress = note_report;
  longest_gap = 0;
  last_report = now();
  arbor_tree_from_lsystem(text, strlen(text), &o, &t);
  double tail = now() - last_report;
  arbor_tree_free(t);
  printf("| %s | %s | %.0f ms | %.1f ms (then %.1f ms to return) |\n", what,
         arbor_status_str((uint32_t)s), ms, longest_gap * 1e3, tail * 1e3);
}

/* The text of a file (NUL-terminated), or NULL. */
static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *b = malloc((size_t)n + 1);
  size_t got = fread(b, 1, (size_t)n, f);
  b[got] = 0;
  fclose(f);
  return b;
}

static void derivation_work(void) {
  printf("\n| derivation work (default limits, `max_work` 2^28 units) | status | time | "
         "longest gap between progress reports |\n|---|---|---|---|\n");
  char *finding = slurp("ffi-tests/hostile/derivation_runs_past_20s.l");
  if (finding) work("round 4: `derivation_runs_past_20s.l`, steps 65,535", finding, 65535);
  free(finding);
  work("a statement loop: `x = x + 1`", "Axiom: A\nA : { while (1) { x = x + 1; } } --> A\n",
       2);
  work("a statement loop: `pow`", "Axiom: A\nA : { while (1) { x = pow(x + 1, 0.5); } } --> A\n",
       2);
  work("a statement loop: `bran(0.001, 1000)` (rejection tries)",
       "Axiom: A\nA : { while (1) { x = bran(0.001, 1000); } } --> A\n", 2);
  work("a statement loop: `biran(100000, 0.5)` (100,000 trials a call)",
       "Axiom: A\nA : { while (1) { x = biran(100000, 0.5); } } --> A\n", 2);
  static char big[1 << 16];
  strcpy(big, "Axiom: ");
  for (int k = 0; k < 5000; k++) strcat(big, "A(1)");
  strcat(big, "\n");
  for (int k = 0; k < 60; k++) {
    char p[64];
    sprintf(p, "A(x) : x > %d --> A(x)\n", k + 5);
    strcat(big, p);
  }
  work("5,000 modules, 60 productions each tried and failing, every step", big, 65535);
  work("interpretation rules 1,000 deep over a doubling string",
       "Axiom: A\nA --> AA\nhomomorphism\nmaximum depth: 1000\nA --> FA\n", 16);
}

int main(int argc, char **argv) {
  snprintf(dir, sizeof dir, "%s", argc > 1 ? argv[1] : "threat");
  mkdir(dir, 0700);
  derivation_work();
  printf("\n| worst input | model size | status | time | peak memory |\n|---|---|---|---|---|\n");
  /* 1. Includes of a 16 MiB comment, as many as fit in 1 KiB of grammar. */
  {
    char p[2048];
    snprintf(p, sizeof p, "%s/big.h", dir);
    FILE *f = fopen(p, "wb");
    fputs("/*", f);
    static char line[1024];
    memset(line, 'x', sizeof line - 1);
    line[sizeof line - 1] = '\n';
    for (int k = 0; k < 16 * 1024 - 1; k++) fwrite(line, 1, sizeof line, f);
    fputs("*/\n", f);
    fclose(f);
    char *g = malloc(1 << 16);
    size_t at = 0;
    while (at < 1000) at += (size_t)sprintf(g + at, "#include \"big.h\"\n");
    sprintf(g + at, "Axiom: F\n");
    put("includes.l", g);
    measure("`#include` of a 16 MiB file, 59 times", "includes.l",
            file_size("includes.l") + file_size("big.h"), 0);
    /* 2. A function set of tiny functions: 4 MiB. */
    FILE *fs = fopen(strcat(strcpy(p, dir), "/many.fset"), "wb");
    fprintf(fs, "funcgalleryver 1 1\nitems: 100000\n");
    for (int k = 0; k < 100000; k++) fprintf(fs, "fver 1 1\nname: f\npoints: 2\n0 0\n1 1\n");
    fclose(fs);
    put("fset.l", "Axiom: F\n");
    at = 0;
    for (int k = 0; k < 40; k++) at += (size_t)sprintf(g + at, "function set: many.fset\n");
    put("fset.v", g);
    measure("`function set:` of a 4 MiB set, 40 times", "fset.l",
            file_size("fset.v") + file_size("many.fset"), 0);
    /* 3. 40,000 `curve:` lines. */
    put("c.con", "points: 4\n0 0 0\n1 1 0\n2 0 1\n3 1 1\n");
    char *v = malloc(40000 * 16);
    at = 0;
    for (int k = 0; k < 40000; k++) at += (size_t)sprintf(v + at, "curve: c.con\n");
    put("curves.l", "Axiom: F\n");
    put("curves.v", v);
    measure("`curve:` 40,000 times", "curves.l", file_size("curves.v") + file_size("c.con"), 0);
    /* 4. A device and 5. a FIFO (the latter read under ANY). */
    put("zero.l", "#include \"/dev/zero\"\nAxiom: F\n");
    measure("`#include \"/dev/zero\"` (ANY)", "zero.l", file_size("zero.l"), 1);
    snprintf(p, sizeof p, "%s/pipe.h", dir);
    unlink(p);
    mkfifo(p, 0600);
    put("fifo.l", "#include \"pipe.h\"\nAxiom: F\n");
    measure("`#include` of a FIFO", "fifo.l", file_size("fifo.l"), 0);
    free(v);
    free(g);
  }
  /* 6. Obstacles: one box filling a default world, and 65,536 spheres with a tree. */
  {
    ArborWorld *w = NULL;
    ArborWorldOptions wo = arbor_world_options_default();
    arbor_world_create(&wo, &w);
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
      lo[k] = wo.min[k];
      hi[k] = wo.max[k];
    }
    double t0 = now();
    ArborStatus s = arbor_world_add_box(w, lo, hi);
    printf("\nobstacles: a box filling the default world: %s in %.1f ms\n",
           arbor_status_str((uint32_t)s), (now() - t0) * 1e3);
    arbor_world_free(w);
    arbor_world_create(&wo, &w);
    float at[3] = {0, 0, 0};
    arbor_world_plant(w, NULL, at, 1, NULL);
    arbor_world_step(w, 10);
    t0 = now();
    for (int k = 0; k < 65536; k++) {
      float c[3] = {wo.min[0] + (k % 61) * 0.3f, wo.min[1] + 2.0f + (k % 7) * 0.5f,
                    wo.min[2] + (k / 61 % 61) * 0.3f};
      arbor_world_add_sphere(w, c, 0.2f);
    }
    double ms = (now() - t0) * 1e3;
    printf("obstacles: 65,536 spheres beside a 10-cycle tree: %.1f ms (%.2f us each)\n", ms,
           ms * 1e3 / 65536);
    arbor_world_free(w);
  }
  return 0;
}
