"""What an E-sail run reports: spin rate, attitude angles, the Coulomb force's resultants."""

import numpy as np
from scipy.spatial.transform import Rotation

from ...control import sensors
from ...core.inputs import InputTable, system_inputs
from ...space.frames import R1, euler_321, euler_323, orbit_frame


def _facing(axis, wind):
    """The least rotation that turns the unit vector ``axis`` onto the line of ``wind``
    (onto ``wind`` or ``-wind``, whichever is nearer)."""
    target = wind if axis @ wind >= 0 else -wind
    return Rotation.align_vectors([target], [axis])[0].as_matrix()


def _angles(vec_Z):
    """Coning (out of the spin plane) and lagging angles of vectors in the tether frames Z
    (Eqs. 59, 61)."""
    gamma = np.arctan2(vec_Z[..., 0], np.hypot(vec_Z[..., 1], vec_Z[..., 2]))
    beta = np.arctan2(vec_Z[..., 2], vec_Z[..., 1])
    return gamma, beta


def outputs(scene, result):
    """Auxiliary variables of Sect. 3 as time series (leading axis: the saved steps).

    Returns a dict with ``t`` and: ``coning``, ``lagging``, ``root_coning``,
    ``root_lagging``, ``length_ratio`` (nt, p); ``omega_B`` (nt, 3, rad/s, the hub's);
    ``spin_rate`` (nt, rad/s: the remote units' mean rate about the normal of their plane,
    the sail's spin without the hub's libration); ``euler_B``
    (psi, theta, phi) and ``euler_E`` (Psi, Theta, Phi) (nt, 3, rad); ``sailing_angle``,
    ``precession_angle`` (nt, rad); ``thrust`` (I) and ``thrust_O`` (nt, 3, N),
    ``thrust_angle`` (from ``Z_O``, rad), ``thrust_moment`` (about the anchors, I, N m);
    ``coulomb_force_B``, ``coulomb_moment_B`` per tether (nt, p, 3, body frame);
    ``reaction_force`` (force of the tethers on the hub, I) and ``reaction_force_O``,
    ``reaction_moment`` (about the hub centre, I), ``reaction_angle`` (from ``Z_O``); and
    the energies of ``result.energy``.
    """
    system, hub = scene.system, scene.hub
    d = result.q[:, system.dofs(hub)]
    C_I_B = hub.rotation(d)
    origin = hub.positions(d, np.zeros(3))
    C_I_O = orbit_frame(scene.heliocentric(result.t, result.reference) + origin)
    out = {"t": result.t}
    rho_Z, tau_Z, ratio = [], [], []
    for zeta, cable in zip(scene.zeta, scene.tethers):
        qc = result.q[:, system.dofs(cable)]
        nodes = qc.reshape(len(result.t), -1, cable.element.nodal_dofs, 3)
        C_Z_I = R1(zeta) @ np.swapaxes(C_I_B, -1, -2)
        rho_Z.append(np.einsum("tij,tj->ti", C_Z_I, nodes[:, -1, 0] - nodes[:, 0, 0]))
        tau_Z.append(np.einsum("tij,tj->ti", C_Z_I, nodes[:, 0, 1]))
        a = np.einsum("egA,teAi->tegi", cable.Sx, cable.element_vectors(qc))
        ratio.append(np.einsum("eg,teg->t", cable.weights, np.linalg.norm(a, axis=-1))
                     / cable.length)
    out["coning"], out["lagging"] = _angles(np.stack(rho_Z, axis=1))
    out["root_coning"], out["root_lagging"] = _angles(np.stack(tau_Z, axis=1))
    out["length_ratio"] = np.stack(ratio, axis=1)
    out["omega_B"] = hub.angular_velocity(d, result.v[:, system.dofs(hub)])
    C_B_O = np.swapaxes(C_I_B, -1, -2) @ C_I_O
    out["euler_B"] = euler_321(C_B_O)
    # E frame: normal of the least-squares plane of the remote units (Eqs. 67-70)
    tips = np.stack([result.q[:, system.dofs(c)[-6:-3]] for c in scene.tethers], axis=1)
    centre = tips.mean(axis=1, keepdims=True)
    normal = np.linalg.svd(tips - centre)[2][:, -1]
    normal *= np.sign(np.einsum("ti,ti->t", normal, C_I_B[:, :, 0]))[:, None]
    k_E = np.cross(normal, tips[:, 0] - centre[:, 0])
    k_E /= np.linalg.norm(k_E, axis=1, keepdims=True)
    C_I_E = np.stack([normal, np.cross(k_E, normal), k_E], axis=-1)
    out["spin_rate"] = sensors.mean_spin_rate(tips - centre, np.stack(
        [result.v[:, system.dofs(c)[-6:-3]] for c in scene.tethers], axis=1), normal)
    out["euler_E"] = euler_323(np.swapaxes(C_I_E, -1, -2) @ C_I_O)
    out["sailing_angle"] = np.arccos(np.clip(np.einsum("ti,ti->t", C_I_B[:, :, 0],
                                                       C_I_O[:, :, 2]), -1, 1))
    i_E_O = np.einsum("tji,tj->ti", C_I_O, normal)
    out["precession_angle"] = np.arctan2(i_E_O[:, 1], i_E_O[:, 0])
    # Coulomb resultants (Eqs. 72-76) by the same quadrature as the force
    force_B, moment_B = _coulomb_resultants(scene, result, C_I_B)
    thrust = np.einsum("tij,tpj->ti", C_I_B, force_B)
    out["coulomb_force_B"], out["coulomb_moment_B"] = force_B, moment_B
    out["thrust"] = thrust
    out["thrust_O"] = np.einsum("tji,tj->ti", C_I_O, thrust)
    out["thrust_angle"] = _angle_from_z(out["thrust_O"])
    out["thrust_moment"] = np.einsum("tij,tpj->ti", C_I_B, moment_B)
    # reactions on the hub from the joint multipliers (Eqs. 77-78)
    pins = [result.multipliers[c.name] for c in system.constraints if c.name.startswith("pin")]
    lam = np.stack(pins, axis=1)
    out["reaction_force"] = lam.sum(axis=1)
    out["reaction_force_O"] = np.einsum("tji,tj->ti", C_I_O, out["reaction_force"])
    anchors_I = hub.positions(d, scene.anchors)
    out["reaction_moment"] = np.cross(anchors_I - origin[:, None], lam).sum(axis=1)
    out["reaction_angle"] = _angle_from_z(out["reaction_force_O"])
    out.update(result.energy)
    return out


