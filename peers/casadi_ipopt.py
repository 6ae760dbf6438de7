#!/usr/bin/env python3
"""Peer: the exact discrete problem of docs/MODEL.md section 4 by direct transcription with
CasADi + IPOPT (the paper's method), multi-start, next to purcell-sim's result. Not CI.

    pip install casadi
    python3 peers/casadi_ipopt.py --check                        # transcription check
    python3 peers/casadi_ipopt.py PROBLEMS.json [--only a,b] [--starts 8] [--guard A] \
        [--jsonl FILE] [--ours BENCH.md] [--max-cpu 400] [--max-iter 3000] [--paths DIR]
    python3 peers/casadi_ipopt.py PROBLEMS.json --table --jsonl FILE [--ours BENCH.md]
    python3 peers/casadi_ipopt.py --cost power [--starts 4]        # the power cost (MODEL.md 11)

PROBLEMS.json is a list in the format of the public suite (tests/problems/public.json):
`name`, `target`, and where given `horizon` (default 100), `step` (0.01), `alpha0` (0,0),
`alpha_end` (alpha0: a loop), `links` (1,1,1), `drag` (1), `ratio` (2), `alpha_max` (none), `ref`,
and `trajectory` (a purcell-sim trajectory.csv of the problem: its shape path is then the first
start, so IPOPT checks that extremal on its own transcription besides the family's). Without PROBLEMS.json:
the paper's problem. Each problem is run from the first --starts starts of a fixed family
(below), one after the other; every start prints a line and, with --jsonl, appends one JSON line
{problem, start, label, status, cost, max_abs_alpha, admissible, replay_error, seconds,
cpu_seconds, iterations}; with --paths, each start's solution goes to DIR/PROBLEM-START.csv
(t, alpha, g, u per step, purcell-sim's column names: a `trajectory` start reads it back,
and its shape loop can be looked at). A (problem, start) pair already in the --jsonl file is not run again
(resume an interrupted run with the same command). With --table nothing is run: the table is
made from the --jsonl file alone (CasADi not needed).

The closing table gives per problem IPOPT's cheapest admissible cost, its largest |alpha_i|
and replay error, how many starts reached it, were admissible, converged and ran, the CPU
seconds per start (min / median / max; the graph build, once per N, h and model, not
included), and with --ours purcell-sim's cost, its relative difference and its time, read
from the table `cargo bench -p purcell-benches --bench suite -- PROBLEMS.json` prints (saved
to BENCH.md). Admissible: IPOPT converged (Solve_Succeeded), max |alpha_i| < pi, and
<= alpha_max when given.

Decision variables: the states x_k = (alpha_k, g_k) (k = 0..N, g = (x, y, theta)) and the
controls u_k (k = 0..N-1). Equality constraints: the exact step alpha_{k+1} = alpha_k + h u_k,
g_{k+1} = g_k exp(-h A(alpha_k) u_k). Bounds: alpha_0 = alpha0, alpha_N = alpha_end, g_0 = e,
g_N = target, and |alpha_i| <= alpha_max on every alpha_k when given. Cost sum h/2 |u_k|^2, or
with --cost power sum h/2 u_k^T G(alpha_k) u_k (G from the same drag matrices, MODEL.md 11). The
connection A
is the resistive-force-theory one of MODEL.md section 2, written out here independently. The
NLP depends on the problem only through N, h, the links, the drag and the ratio (the rest are
bounds), so one IPOPT instance serves all the problems and starts that share them.

Starts: shape loops through alpha0 (the controls their differences / h, g_k their exact
replay), for a transition (alpha_end != alpha0) ridden along the straight path alpha0 -> alpha_end: ellipses and figure-eights (1:2 Lissajous), in mirror pairs (start 2i+1 is start 2i
negated, alpha -> -alpha, so a problem and its mirror image get mirrored starts); see START_FAMILY.
"""
import argparse
import json
import math
import os
import statistics
import time

import numpy as np

try:
    import casadi as ca
except ImportError:  # --table needs no CasADi
    ca = None

DEFAULTS = {"horizon": 100.0, "step": 0.01, "alpha0": [0.0, 0.0], "links": [1.0, 1.0, 1.0],
            "drag": 1.0, "ratio": 2.0, "alpha_max": None}
PAPER = {"name": "paper", "target": [0.1, 0.1, 0.0], "ref": 0.6817478081948872}


