"""The checkpoint of the generalized-alpha integrator (``Checkpoint``, a base of
``GeneralizedAlpha``): everything a continuation needs to be bit-for-bit identical to the
uninterrupted run, and its restoration (``protocols.Checkpointed``)."""

import numpy as np


class Checkpoint:
    """``snapshot`` (with the run's step hooks), ``_snapshot`` (the integrator's own state)
    and ``restore``."""

    STATE = ("t", "q", "v", "a", "abar", "lam", "fd", "fnc", "fcon", "dissipated",
             "external_work", "elastic", "iterations")

    def snapshot(self):
        """Everything a continuation needs to be bit-for-bit identical, including the
        state at which the current iteration matrix was factored (it is rebuilt from it),
        the instability guard's references and the state of the run's step hooks
        (``hooks``, set by ``simulate``: the rectification's rebases, the controllers')."""
        snap = self._snapshot()
        for hook in self.hooks:
            snap.update(hook.snapshot())
        return snap

    def _snapshot(self):
        snap = {k: np.copy(getattr(self, k)) for k in self.STATE}
        snap.update(self.guard.snapshot())
        snap["newton_rate"] = np.float64(self.newton_rate)
        if self.h_next is not None:
            snap["h_next"] = np.float64(self.h_next)
        if self.a_prev is not None:
            snap["a_prev"], snap["h_prev"] = np.copy(self.a_prev), np.float64(self.h_prev)
        if self.da_prev is not None:
            snap["da_prev"] = np.copy(self.da_prev)
            snap["h_prev2"] = np.float64(self.h_prev2)
        if self.abar_h is not None:
            snap["abar_h"] = np.float64(self.abar_h)
        if not self.fit_start:
            snap["plain_start"] = np.float64(1.0)
        if self.fresh_steps or self.strikes or self.tangent_age:
            snap["newton_choice"] = np.array([self.fresh_steps, self.strikes,
                                              self.tangent_age])
        if self.h_factored is not None:
            snap.update({"fact_" + k: np.copy(v) for k, v in self.factored_at.items()})
        return snap

    def restore(self, snap):
        for k in self.STATE:
            value = np.array(snap[k] if k in snap else np.zeros(self.n))  # fcon: pre-guard
            setattr(self, k, value if value.ndim else value.item())
        self.t = float(self.t)
        start = self._open((self.fd, self.fnc, self.fcon), self.elastic)
        self.kinetic, self.potential = start["kinetic"], start["potential"]
        self.energy_rate = start["energy_rate"]
        self.h_next = float(snap["h_next"]) if "h_next" in snap else None
        self.newton_rate = float(snap["newton_rate"]) if "newton_rate" in snap else 1.0
        self.a_prev = np.array(snap["a_prev"]) if "a_prev" in snap else None
        self.h_prev = float(snap["h_prev"]) if "a_prev" in snap else None
        self.da_prev = np.array(snap["da_prev"]) if "da_prev" in snap else None
        self.h_prev2 = float(snap["h_prev2"]) if "da_prev" in snap else None
        # a checkpoint written before abar_h existed: abar belongs to the last step
        self.abar_h = float(snap["abar_h"]) if "abar_h" in snap else self.h_prev
        self.fit_start = "plain_start" not in snap
        choice = snap["newton_choice"] if "newton_choice" in snap else ()
        # (a checkpoint written before the tangent's age was kept: a fresh one)
        self.fresh_steps, self.strikes, self.tangent_age = (
            int(k) for k in (*choice, 0, 0, 0)[:3])
        self.h_factored = None
        if "guard_lowest" in snap:
            self.guard.restore(snap)
        else:  # a checkpoint written before the guard existed
            self.guard.reset(self.t, self.energies())
        if "fact_h" in snap:
            at = {k: np.array(snap["fact_" + k]) for k in ("q", "v", "t", "lam", "h")}
            a = np.array(snap["fact_a"]) if "fact_a" in snap else np.zeros(self.n)
            self._factor(at["q"], at["v"], float(at["t"]), at["lam"], float(at["h"]), a)
