"""A run store that explains itself (``docs/output.md``): ``xarray.open_zarr`` alone shows
labelled data (the positions ``r(time, body, node, component)``, the labels of ``dof`` and
``multiplier``, CF units), old stores without them still load and continue, and a
``Result`` says what it holds."""

import json
import shutil
import warnings

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.core.records import ENERGIES
from skfem_cable.io import RunStore
from skfem_cable.io.schema import STORE
from skfem_cable.model.labels import Points, dof_labels

xr = pytest.importorskip("xarray")

#: What the store adds to the layout before the labels (the old layout lacks them).
NEW = ("r", "body", "node", "component", "s", "dof_body", "dof_node", "dof_component",
       "dof_label", "constraint", "equation")

KW = dict(t_end=0.012, dt=1e-3, every=2)


def hub_and_tethers():
    """A rigid hub and two tethers of 4 and 3 elements pinned to its rim, under gravity."""
    hub = sc.RigidBody.cylinder(radius=1.0, height=2.0, density=884.0)
    sec = sc.Section.circular(1e-3, 7e10, 2700.0)
    t1 = sc.Cable.straight([0, 1, 0], [0, 11, 0], 4, sec, name="tether1")
    t3 = sc.Cable.straight([0, 0, 1], [0, 0, 11], 3, sec, name="tether3")
    system = sc.System([hub, t1, t3]).pin(t1.node(0), hub.point([0, 1, 0]))
    system.pin(t3.node(0), hub.point([0, 0, 1])).add_gravity([0, -9.81, 0])
    return system, hub, t3


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    """``(system, result, run directory)`` of a short run stored in chunks of 2."""
    system, _, _ = hub_and_tethers()
    path = tmp_path_factory.mktemp("labels") / "run"
    result = sc.simulate(system, observers=[RunStore(path, chunk=2)], **KW)
    return system, result, path


def test_plain_xarray_selects_a_body_and_a_component(stored):
    """Before: ``ds.sel(body="tether3", component="x")`` raised (no such dimensions);
    which coordinate belonged to which body was only in ``attrs["bodies"]``."""
    system, result, path = stored
    t3, hub = system.bodies[2], system.bodies[0]
    ds = xr.open_zarr(path / STORE)
    sel = ds.sel(body="tether3", component="x")
    assert sel.r.dims == ("time", "node") and sel.s.dims == ("node",)
    nodes = t3.mesh.p[0]
    expected = result.position(t3, nodes)[..., 0]
    assert np.array_equal(sel.r.values[:, :4], expected)
    assert np.isnan(sel.r.values[:, 4:]).all()  # tether1 has 5 nodes, tether3 4
    assert np.array_equal(sel.s.values[:4], nodes) and np.isnan(sel.s.values[4])
    corners = ds.r.sel(body="hub").values  # a rigid body's points: its base points
    assert np.array_equal(corners[:, :4], result.q[:, system.dofs(hub)].reshape(-1, 4, 3))
    assert list(ds.body.values) == ["hub", "tether1", "tether3"]
    assert list(ds.component.values) == ["x", "y", "z"]
    assert float(ds.r.sel(body="tether1", node=4, component="y").isel(time=0)) == 11.0
    # CF attributes
    assert ds.time.attrs["units"] == "s" and ds.time.attrs["standard_name"] == "time"
    assert ds.time.dtype == np.float64  # not decoded as a timedelta
    assert ds.r.attrs["units"] == "m" and ds.s.attrs["units"] == "m"
    assert ds.kinetic.attrs["units"] == "J" and "long_name" in ds.q.attrs


