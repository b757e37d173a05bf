"""Parameter studies on Dask: parallel efficiency of a sweep of 8 E-sail runs on 2 local
worker processes against the same runs one after the other, and the overhead per task.

The 8 runs are the baseline sail (12 tethers x 5 elements, dt = 0.1 s) at sailing angles
0, 10, ..., 70 deg for ``t_end`` seconds.  Serial: the sweep's own task function
(``study.run_point``) called 8 times in this process, kernels loaded.  Parallel:
``sc.sweep`` on 2 worker processes, once including the start of the ``LocalCluster``
("cold") and once on a started cluster whose workers ran one task ("warm").  Each time is
the minimum of the repeats, measured side by side.  Overheads: a trivial task through the
scheduler (round trip, and per task in a batch of 400), the sweep's bookkeeping per point
(the study run again: every run found finished and reused), a worker's first task (its
kernels loaded: the difference to the same task again), and the peak memory of a worker
against this process after the serial runs.  The machine's other jobs share its cores:
the CPU time of the busiest worker over the serial CPU time is the wall ratio the sweep
reaches when the workers have a core each.
Run ``python benchmarks/sweep_efficiency.py [--quick]`` (``--quick``: runs of 150 s, one
repeat).
"""

import resource
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import skfem_cable as sc
from skfem_cable.cli.bench import arguments
from skfem_cable.scenes.catalog import esail_scene
from skfem_cable.study import run_name, run_point

SETTINGS = {"full": {"t_end": 600.0, "repeats": 3}, "quick": {"t_end": 150.0, "repeats": 1}}
ALPHAS = tuple(range(0, 71, 10))


def peak_memory_mb():
    """Peak resident memory of the calling process so far (MB)."""
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak / 2**20 if sys.platform == "darwin" else peak / 2**10


def serial(folder, fixed):
    """Wall and CPU time of the 8 runs one after the other in this process."""
    start, cpu = time.perf_counter(), time.process_time()
    for alpha in ALPHAS:
        params = {"alpha": alpha, **fixed}
        record = run_point(esail_scene, params, folder / run_name(esail_scene, params),
                           overwrite=True)
        assert record["status"] == "complete", record["error"]
    return time.perf_counter() - start, time.process_time() - cpu


def parallel(folder, fixed, client=None):
    """Wall time of the sweep of the 8 runs on ``client`` (None: a new 2-worker local
    cluster, its start included), the CPU time of its busiest worker (None without
    ``client``) and the study."""
    cpu = client.run(time.process_time) if client else None
    start = time.perf_counter()
    study = sc.sweep(esail_scene, {"alpha": list(ALPHAS)}, client=client, store=folder,
                     fixed=fixed, workers=None if client else 2, overwrite=True,
                     progress=False)
    wall = time.perf_counter() - start
    assert (study.status == "complete").all(), study.error.values
    if client:
        cpu = max(t - cpu[w] for w, t in client.run(time.process_time).items())
    return wall, cpu, study


def task_overheads(client, n=400, repeats=30):
    """Round trip of one trivial task (min and median over ``repeats``, ms) and the wall
    per task of ``n`` trivial tasks submitted at once (ms)."""
    trips = []
    for k in range(repeats):
        start = time.perf_counter()
        client.submit(abs, -k, pure=False).result()
        trips.append(time.perf_counter() - start)
    start = time.perf_counter()
    client.gather(client.map(abs, range(-n, 0), pure=False))
    batch = (time.perf_counter() - start) / n
    return 1e3 * min(trips), 1e3 * float(np.median(trips)), 1e3 * batch


