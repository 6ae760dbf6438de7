/* The C example firmware for QEMU's mps2-an386 (Cortex-M4F): vector table, reset (FPU on,
 * .data copied, .bss zeroed), semihosting output and exit, and the SysTick that counts
 * instructions under `-icount shift=6` (as firmware/mcu does: one instruction is 64 ns of
 * virtual time, the SysTick counts at 25 MHz, so 8/5 ticks an instruction). Flies the gait
 * that `purcell-sim export --format c --out gait.c` wrote. */
#include <stdint.h>

#include "fly.h"
#include "gait.h"

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define CPACR (*(volatile uint32_t *)0xE000ED88u)

const uint32_t PLATFORM_INSN[2] = {5, 8};

/* Semihosting call `op` with argument `arg` (QEMU: -semihosting-config enable=on). */
static uint32_t semihost(uint32_t op, const void *arg) {
  register uint32_t r0 __asm__("r0") = op;
  register const void *r1 __asm__("r1") = arg;
  __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
  return r0;
}

void platform_write(const char *s) { semihost(0x04 /* SYS_WRITE0 */, s); }

/* SYS_EXIT: QEMU exits with 0 for ADP_Stopped_ApplicationExit, 1 for any other reason. */
static void __attribute__((noreturn)) exit_with(int status) {
  semihost(0x18, (const void *)(status == 0 ? 0x20026u : 0x20023u));
  for (;;) {
  }
}

uint32_t platform_now(void) {
  __asm__ volatile("" ::: "memory");
  uint32_t t = SYST_CVR;
  __asm__ volatile("" ::: "memory");
  return t;
}

/* The SysTick counts down over 24 bits; a step is far shorter than a wrap. */
uint32_t platform_elapsed(uint32_t start, uint32_t end) { return (start - end) & 0x00FFFFFFu; }

/* 1000 `nop`s must count 1000 ± 1 instructions more than none (QEMU started with -icount). */
static void __attribute__((noinline)) nops0(void) { __asm__ volatile(""); }
static void __attribute__((noinline)) nops1000(void) { __asm__ volatile(".rept 1000\n nop\n .endr"); }

static int counting_works(void) {
  uint32_t t0 = platform_now();
  nops0();
  uint32_t t1 = platform_now();
  nops1000();
  uint32_t t2 = platform_now();
  uint32_t extra = (platform_elapsed(t1, t2) - platform_elapsed(t0, t1)) * 5u / 8u;
  return extra >= 999 && extra <= 1001;
}

int main(void) {
  SYST_RVR = 0x00FFFFFFu;
  SYST_CVR = 0;
  SYST_CSR = 0x5; /* processor clock, no interrupt, enabled */
  if (!counting_works()) {
    platform_write("failed: 1000 nops did not count as 1000 instructions (QEMU without -icount?)\n");
    return 1;
  }
  return fly("mps2-an386", gait, GAIT_LEN);
}

extern uint32_t _sidata, _sdata, _edata, _sbss, _ebss, _stack_top;

/* The stack's lowest 16 KiB below its top are painted at reset; the deepest use is where the
 * paint was overwritten. */
#define STACK_WINDOW_WORDS 4096u
#define PAINT 0xA5C35A3Cu

/* The window's lowest word (through an integer: the linker symbol is no C object). */
static volatile uint32_t *stack_window(void) {
  return (volatile uint32_t *)((uintptr_t)&_stack_top - 4u * STACK_WINDOW_WORDS);
}

uint32_t platform_stack_bytes(void) {
  volatile uint32_t *p = stack_window(), *top = p + STACK_WINDOW_WORDS;
  if (*p != PAINT) return UINT32_MAX;
  while (p < top && *p == PAINT) p++;
  return (uint32_t)(top - p) * 4u;
}

void __attribute__((noreturn)) reset_handler(void) {
  CPACR |= 0xFu << 20; /* CP10, CP11: full access to the FPU */
  __asm__ volatile("dsb\n isb" ::: "memory");
  for (uint32_t *src = &_sidata, *dst = &_sdata; dst < &_edata;) *dst++ = *src++;
  for (uint32_t *dst = &_sbss; dst < &_ebss;) *dst++ = 0;
  uint32_t *sp;
  __asm__ volatile("mov %0, sp" : "=r"(sp));
  /* Below this frame (16 words of margin): free. */
  for (volatile uint32_t *p = stack_window(); p < sp - 16; p++) *p = PAINT;
  exit_with(main());
}

static void __attribute__((noreturn)) fault_handler(void) {
  platform_write("failed: fault\n");
  exit_with(1);
}

__attribute__((section(".vectors"), used)) static const void *const vectors[16] = {
    &_stack_top,   (const void *)reset_handler, (const void *)fault_handler,
    (const void *)fault_handler, (const void *)fault_handler, (const void *)fault_handler,
    (const void *)fault_handler,
};
