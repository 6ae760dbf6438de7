/* The C example's flight, shared by the QEMU firmware (mps2.c) and the host program (host.c):
 * flies a gait through the C API (purcell.h) and prints the lines the Rust flight prints. */
#ifndef FLY_H
#define FLY_H

#include <stddef.h>
#include <stdint.h>

/* Flies `gait[0..len]` twice: without the digest, each step timed (where the platform
 * counts), then with it, each step timed and its sample read; prints the header, the
 * per-step instructions of both flights, `digest: 0x…`, the final state's bits, the terminal
 * error, the deepest stack use of the run, and `result: ok` (or `failed: <why>`). Returns 0,
 * or 1 on any failure. */
int fly(const char *board, const uint8_t *gait, size_t len);

/* What the platform provides. */
/* Writes a NUL-terminated string to the output. */
void platform_write(const char *s);
/* A raw count, read before and after a measured span. */
uint32_t platform_now(void);
/* Raw counts from `start` to `end`. */
uint32_t platform_elapsed(uint32_t start, uint32_t end);
/* Instructions per raw count, as the fraction PLATFORM_INSN[0] / PLATFORM_INSN[1]; {0, 1}
 * where the platform does not count (the per-step lines are then left out). */
extern const uint32_t PLATFORM_INSN[2];
/* The deepest stack use so far, bytes (0 where the platform does not measure it: the line
 * is then left out; UINT32_MAX if it reached the bottom of the measured window). */
uint32_t platform_stack_bytes(void);

#endif /* FLY_H */
