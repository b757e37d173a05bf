"""The observer loop of a time integration (``Observers``), the one every integrator runs
(``simulate``, the rod chain's ``integrate``), and ``finish_observers``: the machinery
around the ``contract.Observer`` hooks."""

import contextlib


class Observers:
    """The observer loop of a time integration, the one every integrator runs
    (``simulate``, the rod chain's ``integrate``): check the observers, start them, hand
    them each saved step, finish them, also when the run fails.

    ``with Observers(run, observers, result) as watch:`` starts them; ``watch.saved(step)``
    hands a ``Step`` to each and returns the first stop message (a true value returned by
    an observer's ``saved``; not a string: ``"stopped by <class>"``), or None; leaving the
    block finishes them (``finish_observers``), and an exception leaving it carries
    ``result()``, the steps computed so far, as ``err.result``.
    """

    def __init__(self, run, observers, result):
        self.run, self.observers, self.result = run, list(observers or ()), result
        for obs in self.observers:
            if not all(callable(getattr(obs, hook, None))
                       for hook in ("start", "saved", "finish")):
                raise TypeError(f"{obs!r} is not an Observer (needs start, saved and "
                                "finish)")
        self.started = []

    def __enter__(self):
        try:
            for obs in self.observers:
                obs.start(self.run)
                self.started.append(obs)
        except BaseException as err:
            self.__exit__(type(err), err, err.__traceback__)
            raise
        return self

    def saved(self, step):
        stop = None
        for obs in self.observers:
            answer = obs.saved(self.run, step)
            if answer and stop is None:
                stop = answer if isinstance(answer, str) else f"stopped by {type(obs).__name__}"
        return stop

    def __exit__(self, kind, error, traceback):
        if error is not None:
            with contextlib.suppress(Exception):  # the saved steps travel with the error
                error.result = self.result()
        finish_observers(self.started, self.run, error)
        return False


def finish_observers(observers, run, error):
    """Call ``finish(run, error)`` of every observer, even when one of them fails: with
    ``error`` (the run failed) their failures are added to its notes; otherwise the first
    one is raised after all were called.  Every integrator ends its runs with this."""
    first = None
    for obs in observers:
        try:
            obs.finish(run, error)
        except Exception as exc:
            if error is not None:
                if hasattr(error, "add_note"):  # Python >= 3.11
                    error.add_note(f"{type(obs).__name__}.finish failed too: {exc!r}")
            elif first is None:
                first = exc
    if first is not None:
        raise first
