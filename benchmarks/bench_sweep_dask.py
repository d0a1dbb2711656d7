"""Sweep executors side by side: in-process, local processes, a dask.distributed LocalCluster.

One command:  python benchmarks/bench_sweep_dask.py [--grid N] [--periods P] [--backend numpy|c|auto]

Runs the same sweep (rod, theta(0) = 0.06, theta'(0) = 0.01, criterion mean, 100 steps per drive
period) three ways, prints the wall time of each and the ratios, and checks that the three give the
same bytes.  Also prints, for the Floquet-guided pruning (docs/experiments.md), how many
trajectories it integrated and whether its map equals the full one, per criterion.
"""

import argparse
import time

import numpy as np

from pendulab.numerics import sweep as S


def run(args):
    spec = S.make_spec(S.SystemSpec("rod"), grid=args.grid, theta_init=0.06, omega_init=0.01,
                       periods=args.periods, steps_per_period=100, chunk_size=args.chunk)
    S.first_order_system(spec.system)
    t = time.perf_counter()
    serial = S.sweep(spec, executor="serial", backend=args.backend, quiet=True)
    t_serial = time.perf_counter() - t
    t = time.perf_counter()
    procs = S.sweep(spec, executor="processes", workers=2, backend=args.backend, quiet=True)
    t_procs = time.perf_counter() - t
    import distributed
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as lc, distributed.Client(lc) as client:
        t = time.perf_counter()
        client.wait_for_workers(2)
        t_start = time.perf_counter() - t
        t = time.perf_counter()
        remote = S.sweep(spec, dask=client, backend=args.backend, quiet=True)
        t_dask = time.perf_counter() - t
    same = all(np.array_equal(serial.stats[k], o.stats[k]) for o in (procs, remote) for k in S.STATS)
    print(f"sweep {args.grid}x{args.grid}, {args.periods} periods x 100 steps, backend "
          f"{serial.backends}, {len(S.chunks(spec.cells, spec.chunk_size))} chunks")
    print(f"  in-process          {t_serial:8.2f} s   (ratio 1)")
    print(f"  local processes (2) {t_procs:8.2f} s   (ratio {t_procs / t_serial:.2f})")
    print(f"  dask LocalCluster   {t_dask:8.2f} s   (ratio {t_dask / t_serial:.2f}; cluster start "
          f"{t_start:.2f} s not included)")
    print(f"  identical bytes: {same}; stable count {serial.count}")
    for crit in ("mean", "mean-abs", "bounded"):
        for ic in ((0.06, 0.01), (0.1, 0.1)):
            s2 = S.replace(spec, criterion=crit, initial=(ic,))
            full = S.sweep(s2, backend=args.backend, quiet=True, executor="serial")
            pr = S.pruned_sweep(s2, backend=args.backend, quiet=True, executor="serial")
            print(f"  prune {crit:8s} IC {ic}: integrated {pr.simulated} of {s2.cells} "
                  f"({s2.cells - pr.simulated} saved, {100 * (1 - pr.simulated / s2.cells):.0f}%), "
                  f"maps equal: {bool(np.array_equal(full.stable, pr.stable))}, "
                  f"time {full.seconds:.2f} s full vs {pr.seconds:.2f} s pruned")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--grid", type=int, default=40)
    p.add_argument("--periods", type=int, default=300)
    p.add_argument("--chunk", type=int, default=S.CHUNK_SIZE)
    p.add_argument("--backend", default="numpy")
    run(p.parse_args())
