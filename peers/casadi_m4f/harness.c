/* Cortex-M4F harness for the CasADi-generated step (peer comparison, issue 4): replays the
 * costate through step() in float, counts the instructions of each call with SysTick under
 * QEMU -icount shift=6 (8/5 ticks per instruction, as the Rust firmware), prints
 * "insn_per_step: mean=<M> max=<X>" over semihosting and exits through semihosting. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <math.h>

/* The generated file as the issue prescribes: float maths from newlib. */
#define sin sinf
#define cos cosf
#include "step.c"
#include "costate.h"

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

static int semihost(int op, const void *arg) {
  register int r0 __asm__("r0") = op;
  register const void *r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

static void put(const char *s) { semihost(0x04, s); } /* SYS_WRITE0 */

static void __attribute__((noreturn)) quit(int ok) {
  /* SYS_EXIT: ADP_Stopped_ApplicationExit (status 0) or ADP_Stopped_RunTimeErrorUnknown. */
  semihost(0x18, (const void *)(uintptr_t)(ok ? 0x20026u : 0x20023u));
  for (;;) {
  }
}

static inline uint32_t now(void) { return SYST_CVR; }
static inline uint32_t elapsed(uint32_t t0, uint32_t t1) { return (t0 - t1) & 0xFFFFFFu; }

int main(void) {
  SYST_RVR = 0xFFFFFFu;
  SYST_CVR = 0;
  SYST_CSR = 5u; /* enable, processor clock, no interrupt */

  uint32_t base = 0xFFFFFFFFu;
  for (int i = 0; i < 16; i++) {
    uint32_t t0 = now();
    __asm__ volatile("" ::: "memory");
    uint32_t t1 = now();
    uint32_t d = elapsed(t0, t1);
    if (d < base) base = d;
  }

  static float alpha[2], g[3], xi[2], mu[3], u[2], alpha_n[2], g_n[3], xi_n[2];
  static float w[SZ_W];
  const float *arg[SZ_ARG] = {alpha, g, xi, mu};
  float *res[SZ_RES] = {u, alpha_n, g_n, xi_n};
  memcpy(alpha, ALPHA0, sizeof alpha);
  memcpy(xi, XI0, sizeof xi);
  memcpy(mu, MU, sizeof mu);

  uint64_t sum = 0;
  uint32_t max = 0;
  for (int k = 0; k < STEPS; k++) {
    uint32_t t0 = now();
    __asm__ volatile("" ::: "memory");
    int rc = step(arg, res, 0, w, 0);
    __asm__ volatile("" ::: "memory");
    uint32_t t1 = now();
    uint32_t d = elapsed(t0, t1) - base;
    sum += d;
    if (d > max) max = d;
    if (rc != 0 || !isfinite(u[0]) || !isfinite(u[1]) || fabsf(alpha_n[0]) >= 3.14159265f ||
        fabsf(alpha_n[1]) >= 3.14159265f) {
      put("step failed or left the admissible shapes\n");
      quit(0);
    }
    /* This step's outputs are the next one's inputs (after the counted span). */
    memcpy(alpha, alpha_n, sizeof alpha);
    memcpy(g, g_n, sizeof g);
    memcpy(xi, xi_n, sizeof xi);
  }
  /* Ticks to instructions: x 5/8, mean in tenths, rounded. */
  uint32_t tenths = (uint32_t)((sum * 50u + 4u * STEPS) / (8u * STEPS));
  uint32_t maxi = (max * 5u + 4u) / 8u;
  char line[160];
  snprintf(line, sizeof line, "insn_per_step: mean=%lu.%lu max=%lu\n", (unsigned long)(tenths / 10),
           (unsigned long)(tenths % 10), (unsigned long)maxi);
  put(line);
  snprintf(line, sizeof line, "final: alpha=%08lx %08lx g=%08lx %08lx %08lx (float bits)\n",
           (unsigned long)*(uint32_t *)&alpha[0], (unsigned long)*(uint32_t *)&alpha[1],
           (unsigned long)*(uint32_t *)&g[0], (unsigned long)*(uint32_t *)&g[1],
           (unsigned long)*(uint32_t *)&g[2]);
  put(line);
  quit(1);
}

/* ---- start-up: vector table, .data/.bss, FPU on, faults exit 1 ---- */
extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _estack;

void __attribute__((noreturn)) Reset_Handler(void) {
  uint32_t *src = &_sidata, *dst = &_sdata;
  while (dst < &_edata) *dst++ = *src++;
  for (dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  *(volatile uint32_t *)0xE000ED88u |= 0xFu << 20; /* CPACR: CP10, CP11 full access */
  __asm__ volatile("dsb\n isb" ::: "memory");
  main();
  quit(0);
}

void __attribute__((noreturn)) Fault_Handler(void) {
  put("fault\n");
  quit(0);
}

__attribute__((section(".vectors"), used)) static void *const vectors[16] = {
    &_estack, Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, 0, 0, 0, 0, Fault_Handler, Fault_Handler, 0, Fault_Handler, Fault_Handler,
};

/* newlib system calls that printf-family code may pull in. */
void *_sbrk(int incr) {
  extern char _end;
  static char *brk = &_end;
  char *p = brk;
  brk += incr;
  return p;
}
