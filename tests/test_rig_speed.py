"""The start of a run on an unchanged system (issue 47, the E-sail rig against Exudyn).

A ``simulate`` call of the windless E-sail rig spent some 12 ms of CPU before its first
step (a quarter of its 400 steps' time in ``benchmarks/peers.py``): the band ordering of
the iteration matrix, the numba types of the compiled step's arguments and its entry
point, made again at every run, and the system described twice. What a solver derives
from the layout alone is now made once per layout (``Layout.derived``), the mass matrix
without scipy's ``block_diag``, and a run in which no Python could edit the system (no
observers, no step hooks, no Python in the step) does not describe it again at its end.
A system sums its mass matrix again only when its entries change, and a cable like a
recent one (element, mesh, mass per length) takes a copy of its mass matrix.
One small rig (a hub and three tethers of two elements with tip masses, the E-sail's
section), built once."""

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import BilinearForm, MeshLine, asm
from skfem.helpers import dot

import skfem_cable as sc
from skfem_cable.model import system as system_module
from skfem_cable.scenes import esail
from skfem_cable.solvers.galpha import GeneralizedAlpha

RUN = {"t_end": 1.0, "dt": 0.1, "rho_inf": 0.25}


def small_rig():
    """A hub, three radial tethers of 1 km x 2 elements pinned to its rim, tip masses,
    spinning about the hub axis (``benchmarks/peers.py``'s rig, smaller)."""
    cfg = esail.BaselineConfig()
    hub = sc.RigidBody.cylinder(cfg.hub_radius, cfg.hub_height, cfg.hub_density, name="hub")
    tethers, rims = [], []
    for k in range(3):
        e = np.array([0.0, np.cos(2 * np.pi * k / 3), np.sin(2 * np.pi * k / 3)])
        s = np.linspace(0.0, 1e3, 3)
        rims.append(cfg.hub_radius * e)
        tethers.append(sc.Cable(MeshLine(s), cfg.section, (cfg.hub_radius + s)[:, None] * e,
                                np.tile(e, (3, 1)), name=f"tether{k + 1}"))
    system = sc.System([hub, *tethers])
    for cable, rim in zip(tethers, rims):
        system.pin(cable.node(0), hub.point(rim))
        system.add_point_mass(cable.node(-1), cfg.remote_mass)
    v0 = system.rigid_motion_velocity(system.q0, [cfg.spin_rate, 0.0, 0.0])
    return system, hub, sc.State(system, system.q0, v=v0)


@pytest.fixture(scope="module")
def rig():
    return small_rig()


def test_a_run_start_reuses_what_the_layout_derives(rig):
    """Two integrators of one layout share its band ordering, its solver's plan (not its
    work arrays: ``PatternSolver.renewed``), its terms module, the numba type of the
    step's held arguments and the step's entry point, not their arrays; a system edited
    since gets its own."""
    system, _, initial = rig
    a, b = (GeneralizedAlpha(system, rho_inf=0.25) for _ in range(2))
    for g in (a, b):
        g.initialize(initial.q, initial.v, 0.0)
        assert g.step(0.1)[0]
    assert a.lay is b.lay
    assert a.solver.ordering is b.solver.ordering
    assert a.compiled.kind is b.compiled.kind and a.compiled.entry is b.compiled.entry
    assert a.compiled.arrays["q1"] is not b.compiled.arrays["q1"]
    assert a.solver.lu[0][0][1] is not b.solver.lu[0][0][1]  # each its own factor
    assert a.solver.lu[0][3] is b.solver.lu[0][3]  # one plan: the values' places
    assert a.compiled.terms[:2] == b.compiled.terms[:2]  # one terms module
    assert a.compiled.blob is not b.compiled.blob  # each its own terms held
    np.testing.assert_array_equal(a.q, b.q)
    edited, _, _ = small_rig()
    c = GeneralizedAlpha(edited, rho_inf=0.25)
    assert c.lay is not a.lay and c.solver.ordering is not a.solver.ordering
    for x, y in zip(a.solver.ordering, c.solver.ordering):
        np.testing.assert_array_equal(x, y)


def test_runs_on_a_kept_layout_are_bit_for_bit(rig):
    """A run on the kept layout (its ordering, types and entry point reused) is the run on
    a system built afresh, bit for bit, books included."""
    system, _, initial = rig
    sc.simulate(system, initial=initial, **RUN)
    again = sc.simulate(system, initial=initial, **RUN)
    fresh_system, _, fresh_initial = small_rig()
    fresh = sc.simulate(fresh_system, initial=fresh_initial, **RUN)
    for name in ("q", "v", "a", "lam"):
        np.testing.assert_array_equal(getattr(again, name), getattr(fresh, name))
    for name, values in fresh.energy.items():
        np.testing.assert_array_equal(again.energy[name], values)
    assert again.stats["newton"] == fresh.stats["newton"]


def block_diag_mass(system):
    """The mass matrix as ``System.mass_matrix`` built it before: scipy's
    ``block_diag`` of the bodies' blocks, then the point masses."""
    M = sp.block_diag([b.mass_matrix() for b in system.bodies], format="coo")
    rows, cols, vals = [M.row], [M.col], [M.data]
    for point_mass in system.point_masses:
        r, c, m = point_mass.bind(system).mass
        rows.append(r)
        cols.append(c)
        vals.append(m)
    return sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                 np.concatenate(cols))), shape=M.shape)