def connection(a1, a2, links, drag, ratio):
    """A(alpha) (3x2, rows x, y, theta) from W_xi xi + W_alpha alpha_dot = 0 (MODEL.md 2)."""
    W, cols = drag_matrices(a1, a2, links, drag, ratio)
    return ca.solve(W, cols)


def drag_matrices(a1, a2, links, drag, ratio):
    """W_xi (3x3) and W_alpha (3x2) of the balance W_xi xi + W_alpha alpha_dot = 0 (MODEL.md 2)."""
    l0, l1, l2 = links
    k, r = drag, ratio
    h0 = l0 / 2
    c1, s1, c2, s2 = ca.cos(a1), ca.sin(a1), ca.cos(a2), ca.sin(a2)
    parts = [  # (length, tau, nu) with tau = (t, c x t), nu = (n, c x n), c the link's centre
        (l0, ca.vertcat(1, 0, 0), ca.vertcat(0, 1, 0)),
        (l1, ca.vertcat(c1, s1, h0 * s1), ca.vertcat(-s1, c1, h0 * c1 + l1 / 2)),
        (l2, ca.vertcat(c2, s2, -h0 * s2), ca.vertcat(-s2, c2, -h0 * c2 - l2 / 2)),
    ]
    W = ca.SX.zeros(3, 3)
    for l, tau, nu in parts:
        W += k * l * (tau @ tau.T + r * nu @ nu.T)
        W[2, 2] += k * r * l**3 / 12
    nu1, nu2 = parts[1][2], parts[2][2]
    col1 = k * r * l1**2 * (nu1 / 2 + ca.vertcat(0, 0, l1 / 12))
    col2 = k * r * l2**2 * (-nu2 / 2 + ca.vertcat(0, 0, l2 / 12))
    return W, ca.horzcat(col1, col2)


def metric(a1, a2, links, drag, ratio):
    """G(alpha) of the power cost (MODEL.md 11): the Schur complement R_uu - W_alpha^T W_xi^-1
    W_alpha of the 5x5 resistance matrix; R_uu = diag(k r L_i^3 / 3) (an outer link turning
    about its hinge, its centre at L_i/2: k r L_i (L_i/2)^2 + k r L_i^3/12)."""
    W, cols = drag_matrices(a1, a2, links, drag, ratio)
    k, r = drag, ratio
    ruu = ca.diag(ca.vertcat(k * r * links[1] ** 3 / 3, k * r * links[2] ** 3 / 3))
    return ruu - cols.T @ ca.solve(W, cols)


def stage_cost(h, links, drag, ratio, cost):
    """l(x_k, u_k): h/2 |u|^2 (effort) or h/2 u^T G(alpha) u (power)."""
    x, u = ca.SX.sym("x", 5), ca.SX.sym("u", 2)
    if cost == "power":
        ell = h / 2 * (u.T @ metric(x[0], x[1], links, drag, ratio) @ u)
    else:
        ell = h / 2 * ca.sumsqr(u)
    return ca.Function("cost", [x, u], [ell])


def se2_exp(v):
    w = v[2]
    # sin(w)/w and (1-cos w)/w = 2 sin^2(w/2)/w, by series near 0.
    small = ca.fabs(w) < 1e-6
    a = ca.if_else(small, 1 - w**2 / 6, ca.sin(w) / w)
    b = ca.if_else(small, w / 2, 2 * ca.sin(w / 2) ** 2 / w)
    return ca.vertcat(a * v[0] - b * v[1], b * v[0] + a * v[1], w)


def compose(g, d):
    c, s = ca.cos(g[2]), ca.sin(g[2])
    return ca.vertcat(g[0] + c * d[0] - s * d[1], g[1] + s * d[0] + c * d[1], g[2] + d[2])


def step_function(h, links, drag, ratio):
    """x_{k+1} = step(x_k, u_k), x = (alpha1, alpha2, x, y, theta): MODEL.md section 4."""
    x, u = ca.SX.sym("x", 5), ca.SX.sym("u", 2)
    A = connection(x[0], x[1], links, drag, ratio)
    nxt = ca.vertcat(x[:2] + h * u, compose(x[2:], se2_exp(-h * A @ u)))
    return ca.Function("step", [x, u], [nxt])


def full(p):
    q = dict(DEFAULTS)
    q.update(p)
    q.setdefault("alpha_end", q["alpha0"])
    return q


def steps_of(p):
    n = round(p["horizon"] / p["step"])
    if n < 1 or abs(n * p["step"] - p["horizon"]) > 1e-9 * p["horizon"]:
        raise SystemExit(f"{p['name']}: horizon {p['horizon']} is not a whole number of steps {p['step']}")
    return n


