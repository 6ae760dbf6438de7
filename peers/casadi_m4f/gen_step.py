#!/usr/bin/env python3
"""Peer comparison (issues 4 and 14): the same control-law step as a CasADi expression graph,
exported as C, with casadi_real = float for the Cortex-M4F harness in this directory or
double for the host harness in ../casadi_host.

The step is MODEL.md section 5 with two fixed-point passes, written the way a CasADi user
would: W_xi and W_alpha from resistive-force theory, A = W_xi^-1 W_alpha by CasADi's solve,
dA/dalpha by CasADi's AD, dexp and exp from short series in omega (per-step |omega| ~ 1e-3;
closed forms divide by omega^3), the position as (x, y, theta) with cos/sin of theta each step.

usage: gen_step.py COSTATE_JSON OUT_DIR [--real float|double]
       (writes step.c, step.h, costate.h; default float)
"""
import argparse
import json
import os
import sys

import casadi as ca


def connection(alpha, links, ratio):
    """A(alpha) (3x2) with W_xi xi + W_alpha alpha_dot = 0 (MODEL.md sections 1-2)."""
    l0, l1, l2 = links
    r = ratio
    a1, a2 = alpha[0], alpha[1]
    # Each link: centre c, unit tangent t, length l; velocity of the centre from body twist
    # (vx, vy, w) and joint rate: v_c = (vx - w c_y, vy + w c_x) + d c/d alpha * alpha_dot.
    links_geo = []
    c1 = ca.vertcat(l0 / 2 + l1 / 2 * ca.cos(a1), l1 / 2 * ca.sin(a1))
    t1 = ca.vertcat(ca.cos(a1), ca.sin(a1))
    c2 = ca.vertcat(-l0 / 2 - l2 / 2 * ca.cos(a2), -l2 / 2 * ca.sin(a2))
    t2 = ca.vertcat(ca.cos(a2), ca.sin(a2))
    c0 = ca.vertcat(0, 0)
    t0 = ca.vertcat(1, 0)
    links_geo = [(c0, t0, l0, 0), (c1, t1, l1, 1), (c2, t2, l2, 2)]
    w_xi = ca.SX.zeros(3, 3)
    w_al = ca.SX.zeros(3, 2)
    for c, t, l, idx in links_geo:
        n = ca.vertcat(-t[1], t[0])
        # Velocity of the centre per unit (vx, vy, w): columns e1, e2, (-c_y, c_x).
        jv_xi = ca.horzcat(ca.vertcat(1, 0), ca.vertcat(0, 1), ca.vertcat(-c[1], c[0]))
        jw_xi = ca.horzcat(0, 0, 1)
        jv_al = ca.SX.zeros(2, 2)
        jw_al = ca.SX.zeros(1, 2)
        if idx > 0:
            col = idx - 1
            jv_al[:, col] = ca.jacobian(c, alpha[col])
            jw_al[0, col] = 1
        drag = l * (t @ t.T + r * n @ n.T)
        rot = r * l ** 3 / 12
        # Force F = -drag v, moment about the body origin c x F + (-rot w).
        def wrench(jv, jw):
            f = drag @ jv
            m = c[0] * f[1, :] - c[1] * f[0, :] + rot * jw
            return ca.vertcat(f, m)

        w_xi += wrench(jv_xi, jw_xi)
        w_al += wrench(jv_al, jw_al)
    return ca.solve(w_xi, w_al)