@pytest.mark.parametrize("hub_block", [None, "coo with duplicates", "dense"])
def test_mass_matrix_is_block_diag_bit_for_bit(hub_block):
    """The same CSR arrays, byte for byte, as ``block_diag``: CSR blocks (cables, the hub),
    a COO block with duplicate entries and a dense one; point masses on cable nodes and on
    a body point."""
    system, hub, _ = small_rig()
    system.add_point_mass(hub.point([0.1, 0.2, 0.3]), 7.0)
    M = hub.mass_matrix()
    if hub_block == "coo with duplicates":  # each entry split in two halves
        coo = M.tocoo()
        hub.mass_matrix = lambda: sp.coo_matrix((np.r_[coo.data / 2, coo.data / 2], (
            np.r_[coo.row, coo.row], np.r_[coo.col, coo.col])), shape=coo.shape)
    elif hub_block == "dense":
        hub.mass_matrix = lambda: M.toarray()
    ours, theirs = system.mass_matrix(), block_diag_mass(system)
    assert ours.shape == theirs.shape
    for field in ("indptr", "indices", "data"):
        assert getattr(ours, field).dtype == getattr(theirs, field).dtype
        assert getattr(ours, field).tobytes() == getattr(theirs, field).tobytes()


def test_a_run_describes_the_system_again_only_after_the_users_code(rig, monkeypatch):
    """Without observers or controllers a run describes the system once (at its start,
    ``current_layout``); with an observer, or Python in its step (``compiled=False``
    here; a term's Python ``add`` hook likewise), also at its end, where an edit is
    refused."""
    system, _, initial = rig
    system.current_layout()
    calls = []

    def counted(s, *args, **kwargs):
        calls.append(s)
        return describe(s, *args, **kwargs)

    describe = system_module.describe_system
    monkeypatch.setattr(system_module, "describe_system", counted)
    sc.simulate(system, initial=initial, **RUN)
    assert len(calls) == 1

    class Watcher(sc.Observer):
        def saved(self, run, step):
            return None

    calls.clear()
    sc.simulate(system, initial=initial, observers=[Watcher()], **RUN)
    assert len(calls) == 2

    calls.clear()
    sc.simulate(system, initial=initial, compiled=False, t_end=0.2, dt=0.1, rho_inf=0.25)
    assert len(calls) == 2


def test_the_kept_mass_matrix_follows_every_edit():
    """``System.mass_matrix`` keeps the summed matrix while its entries are unchanged: an
    edit of a point mass, of a body's block in place or of a section is in the next one
    (and in a new layout), and a change to a returned matrix is not in the system's."""
    system, _, _ = small_rig()
    tether = system.bodies[1]
    layout = system.current_layout()
    before = system.mass_matrix().toarray()
    system.mass_matrix().data[:] = 0.0
    assert np.array_equal(system.mass_matrix().toarray(), before)
    assert system.current_layout() is layout

    system.point_masses[0].mass *= 2
    assert not np.array_equal(system.mass_matrix().toarray(), before)
    assert system.current_layout() is not layout
    system.point_masses[0].mass /= 2
    assert np.array_equal(system.mass_matrix().toarray(), before)

    layout = system.current_layout()
    tether.mass_matrix().data[0] *= 3  # the body's own block, in place
    edited = system.mass_matrix().toarray()
    assert np.count_nonzero(edited != before) == 1
    assert system.current_layout() is not layout
    tether.section = dataclasses.replace(tether.section, rho=2 * tether.section.rho)
    assert not np.array_equal(system.mass_matrix().toarray(), edited)


def test_a_cable_like_a_recent_one_takes_a_copy_of_its_mass_matrix():
    """A cable with the element, mesh and mass per length of a recent one gets the mass
    matrix of its own assembly, byte for byte, in an object of its own; another mass
    per length or mesh gets another."""
    sec = sc.Section.circular(1e-3, 2e11, 7850.0)
    a, b = (sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sec) for _ in range(2))
    Ma, Mb = a.mass_matrix(), b.mass_matrix()
    assert Mb is not Ma
    mu = sec.mass_per_length
    own = asm(BilinearForm(lambda u, v, w: mu * dot(u, v)), b._exact).tocsr()
    for field in ("indptr", "indices", "data"):
        assert getattr(Mb, field).dtype == getattr(own, field).dtype
        assert getattr(Mb, field).tobytes() == getattr(own, field).tobytes()
    Ma.data[:] = 0.0  # an edit of one cable's matrix is its own
    again = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sec).mass_matrix()
    assert again.data.tobytes() == own.data.tobytes()
    heavy = dataclasses.replace(sec, rho=2 * sec.rho)
    assert np.array_equal(sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, heavy).mass_matrix().data,
                          2 * own.data)
    longer = sc.Cable.straight([0, 0, 0], [2, 0, 0], 4, sec).mass_matrix()
    assert not np.array_equal(longer.data, own.data)
