/* The host C test's checks of the float chain's front-end faults (test_host_front_end.c). */
#ifndef TEST_HOST_FRONT_END_H
#define TEST_HOST_FRONT_END_H

#include "angletrack.h"

/* Runs the checks (one line each), with the float chain's `gains3`; the failures. */
int front_end_checks(const at_gains_f32 *gains3);

#endif /* TEST_HOST_FRONT_END_H */
