/* The C example's flight: see fly.h. Freestanding C11 (no libc): numbers are printed by the
 * helpers below. */
#include "fly.h"

#include <stdbool.h>

#include "purcell.h"

static PurcellFlight flight;

/* Per-step counts: how many, their sum and the largest. */
typedef struct {
  uint32_t n, max;
  uint64_t sum;
} Stats;

static void put(const char *s) { platform_write(s); }

/* `v` in base `base` (10 or 16), at least `digits` digits. */
static void put_uint(uint64_t v, unsigned base, int digits) {
  char buf[24];
  int i = (int)sizeof buf - 1;
  buf[i] = 0;
  do {
    buf[--i] = "0123456789abcdef"[v % base];
    v /= base;
  } while (v != 0 || (int)sizeof buf - 1 - i < digits);
  put(&buf[i]);
}

static void put_hex(uint64_t v, int digits) {
  put("0x");
  put_uint(v, 16, digits);
}

/* `x ≥ 0` as `d.dde±XX` (the terminal error). */
static void put_sci(double x) {
  int e = 0;
  while (x >= 10.0) {
    x /= 10.0;
    e++;
  }
  while (x > 0.0 && x < 1.0) {
    x *= 10.0;
    e--;
  }
  uint32_t hundredths = (uint32_t)(x * 100.0 + 0.5);
  put_uint(hundredths / 100, 10, 1);
  put(".");
  put_uint(hundredths % 100, 10, 2);
  put(e < 0 ? "e-" : "e+");
  put_uint((uint64_t)(e < 0 ? -e : e), 10, 1);
}

/* `name: mean=M.m max=X` in instructions, net of `overhead` raw counts a step. */
static void put_stats(const char *name, const Stats *s) {
  uint64_t num = PLATFORM_INSN[0], den = PLATFORM_INSN[1], n = s->n ? s->n : 1;
  uint64_t tenths = (s->sum * 10 * num + n * den / 2) / (n * den);
  put(name);
  put(": mean=");
  put_uint(tenths / 10, 10, 1);
  put(".");
  put_uint(tenths % 10, 10, 1);
  put(" max=");
  put_uint((s->max * num + den / 2) / den, 10, 1);
  put(" steps=");
  put_uint(s->n, 10, 1);
  put("\n");
}

static int failed(PurcellStatus s) {
  char why[160];
  purcell_status_message(s, why, sizeof why);
  put("failed: ");
  put(why);
  put(" (status ");
  put(s < 0 ? "-" : "");
  put_uint((uint64_t)(s < 0 ? -(int64_t)s : s), 10, 1);
  put(")\n");
  return 1;
}

/* The smallest count of an empty span: subtracted from every step's. */
static uint32_t overhead(void) {
  uint32_t least = UINT32_MAX;
  for (int i = 0; i < 16; i++) {
    uint32_t t0 = platform_now();
    uint32_t t1 = platform_now();
    uint32_t d = platform_elapsed(t0, t1);
    least = d < least ? d : least;
  }
  return least;
}

/* Opens the gait with `options` and runs every step, each counted into `stats`; with
 * `check_samples`, reads each step's sample and checks its index. */
static PurcellStatus run(const uint8_t *gait, size_t len, uint32_t options, Stats *stats,
                         bool check_samples) {
  uint32_t base = overhead();
  PurcellStatus s = purcell_flight_open(&flight, gait, len, options);
  while (s == PURCELL_STATUS_OK) {
    uint32_t t0 = platform_now();
    s = purcell_flight_step(&flight);
    uint32_t t1 = platform_now();
    if (s != PURCELL_STATUS_OK) break;
    uint32_t d = platform_elapsed(t0, t1);
    d = d > base ? d - base : 0;
    stats->sum += d;
    stats->max = d > stats->max ? d : stats->max;
    PurcellSample sample;
    if (check_samples &&
        (purcell_flight_sample(&flight, &sample) != PURCELL_STATUS_OK || sample.k != stats->n)) {
      return PURCELL_STATUS_NO_SAMPLE;
    }
    stats->n++;
  }
  return s == PURCELL_STATUS_FINISHED ? PURCELL_STATUS_OK : s;
}

static uint32_t float_bits(float x) {
  union {
    float f;
    uint32_t u;
  } bits = {.f = x};
  return bits.u;
}

int fly(const char *board, const uint8_t *gait, size_t len) {
  Stats plain = {0}, digested = {0};
  PurcellStatus s = run(gait, len, 0, &plain, false);
  if (s != PURCELL_STATUS_OK) return failed(s);
  PurcellState end;
  purcell_flight_state(&flight, &end);
  s = run(gait, len, PURCELL_OPTION_DIGEST, &digested, true);
  if (s != PURCELL_STATUS_OK) return failed(s);

  PurcellGaitInfo info;
  uint64_t digest;
  PurcellState last;
  PurcellTerminalError error;
  if ((s = purcell_flight_info(&flight, &info)) != PURCELL_STATUS_OK ||
      (s = purcell_flight_digest(&flight, &digest)) != PURCELL_STATUS_OK ||
      (s = purcell_flight_state(&flight, &last)) != PURCELL_STATUS_OK ||
      (s = purcell_flight_terminal_error(&flight, &error)) != PURCELL_STATUS_OK) {
    return failed(s);
  }
  put("purcell-c: board=");
  put(board);
  put(" scalar=f32 steps=");
  put_uint(info.steps, 10, 1);
  put(" checkpoints=");
  put_uint(info.checkpoints, 10, 1);
  put(" arcs=");
  put_uint(info.arcs, 10, 1);
  put(" gait=");
  put_hex(info.crc, 8);
  put("\n");
  if (PLATFORM_INSN[0] != 0) {
    put_stats("insn_per_step", &plain);
    put_stats("insn_per_step_with_digest", &digested);
  }
  put("digest: ");
  put_hex(digest, 16);
  put("\nfinal_state_bits:");
  const float bits[6] = {last.alpha[0], last.alpha[1], last.x, last.y, last.cos_theta,
                         last.sin_theta};
  for (int i = 0; i < 6; i++) {
    put(" ");
    put_hex(float_bits(bits[i]), 1);
  }
  put("\nterminal_error: alpha=");
  put_sci(error.alpha);
  put(" g=");
  put_sci(error.g);
  put("\n");
  /* The flight without the digest ended in the same state, bit for bit. */
  const float other[6] = {end.alpha[0], end.alpha[1], end.x, end.y, end.cos_theta, end.sin_theta};
  for (int i = 0; i < 6; i++) {
    if (float_bits(bits[i]) != float_bits(other[i])) {
      put("failed: the flights with and without the digest ended apart\n");
      return 1;
    }
  }
  uint32_t stack = platform_stack_bytes();
  if (stack == UINT32_MAX) {
    put("failed: the stack reached the bottom of the measured window\n");
    return 1;
  }
  if (stack != 0) {
    put("stack: bytes=");
    put_uint(stack, 10, 1);
    put(" (deepest use of the run: open, steps, digest, terminal error)\n");
  }
  put("result: ok\n");
  return 0;
}
