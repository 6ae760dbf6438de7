"""The paper-style figures of one optimal gait, from the `purcell` package alone.

Solves the paper's problem (target x = y = 0.1 m, theta = 0, T = 100 s, h = 0.01 s, unit links,
k = 1, r = 2; or the target and options given) and writes four figures to OUT (default
`figures/`): the shape loop over the curvature of the connection (theta row), alpha(t), the
position (the path in the plane and x, y, theta over time) and the controls u(t).

    python examples/paper_figures.py [--target X,Y,THETA] [--alpha0 A1,A2] [--out DIR]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import purcell  # noqa: E402


def numbers(text):
    return tuple(float(v) for v in text.split(","))


def shape_loop(s, field, path):
    """The gait in the shape plane over the curvature's theta row (1/rad)."""
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    c = field.centres
    limit = np.abs(field.F[2]).max()
    mesh = ax.pcolormesh(c, c, field.F[2], cmap="RdBu_r", vmin=-limit, vmax=limit)
    fig.colorbar(mesh, ax=ax, label="curvature, theta row (1/rad)")
    ax.plot(s.alpha[:, 0], s.alpha[:, 1], "k", lw=1.5)
    ax.plot(*s.alpha[0], "ko")
    ax.set(xlabel="alpha1 (rad)", ylabel="alpha2 (rad)", aspect="equal")
    estimate = field.integral_over(s.alpha)
    ax.set_title(f"J = {s.cost:.5f} rad²/s; ∬F ≈ ({estimate[0]:.3f} m, {estimate[1]:.3f} m)")
    fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)


def over_time(t, rows, labels, ylabel, title, path):
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for row, label in zip(rows, labels, strict=True):
        ax.plot(t, row, label=label)
    ax.set(xlabel="t (s)", ylabel=ylabel, title=title)
    ax.legend()
    fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)


def position(s, path):
    fig, (plane, time) = plt.subplots(1, 2, figsize=(10, 4))
    plane.plot(s.g[:, 0], s.g[:, 1], "k")
    plane.plot(*s.g[-1, :2], "ro", label="target")
    plane.set(xlabel="x (m)", ylabel="y (m)", aspect="equal", title="path of the middle link")
    plane.legend()
    for k, label in enumerate(["x (m)", "y (m)", "theta (rad)"]):
        time.plot(s.t, s.g[:, k], label=label)
    time.set(xlabel="t (s)", title="position")
    time.legend()
    fig.savefig(path, dpi=150, bbox_inches="tight")
    plt.close(fig)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--target", type=numbers, default=(0.1, 0.1, 0.0))
    p.add_argument("--alpha0", type=numbers, default=(0.0, 0.0))
    p.add_argument("--out", type=Path, default=Path("figures"))
    a = p.parse_args()
    s = purcell.solve(a.target, alpha0=a.alpha0)
    field = purcell.field()
    a.out.mkdir(parents=True, exist_ok=True)
    shape_loop(s, field, a.out / "shape_loop.png")
    over_time(s.t, s.alpha.T, ["alpha1", "alpha2"], "rad", "shape", a.out / "alpha.png")
    position(s, a.out / "position.png")
    over_time(s.t[:-1], s.u.T, ["u1", "u2"], "rad/s", "controls", a.out / "controls.png")
    print(f"cost {s.cost:.10f}, mu {s.mu}, figures in {a.out}/")


if __name__ == "__main__":
    main()
