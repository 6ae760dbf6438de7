/* The C example on the host: the same flight (fly.c) linked against the host's
 * libpurcell_capi.a, printing to stdout; no instruction counts. */
#include <stdio.h>

#include "fly.h"
#include "gait.h"

const uint32_t PLATFORM_INSN[2] = {0, 1};

void platform_write(const char *s) { fputs(s, stdout); }
uint32_t platform_now(void) { return 0; }
uint32_t platform_elapsed(uint32_t start, uint32_t end) { return end - start; }
uint32_t platform_stack_bytes(void) { return 0; }

int main(void) { return fly("host", gait, GAIT_LEN); }
