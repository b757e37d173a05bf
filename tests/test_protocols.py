"""The declared interfaces (``skfem_cable.core.protocols``): what the solvers and ``io`` read of
a system (``IntegrableSystem``, ``SystemView``), what acts between steps (``StepHook``),
and that the code reads nothing else: the sources of ``solvers``, ``io``, ``result`` and
``runner`` are parsed and every attribute they read on a system is compared with the
protocols' members."""

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import io
from skfem_cable.control.controller import ControlLoop
from skfem_cable.core import contract, protocols
from skfem_cable.core.protocols import Checkpointed, IntegrableSystem, StepHook, SystemView, members
from skfem_cable.rodchain.stored import ChainSystem
from skfem_cable.scenes import classics
from skfem_cable.solvers import simulate as simulate_module
from skfem_cable.solvers.guard import EnergyGuard
from skfem_cable.solvers.rectify import Rectification

PACKAGE = Path(sc.__file__).parent

#: Who reads a system, and the protocol that declares what they may read.
READERS = {"io": (SystemView, ["io", "model/labels.py", "model/fingerprint.py"]),
           "solvers": (IntegrableSystem, ["solvers", "results/result.py", "runner"])}

#: The store's readers: io, and the labels and fingerprint (in io before the relayout of
#: issue 46); the ParaView files (io.export, at the root before) read a system as
#: the solvers do, not as the store.
UNCHECKED = {"io/export.py"}

#: Names that hold a system in the readers' sources (the attribute ``.system`` of a run,
#: an integrator, a result, ... holds one too); ``sys`` is the standard module.
SYSTEM_NAMES = {"system"}


def _sources(parts):
    for part in parts:
        path = PACKAGE / part
        yield from [path] if path.suffix == ".py" else sorted(
            p for p in path.rglob("*.py") if p.relative_to(PACKAGE).as_posix()
            not in UNCHECKED)


def _holds_system(node, aliases):
    return ((isinstance(node, ast.Name) and node.id in aliases)
            or (isinstance(node, ast.Attribute) and node.attr == "system"))


def _aliases(tree):
    """The names a module binds to a system: ``SYSTEM_NAMES`` and every name assigned
    from one (``lay, system = ..., self.system`` included), to a fixed point."""
    aliases, grown = set(SYSTEM_NAMES), True
    while grown:
        grown = False
        for node in ast.walk(tree):
            if not isinstance(node, ast.Assign | ast.AnnAssign):
                continue
            targets = node.targets if isinstance(node, ast.Assign) else [node.target]
            for target in targets:
                pairs = [(target, node.value)]
                if isinstance(target, ast.Tuple) and isinstance(node.value, ast.Tuple):
                    pairs = list(zip(target.elts, node.value.elts))
                for name, value in pairs:
                    if (isinstance(name, ast.Name) and name.id not in aliases
                            and value is not None and _holds_system(value, aliases)):
                        aliases.add(name.id)
                        grown = True
    return aliases


def _reads(tree, where, reads, probes):
    """Add to ``reads`` (name -> places) the attributes read (or written) on a system in
    ``tree``, and to ``probes`` its ``getattr``, ``hasattr`` and ``setattr`` calls on one
    (which a declared interface does not need)."""
    aliases = _aliases(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and _holds_system(node.value, aliases):
            reads.setdefault(node.attr, []).append(f"{where}:{node.lineno}")
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
                and node.func.id in ("getattr", "hasattr", "setattr") and node.args
                and _holds_system(node.args[0], aliases)):
            probes.append(f"{where}:{node.lineno}: {ast.unparse(node)}")


def system_reads(parts):
    """``(reads, probes)`` of the modules ``parts`` (relative to the package), as
    ``_reads`` finds them."""
    reads, probes = {}, []
    for path in _sources(parts):
        _reads(ast.parse(path.read_text(), str(path)), path.relative_to(PACKAGE), reads,
               probes)
    return reads, probes


