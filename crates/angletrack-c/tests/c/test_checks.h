/* The host C test's check helpers, one copy for each of its files (test_host.c,
 * test_host_tables.c, test_host_front_end.c): each file counts its own failures. */
#ifndef TEST_CHECKS_H
#define TEST_CHECKS_H

#include <stdio.h>

#include "angletrack.h"

static int failures;

/* Prints PASS or FAIL and `what`; counts a failure. */
static inline void check(int pass, const char *what) {
  printf("%s %s\n", pass ? "PASS" : "FAIL", what);
  failures += !pass;
}

/* check() that `got` is `expected`, the status's message printed. */
static inline void check_status(at_status got, at_status expected, const char *what) {
  char line[200];
  snprintf(line, sizeof line, "%s: status %d \"%s\" (expected %d)", what, (int)got,
           at_status_message(got), (int)expected);
  check(got == expected, line);
}

#endif