class Transcription:
    """One IPOPT instance for every problem with the same N, h, links, drag and ratio."""

    def __init__(self, n, h, links, drag, ratio, max_cpu, max_iter, cost="effort"):
        self.n, self.h = n, h
        t0 = time.time()
        self.step = step_function(h, links, drag, ratio)
        self.stage = stage_cost(h, links, drag, ratio, cost).map(n)
        X = ca.MX.sym("X", 5, n + 1)
        U = ca.MX.sym("U", 2, n)
        w = ca.vertcat(ca.vec(X), ca.vec(U))
        defects = X[:, 1:] - self.step.map(n)(X[:, :-1], U)
        nlp = {"x": w, "f": ca.sum2(self.stage(X[:, :-1], U)), "g": ca.vec(defects)}
        opts = {"expand": True, "print_time": False,
                "ipopt": {"print_level": 0, "max_iter": max_iter, "max_cpu_time": max_cpu,
                          # A defect of 1e-8 per step (IPOPT's default) adds up to ~1e-6 at the
                          # target over 10 000 steps: ask for 1e-12 (the replay error checks it).
                          "tol": 1e-10, "constr_viol_tol": 1e-12}}
        self.solver = ca.nlpsol("ipopt", "ipopt", nlp, opts)
        self.replay = self.step.mapaccum(n)
        self.build_seconds = time.time() - t0

    def bounds(self, p):
        n = self.n
        lo = np.full((5, n + 1), -np.inf)
        hi = np.full((5, n + 1), np.inf)
        if p["alpha_max"] is not None:
            lo[:2, :], hi[:2, :] = -p["alpha_max"], p["alpha_max"]
        lo[:2, 0] = hi[:2, 0] = p["alpha0"]
        lo[:2, n] = hi[:2, n] = p["alpha_end"]
        lo[2:, 0] = hi[2:, 0] = 0.0
        lo[2:, n] = hi[2:, n] = p["target"]
        ulo = np.full(2 * n, -np.inf)
        return (np.concatenate([lo.flatten("F"), ulo]), np.concatenate([hi.flatten("F"), -ulo]))

    def solve(self, p, alpha, guard=None, save=None):
        """IPOPT from the shape path alpha (2 x N+1, from alpha0 to alpha_end). With guard:
        first with the bound |alpha_i| <= guard, then without it from that solution (phase 2's
        result is what counts: an extremal of the problem as posed). With save (a path): the
        solution written there as CSV (save_path)."""
        n, h = self.n, self.h
        u0 = np.diff(alpha, axis=1) / h
        x0 = np.vstack([alpha[:, :1], np.zeros((3, 1))])
        X0 = np.hstack([x0, np.array(self.replay(x0, u0))])
        w = np.concatenate([X0.flatten("F"), u0.flatten("F")])
        t0, c0 = time.time(), time.process_time()
        extra = {}
        if guard is not None:
            w, st = self.ipopt(dict(p, alpha_max=guard), w)
            extra = {"guard": guard, "guard_status": st["return_status"], "guard_cost": self.cost(w)}
        w, st = self.ipopt(p, w)
        dt, dc = time.time() - t0, time.process_time() - c0
        X = w[: 5 * (n + 1)].reshape((n + 1, 5)).T
        U = w[5 * (n + 1):].reshape((n, 2)).T
        amax = float(np.max(np.abs(X[:2])))
        # Independent check of feasibility: replay the controls from (alpha0, e).
        end = np.array(self.replay(np.concatenate([p["alpha0"], [0, 0, 0]]), U))[:, -1]
        err = float(np.max(np.abs(end - np.concatenate([p["alpha_end"], p["target"]]))))
        inside = amax <= p["alpha_max"] + 1e-9 if p["alpha_max"] is not None else amax < math.pi
        if save:
            save_path(save, X, U, h)
        return {"status": st["return_status"], "cost": self.cost(w), "max_abs_alpha": amax,
                "admissible": bool(st["return_status"] == "Solve_Succeeded" and inside),
                "replay_error": err, "seconds": round(dt, 2), "cpu_seconds": round(dc, 2),
                "iterations": st["iter_count"], **extra}

    def ipopt(self, p, w0):
        lbx, ubx = self.bounds(p)
        sol = self.solver(x0=np.clip(w0, lbx, ubx), lbx=lbx, ubx=ubx, lbg=0, ubg=0)
        return np.array(sol["x"]).flatten(), self.solver.stats()

    def cost(self, w):
        X = w[: 5 * (self.n + 1)].reshape((self.n + 1, 5)).T
        U = w[5 * (self.n + 1):].reshape((self.n, 2)).T
        return float(np.sum(np.array(self.stage(X[:, :-1], U))))


