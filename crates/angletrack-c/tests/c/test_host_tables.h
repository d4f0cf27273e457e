/* The host C test's checks of the fixed-point chain and the angle-correction tables
 * (test_host_tables.c). */
#ifndef TEST_HOST_TABLES_H
#define TEST_HOST_TABLES_H

#include "angletrack.h"

/* Runs the checks (one line each), with the float chain's `gains3`; the failures. */
int fixed_chain_checks(const at_gains_f32 *gains3);

#endif /* TEST_HOST_TABLES_H */
