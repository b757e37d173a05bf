"""The record of a saved step: what every saved step of a run holds (``FIELDS``, among
them the ``ENERGIES``) and the settings of a run a checkpoint keeps (``SETTINGS``).

A leaf: the in-memory ``result.Result``, the integrators (``solvers.simulate``) and the
run store (``io``) all build on these names, none on another for them.
"""

import numpy as np

#: Energies recorded at every saved step (``contract.Step.energies``).
ENERGIES = ("kinetic", "axial", "bending", "potential", "dissipated", "external_work")

#: Arrays recorded at every saved step.
FIELDS = ("t", "q", "v", "a", "lam", "iterations") + ENERGIES


#: Settings of a run recorded in a checkpoint (``settings``, an array in this order); all
#: but ``t_end`` must match when the run is resumed.
SETTINGS = ("t_start", "t_end", "dt", "rho_inf", "every", "tol", "max_iter")


def settings_array(settings):
    """The ``SETTINGS`` of a run's settings (a dict, ``contract.Run.settings``) as the
    array a checkpoint stores; NaN for a setting the integrator has not (the rod chain's
    RK4 has no ``rho_inf``)."""
    return np.array([settings.get(k, np.nan) for k in SETTINGS], dtype=float)


#: Prefix of the records (and store variables) of the inputs: ``input_<name>``.
INPUT = "input_"
#: Prefix of the records (and store variables) of the loads' per-step outputs
#: (``Step.outputs``): ``output_<name>``.
OUTPUT = "output_"


def step_record(step):
    """The ``FIELDS`` of a saved step (a ``contract.Step``) as a dict, arrays copied, its
    inputs' values under ``input_<name>`` and the loads' outputs under
    ``output_<name>`` (a float, or an array copied: ``protocols.load_output_shapes``)."""
    record = {"t": step.t, "q": step.q.copy(), "v": step.v.copy(), "a": step.a.copy(),
              "lam": step.lam.copy(), "iterations": step.iterations}
    record.update({name: step.energies[name] for name in ENERGIES})
    record.update({INPUT + name: np.array(value) for name, value in step.inputs.items()})
    record.update({OUTPUT + name: float(value) if np.ndim(value) == 0 else
                   np.array(value, dtype=float) for name, value in step.outputs.items()})
    return record


def prefixed_records(records, prefix):
    """The histories among ``records`` (a dict of arrays) whose keys start with
    ``prefix`` (``INPUT``, ``OUTPUT``): ``{name: array}``, the prefix removed."""
    return {key[len(prefix):]: np.asarray(value) for key, value in records.items()
            if key.startswith(prefix)}


def input_records(records):
    """The inputs' histories among ``records`` (a dict of arrays): ``{name: array}``."""
    return prefixed_records(records, INPUT)