def save_path(path, X, U, h):
    """IPOPT's solution as CSV, one row per step k = 0..N: t, the shape alpha_k, the position
    g_k and u_k (the last row repeats u_{N-1}; the columns of purcell-sim's trajectory.csv that
    a ("trajectory", CSV) start reads)."""
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    u = np.hstack([U, U[:, -1:]])
    t = h * np.arange(X.shape[1])
    cols = np.vstack([t, X, u]).T
    np.savetxt(path, cols, delimiter=",", fmt="%.17g", comments="",
               header="t_s,alpha1_rad,alpha2_rad,x_m,y_m,theta_rad,u1_rad_s,u2_rad_s")


# Start family, in mirror pairs: (kind, a, b, phi, turns, direction). An ellipse through
# alpha0 with radial semi-axis a (along phi, the centre at alpha0 - a (cos phi, sin phi)) and
# tangential semi-axis b, run `turns` times, counter-clockwise for direction +1; a figure-eight
# (a sin s, direction * b sin 2s) rotated by phi, centred at alpha0. The mirror of a start is phi + pi.
START_PAIRS = [  # phi in units of pi
    ("ellipse", 1.0, 1.0, 0.0, 1, +1),
    ("ellipse", 1.0, 1.0, 0.5, 1, -1),
    ("eight", 1.2, 0.6, 0.0, 1, +1),
    ("ellipse", 0.5, 0.5, 0.25, 2, +1),
    ("ellipse", 1.0, 1.0, 0.25, 1, +1),
    ("ellipse", 0.3, 0.3, 0.75, 1, -1),
    ("ellipse", 0.75, 1.5, 0.0, 1, -1),
    ("ellipse", 0.4, 0.6, 0.5, 3, +1),
    ("eight", 1.2, 0.6, 0.5, 1, -1),
    ("ellipse", 1.5, 0.75, 0.75, 1, -1),
    ("ellipse", 0.5, 0.5, 0.75, 2, -1),
    ("ellipse", 0.3, 0.3, 0.25, 1, +1),
]


def start_family():
    for kind, a, b, phi, turns, d in START_PAIRS:
        for mirrored in (False, True):
            yield (kind, a, b, (phi + (1.0 if mirrored else 0.0)) % 2.0, turns, d)


def start_label(s):
    if s[0] == "trajectory":
        return f"trajectory {os.path.basename(os.path.dirname(s[1]))}"
    kind, a, b, phi, turns, d = s
    return f"{kind} a={a} b={b} phi={phi:g}pi n={turns} {'ccw' if d > 0 else 'cw'}"


def start_path(s, alpha0, n, alpha_end=None):
    """Start s through alpha0, ridden along the straight path to alpha_end (default alpha0);
    ("trajectory", CSV): the shape path of purcell-sim's trajectory.csv."""
    if s[0] == "trajectory":
        rows = np.genfromtxt(s[1], delimiter=",", names=True)
        path = np.vstack([rows["alpha1_rad"], rows["alpha2_rad"]])
        if path.shape[1] != n + 1:
            raise SystemExit(f"{s[1]}: {path.shape[1] - 1} steps, the problem has {n}")
        return path
    kind, a, b, phi, turns, d = s
    alpha_end = alpha0 if alpha_end is None else alpha_end
    t = 2 * math.pi * turns * np.arange(n + 1) / n
    if kind == "ellipse":
        p, q = a * (np.cos(t) - 1), d * b * np.sin(t)
    else:
        p, q = a * np.sin(t), d * b * np.sin(2 * t)
    c, sn = math.cos(phi * math.pi), math.sin(phi * math.pi)
    path = np.vstack([c * p - sn * q, sn * p + c * q]) + np.array(alpha0)[:, None]
    path[:, -1] = alpha0  # exactly closed
    if list(alpha_end) != list(alpha0):
        path += np.outer(np.subtract(alpha_end, alpha0), np.arange(n + 1) / n)
        path[:, -1] = alpha_end
    return path


def load_done(path):
    done = {}
    if path and os.path.exists(path):
        for line in open(path):
            if line.strip():
                r = json.loads(line)
                done[(r["problem"], r["label"])] = r
    return done


