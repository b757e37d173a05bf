"""A load that stands for Ctrl-C in the middle of a step (``test_run_storage``,
``test_adaptive``, ``test_export``): ``InterruptingLoad(force, stop_at)`` is the force
function ``force(t)`` that raises ``Interrupt`` past ``stop_at``.  ``stop_at`` is in its
``caches``: the interruption is not the load, so the interrupted run and its continuation
(``stop_at=None``) have one fingerprint (which sees what a function closes over)."""


class Interrupt(Exception):
    """Stands for Ctrl-C in the middle of a step."""


class InterruptingLoad:
    """``force(t)``, raising ``Interrupt`` at times past ``stop_at`` (None: never)."""

    caches = ("stop_at",)

    def __init__(self, force, stop_at=None):
        self.force, self.stop_at = force, stop_at

    def __call__(self, t):
        if self.stop_at is not None and t > self.stop_at:
            raise Interrupt
        return self.force(t)
