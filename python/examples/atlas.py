"""A sweep's cost map: the optimal cost over a lattice of targets, from `purcell` alone.

Solves every target of the lattice (`purcell.sweep`, or `purcell.distributed.sweep` on a local
Dask cluster with --dask N) and writes OUT/atlas.png (the cost over the (x, y) plane at the
first theta, cells whose extremal the certificates do not vouch for, or without one, marked)
and OUT/atlas.csv (the records).

    python examples/atlas.py [--x=FROM:TO:COUNT] [--y=...] [--theta=...] [--horizon T]
                             [--step H] [--dask WORKERS] [--out DIR]
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import purcell  # noqa: E402


def run(a):
    kw = {"horizon": a.horizon, "step": a.step, "starts": a.starts}
    if not a.dask:
        return purcell.sweep(a.x, a.y, a.theta, **kw)
    import distributed

    import purcell.distributed as on_dask

    with (
        distributed.LocalCluster(n_workers=a.dask, threads_per_worker=1) as cluster,
        distributed.Client(cluster) as client,
    ):
        return on_dask.sweep(client, a.x, a.y, a.theta, **kw)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--x", default="-0.2:0.2:9")
    p.add_argument("--y", default="-0.2:0.2:9")
    p.add_argument("--theta", default="0")
    p.add_argument("--horizon", type=float, default=100.0)
    p.add_argument("--step", type=float, default=0.01)
    p.add_argument("--starts", type=int, default=None, help="default: the solver's budget")
    p.add_argument("--dask", type=int, default=0, help="workers of a local Dask cluster")
    p.add_argument("--out", type=Path, default=Path("atlas"))
    a = p.parse_args()
    records = run(a)
    a.out.mkdir(parents=True, exist_ok=True)
    with open(a.out / "atlas.csv", "w") as f:
        f.write(",".join(purcell.COLUMNS) + "\n")
        for r in records:
            f.write(",".join("" if r[k] is None else str(r[k]) for k in purcell.COLUMNS) + "\n")
    theta = records[0]["theta"]
    rows = [r for r in records if r["theta"] == theta]
    xs = sorted({r["x"] for r in rows})
    ys = sorted({r["y"] for r in rows})
    cost = np.full((len(ys), len(xs)), np.nan)
    fig, ax = plt.subplots(figsize=(6, 5))
    for r in rows:
        i, j = xs.index(r["x"]), ys.index(r["y"])
        if r["cost"] is not None:
            cost[j, i] = r["cost"]
        if r["status"] != "ok":
            ax.plot(r["x"], r["y"], "kx")
    mesh = ax.pcolormesh(xs, ys, cost, shading="nearest", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label="J (rad²/s)")
    ax.set(xlabel="target x (m)", ylabel="target y (m)", aspect="equal")
    ax.set_title(f"optimal cost, theta = {theta} rad, T = {a.horizon} s (x: not certified)")
    fig.savefig(a.out / "atlas.png", dpi=150, bbox_inches="tight")
    plt.close(fig)
    solved = sum(r["status"] == "ok" for r in records)
    print(f"{len(records)} targets, {solved} certified, map in {a.out}/atlas.png")


if __name__ == "__main__":
    main()