@pytest.mark.parametrize("reader", READERS)
def test_readers_read_only_what_their_protocol_declares(reader):
    """Every attribute that ``solvers`` (and the ``Result`` they return, the runner's
    summaries) or ``io`` read on a system is a member of ``IntegrableSystem`` or
    ``SystemView``, no one probes a system with ``getattr``, and every member the
    protocol itself declares is read by its readers (nothing declared for nobody)."""
    protocol, parts = READERS[reader]
    reads, probes = system_reads(parts)
    undeclared = {name: where for name, where in reads.items()
                  if name not in members(protocol)}
    assert not undeclared, (f"{reader} reads {undeclared} of a system: declare it in "
                            f"protocols.{protocol.__name__} or read it otherwise")
    assert not probes, probes
    own = [name for name in members(protocol)
           if name in vars(protocol) or name in vars(protocol).get("__annotations__", {})]
    assert set(own) <= set(reads), set(own) - set(reads)
    assert len(reads) > 10  # the scan sees the readers (not an empty set by mistake)


def test_the_scan_sees_aliases_and_undeclared_reads():
    """The scan follows a system through aliases and attributes named ``system``, and
    catches a probe: the test above fails on any of these."""
    tree = ast.parse("def f(system, run):\n"
                     "    lay, s = system.layout, run.system\n"
                     "    t = s\n"
                     "    t.flag = 1\n"
                     "    return t.secret, getattr(system, 'hidden', None), lay.n\n")
    assert _aliases(tree) == {"system", "s", "t"}
    reads, probes = {}, []
    _reads(tree, "f", reads, probes)
    assert set(reads) == {"layout", "flag", "secret"}
    assert probes == ["f:5: getattr(system, 'hidden', None)"]


def _check_implements(obj, protocol):
    """``obj`` has every member of ``protocol``: attributes of the annotated kind, methods
    that accept the protocol's arguments (without evaluating anything but the
    attributes)."""
    annotations = {}
    for cls in reversed(protocol.__mro__):
        annotations.update(vars(cls).get("__annotations__", {}))
    for name in members(protocol):
        assert inspect.getattr_static(obj, name, None) is not None or \
            (name in annotations and hasattr(obj, name)), f"{type(obj).__name__}.{name}"
        value = getattr(obj, name)
        if name in annotations:
            kind = annotations[name]
            assert kind is object or isinstance(value, kind), (name, type(value))
            continue
        declared = inspect.signature(getattr(protocol, name))
        arguments = [p.name for p in list(declared.parameters.values())[1:]
                     if p.default is inspect.Parameter.empty]
        inspect.signature(value).bind(*arguments)  # TypeError: another signature


def _chain_system():
    chain = sc.RodChain.uniform(4, 0.1, 0.25, 2e11, 1e-6)
    q0 = np.tile([0.0, 0.0, -0.25], (4, 1))
    return ChainSystem.of(chain, q0, gravity=(0.0, 0.0, -9.81))


def test_system_is_an_integrable_system_and_a_system_view():
    """A ``System`` (a pendulum; a system in orbit) provides every member of both."""
    system = classics.pendulum(n_elements=2).system
    assert isinstance(system, SystemView)
    _check_implements(system, IntegrableSystem)
    section = sc.Section.circular(1e-3, 2e11, 7850.0)
    orbiting = sc.System([sc.Cable.straight([0, 0, 0], [10, 0, 0], 2, section)])
    orbiting.add_orbit(sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3))
    _check_implements(orbiting, IntegrableSystem)
    assert orbiting.orbit is not None and orbiting.orbit_gravity is not None