def step_function(links, ratio, h, passes=2):
    alpha = ca.SX.sym("alpha", 2)
    g = ca.SX.sym("g", 3)  # x, y, theta
    xi = ca.SX.sym("xi", 2)
    mu = ca.SX.sym("mu", 3)
    a = connection(alpha, links, ratio)
    da = [ca.jacobian(a[:, j], alpha) for j in range(2)]  # da[j][row, i] = dA[row, j]/dalpha_i
    x, y, th = g[0], g[1], g[2]
    c, s = ca.cos(th), ca.sin(th)
    # m = Ad_g^T mu.
    m = ca.vertcat(c * mu[0] + s * mu[1], -s * mu[0] + c * mu[1], y * mu[0] - x * mu[1] + mu[2])

    def solve_u(zeta):
        # B_ij = zeta^T dA/dalpha_i e_j.
        b = ca.SX.zeros(2, 2)
        for i in range(2):
            for j in range(2):
                b[i, j] = ca.dot(zeta, da[j][:, i])
        u = ca.solve(ca.SX.eye(2) - h * b, xi - a.T @ zeta)
        return u, b

    def coefficients(w):
        z = w * w
        sinc = 1 - z / 6 * (1 - z / 20 * (1 - z / 42))
        b = w / 2 * (1 - z / 12 * (1 - z / 30 * (1 - z / 56)))
        c2 = 0.5 * (1 - z / 12 * (1 - z / 30))
        c3 = (1 - z / 20 * (1 - z / 42)) / 6
        return sinc, b, c2, c3

    zeta = m
    for _ in range(passes + 1):
        u, b = solve_u(zeta)
        X = -h * (a @ u)
        sa, sb, c2, c3 = coefficients(X[2])
        q1 = c2 * X[1] + c3 * X[2] * X[0]
        q2 = c3 * X[2] * X[1] - c2 * X[0]
        zeta = ca.vertcat(sa * m[0] + sb * m[1], sa * m[1] - sb * m[0], q1 * m[0] + q2 * m[1] + m[2])
    xi_next = xi + h * (b @ u)
    dx = sa * X[0] - sb * X[1]
    dy = sb * X[0] + sa * X[1]
    g_next = ca.vertcat(x + c * dx - s * dy, y + s * dx + c * dy, th + X[2])
    return ca.Function(
        "step", [alpha, g, xi, mu], [u, alpha + h * u, g_next, xi_next],
        ["alpha", "g", "xi", "mu"], ["u", "alpha_next", "g_next", "xi_next"],
    )


def self_check():
    """The graph against MODEL.md section 7 (A at (0.5, -0.3) and one f64 step, 5 passes)."""
    alpha = ca.SX.sym("alpha", 2)
    a = ca.Function("a", [alpha], [connection(alpha, [1.0, 1.0, 1.0], 2.0)])
    want_a = [[-0.0524221297521321, -0.00701686926608808],
              [0.159747833925603, -0.161423254304907], [0.251599627307099, 0.261512677482497]]
    got = a([0.5, -0.3]).full()
    assert all(abs(got[i][j] - want_a[i][j]) < 1e-13 for i in range(3) for j in range(2)), got
    step = step_function([1.0, 1.0, 1.0], 2.0, 0.01, passes=5)
    u, al, g, xi = step([0.3, -0.4], [0.05, -0.02, 0.2], [0.01, -0.03], [1.5, 13.2, 0.6])
    want = [(u, [-1.9485070881797708, 2.204985349281734]),
            (al, [0.2805149291182023, -0.37795014650718267]),
            (g, [0.04918563550870081, -0.013271901098288786, 0.19942863681122489]),
            (xi, [0.03179965609005496, -0.019447012540811347])]
    for got, ref in want:
        got = got.full().ravel()
        assert all(abs(a - b) < 1e-12 * max(1.0, abs(b)) for a, b in zip(got, ref)), (got, ref)


def main():
    self_check()
    parser = argparse.ArgumentParser(usage=__doc__)
    parser.add_argument("costate")
    parser.add_argument("out")
    parser.add_argument("--real", choices=["float", "double"], default="float")
    args = parser.parse_args()
    with open(args.costate) as f:
        cs = json.load(f)
    out = args.out
    os.makedirs(out, exist_ok=True)
    model = cs["model"]
    fun = step_function(model["links"], model["ratio"], cs["h"])
    cwd = os.getcwd()
    os.chdir(out)
    try:
        fun.generate("step.c", {"casadi_real": args.real, "with_header": True})
    finally:
        os.chdir(cwd)
    fmt = "%.9ef" if args.real == "float" else "%.17e"
    with open(os.path.join(out, "costate.h"), "w") as f:
        f.write("/* Generated by gen_step.py from %s. */\n" % args.costate)
        f.write("#define STEPS %d\n" % cs["steps"])
        f.write("#define SZ_ARG %d\n#define SZ_RES %d\n#define SZ_IW %d\n#define SZ_W %d\n"
                % (fun.sz_arg(), fun.sz_res(), fun.sz_iw(), fun.sz_w()))
        arrays = [("ALPHA0", cs["alpha0"]), ("MU", cs["mu"]), ("XI0", cs["xi0"]),
                  ("TARGET", cs["target"]), ("LINKS", model["links"]),
                  ("MODEL", [model["drag"], model["ratio"], cs["h"]])]
        for name, values in arrays:
            f.write("static const %s %s[%d] = {%s};\n"
                    % (args.real, name, len(values), ", ".join(fmt % v for v in values)))
    print("generated %s/step.c (%s, %d nodes)" % (out, args.real, fun.n_instructions()))


if __name__ == "__main__":
    main()
