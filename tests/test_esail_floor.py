"""A guard against the silent rot of ``benchmarks/esail_floor.py`` (issue 47, "close to the
limit"): its parts run on a 2-tether rig against the step as it is compiled today.  The
script had looked up the kernels of a per-system step module (``k0``, ``k1``) after the
step came to be compiled once per machine: ``AttributeError`` at its first timed part.
And its quick run.  No timing is asserted."""

import json

import numpy as np
import pytest
from test_benchmarks import BENCH, load

from skfem_cable.scenes import esail
from skfem_cable.util.jsonable import jsonable


@pytest.fixture(scope="module")
def floor():
    return load(BENCH / "esail_floor.py")


@pytest.fixture(scope="module")
def rig(floor):
    """The counts of 12 steps of a 2-tether rig of 2 elements per tether, its Newton step
    and integrator, the times of its parts (one loop each)."""
    scene = esail.build(esail.BaselineConfig(n_tethers=2), 10.0, 2)
    counts, newton, integrator = floor.run_counts(scene, 12, 1)
    return counts, newton, integrator, floor.part_times(newton, integrator, 1)


def test_counts_of_a_step(rig):
    """Every step evaluates the residual at least once and solves once per evaluation at
    most (a converged step ends on a correction or on a residual)."""
    counts = rig[0]
    assert counts["evaluations"] >= 1.0 and 0.0 < counts["corrections"] <= \
        counts["evaluations"] + 1e-12 and counts["factorizations"] > 0.0


def test_every_part_is_timed(rig, floor):
    """The cable kernel and the solar wind, each without and with its tangent, the whole
    residual both ways, the factorization and the solve: one positive time each."""
    times = rig[3]
    kernels = [(name, tangent) for name in (*floor.KERNELS, "residual")
               for tangent in (False, True)]
    assert set(times) == {*kernels, "factor", "solve"}
    assert all(np.isfinite(t) and t > 0.0 for t in times.values())


def test_rows_of_the_table(rig, floor):
    """The table's six compiled parts, their work counted on the rig's 4 elements and its
    band LU: positive flops and bytes, the counts of the run per step."""
    counts, newton, integrator, times = rig
    assert floor.elements(integrator) == 4
    flops, nbytes = floor.counted(newton, integrator)
    rows = floor.parts(counts, times, flops, nbytes)
    assert len(rows) == 6
    assert all(fl > 0 and by > 0 for _, _, fl, by, _ in rows)
    assert [per_step for _, per_step, *_ in rows] == [counts["evaluations"]] * 3 + \
        [counts["factorizations"]] * 2 + [counts["corrections"]]



def test_bench_quick_runs_the_floor(rig, floor, capsys):
    """``skfem-cable bench --quick esail_floor``'s run (the script's ``main(["--quick"])``,
    what the command's child process calls: the machine's peaks in a fresh process, 120
    steps of the 12-tether rig, its parts): the table printed, the figures (as the JSON
    record holds them) have the six parts and a step above its floor.  In this process,
    after ``rig``: the compiled loops that time the parts are those of ``rig`` (about 15 s
    of compiling in a fresh process; the command's plumbing is tested on cheaper
    benchmarks in test_benchmarks.py)."""
    figures = json.loads(json.dumps(jsonable(floor.main(["--quick"]))))
    assert "times its scalar floor" in capsys.readouterr().out
    assert len(figures["rows"]) == 6
    step = figures["step"]
    assert step["measured_us"] > step["scalar_floor_us"] > step["floor_us"] > 0.0
