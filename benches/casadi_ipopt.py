#!/usr/bin/env python3
"""Peer comparison: the paper's discrete problem (MODEL.md section 4) by direct transcription
with CasADi + IPOPT, next to purcell-sim's result.

    pip install casadi
    cargo run --release -p host-sim -- solve --out out/paper
    python3 benches/casadi_ipopt.py --report out/paper/report.json [--starts 2] [--steps 10000]

Decision variables: alpha_k (k=0..N), u_k and g_k = (x, y, theta) (k=0..N), with the exact
step g_{k+1} = g_k exp(-h A(alpha_k) u_k) as equality constraints, alpha_{k+1} = alpha_k + h u_k,
alpha_0 = alpha_N = 0, g_0 = e, g_N = (0.1, 0.1, 0). Cost sum h/2 |u_k|^2. The connection A is
the resistive-force-theory one of MODEL.md section 2, written out here independently.
Starts: ellipses in the shape plane (as purcell-sim's). Not part of CI.
"""
import argparse
import json
import math
import time

import casadi as ca


def connection(a1, a2, L=(1.0, 1.0, 1.0), r=2.0):
    """A(alpha) (3x2, rows x, y, theta) from W_xi xi + W_alpha alpha_dot = 0."""
    l0, l1, l2 = L
    h0 = l0 / 2
    c1, s1, c2, s2 = ca.cos(a1), ca.sin(a1), ca.cos(a2), ca.sin(a2)
    links = [  # (length, tau, nu) with tau=(t, c x t), nu=(n, c x n)
        (l0, ca.vertcat(1, 0, 0), ca.vertcat(0, 1, 0)),
        (l1, ca.vertcat(c1, s1, h0 * s1), ca.vertcat(-s1, c1, h0 * c1 + l1 / 2)),
        (l2, ca.vertcat(c2, s2, -h0 * s2), ca.vertcat(-s2, c2, -h0 * c2 - l2 / 2)),
    ]
    W = ca.MX.zeros(3, 3) if isinstance(a1, ca.MX) else ca.SX.zeros(3, 3)
    for l, tau, nu in links:
        W += l * (tau @ tau.T + r * nu @ nu.T)
        W[2, 2] += r * l**3 / 12
    nu1, nu2 = links[1][2], links[2][2]
    col1 = r * l1**2 * (nu1 / 2 + ca.vertcat(0, 0, l1 / 12))
    col2 = r * l2**2 * (-nu2 / 2 + ca.vertcat(0, 0, l2 / 12))
    return ca.solve(W, ca.horzcat(col1, col2))


def se2_exp(v):
    w = v[2]
    # sin(w)/w and (1-cos w)/w = 2 sin^2(w/2)/w, safe near 0 via if_else.
    small = ca.fabs(w) < 1e-6
    a = ca.if_else(small, 1 - w**2 / 6, ca.sin(w) / w)
    b = ca.if_else(small, w / 2, 2 * ca.sin(w / 2) ** 2 / w)
    return ca.vertcat(a * v[0] - b * v[1], b * v[0] + a * v[1], w)


def compose(g, d):
    c, s = ca.cos(g[2]), ca.sin(g[2])
    return ca.vertcat(g[0] + c * d[0] - s * d[1], g[1] + s * d[0] + c * d[1], g[2] + d[2])


def solve(n, T, target, start, expand):
    h = T / n
    opti = ca.Opti()
    al = opti.variable(2, n + 1)
    u = opti.variable(2, n)
    g = opti.variable(3, n + 1)
    # One-step map as a CasADi Function (mapped over k).
    a_s, u_s, g_s = ca.SX.sym("a", 2), ca.SX.sym("u", 2), ca.SX.sym("g", 3)
    A = connection(a_s[0], a_s[1])
    step = ca.Function("step", [a_s, u_s, g_s], [compose(g_s, se2_exp(-h * A @ u_s))])
    F = step.map(n)
    opti.subject_to(g[:, 1:] == F(al[:, :-1], u, g[:, :-1]))
    opti.subject_to(al[:, 1:] == al[:, :-1] + h * u)
    opti.subject_to(al[:, 0] == 0)
    opti.subject_to(al[:, n] == 0)
    opti.subject_to(g[:, 0] == 0)
    opti.subject_to(g[:, n] == ca.DM(target))
    opti.minimize(h / 2 * ca.sumsqr(u))
    a, b, phase, turns = start
    ts = [2 * math.pi * turns * k / n + phase for k in range(n + 1)]
    a1 = [a * (math.cos(t) - math.cos(phase)) for t in ts]
    a2 = [b * (math.sin(t) - math.sin(phase)) for t in ts]
    opti.set_initial(al, ca.DM([a1, a2]))
    opti.set_initial(u, ca.DM([[(a1[k + 1] - a1[k]) / h for k in range(n)], [(a2[k + 1] - a2[k]) / h for k in range(n)]]))
    opti.solver("ipopt", {"expand": expand, "print_time": False}, {"print_level": 0, "max_iter": 3000})
    t0 = time.time()
    try:
        sol = opti.solve()
        ok = True
    except RuntimeError:
        sol = opti.debug
        ok = False
    dt = time.time() - t0
    cost = float(sol.value(h / 2 * ca.sumsqr(u)))
    amax = float(max(abs(x) for x in sol.value(al).flatten()))
    return ok, dt, cost, amax


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--report", help="purcell-sim report.json to compare with")
    ap.add_argument("--steps", type=int, default=10000)
    ap.add_argument("--horizon", type=float, default=100.0)
    ap.add_argument("--starts", type=int, default=2)
    ap.add_argument("--no-expand", action="store_true")
    args = ap.parse_args()
    starts = [(0.5, -0.5, 0.5 * math.pi, 2), (1.0, -1.0, 1.5 * math.pi, 1), (0.5, 0.5, math.pi, 1)]
    print(f"{'method':<26}{'start':<8}{'seconds':>10}{'cost':>12}{'max|alpha|':>12}  status")
    for i, s in enumerate(starts[: args.starts]):
        ok, dt, cost, amax = solve(args.steps, args.horizon, [0.1, 0.1, 0.0], s, not args.no_expand)
        print(f"{'CasADi+IPOPT (MUMPS)':<26}{i:<8}{dt:>10.2f}{cost:>12.6f}{amax:>12.4f}  {'ok' if ok else 'FAILED'}")
    if args.report:
        r = json.load(open(args.report))
        print(f"{'purcell-sim solve':<26}{'all':<8}{r['solve_seconds']:>10.2f}{r['cost']:>12.6f}{r['max_abs_alpha']:>12.4f}  residual {r['residual']:.1e}")
        for x in r["extremals"]:
            print(f"{'  extremal':<26}{x['start']:<8}{'':>10}{x['cost']:>12.6f}{x['max_abs_alpha']:>12.4f}  {'admissible' if x['admissible'] else 'INADMISSIBLE'}")


if __name__ == "__main__":
    main()