def test_coordinates_and_multipliers_are_labelled(stored):
    """Before: ``q(time, dof)`` and ``lam(time, multiplier)`` had no coordinates."""
    system, result, path = stored
    t3 = system.bodies[2]
    ds = xr.open_zarr(path / STORE)
    assert set(ds.q.coords) >= {"dof_body", "dof_node", "dof_component", "dof_label"}
    labelled = ds.set_xindex(["dof_body", "dof_node", "dof_component"])  # xarray's own
    mine = labelled.q.sel(dof_body="tether3")
    assert np.array_equal(mine.values, result.q[:, system.dofs(t3)])
    assert list(mine.dof_component.values[:6]) == ["x", "y", "z", "dx", "dy", "dz"]
    assert list(mine.dof_node.values) == list(np.repeat(np.arange(4), 6))
    assert mine.dof_label.values[4] == "node 0 r_x[1]"  # the body's describe_dof
    assert labelled.q.sel(dof_body="tether3", dof_node=3, dof_component="y").shape == (7,)
    hub = labelled.q.sel(dof_body="hub")
    assert list(hub.dof_component.values) == ["x", "y", "z"] * 4
    assert hub.dof_label.values[3] == "base point B component 0"
    pins = ds.set_xindex("constraint").lam.sel(constraint=system.constraints[-1].name)
    assert pins.shape == (len(result), 3)
    assert list(pins.equation.values) == list(system.constraints[-1].labels)
    assert np.array_equal(pins.values, result.multipliers[system.constraints[-1].name])


def test_labels_follow_the_body_contract():
    """Scalars (a reel's length) belong to no point; repeated names are made unique."""
    sec = sc.Section.circular(1e-3, 7e10, 2700.0)
    a = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sec)
    b = sc.Cable.straight([0, 1, 0], [1, 1, 0], 1, sec)
    reel = sc.Reel(10.0, radius=0.1, inertia=0.02)
    system = sc.System([a, reel, b])
    labels = dof_labels(system)
    assert list(labels["body"]) == ["cable"] * 18 + ["reel"] + ["cable#2"] * 12
    assert labels["node"][18] == -1 and labels["component"][18] == "free length"
    assert list(labels["node"][19:]) == [0] * 6 + [1] * 6
    points = Points(system)
    assert points.bodies == ["cable", "cable#2"] and points.index.shape == (2, 3, 3)
    assert list(points.index[1, :2, 0]) == [19, 25] and (points.index[1, 2] == -1).all()


def test_labels_are_written_once(tmp_path):
    """The labels are written when the store is created, not at each commit (nor when a
    run continues): their files stay as they are."""
    system, _, _ = hub_and_tethers()
    path = tmp_path / "run"
    sc.simulate(system, observers=[RunStore(path, chunk=2)], **dict(KW, t_end=0.004))
    files = [f for name in NEW[1:] for f in (path / STORE / name).rglob("*") if f.is_file()]
    assert len(files) >= len(NEW) - 1
    before = {f: f.stat().st_mtime_ns for f in files}
    sc.simulate(system, resume=RunStore.resume(path), observers=[RunStore(path, chunk=2)],
                **KW)
    assert {f: f.stat().st_mtime_ns for f in files} == before
    assert len(xr.open_zarr(path / STORE).time) == 7


def strip_to_old_layout(path):
    """Turn the store of ``path`` into one of the layout before the labels: no positions,
    no label arrays, no ``coordinates`` attributes, ``variables`` without ``r``."""
    import zarr

    root = path / STORE
    for name in NEW:
        shutil.rmtree(root / name, ignore_errors=True)
    for meta in root.glob("*/zarr.json"):
        data = json.loads(meta.read_text())
        data.get("attributes", {}).pop("coordinates", None)
        meta.write_text(json.dumps(data))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # zarr's note on consolidated metadata in v3
        zarr.consolidate_metadata(str(root))
    manifest = json.loads((path / "manifest.json").read_text())
    manifest["variables"] = [v for v in manifest["variables"] if v != "r"]
    (path / "manifest.json").write_text(json.dumps(manifest))