def _angle_from_z(F_O):
    return np.arctan2(np.hypot(F_O[..., 0], F_O[..., 1]), F_O[..., 2])


def _coulomb_resultants(scene, result, C_I_B):
    """Per-tether Coulomb force ``int f dx`` and moment ``int (r - r_anchor) x f dx`` about
    the anchor, in the body frame, (nt, p, 3) each."""
    inputs = system_inputs(scene.system)
    missing = sorted(set(inputs) - set(result.inputs))
    if missing:
        raise ValueError(f"outputs: the result holds no history of the inputs "
                         f"{', '.join(map(repr, missing))} (set by controllers): the "
                         "Coulomb force of past saved steps cannot be recomputed")
    return _resultants(scene, result, C_I_B, InputTable(inputs))


def _points(scene, result):
    """The quadrature points ``r`` and slopes ``a`` of all tethers at every saved step,
    (nt, n, 3) each (the tethers' points in turn), and each tether's anchor, its first
    node, (nt, p, 3)."""
    system, nt = scene.system, len(result.t)
    r, a, anchor = [], [], []
    for cable in scene.tethers:
        qc = result.q[:, system.dofs(cable)]
        qe = cable.element_vectors(qc)
        r.append(np.einsum("egA,teAi->tegi", cable.S, qe).reshape(nt, -1, 3))
        a.append(np.einsum("egA,teAi->tegi", cable.Sx, qe).reshape(nt, -1, 3))
        anchor.append(qc[:, :3])
    return np.concatenate(r, axis=1), np.concatenate(a, axis=1), np.stack(anchor, axis=1)


def _by_tether(values, owner, p):
    """The sums (nt, p, 3) of ``values`` (nt, n, 3) over the points of each tether
    (``owner``, (n,), its tether's index), in the points' order at each step."""
    nt = len(values)
    bins = (owner + p * np.arange(nt)[:, None]).ravel()
    return np.stack([np.bincount(bins, values[..., i].ravel(), minlength=nt * p)
                     for i in range(3)], axis=-1).reshape(nt, p, 3)


def _resultants(scene, result, C_I_B, table):
    """``_coulomb_resultants`` with the inputs of ``table`` (an ``inputs.InputTable``)
    set, at each saved step, to the values the result recorded.  The points, the sums
    and the moments' arms are taken over all saved steps at once (``_points``,
    ``_by_tether``), and so is the force (``line_forces``) with each step's
    coefficients, Sun and scaling (the voltages once per step, not once per tether)."""
    wf = scene.wind_force
    sources = wf.sources(table)
    p = len(scene.tethers)
    weights = np.concatenate([cable.weights.ravel() for cable in scene.tethers])
    owner = np.concatenate([np.full(cable.weights.size, i)
                            for i, cable in enumerate(scene.tethers)])
    r, a, anchor = _points(scene, result)
    nt = len(result.t)
    coef, sun, scaling = np.empty((nt, p)), np.empty((nt, 3)), np.empty((nt, 2))
    for k, t in enumerate(result.t):
        for name in table.values:
            table.set(name, result.inputs[name][k])
        coef[k] = wf.coefficients(t, sources)
        sun[k] = wf.sun_at(t, result.reference)
        scaling[k] = wf.scaling(t, sources, result.reference)
    fw = wf.line_forces(r, a, coef[:, owner], sun[:, None], scaling[:, None]) * weights[:, None]
    force = _by_tether(fw, owner, p)
    moment = _by_tether(np.cross(r - anchor[:, owner], fw), owner, p)
    RT = np.swapaxes(C_I_B, -1, -2)
    return np.einsum("tij,tpj->tpi", RT, force), np.einsum("tij,tpj->tpi", RT, moment)
