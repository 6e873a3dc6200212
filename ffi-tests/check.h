/* Tiny assertion helpers shared by the C tests (test code only, not part of arbor). */
#ifndef ARBOR_FFI_TESTS_CHECK_H
#define ARBOR_FFI_TESTS_CHECK_H

#include <stdio.h>
#include <stdlib.h>

static int check_failures = 0;
static int check_passes = 0;

#define CHECK(cond, ...)                                                   \
  do {                                                                     \
    if (cond) {                                                            \
      check_passes++;                                                      \
    } else {                                                               \
      check_failures++;                                                    \
      fprintf(stderr, "%s:%d: CHECK(%s) failed: ", __FILE__, __LINE__, #cond); \
      fprintf(stderr, __VA_ARGS__);                                        \
      fprintf(stderr, "\n");                                               \
    }                                                                      \
  } while (0)

#define CHECK_STATUS(expr, expected)                                       \
  do {                                                                     \
    ArborStatus check_s_ = (expr);                                         \
    char check_m_[512];                                                    \
    arbor_last_error_message(check_m_, sizeof check_m_);                   \
    CHECK(check_s_ == (expected), "%s gave %d (%s), expected %d: %s", #expr, \
          (int)check_s_, arbor_status_str((uint32_t)check_s_), (int)(expected), \
          check_m_);                                                       \
  } while (0)

static int check_report(const char *name) {
  printf("%s: %d passed, %d failed\n", name, check_passes, check_failures);
  return check_failures == 0 ? 0 : 1;
}

#endif