def main(argv=None):
    """Parse the arguments, measure and print; returns the rows."""
    from dask.distributed import Client, LocalCluster

    args = arguments(__doc__, "runs of 150 s, one repeat", argv)
    cfg = SETTINGS["quick" if args.quick else "full"]
    fixed = {"t_end": cfg["t_end"], "elements": 5}
    root = Path(tempfile.mkdtemp(prefix="sweep_efficiency_"))
    try:
        run_point(esail_scene, {"alpha": 0.0, "t_end": 1.0}, root / "warm")  # kernels
        walls = {"serial": [], "cold": [], "warm": []}
        cpus = {"serial": [], "warm": []}
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            first = client.gather([client.submit(run_point, esail_scene, {"alpha": 0.0,
                                                 "t_end": 1.0, "elements": 5},
                                                 root / f"first{k}", pure=False,
                                                 workers=[w])
                                   for k, w in enumerate(client.scheduler_info()["workers"])])
            again = client.gather([client.submit(run_point, esail_scene, {"alpha": 0.0,
                                                 "t_end": 1.0, "elements": 5},
                                                 root / f"again{k}", pure=False,
                                                 workers=[w])
                                   for k, w in enumerate(client.scheduler_info()["workers"])])
            for _ in range(cfg["repeats"]):
                wall, cpu = serial(root / "serial", fixed)
                walls["serial"].append(wall)
                cpus["serial"].append(cpu)
                walls["cold"].append(parallel(root / "cold", fixed)[0])
                wall, cpu, study = parallel(root / "warm", fixed, client)
                walls["warm"].append(wall)
                cpus["warm"].append(cpu)
            start = time.perf_counter()
            reused = sc.sweep(esail_scene, {"alpha": list(ALPHAS)}, client=client,
                              store=root / "warm", fixed=fixed, progress=False)
            bookkeeping = (time.perf_counter() - start) / len(ALPHAS)
            assert reused.reused.all()
            trip_min, trip_median, batch = task_overheads(client)
            worker_mb = max(client.run(peak_memory_mb).values())
        best = {k: min(v) for k, v in walls.items()}
        load = np.mean([a["task_wall_time"] - b["task_wall_time"] for a, b in zip(first, again)])
        rows = [{"t_end_s": cfg["t_end"], "runs": len(ALPHAS), "workers": 2,
                 "serial_s": best["serial"], "cold_s": best["cold"], "warm_s": best["warm"],
                 "cold_ratio": best["cold"] / best["serial"],
                 "warm_ratio": best["warm"] / best["serial"],
                 "busiest_worker_cpu_ratio": min(cpus["warm"]) / min(cpus["serial"]),
                 "run_wall_mean_s": float(study.wall_time.mean()),
                 "task_round_trip_min_ms": trip_min, "task_round_trip_median_ms": trip_median,
                 "task_in_batch_ms": batch, "sweep_bookkeeping_per_point_ms": 1e3 * bookkeeping,
                 "first_task_load_s": float(load), "worker_peak_mb": worker_mb,
                 "serial_process_peak_mb": peak_memory_mb()}]
    finally:
        shutil.rmtree(root, ignore_errors=True)
    r = rows[0]
    print(f"| {r['runs']} E-sail runs of {r['t_end_s']:g} s | wall [s] | / serial |")
    print("|---|---|---|")
    print(f"| serial, one process | {r['serial_s']:.2f} | 1 |")
    print(f"| 2 workers, cluster start included | {r['cold_s']:.2f} | {r['cold_ratio']:.3f} |")
    print(f"| 2 workers, started cluster | {r['warm_s']:.2f} | {r['warm_ratio']:.3f} |")
    print(f"\nCPU time of the busiest worker / CPU time of the serial runs: "
          f"{r['busiest_worker_cpu_ratio']:.3f} (the wall ratio on an otherwise idle machine)")
    print(f"mean simulate wall per run in the sweep: {r['run_wall_mean_s']:.2f} s")
    print(f"trivial task round trip: min {trip_min:.2f} ms, median {trip_median:.2f} ms; "
          f"in a batch of 400: {batch:.2f} ms per task")
    print(f"sweep bookkeeping per point (all runs reused): {1e3 * bookkeeping:.0f} ms")
    print(f"a worker's first task loads its kernels: +{load:.2f} s")
    print(f"peak memory: worker {worker_mb:.0f} MB, this process after the serial runs "
          f"{r['serial_process_peak_mb']:.0f} MB")
    return rows


if __name__ == "__main__":
    main()
