/* Semihosting calls of the C example's start-up (startup.c). */
#ifndef SEMIHOSTING_H
#define SEMIHOSTING_H

/* Writes a NUL-terminated string to QEMU's console. */
void semihosting_write(const char *text);
/* Exits QEMU: with status 0 if `status` is 0, else 1. */
void semihosting_exit(int status) __attribute__((noreturn));

#endif /* SEMIHOSTING_H */
