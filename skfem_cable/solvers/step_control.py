"""Step control of a time integration, kept inside the integrator as scipy's solvers keep
it: ``StepControl.advance`` takes a step of a given size and retries a failed one as two
half steps; ``StepControl.adaptive_step`` takes one step of the local-error control.
``simulate`` is then only its loop of steps and saves.  An integrator provides
``step(h) -> (ok, message)``, ``t``, ``stats`` (with ``rejected``), ``h_next`` and
``error_ratio`` (``GeneralizedAlpha``)."""


class SimulationError(RuntimeError):
    """A step failed below the smallest allowed step size; ``result`` holds the steps
    computed so far (observers such as ``io.RunStore`` have written them too)."""

    def __init__(self, message, result):
        super().__init__(message)
        self.result = result


class StepControl:
    """The step control of an integrator (module docstring)."""

    def advance(self, h, max_halvings):
        """One step of size ``h``; a failed step is retried as two half steps, and each
        of those likewise, ``max_halvings`` times at most; below that
        ``SimulationError``.  The halves wait on a stack (in the order of time), not in
        recursive calls: a run that stops at the smallest step raises from here, not ten
        calls deep.  An accepted step makes no stack."""
        depth, pending = 0, []
        while True:
            ok, msg = self.step(h)
            if not ok:
                self.stats["rejected"] += 1
                if depth >= max_halvings:
                    raise SimulationError(f"step failed at the smallest step size {h:.3g} "
                                          f"(dt/2^{depth}): {msg}", None)
                pending += [(0.5 * h, depth + 1)] * 2
            if not pending:
                return
            h, depth = pending.pop()

    def adaptive_step(self, t_end, dt, max_halvings):
        """One accepted step toward ``t_end`` of the local-error control, from the size
        the last one chose (``h_next``, else ``dt``); returns whether it reached ``t_end``.

        The step's estimated local error must lie below its tolerance (``error_ratio``
        <= 1); the next step is ``h min(2, 0.9 r^(-1/3))`` with ``r`` that ratio (kept
        unchanged when that would grow it by less than 25 %, so the factored iteration
        matrix is reused); a rejected step is retried with ``h max(0.2, 0.9 r^(-1/3))``
        (halved after a Newton failure), down to ``dt / 2**max_halvings``.  Two equal
        steps end the run rather than a sliver of a last one.
        """
        h, h_min = self.h_next or dt, dt / 2**max_halvings
        while True:
            remaining = t_end - self.t
            last = h >= remaining * (1 - 1e-12)
            h_try = remaining if last else min(h, 0.5 * remaining) if 2 * h > remaining else h
            ok, msg = self.step(h_try)
            ratio = self.error_ratio
            if ok:
                break
            self.stats["rejected"] += 1
            # halved unless the local error was too large (Newton or the guard failed)
            h = h_try * (0.5 if ratio is None or not ratio > 1.0
                         else max(0.2, 0.9 * ratio ** (-1 / 3)))
            if h < h_min:
                raise SimulationError(f"step failed below the smallest step size "
                                      f"{h_min:.3g} (dt/2^{max_halvings}): {msg}", None)
        self.stats["h_min"] = min(self.stats.get("h_min", float("inf")), h_try)
        self.stats["h_max"] = max(self.stats.get("h_max", 0.0), h_try)
        grow = min(2.0, 0.9 * ratio ** (-1 / 3)) if ratio > 0 else 2.0
        self.h_next = h_try * grow if not 1.0 <= grow < 1.25 else h_try
        return last
