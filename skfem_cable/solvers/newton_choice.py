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

    #: The corrections of a stale step, and the age of its tangent (in steps), from which
    #: the next step refactors at a contraction far below ``STALE_RATE``
    #: (``_choose_newton``): more than the two of a step on a fresh tangent in smooth
    #: motion, on a tangent that has served long enough for a refresh to pay.
    SLOW_STEP, OLD_TANGENT = 3, 16

    #: The contraction above which such a slow step blames its tangent: RADAU5's default
    #: ``THET`` (Hairer & Wanner).  A step of exact corrections (a linear body: a
    #: contraction of 0) that is slow for the test's sake keeps its tangent.
    SLOW_RATE = 1e-3

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
        * **A slow step on an old tangent.** A stale step that took ``SLOW_STEP``
          corrections or more on a tangent that has served ``OLD_TANGENT`` steps or more
          has the next step factor at its predictor if it contracted above ``SLOW_RATE``
          (far below ``STALE_RATE``): the tangent has drifted, and its first correction,
          not the contraction after it, says so.  (A linear bead's exact corrections
          contract by 0 and some of its steps take 3: it refactored every 17 steps for
          nothing without the bound.)  The released 100 m pendulum of
          ``benchmarks/step_exponent.py`` at 1000 elements took 4 corrections a step for
          30 steps (7-37) on the release's tangent, contracting by 2e-3 to 4e-2 from
          scaled residuals of 4e-5 to 6e-5 at the predictor against a tolerance of
          1e-11; a fresh tangent takes 2.  Over the 202 steps from the release, 472, 489,
          500, 540 and 505 corrections at 1000, 1800, 3200, 5600 and 10,000 elements
          become 432, 433, 438, 475 and 492 (7-12 % of the step's CPU time up to 5600
          elements; with 4 corrections for a slow step, 504 at 10,000 elements; with 4
          and a tangent 8 or 32 steps old, 424 with one more factorization or 462 at
          1000).  The 16-element pendulum takes 1062 corrections and 182
          factorizations in 300 steps instead of 1070 and 181; the E-sail rig, the
          orbiting and the full-size sail, the catenary and the controller run make the
          same iterations.  Over the test suite's runs: 2.7 % fewer corrections
          (857,311 -> 834,443), 0.2 % more factorizations (305,110 -> 305,674), fewer
          corrections in 39 tests' runs and more in 2 (one of them interrupted at a
          time, not a step).
        * **Unless the step replaced an old tangent.** A step that refactored within its
          iteration reports a contraction measured across the two matrices (its first
          correction on the new one against its last on the old): it says that the old
          one had gone stale, which the step has already mended.  If that tangent had
          served at most ``YOUNG_TANGENT`` steps before this one, the tangent changes
          within a step or two and the next step starts fresh, as above; if it had served
          longer, the next step iterates on the one just factored.  The released 100 m
          pendulum of ``benchmarks/step_exponent.py`` at 10,000 elements replaces an old
          tangent at step 146 (that of step 49) and factored again at the next predictor:
          11 factorizations in the 202 steps from the release instead of 12, with the same
          492 corrections (before the slow-step rule it replaced two, at steps 119 and
          189, and saved two of 13); at 3200 and 5600 elements one fewer, at 1000 and
          1800 none.  (Since the ringing keeps the extrapolating predictor on a kept
          tangent, ``GeneralizedAlpha.predictor``, the replacement is at step 147, of
          the tangent of step 52.)  The 16-element pendulum, the E-sail rig, the
          orbiting and the full-size sail, the catenary and the controller run make the
          same iterations; the damped pendulum 874 corrections and 255 factorizations
          instead of 872 and 260 (300 steps).  Any bound from 0 to 16 steps gave these
          counts.
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
        slow = (self.iterations >= self.SLOW_STEP and self.tangent_age >= self.OLD_TANGENT
                and self.newton_rate > self.SLOW_RATE)
        if (self.fresh_steps <= 0 and self.iterations >= 2 and not mended
                and (slow or self.newton_rate > self.STALE_RATE)):
            self.fresh_steps = 1