def test_old_layout_loads_and_continues_bit_for_bit(tmp_path):
    """A store written before the labels (no ``r``, no coordinates) still loads
    (``Result.load``, ``xarray.open_zarr``) and continues bit for bit, in its layout."""
    system, _, _ = hub_and_tethers()
    ref = sc.simulate(system, **KW)
    path = tmp_path / "old"
    sc.simulate(system, observers=[RunStore(path, chunk=2)], **dict(KW, t_end=0.006))
    strip_to_old_layout(path)
    ds = xr.open_zarr(path / STORE)
    assert "r" not in ds and "body" not in ds.dims and set(ds.q.coords) == {"time"}
    loaded = sc.Result.load(path, system)
    assert np.array_equal(loaded.q, ref.q[:4]) and np.array_equal(loaded.lam, ref.lam[:4])
    resumed = sc.simulate(system, resume=RunStore.resume(path),
                          observers=[RunStore(path, chunk=2)], **KW)
    assert np.array_equal(resumed.q, ref.q) and np.array_equal(resumed.v, ref.v)
    back = sc.Result.load(path, system)
    assert np.array_equal(back.q, ref.q) and np.array_equal(back.lam, ref.lam)
    assert "r" not in xr.open_zarr(path / STORE)  # continued in its own layout


def test_interrupted_and_resumed_store_keeps_its_positions(tmp_path):
    """The positions of a continued store are those of the uninterrupted run, and a
    commit broken after its arrays (more steps than the manifest's) is cut from ``r``
    too."""
    system, _, _ = hub_and_tethers()
    ref = sc.simulate(system, **KW)
    path = tmp_path / "run"
    sc.simulate(system, observers=[RunStore(path, chunk=2)], **dict(KW, t_end=0.006))
    manifest = json.loads((path / "manifest.json").read_text())
    sc.simulate(system, observers=[RunStore(tmp_path / "longer", chunk=2)], **KW)
    # a broken commit: the arrays hold more steps than the manifest commits
    shutil.rmtree(path / STORE)
    shutil.copytree(tmp_path / "longer" / STORE, path / STORE)
    (path / "manifest.json").write_text(json.dumps(manifest))
    sc.simulate(system, resume=RunStore.resume(path), observers=[RunStore(path, chunk=2)],
                **KW)
    ds = xr.open_zarr(path / STORE)
    points = Points(system)
    assert np.array_equal(ds.r.values, points.positions(ref.q), equal_nan=True)


def test_result_repr_says_what_it_holds(stored):
    """Before: ``<skfem_cable.results.result.Result object at 0x...>``."""
    system, result, path = stored
    text = repr(result)
    assert text.startswith("<Result: 7 saved steps, t = 0 … 0.012 s")
    assert "hub (RigidBody), tether1 (Cable, 4 elements), tether3 (Cable, 3 elements)" in text
    assert "fields: q, v, a, lam, iterations, energy>" in text and len(text.splitlines()) <= 3
    loaded = repr(sc.Result.load(path, system))
    assert "fields: q, v, lam, iterations, energy>" in loaded  # no a: not stored
    sec = sc.Section.circular(1e-3, 7e10, 2700.0)
    many = sc.System([sc.Cable.straight([0, k, 0], [1, k, 0], 2, sec, name=f"t{k}")
                      for k in range(1, 13)])
    records = {name: np.zeros((2, 0)) for name in ("lam",)}
    records.update(t=[0.0, 0.5], q=np.zeros((2, many.n_dofs)), iterations=[0, 2],
                   v=np.zeros((2, many.n_dofs)), a=np.full((2, many.n_dofs), np.nan),
                   **{name: np.zeros(2) for name in ENERGIES})
    short = repr(sc.Result(many, records))
    assert short.startswith("<Result: 2 saved steps, t = 0 … 0.5 s, ")
    assert short.endswith("fields: q, v, iterations, energy>")
    assert "bodies: t1 … t12 (12 × Cable, 2 elements)" in short
    assert len(short.splitlines()) == 1