def run(problems, args):
    done = load_done(args.jsonl)
    cache, results = {}, {}
    family = list(start_family())[: args.starts]
    print(f"{'problem':<20}{'start':>5}  {'label':<50}{'wall s':>8}{'CPU s':>8}{'cost':>12}{'max|a|':>8}"
          f"{'replay':>9}  status", flush=True)

    def model(p):
        return (steps_of(p), p["step"], tuple(p["links"]), p["drag"], p["ratio"])

    order = [model(p) for p in problems]  # problems sharing an IPOPT instance one after the other
    for p in sorted(problems, key=lambda p: order.index(model(p))):
        key = model(p)
        n = key[0]
        rows = []
        guards = [None] + ([args.guard] if args.guard and p["alpha_max"] is None else [])
        # A problem's own `trajectory` (purcell-sim's DIR/trajectory.csv) is its first start.
        mine = [("trajectory", p["trajectory"])] if p.get("trajectory") else []
        for guard, (i, s) in ((g, js) for g in guards for js in enumerate(mine + family)):
            label = start_label(s) + (f" guard {guard}" if guard else "")
            r = done.get((p["name"], label))
            if r is None:
                if key not in cache:
                    cache.clear()  # one instance at a time: each holds the whole NLP
                    cache[key] = Transcription(n, p["step"], p["links"], p["drag"], p["ratio"],
                                               args.max_cpu, args.max_iter, args.cost)
                    print(f"(IPOPT instance for N={n}, h={p['step']}: built in "
                          f"{cache[key].build_seconds:.1f} s)", flush=True)
                r = {"problem": p["name"], "start": i, "label": label}
                save = args.paths and os.path.join(args.paths, f"{p['name']}-{i}{'-guard' if guard else ''}.csv")
                r.update(cache[key].solve(p, start_path(s, p["alpha0"], n, p["alpha_end"]), guard, save))
                if args.jsonl:
                    with open(args.jsonl, "a") as f:
                        f.write(json.dumps(r) + "\n")
            rows.append(r)
            print(f"{p['name']:<20}{i:>5}  {r['label']:<50}{r['seconds']:>8.1f}{r['cpu_seconds']:>8.1f}{r['cost']:>12.7f}"
                  f"{r['max_abs_alpha']:>8.4f}{r['replay_error']:>9.1e}  {r['status']}"
                  f"{'' if r['admissible'] else ' (not admissible)'}", flush=True)
        results[p["name"]] = rows
    return results


def recorded(path):
    """The --jsonl file's starts, per problem, in file order (for --table)."""
    results = {}
    for r in load_done(path).values():
        results.setdefault(r["problem"], []).append(r)
    return results


def bench_table(path):
    """purcell-sim's side: per problem {cost, rel (its J/ref - 1), seconds} or {error, seconds},
    from the table `cargo bench -p purcell-benches --bench suite -- PROBLEMS.json` prints."""
    ours = {}
    for line in open(path):
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 10 or not cells[-1].endswith(" s"):
            continue  # not a problem's row
        name, cost, _, rel = cells[:4]
        seconds = float(cells[-1][:-2])
        try:
            ours[name] = {"cost": float(cost), "rel": None if rel == "–" else float(rel), "seconds": seconds}
        except ValueError:
            ours[name] = {"error": cost, "seconds": seconds}
    return ours


def summary(problems, results, ours):
    """The Markdown table of the module's doc. purcell-sim's difference to IPOPT, ours / IPOPT - 1,
    is taken through the bench's own full-precision J/ref - 1 where the problem lists a ref."""
    print("\n| problem | IPOPT cheapest admissible J | its max abs alpha, replay error "
          "| reached / admissible / converged / starts | IPOPT CPU s per start: min / median / max "
          "| purcell-sim J | purcell-sim / IPOPT - 1 | purcell-sim s |\n|---|---|---|---|---|---|---|---|")
    for p in problems:
        rows = results.get(p["name"], [])
        conv = [r for r in rows if r["status"] == "Solve_Succeeded"]
        adm = [r for r in rows if r["admissible"]]
        best = min(adm, key=lambda r: r["cost"]) if adm else None
        if best:
            hits = sum(abs(r["cost"] - best["cost"]) <= 1e-7 * best["cost"] for r in adm)
            ipopt = (f"{best['cost']:.10g} | {best['max_abs_alpha']:.4f}, {best['replay_error']:.0e} "
                     f"| {hits} / {len(adm)} / {len(conv)} / {len(rows)}")
        else:
            ipopt = f"none | | 0 / 0 / {len(conv)} / {len(rows)}" if rows else "not run | | "
        cpu = [r["cpu_seconds"] for r in rows]
        times = f"{min(cpu):.0f} / {statistics.median(cpu):.0f} / {max(cpu):.0f}" if cpu else ""
        o = ours.get(p["name"])
        if o is None:
            mine = "not in the bench's table | | "
        elif "error" in o:
            mine = f"{o['error']} | | {o['seconds']:.2f}"
        else:
            rel = ""
            if best and best["cost"] > 1e-12:
                exact = p["ref"] * (1 + o["rel"]) if p.get("ref") and o["rel"] is not None else o["cost"]
                rel = f"{exact / best['cost'] - 1:+.1e}"
            elif best:  # a zero optimum: the absolute difference
                rel = f"{o['cost'] - best['cost']:+.0e} (absolute)"
            mine = f"{o['cost']:.7f} | {rel} | {o['seconds']:.2f}"
        print(f"| {p['name']} | {ipopt} | {times} | {mine} |")