def test_the_rod_chain_implements_the_store_view_and_no_more():
    """``ChainSystem`` declares ``SystemView`` (a subclass), provides each member with
    the declared kind, and holds nothing else but its ``chain`` (what observers of a
    rod-chain run read: ``run.system.chain``)."""
    system = _chain_system()
    assert SystemView in ChainSystem.__mro__ and isinstance(system, SystemView)
    _check_implements(system, SystemView)
    assert not isinstance(system, sc.System)
    public = {name for name in dir(system) if not name.startswith("_")}
    assert public - set(members(SystemView)) == {"chain", "of"}
    assert system.vectors.shape == (system.n_dofs // 3, 3)
    assert system.vector_is_position.shape == (system.n_dofs // 3,) and system.orbit is None


def test_the_store_reads_the_chain_through_the_view():
    """What ``io`` makes of the chain: labels of its rod vectors, a fingerprint."""
    system = _chain_system()
    labels = sc.model.labels.dof_labels(system)
    assert list(labels["component"][:3]) == ["dx", "dy", "dz"]
    assert len(io.fingerprint(system)) == 64


@pytest.mark.parametrize("hook", [Rectification, ControlLoop])
def test_built_in_step_hooks_implement_the_protocol(hook):
    """Encke's rectification and the control loop have the five members of ``StepHook``
    with its arguments; the instability guard's state is ``Checkpointed``."""
    assert issubclass(hook, StepHook)
    for name in members(StepHook):
        declared = inspect.signature(getattr(StepHook, name)).parameters
        given = inspect.signature(getattr(hook, name)).parameters
        assert list(given) == list(declared), (name, list(given))
    assert issubclass(EnergyGuard, Checkpointed)
    assert isinstance(EnergyGuard(), Checkpointed)


def test_the_driver_calls_hooks_through_the_protocol_only():
    """``simulate`` and the integrator call on a step hook only the members of
    ``StepHook`` (no probing, no test of its class)."""
    called = set()
    for path in _sources(["solvers/simulate.py", "solvers/galpha.py", "solvers/checkpoint.py",
                          "solvers/initial_state.py", "solvers/books.py"]):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id == "hook"):
                called.add(node.attr)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
                assert not (node.func.id in ("isinstance", "getattr", "hasattr")
                            and ast.unparse(node.args[0]) in ("hook", "hooks")), \
                    ast.unparse(node)
    assert called == set(members(StepHook))


class Tally:
    """A user's step hook (no base class): counts the accepted steps and keeps the
    largest speed seen; its state is in the checkpoints."""

    def __init__(self):
        self.steps, self.fastest = 0, 0.0

    def start(self, integrator):
        self.steps, self.fastest = 0, float(np.abs(integrator.v).max())

    def after_step(self, integrator):
        self.steps += 1
        self.fastest = max(self.fastest, float(np.abs(integrator.v).max()))

    def next_event(self, t):
        return np.inf

    def snapshot(self):
        return {"tally_steps": np.int64(self.steps), "tally_fastest": np.float64(self.fastest)}

    def restore(self, snap):
        self.steps, self.fastest = int(snap["tally_steps"]), float(snap["tally_fastest"])


def _with_hook(monkeypatch, hook):
    """``simulate`` with ``hook`` among its step hooks: ``simulate`` takes no hooks of a
    user (its hooks are the rectification and the control loop), so the test adds one
    where the driver collects them."""
    collect = simulate_module._step_hooks

    def hooks(*args):
        return [*collect(*args), hook]

    monkeypatch.setattr(simulate_module, "_step_hooks", hooks)


def test_a_users_step_hook_runs_and_continues_bit_for_bit(monkeypatch, tmp_path):
    """A minimal class with the five members of ``StepHook`` runs in ``sc.simulate``:
    called after every step, its state in the checkpoint, restored on resume so that the
    continued run ends with the state of the uninterrupted one."""
    assert isinstance(Tally(), StepHook)

    class Interrupt(sc.Observer):
        def saved(self, run, step):
            if step.index >= 10:
                raise KeyboardInterrupt

    def run(**options):
        tally = Tally()
        _with_hook(monkeypatch, tally)
        return sc.simulate(classics.pendulum(n_elements=2).system, 0.02, 1e-3, every=5,
                           **options), tally

    full, whole = run()
    assert whole.steps == 20 and whole.fastest == pytest.approx(np.abs(full.v).max())
    with pytest.raises(KeyboardInterrupt):
        run(observers=[io.RunStore(tmp_path, chunk=2), Interrupt()])
    checkpoint = io.resume(tmp_path).snapshot
    assert int(checkpoint["tally_steps"]) == 10
    resumed, tally = run(resume=io.resume(tmp_path), observers=[io.RunStore(tmp_path)])
    np.testing.assert_array_equal(resumed.q, full.q)
    assert (tally.steps, tally.fastest) == (whole.steps, whole.fastest)


def test_old_names_in_contract_are_the_protocols():
    """``from skfem_cable.core.contract import Body`` (and the others) keeps working for one
    release: the same objects as in ``protocols``."""
    for name in ("Body", "Line", "Load", "Constraint", "Observer", "check_body"):
        assert getattr(contract, name) is getattr(protocols, name)
    assert sc.Observer is protocols.Observer
