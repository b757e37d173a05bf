"""Modified Newton's choice of tangent from step to step (``NewtonChoice``, a base of
``GeneralizedAlpha``): whether the next step factors the iteration matrix at its predictor
or iterates on the one it has."""


class NewtonChoice:
    """``fresh_tangent`` and ``_choose_newton``, on the integrator's ``newton``,
    ``iterations``, ``newton_rate`` and its own state ``fresh_steps``, ``strikes`` and
    ``tangent_age`` (checkpointed, ``Checkpoint``)."""

    #: The longest run of steps from a fresh tangent before the stale one is tried again.
    FRESH_STEPS_MAX = 64

    #: The contraction above which a step of two corrections or more has the next step
    #: refactor (``_choose_newton``).
    STALE_RATE = 0.05

    #: The most steps a tangent replaced within a step may have served before it for the
    #: contraction measured across the replacement to have the next step refactor
    #: (``_choose_newton``).
    YOUNG_TANGENT = 1

    @property
    def fresh_tangent(self):
        """Whether the next step starts from a fresh tangent: ``newton="full"`` (which
        refactors at every iteration), or modified Newton's choice (``_choose_newton``)."""
        return self.newton == "full" or self.fresh_steps > 0

    def _choose_newton(self, fresh, factorizations):
        """Modified Newton's choice for the next steps after an accepted step (one that
        started from a fresh tangent if ``fresh``) that made ``factorizations``.

        * **Runs of fresh steps.** After ``k >= 2`` steps in a row that had to refactor
          (the stale tangent did not contract, or the step changed size: adaptive steps),
          the next ``2^(k-2)`` steps (at most ``FRESH_STEPS_MAX``) factor the tangent at
          their predictor and iterate on it; then a step tries the stale tangent again.
          Long steps of a stiff spinning cable turn the tangent within a step (the axial
          stiffness turns with the tether): the full-size E-sail at 5 s steps took 5.9
          corrections and 2.0 factorizations per step on the stale tangent and 2.25 and
          2.0 in full Newton; it takes 2.1 and 1.0, 7.0 ms on one thread against full
          Newton's 11.6.  The flexible pendulum at 1 ms steps, which refactored in two
          steps of three, takes 2.9 corrections per step instead of 4.5, 0.84 of the time.
        * **A slow stale tangent.** Steps whose stale tangent serves (the E-sail rig) keep
          it, until it serves slowly: a step (after any run of fresh ones) that took two
          corrections or more at a contraction above ``STALE_RATE`` (its first
          correction's error estimate, ``kernels.step.first_error_factor``, then misses
          the tolerance) has the next step factor at its predictor (as Hairer & Wanner's
          RADAU5 refactors after a step that contracted above its ``THET``, 0.001 by
          default and about 0.1 advised for small systems).  The E-sail rig's tangent of
          ``t = 0`` contracts at 0.13 by ``t = 25 s``, and 154 of its first 400 steps took
          a second correction: 557 corrections and 3 factorizations in 400 steps, 406
          and 5 with the refresh (the compiled Newton call 60.6 -> 50.3 us a step; the
          tips' radius the same to 1e-6 m).
        * **Unless the step replaced an old tangent.** A step that refactored within its
          iteration reports a contraction measured across the two matrices (its first
          correction on the new one against its last on the old): it says that the old
          one had gone stale, which the step has already mended.  If that tangent had
          served at most ``YOUNG_TANGENT`` steps before this one, the tangent changes
          within a step or two and the next step starts fresh, as above; if it had served
          longer, the next step iterates on the one just factored.  The released 100 m
          pendulum of ``benchmarks/step_exponent.py`` at 10,000 elements replaces an old
          tangent twice in the 200 steps after the release (at step 119 that of step 34)
          and factored again at the next predictor each time: 4 factorizations in those
          steps instead of 6, with the same 491 corrections (1.5 % of their CPU time); at
          3200 and 5600 elements one fewer, at 1000 and 1800 none.  The 16-element
          pendulum (1070 corrections, 181 factorizations in 300 steps), the E-sail rig,
          the orbiting and the full-size sail, the catenary and the controller run make
          the same iterations; the damped pendulum 874 corrections and 255 factorizations
          instead of 872 and 260.  Any bound from 0 to 16 steps gives these counts.
        """
        mended = False  # an old tangent replaced within the step
        if fresh:
            self.fresh_steps -= 1
        elif factorizations >= 1:
            mended = self.tangent_age > self.YOUNG_TANGENT
            self.strikes = min(self.strikes + 1, 2 + self.FRESH_STEPS_MAX.bit_length())
            if self.strikes >= 2:
                self.fresh_steps = min(2 ** (self.strikes - 2), self.FRESH_STEPS_MAX)
        else:
            self.strikes = 0
        self.tangent_age = 0 if factorizations else self.tangent_age + 1
        if (self.fresh_steps <= 0 and self.iterations >= 2 and not mended
                and self.newton_rate > self.STALE_RATE):
            self.fresh_steps = 1