def check(args):
    """The transcription against two known extremals of the paper's problem."""
    p = full(PAPER)
    tr = Transcription(steps_of(p), p["step"], p["links"], p["drag"], p["ratio"], args.max_cpu, args.max_iter)
    print(f"IPOPT instance built in {tr.build_seconds:.1f} s")
    ok = True
    for s, want in CHECKS:
        r = tr.solve(p, start_path(s, p["alpha0"], tr.n))
        rel = abs(r["cost"] - want) / want
        ok &= rel < 1e-6
        print(f"{start_label(s):<44} J = {r['cost']:.10f} (want {want}, rel {rel:.1e}), max|a| "
              f"{r['max_abs_alpha']:.4f}, replay error {r['replay_error']:.1e}, {r['seconds']:.1f} s, {r['status']}")
    print("transcription check:", "PASSED" if ok else "FAILED")
    return ok


# Paper's problem: the second extremal purcell-sim finds (its report.json at commit aac81d3), and the
# suite's reference (largest |alpha_i| 3.0646).
CHECKS = [(("ellipse", 0.5, 0.5, 1.5, 2, -1), 0.9305278416030258), (("eight", 1.2, 0.6, 1.0, 1, +1), 0.6817478081948872)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("problems", nargs="?", help="problems file (suite format); default: the paper's problem")
    ap.add_argument("--only", help="comma-separated problem names")
    ap.add_argument("--starts", type=int, default=8, help=f"starts per problem (family of {2 * len(START_PAIRS)})")
    ap.add_argument("--jsonl", help="append one JSON line per start here; skip pairs already in it")
    ap.add_argument("--ours", metavar="BENCH.md",
                    help="the saved output of `cargo bench -p purcell-benches --bench suite -- PROBLEMS.json`")
    ap.add_argument("--table", action="store_true", help="run nothing: the table from the --jsonl file alone")
    ap.add_argument("--max-cpu", type=float, default=400.0, help="IPOPT max_cpu_time per start, seconds")
    ap.add_argument("--max-iter", type=int, default=3000, help="IPOPT max_iter per start")
    ap.add_argument("--guard", type=float, metavar="A",
                    help="also run every start in two phases: with |alpha_i| <= A, then without (problems without alpha_max)")
    ap.add_argument("--paths", metavar="DIR",
                    help="write each start's solution to DIR/PROBLEM-START.csv (t, alpha, g, u)")
    ap.add_argument("--check", action="store_true", help="check the transcription on the paper's problem")
    ap.add_argument("--cost", choices=["effort", "power"], default="effort",
                    help="the running cost (MODEL.md 11): effort h/2 |u|^2 or power h/2 u^T G(alpha) u")
    args = ap.parse_args()
    if args.table and not args.jsonl:
        ap.error("--table reads the --jsonl file")
    if ca is None and not args.table:
        raise SystemExit("CasADi is missing: pip install casadi")
    if args.check:
        raise SystemExit(0 if check(args) else 1)
    problems = json.load(open(args.problems)) if args.problems else [PAPER]
    if args.cost != "effort":  # the suite's references are effort costs
        problems = [{k: v for k, v in p.items() if k != "ref"} for p in problems]
    if args.only:
        names = args.only.split(",")
        problems = [p for p in problems if p["name"] in names]
    problems = [full(p) for p in problems]
    results = recorded(args.jsonl) if args.table else run(problems, args)
    summary(problems, results, bench_table(args.ours) if args.ours else {})

if __name__ == "__main__":
    main()
